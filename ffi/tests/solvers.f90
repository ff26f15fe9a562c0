! The spring and graph-Taubin wrappers from Fortran, and the parameter structs built with
! dkf_graph / dkf_spring_system, on a 5-node chain with both ends fixed: the linear springs
! reproduce the linear interpolation, the residual through the raw dk_spring_relative_residual
! is tiny, a NULL array inside the struct is refused with the values untouched, and the
! λ|μ filter keeps a linear field exactly and damps a spike. Prints "solvers: every check held"
! when every check holds.
program solvers
  use, intrinsic :: iso_c_binding, only: c_double, c_int32_t, c_int8_t, c_size_t, c_null_ptr
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
