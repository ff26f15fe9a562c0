! The spring and graph-Taubin wrappers from Fortran, and the parameter structs built with
! dkf_graph / dkf_spring_system, on a 5-node chain with both ends fixed: the linear springs
! reproduce the linear interpolation, the residual through the raw dk_spring_relative_residual
! is tiny, a NULL array inside the struct is refused with the values untouched, and the
! λ|μ filter keeps a linear field exactly and damps a spike. The multigrid wrapper
! dkf_spring_solve_linear_amg (and _f32) gives the same interpolation; the raw
! dk_spring_solve_linear_amg with pools one element short refuses and leaves the values
! untouched. The sliding solve dk_spring_solve_linear_sliding with a dk_constraints built by
! dkf_constraints (and _f32): the middle node slides along x (normal (0, 1)), so x keeps the
! interpolation and y is 0 there; directions one short are refused with the values untouched;
! the wrapper dkf_spring_solve_linear_sliding gives the same values.
! Prints "solvers: every check held" when every check holds.
program solvers
  use, intrinsic :: iso_c_binding, only: c_double, c_float, c_int32_t, c_int8_t, c_size_t, &
                                         c_null_ptr, c_loc
  use deform_kernel
  implicit none

  integer, parameter :: N = 5
  integer(c_int32_t) :: edges(2, N - 1)
  integer(c_int32_t), target :: offsets(N + 1), targets(2 * (N - 1))
  real(c_double), target :: stiffness(2 * (N - 1))
  integer(c_int8_t), target :: fixed(N)
  real(c_double) :: values(2, N), before(2, N), exact(2, N), residual, field(1, N), spike
  real(c_double), allocatable :: scratch(:)
  integer(c_int32_t), allocatable :: index_scratch(:)
  integer(c_size_t) :: used, len
  type(dk_spring_solve_options) :: options
  type(dk_spring_solve_report) :: report
  type(dk_filter_report) :: filter
  type(dk_spring_system) :: sys
  type(dk_amg_options) :: amg
  type(dk_plan_sizes) :: sizes
  real(c_double), allocatable, target :: reals(:)
  integer(c_int32_t), allocatable, target :: indices(:), work(:)
  integer(c_int8_t), target :: no_bytes(1)
  real(c_float), target :: stiffness32(2 * (N - 1))
  real(c_float) :: values32(2, N)
  integer(c_int8_t), target :: kinds(N), mask(N)
  real(c_double), target :: directions(2, N), slid(2, N)
  real(c_float), target :: directions32(2, N)
  real(c_float), allocatable :: scratch32(:)
  type(dk_constraints) :: con
  integer :: i, failures

  failures = 0
  do i = 1, N - 1
    edges(:, i) = [i, i + 1]
  end do
  call expect(dkf_graph_from_edges(int(N, c_size_t), edges, offsets, targets, used) == DK_OK, &
              'graph status')
  call expect(used == 2 * (N - 1), 'graph edges')
  stiffness = 1
  fixed = 0
  fixed(1) = 1
  fixed(N) = 1
  do i = 1, N
    exact(:, i) = [real(i - 1, c_double), 2 * real(i - 1, c_double)]
  end do
  values = 0
  values(:, 1) = exact(:, 1)
  values(:, N) = exact(:, N)

  ! The linear springs through the wrapper (CG, Jacobi preconditioner).
  call expect(dk_spring_solve_options_default(options) == DK_OK, 'options')
  call expect(dk_spring_solve_linear_scratch_len(int(N, c_size_t), 2_c_int32_t, options, len) &
              == DK_OK, 'scratch length')
  allocate(scratch(len))
  call expect(dk_spring_index_scratch_len(int(N, c_size_t), len) == DK_OK, 'index length')
  allocate(index_scratch(len))
  call expect(dkf_spring_solve_linear(offsets, targets, stiffness, fixed, options, values, &
                                      scratch, index_scratch, report) == DK_OK, 'solve status')
  call expect(logical(report%converged), 'solve converged')
  call expect(maxval(abs(values - exact)) <= 1e-12_c_double, 'linear interpolation')

  ! The same system as a struct, through a raw interface.
  sys = dkf_spring_system(dkf_graph(offsets, targets), stiffness, fixed)
  call expect(dk_spring_relative_residual(sys, 2_c_int32_t, values, size(values, kind=c_size_t), &
                                          index_scratch, size(index_scratch, kind=c_size_t), &
                                          residual) == DK_OK, 'residual status')
  call expect(residual <= 1e-10_c_double, 'residual small')
  sys%stiffness = c_null_ptr
  before = values
  call expect(dk_spring_relative_residual(sys, 2_c_int32_t, values, size(values, kind=c_size_t), &
                                          index_scratch, size(index_scratch, kind=c_size_t), &
                                          residual) == DK_ERR_NULL_POINTER, 'NULL stiffness')
  call expect(all(values == before), 'values untouched')

  ! The multigrid solve through the wrapper (pools allocated inside), f64 and f32.
  call expect(dk_amg_options_default(amg) == DK_OK, 'amg options')
  call expect(amg%max_levels == 10 .and. amg%smoother == DK_AMG_CHEBYSHEV, 'amg defaults')
  values = 0
  values(:, 1) = exact(:, 1)
  values(:, N) = exact(:, N)
  call expect(dkf_spring_solve_linear_amg(offsets, targets, stiffness, fixed, options, amg, &
                                          values, report) == DK_OK, 'amg solve status')
  call expect(logical(report%converged), 'amg solve converged')
  call expect(maxval(abs(values - exact)) <= 1e-12_c_double, 'amg linear interpolation')
  stiffness32 = 1
  values32 = 0
  values32(:, 1) = real(exact(:, 1), c_float)
  values32(:, N) = real(exact(:, N), c_float)
  call expect(dk_spring_solve_options_default_f32(options) == DK_OK, 'options f32')
  call expect(dkf_spring_solve_linear_amg_f32(offsets, targets, stiffness32, fixed, options, &
                                              amg, values32, report) == DK_OK, 'amg f32 status')
  call expect(maxval(abs(values32 - real(exact, c_float))) <= 1e-5, 'amg f32 interpolation')
  call expect(dk_spring_solve_options_default(options) == DK_OK, 'options again')

  ! The raw interfaces: exact pool sizes, then pools one element short are refused.
  sys = dkf_spring_system(dkf_graph(offsets, targets), stiffness, fixed)
  call expect(dk_spring_amg_work_len(int(N, c_size_t), size(targets, kind=c_size_t), len) &
              == DK_OK, 'amg work length')
  allocate(work(len))
  call expect(dk_spring_solve_linear_amg_pool_sizes(sys, 2_c_int32_t, amg, work, len, sizes) &
              == DK_OK, 'amg pool sizes')
  call expect(sizes%bytes == 0 .and. sizes%indices > len, 'amg pool layout')
  allocate(reals(sizes%reals), indices(sizes%indices))
  values = 0
  values(:, 1) = exact(:, 1)
  values(:, N) = exact(:, N)
  before = values
  call expect(dk_spring_solve_linear_amg(sys, options, amg, 2_c_int32_t, values, &
                                         size(values, kind=c_size_t), &
                                         dk_plan_pools(c_loc(reals), sizes%reals - 1, &
                                                       c_loc(indices), sizes%indices, &
                                                       c_loc(no_bytes), 0_c_size_t), report) &
              == DK_ERR_BUFFER_TOO_SMALL, 'reals one short')
  call expect(all(values == before), 'values untouched (reals)')
  call expect(dk_spring_solve_linear_amg(sys, options, amg, 2_c_int32_t, values, &
                                         size(values, kind=c_size_t), &
                                         dk_plan_pools(c_loc(reals), sizes%reals, &
                                                       c_loc(indices), sizes%indices - 1, &
                                                       c_loc(no_bytes), 0_c_size_t), report) &
              == DK_ERR_BUFFER_TOO_SMALL, 'indices one short')
  call expect(all(values == before), 'values untouched (indices)')
  call expect(dk_spring_solve_linear_amg(sys, options, amg, 2_c_int32_t, values, &
                                         size(values, kind=c_size_t), &
                                         dkf_plan_pools(reals, indices, no_bytes), report) &
              == DK_OK, 'exact pools')
  call expect(maxval(abs(values - exact)) <= 1e-12_c_double, 'raw amg interpolation')

  ! Sliding: node 3 slides along x (the system's mask from the constraints).
  kinds = 0
  kinds(1) = 1
  kinds(N) = 1
  kinds(3) = 2
  directions = 0
  directions(2, 3) = 1
  directions32 = real(directions, c_float)
  mask = 7
  con = dkf_constraints(kinds, directions)
  call expect(dk_constraints_fixed_mask(con, 2_c_int32_t, mask, int(N, c_size_t)) == DK_OK, &
              'fixed mask status')
  call expect(all(mask == fixed), 'fixed mask')
  call expect(dk_spring_solve_linear_sliding_scratch_len(int(N, c_size_t), 2_c_int32_t, &
                                                         options, len) == DK_OK, &
              'sliding scratch length')
  deallocate(scratch)
  allocate(scratch(len))
  sys = dkf_spring_system(dkf_graph(offsets, targets), stiffness, mask)
  slid = 0
  slid(:, 1) = exact(:, 1)
  slid(:, N) = exact(:, N)
  before = slid
  con%directions_len = con%directions_len - 1
  call expect(dk_spring_solve_linear_sliding(sys, con, options, 2_c_int32_t, slid, &
                                             size(slid, kind=c_size_t), scratch, len, &
                                             index_scratch, size(index_scratch, kind=c_size_t), &
                                             report) == DK_ERR_LENGTH_MISMATCH, &
              'directions one short')
  call expect(all(slid == before), 'values untouched (directions)')
  con = dkf_constraints(kinds, directions)
  call expect(dk_spring_solve_linear_sliding(sys, con, options, 2_c_int32_t, slid, &
                                             size(slid, kind=c_size_t), scratch, len, &
                                             index_scratch, size(index_scratch, kind=c_size_t), &
                                             report) == DK_OK, 'sliding status')
  call expect(logical(report%converged), 'sliding converged')
  call expect(maxval(abs(slid(1, :) - exact(1, :))) <= 1e-12_c_double, 'sliding x interpolated')
  call expect(maxval(abs(slid(2, :) - [0, 0, 0, 4, 8])) <= 1e-12_c_double, 'sliding y')
  call expect(slid(2, 3) == 0, 'sliding node on its line')
  ! The same through the wrapper.
  before = slid
  slid = 0
  slid(:, 1) = exact(:, 1)
  slid(:, N) = exact(:, N)
  call expect(dkf_spring_solve_linear_sliding(offsets, targets, stiffness, mask, kinds, &
                                              directions, options, slid, scratch, &
                                              index_scratch, report) == DK_OK, &
              'sliding wrapper status')
  call expect(all(slid == before), 'sliding wrapper: the same values')
  allocate(scratch32(len))
  values32 = 0
  values32(:, 1) = real(exact(:, 1), c_float)
  values32(:, N) = real(exact(:, N), c_float)
  call expect(dk_spring_solve_linear_sliding_f32(dkf_spring_system_f32(dkf_graph(offsets, &
                                                 targets), stiffness32, mask), &
                                                 dkf_constraints_f32(kinds, directions32), &
                                                 options, 2_c_int32_t, values32, &
                                                 size(values32, kind=c_size_t), scratch32, &
                                                 size(scratch32, kind=c_size_t), index_scratch, &
                                                 size(index_scratch, kind=c_size_t), report) &
              == DK_OK, 'sliding f32 status')
  call expect(maxval(abs(values32 - real(slid, c_float))) <= 1e-5, 'sliding f32')

  ! Graph Taubin: a linear field on the uniform chain is a fixed point, exactly; a spike at
  ! the middle node is damped, the fixed ends stay.
  call expect(dk_taubin_smooth_graph_scratch_len(int(N, c_size_t), 1_c_int32_t, len) == DK_OK, &
              'taubin scratch length')
  deallocate(scratch)
  allocate(scratch(len))
  field(1, :) = exact(1, :)
  call expect(dkf_taubin_smooth_graph(offsets, targets, 0.33_c_double, -0.34_c_double, &
                                      10_c_size_t, field, scratch, filter, fixed=fixed) == DK_OK, &
              'taubin status')
  call expect(all(field(1, :) == exact(1, :)), 'linear field kept')
  call expect(filter%iterations == 10, 'taubin iterations')
  spike = 1
  field(1, 3) = field(1, 3) + spike
  call expect(dkf_taubin_smooth_graph(offsets, targets, 0.33_c_double, -0.34_c_double, &
                                      10_c_size_t, field, scratch, filter, fixed=fixed) == DK_OK, &
              'taubin spike status')
  call expect(abs(field(1, 3) - exact(1, 3)) < 0.5_c_double * spike, 'spike damped')
  call expect(field(1, 1) == exact(1, 1) .and. field(1, N) == exact(1, N), 'ends fixed')

  if (failures == 0) print '(a)', 'solvers: every check held'

contains

  subroutine expect(ok, what)
    logical, intent(in) :: ok
    character(*), intent(in) :: what
    if (.not. ok) then
      print '(2a)', 'FAILED: ', what
      failures = failures + 1
    end if
  end subroutine

end program
