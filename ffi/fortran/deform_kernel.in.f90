! deform-kernel Fortran 2008 bindings (iso_c_binding).
!
! Every function returns an integer(c_int32_t) status: DK_OK (0) is success, anything else is a
! dk_status code (see deform_kernel.h); dk_status_message() describes it. Outputs are written
! only on success. Mesh node indices may be passed 1-based as they are (index_base = 1).
! Functions ending in _f32 take real(c_float) arrays. The dkf_* wrappers take assumed-shape
! contiguous arrays and pass their sizes for you.
module deform_kernel
  use, intrinsic :: iso_c_binding, only: c_int32_t, c_int64_t, c_int8_t, c_size_t, c_double, c_float, &
                                         c_bool, c_ptr, c_funptr, c_char, c_f_pointer, c_associated
  implicit none
  private

  ! The hand-kept part of the module: `cargo xtask codegen` writes ffi/generated/deform_kernel.f90,
  ! this file with, before `contains`, the constants and bind(C) types read from the C header
  ! (so their layouts are the C ones) and the bind(C) interfaces of the C functions, and before
  ! `end module` the _f32 twins of the wrappers marked "Has an _f32 twin".
  ! Pointer fields (type(c_ptr)) take c_loc of a contiguous target array, or c_null_ptr
  ! with length 0 where a field is optional. Flags are integer(c_int8_t) or integer(c_int32_t),
  ! nonzero = true. Options and reports have real(c_double) fields for both precisions (the
  ! _f32 functions round options to float); fill options with the *_default functions.

  ! VTK cell kind codes.
  integer(c_int8_t), parameter, public :: DK_LINE = 3_c_int8_t, DK_TRIANGLE = 5_c_int8_t, &
       DK_QUAD = 9_c_int8_t, DK_TETRA = 10_c_int8_t, DK_HEXAHEDRON = 12_c_int8_t, &
       DK_PRISM = 13_c_int8_t, DK_PYRAMID = 14_c_int8_t

  public :: dk_status_str, dk_status_message
  public :: dkf_graph, dkf_cells, dkf_spring_system, dkf_spring_system_f32, dkf_plan_pools, &
            dkf_plan_pools_f32, dkf_constraints, dkf_constraints_f32
  public :: dkf_rotate_points, dkf_graph_from_edges, dkf_graph_from_cells_len, &
            dkf_graph_from_cells
  public :: dkf_quality_cell_measures, dkf_quality_cell_measures_f32, &
            dkf_quality_min_corner_jacobians, dkf_quality_min_corner_jacobians_f32, &
            dkf_quality_compare, dkf_quality_compare_f32
  public :: dkf_plan_pool_sizes, dkf_plan_pool_sizes_f32, dkf_plan_init, dkf_plan_init_f32, &
            dkf_plan_step, dkf_plan_step_f32, dkf_plan_open, dkf_plan_open_f32
  public :: dkf_spring_solve_linear_amg, dkf_spring_solve_linear_amg_f32
  public :: dkf_spring_solve_linear, dkf_taubin_smooth_arclength, dkf_taubin_smooth_structured, &
            dkf_taubin_smooth_graph, dkf_spring_solve_linear_sliding
  public :: dkf_deform_idw, dkf_deform_idw_f32, dkf_deform_tfi, dkf_deform_tfi_f32
  public :: dkf_deform_spring, dkf_deform_spring_f32

  interface
    function dk_status_str(status) bind(C, name="dk_status_str") result(p)
      import :: c_int32_t, c_ptr
      integer(c_int32_t), value :: status
      type(c_ptr) :: p
    end function

    function c_strlen(s) bind(C, name="strlen") result(n)
      import :: c_ptr, c_size_t
      type(c_ptr), value :: s
      integer(c_size_t) :: n
    end function
  end interface


contains

  !> The English description of a status code.
  function dk_status_message(status) result(msg)
    integer(c_int32_t), intent(in) :: status
    character(len=:), allocatable :: msg
    type(c_ptr) :: p
    character(kind=c_char), pointer :: chars(:)
    integer(c_size_t) :: n, i
    p = dk_status_str(status)
    if (.not. c_associated(p)) then
      msg = ""
      return
    end if
    n = c_strlen(p)
    call c_f_pointer(p, chars, [n])
    allocate(character(len=n) :: msg)
    do i = 1, n
      msg(i:i) = chars(i)
    end do
  end function

  !> Rotates points(3, n) by q into out(3, n), or points(2, n) of the plane z = 0 (q a rotation
  !> about z) into out(2, n).
  function dkf_rotate_points(q, points, out) result(s)
    real(c_double), intent(in) :: q(4)
    real(c_double), intent(in), contiguous :: points(:, :)
    real(c_double), intent(inout), contiguous :: out(:, :)
    integer(c_int32_t) :: s
    integer(c_size_t) :: n, m
    n = size(points, kind=c_size_t)
    m = size(out, kind=c_size_t)
    s = DK_ERR_LENGTH_MISMATCH
    if (size(out, 1) /= size(points, 1)) return
    if (size(points, 1) == 3) s = dk_quat_rotate_points(q, points, n, out, m)
    if (size(points, 1) == 2) s = dk_quat_rotate_points_2d(q, points, n, out, m)
  end function

  !> Graph of an edge list edges(2, m) with 1-based node numbers; offsets(node_count + 1).
  function dkf_graph_from_edges(node_count, edges, offsets, targets, used) result(s)
    integer(c_size_t), intent(in) :: node_count
    integer(c_int32_t), intent(in), contiguous :: edges(:, :)
    integer(c_int32_t), intent(inout), contiguous :: offsets(:), targets(:)
    integer(c_size_t), intent(inout) :: used
    integer(c_int32_t) :: s
    integer(c_int32_t), allocatable :: index_scratch(:)
    allocate(index_scratch(size(edges)))
    s = dk_graph_from_edges(node_count, edges, int(size(edges), c_size_t), 1_c_int32_t, &
                            index_scratch, int(size(index_scratch), c_size_t), offsets, &
                            int(size(offsets), c_size_t), targets, int(size(targets), c_size_t), &
                            used)
  end function

  !> Length targets needs for dkf_graph_from_cells (1-based cell offsets and nodes).
  function dkf_graph_from_cells_len(node_count, cell_offsets, cell_nodes, cell_kinds, &
                                    face_diagonals, len) result(s)
    integer(c_size_t), intent(in) :: node_count
    integer(c_int32_t), intent(in), target, contiguous :: cell_offsets(:), cell_nodes(:)
    integer(c_int8_t), intent(in), target, contiguous :: cell_kinds(:)
    logical, intent(in) :: face_diagonals
    integer(c_size_t), intent(inout) :: len
    integer(c_int32_t) :: s
    integer(c_int32_t), allocatable :: index_scratch(:)
    allocate(index_scratch(size(cell_offsets) + size(cell_nodes)))
    s = dk_graph_from_cells_len(node_count, dkf_cells(cell_offsets, cell_nodes, cell_kinds), &
                                1_c_int32_t, index_scratch, size(index_scratch, kind=c_size_t), &
                                logical(face_diagonals, c_bool), len)
  end function

  !> Edge graph of a mixed-cell mesh given with 1-based cell offsets and node numbers.
  function dkf_graph_from_cells(node_count, cell_offsets, cell_nodes, cell_kinds, &
                                face_diagonals, offsets, targets, used) result(s)
    integer(c_size_t), intent(in) :: node_count
    integer(c_int32_t), intent(in), target, contiguous :: cell_offsets(:), cell_nodes(:)
    integer(c_int8_t), intent(in), target, contiguous :: cell_kinds(:)
    logical, intent(in) :: face_diagonals
    integer(c_int32_t), intent(inout), contiguous :: offsets(:), targets(:)
    integer(c_size_t), intent(inout) :: used
    integer(c_int32_t) :: s
    integer(c_int32_t), allocatable :: index_scratch(:)
    allocate(index_scratch(size(cell_offsets) + size(cell_nodes)))
    s = dk_graph_from_cells(node_count, dkf_cells(cell_offsets, cell_nodes, cell_kinds), &
                            1_c_int32_t, index_scratch, size(index_scratch, kind=c_size_t), &
                            logical(face_diagonals, c_bool), offsets, &
                            int(size(offsets), c_size_t), targets, int(size(targets), c_size_t), &
                            used)
  end function

  !> dk_spring_solve_linear with assumed-shape arrays: values(components, node_count) is
  !> updated in place (components = size(values, 1), 1 to 7); offsets/targets are the 0-based
  !> CSR graph from dk_graph_from_*; scratch needs dk_spring_solve_linear_scratch_len values
  !> (may be empty for Gauss-Seidel and SOR), index_scratch node_count entries.
  function dkf_spring_solve_linear(offsets, targets, stiffness, fixed, options, values, &
                                   scratch, index_scratch, report) result(s)
    integer(c_int32_t), intent(in), target, contiguous :: offsets(:), targets(:)
    real(c_double), intent(in), target, contiguous :: stiffness(:)
    integer(c_int8_t), intent(in), target, contiguous :: fixed(:)
    type(dk_spring_solve_options), intent(in) :: options
    real(c_double), intent(inout), contiguous :: values(:, :)
    real(c_double), intent(inout), contiguous :: scratch(:)
    integer(c_int32_t), intent(inout), contiguous :: index_scratch(:)
    type(dk_spring_solve_report), intent(inout) :: report
    integer(c_int32_t) :: s
    s = dk_spring_solve_linear(dkf_spring_system(dkf_graph(offsets, targets), stiffness, fixed), &
                               options, int(size(values, 1), c_int32_t), values, &
                               int(size(values), c_size_t), scratch, int(size(scratch), c_size_t), &
                               index_scratch, int(size(index_scratch), c_size_t), report)
  end function

  !> dk_spring_solve_linear_sliding with assumed-shape arrays: values(dim, node_count)
  !> (displacements, dim = size(values, 1), 2 or 3) is updated in place; kinds(node_count) and
  !> directions(dim, node_count) as for dkf_constraints, fixed the mask
  !> dk_constraints_fixed_mask writes; scratch needs dk_spring_solve_linear_sliding_scratch_len
  !> values, index_scratch node_count entries; the rest as dkf_spring_solve_linear.
  function dkf_spring_solve_linear_sliding(offsets, targets, stiffness, fixed, kinds, &
                                           directions, options, values, scratch, &
                                           index_scratch, report) result(s)
    integer(c_int32_t), intent(in), target, contiguous :: offsets(:), targets(:)
    real(c_double), intent(in), target, contiguous :: stiffness(:)
    integer(c_int8_t), intent(in), target, contiguous :: fixed(:), kinds(:)
    real(c_double), intent(in), target, contiguous :: directions(:, :)
    type(dk_spring_solve_options), intent(in) :: options
    real(c_double), intent(inout), contiguous :: values(:, :)
    real(c_double), intent(inout), contiguous :: scratch(:)
    integer(c_int32_t), intent(inout), contiguous :: index_scratch(:)
    type(dk_spring_solve_report), intent(inout) :: report
    integer(c_int32_t) :: s
    s = dk_spring_solve_linear_sliding(dkf_spring_system(dkf_graph(offsets, targets), &
                                                         stiffness, fixed), &
                                       dkf_constraints(kinds, directions), options, &
                                       int(size(values, 1), c_int32_t), values, &
                                       int(size(values), c_size_t), scratch, &
                                       int(size(scratch), c_size_t), index_scratch, &
                                       int(size(index_scratch), c_size_t), report)
  end function

  !> dk_spring_solve_linear_amg with assumed-shape arrays: values(components, node_count) is
  !> updated in place (components = size(values, 1), 1 to 7); offsets/targets are the 0-based
  !> CSR graph from dk_graph_from_*; options gives the stopping rules, amg the multigrid options
  !> (dk_amg_options_default). The hierarchy's pools are sized (dk_spring_amg_work_len,
  !> dk_spring_solve_linear_amg_pool_sizes) and allocated here, and the hierarchy is rebuilt on
  !> every call; a plan (dkf_plan_*) keeps it across time steps.
  !> Has an _f32 twin (generated: c_double becomes c_float).
  function dkf_spring_solve_linear_amg(offsets, targets, stiffness, fixed, options, amg, values, &
                                       report) result(s)
    integer(c_int32_t), intent(in), target, contiguous :: offsets(:), targets(:)
    real(c_double), intent(in), target, contiguous :: stiffness(:)
    integer(c_int8_t), intent(in), target, contiguous :: fixed(:)
    type(dk_spring_solve_options), intent(in) :: options
    type(dk_amg_options), intent(in) :: amg
    real(c_double), intent(inout), contiguous :: values(:, :)
    type(dk_spring_solve_report), intent(inout) :: report
    integer(c_int32_t) :: s
    type(dk_spring_system) :: sys
    type(dk_plan_sizes) :: sizes
    integer(c_size_t) :: work_len
    real(c_double), allocatable, target :: reals(:)
    integer(c_int32_t), allocatable, target :: indices(:)
    integer(c_int8_t), allocatable, target :: bytes(:)
    sys = dkf_spring_system(dkf_graph(offsets, targets), stiffness, fixed)
    s = dk_spring_amg_work_len(max(size(offsets, kind=c_size_t) - 1, 0_c_size_t), &
                               size(targets, kind=c_size_t), work_len)
    if (s /= DK_OK) return
    allocate(indices(max(work_len, 1_c_size_t)))
    s = dk_spring_solve_linear_amg_pool_sizes(sys, int(size(values, 1), c_int32_t), amg, indices, &
                                              work_len, sizes)
    if (s /= DK_OK) return
    deallocate(indices)
    allocate(reals(max(sizes%reals, 1_c_size_t)), indices(max(sizes%indices, 1_c_size_t)), &
             bytes(1))
    s = dk_spring_solve_linear_amg(sys, options, amg, int(size(values, 1), c_int32_t), values, &
                                   size(values, kind=c_size_t), dkf_plan_pools(reals, indices, bytes), &
                                   report)
  end function

  !> dk_taubin_smooth_arclength with assumed-shape arrays: points(dim, ni*nj*nk) (dim 2 or 3)
  !> is updated in place; scratch needs dk_taubin_smooth_arclength_scratch_len values.
  function dkf_taubin_smooth_arclength(ni, nj, nk, options, points, scratch, report) result(s)
    integer(c_size_t), intent(in) :: ni, nj, nk
    type(dk_smooth_arclength_options), intent(in) :: options
    real(c_double), intent(inout), contiguous :: points(:, :)
    real(c_double), intent(inout), contiguous :: scratch(:)
    type(dk_smooth_report), intent(inout) :: report
    integer(c_int32_t) :: s
    s = dk_taubin_smooth_arclength(ni, nj, nk, options, points, int(size(points), c_size_t), &
                                   int(size(points, 1), c_int32_t), scratch, &
                                   int(size(scratch), c_size_t), report)
  end function

  !> dk_taubin_smooth_structured with assumed-shape arrays: field (ni*nj*nk values, any
  !> shape, i fastest) is updated in place; scratch needs ni*nj*nk values.
  function dkf_taubin_smooth_structured(ni, nj, nk, lambda, mu, iterations, options, field, &
                                        scratch, report) result(s)
    integer(c_size_t), intent(in) :: ni, nj, nk, iterations
    real(c_double), intent(in) :: lambda, mu
    type(dk_structured_options), intent(in) :: options
    real(c_double), intent(inout), contiguous :: field(:)
    real(c_double), intent(inout), contiguous :: scratch(:)
    type(dk_filter_report), intent(inout) :: report
    integer(c_int32_t) :: s
    s = dk_taubin_smooth_structured(ni, nj, nk, lambda, mu, iterations, options, field, &
                                    int(size(field), c_size_t), scratch, &
                                    int(size(scratch), c_size_t), report)
  end function

  !> dk_taubin_smooth_graph with assumed-shape arrays: values(components, node_count) is
  !> updated in place (components = size(values, 1), 1 to 7); weights (one per directed edge)
  !> and fixed (one per node, nonzero = fixed) are optional; scratch needs size(values) values.
  function dkf_taubin_smooth_graph(offsets, targets, lambda, mu, iterations, values, scratch, &
                                   report, weights, fixed) result(s)
    use, intrinsic :: iso_c_binding, only: c_loc, c_null_ptr
    integer(c_int32_t), intent(in), target, contiguous :: offsets(:), targets(:)
    real(c_double), intent(in) :: lambda, mu
    integer(c_size_t), intent(in) :: iterations
    real(c_double), intent(inout), contiguous :: values(:, :)
    real(c_double), intent(inout), contiguous :: scratch(:)
    type(dk_filter_report), intent(inout) :: report
    real(c_double), intent(in), contiguous, target, optional :: weights(:)
    integer(c_int8_t), intent(in), contiguous, target, optional :: fixed(:)
    integer(c_int32_t) :: s
    type(c_ptr) :: w, f
    integer(c_size_t) :: wl, fl
    w = c_null_ptr
    f = c_null_ptr
    wl = 0
    fl = 0
    if (present(weights)) then
      wl = size(weights, kind=c_size_t)
      if (wl > 0) w = c_loc(weights)
    end if
    if (present(fixed)) then
      fl = size(fixed, kind=c_size_t)
      if (fl > 0) f = c_loc(fixed)
    end if
    s = dk_taubin_smooth_graph(dkf_graph(offsets, targets), w, wl, f, fl, lambda, mu, &
                               iterations, int(size(values, 1), c_int32_t), values, &
                               int(size(values), c_size_t), scratch, int(size(scratch), c_size_t), &
                               report)
  end function
  !> Fills m for the dkf_deform_* wrappers: 1-based nodes(b) and deformed(dim, b); optional
  !> boundary elements (1-based offsets and positions in nodes, VTK kinds), rigid_rotation(4)
  !> or node_rotations(4, b) (else the rotations come from the shape), origin(dim) (else the
  !> default origin). The pointers stay valid while the actual arguments do.
  !> Has an _f32 twin (generated: c_double becomes c_float).
  subroutine dkf_fill_motion(m, nodes, deformed, element_offsets, element_nodes, &
                             element_kinds, rigid_rotation, node_rotations, origin)
    use, intrinsic :: iso_c_binding, only: c_loc
    type(dk_boundary_motion), intent(inout) :: m
    integer(c_int32_t), intent(in), target, contiguous :: nodes(:)
    real(c_double), intent(in), target, contiguous :: deformed(:, :)
    integer(c_int32_t), intent(in), target, contiguous, optional :: element_offsets(:), &
                                                                     element_nodes(:)
    integer(c_int8_t), intent(in), target, contiguous, optional :: element_kinds(:)
    real(c_double), intent(in), optional :: rigid_rotation(4)
    real(c_double), intent(in), target, contiguous, optional :: node_rotations(:, :)
    real(c_double), intent(in), optional :: origin(:)
    integer(c_int32_t) :: s
    integer :: k
    s = dk_boundary_motion_default(m)
    m%index_base = 1
    m%nodes = c_loc(nodes)
    m%nodes_len = size(nodes, kind=c_size_t)
    m%deformed = c_loc(deformed)
    m%deformed_len = size(deformed, kind=c_size_t)
    if (present(element_offsets) .and. present(element_nodes) .and. present(element_kinds)) then
      m%elements = dkf_cells(element_offsets, element_nodes, element_kinds)
    end if
    if (present(rigid_rotation)) then
      m%rotation_source = DK_ROTATIONS_RIGID
      m%rigid_rotation = rigid_rotation
    else if (present(node_rotations)) then
      m%rotation_source = DK_ROTATIONS_PER_NODE
      m%node_rotations = c_loc(node_rotations)
      m%node_rotations_len = size(node_rotations, kind=c_size_t)
    end if
    if (present(origin)) then
      m%has_origin = 1
      do k = 1, min(size(origin), 3)
        m%origin(k) = origin(k)
      end do
    end if
  end subroutine

  !> dk_deform_idw with Fortran arrays and 1-based node numbers: points(dim, n), nodes(b),
  !> deformed(dim, b); scratch(:) (dk_deform_idw_scratch_len), index_scratch(:) (at least
  !> size(nodes) + size(element_offsets) + size(element_nodes)), translations(dim, n) and
  !> rotations(4, n) (workspaces); out(dim, n). Optional arguments as dkf_fill_motion, and
  !> origin_out(dim) for the origin used.
  !> Has an _f32 twin (generated: c_double becomes c_float).
  function dkf_deform_idw(points, nodes, deformed, exponent, scratch, index_scratch, &
                          translations, rotations, out, element_offsets, element_nodes, &
                          element_kinds, rigid_rotation, node_rotations, origin, origin_out) &
      result(s)
    real(c_double), intent(in), contiguous :: points(:, :)
    integer(c_int32_t), intent(in), target, contiguous :: nodes(:)
    real(c_double), intent(in), target, contiguous :: deformed(:, :)
    real(c_double), intent(in) :: exponent
    real(c_double), intent(inout), contiguous :: scratch(:), translations(:, :), &
                                                 rotations(:, :), out(:, :)
    integer(c_int32_t), intent(inout), contiguous :: index_scratch(:)
    integer(c_int32_t), intent(in), target, contiguous, optional :: element_offsets(:), &
                                                                     element_nodes(:)
    integer(c_int8_t), intent(in), target, contiguous, optional :: element_kinds(:)
    real(c_double), intent(in), optional :: rigid_rotation(4)
    real(c_double), intent(in), target, contiguous, optional :: node_rotations(:, :)
    real(c_double), intent(in), optional :: origin(:)
    real(c_double), intent(inout), target, contiguous, optional :: origin_out(:)
    integer(c_int32_t) :: s
    type(dk_boundary_motion) :: m
    real(c_double), target :: none(1)
    real(c_double), pointer, contiguous :: o(:)
    call dkf_fill_motion(m, nodes, deformed, element_offsets, element_nodes, element_kinds, &
                         rigid_rotation, node_rotations, origin)
    o => none(1:0)
    if (present(origin_out)) o => origin_out
    s = dk_deform_idw(points, size(points, kind=c_size_t), int(size(points, 1), c_int32_t), &
                      m, exponent, scratch, size(scratch, kind=c_size_t), index_scratch, &
                      size(index_scratch, kind=c_size_t), translations, &
                      size(translations, kind=c_size_t), rotations, &
                      size(rotations, kind=c_size_t), out, size(out, kind=c_size_t), &
                      o, size(o, kind=c_size_t))
  end function

  !> dk_deform_tfi with Fortran arrays: a dims(1) x dims(2) x dims(3) block (dims(3) = 1 in
  !> 2D), directions a sum of DK_DIRECTION_*; other arguments as dkf_deform_idw (scratch:
  !> dk_deform_tfi_scratch_len).
  !> Has an _f32 twin (generated: c_double becomes c_float).
  function dkf_deform_tfi(dims, directions, points, nodes, deformed, scratch, index_scratch, &
                          translations, rotations, out, element_offsets, element_nodes, &
                          element_kinds, rigid_rotation, node_rotations, origin, origin_out) &
      result(s)
    integer(c_size_t), intent(in) :: dims(3)
    integer(c_int32_t), intent(in) :: directions
    real(c_double), intent(in), contiguous :: points(:, :)
    integer(c_int32_t), intent(in), target, contiguous :: nodes(:)
    real(c_double), intent(in), target, contiguous :: deformed(:, :)
    real(c_double), intent(inout), contiguous :: scratch(:), translations(:, :), &
                                                 rotations(:, :), out(:, :)
    integer(c_int32_t), intent(inout), contiguous :: index_scratch(:)
    integer(c_int32_t), intent(in), target, contiguous, optional :: element_offsets(:), &
                                                                     element_nodes(:)
    integer(c_int8_t), intent(in), target, contiguous, optional :: element_kinds(:)
    real(c_double), intent(in), optional :: rigid_rotation(4)
    real(c_double), intent(in), target, contiguous, optional :: node_rotations(:, :)
    real(c_double), intent(in), optional :: origin(:)
    real(c_double), intent(inout), target, contiguous, optional :: origin_out(:)
    integer(c_int32_t) :: s
    type(dk_boundary_motion) :: m
    real(c_double), target :: none(1)
    real(c_double), pointer, contiguous :: o(:)
    call dkf_fill_motion(m, nodes, deformed, element_offsets, element_nodes, element_kinds, &
                         rigid_rotation, node_rotations, origin)
    o => none(1:0)
    if (present(origin_out)) o => origin_out
    s = dk_deform_tfi(dims(1), dims(2), dims(3), directions, points, &
                      size(points, kind=c_size_t), int(size(points, 1), c_int32_t), m, &
                      scratch, size(scratch, kind=c_size_t), index_scratch, &
                      size(index_scratch, kind=c_size_t), translations, &
                      size(translations, kind=c_size_t), rotations, &
                      size(rotations, kind=c_size_t), out, size(out, kind=c_size_t), &
                      o, size(o, kind=c_size_t))
  end function

  !> dk_deform_spring with Fortran arrays: the 0-based CSR graph offsets(n + 1), targets(:)
  !> from dkf_graph_from_*, stiffness(size(targets)), fixed(n) (nonzero = boundary node),
  !> options; values(:) (second length of dk_deform_spring_scratch_len); index_scratch(:) at
  !> least size(nodes) + size(element_offsets) + size(element_nodes) + n; report receives the
  !> solver report. Other arguments as dkf_deform_idw.
  !> Has an _f32 twin (generated: c_double becomes c_float).
  function dkf_deform_spring(points, nodes, deformed, offsets, targets, stiffness, fixed, &
                             options, scratch, values, index_scratch, translations, rotations, &
                             out, report, element_offsets, element_nodes, element_kinds, &
                             rigid_rotation, node_rotations, origin, origin_out) result(s)
    real(c_double), intent(in), contiguous :: points(:, :)
    integer(c_int32_t), intent(in), target, contiguous :: nodes(:)
    real(c_double), intent(in), target, contiguous :: deformed(:, :)
    integer(c_int32_t), intent(in), target, contiguous :: offsets(:), targets(:)
    real(c_double), intent(in), target, contiguous :: stiffness(:)
    integer(c_int8_t), intent(in), target, contiguous :: fixed(:)
    type(dk_spring_solve_options), intent(in) :: options
    real(c_double), intent(inout), contiguous :: scratch(:), values(:), translations(:, :), &
                                                 rotations(:, :), out(:, :)
    integer(c_int32_t), intent(inout), contiguous :: index_scratch(:)
    type(dk_spring_solve_report), intent(inout) :: report
    integer(c_int32_t), intent(in), target, contiguous, optional :: element_offsets(:), &
                                                                     element_nodes(:)
    integer(c_int8_t), intent(in), target, contiguous, optional :: element_kinds(:)
    real(c_double), intent(in), optional :: rigid_rotation(4)
    real(c_double), intent(in), target, contiguous, optional :: node_rotations(:, :)
    real(c_double), intent(in), optional :: origin(:)
    real(c_double), intent(inout), target, contiguous, optional :: origin_out(:)
    integer(c_int32_t) :: s
    type(dk_boundary_motion) :: m
    type(dk_spring_system) :: sys
    real(c_double), target :: none(1)
    real(c_double), pointer, contiguous :: o(:)
    call dkf_fill_motion(m, nodes, deformed, element_offsets, element_nodes, element_kinds, &
                         rigid_rotation, node_rotations, origin)
    sys = dkf_spring_system(dkf_graph(offsets, targets), stiffness, fixed)
    o => none(1:0)
    if (present(origin_out)) o => origin_out
    s = dk_deform_spring(points, size(points, kind=c_size_t), &
                         int(size(points, 1), c_int32_t), m, sys, options, scratch, &
                         size(scratch, kind=c_size_t), values, size(values, kind=c_size_t), &
                         index_scratch, size(index_scratch, kind=c_size_t), translations, &
                         size(translations, kind=c_size_t), rotations, &
                         size(rotations, kind=c_size_t), out, size(out, kind=c_size_t), &
                         o, size(o, kind=c_size_t), report)
  end function

  !> dk_plan_work_sizes + dk_plan_pool_sizes with Fortran arrays: points(dim, n), the CSR
  !> graph offsets(n + 1), targets(:) from dkf_graph_from_*, the 1-based boundary(:) node
  !> list, options (from dk_plan_options_default), optional boundary elements over
  !> 1..size(boundary) as 1-based element_offsets/element_nodes (as dkf_graph_from_cells takes
  !> cells) and element_kinds, and an optional stiffness(size(targets)) per directed edge (else
  !> Batina's with options%stiffness_exponent). The work buffers and 0-based copies of the node
  !> lists are allocated here and freed on return; pools receives the three pool lengths.
  !> Has an _f32 twin (generated: c_double becomes c_float).
  function dkf_plan_pool_sizes(points, offsets, targets, boundary, options, pools, &
                               element_offsets, element_nodes, element_kinds, stiffness) result(s)
    real(c_double), intent(in), target, contiguous :: points(:, :)
    integer(c_int32_t), intent(in), target, contiguous :: offsets(:), targets(:), boundary(:)
    type(dk_plan_options), intent(in) :: options
    type(dk_plan_sizes), intent(out) :: pools
    integer(c_int32_t), intent(in), contiguous, optional :: element_offsets(:), element_nodes(:)
    integer(c_int8_t), intent(in), contiguous, optional :: element_kinds(:)
    real(c_double), intent(in), target, contiguous, optional :: stiffness(:)
    integer(c_int32_t) :: s
    type(dk_plan_mesh) :: mesh
    type(dk_plan_pools) :: work
    real(c_double), allocatable, target :: wr(:)
    integer(c_int32_t), allocatable, target :: wi(:), b0(:), eo0(:), en0(:)
    integer(c_int8_t), allocatable, target :: wb(:), ek0(:)
    call dkf_plan_mesh(mesh, points, offsets, targets, boundary, b0, eo0, en0, ek0, &
                       element_offsets, element_nodes, element_kinds, stiffness)
    s = dkf_plan_work(mesh, int(size(points, 1), c_int32_t), options, work, wr, wi, wb)
    if (s /= DK_OK) return
    s = dk_plan_pool_sizes(mesh, int(size(points, 1), c_int32_t), options, work, pools)
  end function

  !> dk_plan_init with Fortran arrays (arguments as dkf_plan_pool_sizes; the work buffers are
  !> allocated here): builds the plan in reals(:), indices(:), bytes(:) (at least the lengths
  !> dkf_plan_pool_sizes gave); info receives what the plan holds.
  !> Has an _f32 twin (generated: c_double becomes c_float).
  function dkf_plan_init(points, offsets, targets, boundary, options, reals, indices, bytes, &
                         info, element_offsets, element_nodes, element_kinds, stiffness) result(s)
    real(c_double), intent(in), target, contiguous :: points(:, :)
    integer(c_int32_t), intent(in), target, contiguous :: offsets(:), targets(:), boundary(:)
    type(dk_plan_options), intent(in) :: options
    real(c_double), intent(inout), target, contiguous :: reals(:)
    integer(c_int32_t), intent(inout), target, contiguous :: indices(:)
    integer(c_int8_t), intent(inout), target, contiguous :: bytes(:)
    type(dk_plan_info), intent(inout) :: info
    integer(c_int32_t), intent(in), contiguous, optional :: element_offsets(:), element_nodes(:)
    integer(c_int8_t), intent(in), contiguous, optional :: element_kinds(:)
    real(c_double), intent(in), target, contiguous, optional :: stiffness(:)
    integer(c_int32_t) :: s
    type(dk_plan_mesh) :: mesh
    type(dk_plan_pools) :: work
    real(c_double), allocatable, target :: wr(:)
    integer(c_int32_t), allocatable, target :: wi(:), b0(:), eo0(:), en0(:)
    integer(c_int8_t), allocatable, target :: wb(:), ek0(:)
    call dkf_plan_mesh(mesh, points, offsets, targets, boundary, b0, eo0, en0, ek0, &
                       element_offsets, element_nodes, element_kinds, stiffness)
    s = dkf_plan_work(mesh, int(size(points, 1), c_int32_t), options, work, wr, wi, wb)
    if (s /= DK_OK) return
    s = dk_plan_init(mesh, int(size(points, 1), c_int32_t), options, work, &
                     dkf_plan_pools(reals, indices, bytes), info)
  end function

  !> dk_plan_step with Fortran arrays: deformed(dim, size(boundary)) in, out(dim, n) out;
  !> start DK_PLAN_WARM (default) or DK_PLAN_COLD; rotations from the plan's elements unless
  !> rigid_rotation(4) or node_rotations(4, size(boundary)) is given; origin(dim) optional.
  !> Has an _f32 twin (generated: c_double becomes c_float).
  function dkf_plan_step(reals, indices, bytes, deformed, out, report, start, rigid_rotation, &
                         node_rotations, origin) result(s)
    use, intrinsic :: iso_c_binding, only: c_loc, c_null_ptr
    real(c_double), intent(inout), target, contiguous :: reals(:)
    integer(c_int32_t), intent(inout), target, contiguous :: indices(:)
    integer(c_int8_t), intent(inout), target, contiguous :: bytes(:)
    real(c_double), intent(in), contiguous :: deformed(:, :)
    real(c_double), intent(inout), contiguous :: out(:, :)
    type(dk_plan_step_report), intent(inout) :: report
    integer(c_int32_t), intent(in), optional :: start
    real(c_double), intent(in), target, optional :: rigid_rotation(4)
    real(c_double), intent(in), target, contiguous, optional :: node_rotations(:, :)
    real(c_double), intent(in), target, contiguous, optional :: origin(:)
    integer(c_int32_t) :: s, st, source
    type(c_ptr) :: rot, org
    integer(c_size_t) :: nrot, norg
    st = DK_PLAN_WARM
    if (present(start)) st = start
    source = DK_ROTATIONS_SHAPE
    rot = c_null_ptr
    nrot = 0
    if (present(rigid_rotation)) then
      source = DK_ROTATIONS_RIGID
      rot = c_loc(rigid_rotation)
      nrot = 4
    else if (present(node_rotations)) then
      source = DK_ROTATIONS_PER_NODE
      rot = c_loc(node_rotations)
      nrot = size(node_rotations, kind=c_size_t)
    end if
    org = c_null_ptr
    norg = 0
    if (present(origin)) then
      org = c_loc(origin)
      norg = size(origin, kind=c_size_t)
    end if
    s = dk_plan_step(dkf_plan_pools(reals, indices, bytes), int(size(deformed, 1), c_int32_t), &
                     deformed, size(deformed, kind=c_size_t), source, rot, nrot, org, norg, st, &
                     out, size(out, kind=c_size_t), report)
  end function

  !> dk_plan_open with Fortran arrays (dim 2 or 3).
  !> Has an _f32 twin (generated: c_double becomes c_float).
  function dkf_plan_open(reals, indices, bytes, dim, info) result(s)
    real(c_double), intent(inout), target, contiguous :: reals(:)
    integer(c_int32_t), intent(inout), target, contiguous :: indices(:)
    integer(c_int8_t), intent(inout), target, contiguous :: bytes(:)
    integer(c_int32_t), intent(in) :: dim
    type(dk_plan_info), intent(inout) :: info
    integer(c_int32_t) :: s
    s = dk_plan_open(dkf_plan_pools(reals, indices, bytes), dim, info)
  end function

  !> A dk_plan_pools over reals(:), indices(:), bytes(:) (the arrays need the target attribute
  !> and must outlive every call the struct is passed to, as for dkf_graph).
  !> Has an _f32 twin (generated: c_double becomes c_float).
  function dkf_plan_pools(reals, indices, bytes) result(p)
    use, intrinsic :: iso_c_binding, only: c_loc
    real(c_double), intent(inout), target, contiguous :: reals(:)
    integer(c_int32_t), intent(inout), target, contiguous :: indices(:)
    integer(c_int8_t), intent(inout), target, contiguous :: bytes(:)
    type(dk_plan_pools) :: p
    p = dk_plan_pools(c_loc(reals), size(reals, kind=c_size_t), c_loc(indices), &
                      size(indices, kind=c_size_t), c_loc(bytes), size(bytes, kind=c_size_t))
  end function

  !> The dk_plan_mesh of the plan wrappers: the 1-based boundary and optional element arrays
  !> as 0-based copies in b0, eo0, en0, ek0 (declared target by the caller).
  !> Has an _f32 twin (generated: c_double becomes c_float).
  subroutine dkf_plan_mesh(mesh, points, offsets, targets, boundary, b0, eo0, en0, ek0, &
                           element_offsets, element_nodes, element_kinds, stiffness)
    use, intrinsic :: iso_c_binding, only: c_loc, c_null_ptr
    type(dk_plan_mesh), intent(out) :: mesh
    real(c_double), intent(in), target, contiguous :: points(:, :)
    integer(c_int32_t), intent(in), target, contiguous :: offsets(:), targets(:), boundary(:)
    integer(c_int32_t), allocatable, target, intent(inout) :: b0(:), eo0(:), en0(:)
    integer(c_int8_t), allocatable, target, intent(inout) :: ek0(:)
    integer(c_int32_t), intent(in), contiguous, optional :: element_offsets(:), element_nodes(:)
    integer(c_int8_t), intent(in), contiguous, optional :: element_kinds(:)
    real(c_double), intent(in), target, contiguous, optional :: stiffness(:)
    b0 = boundary - 1
    mesh = dk_plan_mesh(c_loc(points), size(points, kind=c_size_t), dkf_graph(offsets, targets), &
                        c_loc(b0), size(b0, kind=c_size_t), &
                        dk_cells(c_null_ptr, 0, c_null_ptr, 0, c_null_ptr, 0), c_null_ptr, 0)
    if (present(element_offsets) .and. present(element_nodes) .and. present(element_kinds)) then
      eo0 = element_offsets - 1
      en0 = element_nodes - 1
      ek0 = element_kinds
      mesh%elements = dkf_cells(eo0, en0, ek0)
    end if
    if (present(stiffness)) then
      mesh%stiffness = c_loc(stiffness)
      mesh%stiffness_len = size(stiffness, kind=c_size_t)
    end if
  end subroutine

  !> The transient work of dk_plan_init for mesh: sized by dk_plan_work_sizes, allocated in
  !> wr, wi, wb (declared target by the caller) and described by work.
  !> Has an _f32 twin (generated: c_double becomes c_float).
  function dkf_plan_work(mesh, dim, options, work, wr, wi, wb) result(s)
    type(dk_plan_mesh), intent(in) :: mesh
    integer(c_int32_t), intent(in) :: dim
    type(dk_plan_options), intent(in) :: options
    type(dk_plan_pools), intent(out) :: work
    real(c_double), allocatable, target, intent(inout) :: wr(:)
    integer(c_int32_t), allocatable, target, intent(inout) :: wi(:)
    integer(c_int8_t), allocatable, target, intent(inout) :: wb(:)
    integer(c_int32_t) :: s
    type(dk_plan_sizes) :: n
    s = dk_plan_work_sizes(mesh, dim, options, n)
    if (s /= DK_OK) return
    allocate(wr(max(n%reals, 1_c_size_t)), wi(max(n%indices, 1_c_size_t)), &
             wb(max(n%bytes, 1_c_size_t)))
    work = dkf_plan_pools(wr, wi, wb)
  end function

  !> dk_quality_cell_measures with Fortran arrays and 1-based cells (cell_offsets(ncells + 1),
  !> cell_nodes(:), cell_kinds(ncells), as dkf_graph_from_cells takes them): the signed area
  !> (2D) or volume (3D) of every cell of points(dim, n) into out(ncells).
  !> Has an _f32 twin (generated: c_double becomes c_float).
  function dkf_quality_cell_measures(cell_offsets, cell_nodes, cell_kinds, points, out) result(s)
    integer(c_int32_t), intent(in), target, contiguous :: cell_offsets(:), cell_nodes(:)
    integer(c_int8_t), intent(in), target, contiguous :: cell_kinds(:)
    real(c_double), intent(in), contiguous :: points(:, :)
    real(c_double), intent(inout), contiguous :: out(:)
    integer(c_int32_t) :: s
    integer(c_int32_t), allocatable :: index_scratch(:)
    allocate(index_scratch(size(cell_offsets) + size(cell_nodes)))
    s = dk_quality_cell_measures(dkf_cells(cell_offsets, cell_nodes, cell_kinds), 1_c_int32_t, &
                                 index_scratch, &
                                 size(index_scratch, kind=c_size_t), points, &
                                 size(points, kind=c_size_t), int(size(points, 1), c_int32_t), &
                                 out, size(out, kind=c_size_t))
  end function

  !> dk_quality_min_corner_jacobians with Fortran arrays (cells as dkf_quality_cell_measures):
  !> the smallest corner Jacobian of every cell, divided by its edge lengths when scaled.
  !> Has an _f32 twin (generated: c_double becomes c_float).
  function dkf_quality_min_corner_jacobians(cell_offsets, cell_nodes, cell_kinds, points, &
                                            scaled, out) result(s)
    integer(c_int32_t), intent(in), target, contiguous :: cell_offsets(:), cell_nodes(:)
    integer(c_int8_t), intent(in), target, contiguous :: cell_kinds(:)
    real(c_double), intent(in), contiguous :: points(:, :)
    logical, intent(in) :: scaled
    real(c_double), intent(inout), contiguous :: out(:)
    integer(c_int32_t) :: s
    integer(c_int32_t), allocatable :: index_scratch(:)
    allocate(index_scratch(size(cell_offsets) + size(cell_nodes)))
    s = dk_quality_min_corner_jacobians(dkf_cells(cell_offsets, cell_nodes, cell_kinds), &
                                        1_c_int32_t, index_scratch, size(index_scratch, kind=c_size_t), points, &
                                        size(points, kind=c_size_t), &
                                        int(size(points, 1), c_int32_t), &
                                        logical(scaled, c_bool), out, size(out, kind=c_size_t))
  end function

  !> dk_quality_compare with Fortran arrays: deformed(dim, n) against undeformed(dim, n) over
  !> the 1-based cells; with a wall (1-based wall_offsets, wall_nodes, wall_kinds and the CSR
  !> graph_offsets, graph_targets from dkf_graph_from_*, all five or none) also the wall-angle
  !> change (the scratch is allocated here). report receives the comparison; its cell and node
  !> indices are 1-based, or DK_NO_INDEX.
  !> Has an _f32 twin (generated: c_double becomes c_float).
  function dkf_quality_compare(cell_offsets, cell_nodes, cell_kinds, undeformed, deformed, &
                               report, wall_offsets, wall_nodes, wall_kinds, graph_offsets, &
                               graph_targets) result(s)
    use, intrinsic :: iso_c_binding, only: c_null_ptr
    integer(c_int32_t), intent(in), target, contiguous :: cell_offsets(:), cell_nodes(:)
    integer(c_int8_t), intent(in), target, contiguous :: cell_kinds(:)
    real(c_double), intent(in), contiguous :: undeformed(:, :), deformed(:, :)
    type(dk_quality_report), intent(inout) :: report
    integer(c_int32_t), intent(in), target, contiguous, optional :: wall_offsets(:), &
        wall_nodes(:), graph_offsets(:), graph_targets(:)
    integer(c_int8_t), intent(in), target, contiguous, optional :: wall_kinds(:)
    integer(c_int32_t) :: s
    real(c_double), allocatable :: scratch(:)
    integer(c_int32_t), allocatable :: index_scratch(:)
    integer(c_size_t) :: need
    type(dk_cells) :: wall
    type(dk_graph) :: graph
    need = 0
    wall = dk_cells(c_null_ptr, 0, c_null_ptr, 0, c_null_ptr, 0)
    graph = dk_graph(c_null_ptr, 0, c_null_ptr, 0)
    if (present(wall_offsets) .and. present(wall_nodes) .and. present(wall_kinds) .and. &
        present(graph_offsets) .and. present(graph_targets)) then
      wall = dkf_cells(wall_offsets, wall_nodes, wall_kinds)
      graph = dkf_graph(graph_offsets, graph_targets)
      s = dk_quality_wall_angle_scratch_len(size(undeformed, 2, kind=c_size_t), &
                                            int(size(undeformed, 1), c_int32_t), need)
      if (s /= DK_OK) return
    else if (present(wall_offsets) .or. present(wall_nodes) .or. present(wall_kinds) .or. &
             present(graph_offsets) .or. present(graph_targets)) then
      s = DK_ERR_LENGTH_MISMATCH
      return
    end if
    allocate(scratch(max(need, 1_c_size_t)))
    allocate(index_scratch(size(cell_offsets) + size(cell_nodes) + wall%offsets_len + &
                           wall%nodes_len))
    s = dk_quality_compare(dkf_cells(cell_offsets, cell_nodes, cell_kinds), 1_c_int32_t, &
                           index_scratch, size(index_scratch, kind=c_size_t), wall, graph, &
                           undeformed, size(undeformed, kind=c_size_t), &
                           deformed, size(deformed, kind=c_size_t), &
                           int(size(undeformed, 1), c_int32_t), scratch, need, report)
  end function

  !> A dk_graph over the 0-based CSR arrays offsets(:) and targets(:) from dkf_graph_from_*.
  !> The arrays need the target attribute and must outlive every call the struct is passed to
  !> (the struct holds their C addresses).
  function dkf_graph(offsets, targets) result(g)
    use, intrinsic :: iso_c_binding, only: c_loc
    integer(c_int32_t), intent(in), target, contiguous :: offsets(:), targets(:)
    type(dk_graph) :: g
    g = dk_graph(c_loc(offsets), size(offsets, kind=c_size_t), c_loc(targets), &
                 size(targets, kind=c_size_t))
  end function

  !> A dk_cells over offsets(ncells + 1), nodes(:) and kinds(ncells) (read in the index_base
  !> of the call, 1 for the dkf_ wrappers); arrays as for dkf_graph.
  function dkf_cells(offsets, nodes, kinds) result(c)
    use, intrinsic :: iso_c_binding, only: c_loc
    integer(c_int32_t), intent(in), target, contiguous :: offsets(:), nodes(:)
    integer(c_int8_t), intent(in), target, contiguous :: kinds(:)
    type(dk_cells) :: c
    c = dk_cells(c_loc(offsets), size(offsets, kind=c_size_t), c_loc(nodes), &
                 size(nodes, kind=c_size_t), c_loc(kinds), size(kinds, kind=c_size_t))
  end function

  !> A dk_spring_system: the graph (dkf_graph), stiffness(size(targets)) per directed edge and
  !> fixed(n) (nonzero = fixed); arrays as for dkf_graph.
  !> Has an _f32 twin (generated: c_double becomes c_float).
  function dkf_spring_system(graph, stiffness, fixed) result(sys)
    use, intrinsic :: iso_c_binding, only: c_loc
    type(dk_graph), intent(in) :: graph
    real(c_double), intent(in), target, contiguous :: stiffness(:)
    integer(c_int8_t), intent(in), target, contiguous :: fixed(:)
    type(dk_spring_system) :: sys
    sys = dk_spring_system(graph, c_loc(stiffness), size(stiffness, kind=c_size_t), &
                           c_loc(fixed), size(fixed, kind=c_size_t))
  end function

  !> A dk_constraints for the sliding functions: kinds(n) (0 free, 1 fixed, 2 plane, 3 line)
  !> and directions(dim, n) (unit normals of kind 2, unit tangents of kind 3, ignored
  !> otherwise); arrays as for dkf_graph.
  !> Has an _f32 twin (generated: c_double becomes c_float).
  function dkf_constraints(kinds, directions) result(c)
    use, intrinsic :: iso_c_binding, only: c_loc
    integer(c_int8_t), intent(in), target, contiguous :: kinds(:)
    real(c_double), intent(in), target, contiguous :: directions(:, :)
    type(dk_constraints) :: c
    c = dk_constraints(c_loc(kinds), size(kinds, kind=c_size_t), c_loc(directions), &
                       size(directions, kind=c_size_t))
  end function


end module deform_kernel
