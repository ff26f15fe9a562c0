! RBF deformation from Fortran through the generated interfaces (f64 and _f32): thin-plate
! splines move every point of a square rigidly when the whole boundary turns, Wendland C2
! with a greedy fit and the correction writes the boundary motion exactly (1-based boundary),
! and an unknown kernel is refused with the displacements untouched.
! Prints "rbf: every check held" when every check holds.
program rbf
  use, intrinsic :: iso_c_binding, only: c_double, c_float, c_int32_t, c_size_t
  use deform_kernel
  implicit none

  integer, parameter :: nb = 12, n = 16
  real(c_double) :: points(2, n), motion(2, nb), disp(2, n), scratch(1000), c, s
  real(c_float) :: points32(2, n), motion32(2, nb), disp32(2, n), scratch32(1000)
  integer(c_int32_t) :: boundary(nb), index(1000)
  integer(c_size_t) :: len, ilen
  type(dk_rbf_options) :: o
  type(dk_rbf_report) :: report
  integer :: i, k, failures

  failures = 0
  ! A 4 x 4 grid; its 12 perimeter nodes are the boundary (1-based).
  k = 0
  do i = 0, n - 1
    points(1, i + 1) = real(mod(i, 4), c_double)
    points(2, i + 1) = real(i / 4, c_double)
    if (mod(i, 4) == 0 .or. mod(i, 4) == 3 .or. i / 4 == 0 .or. i / 4 == 3) then
      k = k + 1
      boundary(k) = i + 1
    end if
  end do
  c = cos(0.3_c_double)
  s = sin(0.3_c_double)
  do k = 1, nb
    i = boundary(k)
    motion(1, k) = c * points(1, i) - s * points(2, i) - points(1, i) + 0.5_c_double
    motion(2, k) = s * points(1, i) + c * points(2, i) - points(2, i)
  end do

  call expect(dk_rbf_options_default(o) == DK_OK, 'defaults')
  o%kernel = DK_RBF_THIN_PLATE
  call expect(dk_rbf_scratch_len(int(nb, c_size_t), 2, o, len) == DK_OK .and. len <= 1000, &
              'scratch size')
  call expect(dk_rbf_index_scratch_len(int(nb, c_size_t), 2, 1, o, ilen) == DK_OK &
              .and. ilen <= 1000, 'index size')
  call expect(dk_rbf_deform(points, int(2 * n, c_size_t), 2, boundary, int(nb, c_size_t), 1, &
              motion, int(2 * nb, c_size_t), o, index, ilen, scratch, len, disp, &
              int(2 * n, c_size_t), report) == DK_OK, 'tps status')
  call expect(report%centres == nb, 'tps centres')
  do i = 1, n
    call expect(abs(disp(1, i) - (c * points(1, i) - s * points(2, i) - points(1, i) &
                + 0.5_c_double)) <= 1e-12_c_double, 'tps rigid x')
    call expect(abs(disp(2, i) - (s * points(1, i) + c * points(2, i) - points(2, i))) &
                <= 1e-12_c_double, 'tps rigid y')
  end do

  o%kernel = DK_RBF_WENDLAND
  o%radius = 4.0_c_double
  o%tolerance = 0.05_c_double
  o%max_centres = 6_c_size_t
  o%correction_radius = 1.0_c_double
  points32 = real(points, c_float)
  motion32 = real(motion, c_float)
  call expect(dk_rbf_deform_f32(points32, int(2 * n, c_size_t), 2, boundary, &
              int(nb, c_size_t), 1, motion32, int(2 * nb, c_size_t), o, index, 1000_c_size_t, &
              scratch32, 1000_c_size_t, disp32, int(2 * n, c_size_t), report) == DK_OK, &
              'greedy status')
  call expect(report%centres == 6, 'greedy reduced')
  do k = 1, nb
    call expect(all(disp32(:, boundary(k)) == motion32(:, k)), 'wall exact')
  end do

  o%kernel = 7
  disp = 9.0_c_double
  call expect(dk_rbf_deform(points, int(2 * n, c_size_t), 2, boundary, int(nb, c_size_t), 1, &
              motion, int(2 * nb, c_size_t), o, index, 1000_c_size_t, scratch, 1000_c_size_t, &
              disp, int(2 * n, c_size_t), report) == DK_ERR_INVALID_PARAMETER, 'bad kernel')
  call expect(all(disp == 9.0_c_double), 'untouched')

  if (failures == 0) write(*, '(A)') 'rbf: every check held'

contains

  subroutine expect(ok, what)
    logical, intent(in) :: ok
    character(*), intent(in) :: what
    if (.not. ok) then
      write(*, '(A,A)') 'check failed: ', what
      failures = failures + 1
    end if
  end subroutine

end program
