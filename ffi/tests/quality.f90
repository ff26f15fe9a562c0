! Mesh quality from Fortran through the dkf_quality_* wrappers (f64 and _f32) on a 2 x 2
! grid of unit-half squares: exact measures and scaled Jacobians, a rigid motion compared
! (no inversion, ratios 1, wall angle unchanged), a fold detected, a partial wall refused.
! Prints "quality: every check held" when every check holds.
program quality
  use, intrinsic :: iso_c_binding, only: c_double, c_float, c_int32_t, c_int8_t, c_size_t
  use deform_kernel
  implicit none

  integer(c_int32_t) :: cell_offsets(5), cell_nodes(16), offsets(10), wall_offsets(3), &
                        wall_nodes(4)
  integer(c_int32_t), allocatable :: targets(:)
  integer(c_int8_t) :: cell_kinds(4), wall_kinds(2)
  real(c_double) :: points(2, 9), moved(2, 9), measures(4), jac(4), c, s
  real(c_float) :: points32(2, 9), measures32(4)
  integer(c_size_t) :: targets_len, used
  type(dk_quality_report) :: report
  integer :: i, failures

  failures = 0
  do i = 0, 8
    points(1, i + 1) = 0.5_c_double * real(mod(i, 3), c_double)
    points(2, i + 1) = 0.5_c_double * real(i / 3, c_double)
  end do
  cell_offsets = [1, 5, 9, 13, 17]
  cell_nodes = [1, 2, 5, 4, 2, 3, 6, 5, 4, 5, 8, 7, 5, 6, 9, 8]
  cell_kinds = DK_QUAD
  wall_offsets = [1, 3, 5]
  wall_nodes = [1, 2, 2, 3]
  wall_kinds = DK_LINE

  call expect(dkf_quality_cell_measures(cell_offsets, cell_nodes, cell_kinds, points, &
                                        measures) == DK_OK, 'measures status')
  call expect(all(measures == 0.25_c_double), 'measures exact')
  call expect(dkf_quality_min_corner_jacobians(cell_offsets, cell_nodes, cell_kinds, points, &
                                               .true., jac) == DK_OK, 'jacobians status')
  call expect(all(abs(jac - 1.0_c_double) <= 4 * epsilon(1.0_c_double)), 'square jacobians')
  points32 = real(points, c_float)
  call expect(dkf_quality_cell_measures_f32(cell_offsets, cell_nodes, cell_kinds, points32, &
                                            measures32) == DK_OK, 'f32 measures status')
  call expect(all(measures32 == 0.25_c_float), 'f32 measures exact')

  ! A rigid motion: no inversion, ratios 1, the wall angle unchanged.
  call expect(dkf_graph_from_cells_len(9_c_size_t, cell_offsets, cell_nodes, cell_kinds, &
                                       .false., targets_len) == DK_OK, 'graph length')
  allocate(targets(targets_len))
  call expect(dkf_graph_from_cells(9_c_size_t, cell_offsets, cell_nodes, cell_kinds, .false., &
                                   offsets, targets, used) == DK_OK, 'graph')
  c = cos(0.3_c_double)
  s = sin(0.3_c_double)
  moved(1, :) = c * points(1, :) - s * points(2, :) + 2.0_c_double
  moved(2, :) = s * points(1, :) + c * points(2, :) - 1.0_c_double
  call expect(dkf_quality_compare(cell_offsets, cell_nodes, cell_kinds, points, moved, report, &
                                  wall_offsets, wall_nodes, wall_kinds, offsets, &
                                  targets(1:used)) == DK_OK, 'compare status')
  call expect(report%cells == 4 .and. report%inverted_cells == 0 .and. &
              report%folded_cells == 0, 'rigid: nothing inverted or folded')
  call expect(abs(report%min_measure_ratio - 1.0_c_double) < 1e-12_c_double .and. &
              abs(report%max_measure_ratio - 1.0_c_double) < 1e-12_c_double, 'rigid: ratios 1')
  call expect(logical(report%has_wall) .and. report%wall_max_change < 1e-12_c_double, &
              'rigid: wall angle unchanged')

  ! The centre node pushed through the corner: cells invert.
  moved = points
  moved(:, 5) = [-0.4_c_double, -0.4_c_double]
  call expect(dkf_quality_compare(cell_offsets, cell_nodes, cell_kinds, points, moved, &
                                  report) == DK_OK, 'fold status')
  call expect(report%inverted_cells >= 1 .and. report%min_scaled_jacobian < 0.0_c_double, &
              'fold: inverted cells found')
  call expect(.not. logical(report%has_wall), 'no wall given')

  ! Part of a wall is an error, not a silent no-wall comparison.
  call expect(dkf_quality_compare(cell_offsets, cell_nodes, cell_kinds, points, moved, report, &
                                  wall_offsets, wall_nodes) == DK_ERR_LENGTH_MISMATCH, &
              'partial wall refused')

  if (failures /= 0) error stop 1
  write(*, '(A)') 'quality: every check held'

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
