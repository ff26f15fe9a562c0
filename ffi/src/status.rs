//! `dk_status`: the return code of every `dk_*` function, and its message.

use deform_kernel::Error;
use deform_kernel_ffi_export::export;

/// Return code of every `dk_*` function. `DK_OK` (0) is success; every other value names the
/// kind of failure, and on failure no output was written.
#[repr(i32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[allow(non_camel_case_types)]
pub enum dk_status {
    /// Success.
    DK_OK = 0,
    /// A required pointer argument was NULL (or misaligned for its element type).
    DK_ERR_NULL_POINTER = 1,
    /// Two arguments that must describe the same number of items disagree.
    DK_ERR_LENGTH_MISMATCH = 2,
    /// An output or scratch buffer is too small (see the `*_len` queries).
    DK_ERR_BUFFER_TOO_SMALL = 3,
    /// An index is out of range (after subtracting `index_base`).
    DK_ERR_INDEX_OUT_OF_RANGE = 4,
    /// A count does not fit the kernel's 32-bit indices.
    DK_ERR_TOO_LARGE = 5,
    /// CSR offsets are not a valid offsets array.
    DK_ERR_BAD_OFFSETS = 6,
    /// A graph has an edge from a node to itself.
    DK_ERR_SELF_LOOP = 7,
    /// A graph that must be symmetric is not.
    DK_ERR_NOT_SYMMETRIC = 8,
    /// A cell kind code is not one of 3, 5, 9, 10, 12, 13, 14 (VTK numbering).
    DK_ERR_UNKNOWN_CELL_KIND = 9,
    /// A cell's node count does not match its kind.
    DK_ERR_WRONG_NODE_COUNT = 10,
    /// A cell lists the same node twice.
    DK_ERR_REPEATED_NODE = 11,
    /// An input value is NaN or infinite.
    DK_ERR_NON_FINITE = 12,
    /// A scalar parameter is outside its valid range.
    DK_ERR_INVALID_PARAMETER = 13,
    /// A vector or quaternion that must be normalised has zero length.
    DK_ERR_ZERO_LENGTH = 14,
    /// An edge joins two coincident nodes.
    DK_ERR_ZERO_LENGTH_EDGE = 15,
    /// A node's local system is singular.
    DK_ERR_SINGULAR_NODE = 16,
    /// The global system is singular or indefinite.
    DK_ERR_SINGULAR_SYSTEM = 17,
    /// A free node is not connected to any fixed node.
    DK_ERR_UNANCHORED = 18,
    /// A grid line folded (arclength not increasing).
    DK_ERR_FOLDED_LINE = 19,
    /// Structured block dimensions are invalid.
    DK_ERR_BAD_DIMENSIONS = 20,
    /// `index_base` is neither 0 nor 1.
    DK_ERR_BAD_INDEX_BASE = 21,
    /// A boundary node belongs to no boundary element, so its normal or rotation is undefined.
    DK_ERR_ISOLATED_NODE = 22,
    /// A node list names the same node twice.
    DK_ERR_DUPLICATE_NODE = 23,
    /// A value that must be strictly positive (stiffness, weight) is zero or negative.
    DK_ERR_NON_POSITIVE = 24,
    /// A cell's kind does not fit the point dimension of the call.
    DK_ERR_CELL_DIMENSION = 25,
    /// An intermediate result exceeded the floating-point range even after rescaling.
    DK_ERR_OVERFLOW = 26,
    /// A direction that must be a unit vector (a sliding node's normal or tangent) is not.
    DK_ERR_NOT_UNIT = 27,
    /// A node set that must be planar (a symmetry plane) deviates from its fitted plane.
    DK_ERR_NOT_PLANAR = 28,
    /// Plan pools do not hold a valid plan (no plan, another scalar type or dimension, or an
    /// immutable part overwritten: checksum mismatch).
    DK_ERR_BAD_PLAN = 29,
    /// A line end that must be free to slide coincides with another grid point (a seam, an
    /// axis or an interface).
    DK_ERR_SHARED_FREE_END = 30,
    /// A distributed call's partitions are inconsistent (ghost or send/receive lists,
    /// duplicate global ids, counts, rows across processes), or another process found a fault
    /// of its own: every process of the call returns an error.
    DK_ERR_BAD_PARTITION = 31,
    /// A caller's exchange callback returned nonzero on some process of a distributed call:
    /// every process returns this.
    DK_ERR_EXCHANGE = 32,
    /// An error this version of the header does not know (a newer kernel).
    DK_ERR_OTHER = 99,
}

impl From<Error> for dk_status {
    fn from(e: Error) -> Self {
        match e {
            Error::LengthMismatch { .. } => dk_status::DK_ERR_LENGTH_MISMATCH,
            Error::BufferTooSmall { .. } => dk_status::DK_ERR_BUFFER_TOO_SMALL,
            Error::IndexOutOfRange { .. } => dk_status::DK_ERR_INDEX_OUT_OF_RANGE,
            Error::TooLarge { .. } => dk_status::DK_ERR_TOO_LARGE,
            Error::BadOffsets { .. } => dk_status::DK_ERR_BAD_OFFSETS,
            Error::SelfLoop { .. } => dk_status::DK_ERR_SELF_LOOP,
            Error::NotSymmetric { .. } => dk_status::DK_ERR_NOT_SYMMETRIC,
            Error::UnknownCellKind { .. } => dk_status::DK_ERR_UNKNOWN_CELL_KIND,
            Error::WrongNodeCount { .. } => dk_status::DK_ERR_WRONG_NODE_COUNT,
            Error::RepeatedNode { .. } => dk_status::DK_ERR_REPEATED_NODE,
            Error::NonFinite { .. } => dk_status::DK_ERR_NON_FINITE,
            Error::InvalidParameter { .. } => dk_status::DK_ERR_INVALID_PARAMETER,
            Error::ZeroLength { .. } => dk_status::DK_ERR_ZERO_LENGTH,
            Error::ZeroLengthEdge { .. } => dk_status::DK_ERR_ZERO_LENGTH_EDGE,
            Error::SingularNode { .. } => dk_status::DK_ERR_SINGULAR_NODE,
            Error::SingularSystem { .. } => dk_status::DK_ERR_SINGULAR_SYSTEM,
            Error::Unanchored { .. } => dk_status::DK_ERR_UNANCHORED,
            Error::FoldedLine { .. } => dk_status::DK_ERR_FOLDED_LINE,
            Error::BadDimensions { .. } => dk_status::DK_ERR_BAD_DIMENSIONS,
            Error::IsolatedNode { .. } => dk_status::DK_ERR_ISOLATED_NODE,
            Error::DuplicateNode { .. } => dk_status::DK_ERR_DUPLICATE_NODE,
            Error::NonPositive { .. } => dk_status::DK_ERR_NON_POSITIVE,
            Error::CellDimension { .. } => dk_status::DK_ERR_CELL_DIMENSION,
            Error::Overflow { .. } => dk_status::DK_ERR_OVERFLOW,
            Error::NotUnit { .. } => dk_status::DK_ERR_NOT_UNIT,
            Error::NotPlanar { .. } => dk_status::DK_ERR_NOT_PLANAR,
            Error::BadPlan { .. } => dk_status::DK_ERR_BAD_PLAN,
            Error::SharedFreeEnd { .. } => dk_status::DK_ERR_SHARED_FREE_END,
            Error::BadPartition { .. } => dk_status::DK_ERR_BAD_PARTITION,
            _ => dk_status::DK_ERR_OTHER,
        }
    }
}

/// A static, NUL-terminated English description of `status`. Never NULL; unknown values give
/// "unknown status".
#[export]
pub(crate) fn dk_status_str(status: i32) -> &'static core::ffi::CStr {
    match status {
        0 => c"success",
        1 => c"a required pointer argument is NULL or misaligned",
        2 => c"two arguments that must have the same length disagree",
        3 => c"an output or scratch buffer is too small",
        4 => c"an index is out of range",
        5 => c"a count does not fit 32-bit indices",
        6 => c"CSR offsets must start at 0, never decrease and end at the targets length",
        7 => c"a graph has an edge from a node to itself",
        8 => c"the graph is not symmetric",
        9 => c"unknown cell kind (VTK codes 3, 5, 9, 10, 12, 13, 14 are supported)",
        10 => c"a cell's node count does not match its kind",
        11 => c"a cell lists the same node twice",
        12 => c"an input value is NaN or infinite",
        13 => c"a parameter is outside its valid range",
        14 => c"a vector or quaternion has zero length",
        15 => c"an edge joins two coincident nodes",
        16 => c"a node's local system is singular (colinear or coplanar edges)",
        17 => c"the global system is singular or indefinite",
        18 => c"a free node is not connected to any fixed node",
        19 => c"a grid line folded (arclength not increasing)",
        20 => c"structured block dimensions are invalid",
        21 => c"index_base must be 0 or 1",
        22 => c"a boundary node belongs to no boundary element",
        23 => c"a node list names the same node twice",
        24 => c"a value that must be positive (stiffness, weight) is zero or negative",
        25 => c"a cell's kind does not fit the point dimension",
        26 => c"an intermediate result exceeded the floating-point range",
        27 => c"a direction that must be a unit vector is not",
        28 => c"a node set that must be planar deviates from its fitted plane",
        29 => c"the plan pools do not hold a valid plan (none, another type, or overwritten)",
        30 => c"a free line end coincides with another grid point (seam, axis or interface)",
        31 => c"the processes' partitions are inconsistent, or another process found a fault",
        32 => c"an exchange callback failed on some process",
        99 => c"an error unknown to this header version",
        _ => c"unknown status",
    }
}
