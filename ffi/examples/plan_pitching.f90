! A flow solver in Fortran stepping a prepared plan: the same O-grid, pitching motion,
! checkpoint and cold comparison as plan_pitching.c, through the dkf_plan_* wrappers of the
! deform_kernel module. It prints exactly what the C program prints (the host tests compare
! the two outputs, and the C output with the Rust API), and fails unless warm starts take
! fewer iterations than cold ones. Node numbers (cells, boundary, elements) are 1-based here;
! the wrappers pass 0-based copies to the C functions.
!
! Build: gfortran -std=f2008 ffi/generated/deform_kernel.f90 ffi/examples/plan_pitching.f90 \
!        libdeform_kernel.a -lm -lpthread -ldl
program plan_pitching
  use, intrinsic :: iso_c_binding, only: c_double, c_int32_t, c_int64_t, c_int8_t, c_size_t
  use deform_kernel
  implicit none

  integer, parameter :: ni = 48, nj = 16, n = ni * nj, nb = 2 * ni, nsteps = 20
  real(c_double), parameter :: pi = 3.14159265358979323846_c_double
  real(c_double) :: points(2, n), out(2, n), s, w, t, wx, wy, fx, fy
  integer(c_int32_t) :: cell_offsets(ni * (nj - 1) + 1), cell_nodes(4 * ni * (nj - 1))
  integer(c_int8_t) :: cell_kinds(ni * (nj - 1))
  integer(c_int32_t) :: offsets(n + 1), boundary(nb), element_offsets(nb + 1), &
                        element_nodes(2 * nb)
  integer(c_int8_t) :: element_kinds(nb)
  integer(c_int32_t), allocatable :: targets(:), indices(:), i2(:)
  real(c_double), allocatable :: reals(:), r2(:)
  integer(c_int8_t), allocatable :: bytes(:), b2(:)
  integer(c_size_t) :: targets_len, used
  type(dk_plan_options) :: options
  type(dk_plan_sizes) :: pools
  type(dk_plan_info) :: info, copy
  integer(c_size_t) :: total_warm, total_cold
  integer :: i, j, c, ring, k

  do j = 0, nj - 1
    s = real(j, c_double) / real(nj - 1, c_double)
    w = s * s * s
    do i = 0, ni - 1
      t = 2.0_c_double * pi * real(i, c_double) / real(ni, c_double)
      wx = 0.5_c_double * cos(t)
      wy = 0.06_c_double * sin(t)
      fx = 10.0_c_double * cos(t)
      fy = 10.0_c_double * sin(t)
      points(1, j * ni + i + 1) = (1.0_c_double - w) * wx + w * fx
      points(2, j * ni + i + 1) = (1.0_c_double - w) * wy + w * fy
    end do
  end do
  c = 0
  do j = 0, nj - 2
    do i = 0, ni - 1
      cell_offsets(c + 1) = 4 * c + 1
      cell_nodes(4 * c + 1) = j * ni + i + 1
      cell_nodes(4 * c + 2) = j * ni + mod(i + 1, ni) + 1
      cell_nodes(4 * c + 3) = (j + 1) * ni + mod(i + 1, ni) + 1
      cell_nodes(4 * c + 4) = (j + 1) * ni + i + 1
      cell_kinds(c + 1) = DK_QUAD
      c = c + 1
    end do
  end do
  cell_offsets(c + 1) = 4 * c + 1
  call check(dkf_graph_from_cells_len(int(n, c_size_t), cell_offsets, cell_nodes, cell_kinds, &
                                      .true., targets_len))
  allocate(targets(targets_len))
  call check(dkf_graph_from_cells(int(n, c_size_t), cell_offsets, cell_nodes, cell_kinds, &
                                  .true., offsets, targets, used))
  do i = 0, ni - 1
    boundary(i + 1) = i + 1
    boundary(ni + i + 1) = (nj - 1) * ni + i + 1
  end do
  do i = 0, nb - 1
    ring = i / ni
    k = mod(i, ni)
    element_offsets(i + 1) = 2 * i + 1
    element_nodes(2 * i + 1) = ring * ni + k + 1
    element_nodes(2 * i + 2) = ring * ni + mod(k + 1, ni) + 1
    element_kinds(i + 1) = DK_LINE
  end do
  element_offsets(nb + 1) = 2 * nb + 1
  call print_hex('points', reshape(points, [2 * n]))

  ! Set up once (the wrappers allocate and free the transient work buffers).
  call check(dk_plan_options_default(options))
  call check(dkf_plan_pool_sizes(points, offsets, targets(1:used), boundary, options, pools, &
                                 element_offsets, element_nodes, element_kinds))
  allocate(reals(pools%reals), indices(pools%indices), bytes(pools%bytes))
  call check(dkf_plan_init(points, offsets, targets(1:used), boundary, options, reals, indices, &
                           bytes, info, element_offsets, element_nodes, element_kinds))
  write(*, '(A,I0,A,I0,A,I0,A,I0,A,I0,A,I0)') 'plan: ', info%nodes, ' nodes, ', &
      info%boundary, ' boundary points, ', info%amg_levels, ' multigrid levels, pools ', &
      info%used%reals, ' + ', info%used%indices, ' + ', info%used%bytes

  total_warm = steps(reals, indices, bytes, DK_PLAN_WARM, 1, nsteps / 2, .true.)
  ! A checkpoint halfway: the pools hold no pointers, so a copy is a plan.
  r2 = reals
  i2 = indices
  b2 = bytes
  reals = transfer(-1_c_int64_t, 1.0_c_double)
  if (dkf_plan_open(reals, indices, bytes, 2_c_int32_t, copy) /= DK_ERR_BAD_PLAN) then
    write(*, '(A)') 'an overwritten plan was accepted'
    error stop 1
  end if
  call check(dkf_plan_open(r2, i2, b2, 2_c_int32_t, copy))
  if (copy%steps /= nsteps / 2) error stop 1
  total_warm = total_warm + steps(r2, i2, b2, DK_PLAN_WARM, nsteps / 2 + 1, nsteps, .true.)
  call print_hex('final', reshape(out, [2 * n]))

  ! The same steps from cold starts, in a fresh plan.
  call check(dkf_plan_init(points, offsets, targets(1:used), boundary, options, reals, indices, &
                           bytes, info, element_offsets, element_nodes, element_kinds))
  total_cold = steps(reals, indices, bytes, DK_PLAN_COLD, 1, nsteps, .false.)
  write(*, '(A,I0,A,I0)') 'iterations: warm ', total_warm, ', cold ', total_cold
  if (total_warm >= total_cold) error stop 1

contains

  subroutine check(status)
    integer(c_int32_t), intent(in) :: status
    if (status /= DK_OK) then
      write(*, '(A,I0)') 'deform_kernel status ', status
      error stop 1
    end if
  end subroutine

  subroutine print_hex(name, v)
    character(*), intent(in) :: name
    real(c_double), intent(in) :: v(:)
    integer :: m
    write(*, '(A)', advance='no') name
    do m = 1, size(v)
      write(*, '(1X,Z16.16)', advance='no') transfer(v(m), 0_c_int64_t)
    end do
    write(*, '(A)') ''
  end subroutine

  ! The wall turned by the pitch angle about the quarter chord, the far field fixed.
  subroutine boundary_at(step, deformed)
    integer, intent(in) :: step
    real(c_double), intent(out) :: deformed(2, nb)
    real(c_double) :: amplitude, frac, a, ca, sa, x, y
    integer :: m
    amplitude = 5.0_c_double * pi / 180.0_c_double
    if (step <= nsteps / 2) then
      frac = real(step, c_double) / real(nsteps / 2, c_double)
    else
      frac = real(nsteps - step, c_double) / real(nsteps / 2, c_double)
    end if
    a = -amplitude * frac
    ca = cos(a)
    sa = sin(a)
    do m = 1, nb
      x = points(1, boundary(m))
      y = points(2, boundary(m))
      if (m <= ni) then
        x = x + 0.25_c_double
        deformed(1, m) = -0.25_c_double + (ca * x - sa * y)
        deformed(2, m) = sa * x + ca * y
      else
        deformed(1, m) = x
        deformed(2, m) = y
      end if
    end do
  end subroutine

  ! Steps a plan through steps from..to; returns the total iterations (the mesh is in out).
  function steps(r, ix, bt, start, from, to, print) result(total)
    real(c_double), intent(inout) :: r(:)
    integer(c_int32_t), intent(inout) :: ix(:)
    integer(c_int8_t), intent(inout) :: bt(:)
    integer(c_int32_t), intent(in) :: start
    integer, intent(in) :: from, to
    logical, intent(in) :: print
    integer(c_size_t) :: total
    real(c_double) :: deformed(2, nb)
    type(dk_plan_step_report) :: report
    character(32) :: name
    integer :: step
    total = 0
    do step = from, to
      call boundary_at(step, deformed)
      call check(dkf_plan_step(r, ix, bt, deformed, out, report, start))
      if (.not. report%converged .or. report%step /= step) error stop 1
      total = total + report%iterations
      if (print) then
        write(name, '(A,I0,A)') 'step ', step, ' deformed'
        call print_hex(trim(name), reshape(deformed, [2 * nb]))
        write(*, '(A,I0,A,I0,A,I0,A,I0)') 'step ', step, ' iterations ', report%iterations, &
            ' warm ', merge(1, 0, logical(report%warm)), ' extrapolated ', &
            merge(1, 0, logical(report%extrapolated))
      end if
    end do
  end function

end program
