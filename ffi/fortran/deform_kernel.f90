! deform-kernel Fortran 2008 bindings (iso_c_binding).
!
! Every function returns an integer(c_int32_t) status: DK_OK (0) is success, anything else is a
! dk_status code (see deform_kernel.h); dk_status_message() describes it. Outputs are written
! only on success. Mesh node indices may be passed 1-based as they are (index_base = 1).
! Functions ending in _f32 take real(c_float) arrays. The dkf_* wrappers take assumed-shape
! contiguous arrays and pass their sizes for you.
module deform_kernel
  use, intrinsic :: iso_c_binding, only: c_int32_t, c_int8_t, c_size_t, c_double, c_float, &
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
  integer(c_int32_t), parameter, public :: DK_ERR_OTHER = 99

  ! VTK cell kind codes.
  integer(c_int8_t), parameter, public :: DK_LINE = 3_c_int8_t, DK_TRIANGLE = 5_c_int8_t, &
       DK_QUAD = 9_c_int8_t, DK_TETRA = 10_c_int8_t, DK_HEXAHEDRON = 12_c_int8_t, &
       DK_PRISM = 13_c_int8_t, DK_PYRAMID = 14_c_int8_t

  public :: dk_status_str, dk_status_message
  public :: dk_quat_mul, dk_quat_normalize, dk_quat_inverse, dk_quat_from_axis_angle, &
            dk_quat_to_axis_angle, dk_quat_rotation_arc, dk_quat_rotate_points, dk_quat_slerp, &
            dk_quat_nlerp, dk_quat_average
  public :: dk_quat_mul_f32, dk_quat_normalize_f32, dk_quat_inverse_f32, &
            dk_quat_from_axis_angle_f32, dk_quat_to_axis_angle_f32, dk_quat_rotation_arc_f32, &
            dk_quat_rotate_points_f32, dk_quat_slerp_f32, dk_quat_nlerp_f32, dk_quat_average_f32
  public :: dk_graph_from_edges_len, dk_graph_from_edges, dk_cells_check, &
            dk_graph_from_cells_len, dk_graph_from_cells, dk_graph_check
  public :: dkf_rotate_points, dkf_graph_from_edges, dkf_graph_from_cells_len, &
            dkf_graph_from_cells

  ! <<< public: springs, quality, taubin >>>
  ! <<< end public: springs, quality, taubin >>>
  ! <<< public: deformation >>>
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

    ! ---- quaternions, double precision: q = (w, x, y, z) ----
    function dk_quat_mul(a, b, out) bind(C, name="dk_quat_mul") result(s)
      import :: c_int32_t, c_double
      real(c_double), intent(in) :: a(4), b(4)
      real(c_double), intent(inout) :: out(4)
      integer(c_int32_t) :: s
    end function
    function dk_quat_normalize(q, out) bind(C, name="dk_quat_normalize") result(s)
      import :: c_int32_t, c_double
      real(c_double), intent(in) :: q(4)
      real(c_double), intent(inout) :: out(4)
      integer(c_int32_t) :: s
    end function
    function dk_quat_inverse(q, out) bind(C, name="dk_quat_inverse") result(s)
      import :: c_int32_t, c_double
      real(c_double), intent(in) :: q(4)
      real(c_double), intent(inout) :: out(4)
      integer(c_int32_t) :: s
    end function
    function dk_quat_from_axis_angle(axis, angle, out) bind(C, name="dk_quat_from_axis_angle") &
        result(s)
      import :: c_int32_t, c_double
      real(c_double), intent(in) :: axis(3)
      real(c_double), value :: angle
      real(c_double), intent(inout) :: out(4)
      integer(c_int32_t) :: s
    end function
    function dk_quat_to_axis_angle(q, axis_out, angle_out) bind(C, name="dk_quat_to_axis_angle") &
        result(s)
      import :: c_int32_t, c_double
      real(c_double), intent(in) :: q(4)
      real(c_double), intent(inout) :: axis_out(3), angle_out
      integer(c_int32_t) :: s
    end function
    function dk_quat_rotation_arc(from, to, out) bind(C, name="dk_quat_rotation_arc") result(s)
      import :: c_int32_t, c_double
      real(c_double), intent(in) :: from(3), to(3)
      real(c_double), intent(inout) :: out(4)
      integer(c_int32_t) :: s
    end function
    function dk_quat_rotate_points(q, points, points_len, out, out_len) &
        bind(C, name="dk_quat_rotate_points") result(s)
      import :: c_int32_t, c_double, c_size_t
      real(c_double), intent(in) :: q(4), points(*)
      integer(c_size_t), value :: points_len, out_len
      real(c_double), intent(inout) :: out(*)
      integer(c_int32_t) :: s
    end function
    function dk_quat_slerp(a, b, t, out) bind(C, name="dk_quat_slerp") result(s)
      import :: c_int32_t, c_double
      real(c_double), intent(in) :: a(4), b(4)
      real(c_double), value :: t
      real(c_double), intent(inout) :: out(4)
      integer(c_int32_t) :: s
    end function
    function dk_quat_nlerp(a, b, t, out) bind(C, name="dk_quat_nlerp") result(s)
      import :: c_int32_t, c_double
      real(c_double), intent(in) :: a(4), b(4)
      real(c_double), value :: t
      real(c_double), intent(inout) :: out(4)
      integer(c_int32_t) :: s
    end function
    function dk_quat_average(quats, quats_len, weights, weights_len, out) &
        bind(C, name="dk_quat_average") result(s)
      import :: c_int32_t, c_double, c_size_t
      real(c_double), intent(in) :: quats(*), weights(*)
      integer(c_size_t), value :: quats_len, weights_len
      real(c_double), intent(inout) :: out(4)
      integer(c_int32_t) :: s
    end function

    ! ---- quaternions, single precision ----
    function dk_quat_mul_f32(a, b, out) bind(C, name="dk_quat_mul_f32") result(s)
      import :: c_int32_t, c_float
      real(c_float), intent(in) :: a(4), b(4)
      real(c_float), intent(inout) :: out(4)
      integer(c_int32_t) :: s
    end function
    function dk_quat_normalize_f32(q, out) bind(C, name="dk_quat_normalize_f32") result(s)
      import :: c_int32_t, c_float
      real(c_float), intent(in) :: q(4)
      real(c_float), intent(inout) :: out(4)
      integer(c_int32_t) :: s
    end function
    function dk_quat_inverse_f32(q, out) bind(C, name="dk_quat_inverse_f32") result(s)
      import :: c_int32_t, c_float
      real(c_float), intent(in) :: q(4)
      real(c_float), intent(inout) :: out(4)
      integer(c_int32_t) :: s
    end function
    function dk_quat_from_axis_angle_f32(axis, angle, out) &
        bind(C, name="dk_quat_from_axis_angle_f32") result(s)
      import :: c_int32_t, c_float
      real(c_float), intent(in) :: axis(3)
      real(c_float), value :: angle
      real(c_float), intent(inout) :: out(4)
      integer(c_int32_t) :: s
    end function
    function dk_quat_to_axis_angle_f32(q, axis_out, angle_out) &
        bind(C, name="dk_quat_to_axis_angle_f32") result(s)
      import :: c_int32_t, c_float
      real(c_float), intent(in) :: q(4)
      real(c_float), intent(inout) :: axis_out(3), angle_out
      integer(c_int32_t) :: s
    end function
    function dk_quat_rotation_arc_f32(from, to, out) bind(C, name="dk_quat_rotation_arc_f32") &
        result(s)
      import :: c_int32_t, c_float
      real(c_float), intent(in) :: from(3), to(3)
      real(c_float), intent(inout) :: out(4)
      integer(c_int32_t) :: s
    end function
    function dk_quat_rotate_points_f32(q, points, points_len, out, out_len) &
        bind(C, name="dk_quat_rotate_points_f32") result(s)
      import :: c_int32_t, c_float, c_size_t
      real(c_float), intent(in) :: q(4), points(*)
      integer(c_size_t), value :: points_len, out_len
      real(c_float), intent(inout) :: out(*)
      integer(c_int32_t) :: s
    end function
    function dk_quat_slerp_f32(a, b, t, out) bind(C, name="dk_quat_slerp_f32") result(s)
      import :: c_int32_t, c_float
      real(c_float), intent(in) :: a(4), b(4)
      real(c_float), value :: t
      real(c_float), intent(inout) :: out(4)
      integer(c_int32_t) :: s
    end function
    function dk_quat_nlerp_f32(a, b, t, out) bind(C, name="dk_quat_nlerp_f32") result(s)
      import :: c_int32_t, c_float
      real(c_float), intent(in) :: a(4), b(4)
      real(c_float), value :: t
      real(c_float), intent(inout) :: out(4)
      integer(c_int32_t) :: s
    end function
    function dk_quat_average_f32(quats, quats_len, weights, weights_len, out) &
        bind(C, name="dk_quat_average_f32") result(s)
      import :: c_int32_t, c_float, c_size_t
      real(c_float), intent(in) :: quats(*), weights(*)
      integer(c_size_t), value :: quats_len, weights_len
      real(c_float), intent(inout) :: out(4)
      integer(c_int32_t) :: s
    end function

    ! ---- graphs and cells (node indices in index_base; CSR output always 0-based) ----
    function dk_graph_from_edges_len(edges_len, len_out) bind(C, name="dk_graph_from_edges_len") &
        result(s)
      import :: c_int32_t, c_size_t
      integer(c_size_t), value :: edges_len
      integer(c_size_t), intent(inout) :: len_out
      integer(c_int32_t) :: s
    end function
    function dk_graph_from_edges(node_count, edges, edges_len, index_base, offsets, offsets_len, &
        targets, targets_len, used_out) bind(C, name="dk_graph_from_edges") result(s)
      import :: c_int32_t, c_size_t
      integer(c_size_t), value :: node_count, edges_len, offsets_len, targets_len
      integer(c_int32_t), intent(in) :: edges(*)
      integer(c_int32_t), value :: index_base
      integer(c_int32_t), intent(inout) :: offsets(*), targets(*)
      integer(c_size_t), intent(inout) :: used_out
      integer(c_int32_t) :: s
    end function
    function dk_cells_check(node_count, cell_offsets, cell_offsets_len, cell_nodes, &
        cell_nodes_len, cell_kinds, cell_kinds_len, index_base) bind(C, name="dk_cells_check") &
        result(s)
      import :: c_int32_t, c_int8_t, c_size_t
      integer(c_size_t), value :: node_count, cell_offsets_len, cell_nodes_len, cell_kinds_len
      integer(c_int32_t), intent(in) :: cell_offsets(*), cell_nodes(*)
      integer(c_int8_t), intent(in) :: cell_kinds(*)
      integer(c_int32_t), value :: index_base
      integer(c_int32_t) :: s
    end function
    function dk_graph_from_cells_len(node_count, cell_offsets, cell_offsets_len, cell_nodes, &
        cell_nodes_len, cell_kinds, cell_kinds_len, index_base, face_diagonals, len_out) &
        bind(C, name="dk_graph_from_cells_len") result(s)
      import :: c_int32_t, c_int8_t, c_size_t, c_bool
      integer(c_size_t), value :: node_count, cell_offsets_len, cell_nodes_len, cell_kinds_len
      integer(c_int32_t), intent(in) :: cell_offsets(*), cell_nodes(*)
      integer(c_int8_t), intent(in) :: cell_kinds(*)
      integer(c_int32_t), value :: index_base
      logical(c_bool), value :: face_diagonals
      integer(c_size_t), intent(inout) :: len_out
      integer(c_int32_t) :: s
    end function
    function dk_graph_from_cells(node_count, cell_offsets, cell_offsets_len, cell_nodes, &
        cell_nodes_len, cell_kinds, cell_kinds_len, index_base, face_diagonals, offsets, &
        offsets_len, targets, targets_len, used_out) bind(C, name="dk_graph_from_cells") result(s)
      import :: c_int32_t, c_int8_t, c_size_t, c_bool
      integer(c_size_t), value :: node_count, cell_offsets_len, cell_nodes_len, cell_kinds_len
      integer(c_int32_t), intent(in) :: cell_offsets(*), cell_nodes(*)
      integer(c_int8_t), intent(in) :: cell_kinds(*)
      integer(c_int32_t), value :: index_base
      logical(c_bool), value :: face_diagonals
      integer(c_size_t), value :: offsets_len, targets_len
      integer(c_int32_t), intent(inout) :: offsets(*), targets(*)
      integer(c_size_t), intent(inout) :: used_out
      integer(c_int32_t) :: s
    end function
    function dk_graph_check(offsets, offsets_len, targets, targets_len, require_symmetric) &
        bind(C, name="dk_graph_check") result(s)
      import :: c_int32_t, c_size_t, c_bool
      integer(c_int32_t), intent(in) :: offsets(*), targets(*)
      integer(c_size_t), value :: offsets_len, targets_len
      logical(c_bool), value :: require_symmetric
      integer(c_int32_t) :: s
    end function
  ! <<< interfaces: springs, quality, taubin >>>
  ! <<< end interfaces: springs, quality, taubin >>>
  ! <<< interfaces: deformation >>>
  ! <<< end interfaces: deformation >>>
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
    s = dk_graph_from_edges(node_count, edges, int(size(edges), c_size_t), 1_c_int32_t, &
                            offsets, int(size(offsets), c_size_t), targets, &
                            int(size(targets), c_size_t), used)
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
    s = dk_graph_from_cells_len(node_count, cell_offsets, int(size(cell_offsets), c_size_t), &
                                cell_nodes, int(size(cell_nodes), c_size_t), cell_kinds, &
                                int(size(cell_kinds), c_size_t), 1_c_int32_t, &
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
    s = dk_graph_from_cells(node_count, cell_offsets, int(size(cell_offsets), c_size_t), &
                            cell_nodes, int(size(cell_nodes), c_size_t), cell_kinds, &
                            int(size(cell_kinds), c_size_t), 1_c_int32_t, &
                            logical(face_diagonals, c_bool), offsets, &
                            int(size(offsets), c_size_t), targets, int(size(targets), c_size_t), &
                            used)
  end function

  ! <<< wrappers: springs, quality, taubin >>>
  ! <<< end wrappers: springs, quality, taubin >>>
  ! <<< wrappers: deformation >>>
  ! <<< end wrappers: deformation >>>

end module deform_kernel
