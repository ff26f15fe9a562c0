! deform-kernel from Fortran: the same steps as deform_and_smooth.c (quaternion deformation of
! an O-grid around a pitching and plunging elliptic body by IDW, TFI and linear springs, then
! Taubin smoothing of the radial lines), with 1-based numbering as a Fortran code stores it and
! the dkf_deform_* wrappers. Prints every result's bit pattern for the bit-parity test: the
! output is identical to the C program's.
!
! Build: gfortran -std=f2008 ffi/generated/deform_kernel.f90 deform_and_smooth.f90 \
!        ffi/capi/target/release/libdeform_kernel.a -lm
program deform_and_smooth
  use, intrinsic :: iso_c_binding
  use deform_kernel
  implicit none
  integer, parameter :: NI = 24, NJ = 12, N = NI * NJ, NB = 2 * NI, NC = NI * (NJ - 1)
  integer, parameter :: MAXSCR = 40 * N, MAXEDGE = 8 * NC
  real(c_double) :: points(2, N), out(2, N), tfi(2, N), translations(2, N), rotations(4, N)
  real(c_double) :: deformed(2, NB), node_rot(4, NB), scratch(MAXSCR), values(MAXSCR)
  real(c_double) :: stiffness(MAXEDGE), wall(2, NI), turned(2, NI), q(4), origin(2)
  real(c_double) :: axis(3) = [0.0_c_double, 0.0_c_double, 1.0_c_double]
  real(c_double) :: pivot(2) = [0.25_c_double, 0.0_c_double]
  real(c_double) :: shift(2) = [0.05_c_double, 0.1_c_double]
  real(c_float) :: points32(2, N), out32(2, N), translations32(2, N), rotations32(4, N)
  real(c_float) :: deformed32(2, NB), node_rot32(4, NB), scratch32(MAXSCR), values32(MAXSCR)
  real(c_float) :: stiffness32(MAXEDGE)
  integer(c_int32_t) :: nodes(NB), element_offsets(NB + 1), element_nodes(2 * NB)
  integer(c_int32_t), target :: cell_offsets(NC + 1), cell_nodes(4 * NC), offsets(N + 1)
  integer(c_int32_t), target :: targets(MAXEDGE)
  integer(c_int32_t) :: index_scratch(5 * NB + N)
  integer(c_int32_t) :: cell_scratch(5 * NC + 1) ! 0-based copies of the 1-based cell arrays
  integer(c_int8_t) :: element_kinds(NB), fixed(N)
  integer(c_int8_t), target :: cell_kinds(NC)
  type(dk_cells) :: cells ! the C structs hold the addresses of the target arrays above
  type(dk_graph) :: graph
  integer(c_size_t) :: dims(3) = [int(NI, c_size_t), int(NJ, c_size_t), 1_c_size_t]
  integer(c_size_t) :: length, targets_len, values_len
  type(dk_spring_solve_options) :: options
  type(dk_spring_solve_report) :: spring_report
  type(dk_smooth_arclength_options) :: smooth
  type(dk_smooth_report) :: report
  integer :: k, i, j, lp

  call make_grid(points)
  points32 = real(points, c_float)

  ! The boundary: wall nodes first, then the far field; its segments as 1-based positions in
  ! the boundary list, each loop counter-clockwise.
  do k = 0, NI - 1
    nodes(k + 1) = k + 1
    nodes(NI + k + 1) = NI * (NJ - 1) + k + 1
  end do
  do k = 0, NB - 1
    lp = k / NI * NI
    element_offsets(k + 1) = 2 * k + 1
    element_nodes(2 * k + 1) = k + 1
    element_nodes(2 * k + 2) = lp + mod(k + 1, NI) + 1
  end do
  element_offsets(NB + 1) = 2 * NB + 1
  element_kinds = DK_LINE

  ! The grid's quadrilaterals (periodic in i), their edge graph (always 0-based), Batina's
  ! stiffness and the fixed mask (exactly the boundary nodes).
  do k = 0, NC - 1
    i = mod(k, NI)
    j = k / NI
    cell_offsets(k + 1) = 4 * k + 1
    cell_nodes(4 * k + 1:4 * k + 4) = [i + NI * j, mod(i + 1, NI) + NI * j, &
                                       mod(i + 1, NI) + NI * (j + 1), i + NI * (j + 1)] + 1
  end do
  cell_offsets(NC + 1) = 4 * NC + 1
  cell_kinds = DK_QUAD
  cells = dkf_cells(cell_offsets, cell_nodes, cell_kinds)
  call check(dk_graph_from_cells_len(int(N, c_size_t), cells, 1_c_int32_t, cell_scratch, &
                                     int(5 * NC + 1, c_size_t), .false._c_bool, length), &
             "graph_from_cells_len")
  if (length > MAXEDGE) stop 1
  call check(dk_graph_from_cells(int(N, c_size_t), cells, 1_c_int32_t, cell_scratch, &
                                 int(5 * NC + 1, c_size_t), .false._c_bool, offsets, &
                                 int(N + 1, c_size_t), targets, length, targets_len), &
             "graph_from_cells")
  graph = dkf_graph(offsets, targets(1:targets_len))
  call check(dk_spring_batina_stiffness(graph, points, int(2 * N, c_size_t), 2_c_int32_t, &
                                        1.0_c_double, stiffness, targets_len), "stiffness")
  call check(dk_spring_batina_stiffness_f32(graph, points32, int(2 * N, c_size_t), &
                                            2_c_int32_t, 1.0_c_float, stiffness32, &
                                            targets_len), "stiffness_f32")
  fixed = 0
  fixed(nodes) = 1

  ! The motion: the wall pitches by 0.15 rad about the pivot and plunges; the far field stays.
  call check(dk_quat_from_axis_angle(axis, 0.15_c_double, q), "from_axis_angle")
  do k = 1, NI
    wall(:, k) = points(:, k) - pivot
  end do
  call check(dkf_rotate_points(q, wall, turned), "rotate_points")
  do k = 1, NI
    deformed(1, k) = (turned(1, k) + pivot(1)) + shift(1)
    deformed(2, k) = (turned(2, k) + pivot(2)) + shift(2)
    deformed(:, NI + k) = points(:, nodes(NI + k))
    node_rot(:, k) = q
    node_rot(:, NI + k) = [1.0_c_double, 0.0_c_double, 0.0_c_double, 0.0_c_double]
  end do
  deformed32 = real(deformed, c_float)
  node_rot32 = real(node_rot, c_float)

  ! 1. Inverse-distance weighting, rotations from the boundary shape, default origin.
  call check(dk_deform_idw_scratch_len(int(N, c_size_t), int(NB, c_size_t), 2_c_int32_t, &
                                       length), "idw_scratch_len")
  if (length > MAXSCR) stop 1
  call check(dkf_deform_idw(points, nodes, deformed, 3.0_c_double, scratch(1:length), &
                            index_scratch, translations, rotations, out, &
                            element_offsets=element_offsets, element_nodes=element_nodes, &
                            element_kinds=element_kinds, origin_out=origin), "deform_idw")
  call print_f64("idw_origin", origin)
  call print_f64("idw", reshape(out, [2 * N]))

  ! 2. Transfinite interpolation along j, per-node rotations, origin at the pivot.
  call check(dk_deform_tfi_scratch_len(dims(1), dims(2), dims(3), int(NB, c_size_t), &
                                       2_c_int32_t, length), "tfi_scratch_len")
  if (length > MAXSCR) stop 1
  call check(dkf_deform_tfi(dims, DK_DIRECTION_J, points, nodes, deformed, scratch(1:length), &
                            index_scratch, translations, rotations, tfi, &
                            element_offsets=element_offsets, element_nodes=element_nodes, &
                            element_kinds=element_kinds, node_rotations=node_rot, &
                            origin=pivot), "deform_tfi")
  call print_f64("tfi", reshape(tfi, [2 * N]))

  ! 3. Linear springs (CG, Jacobi preconditioner), rotations from the boundary shape.
  call check(dk_spring_solve_options_default(options), "solve_options_default")
  call check(dk_deform_spring_scratch_len(int(N, c_size_t), int(NB, c_size_t), 2_c_int32_t, &
                                          options, length, values_len), "spring_scratch_len")
  if (length > MAXSCR .or. values_len > MAXSCR) stop 1
  call check(dkf_deform_spring(points, nodes, deformed, offsets, targets(1:targets_len), &
                               stiffness(1:targets_len), fixed, options, scratch(1:length), &
                               values(1:values_len), index_scratch, translations, rotations, &
                               out, spring_report, element_offsets=element_offsets, &
                               element_nodes=element_nodes, element_kinds=element_kinds, &
                               origin_out=origin), "deform_spring")
  call print_f64("spring_origin", origin)
  call print_f64("spring", reshape(out, [2 * N]))
  if (spring_report%converged) then
    write (*, '(a)') "spring_converged 1"
  else
    write (*, '(a)') "spring_converged 0"
  end if

  ! 4. Taubin smoothing of the TFI grid's radial lines (normalised arclength).
  call check(dk_smooth_arclength_options_default(1_c_int32_t, smooth), "smooth_options")
  smooth%normalised = 1
  smooth%iterations = 10
  call check(dk_taubin_smooth_arclength_scratch_len(dims(1), dims(2), dims(3), smooth, &
                                                    2_c_int32_t, length), "smooth_scratch_len")
  if (length > MAXSCR) stop 1
  call check(dk_taubin_smooth_arclength(dims(1), dims(2), dims(3), smooth, tfi, &
                                        int(2 * N, c_size_t), 2_c_int32_t, scratch, length, &
                                        report), "smooth_arclength")
  call print_f64("smoothed", reshape(tfi, [2 * N]))
  write (*, '(a, i0)') "smooth_iterations ", report%iterations

  ! The same steps in single precision.
  call check(dk_deform_idw_scratch_len(int(N, c_size_t), int(NB, c_size_t), 2_c_int32_t, &
                                       length), "idw_scratch_len")
  call check(dkf_deform_idw_f32(points32, nodes, deformed32, 3.0_c_float, scratch32(1:length), &
                                index_scratch, translations32, rotations32, out32, &
                                element_offsets=element_offsets, element_nodes=element_nodes, &
                                element_kinds=element_kinds), "deform_idw_f32")
  call print_f32("idw_f32", reshape(out32, [2 * N]))

  call check(dk_deform_tfi_scratch_len(dims(1), dims(2), dims(3), int(NB, c_size_t), &
                                       2_c_int32_t, length), "tfi_scratch_len")
  call check(dkf_deform_tfi_f32(dims, DK_DIRECTION_J, points32, nodes, deformed32, &
                                scratch32(1:length), index_scratch, translations32, &
                                rotations32, out32, element_offsets=element_offsets, &
                                element_nodes=element_nodes, element_kinds=element_kinds, &
                                node_rotations=node_rot32, origin=real(pivot, c_float)), &
             "deform_tfi_f32")
  call print_f32("tfi_f32", reshape(out32, [2 * N]))

  call check(dk_taubin_smooth_arclength_scratch_len(dims(1), dims(2), dims(3), smooth, &
                                                    2_c_int32_t, length), "smooth_scratch_len")
  call check(dk_taubin_smooth_arclength_f32(dims(1), dims(2), dims(3), smooth, out32, &
                                            int(2 * N, c_size_t), 2_c_int32_t, scratch32, &
                                            length, report), "smooth_arclength_f32")
  call print_f32("smoothed_f32", reshape(out32, [2 * N]))

  call check(dk_spring_solve_options_default_f32(options), "solve_options_default_f32")
  call check(dk_deform_spring_scratch_len(int(N, c_size_t), int(NB, c_size_t), 2_c_int32_t, &
                                          options, length, values_len), "spring_scratch_len")
  call check(dkf_deform_spring_f32(points32, nodes, deformed32, offsets, &
                                   targets(1:targets_len), stiffness32(1:targets_len), fixed, &
                                   options, scratch32(1:length), values32(1:values_len), &
                                   index_scratch, translations32, rotations32, out32, &
                                   spring_report, element_offsets=element_offsets, &
                                   element_nodes=element_nodes, element_kinds=element_kinds), &
             "deform_spring_f32")
  call print_f32("spring_f32", reshape(out32, [2 * N]))

contains

  ! The O-grid of deform_and_smooth.c, point (i, j) in column i + NI j + 1, with the same
  ! operations in the same order (+ - * / only), so the bits agree.
  subroutine make_grid(p)
    real(c_double), intent(out) :: p(2, N)
    integer :: m, ii, jj
    real(c_double) :: f, s, t, c, d, cx, cy, wx, wy, fx, fy
    m = NI / 4
    do jj = 0, NJ - 1
      f = real(jj, c_double) / real(NJ - 1, c_double)
      s = f * f
      do ii = 0, NI - 1
        t = real(mod(ii, m), c_double) / real(m, c_double)
        c = (1.0_c_double - t * t) / (1.0_c_double + t * t)
        d = (2.0_c_double * t) / (1.0_c_double + t * t)
        select case (ii / m)
        case (0)
          cx = c
          cy = d
        case (1)
          cx = -d
          cy = c
        case (2)
          cx = -c
          cy = -d
        case default
          cx = d
          cy = -c
        end select
        wx = cx
        wy = 0.4_c_double * cy
        fx = 8.0_c_double * cx
        fy = 8.0_c_double * cy
        p(1, ii + NI * jj + 1) = wx + s * (fx - wx)
        p(2, ii + NI * jj + 1) = wy + s * (fy - wy)
      end do
    end do
  end subroutine

  subroutine check(status, what)
    integer(c_int32_t), intent(in) :: status
    character(len=*), intent(in) :: what
    if (status /= DK_OK) then
      write (0, '(a, a, a)') what, " failed: ", dk_status_message(status)
      stop 1
    end if
  end subroutine

  subroutine print_f64(name, v)
    character(len=*), intent(in) :: name
    real(c_double), intent(in) :: v(:)
    integer :: kk
    write (*, '(a)', advance='no') name
    do kk = 1, size(v)
      write (*, '(a, z16.16)', advance='no') " ", transfer(v(kk), 0_c_int64_t)
    end do
    write (*, '(a)') ""
  end subroutine

  subroutine print_f32(name, v)
    character(len=*), intent(in) :: name
    real(c_float), intent(in) :: v(:)
    integer :: kk
    write (*, '(a)', advance='no') name
    do kk = 1, size(v)
      write (*, '(a, z8.8)', advance='no') " ", transfer(v(kk), 0_c_int32_t)
    end do
    write (*, '(a)') ""
  end subroutine

end program deform_and_smooth
