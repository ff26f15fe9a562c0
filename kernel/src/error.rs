//! The kernel's one error type.
//!
//! Every fallible routine validates all of its inputs before writing any output, so an `Err`
//! always means "nothing was changed". Each variant names the offending argument (by its Rust
//! parameter name) and, where there is one, the offending position or value.

use core::fmt;

/// Everything that can go wrong in the kernel.
#[non_exhaustive]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Error {
    /// Two arguments that must describe the same number of items disagree.
    LengthMismatch {
        /// The argument whose length is wrong.
        arg: &'static str,
        /// The length it must have.
        expected: usize,
        /// The length it has.
        actual: usize,
    },
    /// A caller-provided output or scratch buffer is too small (see the `*_len` queries).
    BufferTooSmall {
        /// The buffer.
        arg: &'static str,
        /// The length it needs at least.
        needed: usize,
        /// The length it has.
        actual: usize,
    },
    /// An index is outside its valid range.
    IndexOutOfRange {
        /// The argument holding the index.
        arg: &'static str,
        /// Position of the index within that argument.
        position: usize,
        /// The index found.
        index: usize,
        /// The exclusive upper bound it must respect.
        bound: usize,
    },
    /// A count does not fit the kernel's `u32` index type.
    TooLarge {
        /// The argument.
        arg: &'static str,
        /// Its size.
        value: usize,
    },
    /// CSR offsets are not a valid offsets array (must start at 0, never decrease and end at
    /// the length of the targets array).
    BadOffsets {
        /// The offsets argument.
        arg: &'static str,
        /// Position of the first bad entry.
        position: usize,
    },
    /// A graph has an edge from a node to itself.
    SelfLoop {
        /// The node.
        node: usize,
    },
    /// Buffers given as a prepared plan ([`Plan::open`](crate::plan::Plan::open)) do not hold
    /// one: wrong magic, version, scalar type, dimension or sizes, inconsistent sections, or a
    /// checksum mismatch of the parts that never change (a corrupted or foreign buffer).
    BadPlan {
        /// What is wrong.
        reason: &'static str,
    },
    /// A graph that must be symmetric has an edge `from → to` without `to → from`.
    NotSymmetric {
        /// Source of the unmatched edge.
        from: usize,
        /// Target of the unmatched edge.
        to: usize,
    },
    /// A cell has a kind code the kernel does not know.
    UnknownCellKind {
        /// The cell.
        cell: usize,
        /// Its kind code (VTK numbering).
        kind: u8,
    },
    /// A cell's node count does not match its kind.
    WrongNodeCount {
        /// The cell.
        cell: usize,
        /// Its kind code (VTK numbering).
        kind: u8,
        /// The node count the kind has.
        expected: usize,
        /// The node count given.
        actual: usize,
    },
    /// A cell lists the same node twice.
    RepeatedNode {
        /// The cell.
        cell: usize,
        /// The repeated node.
        node: usize,
    },
    /// A value is NaN or infinite.
    NonFinite {
        /// The argument.
        arg: &'static str,
        /// Position of the first non-finite item.
        position: usize,
    },
    /// A scalar parameter is outside its valid range.
    InvalidParameter {
        /// The parameter.
        arg: &'static str,
        /// What it must satisfy.
        reason: &'static str,
    },
    /// A quaternion or vector that must be normalised has zero (or subnormal) length.
    ZeroLength {
        /// The argument.
        arg: &'static str,
        /// Position of the item (0 for a single value).
        position: usize,
    },
    /// An edge joins two nodes at the same position, so a length-based weight is undefined.
    ZeroLengthEdge {
        /// One end of the edge.
        from: usize,
        /// The other end.
        to: usize,
    },
    /// A node's local system (2×2 or 3×3) is singular: its edges are colinear or coplanar.
    SingularNode {
        /// The node.
        node: usize,
    },
    /// The global system is singular or not positive definite (for example a truss of quads
    /// without diagonals is a mechanism).
    SingularSystem {
        /// The iteration at which the breakdown was detected.
        iteration: usize,
    },
    /// A free node is not connected (through free nodes) to any fixed node, so its value is
    /// undetermined.
    Unanchored {
        /// The first such node.
        node: usize,
    },
    /// A grid line's arclength stopped increasing strictly (the grid folded).
    FoldedLine {
        /// Index of the line's first point.
        line: usize,
        /// The iteration at which the fold appeared (0 = in the input).
        iteration: usize,
    },
    /// A line end that must be free to slide coincides with another grid point's end (an
    /// O-grid seam, a wake cut, a collapsed axis, a block interface): freeing it would open
    /// what is closed.
    SharedFreeEnd {
        /// The free end point (linear index).
        point: usize,
        /// The grid point it coincides with.
        other: usize,
    },
    /// A structured block's dimensions are invalid (zero, or a product that overflows).
    BadDimensions {
        /// The dimensions argument.
        arg: &'static str,
    },
    /// A boundary node belongs to no boundary element (or all of its element edges are
    /// degenerate), so its normal or rotation is undetermined.
    IsolatedNode {
        /// The node (index into the boundary point list).
        node: usize,
    },
    /// A node list names the same node twice.
    DuplicateNode {
        /// The argument holding the list.
        arg: &'static str,
        /// Position of the second occurrence.
        position: usize,
        /// The repeated node.
        node: usize,
    },
    /// A value that must be strictly positive (a spring stiffness, a weight) is zero or
    /// negative.
    NonPositive {
        /// The argument.
        arg: &'static str,
        /// Position of the first offending item.
        position: usize,
    },
    /// A cell's kind does not fit the point dimension (a routine for `D = 2` got a 3D cell,
    /// or a 2D routine got a line).
    CellDimension {
        /// The cell (or boundary element).
        cell: usize,
        /// Its kind code (VTK numbering).
        kind: u8,
        /// The point dimension `D` of the call.
        dimension: usize,
    },
    /// An intermediate quantity exceeded the floating-point range even after the kernel's
    /// power-of-two rescaling (for example stiffness and values whose products span more than
    /// the exponent range): no result is returned rather than a wrong one.
    Overflow {
        /// The argument whose scale caused it.
        arg: &'static str,
    },
    /// A direction that must be a unit vector (a sliding node's plane normal or line tangent)
    /// is not one within the tolerance ([`crate::spring::constraints::unit_tolerance`]).
    NotUnit {
        /// The argument.
        arg: &'static str,
        /// Position of the item.
        position: usize,
    },
    /// A node set that must lie on a plane (a line in 2D) deviates from its least-squares fit
    /// by more than the tolerance.
    NotPlanar {
        /// The argument.
        arg: &'static str,
        /// Position (in the argument) of the node farthest from the fitted plane.
        position: usize,
    },
    /// A process's partition ([`crate::partition`]) is inconsistent, in itself or with the
    /// other processes' (found by the one reduction every process joins, so every process
    /// returns an error together).
    BadPartition {
        /// What is wrong.
        fault: PartitionFault,
        /// The local node, neighbour or list entry concerned (0 when the fault is global).
        position: usize,
    },
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            Error::LengthMismatch { arg, expected, actual } => {
                write!(f, "`{arg}` has length {actual}, expected {expected}")
            }
            Error::BufferTooSmall { arg, needed, actual } => {
                write!(f, "buffer `{arg}` has length {actual}, needs at least {needed}")
            }
            Error::IndexOutOfRange { arg, position, index, bound } => write!(
                f,
                "`{arg}[{position}]` = {index} is out of range (must be < {bound})"
            ),
            Error::TooLarge { arg, value } => {
                write!(f, "`{arg}` has size {value}, which does not fit a u32 index")
            }
            Error::BadOffsets { arg, position } => write!(
                f,
                "`{arg}[{position}]` breaks the CSR offsets rule (start at 0, non-decreasing, end at the targets length)"
            ),
            Error::SelfLoop { node } => write!(f, "node {node} has an edge to itself"),
            Error::NotSymmetric { from, to } => {
                write!(f, "edge {from} -> {to} has no reverse edge {to} -> {from}")
            }
            Error::UnknownCellKind { cell, kind } => {
                write!(f, "cell {cell} has unknown kind code {kind}")
            }
            Error::WrongNodeCount { cell, kind, expected, actual } => write!(
                f,
                "cell {cell} (kind {kind}) has {actual} nodes, expected {expected}"
            ),
            Error::RepeatedNode { cell, node } => {
                write!(f, "cell {cell} lists node {node} more than once")
            }
            Error::NonFinite { arg, position } => {
                write!(f, "`{arg}` has a NaN or infinite value at position {position}")
            }
            Error::InvalidParameter { arg, reason } => write!(f, "`{arg}` {reason}"),
            Error::ZeroLength { arg, position } => {
                write!(f, "`{arg}` item {position} has zero length and cannot be normalised")
            }
            Error::ZeroLengthEdge { from, to } => {
                write!(f, "edge {from} -> {to} has zero length")
            }
            Error::SingularNode { node } => write!(
                f,
                "the local system of node {node} is singular (its edges are colinear or coplanar)"
            ),
            Error::SingularSystem { iteration } => write!(
                f,
                "the global system is singular or indefinite (breakdown at iteration {iteration})"
            ),
            Error::Unanchored { node } => write!(
                f,
                "free node {node} is not connected to any fixed node"
            ),
            Error::FoldedLine { line, iteration } => write!(
                f,
                "the grid line starting at point {line} folded (arclength not increasing) at iteration {iteration}"
            ),
            Error::SharedFreeEnd { point, other } => write!(
                f,
                "the free line end at point {point} coincides with grid point {other} (a seam, axis or interface): keep that end fixed"
            ),
            Error::BadDimensions { arg } => {
                write!(f, "`{arg}` has a zero dimension or too many points")
            }
            Error::IsolatedNode { node } => write!(
                f,
                "boundary node {node} has no usable boundary element, so its normal or rotation is undetermined"
            ),
            Error::DuplicateNode { arg, position, node } => {
                write!(f, "`{arg}[{position}]` repeats node {node}")
            }
            Error::NonPositive { arg, position } => {
                write!(f, "`{arg}` has a zero or negative value at position {position}")
            }
            Error::CellDimension { cell, kind, dimension } => write!(
                f,
                "cell {cell} (kind {kind}) is not a valid cell for {dimension}D points"
            ),
            Error::Overflow { arg } => write!(
                f,
                "a computation on `{arg}` exceeded the floating-point range"
            ),
            Error::NotUnit { arg, position } => {
                write!(f, "`{arg}` item {position} is not a unit vector")
            }
            Error::BadPlan { reason } => write!(f, "the buffers are not a valid plan: {reason}"),
            Error::NotPlanar { arg, position } => write!(
                f,
                "the nodes of `{arg}` are not planar: item {position} is farther from the fitted plane than the tolerance"
            ),
            Error::BadPartition { fault, position } => {
                write!(f, "bad partition at {position}: {}", fault.describe())
            }
        }
    }
}

impl core::error::Error for Error {}

#[cfg(feature = "defmt")]
impl defmt::Format for Error {
    fn format(&self, f: defmt::Formatter) {
        match *self {
            Error::LengthMismatch {
                arg,
                expected,
                actual,
            } => {
                defmt::write!(f, "LengthMismatch({=str}: {} != {})", arg, actual, expected)
            }
            Error::BufferTooSmall {
                arg,
                needed,
                actual,
            } => {
                defmt::write!(f, "BufferTooSmall({=str}: {} < {})", arg, actual, needed)
            }
            Error::IndexOutOfRange {
                arg,
                position,
                index,
                bound,
            } => defmt::write!(
                f,
                "IndexOutOfRange({=str}[{}] = {} >= {})",
                arg,
                position,
                index,
                bound
            ),
            Error::TooLarge { arg, value } => defmt::write!(f, "TooLarge({=str}: {})", arg, value),
            Error::BadOffsets { arg, position } => {
                defmt::write!(f, "BadOffsets({=str}[{}])", arg, position)
            }
            Error::SelfLoop { node } => defmt::write!(f, "SelfLoop({})", node),
            Error::NotSymmetric { from, to } => {
                defmt::write!(f, "NotSymmetric({} -> {})", from, to)
            }
            Error::UnknownCellKind { cell, kind } => {
                defmt::write!(f, "UnknownCellKind(cell {}: {})", cell, kind)
            }
            Error::WrongNodeCount {
                cell,
                kind,
                expected,
                actual,
            } => defmt::write!(
                f,
                "WrongNodeCount(cell {} kind {}: {} != {})",
                cell,
                kind,
                actual,
                expected
            ),
            Error::RepeatedNode { cell, node } => {
                defmt::write!(f, "RepeatedNode(cell {}: {})", cell, node)
            }
            Error::NonFinite { arg, position } => {
                defmt::write!(f, "NonFinite({=str}[{}])", arg, position)
            }
            Error::InvalidParameter { arg, reason } => {
                defmt::write!(f, "InvalidParameter({=str}: {=str})", arg, reason)
            }
            Error::ZeroLength { arg, position } => {
                defmt::write!(f, "ZeroLength({=str}[{}])", arg, position)
            }
            Error::ZeroLengthEdge { from, to } => {
                defmt::write!(f, "ZeroLengthEdge({} -> {})", from, to)
            }
            Error::SingularNode { node } => defmt::write!(f, "SingularNode({})", node),
            Error::SingularSystem { iteration } => {
                defmt::write!(f, "SingularSystem(iteration {})", iteration)
            }
            Error::Unanchored { node } => defmt::write!(f, "Unanchored({})", node),
            Error::FoldedLine { line, iteration } => {
                defmt::write!(f, "FoldedLine(line {} iteration {})", line, iteration)
            }
            Error::SharedFreeEnd { point, other } => {
                defmt::write!(f, "SharedFreeEnd({} = {})", point, other)
            }
            Error::BadDimensions { arg } => defmt::write!(f, "BadDimensions({=str})", arg),
            Error::IsolatedNode { node } => defmt::write!(f, "IsolatedNode({})", node),
            Error::DuplicateNode {
                arg,
                position,
                node,
            } => defmt::write!(f, "DuplicateNode({=str}[{}] = {})", arg, position, node),
            Error::NonPositive { arg, position } => {
                defmt::write!(f, "NonPositive({=str}[{}])", arg, position)
            }
            Error::CellDimension {
                cell,
                kind,
                dimension,
            } => defmt::write!(
                f,
                "CellDimension(cell {} kind {}: {}D)",
                cell,
                kind,
                dimension
            ),
            Error::Overflow { arg } => defmt::write!(f, "Overflow({=str})", arg),
            Error::NotUnit { arg, position } => {
                defmt::write!(f, "NotUnit({=str}[{}])", arg, position)
            }
            Error::BadPlan { reason } => defmt::write!(f, "BadPlan({=str})", reason),
            Error::NotPlanar { arg, position } => {
                defmt::write!(f, "NotPlanar({=str}[{}])", arg, position)
            }
            Error::BadPartition { fault, position } => {
                defmt::write!(f, "BadPartition({=str} at {})", fault.describe(), position)
            }
        }
    }
}

/// What [`Error::BadPartition`] found wrong with a process's partition.
#[non_exhaustive]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PartitionFault {
    /// The process owns no node (every process must own at least one).
    NoOwnedNodes,
    /// The owned count exceeds the local node count.
    OwnedBeyondLocal,
    /// A global id is not below the global node count.
    GlobalIdRange,
    /// Two local nodes have the same global id (`position`: the later one).
    DuplicateGlobalId,
    /// A neighbour rank is this process, not below the process count, or listed twice.
    NeighbourRank,
    /// A send list names a node this process does not own.
    SendNotOwned,
    /// A receive list names a node that is not a ghost (owned, or past the local nodes).
    ReceiveNotGhost,
    /// A ghost is received twice (from one neighbour or two).
    GhostReceivedTwice,
    /// A ghost is in no receive list: no owner sends it.
    GhostNotReceived,
    /// The owned counts of all processes do not add up to the global node count.
    OwnedCount,
    /// The owned global ids of all processes are not each id once (checksums of the ids and
    /// their squares).
    OwnedIds,
    /// The send and receive lists of the processes do not match (a neighbour that does not
    /// list this process back, a count, or a global id at some list position).
    Pattern,
    /// The owned rows disagree between processes: an edge seen from one side only (a missing
    /// cell) or with another stiffness or fixed flag (a ghost's coordinates or mask differ
    /// from its owner's).
    Rows,
    /// The boundary of a partitioned quaternion deformation does not match between processes:
    /// the boundary or element counts differ, or a boundary position, element or global id
    /// is given by no process or twice (`position`: the boundary position, or `B +` the
    /// element).
    Boundary,
    /// Another process found a fault in its own partition (this one found none).
    OtherProcess,
}

impl PartitionFault {
    /// One line of English.
    pub const fn describe(self) -> &'static str {
        match self {
            PartitionFault::NoOwnedNodes => "the process owns no node",
            PartitionFault::OwnedBeyondLocal => "more owned nodes than local nodes",
            PartitionFault::GlobalIdRange => "a global id is not below the global node count",
            PartitionFault::DuplicateGlobalId => "two local nodes have the same global id",
            PartitionFault::NeighbourRank => {
                "a neighbour rank is this process, out of range or listed twice"
            }
            PartitionFault::SendNotOwned => "a send list names a node that is not owned",
            PartitionFault::ReceiveNotGhost => "a receive list names a node that is not a ghost",
            PartitionFault::GhostReceivedTwice => "a ghost is received twice",
            PartitionFault::GhostNotReceived => "a ghost is in no receive list",
            PartitionFault::OwnedCount => "the owned counts do not add up to the global node count",
            PartitionFault::OwnedIds => "the owned global ids are not each id exactly once",
            PartitionFault::Pattern => "send and receive lists do not match between processes",
            PartitionFault::Rows => "the owned rows do not match between processes",
            PartitionFault::Boundary => "the boundary lists do not match between processes",
            PartitionFault::OtherProcess => "another process rejected its partition",
        }
    }
}

/// Shorthand for `Result<T, Error>`.
pub type Result<T> = core::result::Result<T, Error>;
