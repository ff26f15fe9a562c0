! deform-kernel from Fortran: the same steps as mesh_basics.c, with 1-based mesh numbering as
! a Fortran code stores it. Prints every result's bit pattern for the bit-parity test.
!
! Build: gfortran -std=f2008 ffi/generated/deform_kernel.f90 mesh_basics.f90 \
!        ffi/capi/target/release/libdeform_kernel.a -lm
program mesh_basics
  use, intrinsic :: iso_c_binding
  use deform_kernel
  implicit none
  real(c_double) :: points(3, 9), rotated(3, 9), q(4), arc(4), mid(4), avg(4), quats(4, 3)
  real(c_double) :: axis(3) = [0.0_c_double, 0.0_c_double, 1.0_c_double]
  real(c_double) :: from(3) = [1.0_c_double, 0.0_c_double, 0.0_c_double]
  real(c_double) :: to(3) = [0.0_c_double, 1.0_c_double, 0.5_c_double]
  real(c_double) :: weights(3) = [1.0_c_double, 2.0_c_double, 0.5_c_double]
  real(c_float) :: points32(3, 9), rotated32(3, 9), q32(4), turned32(2, 9)
  real(c_float) :: axis32(3) = [0.0_c_float, 0.0_c_float, 1.0_c_float]
  integer(c_int32_t) :: cell_offsets(5) = [1, 5, 9, 13, 17]
  integer(c_int32_t) :: cell_nodes(16) = [1, 2, 5, 4, 2, 3, 6, 5, 4, 5, 8, 7, 5, 6, 9, 8]
  integer(c_int8_t) :: cell_kinds(4)
  integer(c_int32_t) :: offsets(10), targets(64)
  integer(c_size_t) :: targets_len, used
  integer :: i

  cell_kinds = DK_QUAD
  do i = 0, 8
    points(:, i + 1) = [real(mod(i, 3), c_double) * 0.5_c_double, &
                        real(i / 3, c_double) * 0.25_c_double, 0.0_c_double]
    points32(:, i + 1) = real(points(:, i + 1), c_float)
  end do

  call check(dkf_graph_from_cells_len(9_c_size_t, cell_offsets, cell_nodes, cell_kinds, .true., &
                                      targets_len), "graph_from_cells_len")
  if (targets_len > size(targets)) stop 1
  call check(dkf_graph_from_cells(9_c_size_t, cell_offsets, cell_nodes, cell_kinds, .true., &
                                  offsets, targets(1:targets_len), used), "graph_from_cells")
  call print_ints("offsets", offsets)
  call print_ints("targets", targets(1:used))

  call check(dk_quat_from_axis_angle(axis, 0.3_c_double, q), "from_axis_angle")
  call check(dkf_rotate_points(q, points, rotated), "rotate_points")
  call print_f64("rotated", reshape(rotated, [27]))

  call check(dk_quat_from_axis_angle_f32(axis32, 0.3_c_float, q32), "from_axis_angle_f32")
  call check(dk_quat_rotate_points_f32(q32, points32, 27_c_size_t, rotated32, 27_c_size_t), &
             "rotate_points_f32")
  call print_f32("rotated_f32", reshape(rotated32, [27]))
  ! A 2D mesh needs no z: the same rotation (about z) on (x, y) pairs.
  call check(dk_quat_rotate_points_2d_f32(q32, points32(1:2, :), 18_c_size_t, turned32, &
                                          18_c_size_t), "rotate_points_2d_f32")
  call print_f32("rotated_2d_f32", reshape(turned32, [18]))

  call check(dk_quat_rotation_arc(from, to, arc), "rotation_arc")
  call print_f64("arc", arc)
  call check(dk_quat_slerp(q, arc, 0.25_c_double, mid), "slerp")
  call print_f64("slerp", mid)
  quats(:, 1) = q
  quats(:, 2) = arc
  quats(:, 3) = -mid
  call check(dk_quat_average(quats, 12_c_size_t, weights, 3_c_size_t, avg), "average")
  call print_f64("average", avg)

contains

  subroutine check(status, what)
    integer(c_int32_t), intent(in) :: status
    character(len=*), intent(in) :: what
    if (status /= DK_OK) then
      write (0, '(a, a, a)') what, " failed: ", dk_status_message(status)
      stop 1
    end if
  end subroutine

  subroutine print_ints(name, v)
    character(len=*), intent(in) :: name
    integer(c_int32_t), intent(in) :: v(:)
    integer :: k
    write (*, '(a)', advance='no') name
    do k = 1, size(v)
      write (*, '(a, i0)', advance='no') " ", v(k)
    end do
    write (*, '(a)') ""
  end subroutine

  subroutine print_f64(name, v)
    character(len=*), intent(in) :: name
    real(c_double), intent(in) :: v(:)
    integer :: k
    write (*, '(a)', advance='no') name
    do k = 1, size(v)
      write (*, '(a, z16.16)', advance='no') " ", transfer(v(k), 0_c_int64_t)
    end do
    write (*, '(a)') ""
  end subroutine

  subroutine print_f32(name, v)
    character(len=*), intent(in) :: name
    real(c_float), intent(in) :: v(:)
    integer :: k
    write (*, '(a)', advance='no') name
    do k = 1, size(v)
      write (*, '(a, z8.8)', advance='no') " ", transfer(v(k), 0_c_int32_t)
    end do
    write (*, '(a)') ""
  end subroutine

end program mesh_basics
