! The fast IDW deformation and its derivatives from Fortran through the generated interfaces
! (f64 and _f32), with a dk_boundary_motion built from Fortran arrays by c_loc (1-based
! boundary): a rigid turn of the whole boundary of a 12 x 12 grid turns every interior node
! (tree clusters in use), the fast result agrees with the exact dk_deform_idw, the tangent and
! the adjoint pass the dot-product identity, the _f32 twin reproduces the boundary bit for
! bit, and theta = 1.5 is refused with the output untouched.
! Prints "deformation_fast: every check held" when every check holds.
program deformation_fast
  use, intrinsic :: iso_c_binding, only: c_double, c_float, c_int32_t, c_size_t, c_loc
  use deform_kernel
  implicit none

  integer, parameter :: m = 12, n = m * m, nb = 4 * (m - 1)
  real(c_double), parameter :: angle = 0.2_c_double, centre = 5.5_c_double
  real(c_double) :: points(2, n), out(2, n), exact(2, n), tr(2, n), rot(4, n), origin(2)
  real(c_double) :: tangent(2, n), weights(2, n), direction(2, nb), gradient(2, nb), none(1)
  real(c_double) :: bound(1)
  real(c_double), target :: deformed(2, nb)
  real(c_float), target :: deformed32(2, nb)
  real(c_float) :: points32(2, n), out32(2, n), tr32(2, n), rot32(4, n), none32(1)
  integer(c_int32_t), target :: boundary(nb)
  real(c_double), allocatable :: scratch(:), tree(:), sens(:)
  real(c_float), allocatable :: scratch32(:), tree32(:)
  integer(c_int32_t), allocatable :: index(:), tree_index(:)
  integer(c_size_t) :: lens(4), ilen
  type(dk_boundary_motion) :: motion
  type(dk_boundary_motion_f32) :: motion32
  real(c_double) :: c, s, x, y, lhs, rhs
  integer :: i, k, failures

  failures = 0
  k = 0
  do i = 0, n - 1
    points(1, i + 1) = real(mod(i, m), c_double)
    points(2, i + 1) = real(i / m, c_double)
    if (mod(i, m) == 0 .or. mod(i, m) == m - 1 .or. i / m == 0 .or. i / m == m - 1) then
      k = k + 1
      boundary(k) = i + 1
    end if
  end do
  c = cos(angle)
  s = sin(angle)
  do k = 1, nb
    x = points(1, boundary(k)) - centre
    y = points(2, boundary(k)) - centre
    deformed(1, k) = centre + c * x - s * y
    deformed(2, k) = centre + s * x + c * y
  end do

  call expect(dk_boundary_motion_default(motion) == DK_OK, 'defaults')
  motion%nodes = c_loc(boundary)
  motion%nodes_len = int(nb, c_size_t)
  motion%deformed = c_loc(deformed)
  motion%deformed_len = int(2 * nb, c_size_t)
  motion%index_base = 1
  motion%rotation_source = DK_ROTATIONS_RIGID
  motion%rigid_rotation = [cos(angle / 2), 0.0_c_double, 0.0_c_double, sin(angle / 2)]
  motion%origin = [centre, centre, 0.0_c_double]
  motion%has_origin = 1

  call expect(dk_deform_idw_fast_lens(int(n, c_size_t), int(nb, c_size_t), 2, lens) == DK_OK, &
              'lens')
  call expect(dk_boundary_motion_index_scratch_len(motion, ilen) == DK_OK, 'index length')
  allocate(scratch(lens(1)), tree_index(lens(2)), tree(lens(3)), sens(lens(4)), index(ilen))
  allocate(scratch32(lens(1)), tree32(lens(3)))

  ! theta = 0.7 with a 44-node boundary weighs clusters as a whole for the far side.
  call expect(dk_deform_idw_fast(points, int(2 * n, c_size_t), 2, motion, 2.0_c_double, &
              0.7_c_double, 0.1_c_double, scratch, lens(1), index, ilen, tree_index, lens(2), &
              tree, lens(3), tr, int(2 * n, c_size_t), rot, int(4 * n, c_size_t), out, &
              int(2 * n, c_size_t), origin, 2_c_size_t, bound, 1_c_size_t) == DK_OK, &
              'fast status')
  call expect(all(origin == [centre, centre]), 'origin')
  ! A bound above zero: some cluster was weighed as a whole.
  call expect(bound(1) > 0.0_c_double .and. bound(1) <= 0.1_c_double, 'clusters in use')
  do i = 1, n
    x = points(1, i) - centre
    y = points(2, i) - centre
    call expect(abs(out(1, i) - (centre + c * x - s * y)) <= 1e-12_c_double, 'rigid x')
    call expect(abs(out(2, i) - (centre + s * x + c * y)) <= 1e-12_c_double, 'rigid y')
  end do
  do k = 1, nb
    call expect(all(out(:, boundary(k)) == deformed(:, k)), 'boundary exact')
  end do
  call expect(dk_deform_idw(points, int(2 * n, c_size_t), 2, motion, 2.0_c_double, scratch, &
              lens(1), index, ilen, tr, int(2 * n, c_size_t), rot, int(4 * n, c_size_t), &
              exact, int(2 * n, c_size_t), none, 0_c_size_t) == DK_OK, 'exact status')
  call expect(maxval(abs(out - exact)) <= 1e-12_c_double, 'fast = exact for a rigid turn')

  ! Tangent and adjoint: <J v, w> = <v, J^T w>.
  do k = 1, nb
    direction(1, k) = sin(1.0_c_double * k)
    direction(2, k) = cos(2.0_c_double * k)
  end do
  do i = 1, n
    weights(1, i) = cos(0.7_c_double * i)
    weights(2, i) = sin(1.3_c_double * i)
  end do
  call expect(dk_deform_idw_fast_tangent(points, int(2 * n, c_size_t), 2, motion, &
              2.0_c_double, 0.7_c_double, 0.1_c_double, direction, int(2 * nb, c_size_t), &
              sens, lens(4), index, ilen, tree_index, lens(2), tree, lens(3), tr, &
              int(2 * n, c_size_t), rot, int(4 * n, c_size_t), tangent, &
              int(2 * n, c_size_t)) == DK_OK, 'tangent status')
  call expect(dk_deform_idw_fast_adjoint(points, int(2 * n, c_size_t), 2, motion, &
              2.0_c_double, 0.7_c_double, 0.1_c_double, weights, int(2 * n, c_size_t), &
              sens, lens(4), index, ilen, tree_index, lens(2), tree, lens(3), tr, &
              int(2 * n, c_size_t), rot, int(4 * n, c_size_t), gradient, &
              int(2 * nb, c_size_t)) == DK_OK, 'adjoint status')
  lhs = sum(tangent * weights)
  rhs = sum(direction * gradient)
  call expect(abs(lhs - rhs) <= 1e-12_c_double * max(1.0_c_double, abs(lhs)), 'dot product')
  do k = 1, nb
    call expect(all(tangent(:, boundary(k)) == direction(:, k)), 'tangent boundary exact')
  end do

  ! The _f32 twin: boundary nodes bit for bit.
  call expect(dk_boundary_motion_default_f32(motion32) == DK_OK, 'defaults f32')
  points32 = real(points, c_float)
  deformed32 = real(deformed, c_float)
  motion32%nodes = c_loc(boundary)
  motion32%nodes_len = int(nb, c_size_t)
  motion32%deformed = c_loc(deformed32)
  motion32%deformed_len = int(2 * nb, c_size_t)
  motion32%index_base = 1
  motion32%rotation_source = DK_ROTATIONS_RIGID
  motion32%rigid_rotation = real(motion%rigid_rotation, c_float)
  motion32%origin = real(motion%origin, c_float)
  motion32%has_origin = 1
  call expect(dk_deform_idw_fast_f32(points32, int(2 * n, c_size_t), 2, motion32, 2.0_c_float, &
              0.7_c_float, 0.1_c_float, scratch32, lens(1), index, ilen, tree_index, lens(2), &
              tree32, lens(3), tr32, int(2 * n, c_size_t), rot32, int(4 * n, c_size_t), out32, &
              int(2 * n, c_size_t), none32, 0_c_size_t, none32, 0_c_size_t) == DK_OK, &
              'f32 status')
  do k = 1, nb
    call expect(all(out32(:, boundary(k)) == deformed32(:, k)), 'f32 boundary exact')
  end do
  call expect(maxval(abs(real(out32, c_double) - out)) <= 1e-5_c_double, 'f32 near f64')

  ! theta outside [0, 1): refused, nothing written.
  out = 9.0_c_double
  call expect(dk_deform_idw_fast(points, int(2 * n, c_size_t), 2, motion, 2.0_c_double, &
              1.5_c_double, 0.1_c_double, scratch, lens(1), index, ilen, tree_index, lens(2), &
              tree, lens(3), tr, int(2 * n, c_size_t), rot, int(4 * n, c_size_t), out, &
              int(2 * n, c_size_t), none, 0_c_size_t, none, 0_c_size_t) &
              == DK_ERR_INVALID_PARAMETER, 'bad theta')
  call expect(all(out == 9.0_c_double), 'untouched')

  if (failures == 0) write(*, '(A)') 'deformation_fast: every check held'

contains

  subroutine expect(ok, what)
    logical, intent(in) :: ok
    character(*), intent(in) :: what
    if (.not. ok) then
      failures = failures + 1
      write(*, '(A, A)') 'FAILED: ', what
    end if
  end subroutine

end program
