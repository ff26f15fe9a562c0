! deform-kernel Fortran 2008 bindings (iso_c_binding).
!
! Every function returns an integer(c_int32_t) status: DK_OK (0) is success, anything else is a
! dk_status code (see deform_kernel.h); dk_status_message() describes it. Outputs are written
! only on success. Mesh node indices may be passed 1-based as they are (index_base = 1).
! Functions ending in _f32 take real(c_float) arrays. The dkf_* wrappers take assumed-shape
! contiguous arrays and pass their sizes for you.
module deform_kernel
  use, intrinsic :: iso_c_binding, only: c_int32_t, c_int64_t, c_int8_t, c_size_t, c_double, c_float, &
                                         c_bool, c_ptr, c_char, c_f_pointer, c_associated
  implicit none
  private

  integer(c_int32_t), parameter, public :: DK_OK = 0
  integer(c_int32_t), parameter, public :: DK_ERR_NULL_POINTER = 1
  integer(c_int32_t), parameter, public :: DK_ERR_LENGTH_MISMATCH = 2
  integer(c_int32_t), parameter, public :: DK_ERR_BUFFER_TOO_SMALL = 3
  integer(c_int32_t), parameter, public :: DK_ERR_INDEX_OUT_OF_RANGE = 4
  integer(c_int32_t), parameter, public :: DK_ERR_TOO_LARGE = 5
  integer(c_int32_t), parameter, public :: DK_ERR_BAD_OFFSETS = 6
  integer(c_int32_t), parameter, public :: DK_ERR_SELF_LOOP = 7
  integer(c_int32_t), parameter, public :: DK_ERR_NOT_SYMMETRIC = 8
  integer(c_int32_t), parameter, public :: DK_ERR_UNKNOWN_CELL_KIND = 9
  integer(c_int32_t), parameter, public :: DK_ERR_WRONG_NODE_COUNT = 10
  integer(c_int32_t), parameter, public :: DK_ERR_REPEATED_NODE = 11
  integer(c_int32_t), parameter, public :: DK_ERR_NON_FINITE = 12
  integer(c_int32_t), parameter, public :: DK_ERR_INVALID_PARAMETER = 13
  integer(c_int32_t), parameter, public :: DK_ERR_ZERO_LENGTH = 14
  integer(c_int32_t), parameter, public :: DK_ERR_ZERO_LENGTH_EDGE = 15
  integer(c_int32_t), parameter, public :: DK_ERR_SINGULAR_NODE = 16
  integer(c_int32_t), parameter, public :: DK_ERR_SINGULAR_SYSTEM = 17
  integer(c_int32_t), parameter, public :: DK_ERR_UNANCHORED = 18
  integer(c_int32_t), parameter, public :: DK_ERR_FOLDED_LINE = 19
  integer(c_int32_t), parameter, public :: DK_ERR_BAD_DIMENSIONS = 20
  integer(c_int32_t), parameter, public :: DK_ERR_BAD_INDEX_BASE = 21
  integer(c_int32_t), parameter, public :: DK_ERR_ISOLATED_NODE = 22
  integer(c_int32_t), parameter, public :: DK_ERR_DUPLICATE_NODE = 23
  integer(c_int32_t), parameter, public :: DK_ERR_NON_POSITIVE = 24
  integer(c_int32_t), parameter, public :: DK_ERR_CELL_DIMENSION = 25
  integer(c_int32_t), parameter, public :: DK_ERR_OVERFLOW = 26
  integer(c_int32_t), parameter, public :: DK_ERR_NOT_UNIT = 27
  integer(c_int32_t), parameter, public :: DK_ERR_NOT_PLANAR = 28
  integer(c_int32_t), parameter, public :: DK_ERR_BAD_PLAN = 29
  integer(c_int32_t), parameter, public :: DK_ERR_OTHER = 99

  ! VTK cell kind codes.
  integer(c_int8_t), parameter, public :: DK_LINE = 3_c_int8_t, DK_TRIANGLE = 5_c_int8_t, &
       DK_QUAD = 9_c_int8_t, DK_TETRA = 10_c_int8_t, DK_HEXAHEDRON = 12_c_int8_t, &
       DK_PRISM = 13_c_int8_t, DK_PYRAMID = 14_c_int8_t

  public :: dk_status_str, dk_status_message
  public :: dkf_rotate_points, dkf_graph_from_edges, dkf_graph_from_cells_len, &
            dkf_graph_from_cells

  ! <<< public: springs, quality, taubin >>>
  ! Springs, quality and Taubin smoothing (dk_spring_*, dk_quality_*, dk_taubin_*). Options and
  ! reports have real(c_double) fields for both precisions; flags in option structs are
  ! integer(c_int8_t) (nonzero = true). Fill options with the *_default functions.
  integer(c_int32_t), parameter, public :: DK_PROLONGATION_VALUES = 0, &
       DK_PROLONGATION_CORRECTION = 1
  integer(c_int32_t), parameter, public :: DK_LINEAR_JACOBI = 0, DK_LINEAR_GAUSS_SEIDEL = 1, &
       DK_LINEAR_SOR = 2, DK_LINEAR_CG = 3
  integer(c_int32_t), parameter, public :: DK_PRECONDITIONER_NONE = 0, &
       DK_PRECONDITIONER_JACOBI = 1, DK_PRECONDITIONER_SSOR = 2
  integer(c_int32_t), parameter, public :: DK_ANGLE_DIRECT_GAUSS_SEIDEL = 0, &
       DK_ANGLE_DIRECT_JACOBI = 1, DK_ANGLE_CG = 2
  !> "No such index" in the quality reports (C: SIZE_MAX).
  integer(c_size_t), parameter, public :: DK_NO_INDEX = -1_c_size_t

  !> Coarse-grid settings (C struct dk_taubin_coarse).
  type, bind(C), public :: dk_taubin_coarse
    integer(c_size_t) :: factor(3)
    integer(c_int32_t) :: prolongation
  end type

  !> Options of the structured filters (C struct dk_structured_options); pinned is c_loc of
  !> an integer(c_int8_t) array (one per point) or c_null_ptr.
  type, bind(C), public :: dk_structured_options
    type(c_ptr) :: pinned
    integer(c_size_t) :: pinned_len
    integer(c_int8_t) :: mirror(3)
  end type

  !> A box of structured indices (C struct dk_block_region); with index_base 1 the bounds
  !> are 1-based and inclusive.
  type, bind(C), public :: dk_block_region
    integer(c_size_t) :: lo(3)
    integer(c_size_t) :: hi(3)
  end type

  !> What a filter run did (C struct dk_filter_report).
  type, bind(C), public :: dk_filter_report
    integer(c_size_t) :: iterations
    real(c_double) :: last_change
  end type

  !> Settings of dk_taubin_smooth_arclength (C struct dk_smooth_arclength_options); fill with
  !> dk_smooth_arclength_options_default. direction is 0 (i), 1 (j) or 2 (k).
  type, bind(C), public :: dk_smooth_arclength_options
    real(c_double) :: lambda
    real(c_double) :: mu
    integer(c_size_t) :: iterations
    integer(c_size_t) :: coarse_iterations
    type(c_ptr) :: pinned
    integer(c_size_t) :: pinned_len
    type(dk_taubin_coarse) :: coarse
    integer(c_int32_t) :: direction
    integer(c_int8_t) :: normalised
    integer(c_int8_t) :: use_coarse
    integer(c_int8_t) :: mirror(3)
  end type

  !> What dk_taubin_smooth_arclength did (C struct dk_smooth_report); point indices are
  !> 0-based linear indices.
  type, bind(C), public :: dk_smooth_report
    integer(c_size_t) :: iterations
    real(c_double) :: last_change
    real(c_double) :: max_displacement
    real(c_double) :: stretching_before
    real(c_double) :: stretching_after
    integer(c_size_t) :: stretching_before_point
    integer(c_size_t) :: stretching_after_point
  end type

  !> Method and stopping rules of dk_spring_solve_linear (C struct dk_spring_solve_options).
  type, bind(C), public :: dk_spring_solve_options
    integer(c_size_t) :: max_iterations
    real(c_double) :: residual_tol
    real(c_double) :: update_tol
    real(c_double) :: omega
    integer(c_int32_t) :: method
    integer(c_int32_t) :: preconditioner
  end type

  !> Method, regularisation and stopping rules of the angle springs
  !> (C struct dk_spring_angle_options).
  type, bind(C), public :: dk_spring_angle_options
    integer(c_size_t) :: max_iterations
    real(c_double) :: residual_tol
    real(c_double) :: update_tol
    real(c_double) :: epsilon
    integer(c_int32_t) :: method
  end type

  !> What a spring solve did (C struct dk_spring_solve_report).
  type, bind(C), public :: dk_spring_solve_report
    integer(c_size_t) :: iterations
    real(c_double) :: residual
    real(c_double) :: max_update
    logical(c_bool) :: converged
  end type

  !> Result of one sweep (C struct dk_spring_sweep).
  type, bind(C), public :: dk_spring_sweep
    real(c_double) :: max_change
    real(c_double) :: residual_sq
  end type

  !> Quality of one cell (C struct dk_cell_quality).
  type, bind(C), public :: dk_cell_quality
    real(c_double) :: measure
    real(c_double) :: min_jacobian
    real(c_double) :: min_scaled_jacobian
  end type

  !> Result of dk_quality_wall_angle_change (C struct dk_wall_angle_change); node is in the
  !> caller's index_base, or DK_NO_INDEX.
  type, bind(C), public :: dk_wall_angle_change
    real(c_double) :: max_change
    integer(c_size_t) :: node
    integer(c_size_t) :: measured
    integer(c_size_t) :: skipped
  end type

  !> Result of dk_quality_compare (C struct dk_quality_report); cell and node indices are in
  !> the caller's index_base, or DK_NO_INDEX.
  type, bind(C), public :: dk_quality_report
    integer(c_size_t) :: cells
    integer(c_size_t) :: inverted_cells
    integer(c_size_t) :: folded_cells
    integer(c_size_t) :: folded_cells_undeformed
    integer(c_size_t) :: degenerate_cells
    integer(c_size_t) :: min_ratio_cell
    integer(c_size_t) :: max_ratio_cell
    integer(c_size_t) :: wall_node
    integer(c_size_t) :: wall_measured
    integer(c_size_t) :: wall_skipped
    real(c_double) :: min_measure_ratio
    real(c_double) :: max_measure_ratio
    real(c_double) :: min_measure
    real(c_double) :: min_scaled_jacobian
    real(c_double) :: wall_max_change
    logical(c_bool) :: has_wall
  end type

  ! Prepared plans (dk_plan_*): methods, solvers, starts.
  integer(c_int32_t), parameter, public :: DK_PLAN_SPRING = 1, DK_PLAN_QUATERNION = 2
  integer(c_int32_t), parameter, public :: DK_PLAN_SOLVER_AMG = 0, DK_PLAN_SOLVER_LINEAR = 1
  integer(c_int32_t), parameter, public :: DK_PLAN_WARM = 0, DK_PLAN_COLD = 1
  integer(c_int32_t), parameter, public :: DK_AMG_JACOBI = 0, DK_AMG_CHEBYSHEV = 1

  !> The multigrid preconditioner's options (C struct dk_amg_options).
  type, bind(C), public :: dk_amg_options
    real(c_double) :: strength_theta
    integer(c_size_t) :: max_levels
    integer(c_size_t) :: max_coarse
    integer(c_size_t) :: sweeps
    integer(c_int32_t) :: smoother
  end type

  !> How a plan is built (C struct dk_plan_options); fill with dk_plan_options_default.
  type, bind(C), public :: dk_plan_options
    integer(c_int32_t) :: method
    integer(c_int32_t) :: solver
    real(c_double) :: stiffness_exponent
    type(dk_spring_solve_options) :: linear
    type(dk_amg_options) :: amg
  end type

  !> Lengths of the plan pools or work buffers (C struct dk_plan_sizes).
  type, bind(C), public :: dk_plan_sizes
    integer(c_size_t) :: reals
    integer(c_size_t) :: indices
    integer(c_size_t) :: bytes
  end type

  !> What a plan holds (C struct dk_plan_info).
  type, bind(C), public :: dk_plan_info
    integer(c_size_t) :: nodes
    integer(c_size_t) :: boundary
    integer(c_int64_t) :: steps
    integer(c_size_t) :: amg_levels
    type(dk_plan_sizes) :: used
    integer(c_int32_t) :: method
  end type

  !> What one dk_plan_step did (C struct dk_plan_step_report).
  type, bind(C), public :: dk_plan_step_report
    integer(c_size_t) :: iterations
    real(c_double) :: residual
    real(c_double) :: max_update
    integer(c_int64_t) :: step
    logical(c_bool) :: converged
    logical(c_bool) :: warm
    logical(c_bool) :: extrapolated
  end type

  public :: dkf_quality_cell_measures, dkf_quality_cell_measures_f32, &
            dkf_quality_min_corner_jacobians, dkf_quality_min_corner_jacobians_f32, &
            dkf_quality_compare, dkf_quality_compare_f32
  public :: dkf_plan_pool_sizes, dkf_plan_pool_sizes_f32, dkf_plan_init, dkf_plan_init_f32, &
            dkf_plan_step, dkf_plan_step_f32, dkf_plan_open, dkf_plan_open_f32
  public :: dkf_spring_solve_linear, dkf_taubin_smooth_arclength, dkf_taubin_smooth_structured, &
            dkf_taubin_smooth_graph
  ! <<< end public: springs, quality, taubin >>>
  ! <<< public: deformation >>>
  ! Quaternion deformation (dk_deform_*): rotation sources and TFI direction bits.
  integer(c_int32_t), parameter, public :: DK_ROTATIONS_SHAPE = 0, DK_ROTATIONS_RIGID = 1, &
       DK_ROTATIONS_PER_NODE = 2
  integer(c_int32_t), parameter, public :: DK_DIRECTION_I = 1, DK_DIRECTION_J = 2, &
       DK_DIRECTION_K = 4

  !> The prescribed boundary motion (C struct dk_boundary_motion). Fill it with
  !> dk_boundary_motion_default, then point its arrays at contiguous target arrays with c_loc,
  !> or let the dkf_deform_* wrappers fill it from assumed-shape arrays.
  type, bind(C), public :: dk_boundary_motion
    type(c_ptr) :: nodes
    integer(c_size_t) :: nodes_len
    type(c_ptr) :: deformed
    integer(c_size_t) :: deformed_len
    type(c_ptr) :: element_offsets
    integer(c_size_t) :: element_offsets_len
    type(c_ptr) :: element_nodes
    integer(c_size_t) :: element_nodes_len
    type(c_ptr) :: element_kinds
    integer(c_size_t) :: element_kinds_len
    type(c_ptr) :: node_rotations
    integer(c_size_t) :: node_rotations_len
    real(c_double) :: rigid_rotation(4)
    real(c_double) :: origin(3)
    integer(c_int32_t) :: index_base
    integer(c_int32_t) :: rotation_source
    integer(c_int32_t) :: has_origin
  end type

  !> Single-precision twin of dk_boundary_motion.
  type, bind(C), public :: dk_boundary_motion_f32
    type(c_ptr) :: nodes
    integer(c_size_t) :: nodes_len
    type(c_ptr) :: deformed
    integer(c_size_t) :: deformed_len
    type(c_ptr) :: element_offsets
    integer(c_size_t) :: element_offsets_len
    type(c_ptr) :: element_nodes
    integer(c_size_t) :: element_nodes_len
    type(c_ptr) :: element_kinds
    integer(c_size_t) :: element_kinds_len
    type(c_ptr) :: node_rotations
    integer(c_size_t) :: node_rotations_len
    real(c_float) :: rigid_rotation(4)
    real(c_float) :: origin(3)
    integer(c_int32_t) :: index_base
    integer(c_int32_t) :: rotation_source
    integer(c_int32_t) :: has_origin
  end type

  public :: dkf_deform_idw, dkf_deform_idw_f32, dkf_deform_tfi, dkf_deform_tfi_f32
  public :: dkf_deform_spring, dkf_deform_spring_f32
  ! <<< end public: deformation >>>

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

  ! <<< generated by `cargo xtask codegen` from ffi/abi/*.abi: do not edit >>>
  public :: dk_boundary_motion_default, dk_boundary_motion_default_f32, &
            dk_boundary_motion_index_scratch_len, dk_boundary_motion_index_scratch_len_f32, &
            dk_deform_idw_scratch_len, dk_deform_idw, dk_deform_idw_f32, &
            dk_deform_tfi_scratch_len, dk_deform_tfi, dk_deform_tfi_f32, &
            dk_deform_boundary_normals_scratch_len, dk_deform_boundary_normals, &
            dk_deform_boundary_normals_f32, dk_deform_boundary_rotations_scratch_len, &
            dk_deform_boundary_rotations, dk_deform_boundary_rotations_f32, &
            dk_deform_rigid_rotations, dk_deform_rigid_rotations_f32, dk_deform_boundary_origin, &
            dk_deform_boundary_origin_f32, dk_deform_boundary_translations, &
            dk_deform_boundary_translations_f32, dk_deform_propagate_idw, &
            dk_deform_propagate_idw_f32, dk_deform_propagate_tfi_scratch_len, &
            dk_deform_propagate_tfi, dk_deform_propagate_tfi_f32, dk_deform_displacement_tfi, &
            dk_deform_displacement_tfi_f32, dk_deform_update_points, dk_deform_update_points_f32, &
            dk_deform_localize_nodes_scratch_len, dk_deform_localize_nodes, &
            dk_deform_spring_scratch_len, dk_deform_spring_index_scratch_len, &
            dk_deform_spring_index_scratch_len_f32, dk_deform_spring, dk_deform_spring_f32, &
            dk_deform_propagate_spring_scratch_len, dk_deform_propagate_spring, &
            dk_deform_propagate_spring_f32, dk_graph_from_edges_len, dk_graph_from_edges, &
            dk_cells_check, dk_graph_from_cells_len, dk_graph_from_cells, dk_graph_check, &
            dk_plan_options_default, dk_plan_options_default_f32, dk_plan_work_sizes, &
            dk_plan_work_sizes_f32, dk_plan_pool_sizes, dk_plan_pool_sizes_f32, dk_plan_init, &
            dk_plan_init_f32, dk_plan_open, dk_plan_open_f32, dk_plan_step, dk_plan_step_f32, &
            dk_quality_cell_quality, dk_quality_cell_quality_f32, dk_quality_cell_measures, &
            dk_quality_cell_measures_f32, dk_quality_min_corner_jacobians, &
            dk_quality_min_corner_jacobians_f32, dk_quality_inverted_cells, &
            dk_quality_inverted_cells_f32, dk_quality_folded_cells, dk_quality_folded_cells_f32, &
            dk_quality_wall_angle_scratch_len, dk_quality_compare, dk_quality_compare_f32, &
            dk_quality_wall_angle_change, dk_quality_wall_angle_change_f32, dk_quat_mul, &
            dk_quat_mul_f32, dk_quat_normalize, dk_quat_normalize_f32, dk_quat_inverse, &
            dk_quat_inverse_f32, dk_quat_from_axis_angle, dk_quat_from_axis_angle_f32, &
            dk_quat_to_axis_angle, dk_quat_to_axis_angle_f32, dk_quat_rotation_arc, &
            dk_quat_rotation_arc_f32, dk_quat_rotate_points, dk_quat_rotate_points_f32, &
            dk_quat_slerp, dk_quat_slerp_f32, dk_quat_nlerp, dk_quat_nlerp_f32, dk_quat_average, &
            dk_quat_average_f32, dk_spring_batina_stiffness, dk_spring_batina_stiffness_f32, &
            dk_spring_index_scratch_len, dk_spring_solve_options_default, &
            dk_spring_solve_options_default_f32, dk_spring_solve_linear_scratch_len, &
            dk_spring_solve_linear, dk_spring_solve_linear_f32, dk_spring_jacobi_sweep, &
            dk_spring_jacobi_sweep_f32, dk_spring_jacobi_sweep_exact, &
            dk_spring_jacobi_sweep_exact_f32, dk_exact_sum_value, dk_spring_sor_sweep, &
            dk_spring_sor_sweep_f32, dk_spring_relative_residual, dk_spring_relative_residual_f32, &
            dk_spring_angle_options_default, dk_spring_angle_options_default_f32, &
            dk_spring_solve_angle_scratch_len, dk_spring_solve_angle_scratch_len_f32, &
            dk_spring_angle_rigidity_probe_scratch_len, dk_spring_solve_angle, &
            dk_spring_solve_angle_f32, dk_spring_angle_jacobi_sweep, &
            dk_spring_angle_jacobi_sweep_f32, dk_spring_angle_gauss_seidel_sweep, &
            dk_spring_angle_gauss_seidel_sweep_f32, dk_spring_angle_rigidity_probe, &
            dk_spring_angle_rigidity_probe_f32, dk_spring_wall_distances, &
            dk_spring_wall_distances_f32, dk_spring_wall_distance_factors, &
            dk_spring_wall_distance_factors_f32, dk_spring_dual_volumes, &
            dk_spring_dual_volumes_f32, dk_spring_inverse_volume_factors, &
            dk_spring_inverse_volume_factors_f32, dk_spring_scale_stiffness, &
            dk_spring_scale_stiffness_f32, dk_taubin_params_paper, dk_taubin_params_paper_f32, &
            dk_taubin_params_from_pass_band, dk_taubin_params_from_pass_band_f32, &
            dk_smooth_arclength_options_default, dk_taubin_smooth_arclength_scratch_len, &
            dk_taubin_smooth_arclength, dk_taubin_smooth_arclength_f32, &
            dk_taubin_smooth_structured_scratch_len, dk_taubin_smooth_structured, &
            dk_taubin_smooth_structured_f32, dk_taubin_structured_sweep, &
            dk_taubin_structured_sweep_f32, dk_taubin_smooth_structured_coarse_scratch_len, &
            dk_taubin_smooth_structured_coarse, dk_taubin_smooth_structured_coarse_f32, &
            dk_taubin_smooth_graph_scratch_len, dk_taubin_smooth_graph, &
            dk_taubin_smooth_graph_f32, dk_taubin_graph_sweep, dk_taubin_graph_sweep_f32, &
            dk_taubin_inverse_distance_weights, dk_taubin_inverse_distance_weights_f32, &
            dk_taubin_arclength, dk_taubin_arclength_f32, dk_taubin_redistribute_scratch_len, &
            dk_taubin_redistribute, dk_taubin_redistribute_f32, dk_taubin_stretching, &
            dk_taubin_stretching_f32, dk_taubin_max_stretching, dk_taubin_max_stretching_f32, &
            dk_taubin_check_lines_increasing, dk_taubin_check_lines_increasing_f32

  interface
    function dk_boundary_motion_default(out) bind(C, name="dk_boundary_motion_default") result(s)
      import :: c_int32_t, dk_boundary_motion
      type(dk_boundary_motion), intent(inout) :: out
      integer(c_int32_t) :: s
    end function
    function dk_boundary_motion_default_f32(out) bind(C, name="dk_boundary_motion_default_f32") &
        result(s)
      import :: c_int32_t, dk_boundary_motion_f32
      type(dk_boundary_motion_f32), intent(inout) :: out
      integer(c_int32_t) :: s
    end function
    function dk_boundary_motion_index_scratch_len(motion, len_out) bind(C, &
        name="dk_boundary_motion_index_scratch_len") result(s)
      import :: c_int32_t, c_size_t, dk_boundary_motion
      type(dk_boundary_motion), intent(in) :: motion
      integer(c_size_t), intent(inout) :: len_out
      integer(c_int32_t) :: s
    end function
    function dk_boundary_motion_index_scratch_len_f32(motion, len_out) bind(C, &
        name="dk_boundary_motion_index_scratch_len_f32") result(s)
      import :: c_int32_t, c_size_t, dk_boundary_motion_f32
      type(dk_boundary_motion_f32), intent(in) :: motion
      integer(c_size_t), intent(inout) :: len_out
      integer(c_int32_t) :: s
    end function
    function dk_deform_idw_scratch_len(node_count, boundary_len, dim, len_out) bind(C, &
        name="dk_deform_idw_scratch_len") result(s)
      import :: c_int32_t, c_size_t
      integer(c_size_t), value :: node_count
      integer(c_size_t), value :: boundary_len
      integer(c_int32_t), value :: dim
      integer(c_size_t), intent(inout) :: len_out
      integer(c_int32_t) :: s
    end function
    function dk_deform_idw(points, points_len, dim, motion, exponent, scratch, scratch_len, &
        index_scratch, index_scratch_len, translations, translations_len, rotations, &
        rotations_len, out, out_len, origin_out, origin_out_len) bind(C, name="dk_deform_idw") &
        result(s)
      import :: c_double, c_int32_t, c_size_t, dk_boundary_motion
      real(c_double), intent(in) :: points(*)
      integer(c_size_t), value :: points_len
      integer(c_int32_t), value :: dim
      type(dk_boundary_motion), intent(in) :: motion
      real(c_double), value :: exponent
      real(c_double), intent(inout) :: scratch(*)
      integer(c_size_t), value :: scratch_len
      integer(c_int32_t), intent(inout) :: index_scratch(*)
      integer(c_size_t), value :: index_scratch_len
      real(c_double), intent(inout) :: translations(*)
      integer(c_size_t), value :: translations_len
      real(c_double), intent(inout) :: rotations(*)
      integer(c_size_t), value :: rotations_len
      real(c_double), intent(inout) :: out(*)
      integer(c_size_t), value :: out_len
      real(c_double), intent(inout) :: origin_out(*)
      integer(c_size_t), value :: origin_out_len
      integer(c_int32_t) :: s
    end function
    function dk_deform_idw_f32(points, points_len, dim, motion, exponent, scratch, scratch_len, &
        index_scratch, index_scratch_len, translations, translations_len, rotations, &
        rotations_len, out, out_len, origin_out, origin_out_len) bind(C, name="dk_deform_idw_f32") &
        result(s)
      import :: c_float, c_int32_t, c_size_t, dk_boundary_motion_f32
      real(c_float), intent(in) :: points(*)
      integer(c_size_t), value :: points_len
      integer(c_int32_t), value :: dim
      type(dk_boundary_motion_f32), intent(in) :: motion
      real(c_float), value :: exponent
      real(c_float), intent(inout) :: scratch(*)
      integer(c_size_t), value :: scratch_len
      integer(c_int32_t), intent(inout) :: index_scratch(*)
      integer(c_size_t), value :: index_scratch_len
      real(c_float), intent(inout) :: translations(*)
      integer(c_size_t), value :: translations_len
      real(c_float), intent(inout) :: rotations(*)
      integer(c_size_t), value :: rotations_len
      real(c_float), intent(inout) :: out(*)
      integer(c_size_t), value :: out_len
      real(c_float), intent(inout) :: origin_out(*)
      integer(c_size_t), value :: origin_out_len
      integer(c_int32_t) :: s
    end function
    function dk_deform_tfi_scratch_len(ni, nj, nk, boundary_len, dim, len_out) bind(C, &
        name="dk_deform_tfi_scratch_len") result(s)
      import :: c_int32_t, c_size_t
      integer(c_size_t), value :: ni
      integer(c_size_t), value :: nj
      integer(c_size_t), value :: nk
      integer(c_size_t), value :: boundary_len
      integer(c_int32_t), value :: dim
      integer(c_size_t), intent(inout) :: len_out
      integer(c_int32_t) :: s
    end function
    function dk_deform_tfi(ni, nj, nk, directions, points, points_len, dim, motion, scratch, &
        scratch_len, index_scratch, index_scratch_len, translations, translations_len, rotations, &
        rotations_len, out, out_len, origin_out, origin_out_len) bind(C, name="dk_deform_tfi") &
        result(s)
      import :: c_double, c_int32_t, c_size_t, dk_boundary_motion
      integer(c_size_t), value :: ni
      integer(c_size_t), value :: nj
      integer(c_size_t), value :: nk
      integer(c_int32_t), value :: directions
      real(c_double), intent(in) :: points(*)
      integer(c_size_t), value :: points_len
      integer(c_int32_t), value :: dim
      type(dk_boundary_motion), intent(in) :: motion
      real(c_double), intent(inout) :: scratch(*)
      integer(c_size_t), value :: scratch_len
      integer(c_int32_t), intent(inout) :: index_scratch(*)
      integer(c_size_t), value :: index_scratch_len
      real(c_double), intent(inout) :: translations(*)
      integer(c_size_t), value :: translations_len
      real(c_double), intent(inout) :: rotations(*)
      integer(c_size_t), value :: rotations_len
      real(c_double), intent(inout) :: out(*)
      integer(c_size_t), value :: out_len
      real(c_double), intent(inout) :: origin_out(*)
      integer(c_size_t), value :: origin_out_len
      integer(c_int32_t) :: s
    end function
    function dk_deform_tfi_f32(ni, nj, nk, directions, points, points_len, dim, motion, scratch, &
        scratch_len, index_scratch, index_scratch_len, translations, translations_len, rotations, &
        rotations_len, out, out_len, origin_out, origin_out_len) bind(C, name="dk_deform_tfi_f32") &
        result(s)
      import :: c_float, c_int32_t, c_size_t, dk_boundary_motion_f32
      integer(c_size_t), value :: ni
      integer(c_size_t), value :: nj
      integer(c_size_t), value :: nk
      integer(c_int32_t), value :: directions
      real(c_float), intent(in) :: points(*)
      integer(c_size_t), value :: points_len
      integer(c_int32_t), value :: dim
      type(dk_boundary_motion_f32), intent(in) :: motion
      real(c_float), intent(inout) :: scratch(*)
      integer(c_size_t), value :: scratch_len
      integer(c_int32_t), intent(inout) :: index_scratch(*)
      integer(c_size_t), value :: index_scratch_len
      real(c_float), intent(inout) :: translations(*)
      integer(c_size_t), value :: translations_len
      real(c_float), intent(inout) :: rotations(*)
      integer(c_size_t), value :: rotations_len
      real(c_float), intent(inout) :: out(*)
      integer(c_size_t), value :: out_len
      real(c_float), intent(inout) :: origin_out(*)
      integer(c_size_t), value :: origin_out_len
      integer(c_int32_t) :: s
    end function
    function dk_deform_boundary_normals_scratch_len(boundary_len, len_out) bind(C, &
        name="dk_deform_boundary_normals_scratch_len") result(s)
      import :: c_int32_t, c_size_t
      integer(c_size_t), value :: boundary_len
      integer(c_size_t), intent(inout) :: len_out
      integer(c_int32_t) :: s
    end function
    function dk_deform_boundary_normals(points, points_len, dim, element_offsets, &
        element_offsets_len, element_nodes, element_nodes_len, element_kinds, element_kinds_len, &
        index_base, scratch, scratch_len, index_scratch, index_scratch_len, normals, normals_len) &
        bind(C, name="dk_deform_boundary_normals") result(s)
      import :: c_double, c_int32_t, c_int8_t, c_size_t
      real(c_double), intent(in) :: points(*)
      integer(c_size_t), value :: points_len
      integer(c_int32_t), value :: dim
      integer(c_int32_t), intent(in) :: element_offsets(*)
      integer(c_size_t), value :: element_offsets_len
      integer(c_int32_t), intent(in) :: element_nodes(*)
      integer(c_size_t), value :: element_nodes_len
      integer(c_int8_t), intent(in) :: element_kinds(*)
      integer(c_size_t), value :: element_kinds_len
      integer(c_int32_t), value :: index_base
      real(c_double), intent(inout) :: scratch(*)
      integer(c_size_t), value :: scratch_len
      integer(c_int32_t), intent(inout) :: index_scratch(*)
      integer(c_size_t), value :: index_scratch_len
      real(c_double), intent(inout) :: normals(*)
      integer(c_size_t), value :: normals_len
      integer(c_int32_t) :: s
    end function
    function dk_deform_boundary_normals_f32(points, points_len, dim, element_offsets, &
        element_offsets_len, element_nodes, element_nodes_len, element_kinds, element_kinds_len, &
        index_base, scratch, scratch_len, index_scratch, index_scratch_len, normals, normals_len) &
        bind(C, name="dk_deform_boundary_normals_f32") result(s)
      import :: c_float, c_int32_t, c_int8_t, c_size_t
      real(c_float), intent(in) :: points(*)
      integer(c_size_t), value :: points_len
      integer(c_int32_t), value :: dim
      integer(c_int32_t), intent(in) :: element_offsets(*)
      integer(c_size_t), value :: element_offsets_len
      integer(c_int32_t), intent(in) :: element_nodes(*)
      integer(c_size_t), value :: element_nodes_len
      integer(c_int8_t), intent(in) :: element_kinds(*)
      integer(c_size_t), value :: element_kinds_len
      integer(c_int32_t), value :: index_base
      real(c_float), intent(inout) :: scratch(*)
      integer(c_size_t), value :: scratch_len
      integer(c_int32_t), intent(inout) :: index_scratch(*)
      integer(c_size_t), value :: index_scratch_len
      real(c_float), intent(inout) :: normals(*)
      integer(c_size_t), value :: normals_len
      integer(c_int32_t) :: s
    end function
    function dk_deform_boundary_rotations_scratch_len(boundary_len, dim, len_out) bind(C, &
        name="dk_deform_boundary_rotations_scratch_len") result(s)
      import :: c_int32_t, c_size_t
      integer(c_size_t), value :: boundary_len
      integer(c_int32_t), value :: dim
      integer(c_size_t), intent(inout) :: len_out
      integer(c_int32_t) :: s
    end function
    function dk_deform_boundary_rotations(undeformed, undeformed_len, deformed, deformed_len, dim, &
        element_offsets, element_offsets_len, element_nodes, element_nodes_len, element_kinds, &
        element_kinds_len, index_base, scratch, scratch_len, index_scratch, index_scratch_len, &
        rotations, rotations_len) bind(C, name="dk_deform_boundary_rotations") result(s)
      import :: c_double, c_int32_t, c_int8_t, c_size_t
      real(c_double), intent(in) :: undeformed(*)
      integer(c_size_t), value :: undeformed_len
      real(c_double), intent(in) :: deformed(*)
      integer(c_size_t), value :: deformed_len
      integer(c_int32_t), value :: dim
      integer(c_int32_t), intent(in) :: element_offsets(*)
      integer(c_size_t), value :: element_offsets_len
      integer(c_int32_t), intent(in) :: element_nodes(*)
      integer(c_size_t), value :: element_nodes_len
      integer(c_int8_t), intent(in) :: element_kinds(*)
      integer(c_size_t), value :: element_kinds_len
      integer(c_int32_t), value :: index_base
      real(c_double), intent(inout) :: scratch(*)
      integer(c_size_t), value :: scratch_len
      integer(c_int32_t), intent(inout) :: index_scratch(*)
      integer(c_size_t), value :: index_scratch_len
      real(c_double), intent(inout) :: rotations(*)
      integer(c_size_t), value :: rotations_len
      integer(c_int32_t) :: s
    end function
    function dk_deform_boundary_rotations_f32(undeformed, undeformed_len, deformed, deformed_len, &
        dim, element_offsets, element_offsets_len, element_nodes, element_nodes_len, &
        element_kinds, element_kinds_len, index_base, scratch, scratch_len, index_scratch, &
        index_scratch_len, rotations, rotations_len) bind(C, &
        name="dk_deform_boundary_rotations_f32") result(s)
      import :: c_float, c_int32_t, c_int8_t, c_size_t
      real(c_float), intent(in) :: undeformed(*)
      integer(c_size_t), value :: undeformed_len
      real(c_float), intent(in) :: deformed(*)
      integer(c_size_t), value :: deformed_len
      integer(c_int32_t), value :: dim
      integer(c_int32_t), intent(in) :: element_offsets(*)
      integer(c_size_t), value :: element_offsets_len
      integer(c_int32_t), intent(in) :: element_nodes(*)
      integer(c_size_t), value :: element_nodes_len
      integer(c_int8_t), intent(in) :: element_kinds(*)
      integer(c_size_t), value :: element_kinds_len
      integer(c_int32_t), value :: index_base
      real(c_float), intent(inout) :: scratch(*)
      integer(c_size_t), value :: scratch_len
      integer(c_int32_t), intent(inout) :: index_scratch(*)
      integer(c_size_t), value :: index_scratch_len
      real(c_float), intent(inout) :: rotations(*)
      integer(c_size_t), value :: rotations_len
      integer(c_int32_t) :: s
    end function
    function dk_deform_rigid_rotations(q, rotations, rotations_len) bind(C, &
        name="dk_deform_rigid_rotations") result(s)
      import :: c_double, c_int32_t, c_size_t
      real(c_double), intent(in) :: q(4)
      real(c_double), intent(inout) :: rotations(*)
      integer(c_size_t), value :: rotations_len
      integer(c_int32_t) :: s
    end function
    function dk_deform_rigid_rotations_f32(q, rotations, rotations_len) bind(C, &
        name="dk_deform_rigid_rotations_f32") result(s)
      import :: c_float, c_int32_t, c_size_t
      real(c_float), intent(in) :: q(4)
      real(c_float), intent(inout) :: rotations(*)
      integer(c_size_t), value :: rotations_len
      integer(c_int32_t) :: s
    end function
    function dk_deform_boundary_origin(undeformed, undeformed_len, deformed, deformed_len, dim, &
        origin_out, origin_out_len) bind(C, name="dk_deform_boundary_origin") result(s)
      import :: c_double, c_int32_t, c_size_t
      real(c_double), intent(in) :: undeformed(*)
      integer(c_size_t), value :: undeformed_len
      real(c_double), intent(in) :: deformed(*)
      integer(c_size_t), value :: deformed_len
      integer(c_int32_t), value :: dim
      real(c_double), intent(inout) :: origin_out(*)
      integer(c_size_t), value :: origin_out_len
      integer(c_int32_t) :: s
    end function
    function dk_deform_boundary_origin_f32(undeformed, undeformed_len, deformed, deformed_len, &
        dim, origin_out, origin_out_len) bind(C, name="dk_deform_boundary_origin_f32") result(s)
      import :: c_float, c_int32_t, c_size_t
      real(c_float), intent(in) :: undeformed(*)
      integer(c_size_t), value :: undeformed_len
      real(c_float), intent(in) :: deformed(*)
      integer(c_size_t), value :: deformed_len
      integer(c_int32_t), value :: dim
      real(c_float), intent(inout) :: origin_out(*)
      integer(c_size_t), value :: origin_out_len
      integer(c_int32_t) :: s
    end function
    function dk_deform_boundary_translations(origin, origin_len, undeformed, undeformed_len, &
        deformed, deformed_len, dim, rotations, rotations_len, translations, translations_len) &
        bind(C, name="dk_deform_boundary_translations") result(s)
      import :: c_double, c_int32_t, c_size_t
      real(c_double), intent(in) :: origin(*)
      integer(c_size_t), value :: origin_len
      real(c_double), intent(in) :: undeformed(*)
      integer(c_size_t), value :: undeformed_len
      real(c_double), intent(in) :: deformed(*)
      integer(c_size_t), value :: deformed_len
      integer(c_int32_t), value :: dim
      real(c_double), intent(in) :: rotations(*)
      integer(c_size_t), value :: rotations_len
      real(c_double), intent(inout) :: translations(*)
      integer(c_size_t), value :: translations_len
      integer(c_int32_t) :: s
    end function
    function dk_deform_boundary_translations_f32(origin, origin_len, undeformed, undeformed_len, &
        deformed, deformed_len, dim, rotations, rotations_len, translations, translations_len) &
        bind(C, name="dk_deform_boundary_translations_f32") result(s)
      import :: c_float, c_int32_t, c_size_t
      real(c_float), intent(in) :: origin(*)
      integer(c_size_t), value :: origin_len
      real(c_float), intent(in) :: undeformed(*)
      integer(c_size_t), value :: undeformed_len
      real(c_float), intent(in) :: deformed(*)
      integer(c_size_t), value :: deformed_len
      integer(c_int32_t), value :: dim
      real(c_float), intent(in) :: rotations(*)
      integer(c_size_t), value :: rotations_len
      real(c_float), intent(inout) :: translations(*)
      integer(c_size_t), value :: translations_len
      integer(c_int32_t) :: s
    end function
    function dk_deform_propagate_idw(points, points_len, dim, boundary, boundary_len, index_base, &
        exponent, index_scratch, index_scratch_len, translations, translations_len, rotations, &
        rotations_len) bind(C, name="dk_deform_propagate_idw") result(s)
      import :: c_double, c_int32_t, c_size_t
      real(c_double), intent(in) :: points(*)
      integer(c_size_t), value :: points_len
      integer(c_int32_t), value :: dim
      integer(c_int32_t), intent(in) :: boundary(*)
      integer(c_size_t), value :: boundary_len
      integer(c_int32_t), value :: index_base
      real(c_double), value :: exponent
      integer(c_int32_t), intent(inout) :: index_scratch(*)
      integer(c_size_t), value :: index_scratch_len
      real(c_double), intent(inout) :: translations(*)
      integer(c_size_t), value :: translations_len
      real(c_double), intent(inout) :: rotations(*)
      integer(c_size_t), value :: rotations_len
      integer(c_int32_t) :: s
    end function
    function dk_deform_propagate_idw_f32(points, points_len, dim, boundary, boundary_len, &
        index_base, exponent, index_scratch, index_scratch_len, translations, translations_len, &
        rotations, rotations_len) bind(C, name="dk_deform_propagate_idw_f32") result(s)
      import :: c_float, c_int32_t, c_size_t
      real(c_float), intent(in) :: points(*)
      integer(c_size_t), value :: points_len
      integer(c_int32_t), value :: dim
      integer(c_int32_t), intent(in) :: boundary(*)
      integer(c_size_t), value :: boundary_len
      integer(c_int32_t), value :: index_base
      real(c_float), value :: exponent
      integer(c_int32_t), intent(inout) :: index_scratch(*)
      integer(c_size_t), value :: index_scratch_len
      real(c_float), intent(inout) :: translations(*)
      integer(c_size_t), value :: translations_len
      real(c_float), intent(inout) :: rotations(*)
      integer(c_size_t), value :: rotations_len
      integer(c_int32_t) :: s
    end function
    function dk_deform_propagate_tfi_scratch_len(ni, nj, nk, dim, len_out) bind(C, &
        name="dk_deform_propagate_tfi_scratch_len") result(s)
      import :: c_int32_t, c_size_t
      integer(c_size_t), value :: ni
      integer(c_size_t), value :: nj
      integer(c_size_t), value :: nk
      integer(c_int32_t), value :: dim
      integer(c_size_t), intent(inout) :: len_out
      integer(c_int32_t) :: s
    end function
    function dk_deform_propagate_tfi(ni, nj, nk, directions, points, points_len, dim, scratch, &
        scratch_len, translations, translations_len, rotations, rotations_len) bind(C, &
        name="dk_deform_propagate_tfi") result(s)
      import :: c_double, c_int32_t, c_size_t
      integer(c_size_t), value :: ni
      integer(c_size_t), value :: nj
      integer(c_size_t), value :: nk
      integer(c_int32_t), value :: directions
      real(c_double), intent(in) :: points(*)
      integer(c_size_t), value :: points_len
      integer(c_int32_t), value :: dim
      real(c_double), intent(inout) :: scratch(*)
      integer(c_size_t), value :: scratch_len
      real(c_double), intent(inout) :: translations(*)
      integer(c_size_t), value :: translations_len
      real(c_double), intent(inout) :: rotations(*)
      integer(c_size_t), value :: rotations_len
      integer(c_int32_t) :: s
    end function
    function dk_deform_propagate_tfi_f32(ni, nj, nk, directions, points, points_len, dim, scratch, &
        scratch_len, translations, translations_len, rotations, rotations_len) bind(C, &
        name="dk_deform_propagate_tfi_f32") result(s)
      import :: c_float, c_int32_t, c_size_t
      integer(c_size_t), value :: ni
      integer(c_size_t), value :: nj
      integer(c_size_t), value :: nk
      integer(c_int32_t), value :: directions
      real(c_float), intent(in) :: points(*)
      integer(c_size_t), value :: points_len
      integer(c_int32_t), value :: dim
      real(c_float), intent(inout) :: scratch(*)
      integer(c_size_t), value :: scratch_len
      real(c_float), intent(inout) :: translations(*)
      integer(c_size_t), value :: translations_len
      real(c_float), intent(inout) :: rotations(*)
      integer(c_size_t), value :: rotations_len
      integer(c_int32_t) :: s
    end function
    function dk_deform_displacement_tfi(ni, nj, nk, directions, points, points_len, dim, scratch, &
        scratch_len, displacements, displacements_len) bind(C, name="dk_deform_displacement_tfi") &
        result(s)
      import :: c_double, c_int32_t, c_size_t
      integer(c_size_t), value :: ni
      integer(c_size_t), value :: nj
      integer(c_size_t), value :: nk
      integer(c_int32_t), value :: directions
      real(c_double), intent(in) :: points(*)
      integer(c_size_t), value :: points_len
      integer(c_int32_t), value :: dim
      real(c_double), intent(inout) :: scratch(*)
      integer(c_size_t), value :: scratch_len
      real(c_double), intent(inout) :: displacements(*)
      integer(c_size_t), value :: displacements_len
      integer(c_int32_t) :: s
    end function
    function dk_deform_displacement_tfi_f32(ni, nj, nk, directions, points, points_len, dim, &
        scratch, scratch_len, displacements, displacements_len) bind(C, &
        name="dk_deform_displacement_tfi_f32") result(s)
      import :: c_float, c_int32_t, c_size_t
      integer(c_size_t), value :: ni
      integer(c_size_t), value :: nj
      integer(c_size_t), value :: nk
      integer(c_int32_t), value :: directions
      real(c_float), intent(in) :: points(*)
      integer(c_size_t), value :: points_len
      integer(c_int32_t), value :: dim
      real(c_float), intent(inout) :: scratch(*)
      integer(c_size_t), value :: scratch_len
      real(c_float), intent(inout) :: displacements(*)
      integer(c_size_t), value :: displacements_len
      integer(c_int32_t) :: s
    end function
    function dk_deform_update_points(origin, origin_len, points, points_len, dim, translations, &
        translations_len, rotations, rotations_len, boundary, boundary_len, index_base, &
        boundary_deformed, boundary_deformed_len, index_scratch, index_scratch_len, out, out_len) &
        bind(C, name="dk_deform_update_points") result(s)
      import :: c_double, c_int32_t, c_size_t
      real(c_double), intent(in) :: origin(*)
      integer(c_size_t), value :: origin_len
      real(c_double), intent(in) :: points(*)
      integer(c_size_t), value :: points_len
      integer(c_int32_t), value :: dim
      real(c_double), intent(in) :: translations(*)
      integer(c_size_t), value :: translations_len
      real(c_double), intent(in) :: rotations(*)
      integer(c_size_t), value :: rotations_len
      integer(c_int32_t), intent(in) :: boundary(*)
      integer(c_size_t), value :: boundary_len
      integer(c_int32_t), value :: index_base
      real(c_double), intent(in) :: boundary_deformed(*)
      integer(c_size_t), value :: boundary_deformed_len
      integer(c_int32_t), intent(inout) :: index_scratch(*)
      integer(c_size_t), value :: index_scratch_len
      real(c_double), intent(inout) :: out(*)
      integer(c_size_t), value :: out_len
      integer(c_int32_t) :: s
    end function
    function dk_deform_update_points_f32(origin, origin_len, points, points_len, dim, &
        translations, translations_len, rotations, rotations_len, boundary, boundary_len, &
        index_base, boundary_deformed, boundary_deformed_len, index_scratch, index_scratch_len, &
        out, out_len) bind(C, name="dk_deform_update_points_f32") result(s)
      import :: c_float, c_int32_t, c_size_t
      real(c_float), intent(in) :: origin(*)
      integer(c_size_t), value :: origin_len
      real(c_float), intent(in) :: points(*)
      integer(c_size_t), value :: points_len
      integer(c_int32_t), value :: dim
      real(c_float), intent(in) :: translations(*)
      integer(c_size_t), value :: translations_len
      real(c_float), intent(in) :: rotations(*)
      integer(c_size_t), value :: rotations_len
      integer(c_int32_t), intent(in) :: boundary(*)
      integer(c_size_t), value :: boundary_len
      integer(c_int32_t), value :: index_base
      real(c_float), intent(in) :: boundary_deformed(*)
      integer(c_size_t), value :: boundary_deformed_len
      integer(c_int32_t), intent(inout) :: index_scratch(*)
      integer(c_size_t), value :: index_scratch_len
      real(c_float), intent(inout) :: out(*)
      integer(c_size_t), value :: out_len
      integer(c_int32_t) :: s
    end function
    function dk_deform_localize_nodes_scratch_len(node_count, boundary_len, global_len, &
        index_base, len_out) bind(C, name="dk_deform_localize_nodes_scratch_len") result(s)
      import :: c_int32_t, c_size_t
      integer(c_size_t), value :: node_count
      integer(c_size_t), value :: boundary_len
      integer(c_size_t), value :: global_len
      integer(c_int32_t), value :: index_base
      integer(c_size_t), intent(inout) :: len_out
      integer(c_int32_t) :: s
    end function
    function dk_deform_localize_nodes(node_count, boundary, boundary_len, global, global_len, &
        index_base, scratch, scratch_len, local, local_len) bind(C, &
        name="dk_deform_localize_nodes") result(s)
      import :: c_int32_t, c_size_t
      integer(c_size_t), value :: node_count
      integer(c_int32_t), intent(in) :: boundary(*)
      integer(c_size_t), value :: boundary_len
      integer(c_int32_t), intent(in) :: global(*)
      integer(c_size_t), value :: global_len
      integer(c_int32_t), value :: index_base
      integer(c_int32_t), intent(inout) :: scratch(*)
      integer(c_size_t), value :: scratch_len
      integer(c_int32_t), intent(inout) :: local(*)
      integer(c_size_t), value :: local_len
      integer(c_int32_t) :: s
    end function
    function dk_deform_spring_scratch_len(node_count, boundary_len, dim, options, scratch_len_out, &
        values_len_out) bind(C, name="dk_deform_spring_scratch_len") result(s)
      import :: c_int32_t, c_size_t, dk_spring_solve_options
      integer(c_size_t), value :: node_count
      integer(c_size_t), value :: boundary_len
      integer(c_int32_t), value :: dim
      type(dk_spring_solve_options), intent(in) :: options
      integer(c_size_t), intent(inout) :: scratch_len_out
      integer(c_size_t), intent(inout) :: values_len_out
      integer(c_int32_t) :: s
    end function
    function dk_deform_spring_index_scratch_len(motion, node_count, len_out) bind(C, &
        name="dk_deform_spring_index_scratch_len") result(s)
      import :: c_int32_t, c_size_t, dk_boundary_motion
      type(dk_boundary_motion), intent(in) :: motion
      integer(c_size_t), value :: node_count
      integer(c_size_t), intent(inout) :: len_out
      integer(c_int32_t) :: s
    end function
    function dk_deform_spring_index_scratch_len_f32(motion, node_count, len_out) bind(C, &
        name="dk_deform_spring_index_scratch_len_f32") result(s)
      import :: c_int32_t, c_size_t, dk_boundary_motion_f32
      type(dk_boundary_motion_f32), intent(in) :: motion
      integer(c_size_t), value :: node_count
      integer(c_size_t), intent(inout) :: len_out
      integer(c_int32_t) :: s
    end function
    function dk_deform_spring(points, points_len, dim, motion, offsets, offsets_len, targets, &
        targets_len, stiffness, stiffness_len, fixed, fixed_len, options, scratch, scratch_len, &
        values, values_len, index_scratch, index_scratch_len, translations, translations_len, &
        rotations, rotations_len, out, out_len, origin_out, origin_out_len, report) bind(C, &
        name="dk_deform_spring") result(s)
      import :: c_double, c_int32_t, c_int8_t, c_size_t, dk_boundary_motion, &
          dk_spring_solve_options, dk_spring_solve_report
      real(c_double), intent(in) :: points(*)
      integer(c_size_t), value :: points_len
      integer(c_int32_t), value :: dim
      type(dk_boundary_motion), intent(in) :: motion
      integer(c_int32_t), intent(in) :: offsets(*)
      integer(c_size_t), value :: offsets_len
      integer(c_int32_t), intent(in) :: targets(*)
      integer(c_size_t), value :: targets_len
      real(c_double), intent(in) :: stiffness(*)
      integer(c_size_t), value :: stiffness_len
      integer(c_int8_t), intent(in) :: fixed(*)
      integer(c_size_t), value :: fixed_len
      type(dk_spring_solve_options), intent(in) :: options
      real(c_double), intent(inout) :: scratch(*)
      integer(c_size_t), value :: scratch_len
      real(c_double), intent(inout) :: values(*)
      integer(c_size_t), value :: values_len
      integer(c_int32_t), intent(inout) :: index_scratch(*)
      integer(c_size_t), value :: index_scratch_len
      real(c_double), intent(inout) :: translations(*)
      integer(c_size_t), value :: translations_len
      real(c_double), intent(inout) :: rotations(*)
      integer(c_size_t), value :: rotations_len
      real(c_double), intent(inout) :: out(*)
      integer(c_size_t), value :: out_len
      real(c_double), intent(inout) :: origin_out(*)
      integer(c_size_t), value :: origin_out_len
      type(dk_spring_solve_report), intent(inout) :: report
      integer(c_int32_t) :: s
    end function
    function dk_deform_spring_f32(points, points_len, dim, motion, offsets, offsets_len, targets, &
        targets_len, stiffness, stiffness_len, fixed, fixed_len, options, scratch, scratch_len, &
        values, values_len, index_scratch, index_scratch_len, translations, translations_len, &
        rotations, rotations_len, out, out_len, origin_out, origin_out_len, report) bind(C, &
        name="dk_deform_spring_f32") result(s)
      import :: c_float, c_int32_t, c_int8_t, c_size_t, dk_boundary_motion_f32, &
          dk_spring_solve_options, dk_spring_solve_report
      real(c_float), intent(in) :: points(*)
      integer(c_size_t), value :: points_len
      integer(c_int32_t), value :: dim
      type(dk_boundary_motion_f32), intent(in) :: motion
      integer(c_int32_t), intent(in) :: offsets(*)
      integer(c_size_t), value :: offsets_len
      integer(c_int32_t), intent(in) :: targets(*)
      integer(c_size_t), value :: targets_len
      real(c_float), intent(in) :: stiffness(*)
      integer(c_size_t), value :: stiffness_len
      integer(c_int8_t), intent(in) :: fixed(*)
      integer(c_size_t), value :: fixed_len
      type(dk_spring_solve_options), intent(in) :: options
      real(c_float), intent(inout) :: scratch(*)
      integer(c_size_t), value :: scratch_len
      real(c_float), intent(inout) :: values(*)
      integer(c_size_t), value :: values_len
      integer(c_int32_t), intent(inout) :: index_scratch(*)
      integer(c_size_t), value :: index_scratch_len
      real(c_float), intent(inout) :: translations(*)
      integer(c_size_t), value :: translations_len
      real(c_float), intent(inout) :: rotations(*)
      integer(c_size_t), value :: rotations_len
      real(c_float), intent(inout) :: out(*)
      integer(c_size_t), value :: out_len
      real(c_float), intent(inout) :: origin_out(*)
      integer(c_size_t), value :: origin_out_len
      type(dk_spring_solve_report), intent(inout) :: report
      integer(c_int32_t) :: s
    end function
    function dk_deform_propagate_spring_scratch_len(node_count, dim, options, len_out) bind(C, &
        name="dk_deform_propagate_spring_scratch_len") result(s)
      import :: c_int32_t, c_size_t, dk_spring_solve_options
      integer(c_size_t), value :: node_count
      integer(c_int32_t), value :: dim
      type(dk_spring_solve_options), intent(in) :: options
      integer(c_size_t), intent(inout) :: len_out
      integer(c_int32_t) :: s
    end function
    function dk_deform_propagate_spring(offsets, offsets_len, targets, targets_len, stiffness, &
        stiffness_len, fixed, fixed_len, options, dim, index_scratch, index_scratch_len, values, &
        values_len, translations, translations_len, rotations, rotations_len, report) bind(C, &
        name="dk_deform_propagate_spring") result(s)
      import :: c_double, c_int32_t, c_int8_t, c_size_t, dk_spring_solve_options, &
          dk_spring_solve_report
      integer(c_int32_t), intent(in) :: offsets(*)
      integer(c_size_t), value :: offsets_len
      integer(c_int32_t), intent(in) :: targets(*)
      integer(c_size_t), value :: targets_len
      real(c_double), intent(in) :: stiffness(*)
      integer(c_size_t), value :: stiffness_len
      integer(c_int8_t), intent(in) :: fixed(*)
      integer(c_size_t), value :: fixed_len
      type(dk_spring_solve_options), intent(in) :: options
      integer(c_int32_t), value :: dim
      integer(c_int32_t), intent(inout) :: index_scratch(*)
      integer(c_size_t), value :: index_scratch_len
      real(c_double), intent(inout) :: values(*)
      integer(c_size_t), value :: values_len
      real(c_double), intent(inout) :: translations(*)
      integer(c_size_t), value :: translations_len
      real(c_double), intent(inout) :: rotations(*)
      integer(c_size_t), value :: rotations_len
      type(dk_spring_solve_report), intent(inout) :: report
      integer(c_int32_t) :: s
    end function
    function dk_deform_propagate_spring_f32(offsets, offsets_len, targets, targets_len, stiffness, &
        stiffness_len, fixed, fixed_len, options, dim, index_scratch, index_scratch_len, values, &
        values_len, translations, translations_len, rotations, rotations_len, report) bind(C, &
        name="dk_deform_propagate_spring_f32") result(s)
      import :: c_float, c_int32_t, c_int8_t, c_size_t, dk_spring_solve_options, &
          dk_spring_solve_report
      integer(c_int32_t), intent(in) :: offsets(*)
      integer(c_size_t), value :: offsets_len
      integer(c_int32_t), intent(in) :: targets(*)
      integer(c_size_t), value :: targets_len
      real(c_float), intent(in) :: stiffness(*)
      integer(c_size_t), value :: stiffness_len
      integer(c_int8_t), intent(in) :: fixed(*)
      integer(c_size_t), value :: fixed_len
      type(dk_spring_solve_options), intent(in) :: options
      integer(c_int32_t), value :: dim
      integer(c_int32_t), intent(inout) :: index_scratch(*)
      integer(c_size_t), value :: index_scratch_len
      real(c_float), intent(inout) :: values(*)
      integer(c_size_t), value :: values_len
      real(c_float), intent(inout) :: translations(*)
      integer(c_size_t), value :: translations_len
      real(c_float), intent(inout) :: rotations(*)
      integer(c_size_t), value :: rotations_len
      type(dk_spring_solve_report), intent(inout) :: report
      integer(c_int32_t) :: s
    end function
    function dk_graph_from_edges_len(edges_len, len_out) bind(C, name="dk_graph_from_edges_len") &
        result(s)
      import :: c_int32_t, c_size_t
      integer(c_size_t), value :: edges_len
      integer(c_size_t), intent(inout) :: len_out
      integer(c_int32_t) :: s
    end function
    function dk_graph_from_edges(node_count, edges, edges_len, index_base, index_scratch, &
        index_scratch_len, offsets, offsets_len, targets, targets_len, used_out) bind(C, &
        name="dk_graph_from_edges") result(s)
      import :: c_int32_t, c_size_t
      integer(c_size_t), value :: node_count
      integer(c_int32_t), intent(in) :: edges(*)
      integer(c_size_t), value :: edges_len
      integer(c_int32_t), value :: index_base
      integer(c_int32_t), intent(inout) :: index_scratch(*)
      integer(c_size_t), value :: index_scratch_len
      integer(c_int32_t), intent(inout) :: offsets(*)
      integer(c_size_t), value :: offsets_len
      integer(c_int32_t), intent(inout) :: targets(*)
      integer(c_size_t), value :: targets_len
      integer(c_size_t), intent(inout) :: used_out
      integer(c_int32_t) :: s
    end function
    function dk_cells_check(node_count, cell_offsets, cell_offsets_len, cell_nodes, &
        cell_nodes_len, cell_kinds, cell_kinds_len, index_base, index_scratch, index_scratch_len) &
        bind(C, name="dk_cells_check") result(s)
      import :: c_int32_t, c_int8_t, c_size_t
      integer(c_size_t), value :: node_count
      integer(c_int32_t), intent(in) :: cell_offsets(*)
      integer(c_size_t), value :: cell_offsets_len
      integer(c_int32_t), intent(in) :: cell_nodes(*)
      integer(c_size_t), value :: cell_nodes_len
      integer(c_int8_t), intent(in) :: cell_kinds(*)
      integer(c_size_t), value :: cell_kinds_len
      integer(c_int32_t), value :: index_base
      integer(c_int32_t), intent(inout) :: index_scratch(*)
      integer(c_size_t), value :: index_scratch_len
      integer(c_int32_t) :: s
    end function
    function dk_graph_from_cells_len(node_count, cell_offsets, cell_offsets_len, cell_nodes, &
        cell_nodes_len, cell_kinds, cell_kinds_len, index_base, index_scratch, index_scratch_len, &
        face_diagonals, len_out) bind(C, name="dk_graph_from_cells_len") result(s)
      import :: c_bool, c_int32_t, c_int8_t, c_size_t
      integer(c_size_t), value :: node_count
      integer(c_int32_t), intent(in) :: cell_offsets(*)
      integer(c_size_t), value :: cell_offsets_len
      integer(c_int32_t), intent(in) :: cell_nodes(*)
      integer(c_size_t), value :: cell_nodes_len
      integer(c_int8_t), intent(in) :: cell_kinds(*)
      integer(c_size_t), value :: cell_kinds_len
      integer(c_int32_t), value :: index_base
      integer(c_int32_t), intent(inout) :: index_scratch(*)
      integer(c_size_t), value :: index_scratch_len
      logical(c_bool), value :: face_diagonals
      integer(c_size_t), intent(inout) :: len_out
      integer(c_int32_t) :: s
    end function
    function dk_graph_from_cells(node_count, cell_offsets, cell_offsets_len, cell_nodes, &
        cell_nodes_len, cell_kinds, cell_kinds_len, index_base, index_scratch, index_scratch_len, &
        face_diagonals, offsets, offsets_len, targets, targets_len, used_out) bind(C, &
        name="dk_graph_from_cells") result(s)
      import :: c_bool, c_int32_t, c_int8_t, c_size_t
      integer(c_size_t), value :: node_count
      integer(c_int32_t), intent(in) :: cell_offsets(*)
      integer(c_size_t), value :: cell_offsets_len
      integer(c_int32_t), intent(in) :: cell_nodes(*)
      integer(c_size_t), value :: cell_nodes_len
      integer(c_int8_t), intent(in) :: cell_kinds(*)
      integer(c_size_t), value :: cell_kinds_len
      integer(c_int32_t), value :: index_base
      integer(c_int32_t), intent(inout) :: index_scratch(*)
      integer(c_size_t), value :: index_scratch_len
      logical(c_bool), value :: face_diagonals
      integer(c_int32_t), intent(inout) :: offsets(*)
      integer(c_size_t), value :: offsets_len
      integer(c_int32_t), intent(inout) :: targets(*)
      integer(c_size_t), value :: targets_len
      integer(c_size_t), intent(inout) :: used_out
      integer(c_int32_t) :: s
    end function
    function dk_graph_check(offsets, offsets_len, targets, targets_len, require_symmetric) bind(C, &
        name="dk_graph_check") result(s)
      import :: c_bool, c_int32_t, c_size_t
      integer(c_int32_t), intent(in) :: offsets(*)
      integer(c_size_t), value :: offsets_len
      integer(c_int32_t), intent(in) :: targets(*)
      integer(c_size_t), value :: targets_len
      logical(c_bool), value :: require_symmetric
      integer(c_int32_t) :: s
    end function
    function dk_plan_options_default(out) bind(C, name="dk_plan_options_default") result(s)
      import :: c_int32_t, dk_plan_options
      type(dk_plan_options), intent(inout) :: out
      integer(c_int32_t) :: s
    end function
    function dk_plan_options_default_f32(out) bind(C, name="dk_plan_options_default_f32") &
        result(s)
      import :: c_int32_t, dk_plan_options
      type(dk_plan_options), intent(inout) :: out
      integer(c_int32_t) :: s
    end function
    function dk_plan_work_sizes(points, points_len, offsets, offsets_len, targets, targets_len, &
        boundary, boundary_len, element_offsets, element_offsets_len, element_nodes, &
        element_nodes_len, element_kinds, element_kinds_len, stiffness, stiffness_len, dim, &
        options, sizes_out) bind(C, name="dk_plan_work_sizes") result(s)
      import :: c_double, c_int32_t, c_ptr, c_size_t, dk_plan_options, dk_plan_sizes
      real(c_double), intent(in) :: points(*)
      integer(c_size_t), value :: points_len
      integer(c_int32_t), intent(in) :: offsets(*)
      integer(c_size_t), value :: offsets_len
      integer(c_int32_t), intent(in) :: targets(*)
      integer(c_size_t), value :: targets_len
      integer(c_int32_t), intent(in) :: boundary(*)
      integer(c_size_t), value :: boundary_len
      type(c_ptr), value :: element_offsets
      integer(c_size_t), value :: element_offsets_len
      type(c_ptr), value :: element_nodes
      integer(c_size_t), value :: element_nodes_len
      type(c_ptr), value :: element_kinds
      integer(c_size_t), value :: element_kinds_len
      type(c_ptr), value :: stiffness
      integer(c_size_t), value :: stiffness_len
      integer(c_int32_t), value :: dim
      type(dk_plan_options), intent(in) :: options
      type(dk_plan_sizes), intent(inout) :: sizes_out
      integer(c_int32_t) :: s
    end function
    function dk_plan_work_sizes_f32(points, points_len, offsets, offsets_len, targets, &
        targets_len, boundary, boundary_len, element_offsets, element_offsets_len, element_nodes, &
        element_nodes_len, element_kinds, element_kinds_len, stiffness, stiffness_len, dim, &
        options, sizes_out) bind(C, name="dk_plan_work_sizes_f32") result(s)
      import :: c_float, c_int32_t, c_ptr, c_size_t, dk_plan_options, dk_plan_sizes
      real(c_float), intent(in) :: points(*)
      integer(c_size_t), value :: points_len
      integer(c_int32_t), intent(in) :: offsets(*)
      integer(c_size_t), value :: offsets_len
      integer(c_int32_t), intent(in) :: targets(*)
      integer(c_size_t), value :: targets_len
      integer(c_int32_t), intent(in) :: boundary(*)
      integer(c_size_t), value :: boundary_len
      type(c_ptr), value :: element_offsets
      integer(c_size_t), value :: element_offsets_len
      type(c_ptr), value :: element_nodes
      integer(c_size_t), value :: element_nodes_len
      type(c_ptr), value :: element_kinds
      integer(c_size_t), value :: element_kinds_len
      type(c_ptr), value :: stiffness
      integer(c_size_t), value :: stiffness_len
      integer(c_int32_t), value :: dim
      type(dk_plan_options), intent(in) :: options
      type(dk_plan_sizes), intent(inout) :: sizes_out
      integer(c_int32_t) :: s
    end function
    function dk_plan_pool_sizes(points, points_len, offsets, offsets_len, targets, targets_len, &
        boundary, boundary_len, element_offsets, element_offsets_len, element_nodes, &
        element_nodes_len, element_kinds, element_kinds_len, stiffness, stiffness_len, dim, &
        options, work_reals, work_reals_len, work_indices, work_indices_len, work_bytes, &
        work_bytes_len, sizes_out) bind(C, name="dk_plan_pool_sizes") result(s)
      import :: c_double, c_int32_t, c_int8_t, c_ptr, c_size_t, dk_plan_options, dk_plan_sizes
      real(c_double), intent(in) :: points(*)
      integer(c_size_t), value :: points_len
      integer(c_int32_t), intent(in) :: offsets(*)
      integer(c_size_t), value :: offsets_len
      integer(c_int32_t), intent(in) :: targets(*)
      integer(c_size_t), value :: targets_len
      integer(c_int32_t), intent(in) :: boundary(*)
      integer(c_size_t), value :: boundary_len
      type(c_ptr), value :: element_offsets
      integer(c_size_t), value :: element_offsets_len
      type(c_ptr), value :: element_nodes
      integer(c_size_t), value :: element_nodes_len
      type(c_ptr), value :: element_kinds
      integer(c_size_t), value :: element_kinds_len
      type(c_ptr), value :: stiffness
      integer(c_size_t), value :: stiffness_len
      integer(c_int32_t), value :: dim
      type(dk_plan_options), intent(in) :: options
      real(c_double), intent(inout) :: work_reals(*)
      integer(c_size_t), value :: work_reals_len
      integer(c_int32_t), intent(inout) :: work_indices(*)
      integer(c_size_t), value :: work_indices_len
      integer(c_int8_t), intent(inout) :: work_bytes(*)
      integer(c_size_t), value :: work_bytes_len
      type(dk_plan_sizes), intent(inout) :: sizes_out
      integer(c_int32_t) :: s
    end function
    function dk_plan_pool_sizes_f32(points, points_len, offsets, offsets_len, targets, &
        targets_len, boundary, boundary_len, element_offsets, element_offsets_len, element_nodes, &
        element_nodes_len, element_kinds, element_kinds_len, stiffness, stiffness_len, dim, &
        options, work_reals, work_reals_len, work_indices, work_indices_len, work_bytes, &
        work_bytes_len, sizes_out) bind(C, name="dk_plan_pool_sizes_f32") result(s)
      import :: c_float, c_int32_t, c_int8_t, c_ptr, c_size_t, dk_plan_options, dk_plan_sizes
      real(c_float), intent(in) :: points(*)
      integer(c_size_t), value :: points_len
      integer(c_int32_t), intent(in) :: offsets(*)
      integer(c_size_t), value :: offsets_len
      integer(c_int32_t), intent(in) :: targets(*)
      integer(c_size_t), value :: targets_len
      integer(c_int32_t), intent(in) :: boundary(*)
      integer(c_size_t), value :: boundary_len
      type(c_ptr), value :: element_offsets
      integer(c_size_t), value :: element_offsets_len
      type(c_ptr), value :: element_nodes
      integer(c_size_t), value :: element_nodes_len
      type(c_ptr), value :: element_kinds
      integer(c_size_t), value :: element_kinds_len
      type(c_ptr), value :: stiffness
      integer(c_size_t), value :: stiffness_len
      integer(c_int32_t), value :: dim
      type(dk_plan_options), intent(in) :: options
      real(c_float), intent(inout) :: work_reals(*)
      integer(c_size_t), value :: work_reals_len
      integer(c_int32_t), intent(inout) :: work_indices(*)
      integer(c_size_t), value :: work_indices_len
      integer(c_int8_t), intent(inout) :: work_bytes(*)
      integer(c_size_t), value :: work_bytes_len
      type(dk_plan_sizes), intent(inout) :: sizes_out
      integer(c_int32_t) :: s
    end function
    function dk_plan_init(points, points_len, offsets, offsets_len, targets, targets_len, &
        boundary, boundary_len, element_offsets, element_offsets_len, element_nodes, &
        element_nodes_len, element_kinds, element_kinds_len, stiffness, stiffness_len, dim, &
        options, work_reals, work_reals_len, work_indices, work_indices_len, work_bytes, &
        work_bytes_len, reals, reals_len, indices, indices_len, bytes, bytes_len, info_out) &
        bind(C, name="dk_plan_init") result(s)
      import :: c_double, c_int32_t, c_int8_t, c_ptr, c_size_t, dk_plan_info, dk_plan_options
      real(c_double), intent(in) :: points(*)
      integer(c_size_t), value :: points_len
      integer(c_int32_t), intent(in) :: offsets(*)
      integer(c_size_t), value :: offsets_len
      integer(c_int32_t), intent(in) :: targets(*)
      integer(c_size_t), value :: targets_len
      integer(c_int32_t), intent(in) :: boundary(*)
      integer(c_size_t), value :: boundary_len
      type(c_ptr), value :: element_offsets
      integer(c_size_t), value :: element_offsets_len
      type(c_ptr), value :: element_nodes
      integer(c_size_t), value :: element_nodes_len
      type(c_ptr), value :: element_kinds
      integer(c_size_t), value :: element_kinds_len
      type(c_ptr), value :: stiffness
      integer(c_size_t), value :: stiffness_len
      integer(c_int32_t), value :: dim
      type(dk_plan_options), intent(in) :: options
      real(c_double), intent(inout) :: work_reals(*)
      integer(c_size_t), value :: work_reals_len
      integer(c_int32_t), intent(inout) :: work_indices(*)
      integer(c_size_t), value :: work_indices_len
      integer(c_int8_t), intent(inout) :: work_bytes(*)
      integer(c_size_t), value :: work_bytes_len
      real(c_double), intent(inout) :: reals(*)
      integer(c_size_t), value :: reals_len
      integer(c_int32_t), intent(inout) :: indices(*)
      integer(c_size_t), value :: indices_len
      integer(c_int8_t), intent(inout) :: bytes(*)
      integer(c_size_t), value :: bytes_len
      type(dk_plan_info), intent(inout) :: info_out
      integer(c_int32_t) :: s
    end function
    function dk_plan_init_f32(points, points_len, offsets, offsets_len, targets, targets_len, &
        boundary, boundary_len, element_offsets, element_offsets_len, element_nodes, &
        element_nodes_len, element_kinds, element_kinds_len, stiffness, stiffness_len, dim, &
        options, work_reals, work_reals_len, work_indices, work_indices_len, work_bytes, &
        work_bytes_len, reals, reals_len, indices, indices_len, bytes, bytes_len, info_out) &
        bind(C, name="dk_plan_init_f32") result(s)
      import :: c_float, c_int32_t, c_int8_t, c_ptr, c_size_t, dk_plan_info, dk_plan_options
      real(c_float), intent(in) :: points(*)
      integer(c_size_t), value :: points_len
      integer(c_int32_t), intent(in) :: offsets(*)
      integer(c_size_t), value :: offsets_len
      integer(c_int32_t), intent(in) :: targets(*)
      integer(c_size_t), value :: targets_len
      integer(c_int32_t), intent(in) :: boundary(*)
      integer(c_size_t), value :: boundary_len
      type(c_ptr), value :: element_offsets
      integer(c_size_t), value :: element_offsets_len
      type(c_ptr), value :: element_nodes
      integer(c_size_t), value :: element_nodes_len
      type(c_ptr), value :: element_kinds
      integer(c_size_t), value :: element_kinds_len
      type(c_ptr), value :: stiffness
      integer(c_size_t), value :: stiffness_len
      integer(c_int32_t), value :: dim
      type(dk_plan_options), intent(in) :: options
      real(c_float), intent(inout) :: work_reals(*)
      integer(c_size_t), value :: work_reals_len
      integer(c_int32_t), intent(inout) :: work_indices(*)
      integer(c_size_t), value :: work_indices_len
      integer(c_int8_t), intent(inout) :: work_bytes(*)
      integer(c_size_t), value :: work_bytes_len
      real(c_float), intent(inout) :: reals(*)
      integer(c_size_t), value :: reals_len
      integer(c_int32_t), intent(inout) :: indices(*)
      integer(c_size_t), value :: indices_len
      integer(c_int8_t), intent(inout) :: bytes(*)
      integer(c_size_t), value :: bytes_len
      type(dk_plan_info), intent(inout) :: info_out
      integer(c_int32_t) :: s
    end function
    function dk_plan_open(reals, reals_len, indices, indices_len, bytes, bytes_len, dim, info_out) &
        bind(C, name="dk_plan_open") result(s)
      import :: c_double, c_int32_t, c_int8_t, c_size_t, dk_plan_info
      real(c_double), intent(inout) :: reals(*)
      integer(c_size_t), value :: reals_len
      integer(c_int32_t), intent(inout) :: indices(*)
      integer(c_size_t), value :: indices_len
      integer(c_int8_t), intent(inout) :: bytes(*)
      integer(c_size_t), value :: bytes_len
      integer(c_int32_t), value :: dim
      type(dk_plan_info), intent(inout) :: info_out
      integer(c_int32_t) :: s
    end function
    function dk_plan_open_f32(reals, reals_len, indices, indices_len, bytes, bytes_len, dim, &
        info_out) bind(C, name="dk_plan_open_f32") result(s)
      import :: c_float, c_int32_t, c_int8_t, c_size_t, dk_plan_info
      real(c_float), intent(inout) :: reals(*)
      integer(c_size_t), value :: reals_len
      integer(c_int32_t), intent(inout) :: indices(*)
      integer(c_size_t), value :: indices_len
      integer(c_int8_t), intent(inout) :: bytes(*)
      integer(c_size_t), value :: bytes_len
      integer(c_int32_t), value :: dim
      type(dk_plan_info), intent(inout) :: info_out
      integer(c_int32_t) :: s
    end function
    function dk_plan_step(reals, reals_len, indices, indices_len, bytes, bytes_len, dim, deformed, &
        deformed_len, rotation_source, rotations, rotations_len, origin, origin_len, start, out, &
        out_len, report_out) bind(C, name="dk_plan_step") result(s)
      import :: c_double, c_int32_t, c_int8_t, c_ptr, c_size_t, dk_plan_step_report
      real(c_double), intent(inout) :: reals(*)
      integer(c_size_t), value :: reals_len
      integer(c_int32_t), intent(inout) :: indices(*)
      integer(c_size_t), value :: indices_len
      integer(c_int8_t), intent(inout) :: bytes(*)
      integer(c_size_t), value :: bytes_len
      integer(c_int32_t), value :: dim
      real(c_double), intent(in) :: deformed(*)
      integer(c_size_t), value :: deformed_len
      integer(c_int32_t), value :: rotation_source
      type(c_ptr), value :: rotations
      integer(c_size_t), value :: rotations_len
      type(c_ptr), value :: origin
      integer(c_size_t), value :: origin_len
      integer(c_int32_t), value :: start
      real(c_double), intent(inout) :: out(*)
      integer(c_size_t), value :: out_len
      type(dk_plan_step_report), intent(inout) :: report_out
      integer(c_int32_t) :: s
    end function
    function dk_plan_step_f32(reals, reals_len, indices, indices_len, bytes, bytes_len, dim, &
        deformed, deformed_len, rotation_source, rotations, rotations_len, origin, origin_len, &
        start, out, out_len, report_out) bind(C, name="dk_plan_step_f32") result(s)
      import :: c_float, c_int32_t, c_int8_t, c_ptr, c_size_t, dk_plan_step_report
      real(c_float), intent(inout) :: reals(*)
      integer(c_size_t), value :: reals_len
      integer(c_int32_t), intent(inout) :: indices(*)
      integer(c_size_t), value :: indices_len
      integer(c_int8_t), intent(inout) :: bytes(*)
      integer(c_size_t), value :: bytes_len
      integer(c_int32_t), value :: dim
      real(c_float), intent(in) :: deformed(*)
      integer(c_size_t), value :: deformed_len
      integer(c_int32_t), value :: rotation_source
      type(c_ptr), value :: rotations
      integer(c_size_t), value :: rotations_len
      type(c_ptr), value :: origin
      integer(c_size_t), value :: origin_len
      integer(c_int32_t), value :: start
      real(c_float), intent(inout) :: out(*)
      integer(c_size_t), value :: out_len
      type(dk_plan_step_report), intent(inout) :: report_out
      integer(c_int32_t) :: s
    end function
    function dk_quality_cell_quality(kind, corners, corners_len, dim, out) bind(C, &
        name="dk_quality_cell_quality") result(s)
      import :: c_double, c_int32_t, c_int8_t, c_size_t, dk_cell_quality
      integer(c_int8_t), value :: kind
      real(c_double), intent(in) :: corners(*)
      integer(c_size_t), value :: corners_len
      integer(c_int32_t), value :: dim
      type(dk_cell_quality), intent(inout) :: out
      integer(c_int32_t) :: s
    end function
    function dk_quality_cell_quality_f32(kind, corners, corners_len, dim, out) bind(C, &
        name="dk_quality_cell_quality_f32") result(s)
      import :: c_float, c_int32_t, c_int8_t, c_size_t, dk_cell_quality
      integer(c_int8_t), value :: kind
      real(c_float), intent(in) :: corners(*)
      integer(c_size_t), value :: corners_len
      integer(c_int32_t), value :: dim
      type(dk_cell_quality), intent(inout) :: out
      integer(c_int32_t) :: s
    end function
    function dk_quality_cell_measures(cell_offsets, cell_offsets_len, cell_nodes, cell_nodes_len, &
        cell_kinds, cell_kinds_len, index_base, index_scratch, index_scratch_len, points, &
        points_len, dim, out, out_len) bind(C, name="dk_quality_cell_measures") result(s)
      import :: c_double, c_int32_t, c_int8_t, c_size_t
      integer(c_int32_t), intent(in) :: cell_offsets(*)
      integer(c_size_t), value :: cell_offsets_len
      integer(c_int32_t), intent(in) :: cell_nodes(*)
      integer(c_size_t), value :: cell_nodes_len
      integer(c_int8_t), intent(in) :: cell_kinds(*)
      integer(c_size_t), value :: cell_kinds_len
      integer(c_int32_t), value :: index_base
      integer(c_int32_t), intent(inout) :: index_scratch(*)
      integer(c_size_t), value :: index_scratch_len
      real(c_double), intent(in) :: points(*)
      integer(c_size_t), value :: points_len
      integer(c_int32_t), value :: dim
      real(c_double), intent(inout) :: out(*)
      integer(c_size_t), value :: out_len
      integer(c_int32_t) :: s
    end function
    function dk_quality_cell_measures_f32(cell_offsets, cell_offsets_len, cell_nodes, &
        cell_nodes_len, cell_kinds, cell_kinds_len, index_base, index_scratch, index_scratch_len, &
        points, points_len, dim, out, out_len) bind(C, name="dk_quality_cell_measures_f32") &
        result(s)
      import :: c_float, c_int32_t, c_int8_t, c_size_t
      integer(c_int32_t), intent(in) :: cell_offsets(*)
      integer(c_size_t), value :: cell_offsets_len
      integer(c_int32_t), intent(in) :: cell_nodes(*)
      integer(c_size_t), value :: cell_nodes_len
      integer(c_int8_t), intent(in) :: cell_kinds(*)
      integer(c_size_t), value :: cell_kinds_len
      integer(c_int32_t), value :: index_base
      integer(c_int32_t), intent(inout) :: index_scratch(*)
      integer(c_size_t), value :: index_scratch_len
      real(c_float), intent(in) :: points(*)
      integer(c_size_t), value :: points_len
      integer(c_int32_t), value :: dim
      real(c_float), intent(inout) :: out(*)
      integer(c_size_t), value :: out_len
      integer(c_int32_t) :: s
    end function
    function dk_quality_min_corner_jacobians(cell_offsets, cell_offsets_len, cell_nodes, &
        cell_nodes_len, cell_kinds, cell_kinds_len, index_base, index_scratch, index_scratch_len, &
        points, points_len, dim, scaled, out, out_len) bind(C, &
        name="dk_quality_min_corner_jacobians") result(s)
      import :: c_bool, c_double, c_int32_t, c_int8_t, c_size_t
      integer(c_int32_t), intent(in) :: cell_offsets(*)
      integer(c_size_t), value :: cell_offsets_len
      integer(c_int32_t), intent(in) :: cell_nodes(*)
      integer(c_size_t), value :: cell_nodes_len
      integer(c_int8_t), intent(in) :: cell_kinds(*)
      integer(c_size_t), value :: cell_kinds_len
      integer(c_int32_t), value :: index_base
      integer(c_int32_t), intent(inout) :: index_scratch(*)
      integer(c_size_t), value :: index_scratch_len
      real(c_double), intent(in) :: points(*)
      integer(c_size_t), value :: points_len
      integer(c_int32_t), value :: dim
      logical(c_bool), value :: scaled
      real(c_double), intent(inout) :: out(*)
      integer(c_size_t), value :: out_len
      integer(c_int32_t) :: s
    end function
    function dk_quality_min_corner_jacobians_f32(cell_offsets, cell_offsets_len, cell_nodes, &
        cell_nodes_len, cell_kinds, cell_kinds_len, index_base, index_scratch, index_scratch_len, &
        points, points_len, dim, scaled, out, out_len) bind(C, &
        name="dk_quality_min_corner_jacobians_f32") result(s)
      import :: c_bool, c_float, c_int32_t, c_int8_t, c_size_t
      integer(c_int32_t), intent(in) :: cell_offsets(*)
      integer(c_size_t), value :: cell_offsets_len
      integer(c_int32_t), intent(in) :: cell_nodes(*)
      integer(c_size_t), value :: cell_nodes_len
      integer(c_int8_t), intent(in) :: cell_kinds(*)
      integer(c_size_t), value :: cell_kinds_len
      integer(c_int32_t), value :: index_base
      integer(c_int32_t), intent(inout) :: index_scratch(*)
      integer(c_size_t), value :: index_scratch_len
      real(c_float), intent(in) :: points(*)
      integer(c_size_t), value :: points_len
      integer(c_int32_t), value :: dim
      logical(c_bool), value :: scaled
      real(c_float), intent(inout) :: out(*)
      integer(c_size_t), value :: out_len
      integer(c_int32_t) :: s
    end function
    function dk_quality_inverted_cells(cell_offsets, cell_offsets_len, cell_nodes, cell_nodes_len, &
        cell_kinds, cell_kinds_len, index_base, index_scratch, index_scratch_len, undeformed, &
        undeformed_len, deformed, deformed_len, dim, count_out) bind(C, &
        name="dk_quality_inverted_cells") result(s)
      import :: c_double, c_int32_t, c_int8_t, c_size_t
      integer(c_int32_t), intent(in) :: cell_offsets(*)
      integer(c_size_t), value :: cell_offsets_len
      integer(c_int32_t), intent(in) :: cell_nodes(*)
      integer(c_size_t), value :: cell_nodes_len
      integer(c_int8_t), intent(in) :: cell_kinds(*)
      integer(c_size_t), value :: cell_kinds_len
      integer(c_int32_t), value :: index_base
      integer(c_int32_t), intent(inout) :: index_scratch(*)
      integer(c_size_t), value :: index_scratch_len
      real(c_double), intent(in) :: undeformed(*)
      integer(c_size_t), value :: undeformed_len
      real(c_double), intent(in) :: deformed(*)
      integer(c_size_t), value :: deformed_len
      integer(c_int32_t), value :: dim
      integer(c_size_t), intent(inout) :: count_out
      integer(c_int32_t) :: s
    end function
    function dk_quality_inverted_cells_f32(cell_offsets, cell_offsets_len, cell_nodes, &
        cell_nodes_len, cell_kinds, cell_kinds_len, index_base, index_scratch, index_scratch_len, &
        undeformed, undeformed_len, deformed, deformed_len, dim, count_out) bind(C, &
        name="dk_quality_inverted_cells_f32") result(s)
      import :: c_float, c_int32_t, c_int8_t, c_size_t
      integer(c_int32_t), intent(in) :: cell_offsets(*)
      integer(c_size_t), value :: cell_offsets_len
      integer(c_int32_t), intent(in) :: cell_nodes(*)
      integer(c_size_t), value :: cell_nodes_len
      integer(c_int8_t), intent(in) :: cell_kinds(*)
      integer(c_size_t), value :: cell_kinds_len
      integer(c_int32_t), value :: index_base
      integer(c_int32_t), intent(inout) :: index_scratch(*)
      integer(c_size_t), value :: index_scratch_len
      real(c_float), intent(in) :: undeformed(*)
      integer(c_size_t), value :: undeformed_len
      real(c_float), intent(in) :: deformed(*)
      integer(c_size_t), value :: deformed_len
      integer(c_int32_t), value :: dim
      integer(c_size_t), intent(inout) :: count_out
      integer(c_int32_t) :: s
    end function
    function dk_quality_folded_cells(cell_offsets, cell_offsets_len, cell_nodes, cell_nodes_len, &
        cell_kinds, cell_kinds_len, index_base, index_scratch, index_scratch_len, points, &
        points_len, dim, count_out) bind(C, name="dk_quality_folded_cells") result(s)
      import :: c_double, c_int32_t, c_int8_t, c_size_t
      integer(c_int32_t), intent(in) :: cell_offsets(*)
      integer(c_size_t), value :: cell_offsets_len
      integer(c_int32_t), intent(in) :: cell_nodes(*)
      integer(c_size_t), value :: cell_nodes_len
      integer(c_int8_t), intent(in) :: cell_kinds(*)
      integer(c_size_t), value :: cell_kinds_len
      integer(c_int32_t), value :: index_base
      integer(c_int32_t), intent(inout) :: index_scratch(*)
      integer(c_size_t), value :: index_scratch_len
      real(c_double), intent(in) :: points(*)
      integer(c_size_t), value :: points_len
      integer(c_int32_t), value :: dim
      integer(c_size_t), intent(inout) :: count_out
      integer(c_int32_t) :: s
    end function
    function dk_quality_folded_cells_f32(cell_offsets, cell_offsets_len, cell_nodes, &
        cell_nodes_len, cell_kinds, cell_kinds_len, index_base, index_scratch, index_scratch_len, &
        points, points_len, dim, count_out) bind(C, name="dk_quality_folded_cells_f32") result(s)
      import :: c_float, c_int32_t, c_int8_t, c_size_t
      integer(c_int32_t), intent(in) :: cell_offsets(*)
      integer(c_size_t), value :: cell_offsets_len
      integer(c_int32_t), intent(in) :: cell_nodes(*)
      integer(c_size_t), value :: cell_nodes_len
      integer(c_int8_t), intent(in) :: cell_kinds(*)
      integer(c_size_t), value :: cell_kinds_len
      integer(c_int32_t), value :: index_base
      integer(c_int32_t), intent(inout) :: index_scratch(*)
      integer(c_size_t), value :: index_scratch_len
      real(c_float), intent(in) :: points(*)
      integer(c_size_t), value :: points_len
      integer(c_int32_t), value :: dim
      integer(c_size_t), intent(inout) :: count_out
      integer(c_int32_t) :: s
    end function
    function dk_quality_wall_angle_scratch_len(node_count, dim, len_out) bind(C, &
        name="dk_quality_wall_angle_scratch_len") result(s)
      import :: c_int32_t, c_size_t
      integer(c_size_t), value :: node_count
      integer(c_int32_t), value :: dim
      integer(c_size_t), intent(inout) :: len_out
      integer(c_int32_t) :: s
    end function
    function dk_quality_compare(cell_offsets, cell_offsets_len, cell_nodes, cell_nodes_len, &
        cell_kinds, cell_kinds_len, index_base, index_scratch, index_scratch_len, wall_offsets, &
        wall_offsets_len, wall_nodes, wall_nodes_len, wall_kinds, wall_kinds_len, graph_offsets, &
        graph_offsets_len, graph_targets, graph_targets_len, undeformed, undeformed_len, deformed, &
        deformed_len, dim, scratch, scratch_len, report) bind(C, name="dk_quality_compare") &
        result(s)
      import :: c_double, c_int32_t, c_int8_t, c_ptr, c_size_t, dk_quality_report
      integer(c_int32_t), intent(in) :: cell_offsets(*)
      integer(c_size_t), value :: cell_offsets_len
      integer(c_int32_t), intent(in) :: cell_nodes(*)
      integer(c_size_t), value :: cell_nodes_len
      integer(c_int8_t), intent(in) :: cell_kinds(*)
      integer(c_size_t), value :: cell_kinds_len
      integer(c_int32_t), value :: index_base
      integer(c_int32_t), intent(inout) :: index_scratch(*)
      integer(c_size_t), value :: index_scratch_len
      type(c_ptr), value :: wall_offsets
      integer(c_size_t), value :: wall_offsets_len
      type(c_ptr), value :: wall_nodes
      integer(c_size_t), value :: wall_nodes_len
      type(c_ptr), value :: wall_kinds
      integer(c_size_t), value :: wall_kinds_len
      type(c_ptr), value :: graph_offsets
      integer(c_size_t), value :: graph_offsets_len
      type(c_ptr), value :: graph_targets
      integer(c_size_t), value :: graph_targets_len
      real(c_double), intent(in) :: undeformed(*)
      integer(c_size_t), value :: undeformed_len
      real(c_double), intent(in) :: deformed(*)
      integer(c_size_t), value :: deformed_len
      integer(c_int32_t), value :: dim
      real(c_double), intent(inout) :: scratch(*)
      integer(c_size_t), value :: scratch_len
      type(dk_quality_report), intent(inout) :: report
      integer(c_int32_t) :: s
    end function
    function dk_quality_compare_f32(cell_offsets, cell_offsets_len, cell_nodes, cell_nodes_len, &
        cell_kinds, cell_kinds_len, index_base, index_scratch, index_scratch_len, wall_offsets, &
        wall_offsets_len, wall_nodes, wall_nodes_len, wall_kinds, wall_kinds_len, graph_offsets, &
        graph_offsets_len, graph_targets, graph_targets_len, undeformed, undeformed_len, deformed, &
        deformed_len, dim, scratch, scratch_len, report) bind(C, name="dk_quality_compare_f32") &
        result(s)
      import :: c_float, c_int32_t, c_int8_t, c_ptr, c_size_t, dk_quality_report
      integer(c_int32_t), intent(in) :: cell_offsets(*)
      integer(c_size_t), value :: cell_offsets_len
      integer(c_int32_t), intent(in) :: cell_nodes(*)
      integer(c_size_t), value :: cell_nodes_len
      integer(c_int8_t), intent(in) :: cell_kinds(*)
      integer(c_size_t), value :: cell_kinds_len
      integer(c_int32_t), value :: index_base
      integer(c_int32_t), intent(inout) :: index_scratch(*)
      integer(c_size_t), value :: index_scratch_len
      type(c_ptr), value :: wall_offsets
      integer(c_size_t), value :: wall_offsets_len
      type(c_ptr), value :: wall_nodes
      integer(c_size_t), value :: wall_nodes_len
      type(c_ptr), value :: wall_kinds
      integer(c_size_t), value :: wall_kinds_len
      type(c_ptr), value :: graph_offsets
      integer(c_size_t), value :: graph_offsets_len
      type(c_ptr), value :: graph_targets
      integer(c_size_t), value :: graph_targets_len
      real(c_float), intent(in) :: undeformed(*)
      integer(c_size_t), value :: undeformed_len
      real(c_float), intent(in) :: deformed(*)
      integer(c_size_t), value :: deformed_len
      integer(c_int32_t), value :: dim
      real(c_float), intent(inout) :: scratch(*)
      integer(c_size_t), value :: scratch_len
      type(dk_quality_report), intent(inout) :: report
      integer(c_int32_t) :: s
    end function
    function dk_quality_wall_angle_change(wall_offsets, wall_offsets_len, wall_nodes, &
        wall_nodes_len, wall_kinds, wall_kinds_len, index_base, index_scratch, index_scratch_len, &
        graph_offsets, graph_offsets_len, graph_targets, graph_targets_len, undeformed, &
        undeformed_len, deformed, deformed_len, dim, scratch, scratch_len, out) bind(C, &
        name="dk_quality_wall_angle_change") result(s)
      import :: c_double, c_int32_t, c_int8_t, c_size_t, dk_wall_angle_change
      integer(c_int32_t), intent(in) :: wall_offsets(*)
      integer(c_size_t), value :: wall_offsets_len
      integer(c_int32_t), intent(in) :: wall_nodes(*)
      integer(c_size_t), value :: wall_nodes_len
      integer(c_int8_t), intent(in) :: wall_kinds(*)
      integer(c_size_t), value :: wall_kinds_len
      integer(c_int32_t), value :: index_base
      integer(c_int32_t), intent(inout) :: index_scratch(*)
      integer(c_size_t), value :: index_scratch_len
      integer(c_int32_t), intent(in) :: graph_offsets(*)
      integer(c_size_t), value :: graph_offsets_len
      integer(c_int32_t), intent(in) :: graph_targets(*)
      integer(c_size_t), value :: graph_targets_len
      real(c_double), intent(in) :: undeformed(*)
      integer(c_size_t), value :: undeformed_len
      real(c_double), intent(in) :: deformed(*)
      integer(c_size_t), value :: deformed_len
      integer(c_int32_t), value :: dim
      real(c_double), intent(inout) :: scratch(*)
      integer(c_size_t), value :: scratch_len
      type(dk_wall_angle_change), intent(inout) :: out
      integer(c_int32_t) :: s
    end function
    function dk_quality_wall_angle_change_f32(wall_offsets, wall_offsets_len, wall_nodes, &
        wall_nodes_len, wall_kinds, wall_kinds_len, index_base, index_scratch, index_scratch_len, &
        graph_offsets, graph_offsets_len, graph_targets, graph_targets_len, undeformed, &
        undeformed_len, deformed, deformed_len, dim, scratch, scratch_len, out) bind(C, &
        name="dk_quality_wall_angle_change_f32") result(s)
      import :: c_float, c_int32_t, c_int8_t, c_size_t, dk_wall_angle_change
      integer(c_int32_t), intent(in) :: wall_offsets(*)
      integer(c_size_t), value :: wall_offsets_len
      integer(c_int32_t), intent(in) :: wall_nodes(*)
      integer(c_size_t), value :: wall_nodes_len
      integer(c_int8_t), intent(in) :: wall_kinds(*)
      integer(c_size_t), value :: wall_kinds_len
      integer(c_int32_t), value :: index_base
      integer(c_int32_t), intent(inout) :: index_scratch(*)
      integer(c_size_t), value :: index_scratch_len
      integer(c_int32_t), intent(in) :: graph_offsets(*)
      integer(c_size_t), value :: graph_offsets_len
      integer(c_int32_t), intent(in) :: graph_targets(*)
      integer(c_size_t), value :: graph_targets_len
      real(c_float), intent(in) :: undeformed(*)
      integer(c_size_t), value :: undeformed_len
      real(c_float), intent(in) :: deformed(*)
      integer(c_size_t), value :: deformed_len
      integer(c_int32_t), value :: dim
      real(c_float), intent(inout) :: scratch(*)
      integer(c_size_t), value :: scratch_len
      type(dk_wall_angle_change), intent(inout) :: out
      integer(c_int32_t) :: s
    end function
    function dk_quat_mul(a, b, out) bind(C, name="dk_quat_mul") result(s)
      import :: c_double, c_int32_t
      real(c_double), intent(in) :: a(4)
      real(c_double), intent(in) :: b(4)
      real(c_double), intent(inout) :: out(4)
      integer(c_int32_t) :: s
    end function
    function dk_quat_mul_f32(a, b, out) bind(C, name="dk_quat_mul_f32") result(s)
      import :: c_float, c_int32_t
      real(c_float), intent(in) :: a(4)
      real(c_float), intent(in) :: b(4)
      real(c_float), intent(inout) :: out(4)
      integer(c_int32_t) :: s
    end function
    function dk_quat_normalize(q, out) bind(C, name="dk_quat_normalize") result(s)
      import :: c_double, c_int32_t
      real(c_double), intent(in) :: q(4)
      real(c_double), intent(inout) :: out(4)
      integer(c_int32_t) :: s
    end function
    function dk_quat_normalize_f32(q, out) bind(C, name="dk_quat_normalize_f32") result(s)
      import :: c_float, c_int32_t
      real(c_float), intent(in) :: q(4)
      real(c_float), intent(inout) :: out(4)
      integer(c_int32_t) :: s
    end function
    function dk_quat_inverse(q, out) bind(C, name="dk_quat_inverse") result(s)
      import :: c_double, c_int32_t
      real(c_double), intent(in) :: q(4)
      real(c_double), intent(inout) :: out(4)
      integer(c_int32_t) :: s
    end function
    function dk_quat_inverse_f32(q, out) bind(C, name="dk_quat_inverse_f32") result(s)
      import :: c_float, c_int32_t
      real(c_float), intent(in) :: q(4)
      real(c_float), intent(inout) :: out(4)
      integer(c_int32_t) :: s
    end function
    function dk_quat_from_axis_angle(axis, angle, out) bind(C, name="dk_quat_from_axis_angle") &
        result(s)
      import :: c_double, c_int32_t
      real(c_double), intent(in) :: axis(3)
      real(c_double), value :: angle
      real(c_double), intent(inout) :: out(4)
      integer(c_int32_t) :: s
    end function
    function dk_quat_from_axis_angle_f32(axis, angle, out) bind(C, &
        name="dk_quat_from_axis_angle_f32") result(s)
      import :: c_float, c_int32_t
      real(c_float), intent(in) :: axis(3)
      real(c_float), value :: angle
      real(c_float), intent(inout) :: out(4)
      integer(c_int32_t) :: s
    end function
    function dk_quat_to_axis_angle(q, axis_out, angle_out) bind(C, name="dk_quat_to_axis_angle") &
        result(s)
      import :: c_double, c_int32_t
      real(c_double), intent(in) :: q(4)
      real(c_double), intent(inout) :: axis_out(3)
      real(c_double), intent(inout) :: angle_out
      integer(c_int32_t) :: s
    end function
    function dk_quat_to_axis_angle_f32(q, axis_out, angle_out) bind(C, &
        name="dk_quat_to_axis_angle_f32") result(s)
      import :: c_float, c_int32_t
      real(c_float), intent(in) :: q(4)
      real(c_float), intent(inout) :: axis_out(3)
      real(c_float), intent(inout) :: angle_out
      integer(c_int32_t) :: s
    end function
    function dk_quat_rotation_arc(from, to, out) bind(C, name="dk_quat_rotation_arc") result(s)
      import :: c_double, c_int32_t
      real(c_double), intent(in) :: from(3)
      real(c_double), intent(in) :: to(3)
      real(c_double), intent(inout) :: out(4)
      integer(c_int32_t) :: s
    end function
    function dk_quat_rotation_arc_f32(from, to, out) bind(C, name="dk_quat_rotation_arc_f32") &
        result(s)
      import :: c_float, c_int32_t
      real(c_float), intent(in) :: from(3)
      real(c_float), intent(in) :: to(3)
      real(c_float), intent(inout) :: out(4)
      integer(c_int32_t) :: s
    end function
    function dk_quat_rotate_points(q, points, points_len, out, out_len) bind(C, &
        name="dk_quat_rotate_points") result(s)
      import :: c_double, c_int32_t, c_size_t
      real(c_double), intent(in) :: q(4)
      real(c_double), intent(in) :: points(*)
      integer(c_size_t), value :: points_len
      real(c_double), intent(inout) :: out(*)
      integer(c_size_t), value :: out_len
      integer(c_int32_t) :: s
    end function
    function dk_quat_rotate_points_f32(q, points, points_len, out, out_len) bind(C, &
        name="dk_quat_rotate_points_f32") result(s)
      import :: c_float, c_int32_t, c_size_t
      real(c_float), intent(in) :: q(4)
      real(c_float), intent(in) :: points(*)
      integer(c_size_t), value :: points_len
      real(c_float), intent(inout) :: out(*)
      integer(c_size_t), value :: out_len
      integer(c_int32_t) :: s
    end function
    function dk_quat_slerp(a, b, t, out) bind(C, name="dk_quat_slerp") result(s)
      import :: c_double, c_int32_t
      real(c_double), intent(in) :: a(4)
      real(c_double), intent(in) :: b(4)
      real(c_double), value :: t
      real(c_double), intent(inout) :: out(4)
      integer(c_int32_t) :: s
    end function
    function dk_quat_slerp_f32(a, b, t, out) bind(C, name="dk_quat_slerp_f32") result(s)
      import :: c_float, c_int32_t
      real(c_float), intent(in) :: a(4)
      real(c_float), intent(in) :: b(4)
      real(c_float), value :: t
      real(c_float), intent(inout) :: out(4)
      integer(c_int32_t) :: s
    end function
    function dk_quat_nlerp(a, b, t, out) bind(C, name="dk_quat_nlerp") result(s)
      import :: c_double, c_int32_t
      real(c_double), intent(in) :: a(4)
      real(c_double), intent(in) :: b(4)
      real(c_double), value :: t
      real(c_double), intent(inout) :: out(4)
      integer(c_int32_t) :: s
    end function
    function dk_quat_nlerp_f32(a, b, t, out) bind(C, name="dk_quat_nlerp_f32") result(s)
      import :: c_float, c_int32_t
      real(c_float), intent(in) :: a(4)
      real(c_float), intent(in) :: b(4)
      real(c_float), value :: t
      real(c_float), intent(inout) :: out(4)
      integer(c_int32_t) :: s
    end function
    function dk_quat_average(quats, quats_len, weights, weights_len, out) bind(C, &
        name="dk_quat_average") result(s)
      import :: c_double, c_int32_t, c_size_t
      real(c_double), intent(in) :: quats(*)
      integer(c_size_t), value :: quats_len
      real(c_double), intent(in) :: weights(*)
      integer(c_size_t), value :: weights_len
      real(c_double), intent(inout) :: out(4)
      integer(c_int32_t) :: s
    end function
    function dk_quat_average_f32(quats, quats_len, weights, weights_len, out) bind(C, &
        name="dk_quat_average_f32") result(s)
      import :: c_float, c_int32_t, c_size_t
      real(c_float), intent(in) :: quats(*)
      integer(c_size_t), value :: quats_len
      real(c_float), intent(in) :: weights(*)
      integer(c_size_t), value :: weights_len
      real(c_float), intent(inout) :: out(4)
      integer(c_int32_t) :: s
    end function
    function dk_spring_batina_stiffness(offsets, offsets_len, targets, targets_len, points, &
        points_len, dim, exponent, stiffness, stiffness_len) bind(C, &
        name="dk_spring_batina_stiffness") result(s)
      import :: c_double, c_int32_t, c_size_t
      integer(c_int32_t), intent(in) :: offsets(*)
      integer(c_size_t), value :: offsets_len
      integer(c_int32_t), intent(in) :: targets(*)
      integer(c_size_t), value :: targets_len
      real(c_double), intent(in) :: points(*)
      integer(c_size_t), value :: points_len
      integer(c_int32_t), value :: dim
      real(c_double), value :: exponent
      real(c_double), intent(inout) :: stiffness(*)
      integer(c_size_t), value :: stiffness_len
      integer(c_int32_t) :: s
    end function
    function dk_spring_batina_stiffness_f32(offsets, offsets_len, targets, targets_len, points, &
        points_len, dim, exponent, stiffness, stiffness_len) bind(C, &
        name="dk_spring_batina_stiffness_f32") result(s)
      import :: c_float, c_int32_t, c_size_t
      integer(c_int32_t), intent(in) :: offsets(*)
      integer(c_size_t), value :: offsets_len
      integer(c_int32_t), intent(in) :: targets(*)
      integer(c_size_t), value :: targets_len
      real(c_float), intent(in) :: points(*)
      integer(c_size_t), value :: points_len
      integer(c_int32_t), value :: dim
      real(c_float), value :: exponent
      real(c_float), intent(inout) :: stiffness(*)
      integer(c_size_t), value :: stiffness_len
      integer(c_int32_t) :: s
    end function
    function dk_spring_index_scratch_len(node_count, len_out) bind(C, &
        name="dk_spring_index_scratch_len") result(s)
      import :: c_int32_t, c_size_t
      integer(c_size_t), value :: node_count
      integer(c_size_t), intent(inout) :: len_out
      integer(c_int32_t) :: s
    end function
    function dk_spring_solve_options_default(out) bind(C, name="dk_spring_solve_options_default") &
        result(s)
      import :: c_int32_t, dk_spring_solve_options
      type(dk_spring_solve_options), intent(inout) :: out
      integer(c_int32_t) :: s
    end function
    function dk_spring_solve_options_default_f32(out) bind(C, &
        name="dk_spring_solve_options_default_f32") result(s)
      import :: c_int32_t, dk_spring_solve_options
      type(dk_spring_solve_options), intent(inout) :: out
      integer(c_int32_t) :: s
    end function
    function dk_spring_solve_linear_scratch_len(node_count, components, options, len_out) bind(C, &
        name="dk_spring_solve_linear_scratch_len") result(s)
      import :: c_int32_t, c_size_t, dk_spring_solve_options
      integer(c_size_t), value :: node_count
      integer(c_int32_t), value :: components
      type(dk_spring_solve_options), intent(in) :: options
      integer(c_size_t), intent(inout) :: len_out
      integer(c_int32_t) :: s
    end function
    function dk_spring_solve_linear(offsets, offsets_len, targets, targets_len, stiffness, &
        stiffness_len, fixed, fixed_len, options, components, values, values_len, scratch, &
        scratch_len, index_scratch, index_scratch_len, report) bind(C, &
        name="dk_spring_solve_linear") result(s)
      import :: c_double, c_int32_t, c_int8_t, c_size_t, dk_spring_solve_options, &
          dk_spring_solve_report
      integer(c_int32_t), intent(in) :: offsets(*)
      integer(c_size_t), value :: offsets_len
      integer(c_int32_t), intent(in) :: targets(*)
      integer(c_size_t), value :: targets_len
      real(c_double), intent(in) :: stiffness(*)
      integer(c_size_t), value :: stiffness_len
      integer(c_int8_t), intent(in) :: fixed(*)
      integer(c_size_t), value :: fixed_len
      type(dk_spring_solve_options), intent(in) :: options
      integer(c_int32_t), value :: components
      real(c_double), intent(inout) :: values(*)
      integer(c_size_t), value :: values_len
      real(c_double), intent(inout) :: scratch(*)
      integer(c_size_t), value :: scratch_len
      integer(c_int32_t), intent(inout) :: index_scratch(*)
      integer(c_size_t), value :: index_scratch_len
      type(dk_spring_solve_report), intent(inout) :: report
      integer(c_int32_t) :: s
    end function
    function dk_spring_solve_linear_f32(offsets, offsets_len, targets, targets_len, stiffness, &
        stiffness_len, fixed, fixed_len, options, components, values, values_len, scratch, &
        scratch_len, index_scratch, index_scratch_len, report) bind(C, &
        name="dk_spring_solve_linear_f32") result(s)
      import :: c_float, c_int32_t, c_int8_t, c_size_t, dk_spring_solve_options, &
          dk_spring_solve_report
      integer(c_int32_t), intent(in) :: offsets(*)
      integer(c_size_t), value :: offsets_len
      integer(c_int32_t), intent(in) :: targets(*)
      integer(c_size_t), value :: targets_len
      real(c_float), intent(in) :: stiffness(*)
      integer(c_size_t), value :: stiffness_len
      integer(c_int8_t), intent(in) :: fixed(*)
      integer(c_size_t), value :: fixed_len
      type(dk_spring_solve_options), intent(in) :: options
      integer(c_int32_t), value :: components
      real(c_float), intent(inout) :: values(*)
      integer(c_size_t), value :: values_len
      real(c_float), intent(inout) :: scratch(*)
      integer(c_size_t), value :: scratch_len
      integer(c_int32_t), intent(inout) :: index_scratch(*)
      integer(c_size_t), value :: index_scratch_len
      type(dk_spring_solve_report), intent(inout) :: report
      integer(c_int32_t) :: s
    end function
    function dk_spring_jacobi_sweep(offsets, offsets_len, targets, targets_len, stiffness, &
        stiffness_len, fixed, fixed_len, nodes_start, nodes_end, index_base, components, src, &
        src_len, dst, dst_len, index_scratch, index_scratch_len, sweep) bind(C, &
        name="dk_spring_jacobi_sweep") result(s)
      import :: c_double, c_int32_t, c_int8_t, c_size_t, dk_spring_sweep
      integer(c_int32_t), intent(in) :: offsets(*)
      integer(c_size_t), value :: offsets_len
      integer(c_int32_t), intent(in) :: targets(*)
      integer(c_size_t), value :: targets_len
      real(c_double), intent(in) :: stiffness(*)
      integer(c_size_t), value :: stiffness_len
      integer(c_int8_t), intent(in) :: fixed(*)
      integer(c_size_t), value :: fixed_len
      integer(c_size_t), value :: nodes_start
      integer(c_size_t), value :: nodes_end
      integer(c_int32_t), value :: index_base
      integer(c_int32_t), value :: components
      real(c_double), intent(in) :: src(*)
      integer(c_size_t), value :: src_len
      real(c_double), intent(inout) :: dst(*)
      integer(c_size_t), value :: dst_len
      integer(c_int32_t), intent(inout) :: index_scratch(*)
      integer(c_size_t), value :: index_scratch_len
      type(dk_spring_sweep), intent(inout) :: sweep
      integer(c_int32_t) :: s
    end function
    function dk_spring_jacobi_sweep_f32(offsets, offsets_len, targets, targets_len, stiffness, &
        stiffness_len, fixed, fixed_len, nodes_start, nodes_end, index_base, components, src, &
        src_len, dst, dst_len, index_scratch, index_scratch_len, sweep) bind(C, &
        name="dk_spring_jacobi_sweep_f32") result(s)
      import :: c_float, c_int32_t, c_int8_t, c_size_t, dk_spring_sweep
      integer(c_int32_t), intent(in) :: offsets(*)
      integer(c_size_t), value :: offsets_len
      integer(c_int32_t), intent(in) :: targets(*)
      integer(c_size_t), value :: targets_len
      real(c_float), intent(in) :: stiffness(*)
      integer(c_size_t), value :: stiffness_len
      integer(c_int8_t), intent(in) :: fixed(*)
      integer(c_size_t), value :: fixed_len
      integer(c_size_t), value :: nodes_start
      integer(c_size_t), value :: nodes_end
      integer(c_int32_t), value :: index_base
      integer(c_int32_t), value :: components
      real(c_float), intent(in) :: src(*)
      integer(c_size_t), value :: src_len
      real(c_float), intent(inout) :: dst(*)
      integer(c_size_t), value :: dst_len
      integer(c_int32_t), intent(inout) :: index_scratch(*)
      integer(c_size_t), value :: index_scratch_len
      type(dk_spring_sweep), intent(inout) :: sweep
      integer(c_int32_t) :: s
    end function
    function dk_spring_jacobi_sweep_exact(offsets, offsets_len, targets, targets_len, stiffness, &
        stiffness_len, fixed, fixed_len, nodes_start, nodes_end, index_base, components, src, &
        src_len, dst, dst_len, index_scratch, index_scratch_len, sweep, residual_words) bind(C, &
        name="dk_spring_jacobi_sweep_exact") result(s)
      import :: c_double, c_int32_t, c_int64_t, c_int8_t, c_size_t, dk_spring_sweep
      integer(c_int32_t), intent(in) :: offsets(*)
      integer(c_size_t), value :: offsets_len
      integer(c_int32_t), intent(in) :: targets(*)
      integer(c_size_t), value :: targets_len
      real(c_double), intent(in) :: stiffness(*)
      integer(c_size_t), value :: stiffness_len
      integer(c_int8_t), intent(in) :: fixed(*)
      integer(c_size_t), value :: fixed_len
      integer(c_size_t), value :: nodes_start
      integer(c_size_t), value :: nodes_end
      integer(c_int32_t), value :: index_base
      integer(c_int32_t), value :: components
      real(c_double), intent(in) :: src(*)
      integer(c_size_t), value :: src_len
      real(c_double), intent(inout) :: dst(*)
      integer(c_size_t), value :: dst_len
      integer(c_int32_t), intent(inout) :: index_scratch(*)
      integer(c_size_t), value :: index_scratch_len
      type(dk_spring_sweep), intent(inout) :: sweep
      integer(c_int64_t), intent(inout) :: residual_words(72)
      integer(c_int32_t) :: s
    end function
    function dk_spring_jacobi_sweep_exact_f32(offsets, offsets_len, targets, targets_len, &
        stiffness, stiffness_len, fixed, fixed_len, nodes_start, nodes_end, index_base, &
        components, src, src_len, dst, dst_len, index_scratch, index_scratch_len, sweep, &
        residual_words) bind(C, name="dk_spring_jacobi_sweep_exact_f32") result(s)
      import :: c_float, c_int32_t, c_int64_t, c_int8_t, c_size_t, dk_spring_sweep
      integer(c_int32_t), intent(in) :: offsets(*)
      integer(c_size_t), value :: offsets_len
      integer(c_int32_t), intent(in) :: targets(*)
      integer(c_size_t), value :: targets_len
      real(c_float), intent(in) :: stiffness(*)
      integer(c_size_t), value :: stiffness_len
      integer(c_int8_t), intent(in) :: fixed(*)
      integer(c_size_t), value :: fixed_len
      integer(c_size_t), value :: nodes_start
      integer(c_size_t), value :: nodes_end
      integer(c_int32_t), value :: index_base
      integer(c_int32_t), value :: components
      real(c_float), intent(in) :: src(*)
      integer(c_size_t), value :: src_len
      real(c_float), intent(inout) :: dst(*)
      integer(c_size_t), value :: dst_len
      integer(c_int32_t), intent(inout) :: index_scratch(*)
      integer(c_size_t), value :: index_scratch_len
      type(dk_spring_sweep), intent(inout) :: sweep
      integer(c_int64_t), intent(inout) :: residual_words(72)
      integer(c_int32_t) :: s
    end function
    function dk_exact_sum_value(words, value_out) bind(C, name="dk_exact_sum_value") result(s)
      import :: c_double, c_int32_t, c_int64_t
      integer(c_int64_t), intent(in) :: words(72)
      real(c_double), intent(inout) :: value_out
      integer(c_int32_t) :: s
    end function
    function dk_spring_sor_sweep(offsets, offsets_len, targets, targets_len, stiffness, &
        stiffness_len, fixed, fixed_len, nodes_start, nodes_end, index_base, omega, components, &
        values, values_len, index_scratch, index_scratch_len, sweep) bind(C, &
        name="dk_spring_sor_sweep") result(s)
      import :: c_double, c_int32_t, c_int8_t, c_size_t, dk_spring_sweep
      integer(c_int32_t), intent(in) :: offsets(*)
      integer(c_size_t), value :: offsets_len
      integer(c_int32_t), intent(in) :: targets(*)
      integer(c_size_t), value :: targets_len
      real(c_double), intent(in) :: stiffness(*)
      integer(c_size_t), value :: stiffness_len
      integer(c_int8_t), intent(in) :: fixed(*)
      integer(c_size_t), value :: fixed_len
      integer(c_size_t), value :: nodes_start
      integer(c_size_t), value :: nodes_end
      integer(c_int32_t), value :: index_base
      real(c_double), value :: omega
      integer(c_int32_t), value :: components
      real(c_double), intent(inout) :: values(*)
      integer(c_size_t), value :: values_len
      integer(c_int32_t), intent(inout) :: index_scratch(*)
      integer(c_size_t), value :: index_scratch_len
      type(dk_spring_sweep), intent(inout) :: sweep
      integer(c_int32_t) :: s
    end function
    function dk_spring_sor_sweep_f32(offsets, offsets_len, targets, targets_len, stiffness, &
        stiffness_len, fixed, fixed_len, nodes_start, nodes_end, index_base, omega, components, &
        values, values_len, index_scratch, index_scratch_len, sweep) bind(C, &
        name="dk_spring_sor_sweep_f32") result(s)
      import :: c_float, c_int32_t, c_int8_t, c_size_t, dk_spring_sweep
      integer(c_int32_t), intent(in) :: offsets(*)
      integer(c_size_t), value :: offsets_len
      integer(c_int32_t), intent(in) :: targets(*)
      integer(c_size_t), value :: targets_len
      real(c_float), intent(in) :: stiffness(*)
      integer(c_size_t), value :: stiffness_len
      integer(c_int8_t), intent(in) :: fixed(*)
      integer(c_size_t), value :: fixed_len
      integer(c_size_t), value :: nodes_start
      integer(c_size_t), value :: nodes_end
      integer(c_int32_t), value :: index_base
      real(c_float), value :: omega
      integer(c_int32_t), value :: components
      real(c_float), intent(inout) :: values(*)
      integer(c_size_t), value :: values_len
      integer(c_int32_t), intent(inout) :: index_scratch(*)
      integer(c_size_t), value :: index_scratch_len
      type(dk_spring_sweep), intent(inout) :: sweep
      integer(c_int32_t) :: s
    end function
    function dk_spring_relative_residual(offsets, offsets_len, targets, targets_len, stiffness, &
        stiffness_len, fixed, fixed_len, components, values, values_len, index_scratch, &
        index_scratch_len, residual_out) bind(C, name="dk_spring_relative_residual") result(s)
      import :: c_double, c_int32_t, c_int8_t, c_size_t
      integer(c_int32_t), intent(in) :: offsets(*)
      integer(c_size_t), value :: offsets_len
      integer(c_int32_t), intent(in) :: targets(*)
      integer(c_size_t), value :: targets_len
      real(c_double), intent(in) :: stiffness(*)
      integer(c_size_t), value :: stiffness_len
      integer(c_int8_t), intent(in) :: fixed(*)
      integer(c_size_t), value :: fixed_len
      integer(c_int32_t), value :: components
      real(c_double), intent(in) :: values(*)
      integer(c_size_t), value :: values_len
      integer(c_int32_t), intent(inout) :: index_scratch(*)
      integer(c_size_t), value :: index_scratch_len
      real(c_double), intent(inout) :: residual_out
      integer(c_int32_t) :: s
    end function
    function dk_spring_relative_residual_f32(offsets, offsets_len, targets, targets_len, &
        stiffness, stiffness_len, fixed, fixed_len, components, values, values_len, index_scratch, &
        index_scratch_len, residual_out) bind(C, name="dk_spring_relative_residual_f32") result(s)
      import :: c_float, c_int32_t, c_int8_t, c_size_t
      integer(c_int32_t), intent(in) :: offsets(*)
      integer(c_size_t), value :: offsets_len
      integer(c_int32_t), intent(in) :: targets(*)
      integer(c_size_t), value :: targets_len
      real(c_float), intent(in) :: stiffness(*)
      integer(c_size_t), value :: stiffness_len
      integer(c_int8_t), intent(in) :: fixed(*)
      integer(c_size_t), value :: fixed_len
      integer(c_int32_t), value :: components
      real(c_float), intent(in) :: values(*)
      integer(c_size_t), value :: values_len
      integer(c_int32_t), intent(inout) :: index_scratch(*)
      integer(c_size_t), value :: index_scratch_len
      real(c_float), intent(inout) :: residual_out
      integer(c_int32_t) :: s
    end function
    function dk_spring_angle_options_default(out) bind(C, name="dk_spring_angle_options_default") &
        result(s)
      import :: c_int32_t, dk_spring_angle_options
      type(dk_spring_angle_options), intent(inout) :: out
      integer(c_int32_t) :: s
    end function
    function dk_spring_angle_options_default_f32(out) bind(C, &
        name="dk_spring_angle_options_default_f32") result(s)
      import :: c_int32_t, dk_spring_angle_options
      type(dk_spring_angle_options), intent(inout) :: out
      integer(c_int32_t) :: s
    end function
    function dk_spring_solve_angle_scratch_len(node_count, dim, options, len_out) bind(C, &
        name="dk_spring_solve_angle_scratch_len") result(s)
      import :: c_int32_t, c_size_t, dk_spring_angle_options
      integer(c_size_t), value :: node_count
      integer(c_int32_t), value :: dim
      type(dk_spring_angle_options), intent(in) :: options
      integer(c_size_t), intent(inout) :: len_out
      integer(c_int32_t) :: s
    end function
    function dk_spring_solve_angle_scratch_len_f32(node_count, dim, options, len_out) bind(C, &
        name="dk_spring_solve_angle_scratch_len_f32") result(s)
      import :: c_int32_t, c_size_t, dk_spring_angle_options
      integer(c_size_t), value :: node_count
      integer(c_int32_t), value :: dim
      type(dk_spring_angle_options), intent(in) :: options
      integer(c_size_t), intent(inout) :: len_out
      integer(c_int32_t) :: s
    end function
    function dk_spring_angle_rigidity_probe_scratch_len(node_count, dim, len_out) bind(C, &
        name="dk_spring_angle_rigidity_probe_scratch_len") result(s)
      import :: c_int32_t, c_size_t
      integer(c_size_t), value :: node_count
      integer(c_int32_t), value :: dim
      integer(c_size_t), intent(inout) :: len_out
      integer(c_int32_t) :: s
    end function
    function dk_spring_solve_angle(offsets, offsets_len, targets, targets_len, stiffness, &
        stiffness_len, fixed, fixed_len, points, points_len, dim, options, values, values_len, &
        scratch, scratch_len, index_scratch, index_scratch_len, report) bind(C, &
        name="dk_spring_solve_angle") result(s)
      import :: c_double, c_int32_t, c_int8_t, c_size_t, dk_spring_angle_options, &
          dk_spring_solve_report
      integer(c_int32_t), intent(in) :: offsets(*)
      integer(c_size_t), value :: offsets_len
      integer(c_int32_t), intent(in) :: targets(*)
      integer(c_size_t), value :: targets_len
      real(c_double), intent(in) :: stiffness(*)
      integer(c_size_t), value :: stiffness_len
      integer(c_int8_t), intent(in) :: fixed(*)
      integer(c_size_t), value :: fixed_len
      real(c_double), intent(in) :: points(*)
      integer(c_size_t), value :: points_len
      integer(c_int32_t), value :: dim
      type(dk_spring_angle_options), intent(in) :: options
      real(c_double), intent(inout) :: values(*)
      integer(c_size_t), value :: values_len
      real(c_double), intent(inout) :: scratch(*)
      integer(c_size_t), value :: scratch_len
      integer(c_int32_t), intent(inout) :: index_scratch(*)
      integer(c_size_t), value :: index_scratch_len
      type(dk_spring_solve_report), intent(inout) :: report
      integer(c_int32_t) :: s
    end function
    function dk_spring_solve_angle_f32(offsets, offsets_len, targets, targets_len, stiffness, &
        stiffness_len, fixed, fixed_len, points, points_len, dim, options, values, values_len, &
        scratch, scratch_len, index_scratch, index_scratch_len, report) bind(C, &
        name="dk_spring_solve_angle_f32") result(s)
      import :: c_float, c_int32_t, c_int8_t, c_size_t, dk_spring_angle_options, &
          dk_spring_solve_report
      integer(c_int32_t), intent(in) :: offsets(*)
      integer(c_size_t), value :: offsets_len
      integer(c_int32_t), intent(in) :: targets(*)
      integer(c_size_t), value :: targets_len
      real(c_float), intent(in) :: stiffness(*)
      integer(c_size_t), value :: stiffness_len
      integer(c_int8_t), intent(in) :: fixed(*)
      integer(c_size_t), value :: fixed_len
      real(c_float), intent(in) :: points(*)
      integer(c_size_t), value :: points_len
      integer(c_int32_t), value :: dim
      type(dk_spring_angle_options), intent(in) :: options
      real(c_float), intent(inout) :: values(*)
      integer(c_size_t), value :: values_len
      real(c_float), intent(inout) :: scratch(*)
      integer(c_size_t), value :: scratch_len
      integer(c_int32_t), intent(inout) :: index_scratch(*)
      integer(c_size_t), value :: index_scratch_len
      type(dk_spring_solve_report), intent(inout) :: report
      integer(c_int32_t) :: s
    end function
    function dk_spring_angle_jacobi_sweep(offsets, offsets_len, targets, targets_len, stiffness, &
        stiffness_len, fixed, fixed_len, points, points_len, dim, epsilon, nodes_start, nodes_end, &
        index_base, src, src_len, dst, dst_len, index_scratch, index_scratch_len, sweep) bind(C, &
        name="dk_spring_angle_jacobi_sweep") result(s)
      import :: c_double, c_int32_t, c_int8_t, c_size_t, dk_spring_sweep
      integer(c_int32_t), intent(in) :: offsets(*)
      integer(c_size_t), value :: offsets_len
      integer(c_int32_t), intent(in) :: targets(*)
      integer(c_size_t), value :: targets_len
      real(c_double), intent(in) :: stiffness(*)
      integer(c_size_t), value :: stiffness_len
      integer(c_int8_t), intent(in) :: fixed(*)
      integer(c_size_t), value :: fixed_len
      real(c_double), intent(in) :: points(*)
      integer(c_size_t), value :: points_len
      integer(c_int32_t), value :: dim
      real(c_double), value :: epsilon
      integer(c_size_t), value :: nodes_start
      integer(c_size_t), value :: nodes_end
      integer(c_int32_t), value :: index_base
      real(c_double), intent(in) :: src(*)
      integer(c_size_t), value :: src_len
      real(c_double), intent(inout) :: dst(*)
      integer(c_size_t), value :: dst_len
      integer(c_int32_t), intent(inout) :: index_scratch(*)
      integer(c_size_t), value :: index_scratch_len
      type(dk_spring_sweep), intent(inout) :: sweep
      integer(c_int32_t) :: s
    end function
    function dk_spring_angle_jacobi_sweep_f32(offsets, offsets_len, targets, targets_len, &
        stiffness, stiffness_len, fixed, fixed_len, points, points_len, dim, epsilon, nodes_start, &
        nodes_end, index_base, src, src_len, dst, dst_len, index_scratch, index_scratch_len, &
        sweep) bind(C, name="dk_spring_angle_jacobi_sweep_f32") result(s)
      import :: c_float, c_int32_t, c_int8_t, c_size_t, dk_spring_sweep
      integer(c_int32_t), intent(in) :: offsets(*)
      integer(c_size_t), value :: offsets_len
      integer(c_int32_t), intent(in) :: targets(*)
      integer(c_size_t), value :: targets_len
      real(c_float), intent(in) :: stiffness(*)
      integer(c_size_t), value :: stiffness_len
      integer(c_int8_t), intent(in) :: fixed(*)
      integer(c_size_t), value :: fixed_len
      real(c_float), intent(in) :: points(*)
      integer(c_size_t), value :: points_len
      integer(c_int32_t), value :: dim
      real(c_float), value :: epsilon
      integer(c_size_t), value :: nodes_start
      integer(c_size_t), value :: nodes_end
      integer(c_int32_t), value :: index_base
      real(c_float), intent(in) :: src(*)
      integer(c_size_t), value :: src_len
      real(c_float), intent(inout) :: dst(*)
      integer(c_size_t), value :: dst_len
      integer(c_int32_t), intent(inout) :: index_scratch(*)
      integer(c_size_t), value :: index_scratch_len
      type(dk_spring_sweep), intent(inout) :: sweep
      integer(c_int32_t) :: s
    end function
    function dk_spring_angle_gauss_seidel_sweep(offsets, offsets_len, targets, targets_len, &
        stiffness, stiffness_len, fixed, fixed_len, points, points_len, dim, epsilon, nodes_start, &
        nodes_end, index_base, values, values_len, index_scratch, index_scratch_len, sweep) &
        bind(C, name="dk_spring_angle_gauss_seidel_sweep") result(s)
      import :: c_double, c_int32_t, c_int8_t, c_size_t, dk_spring_sweep
      integer(c_int32_t), intent(in) :: offsets(*)
      integer(c_size_t), value :: offsets_len
      integer(c_int32_t), intent(in) :: targets(*)
      integer(c_size_t), value :: targets_len
      real(c_double), intent(in) :: stiffness(*)
      integer(c_size_t), value :: stiffness_len
      integer(c_int8_t), intent(in) :: fixed(*)
      integer(c_size_t), value :: fixed_len
      real(c_double), intent(in) :: points(*)
      integer(c_size_t), value :: points_len
      integer(c_int32_t), value :: dim
      real(c_double), value :: epsilon
      integer(c_size_t), value :: nodes_start
      integer(c_size_t), value :: nodes_end
      integer(c_int32_t), value :: index_base
      real(c_double), intent(inout) :: values(*)
      integer(c_size_t), value :: values_len
      integer(c_int32_t), intent(inout) :: index_scratch(*)
      integer(c_size_t), value :: index_scratch_len
      type(dk_spring_sweep), intent(inout) :: sweep
      integer(c_int32_t) :: s
    end function
    function dk_spring_angle_gauss_seidel_sweep_f32(offsets, offsets_len, targets, targets_len, &
        stiffness, stiffness_len, fixed, fixed_len, points, points_len, dim, epsilon, nodes_start, &
        nodes_end, index_base, values, values_len, index_scratch, index_scratch_len, sweep) &
        bind(C, name="dk_spring_angle_gauss_seidel_sweep_f32") result(s)
      import :: c_float, c_int32_t, c_int8_t, c_size_t, dk_spring_sweep
      integer(c_int32_t), intent(in) :: offsets(*)
      integer(c_size_t), value :: offsets_len
      integer(c_int32_t), intent(in) :: targets(*)
      integer(c_size_t), value :: targets_len
      real(c_float), intent(in) :: stiffness(*)
      integer(c_size_t), value :: stiffness_len
      integer(c_int8_t), intent(in) :: fixed(*)
      integer(c_size_t), value :: fixed_len
      real(c_float), intent(in) :: points(*)
      integer(c_size_t), value :: points_len
      integer(c_int32_t), value :: dim
      real(c_float), value :: epsilon
      integer(c_size_t), value :: nodes_start
      integer(c_size_t), value :: nodes_end
      integer(c_int32_t), value :: index_base
      real(c_float), intent(inout) :: values(*)
      integer(c_size_t), value :: values_len
      integer(c_int32_t), intent(inout) :: index_scratch(*)
      integer(c_size_t), value :: index_scratch_len
      type(dk_spring_sweep), intent(inout) :: sweep
      integer(c_int32_t) :: s
    end function
    function dk_spring_angle_rigidity_probe(offsets, offsets_len, targets, targets_len, stiffness, &
        stiffness_len, fixed, fixed_len, points, points_len, dim, options, scratch, scratch_len, &
        index_scratch, index_scratch_len, amplification_out) bind(C, &
        name="dk_spring_angle_rigidity_probe") result(s)
      import :: c_double, c_int32_t, c_int8_t, c_size_t, dk_spring_angle_options
      integer(c_int32_t), intent(in) :: offsets(*)
      integer(c_size_t), value :: offsets_len
      integer(c_int32_t), intent(in) :: targets(*)
      integer(c_size_t), value :: targets_len
      real(c_double), intent(in) :: stiffness(*)
      integer(c_size_t), value :: stiffness_len
      integer(c_int8_t), intent(in) :: fixed(*)
      integer(c_size_t), value :: fixed_len
      real(c_double), intent(in) :: points(*)
      integer(c_size_t), value :: points_len
      integer(c_int32_t), value :: dim
      type(dk_spring_angle_options), intent(in) :: options
      real(c_double), intent(inout) :: scratch(*)
      integer(c_size_t), value :: scratch_len
      integer(c_int32_t), intent(inout) :: index_scratch(*)
      integer(c_size_t), value :: index_scratch_len
      real(c_double), intent(inout) :: amplification_out
      integer(c_int32_t) :: s
    end function
    function dk_spring_angle_rigidity_probe_f32(offsets, offsets_len, targets, targets_len, &
        stiffness, stiffness_len, fixed, fixed_len, points, points_len, dim, options, scratch, &
        scratch_len, index_scratch, index_scratch_len, amplification_out) bind(C, &
        name="dk_spring_angle_rigidity_probe_f32") result(s)
      import :: c_float, c_int32_t, c_int8_t, c_size_t, dk_spring_angle_options
      integer(c_int32_t), intent(in) :: offsets(*)
      integer(c_size_t), value :: offsets_len
      integer(c_int32_t), intent(in) :: targets(*)
      integer(c_size_t), value :: targets_len
      real(c_float), intent(in) :: stiffness(*)
      integer(c_size_t), value :: stiffness_len
      integer(c_int8_t), intent(in) :: fixed(*)
      integer(c_size_t), value :: fixed_len
      real(c_float), intent(in) :: points(*)
      integer(c_size_t), value :: points_len
      integer(c_int32_t), value :: dim
      type(dk_spring_angle_options), intent(in) :: options
      real(c_float), intent(inout) :: scratch(*)
      integer(c_size_t), value :: scratch_len
      integer(c_int32_t), intent(inout) :: index_scratch(*)
      integer(c_size_t), value :: index_scratch_len
      real(c_float), intent(inout) :: amplification_out
      integer(c_int32_t) :: s
    end function
    function dk_spring_wall_distances(points, points_len, dim, wall, wall_len, index_base, &
        index_scratch, index_scratch_len, out, out_len) bind(C, name="dk_spring_wall_distances") &
        result(s)
      import :: c_double, c_int32_t, c_size_t
      real(c_double), intent(in) :: points(*)
      integer(c_size_t), value :: points_len
      integer(c_int32_t), value :: dim
      integer(c_int32_t), intent(in) :: wall(*)
      integer(c_size_t), value :: wall_len
      integer(c_int32_t), value :: index_base
      integer(c_int32_t), intent(inout) :: index_scratch(*)
      integer(c_size_t), value :: index_scratch_len
      real(c_double), intent(inout) :: out(*)
      integer(c_size_t), value :: out_len
      integer(c_int32_t) :: s
    end function
    function dk_spring_wall_distances_f32(points, points_len, dim, wall, wall_len, index_base, &
        index_scratch, index_scratch_len, out, out_len) bind(C, &
        name="dk_spring_wall_distances_f32") result(s)
      import :: c_float, c_int32_t, c_size_t
      real(c_float), intent(in) :: points(*)
      integer(c_size_t), value :: points_len
      integer(c_int32_t), value :: dim
      integer(c_int32_t), intent(in) :: wall(*)
      integer(c_size_t), value :: wall_len
      integer(c_int32_t), value :: index_base
      integer(c_int32_t), intent(inout) :: index_scratch(*)
      integer(c_size_t), value :: index_scratch_len
      real(c_float), intent(inout) :: out(*)
      integer(c_size_t), value :: out_len
      integer(c_int32_t) :: s
    end function
    function dk_spring_wall_distance_factors(distances, distances_len, exponent) bind(C, &
        name="dk_spring_wall_distance_factors") result(s)
      import :: c_double, c_int32_t, c_size_t
      real(c_double), intent(inout) :: distances(*)
      integer(c_size_t), value :: distances_len
      real(c_double), value :: exponent
      integer(c_int32_t) :: s
    end function
    function dk_spring_wall_distance_factors_f32(distances, distances_len, exponent) bind(C, &
        name="dk_spring_wall_distance_factors_f32") result(s)
      import :: c_float, c_int32_t, c_size_t
      real(c_float), intent(inout) :: distances(*)
      integer(c_size_t), value :: distances_len
      real(c_float), value :: exponent
      integer(c_int32_t) :: s
    end function
    function dk_spring_dual_volumes(cell_offsets, cell_offsets_len, cell_nodes, cell_nodes_len, &
        cell_kinds, cell_kinds_len, index_base, index_scratch, index_scratch_len, points, &
        points_len, dim, out, out_len, scratch, scratch_len) bind(C, &
        name="dk_spring_dual_volumes") result(s)
      import :: c_double, c_int32_t, c_int8_t, c_size_t
      integer(c_int32_t), intent(in) :: cell_offsets(*)
      integer(c_size_t), value :: cell_offsets_len
      integer(c_int32_t), intent(in) :: cell_nodes(*)
      integer(c_size_t), value :: cell_nodes_len
      integer(c_int8_t), intent(in) :: cell_kinds(*)
      integer(c_size_t), value :: cell_kinds_len
      integer(c_int32_t), value :: index_base
      integer(c_int32_t), intent(inout) :: index_scratch(*)
      integer(c_size_t), value :: index_scratch_len
      real(c_double), intent(in) :: points(*)
      integer(c_size_t), value :: points_len
      integer(c_int32_t), value :: dim
      real(c_double), intent(inout) :: out(*)
      integer(c_size_t), value :: out_len
      real(c_double), intent(inout) :: scratch(*)
      integer(c_size_t), value :: scratch_len
      integer(c_int32_t) :: s
    end function
    function dk_spring_dual_volumes_f32(cell_offsets, cell_offsets_len, cell_nodes, &
        cell_nodes_len, cell_kinds, cell_kinds_len, index_base, index_scratch, index_scratch_len, &
        points, points_len, dim, out, out_len, scratch, scratch_len) bind(C, &
        name="dk_spring_dual_volumes_f32") result(s)
      import :: c_float, c_int32_t, c_int8_t, c_size_t
      integer(c_int32_t), intent(in) :: cell_offsets(*)
      integer(c_size_t), value :: cell_offsets_len
      integer(c_int32_t), intent(in) :: cell_nodes(*)
      integer(c_size_t), value :: cell_nodes_len
      integer(c_int8_t), intent(in) :: cell_kinds(*)
      integer(c_size_t), value :: cell_kinds_len
      integer(c_int32_t), value :: index_base
      integer(c_int32_t), intent(inout) :: index_scratch(*)
      integer(c_size_t), value :: index_scratch_len
      real(c_float), intent(in) :: points(*)
      integer(c_size_t), value :: points_len
      integer(c_int32_t), value :: dim
      real(c_float), intent(inout) :: out(*)
      integer(c_size_t), value :: out_len
      real(c_float), intent(inout) :: scratch(*)
      integer(c_size_t), value :: scratch_len
      integer(c_int32_t) :: s
    end function
    function dk_spring_inverse_volume_factors(volumes, volumes_len, exponent) bind(C, &
        name="dk_spring_inverse_volume_factors") result(s)
      import :: c_double, c_int32_t, c_size_t
      real(c_double), intent(inout) :: volumes(*)
      integer(c_size_t), value :: volumes_len
      real(c_double), value :: exponent
      integer(c_int32_t) :: s
    end function
    function dk_spring_inverse_volume_factors_f32(volumes, volumes_len, exponent) bind(C, &
        name="dk_spring_inverse_volume_factors_f32") result(s)
      import :: c_float, c_int32_t, c_size_t
      real(c_float), intent(inout) :: volumes(*)
      integer(c_size_t), value :: volumes_len
      real(c_float), value :: exponent
      integer(c_int32_t) :: s
    end function
    function dk_spring_scale_stiffness(offsets, offsets_len, targets, targets_len, factors, &
        factors_len, stiffness, stiffness_len) bind(C, name="dk_spring_scale_stiffness") result(s)
      import :: c_double, c_int32_t, c_size_t
      integer(c_int32_t), intent(in) :: offsets(*)
      integer(c_size_t), value :: offsets_len
      integer(c_int32_t), intent(in) :: targets(*)
      integer(c_size_t), value :: targets_len
      real(c_double), intent(in) :: factors(*)
      integer(c_size_t), value :: factors_len
      real(c_double), intent(inout) :: stiffness(*)
      integer(c_size_t), value :: stiffness_len
      integer(c_int32_t) :: s
    end function
    function dk_spring_scale_stiffness_f32(offsets, offsets_len, targets, targets_len, factors, &
        factors_len, stiffness, stiffness_len) bind(C, name="dk_spring_scale_stiffness_f32") &
        result(s)
      import :: c_float, c_int32_t, c_size_t
      integer(c_int32_t), intent(in) :: offsets(*)
      integer(c_size_t), value :: offsets_len
      integer(c_int32_t), intent(in) :: targets(*)
      integer(c_size_t), value :: targets_len
      real(c_float), intent(in) :: factors(*)
      integer(c_size_t), value :: factors_len
      real(c_float), intent(inout) :: stiffness(*)
      integer(c_size_t), value :: stiffness_len
      integer(c_int32_t) :: s
    end function
    function dk_taubin_params_paper(lambda_out, mu_out) bind(C, name="dk_taubin_params_paper") &
        result(s)
      import :: c_double, c_int32_t
      real(c_double), intent(inout) :: lambda_out
      real(c_double), intent(inout) :: mu_out
      integer(c_int32_t) :: s
    end function
    function dk_taubin_params_paper_f32(lambda_out, mu_out) bind(C, &
        name="dk_taubin_params_paper_f32") result(s)
      import :: c_float, c_int32_t
      real(c_float), intent(inout) :: lambda_out
      real(c_float), intent(inout) :: mu_out
      integer(c_int32_t) :: s
    end function
    function dk_taubin_params_from_pass_band(lambda, pass_band, lambda_out, mu_out) bind(C, &
        name="dk_taubin_params_from_pass_band") result(s)
      import :: c_double, c_int32_t
      real(c_double), value :: lambda
      real(c_double), value :: pass_band
      real(c_double), intent(inout) :: lambda_out
      real(c_double), intent(inout) :: mu_out
      integer(c_int32_t) :: s
    end function
    function dk_taubin_params_from_pass_band_f32(lambda, pass_band, lambda_out, mu_out) bind(C, &
        name="dk_taubin_params_from_pass_band_f32") result(s)
      import :: c_float, c_int32_t
      real(c_float), value :: lambda
      real(c_float), value :: pass_band
      real(c_float), intent(inout) :: lambda_out
      real(c_float), intent(inout) :: mu_out
      integer(c_int32_t) :: s
    end function
    function dk_smooth_arclength_options_default(direction, out) bind(C, &
        name="dk_smooth_arclength_options_default") result(s)
      import :: c_int32_t, dk_smooth_arclength_options
      integer(c_int32_t), value :: direction
      type(dk_smooth_arclength_options), intent(inout) :: out
      integer(c_int32_t) :: s
    end function
    function dk_taubin_smooth_arclength_scratch_len(ni, nj, nk, options, dim, len_out) bind(C, &
        name="dk_taubin_smooth_arclength_scratch_len") result(s)
      import :: c_int32_t, c_size_t, dk_smooth_arclength_options
      integer(c_size_t), value :: ni
      integer(c_size_t), value :: nj
      integer(c_size_t), value :: nk
      type(dk_smooth_arclength_options), intent(in) :: options
      integer(c_int32_t), value :: dim
      integer(c_size_t), intent(inout) :: len_out
      integer(c_int32_t) :: s
    end function
    function dk_taubin_smooth_arclength(ni, nj, nk, options, points, points_len, dim, scratch, &
        scratch_len, report) bind(C, name="dk_taubin_smooth_arclength") result(s)
      import :: c_double, c_int32_t, c_size_t, dk_smooth_arclength_options, dk_smooth_report
      integer(c_size_t), value :: ni
      integer(c_size_t), value :: nj
      integer(c_size_t), value :: nk
      type(dk_smooth_arclength_options), intent(in) :: options
      real(c_double), intent(inout) :: points(*)
      integer(c_size_t), value :: points_len
      integer(c_int32_t), value :: dim
      real(c_double), intent(inout) :: scratch(*)
      integer(c_size_t), value :: scratch_len
      type(dk_smooth_report), intent(inout) :: report
      integer(c_int32_t) :: s
    end function
    function dk_taubin_smooth_arclength_f32(ni, nj, nk, options, points, points_len, dim, scratch, &
        scratch_len, report) bind(C, name="dk_taubin_smooth_arclength_f32") result(s)
      import :: c_float, c_int32_t, c_size_t, dk_smooth_arclength_options, dk_smooth_report
      integer(c_size_t), value :: ni
      integer(c_size_t), value :: nj
      integer(c_size_t), value :: nk
      type(dk_smooth_arclength_options), intent(in) :: options
      real(c_float), intent(inout) :: points(*)
      integer(c_size_t), value :: points_len
      integer(c_int32_t), value :: dim
      real(c_float), intent(inout) :: scratch(*)
      integer(c_size_t), value :: scratch_len
      type(dk_smooth_report), intent(inout) :: report
      integer(c_int32_t) :: s
    end function
    function dk_taubin_smooth_structured_scratch_len(ni, nj, nk, len_out) bind(C, &
        name="dk_taubin_smooth_structured_scratch_len") result(s)
      import :: c_int32_t, c_size_t
      integer(c_size_t), value :: ni
      integer(c_size_t), value :: nj
      integer(c_size_t), value :: nk
      integer(c_size_t), intent(inout) :: len_out
      integer(c_int32_t) :: s
    end function
    function dk_taubin_smooth_structured(ni, nj, nk, lambda, mu, iterations, options, field, &
        field_len, scratch, scratch_len, report) bind(C, name="dk_taubin_smooth_structured") &
        result(s)
      import :: c_double, c_int32_t, c_size_t, dk_filter_report, dk_structured_options
      integer(c_size_t), value :: ni
      integer(c_size_t), value :: nj
      integer(c_size_t), value :: nk
      real(c_double), value :: lambda
      real(c_double), value :: mu
      integer(c_size_t), value :: iterations
      type(dk_structured_options), intent(in) :: options
      real(c_double), intent(inout) :: field(*)
      integer(c_size_t), value :: field_len
      real(c_double), intent(inout) :: scratch(*)
      integer(c_size_t), value :: scratch_len
      type(dk_filter_report), intent(inout) :: report
      integer(c_int32_t) :: s
    end function
    function dk_taubin_smooth_structured_f32(ni, nj, nk, lambda, mu, iterations, options, field, &
        field_len, scratch, scratch_len, report) bind(C, name="dk_taubin_smooth_structured_f32") &
        result(s)
      import :: c_float, c_int32_t, c_size_t, dk_filter_report, dk_structured_options
      integer(c_size_t), value :: ni
      integer(c_size_t), value :: nj
      integer(c_size_t), value :: nk
      real(c_float), value :: lambda
      real(c_float), value :: mu
      integer(c_size_t), value :: iterations
      type(dk_structured_options), intent(in) :: options
      real(c_float), intent(inout) :: field(*)
      integer(c_size_t), value :: field_len
      real(c_float), intent(inout) :: scratch(*)
      integer(c_size_t), value :: scratch_len
      type(dk_filter_report), intent(inout) :: report
      integer(c_int32_t) :: s
    end function
    function dk_taubin_structured_sweep(ni, nj, nk, src, src_len, weight, options, region, &
        index_base, dst, dst_len, max_change_out) bind(C, name="dk_taubin_structured_sweep") &
        result(s)
      import :: c_double, c_int32_t, c_size_t, dk_block_region, dk_structured_options
      integer(c_size_t), value :: ni
      integer(c_size_t), value :: nj
      integer(c_size_t), value :: nk
      real(c_double), intent(in) :: src(*)
      integer(c_size_t), value :: src_len
      real(c_double), value :: weight
      type(dk_structured_options), intent(in) :: options
      type(dk_block_region), intent(in) :: region
      integer(c_int32_t), value :: index_base
      real(c_double), intent(inout) :: dst(*)
      integer(c_size_t), value :: dst_len
      real(c_double), intent(inout) :: max_change_out
      integer(c_int32_t) :: s
    end function
    function dk_taubin_structured_sweep_f32(ni, nj, nk, src, src_len, weight, options, region, &
        index_base, dst, dst_len, max_change_out) bind(C, name="dk_taubin_structured_sweep_f32") &
        result(s)
      import :: c_float, c_int32_t, c_size_t, dk_block_region, dk_structured_options
      integer(c_size_t), value :: ni
      integer(c_size_t), value :: nj
      integer(c_size_t), value :: nk
      real(c_float), intent(in) :: src(*)
      integer(c_size_t), value :: src_len
      real(c_float), value :: weight
      type(dk_structured_options), intent(in) :: options
      type(dk_block_region), intent(in) :: region
      integer(c_int32_t), value :: index_base
      real(c_float), intent(inout) :: dst(*)
      integer(c_size_t), value :: dst_len
      real(c_float), intent(inout) :: max_change_out
      integer(c_int32_t) :: s
    end function
    function dk_taubin_smooth_structured_coarse_scratch_len(ni, nj, nk, coarse, len_out) bind(C, &
        name="dk_taubin_smooth_structured_coarse_scratch_len") result(s)
      import :: c_int32_t, c_size_t, dk_taubin_coarse
      integer(c_size_t), value :: ni
      integer(c_size_t), value :: nj
      integer(c_size_t), value :: nk
      type(dk_taubin_coarse), intent(in) :: coarse
      integer(c_size_t), intent(inout) :: len_out
      integer(c_int32_t) :: s
    end function
    function dk_taubin_smooth_structured_coarse(ni, nj, nk, coarse, lambda, mu, iterations, &
        options, field, field_len, scratch, scratch_len, report) bind(C, &
        name="dk_taubin_smooth_structured_coarse") result(s)
      import :: c_double, c_int32_t, c_size_t, dk_filter_report, dk_structured_options, &
          dk_taubin_coarse
      integer(c_size_t), value :: ni
      integer(c_size_t), value :: nj
      integer(c_size_t), value :: nk
      type(dk_taubin_coarse), intent(in) :: coarse
      real(c_double), value :: lambda
      real(c_double), value :: mu
      integer(c_size_t), value :: iterations
      type(dk_structured_options), intent(in) :: options
      real(c_double), intent(inout) :: field(*)
      integer(c_size_t), value :: field_len
      real(c_double), intent(inout) :: scratch(*)
      integer(c_size_t), value :: scratch_len
      type(dk_filter_report), intent(inout) :: report
      integer(c_int32_t) :: s
    end function
    function dk_taubin_smooth_structured_coarse_f32(ni, nj, nk, coarse, lambda, mu, iterations, &
        options, field, field_len, scratch, scratch_len, report) bind(C, &
        name="dk_taubin_smooth_structured_coarse_f32") result(s)
      import :: c_float, c_int32_t, c_size_t, dk_filter_report, dk_structured_options, &
          dk_taubin_coarse
      integer(c_size_t), value :: ni
      integer(c_size_t), value :: nj
      integer(c_size_t), value :: nk
      type(dk_taubin_coarse), intent(in) :: coarse
      real(c_float), value :: lambda
      real(c_float), value :: mu
      integer(c_size_t), value :: iterations
      type(dk_structured_options), intent(in) :: options
      real(c_float), intent(inout) :: field(*)
      integer(c_size_t), value :: field_len
      real(c_float), intent(inout) :: scratch(*)
      integer(c_size_t), value :: scratch_len
      type(dk_filter_report), intent(inout) :: report
      integer(c_int32_t) :: s
    end function
    function dk_taubin_smooth_graph_scratch_len(node_count, components, len_out) bind(C, &
        name="dk_taubin_smooth_graph_scratch_len") result(s)
      import :: c_int32_t, c_size_t
      integer(c_size_t), value :: node_count
      integer(c_int32_t), value :: components
      integer(c_size_t), intent(inout) :: len_out
      integer(c_int32_t) :: s
    end function
    function dk_taubin_smooth_graph(offsets, offsets_len, targets, targets_len, weights, &
        weights_len, fixed, fixed_len, lambda, mu, iterations, components, values, values_len, &
        scratch, scratch_len, report) bind(C, name="dk_taubin_smooth_graph") result(s)
      import :: c_double, c_int32_t, c_ptr, c_size_t, dk_filter_report
      integer(c_int32_t), intent(in) :: offsets(*)
      integer(c_size_t), value :: offsets_len
      integer(c_int32_t), intent(in) :: targets(*)
      integer(c_size_t), value :: targets_len
      type(c_ptr), value :: weights
      integer(c_size_t), value :: weights_len
      type(c_ptr), value :: fixed
      integer(c_size_t), value :: fixed_len
      real(c_double), value :: lambda
      real(c_double), value :: mu
      integer(c_size_t), value :: iterations
      integer(c_int32_t), value :: components
      real(c_double), intent(inout) :: values(*)
      integer(c_size_t), value :: values_len
      real(c_double), intent(inout) :: scratch(*)
      integer(c_size_t), value :: scratch_len
      type(dk_filter_report), intent(inout) :: report
      integer(c_int32_t) :: s
    end function
    function dk_taubin_smooth_graph_f32(offsets, offsets_len, targets, targets_len, weights, &
        weights_len, fixed, fixed_len, lambda, mu, iterations, components, values, values_len, &
        scratch, scratch_len, report) bind(C, name="dk_taubin_smooth_graph_f32") result(s)
      import :: c_float, c_int32_t, c_ptr, c_size_t, dk_filter_report
      integer(c_int32_t), intent(in) :: offsets(*)
      integer(c_size_t), value :: offsets_len
      integer(c_int32_t), intent(in) :: targets(*)
      integer(c_size_t), value :: targets_len
      type(c_ptr), value :: weights
      integer(c_size_t), value :: weights_len
      type(c_ptr), value :: fixed
      integer(c_size_t), value :: fixed_len
      real(c_float), value :: lambda
      real(c_float), value :: mu
      integer(c_size_t), value :: iterations
      integer(c_int32_t), value :: components
      real(c_float), intent(inout) :: values(*)
      integer(c_size_t), value :: values_len
      real(c_float), intent(inout) :: scratch(*)
      integer(c_size_t), value :: scratch_len
      type(dk_filter_report), intent(inout) :: report
      integer(c_int32_t) :: s
    end function
    function dk_taubin_graph_sweep(offsets, offsets_len, targets, targets_len, weights, &
        weights_len, fixed, fixed_len, src, src_len, components, weight, nodes_start, nodes_end, &
        index_base, dst, dst_len, max_change_out) bind(C, name="dk_taubin_graph_sweep") result(s)
      import :: c_double, c_int32_t, c_ptr, c_size_t
      integer(c_int32_t), intent(in) :: offsets(*)
      integer(c_size_t), value :: offsets_len
      integer(c_int32_t), intent(in) :: targets(*)
      integer(c_size_t), value :: targets_len
      type(c_ptr), value :: weights
      integer(c_size_t), value :: weights_len
      type(c_ptr), value :: fixed
      integer(c_size_t), value :: fixed_len
      real(c_double), intent(in) :: src(*)
      integer(c_size_t), value :: src_len
      integer(c_int32_t), value :: components
      real(c_double), value :: weight
      integer(c_size_t), value :: nodes_start
      integer(c_size_t), value :: nodes_end
      integer(c_int32_t), value :: index_base
      real(c_double), intent(inout) :: dst(*)
      integer(c_size_t), value :: dst_len
      real(c_double), intent(inout) :: max_change_out
      integer(c_int32_t) :: s
    end function
    function dk_taubin_graph_sweep_f32(offsets, offsets_len, targets, targets_len, weights, &
        weights_len, fixed, fixed_len, src, src_len, components, weight, nodes_start, nodes_end, &
        index_base, dst, dst_len, max_change_out) bind(C, name="dk_taubin_graph_sweep_f32") &
        result(s)
      import :: c_float, c_int32_t, c_ptr, c_size_t
      integer(c_int32_t), intent(in) :: offsets(*)
      integer(c_size_t), value :: offsets_len
      integer(c_int32_t), intent(in) :: targets(*)
      integer(c_size_t), value :: targets_len
      type(c_ptr), value :: weights
      integer(c_size_t), value :: weights_len
      type(c_ptr), value :: fixed
      integer(c_size_t), value :: fixed_len
      real(c_float), intent(in) :: src(*)
      integer(c_size_t), value :: src_len
      integer(c_int32_t), value :: components
      real(c_float), value :: weight
      integer(c_size_t), value :: nodes_start
      integer(c_size_t), value :: nodes_end
      integer(c_int32_t), value :: index_base
      real(c_float), intent(inout) :: dst(*)
      integer(c_size_t), value :: dst_len
      real(c_float), intent(inout) :: max_change_out
      integer(c_int32_t) :: s
    end function
    function dk_taubin_inverse_distance_weights(offsets, offsets_len, targets, targets_len, &
        points, points_len, dim, weights, weights_len) bind(C, &
        name="dk_taubin_inverse_distance_weights") result(s)
      import :: c_double, c_int32_t, c_ptr, c_size_t
      integer(c_int32_t), intent(in) :: offsets(*)
      integer(c_size_t), value :: offsets_len
      integer(c_int32_t), intent(in) :: targets(*)
      integer(c_size_t), value :: targets_len
      real(c_double), intent(in) :: points(*)
      integer(c_size_t), value :: points_len
      integer(c_int32_t), value :: dim
      type(c_ptr), value :: weights
      integer(c_size_t), value :: weights_len
      integer(c_int32_t) :: s
    end function
    function dk_taubin_inverse_distance_weights_f32(offsets, offsets_len, targets, targets_len, &
        points, points_len, dim, weights, weights_len) bind(C, &
        name="dk_taubin_inverse_distance_weights_f32") result(s)
      import :: c_float, c_int32_t, c_ptr, c_size_t
      integer(c_int32_t), intent(in) :: offsets(*)
      integer(c_size_t), value :: offsets_len
      integer(c_int32_t), intent(in) :: targets(*)
      integer(c_size_t), value :: targets_len
      real(c_float), intent(in) :: points(*)
      integer(c_size_t), value :: points_len
      integer(c_int32_t), value :: dim
      type(c_ptr), value :: weights
      integer(c_size_t), value :: weights_len
      integer(c_int32_t) :: s
    end function
    function dk_taubin_arclength(ni, nj, nk, points, points_len, dim, direction, normalised, out, &
        out_len) bind(C, name="dk_taubin_arclength") result(s)
      import :: c_bool, c_double, c_int32_t, c_size_t
      integer(c_size_t), value :: ni
      integer(c_size_t), value :: nj
      integer(c_size_t), value :: nk
      real(c_double), intent(in) :: points(*)
      integer(c_size_t), value :: points_len
      integer(c_int32_t), value :: dim
      integer(c_int32_t), value :: direction
      logical(c_bool), value :: normalised
      real(c_double), intent(inout) :: out(*)
      integer(c_size_t), value :: out_len
      integer(c_int32_t) :: s
    end function
    function dk_taubin_arclength_f32(ni, nj, nk, points, points_len, dim, direction, normalised, &
        out, out_len) bind(C, name="dk_taubin_arclength_f32") result(s)
      import :: c_bool, c_float, c_int32_t, c_size_t
      integer(c_size_t), value :: ni
      integer(c_size_t), value :: nj
      integer(c_size_t), value :: nk
      real(c_float), intent(in) :: points(*)
      integer(c_size_t), value :: points_len
      integer(c_int32_t), value :: dim
      integer(c_int32_t), value :: direction
      logical(c_bool), value :: normalised
      real(c_float), intent(inout) :: out(*)
      integer(c_size_t), value :: out_len
      integer(c_int32_t) :: s
    end function
    function dk_taubin_redistribute_scratch_len(ni, nj, nk, dim, direction, len_out) bind(C, &
        name="dk_taubin_redistribute_scratch_len") result(s)
      import :: c_int32_t, c_size_t
      integer(c_size_t), value :: ni
      integer(c_size_t), value :: nj
      integer(c_size_t), value :: nk
      integer(c_int32_t), value :: dim
      integer(c_int32_t), value :: direction
      integer(c_size_t), intent(inout) :: len_out
      integer(c_int32_t) :: s
    end function
    function dk_taubin_redistribute(ni, nj, nk, direction, targets, targets_len, normalised, &
        points, points_len, dim, scratch, scratch_len, max_displacement_out) bind(C, &
        name="dk_taubin_redistribute") result(s)
      import :: c_bool, c_double, c_int32_t, c_size_t
      integer(c_size_t), value :: ni
      integer(c_size_t), value :: nj
      integer(c_size_t), value :: nk
      integer(c_int32_t), value :: direction
      real(c_double), intent(in) :: targets(*)
      integer(c_size_t), value :: targets_len
      logical(c_bool), value :: normalised
      real(c_double), intent(inout) :: points(*)
      integer(c_size_t), value :: points_len
      integer(c_int32_t), value :: dim
      real(c_double), intent(inout) :: scratch(*)
      integer(c_size_t), value :: scratch_len
      real(c_double), intent(inout) :: max_displacement_out
      integer(c_int32_t) :: s
    end function
    function dk_taubin_redistribute_f32(ni, nj, nk, direction, targets, targets_len, normalised, &
        points, points_len, dim, scratch, scratch_len, max_displacement_out) bind(C, &
        name="dk_taubin_redistribute_f32") result(s)
      import :: c_bool, c_float, c_int32_t, c_size_t
      integer(c_size_t), value :: ni
      integer(c_size_t), value :: nj
      integer(c_size_t), value :: nk
      integer(c_int32_t), value :: direction
      real(c_float), intent(in) :: targets(*)
      integer(c_size_t), value :: targets_len
      logical(c_bool), value :: normalised
      real(c_float), intent(inout) :: points(*)
      integer(c_size_t), value :: points_len
      integer(c_int32_t), value :: dim
      real(c_float), intent(inout) :: scratch(*)
      integer(c_size_t), value :: scratch_len
      real(c_float), intent(inout) :: max_displacement_out
      integer(c_int32_t) :: s
    end function
    function dk_taubin_stretching(ni, nj, nk, points, points_len, dim, direction, out, out_len) &
        bind(C, name="dk_taubin_stretching") result(s)
      import :: c_double, c_int32_t, c_size_t
      integer(c_size_t), value :: ni
      integer(c_size_t), value :: nj
      integer(c_size_t), value :: nk
      real(c_double), intent(in) :: points(*)
      integer(c_size_t), value :: points_len
      integer(c_int32_t), value :: dim
      integer(c_int32_t), value :: direction
      real(c_double), intent(inout) :: out(*)
      integer(c_size_t), value :: out_len
      integer(c_int32_t) :: s
    end function
    function dk_taubin_stretching_f32(ni, nj, nk, points, points_len, dim, direction, out, &
        out_len) bind(C, name="dk_taubin_stretching_f32") result(s)
      import :: c_float, c_int32_t, c_size_t
      integer(c_size_t), value :: ni
      integer(c_size_t), value :: nj
      integer(c_size_t), value :: nk
      real(c_float), intent(in) :: points(*)
      integer(c_size_t), value :: points_len
      integer(c_int32_t), value :: dim
      integer(c_int32_t), value :: direction
      real(c_float), intent(inout) :: out(*)
      integer(c_size_t), value :: out_len
      integer(c_int32_t) :: s
    end function
    function dk_taubin_max_stretching(ni, nj, nk, points, points_len, dim, direction, value_out, &
        point_out) bind(C, name="dk_taubin_max_stretching") result(s)
      import :: c_double, c_int32_t, c_size_t
      integer(c_size_t), value :: ni
      integer(c_size_t), value :: nj
      integer(c_size_t), value :: nk
      real(c_double), intent(in) :: points(*)
      integer(c_size_t), value :: points_len
      integer(c_int32_t), value :: dim
      integer(c_int32_t), value :: direction
      real(c_double), intent(inout) :: value_out
      integer(c_size_t), intent(inout) :: point_out
      integer(c_int32_t) :: s
    end function
    function dk_taubin_max_stretching_f32(ni, nj, nk, points, points_len, dim, direction, &
        value_out, point_out) bind(C, name="dk_taubin_max_stretching_f32") result(s)
      import :: c_float, c_int32_t, c_size_t
      integer(c_size_t), value :: ni
      integer(c_size_t), value :: nj
      integer(c_size_t), value :: nk
      real(c_float), intent(in) :: points(*)
      integer(c_size_t), value :: points_len
      integer(c_int32_t), value :: dim
      integer(c_int32_t), value :: direction
      real(c_float), intent(inout) :: value_out
      integer(c_size_t), intent(inout) :: point_out
      integer(c_int32_t) :: s
    end function
    function dk_taubin_check_lines_increasing(ni, nj, nk, field, field_len, direction, iteration, &
        points, points_len, dim) bind(C, name="dk_taubin_check_lines_increasing") result(s)
      import :: c_double, c_int32_t, c_ptr, c_size_t
      integer(c_size_t), value :: ni
      integer(c_size_t), value :: nj
      integer(c_size_t), value :: nk
      real(c_double), intent(in) :: field(*)
      integer(c_size_t), value :: field_len
      integer(c_int32_t), value :: direction
      integer(c_size_t), value :: iteration
      type(c_ptr), value :: points
      integer(c_size_t), value :: points_len
      integer(c_int32_t), value :: dim
      integer(c_int32_t) :: s
    end function
    function dk_taubin_check_lines_increasing_f32(ni, nj, nk, field, field_len, direction, &
        iteration, points, points_len, dim) bind(C, name="dk_taubin_check_lines_increasing_f32") &
        result(s)
      import :: c_float, c_int32_t, c_ptr, c_size_t
      integer(c_size_t), value :: ni
      integer(c_size_t), value :: nj
      integer(c_size_t), value :: nk
      real(c_float), intent(in) :: field(*)
      integer(c_size_t), value :: field_len
      integer(c_int32_t), value :: direction
      integer(c_size_t), value :: iteration
      type(c_ptr), value :: points
      integer(c_size_t), value :: points_len
      integer(c_int32_t), value :: dim
      integer(c_int32_t) :: s
    end function
  end interface
  ! <<< end generated >>>

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

  !> Rotates points(3, n) by q into out(3, n).
  function dkf_rotate_points(q, points, out) result(s)
    real(c_double), intent(in) :: q(4)
    real(c_double), intent(in), contiguous :: points(:, :)
    real(c_double), intent(inout), contiguous :: out(:, :)
    integer(c_int32_t) :: s
    s = dk_quat_rotate_points(q, points, int(size(points), c_size_t), out, &
                              int(size(out), c_size_t))
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
    integer(c_int32_t), intent(in), contiguous :: cell_offsets(:), cell_nodes(:)
    integer(c_int8_t), intent(in), contiguous :: cell_kinds(:)
    logical, intent(in) :: face_diagonals
    integer(c_size_t), intent(inout) :: len
    integer(c_int32_t) :: s
    integer(c_int32_t), allocatable :: index_scratch(:)
    allocate(index_scratch(size(cell_offsets) + size(cell_nodes)))
    s = dk_graph_from_cells_len(node_count, cell_offsets, int(size(cell_offsets), c_size_t), &
                                cell_nodes, int(size(cell_nodes), c_size_t), cell_kinds, &
                                int(size(cell_kinds), c_size_t), 1_c_int32_t, index_scratch, &
                                int(size(index_scratch), c_size_t), &
                                logical(face_diagonals, c_bool), len)
  end function

  !> Edge graph of a mixed-cell mesh given with 1-based cell offsets and node numbers.
  function dkf_graph_from_cells(node_count, cell_offsets, cell_nodes, cell_kinds, &
                                face_diagonals, offsets, targets, used) result(s)
    integer(c_size_t), intent(in) :: node_count
    integer(c_int32_t), intent(in), contiguous :: cell_offsets(:), cell_nodes(:)
    integer(c_int8_t), intent(in), contiguous :: cell_kinds(:)
    logical, intent(in) :: face_diagonals
    integer(c_int32_t), intent(inout), contiguous :: offsets(:), targets(:)
    integer(c_size_t), intent(inout) :: used
    integer(c_int32_t) :: s
    integer(c_int32_t), allocatable :: index_scratch(:)
    allocate(index_scratch(size(cell_offsets) + size(cell_nodes)))
    s = dk_graph_from_cells(node_count, cell_offsets, int(size(cell_offsets), c_size_t), &
                            cell_nodes, int(size(cell_nodes), c_size_t), cell_kinds, &
                            int(size(cell_kinds), c_size_t), 1_c_int32_t, index_scratch, &
                            int(size(index_scratch), c_size_t), &
                            logical(face_diagonals, c_bool), offsets, &
                            int(size(offsets), c_size_t), targets, int(size(targets), c_size_t), &
                            used)
  end function

  ! <<< wrappers: springs, quality, taubin >>>
  !> dk_spring_solve_linear with assumed-shape arrays: values(components, node_count) is
  !> updated in place (components = size(values, 1), 1 to 7); offsets/targets are the 0-based
  !> CSR graph from dk_graph_from_*; scratch needs dk_spring_solve_linear_scratch_len values
  !> (may be empty for Gauss-Seidel and SOR), index_scratch node_count entries.
  function dkf_spring_solve_linear(offsets, targets, stiffness, fixed, options, values, &
                                   scratch, index_scratch, report) result(s)
    integer(c_int32_t), intent(in), contiguous :: offsets(:), targets(:)
    real(c_double), intent(in), contiguous :: stiffness(:)
    integer(c_int8_t), intent(in), contiguous :: fixed(:)
    type(dk_spring_solve_options), intent(in) :: options
    real(c_double), intent(inout), contiguous :: values(:, :)
    real(c_double), intent(inout), contiguous :: scratch(:)
    integer(c_int32_t), intent(inout), contiguous :: index_scratch(:)
    type(dk_spring_solve_report), intent(inout) :: report
    integer(c_int32_t) :: s
    s = dk_spring_solve_linear(offsets, int(size(offsets), c_size_t), targets, &
                               int(size(targets), c_size_t), stiffness, &
                               int(size(stiffness), c_size_t), fixed, int(size(fixed), c_size_t), &
                               options, int(size(values, 1), c_int32_t), values, &
                               int(size(values), c_size_t), scratch, int(size(scratch), c_size_t), &
                               index_scratch, int(size(index_scratch), c_size_t), report)
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
    integer(c_int32_t), intent(in), contiguous :: offsets(:), targets(:)
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
    s = dk_taubin_smooth_graph(offsets, int(size(offsets), c_size_t), targets, &
                               int(size(targets), c_size_t), w, wl, f, fl, lambda, mu, &
                               iterations, int(size(values, 1), c_int32_t), values, &
                               int(size(values), c_size_t), scratch, int(size(scratch), c_size_t), &
                               report)
  end function
  ! <<< end wrappers: springs, quality, taubin >>>
  ! <<< wrappers: deformation >>>
  !> Fills m for the dkf_deform_* wrappers: 1-based nodes(b) and deformed(dim, b); optional
  !> boundary elements (1-based offsets and positions in nodes, VTK kinds), rigid_rotation(4)
  !> or node_rotations(4, b) (else the rotations come from the shape), origin(dim) (else the
  !> default origin). The pointers stay valid while the actual arguments do.
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
      m%element_offsets = c_loc(element_offsets)
      m%element_offsets_len = size(element_offsets, kind=c_size_t)
      m%element_nodes = c_loc(element_nodes)
      m%element_nodes_len = size(element_nodes, kind=c_size_t)
      m%element_kinds = c_loc(element_kinds)
      m%element_kinds_len = size(element_kinds, kind=c_size_t)
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
    real(c_double), intent(inout), contiguous, optional :: origin_out(:)
    integer(c_int32_t) :: s
    type(dk_boundary_motion) :: m
    real(c_double) :: none(1)
    call dkf_fill_motion(m, nodes, deformed, element_offsets, element_nodes, element_kinds, &
                         rigid_rotation, node_rotations, origin)
    if (present(origin_out)) then
      s = dk_deform_idw(points, size(points, kind=c_size_t), int(size(points, 1), c_int32_t), &
                        m, exponent, scratch, size(scratch, kind=c_size_t), index_scratch, &
                        size(index_scratch, kind=c_size_t), translations, &
                        size(translations, kind=c_size_t), rotations, &
                        size(rotations, kind=c_size_t), out, size(out, kind=c_size_t), &
                        origin_out, size(origin_out, kind=c_size_t))
    else
      s = dk_deform_idw(points, size(points, kind=c_size_t), int(size(points, 1), c_int32_t), &
                        m, exponent, scratch, size(scratch, kind=c_size_t), index_scratch, &
                        size(index_scratch, kind=c_size_t), translations, &
                        size(translations, kind=c_size_t), rotations, &
                        size(rotations, kind=c_size_t), out, size(out, kind=c_size_t), &
                        none, 0_c_size_t)
    end if
  end function

  !> dk_deform_tfi with Fortran arrays: a dims(1) x dims(2) x dims(3) block (dims(3) = 1 in
  !> 2D), directions a sum of DK_DIRECTION_*; other arguments as dkf_deform_idw (scratch:
  !> dk_deform_tfi_scratch_len).
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
    real(c_double), intent(inout), contiguous, optional :: origin_out(:)
    integer(c_int32_t) :: s
    type(dk_boundary_motion) :: m
    real(c_double) :: none(1)
    call dkf_fill_motion(m, nodes, deformed, element_offsets, element_nodes, element_kinds, &
                         rigid_rotation, node_rotations, origin)
    if (present(origin_out)) then
      s = dk_deform_tfi(dims(1), dims(2), dims(3), directions, points, &
                        size(points, kind=c_size_t), int(size(points, 1), c_int32_t), m, &
                        scratch, size(scratch, kind=c_size_t), index_scratch, &
                        size(index_scratch, kind=c_size_t), translations, &
                        size(translations, kind=c_size_t), rotations, &
                        size(rotations, kind=c_size_t), out, size(out, kind=c_size_t), &
                        origin_out, size(origin_out, kind=c_size_t))
    else
      s = dk_deform_tfi(dims(1), dims(2), dims(3), directions, points, &
                        size(points, kind=c_size_t), int(size(points, 1), c_int32_t), m, &
                        scratch, size(scratch, kind=c_size_t), index_scratch, &
                        size(index_scratch, kind=c_size_t), translations, &
                        size(translations, kind=c_size_t), rotations, &
                        size(rotations, kind=c_size_t), out, size(out, kind=c_size_t), &
                        none, 0_c_size_t)
    end if
  end function

  !> dk_deform_spring with Fortran arrays: the 0-based CSR graph offsets(n + 1), targets(:)
  !> from dkf_graph_from_*, stiffness(size(targets)), fixed(n) (nonzero = boundary node),
  !> options; values(:) (second length of dk_deform_spring_scratch_len); index_scratch(:) at
  !> least size(nodes) + size(element_offsets) + size(element_nodes) + n; report receives the
  !> solver report. Other arguments as dkf_deform_idw.
  function dkf_deform_spring(points, nodes, deformed, offsets, targets, stiffness, fixed, &
                             options, scratch, values, index_scratch, translations, rotations, &
                             out, report, element_offsets, element_nodes, element_kinds, &
                             rigid_rotation, node_rotations, origin, origin_out) result(s)
    real(c_double), intent(in), contiguous :: points(:, :)
    integer(c_int32_t), intent(in), target, contiguous :: nodes(:)
    real(c_double), intent(in), target, contiguous :: deformed(:, :)
    integer(c_int32_t), intent(in), contiguous :: offsets(:), targets(:)
    real(c_double), intent(in), contiguous :: stiffness(:)
    integer(c_int8_t), intent(in), contiguous :: fixed(:)
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
    real(c_double), intent(inout), contiguous, optional :: origin_out(:)
    integer(c_int32_t) :: s
    type(dk_boundary_motion) :: m
    real(c_double) :: none(1)
    call dkf_fill_motion(m, nodes, deformed, element_offsets, element_nodes, element_kinds, &
                         rigid_rotation, node_rotations, origin)
    if (present(origin_out)) then
      s = dk_deform_spring(points, size(points, kind=c_size_t), &
                           int(size(points, 1), c_int32_t), m, offsets, &
                           size(offsets, kind=c_size_t), targets, size(targets, kind=c_size_t), &
                           stiffness, size(stiffness, kind=c_size_t), fixed, &
                           size(fixed, kind=c_size_t), options, scratch, &
                           size(scratch, kind=c_size_t), values, size(values, kind=c_size_t), &
                           index_scratch, size(index_scratch, kind=c_size_t), translations, &
                           size(translations, kind=c_size_t), rotations, &
                           size(rotations, kind=c_size_t), out, size(out, kind=c_size_t), &
                           origin_out, size(origin_out, kind=c_size_t), report)
    else
      s = dk_deform_spring(points, size(points, kind=c_size_t), &
                           int(size(points, 1), c_int32_t), m, offsets, &
                           size(offsets, kind=c_size_t), targets, size(targets, kind=c_size_t), &
                           stiffness, size(stiffness, kind=c_size_t), fixed, &
                           size(fixed, kind=c_size_t), options, scratch, &
                           size(scratch, kind=c_size_t), values, size(values, kind=c_size_t), &
                           index_scratch, size(index_scratch, kind=c_size_t), translations, &
                           size(translations, kind=c_size_t), rotations, &
                           size(rotations, kind=c_size_t), out, size(out, kind=c_size_t), &
                           none, 0_c_size_t, report)
    end if
  end function

  !> dk_plan_work_sizes + dk_plan_pool_sizes with Fortran arrays: points(dim, n), the CSR
  !> graph offsets(n + 1), targets(:) from dkf_graph_from_*, the 1-based boundary(:) node
  !> list, options (from dk_plan_options_default), optional boundary elements over
  !> 1..size(boundary) as 1-based element_offsets/element_nodes (as dkf_graph_from_cells takes
  !> cells) and element_kinds, and an optional stiffness(size(targets)) per directed edge (else
  !> Batina's with options%stiffness_exponent). The work buffers and 0-based copies of the node
  !> lists are allocated here and freed on return; pools receives the three pool lengths.
  function dkf_plan_pool_sizes(points, offsets, targets, boundary, options, pools, &
                               element_offsets, element_nodes, element_kinds, stiffness) result(s)
    use, intrinsic :: iso_c_binding, only: c_loc, c_null_ptr
    real(c_double), intent(in), contiguous :: points(:, :)
    integer(c_int32_t), intent(in), contiguous :: offsets(:), targets(:), boundary(:)
    type(dk_plan_options), intent(in) :: options
    type(dk_plan_sizes), intent(out) :: pools
    integer(c_int32_t), intent(in), contiguous, optional :: element_offsets(:), element_nodes(:)
    integer(c_int8_t), intent(in), contiguous, optional :: element_kinds(:)
    real(c_double), intent(in), target, contiguous, optional :: stiffness(:)
    integer(c_int32_t) :: s
    type(dk_plan_sizes) :: work
    real(c_double), allocatable :: wr(:)
    integer(c_int32_t), allocatable :: wi(:)
    integer(c_int8_t), allocatable :: wb(:)
    type(c_ptr) :: eo, en, ek, k
    integer(c_size_t) :: neo, nen, nek, nk
    integer(c_int32_t), allocatable, target :: b0(:), eo0(:), en0(:)
    integer(c_int8_t), allocatable, target :: ek0(:)
    allocate(b0(size(boundary)))
    b0 = boundary - 1
    call dkf_plan_elements(element_offsets, element_nodes, element_kinds, eo0, en0, ek0, eo, neo, &
                           en, nen, ek, nek)
    k = c_null_ptr
    nk = 0
    if (present(stiffness)) then
      k = c_loc(stiffness)
      nk = size(stiffness, kind=c_size_t)
    end if
    s = dk_plan_work_sizes(points, size(points, kind=c_size_t), offsets, &
                           size(offsets, kind=c_size_t), targets, size(targets, kind=c_size_t), &
                           b0, size(b0, kind=c_size_t), eo, neo, en, nen, ek, nek, k, nk, &
                           int(size(points, 1), c_int32_t), options, work)
    if (s /= DK_OK) return
    allocate(wr(max(work%reals, 1_c_size_t)), wi(max(work%indices, 1_c_size_t)), &
             wb(max(work%bytes, 1_c_size_t)))
    s = dk_plan_pool_sizes(points, size(points, kind=c_size_t), offsets, &
                           size(offsets, kind=c_size_t), targets, size(targets, kind=c_size_t), &
                           b0, size(b0, kind=c_size_t), eo, neo, en, nen, ek, nek, k, nk, &
                           int(size(points, 1), c_int32_t), options, wr, work%reals, wi, &
                           work%indices, wb, work%bytes, pools)
  end function

  !> dk_plan_init with Fortran arrays (arguments as dkf_plan_pool_sizes; the work buffers are
  !> allocated here): builds the plan in reals(:), indices(:), bytes(:) (at least the lengths
  !> dkf_plan_pool_sizes gave); info receives what the plan holds.
  function dkf_plan_init(points, offsets, targets, boundary, options, reals, indices, bytes, &
                         info, element_offsets, element_nodes, element_kinds, stiffness) result(s)
    use, intrinsic :: iso_c_binding, only: c_loc, c_null_ptr
    real(c_double), intent(in), contiguous :: points(:, :)
    integer(c_int32_t), intent(in), contiguous :: offsets(:), targets(:), boundary(:)
    type(dk_plan_options), intent(in) :: options
    real(c_double), intent(inout), contiguous :: reals(:)
    integer(c_int32_t), intent(inout), contiguous :: indices(:)
    integer(c_int8_t), intent(inout), contiguous :: bytes(:)
    type(dk_plan_info), intent(inout) :: info
    integer(c_int32_t), intent(in), contiguous, optional :: element_offsets(:), element_nodes(:)
    integer(c_int8_t), intent(in), contiguous, optional :: element_kinds(:)
    real(c_double), intent(in), target, contiguous, optional :: stiffness(:)
    integer(c_int32_t) :: s
    type(dk_plan_sizes) :: work
    real(c_double), allocatable :: wr(:)
    integer(c_int32_t), allocatable :: wi(:)
    integer(c_int8_t), allocatable :: wb(:)
    type(c_ptr) :: eo, en, ek, k
    integer(c_size_t) :: neo, nen, nek, nk
    integer(c_int32_t), allocatable, target :: b0(:), eo0(:), en0(:)
    integer(c_int8_t), allocatable, target :: ek0(:)
    allocate(b0(size(boundary)))
    b0 = boundary - 1
    call dkf_plan_elements(element_offsets, element_nodes, element_kinds, eo0, en0, ek0, eo, neo, &
                           en, nen, ek, nek)
    k = c_null_ptr
    nk = 0
    if (present(stiffness)) then
      k = c_loc(stiffness)
      nk = size(stiffness, kind=c_size_t)
    end if
    s = dk_plan_work_sizes(points, size(points, kind=c_size_t), offsets, &
                           size(offsets, kind=c_size_t), targets, size(targets, kind=c_size_t), &
                           b0, size(b0, kind=c_size_t), eo, neo, en, nen, ek, nek, k, nk, &
                           int(size(points, 1), c_int32_t), options, work)
    if (s /= DK_OK) return
    allocate(wr(max(work%reals, 1_c_size_t)), wi(max(work%indices, 1_c_size_t)), &
             wb(max(work%bytes, 1_c_size_t)))
    s = dk_plan_init(points, size(points, kind=c_size_t), offsets, size(offsets, kind=c_size_t), &
                     targets, size(targets, kind=c_size_t), b0, size(b0, kind=c_size_t), eo, &
                     neo, en, nen, ek, nek, k, nk, &
                     int(size(points, 1), c_int32_t), options, wr, work%reals, wi, work%indices, &
                     wb, work%bytes, reals, size(reals, kind=c_size_t), indices, &
                     size(indices, kind=c_size_t), bytes, size(bytes, kind=c_size_t), info)
  end function

  !> dk_plan_step with Fortran arrays: deformed(dim, size(boundary)) in, out(dim, n) out;
  !> start DK_PLAN_WARM (default) or DK_PLAN_COLD; rotations from the plan's elements unless
  !> rigid_rotation(4) or node_rotations(4, size(boundary)) is given; origin(dim) optional.
  function dkf_plan_step(reals, indices, bytes, deformed, out, report, start, rigid_rotation, &
                         node_rotations, origin) result(s)
    use, intrinsic :: iso_c_binding, only: c_loc, c_null_ptr
    real(c_double), intent(inout), contiguous :: reals(:)
    integer(c_int32_t), intent(inout), contiguous :: indices(:)
    integer(c_int8_t), intent(inout), contiguous :: bytes(:)
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
    s = dk_plan_step(reals, size(reals, kind=c_size_t), indices, size(indices, kind=c_size_t), &
                     bytes, size(bytes, kind=c_size_t), int(size(deformed, 1), c_int32_t), &
                     deformed, size(deformed, kind=c_size_t), source, rot, nrot, org, norg, st, &
                     out, size(out, kind=c_size_t), report)
  end function

  !> dk_plan_open with Fortran arrays (dim 2 or 3).
  function dkf_plan_open(reals, indices, bytes, dim, info) result(s)
    real(c_double), intent(inout), contiguous :: reals(:)
    integer(c_int32_t), intent(inout), contiguous :: indices(:)
    integer(c_int8_t), intent(inout), contiguous :: bytes(:)
    integer(c_int32_t), intent(in) :: dim
    type(dk_plan_info), intent(inout) :: info
    integer(c_int32_t) :: s
    s = dk_plan_open(reals, size(reals, kind=c_size_t), indices, size(indices, kind=c_size_t), &
                     bytes, size(bytes, kind=c_size_t), dim, info)
  end function

  !> The optional 1-based element arrays of the plan wrappers as 0-based copies (eo0, en0,
  !> ek0, declared target by the caller) and C pointers to them with their lengths.
  subroutine dkf_plan_elements(element_offsets, element_nodes, element_kinds, eo0, en0, ek0, eo, &
                               neo, en, nen, ek, nek)
    use, intrinsic :: iso_c_binding, only: c_loc, c_null_ptr
    integer(c_int32_t), intent(in), contiguous, optional :: element_offsets(:), element_nodes(:)
    integer(c_int8_t), intent(in), contiguous, optional :: element_kinds(:)
    integer(c_int32_t), allocatable, target, intent(inout) :: eo0(:), en0(:)
    integer(c_int8_t), allocatable, target, intent(inout) :: ek0(:)
    type(c_ptr), intent(out) :: eo, en, ek
    integer(c_size_t), intent(out) :: neo, nen, nek
    eo = c_null_ptr
    en = c_null_ptr
    ek = c_null_ptr
    neo = 0
    nen = 0
    nek = 0
    if (present(element_offsets)) then
      allocate(eo0(size(element_offsets)))
      eo0 = element_offsets - 1
      eo = c_loc(eo0)
      neo = size(eo0, kind=c_size_t)
    end if
    if (present(element_nodes)) then
      allocate(en0(size(element_nodes)))
      en0 = element_nodes - 1
      en = c_loc(en0)
      nen = size(en0, kind=c_size_t)
    end if
    if (present(element_kinds)) then
      allocate(ek0(size(element_kinds)))
      ek0 = element_kinds
      ek = c_loc(ek0)
      nek = size(ek0, kind=c_size_t)
    end if
  end subroutine

  !> dk_quality_cell_measures with Fortran arrays and 1-based cells (cell_offsets(ncells + 1),
  !> cell_nodes(:), cell_kinds(ncells), as dkf_graph_from_cells takes them): the signed area
  !> (2D) or volume (3D) of every cell of points(dim, n) into out(ncells).
  function dkf_quality_cell_measures(cell_offsets, cell_nodes, cell_kinds, points, out) result(s)
    integer(c_int32_t), intent(in), contiguous :: cell_offsets(:), cell_nodes(:)
    integer(c_int8_t), intent(in), contiguous :: cell_kinds(:)
    real(c_double), intent(in), contiguous :: points(:, :)
    real(c_double), intent(inout), contiguous :: out(:)
    integer(c_int32_t) :: s
    integer(c_int32_t), allocatable :: index_scratch(:)
    allocate(index_scratch(size(cell_offsets) + size(cell_nodes)))
    s = dk_quality_cell_measures(cell_offsets, size(cell_offsets, kind=c_size_t), cell_nodes, &
                                 size(cell_nodes, kind=c_size_t), cell_kinds, &
                                 size(cell_kinds, kind=c_size_t), 1_c_int32_t, index_scratch, &
                                 size(index_scratch, kind=c_size_t), points, &
                                 size(points, kind=c_size_t), int(size(points, 1), c_int32_t), &
                                 out, size(out, kind=c_size_t))
  end function

  !> dk_quality_min_corner_jacobians with Fortran arrays (cells as dkf_quality_cell_measures):
  !> the smallest corner Jacobian of every cell, divided by its edge lengths when scaled.
  function dkf_quality_min_corner_jacobians(cell_offsets, cell_nodes, cell_kinds, points, &
                                            scaled, out) result(s)
    integer(c_int32_t), intent(in), contiguous :: cell_offsets(:), cell_nodes(:)
    integer(c_int8_t), intent(in), contiguous :: cell_kinds(:)
    real(c_double), intent(in), contiguous :: points(:, :)
    logical, intent(in) :: scaled
    real(c_double), intent(inout), contiguous :: out(:)
    integer(c_int32_t) :: s
    integer(c_int32_t), allocatable :: index_scratch(:)
    allocate(index_scratch(size(cell_offsets) + size(cell_nodes)))
    s = dk_quality_min_corner_jacobians(cell_offsets, size(cell_offsets, kind=c_size_t), &
                                        cell_nodes, size(cell_nodes, kind=c_size_t), cell_kinds, &
                                        size(cell_kinds, kind=c_size_t), 1_c_int32_t, &
                                        index_scratch, size(index_scratch, kind=c_size_t), points, &
                                        size(points, kind=c_size_t), &
                                        int(size(points, 1), c_int32_t), &
                                        logical(scaled, c_bool), out, size(out, kind=c_size_t))
  end function

  !> dk_quality_compare with Fortran arrays: deformed(dim, n) against undeformed(dim, n) over
  !> the 1-based cells; with a wall (1-based wall_offsets, wall_nodes, wall_kinds and the CSR
  !> graph_offsets, graph_targets from dkf_graph_from_*, all five or none) also the wall-angle
  !> change (the scratch is allocated here). report receives the comparison; its cell and node
  !> indices are 1-based, or DK_NO_INDEX.
  function dkf_quality_compare(cell_offsets, cell_nodes, cell_kinds, undeformed, deformed, &
                               report, wall_offsets, wall_nodes, wall_kinds, graph_offsets, &
                               graph_targets) result(s)
    use, intrinsic :: iso_c_binding, only: c_loc, c_null_ptr
    integer(c_int32_t), intent(in), contiguous :: cell_offsets(:), cell_nodes(:)
    integer(c_int8_t), intent(in), contiguous :: cell_kinds(:)
    real(c_double), intent(in), contiguous :: undeformed(:, :), deformed(:, :)
    type(dk_quality_report), intent(inout) :: report
    integer(c_int32_t), intent(in), target, contiguous, optional :: wall_offsets(:), &
        wall_nodes(:), graph_offsets(:), graph_targets(:)
    integer(c_int8_t), intent(in), target, contiguous, optional :: wall_kinds(:)
    integer(c_int32_t) :: s
    real(c_double), allocatable :: scratch(:)
    integer(c_int32_t), allocatable :: index_scratch(:)
    integer(c_size_t) :: need
    type(c_ptr) :: wo, wn, wk, go, gt
    integer(c_size_t) :: nwo, nwn, nwk, ngo, ngt
    wo = c_null_ptr
    wn = c_null_ptr
    wk = c_null_ptr
    go = c_null_ptr
    gt = c_null_ptr
    nwo = 0
    nwn = 0
    nwk = 0
    ngo = 0
    ngt = 0
    need = 0
    if (present(wall_offsets) .and. present(wall_nodes) .and. present(wall_kinds) .and. &
        present(graph_offsets) .and. present(graph_targets)) then
      wo = c_loc(wall_offsets)
      wn = c_loc(wall_nodes)
      wk = c_loc(wall_kinds)
      go = c_loc(graph_offsets)
      gt = c_loc(graph_targets)
      nwo = size(wall_offsets, kind=c_size_t)
      nwn = size(wall_nodes, kind=c_size_t)
      nwk = size(wall_kinds, kind=c_size_t)
      ngo = size(graph_offsets, kind=c_size_t)
      ngt = size(graph_targets, kind=c_size_t)
      s = dk_quality_wall_angle_scratch_len(size(undeformed, 2, kind=c_size_t), &
                                            int(size(undeformed, 1), c_int32_t), need)
      if (s /= DK_OK) return
    else if (present(wall_offsets) .or. present(wall_nodes) .or. present(wall_kinds) .or. &
             present(graph_offsets) .or. present(graph_targets)) then
      s = DK_ERR_LENGTH_MISMATCH
      return
    end if
    allocate(scratch(max(need, 1_c_size_t)))
    allocate(index_scratch(size(cell_offsets) + size(cell_nodes) + nwo + nwn))
    s = dk_quality_compare(cell_offsets, size(cell_offsets, kind=c_size_t), cell_nodes, &
                           size(cell_nodes, kind=c_size_t), cell_kinds, &
                           size(cell_kinds, kind=c_size_t), 1_c_int32_t, index_scratch, &
                           size(index_scratch, kind=c_size_t), wo, nwo, wn, nwn, wk, &
                           nwk, go, ngo, gt, ngt, undeformed, size(undeformed, kind=c_size_t), &
                           deformed, size(deformed, kind=c_size_t), &
                           int(size(undeformed, 1), c_int32_t), scratch, need, report)
  end function

  ! <<< generated by `cargo xtask codegen`: the _f32 twins of the dkf_ wrappers above >>>
  !> Single-precision twin of dkf_fill_motion.
  !> Fills m for the dkf_deform_* wrappers: 1-based nodes(b) and deformed(dim, b); optional
  !> boundary elements (1-based offsets and positions in nodes, VTK kinds), rigid_rotation(4)
  !> or node_rotations(4, b) (else the rotations come from the shape), origin(dim) (else the
  !> default origin). The pointers stay valid while the actual arguments do.
  subroutine dkf_fill_motion_f32(m, nodes, deformed, element_offsets, element_nodes, &
                             element_kinds, rigid_rotation, node_rotations, origin)
    use, intrinsic :: iso_c_binding, only: c_loc
    type(dk_boundary_motion_f32), intent(inout) :: m
    integer(c_int32_t), intent(in), target, contiguous :: nodes(:)
    real(c_float), intent(in), target, contiguous :: deformed(:, :)
    integer(c_int32_t), intent(in), target, contiguous, optional :: element_offsets(:), &
                                                                     element_nodes(:)
    integer(c_int8_t), intent(in), target, contiguous, optional :: element_kinds(:)
    real(c_float), intent(in), optional :: rigid_rotation(4)
    real(c_float), intent(in), target, contiguous, optional :: node_rotations(:, :)
    real(c_float), intent(in), optional :: origin(:)
    integer(c_int32_t) :: s
    integer :: k
    s = dk_boundary_motion_default_f32(m)
    m%index_base = 1
    m%nodes = c_loc(nodes)
    m%nodes_len = size(nodes, kind=c_size_t)
    m%deformed = c_loc(deformed)
    m%deformed_len = size(deformed, kind=c_size_t)
    if (present(element_offsets) .and. present(element_nodes) .and. present(element_kinds)) then
      m%element_offsets = c_loc(element_offsets)
      m%element_offsets_len = size(element_offsets, kind=c_size_t)
      m%element_nodes = c_loc(element_nodes)
      m%element_nodes_len = size(element_nodes, kind=c_size_t)
      m%element_kinds = c_loc(element_kinds)
      m%element_kinds_len = size(element_kinds, kind=c_size_t)
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

  !> Single-precision twin of dkf_deform_idw.
  !> dk_deform_idw_f32 with Fortran arrays and 1-based node numbers: points(dim, n), nodes(b),
  !> deformed(dim, b); scratch(:) (dk_deform_idw_scratch_len), index_scratch(:) (at least
  !> size(nodes) + size(element_offsets) + size(element_nodes)), translations(dim, n) and
  !> rotations(4, n) (workspaces); out(dim, n). Optional arguments as dkf_fill_motion_f32, and
  !> origin_out(dim) for the origin used.
  function dkf_deform_idw_f32(points, nodes, deformed, exponent, scratch, index_scratch, &
                          translations, rotations, out, element_offsets, element_nodes, &
                          element_kinds, rigid_rotation, node_rotations, origin, origin_out) &
      result(s)
    real(c_float), intent(in), contiguous :: points(:, :)
    integer(c_int32_t), intent(in), target, contiguous :: nodes(:)
    real(c_float), intent(in), target, contiguous :: deformed(:, :)
    real(c_float), intent(in) :: exponent
    real(c_float), intent(inout), contiguous :: scratch(:), translations(:, :), &
                                                 rotations(:, :), out(:, :)
    integer(c_int32_t), intent(inout), contiguous :: index_scratch(:)
    integer(c_int32_t), intent(in), target, contiguous, optional :: element_offsets(:), &
                                                                     element_nodes(:)
    integer(c_int8_t), intent(in), target, contiguous, optional :: element_kinds(:)
    real(c_float), intent(in), optional :: rigid_rotation(4)
    real(c_float), intent(in), target, contiguous, optional :: node_rotations(:, :)
    real(c_float), intent(in), optional :: origin(:)
    real(c_float), intent(inout), contiguous, optional :: origin_out(:)
    integer(c_int32_t) :: s
    type(dk_boundary_motion_f32) :: m
    real(c_float) :: none(1)
    call dkf_fill_motion_f32(m, nodes, deformed, element_offsets, element_nodes, element_kinds, &
                         rigid_rotation, node_rotations, origin)
    if (present(origin_out)) then
      s = dk_deform_idw_f32(points, size(points, kind=c_size_t), int(size(points, 1), c_int32_t), &
                        m, exponent, scratch, size(scratch, kind=c_size_t), index_scratch, &
                        size(index_scratch, kind=c_size_t), translations, &
                        size(translations, kind=c_size_t), rotations, &
                        size(rotations, kind=c_size_t), out, size(out, kind=c_size_t), &
                        origin_out, size(origin_out, kind=c_size_t))
    else
      s = dk_deform_idw_f32(points, size(points, kind=c_size_t), int(size(points, 1), c_int32_t), &
                        m, exponent, scratch, size(scratch, kind=c_size_t), index_scratch, &
                        size(index_scratch, kind=c_size_t), translations, &
                        size(translations, kind=c_size_t), rotations, &
                        size(rotations, kind=c_size_t), out, size(out, kind=c_size_t), &
                        none, 0_c_size_t)
    end if
  end function

  !> Single-precision twin of dkf_deform_tfi.
  !> dk_deform_tfi_f32 with Fortran arrays: a dims(1) x dims(2) x dims(3) block (dims(3) = 1 in
  !> 2D), directions a sum of DK_DIRECTION_*; other arguments as dkf_deform_idw_f32 (scratch:
  !> dk_deform_tfi_scratch_len).
  function dkf_deform_tfi_f32(dims, directions, points, nodes, deformed, scratch, index_scratch, &
                          translations, rotations, out, element_offsets, element_nodes, &
                          element_kinds, rigid_rotation, node_rotations, origin, origin_out) &
      result(s)
    integer(c_size_t), intent(in) :: dims(3)
    integer(c_int32_t), intent(in) :: directions
    real(c_float), intent(in), contiguous :: points(:, :)
    integer(c_int32_t), intent(in), target, contiguous :: nodes(:)
    real(c_float), intent(in), target, contiguous :: deformed(:, :)
    real(c_float), intent(inout), contiguous :: scratch(:), translations(:, :), &
                                                 rotations(:, :), out(:, :)
    integer(c_int32_t), intent(inout), contiguous :: index_scratch(:)
    integer(c_int32_t), intent(in), target, contiguous, optional :: element_offsets(:), &
                                                                     element_nodes(:)
    integer(c_int8_t), intent(in), target, contiguous, optional :: element_kinds(:)
    real(c_float), intent(in), optional :: rigid_rotation(4)
    real(c_float), intent(in), target, contiguous, optional :: node_rotations(:, :)
    real(c_float), intent(in), optional :: origin(:)
    real(c_float), intent(inout), contiguous, optional :: origin_out(:)
    integer(c_int32_t) :: s
    type(dk_boundary_motion_f32) :: m
    real(c_float) :: none(1)
    call dkf_fill_motion_f32(m, nodes, deformed, element_offsets, element_nodes, element_kinds, &
                         rigid_rotation, node_rotations, origin)
    if (present(origin_out)) then
      s = dk_deform_tfi_f32(dims(1), dims(2), dims(3), directions, points, &
                        size(points, kind=c_size_t), int(size(points, 1), c_int32_t), m, &
                        scratch, size(scratch, kind=c_size_t), index_scratch, &
                        size(index_scratch, kind=c_size_t), translations, &
                        size(translations, kind=c_size_t), rotations, &
                        size(rotations, kind=c_size_t), out, size(out, kind=c_size_t), &
                        origin_out, size(origin_out, kind=c_size_t))
    else
      s = dk_deform_tfi_f32(dims(1), dims(2), dims(3), directions, points, &
                        size(points, kind=c_size_t), int(size(points, 1), c_int32_t), m, &
                        scratch, size(scratch, kind=c_size_t), index_scratch, &
                        size(index_scratch, kind=c_size_t), translations, &
                        size(translations, kind=c_size_t), rotations, &
                        size(rotations, kind=c_size_t), out, size(out, kind=c_size_t), &
                        none, 0_c_size_t)
    end if
  end function

  !> Single-precision twin of dkf_deform_spring.
  !> dk_deform_spring_f32 with Fortran arrays: the 0-based CSR graph offsets(n + 1), targets(:)
  !> from dkf_graph_from_*, stiffness(size(targets)), fixed(n) (nonzero = boundary node),
  !> options; values(:) (second length of dk_deform_spring_scratch_len); index_scratch(:) at
  !> least size(nodes) + size(element_offsets) + size(element_nodes) + n; report receives the
  !> solver report. Other arguments as dkf_deform_idw_f32.
  function dkf_deform_spring_f32(points, nodes, deformed, offsets, targets, stiffness, fixed, &
                             options, scratch, values, index_scratch, translations, rotations, &
                             out, report, element_offsets, element_nodes, element_kinds, &
                             rigid_rotation, node_rotations, origin, origin_out) result(s)
    real(c_float), intent(in), contiguous :: points(:, :)
    integer(c_int32_t), intent(in), target, contiguous :: nodes(:)
    real(c_float), intent(in), target, contiguous :: deformed(:, :)
    integer(c_int32_t), intent(in), contiguous :: offsets(:), targets(:)
    real(c_float), intent(in), contiguous :: stiffness(:)
    integer(c_int8_t), intent(in), contiguous :: fixed(:)
    type(dk_spring_solve_options), intent(in) :: options
    real(c_float), intent(inout), contiguous :: scratch(:), values(:), translations(:, :), &
                                                 rotations(:, :), out(:, :)
    integer(c_int32_t), intent(inout), contiguous :: index_scratch(:)
    type(dk_spring_solve_report), intent(inout) :: report
    integer(c_int32_t), intent(in), target, contiguous, optional :: element_offsets(:), &
                                                                     element_nodes(:)
    integer(c_int8_t), intent(in), target, contiguous, optional :: element_kinds(:)
    real(c_float), intent(in), optional :: rigid_rotation(4)
    real(c_float), intent(in), target, contiguous, optional :: node_rotations(:, :)
    real(c_float), intent(in), optional :: origin(:)
    real(c_float), intent(inout), contiguous, optional :: origin_out(:)
    integer(c_int32_t) :: s
    type(dk_boundary_motion_f32) :: m
    real(c_float) :: none(1)
    call dkf_fill_motion_f32(m, nodes, deformed, element_offsets, element_nodes, element_kinds, &
                         rigid_rotation, node_rotations, origin)
    if (present(origin_out)) then
      s = dk_deform_spring_f32(points, size(points, kind=c_size_t), &
                           int(size(points, 1), c_int32_t), m, offsets, &
                           size(offsets, kind=c_size_t), targets, size(targets, kind=c_size_t), &
                           stiffness, size(stiffness, kind=c_size_t), fixed, &
                           size(fixed, kind=c_size_t), options, scratch, &
                           size(scratch, kind=c_size_t), values, size(values, kind=c_size_t), &
                           index_scratch, size(index_scratch, kind=c_size_t), translations, &
                           size(translations, kind=c_size_t), rotations, &
                           size(rotations, kind=c_size_t), out, size(out, kind=c_size_t), &
                           origin_out, size(origin_out, kind=c_size_t), report)
    else
      s = dk_deform_spring_f32(points, size(points, kind=c_size_t), &
                           int(size(points, 1), c_int32_t), m, offsets, &
                           size(offsets, kind=c_size_t), targets, size(targets, kind=c_size_t), &
                           stiffness, size(stiffness, kind=c_size_t), fixed, &
                           size(fixed, kind=c_size_t), options, scratch, &
                           size(scratch, kind=c_size_t), values, size(values, kind=c_size_t), &
                           index_scratch, size(index_scratch, kind=c_size_t), translations, &
                           size(translations, kind=c_size_t), rotations, &
                           size(rotations, kind=c_size_t), out, size(out, kind=c_size_t), &
                           none, 0_c_size_t, report)
    end if
  end function

  !> Single-precision twin of dkf_plan_pool_sizes.
  !> dk_plan_work_sizes_f32 + dk_plan_pool_sizes_f32 with Fortran arrays: points(dim, n), the CSR
  !> graph offsets(n + 1), targets(:) from dkf_graph_from_*, the 1-based boundary(:) node
  !> list, options (from dk_plan_options_default_f32), optional boundary elements over
  !> 1..size(boundary) as 1-based element_offsets/element_nodes (as dkf_graph_from_cells takes
  !> cells) and element_kinds, and an optional stiffness(size(targets)) per directed edge (else
  !> Batina's with options%stiffness_exponent). The work buffers and 0-based copies of the node
  !> lists are allocated here and freed on return; pools receives the three pool lengths.
  function dkf_plan_pool_sizes_f32(points, offsets, targets, boundary, options, pools, &
                               element_offsets, element_nodes, element_kinds, stiffness) result(s)
    use, intrinsic :: iso_c_binding, only: c_loc, c_null_ptr
    real(c_float), intent(in), contiguous :: points(:, :)
    integer(c_int32_t), intent(in), contiguous :: offsets(:), targets(:), boundary(:)
    type(dk_plan_options), intent(in) :: options
    type(dk_plan_sizes), intent(out) :: pools
    integer(c_int32_t), intent(in), contiguous, optional :: element_offsets(:), element_nodes(:)
    integer(c_int8_t), intent(in), contiguous, optional :: element_kinds(:)
    real(c_float), intent(in), target, contiguous, optional :: stiffness(:)
    integer(c_int32_t) :: s
    type(dk_plan_sizes) :: work
    real(c_float), allocatable :: wr(:)
    integer(c_int32_t), allocatable :: wi(:)
    integer(c_int8_t), allocatable :: wb(:)
    type(c_ptr) :: eo, en, ek, k
    integer(c_size_t) :: neo, nen, nek, nk
    integer(c_int32_t), allocatable, target :: b0(:), eo0(:), en0(:)
    integer(c_int8_t), allocatable, target :: ek0(:)
    allocate(b0(size(boundary)))
    b0 = boundary - 1
    call dkf_plan_elements(element_offsets, element_nodes, element_kinds, eo0, en0, ek0, eo, neo, &
                           en, nen, ek, nek)
    k = c_null_ptr
    nk = 0
    if (present(stiffness)) then
      k = c_loc(stiffness)
      nk = size(stiffness, kind=c_size_t)
    end if
    s = dk_plan_work_sizes_f32(points, size(points, kind=c_size_t), offsets, &
                           size(offsets, kind=c_size_t), targets, size(targets, kind=c_size_t), &
                           b0, size(b0, kind=c_size_t), eo, neo, en, nen, ek, nek, k, nk, &
                           int(size(points, 1), c_int32_t), options, work)
    if (s /= DK_OK) return
    allocate(wr(max(work%reals, 1_c_size_t)), wi(max(work%indices, 1_c_size_t)), &
             wb(max(work%bytes, 1_c_size_t)))
    s = dk_plan_pool_sizes_f32(points, size(points, kind=c_size_t), offsets, &
                           size(offsets, kind=c_size_t), targets, size(targets, kind=c_size_t), &
                           b0, size(b0, kind=c_size_t), eo, neo, en, nen, ek, nek, k, nk, &
                           int(size(points, 1), c_int32_t), options, wr, work%reals, wi, &
                           work%indices, wb, work%bytes, pools)
  end function

  !> Single-precision twin of dkf_plan_init.
  !> dk_plan_init_f32 with Fortran arrays (arguments as dkf_plan_pool_sizes_f32; the work buffers are
  !> allocated here): builds the plan in reals(:), indices(:), bytes(:) (at least the lengths
  !> dkf_plan_pool_sizes_f32 gave); info receives what the plan holds.
  function dkf_plan_init_f32(points, offsets, targets, boundary, options, reals, indices, bytes, &
                         info, element_offsets, element_nodes, element_kinds, stiffness) result(s)
    use, intrinsic :: iso_c_binding, only: c_loc, c_null_ptr
    real(c_float), intent(in), contiguous :: points(:, :)
    integer(c_int32_t), intent(in), contiguous :: offsets(:), targets(:), boundary(:)
    type(dk_plan_options), intent(in) :: options
    real(c_float), intent(inout), contiguous :: reals(:)
    integer(c_int32_t), intent(inout), contiguous :: indices(:)
    integer(c_int8_t), intent(inout), contiguous :: bytes(:)
    type(dk_plan_info), intent(inout) :: info
    integer(c_int32_t), intent(in), contiguous, optional :: element_offsets(:), element_nodes(:)
    integer(c_int8_t), intent(in), contiguous, optional :: element_kinds(:)
    real(c_float), intent(in), target, contiguous, optional :: stiffness(:)
    integer(c_int32_t) :: s
    type(dk_plan_sizes) :: work
    real(c_float), allocatable :: wr(:)
    integer(c_int32_t), allocatable :: wi(:)
    integer(c_int8_t), allocatable :: wb(:)
    type(c_ptr) :: eo, en, ek, k
    integer(c_size_t) :: neo, nen, nek, nk
    integer(c_int32_t), allocatable, target :: b0(:), eo0(:), en0(:)
    integer(c_int8_t), allocatable, target :: ek0(:)
    allocate(b0(size(boundary)))
    b0 = boundary - 1
    call dkf_plan_elements(element_offsets, element_nodes, element_kinds, eo0, en0, ek0, eo, neo, &
                           en, nen, ek, nek)
    k = c_null_ptr
    nk = 0
    if (present(stiffness)) then
      k = c_loc(stiffness)
      nk = size(stiffness, kind=c_size_t)
    end if
    s = dk_plan_work_sizes_f32(points, size(points, kind=c_size_t), offsets, &
                           size(offsets, kind=c_size_t), targets, size(targets, kind=c_size_t), &
                           b0, size(b0, kind=c_size_t), eo, neo, en, nen, ek, nek, k, nk, &
                           int(size(points, 1), c_int32_t), options, work)
    if (s /= DK_OK) return
    allocate(wr(max(work%reals, 1_c_size_t)), wi(max(work%indices, 1_c_size_t)), &
             wb(max(work%bytes, 1_c_size_t)))
    s = dk_plan_init_f32(points, size(points, kind=c_size_t), offsets, size(offsets, kind=c_size_t), &
                     targets, size(targets, kind=c_size_t), b0, size(b0, kind=c_size_t), eo, &
                     neo, en, nen, ek, nek, k, nk, &
                     int(size(points, 1), c_int32_t), options, wr, work%reals, wi, work%indices, &
                     wb, work%bytes, reals, size(reals, kind=c_size_t), indices, &
                     size(indices, kind=c_size_t), bytes, size(bytes, kind=c_size_t), info)
  end function

  !> Single-precision twin of dkf_plan_step.
  !> dk_plan_step_f32 with Fortran arrays: deformed(dim, size(boundary)) in, out(dim, n) out;
  !> start DK_PLAN_WARM (default) or DK_PLAN_COLD; rotations from the plan's elements unless
  !> rigid_rotation(4) or node_rotations(4, size(boundary)) is given; origin(dim) optional.
  function dkf_plan_step_f32(reals, indices, bytes, deformed, out, report, start, rigid_rotation, &
                         node_rotations, origin) result(s)
    use, intrinsic :: iso_c_binding, only: c_loc, c_null_ptr
    real(c_float), intent(inout), contiguous :: reals(:)
    integer(c_int32_t), intent(inout), contiguous :: indices(:)
    integer(c_int8_t), intent(inout), contiguous :: bytes(:)
    real(c_float), intent(in), contiguous :: deformed(:, :)
    real(c_float), intent(inout), contiguous :: out(:, :)
    type(dk_plan_step_report), intent(inout) :: report
    integer(c_int32_t), intent(in), optional :: start
    real(c_float), intent(in), target, optional :: rigid_rotation(4)
    real(c_float), intent(in), target, contiguous, optional :: node_rotations(:, :)
    real(c_float), intent(in), target, contiguous, optional :: origin(:)
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
    s = dk_plan_step_f32(reals, size(reals, kind=c_size_t), indices, size(indices, kind=c_size_t), &
                     bytes, size(bytes, kind=c_size_t), int(size(deformed, 1), c_int32_t), &
                     deformed, size(deformed, kind=c_size_t), source, rot, nrot, org, norg, st, &
                     out, size(out, kind=c_size_t), report)
  end function

  !> Single-precision twin of dkf_plan_open.
  !> dk_plan_open_f32 with Fortran arrays (dim 2 or 3).
  function dkf_plan_open_f32(reals, indices, bytes, dim, info) result(s)
    real(c_float), intent(inout), contiguous :: reals(:)
    integer(c_int32_t), intent(inout), contiguous :: indices(:)
    integer(c_int8_t), intent(inout), contiguous :: bytes(:)
    integer(c_int32_t), intent(in) :: dim
    type(dk_plan_info), intent(inout) :: info
    integer(c_int32_t) :: s
    s = dk_plan_open_f32(reals, size(reals, kind=c_size_t), indices, size(indices, kind=c_size_t), &
                     bytes, size(bytes, kind=c_size_t), dim, info)
  end function

  !> Single-precision twin of dkf_quality_cell_measures.
  !> dk_quality_cell_measures_f32 with Fortran arrays and 1-based cells (cell_offsets(ncells + 1),
  !> cell_nodes(:), cell_kinds(ncells), as dkf_graph_from_cells takes them): the signed area
  !> (2D) or volume (3D) of every cell of points(dim, n) into out(ncells).
  function dkf_quality_cell_measures_f32(cell_offsets, cell_nodes, cell_kinds, points, out) result(s)
    integer(c_int32_t), intent(in), contiguous :: cell_offsets(:), cell_nodes(:)
    integer(c_int8_t), intent(in), contiguous :: cell_kinds(:)
    real(c_float), intent(in), contiguous :: points(:, :)
    real(c_float), intent(inout), contiguous :: out(:)
    integer(c_int32_t) :: s
    integer(c_int32_t), allocatable :: index_scratch(:)
    allocate(index_scratch(size(cell_offsets) + size(cell_nodes)))
    s = dk_quality_cell_measures_f32(cell_offsets, size(cell_offsets, kind=c_size_t), cell_nodes, &
                                 size(cell_nodes, kind=c_size_t), cell_kinds, &
                                 size(cell_kinds, kind=c_size_t), 1_c_int32_t, index_scratch, &
                                 size(index_scratch, kind=c_size_t), points, &
                                 size(points, kind=c_size_t), int(size(points, 1), c_int32_t), &
                                 out, size(out, kind=c_size_t))
  end function

  !> Single-precision twin of dkf_quality_min_corner_jacobians.
  !> dk_quality_min_corner_jacobians_f32 with Fortran arrays (cells as dkf_quality_cell_measures_f32):
  !> the smallest corner Jacobian of every cell, divided by its edge lengths when scaled.
  function dkf_quality_min_corner_jacobians_f32(cell_offsets, cell_nodes, cell_kinds, points, &
                                            scaled, out) result(s)
    integer(c_int32_t), intent(in), contiguous :: cell_offsets(:), cell_nodes(:)
    integer(c_int8_t), intent(in), contiguous :: cell_kinds(:)
    real(c_float), intent(in), contiguous :: points(:, :)
    logical, intent(in) :: scaled
    real(c_float), intent(inout), contiguous :: out(:)
    integer(c_int32_t) :: s
    integer(c_int32_t), allocatable :: index_scratch(:)
    allocate(index_scratch(size(cell_offsets) + size(cell_nodes)))
    s = dk_quality_min_corner_jacobians_f32(cell_offsets, size(cell_offsets, kind=c_size_t), &
                                        cell_nodes, size(cell_nodes, kind=c_size_t), cell_kinds, &
                                        size(cell_kinds, kind=c_size_t), 1_c_int32_t, &
                                        index_scratch, size(index_scratch, kind=c_size_t), points, &
                                        size(points, kind=c_size_t), &
                                        int(size(points, 1), c_int32_t), &
                                        logical(scaled, c_bool), out, size(out, kind=c_size_t))
  end function

  !> Single-precision twin of dkf_quality_compare.
  !> dk_quality_compare_f32 with Fortran arrays: deformed(dim, n) against undeformed(dim, n) over
  !> the 1-based cells; with a wall (1-based wall_offsets, wall_nodes, wall_kinds and the CSR
  !> graph_offsets, graph_targets from dkf_graph_from_*, all five or none) also the wall-angle
  !> change (the scratch is allocated here). report receives the comparison; its cell and node
  !> indices are 1-based, or DK_NO_INDEX.
  function dkf_quality_compare_f32(cell_offsets, cell_nodes, cell_kinds, undeformed, deformed, &
                               report, wall_offsets, wall_nodes, wall_kinds, graph_offsets, &
                               graph_targets) result(s)
    use, intrinsic :: iso_c_binding, only: c_loc, c_null_ptr
    integer(c_int32_t), intent(in), contiguous :: cell_offsets(:), cell_nodes(:)
    integer(c_int8_t), intent(in), contiguous :: cell_kinds(:)
    real(c_float), intent(in), contiguous :: undeformed(:, :), deformed(:, :)
    type(dk_quality_report), intent(inout) :: report
    integer(c_int32_t), intent(in), target, contiguous, optional :: wall_offsets(:), &
        wall_nodes(:), graph_offsets(:), graph_targets(:)
    integer(c_int8_t), intent(in), target, contiguous, optional :: wall_kinds(:)
    integer(c_int32_t) :: s
    real(c_float), allocatable :: scratch(:)
    integer(c_int32_t), allocatable :: index_scratch(:)
    integer(c_size_t) :: need
    type(c_ptr) :: wo, wn, wk, go, gt
    integer(c_size_t) :: nwo, nwn, nwk, ngo, ngt
    wo = c_null_ptr
    wn = c_null_ptr
    wk = c_null_ptr
    go = c_null_ptr
    gt = c_null_ptr
    nwo = 0
    nwn = 0
    nwk = 0
    ngo = 0
    ngt = 0
    need = 0
    if (present(wall_offsets) .and. present(wall_nodes) .and. present(wall_kinds) .and. &
        present(graph_offsets) .and. present(graph_targets)) then
      wo = c_loc(wall_offsets)
      wn = c_loc(wall_nodes)
      wk = c_loc(wall_kinds)
      go = c_loc(graph_offsets)
      gt = c_loc(graph_targets)
      nwo = size(wall_offsets, kind=c_size_t)
      nwn = size(wall_nodes, kind=c_size_t)
      nwk = size(wall_kinds, kind=c_size_t)
      ngo = size(graph_offsets, kind=c_size_t)
      ngt = size(graph_targets, kind=c_size_t)
      s = dk_quality_wall_angle_scratch_len(size(undeformed, 2, kind=c_size_t), &
                                            int(size(undeformed, 1), c_int32_t), need)
      if (s /= DK_OK) return
    else if (present(wall_offsets) .or. present(wall_nodes) .or. present(wall_kinds) .or. &
             present(graph_offsets) .or. present(graph_targets)) then
      s = DK_ERR_LENGTH_MISMATCH
      return
    end if
    allocate(scratch(max(need, 1_c_size_t)))
    allocate(index_scratch(size(cell_offsets) + size(cell_nodes) + nwo + nwn))
    s = dk_quality_compare_f32(cell_offsets, size(cell_offsets, kind=c_size_t), cell_nodes, &
                           size(cell_nodes, kind=c_size_t), cell_kinds, &
                           size(cell_kinds, kind=c_size_t), 1_c_int32_t, index_scratch, &
                           size(index_scratch, kind=c_size_t), wo, nwo, wn, nwn, wk, &
                           nwk, go, ngo, gt, ngt, undeformed, size(undeformed, kind=c_size_t), &
                           deformed, size(deformed, kind=c_size_t), &
                           int(size(undeformed, 1), c_int32_t), scratch, need, report)
  end function
  ! <<< end generated twins >>>
  ! <<< end wrappers: deformation >>>

end module deform_kernel
