//! Mixed-element cell lists: the [`Cells`] view and the [`CellKind`] table.
//!
//! Cells are stored like a CSR array: cell `c` has kind `kinds[c]` (a VTK type code) and
//! nodes `nodes[offsets[c]..offsets[c + 1]]`, in VTK node order.

use crate::check;
use crate::error::{Error, Result};

/// The element kinds the kernel understands, with their VTK type codes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[repr(u8)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum CellKind {
    /// 2-node line segment (VTK 3).
    Line = 3,
    /// 3-node triangle (VTK 5).
    Triangle = 5,
    /// 4-node quadrilateral (VTK 9).
    Quad = 9,
    /// 4-node tetrahedron (VTK 10).
    Tetra = 10,
    /// 8-node hexahedron (VTK 12).
    Hexahedron = 12,
    /// 6-node prism / wedge (VTK 13).
    Prism = 13,
    /// 5-node pyramid (VTK 14).
    Pyramid = 14,
}

const LINE_EDGES: [[u8; 2]; 1] = [[0, 1]];
const TRI_EDGES: [[u8; 2]; 3] = [[0, 1], [1, 2], [2, 0]];
const QUAD_EDGES: [[u8; 2]; 4] = [[0, 1], [1, 2], [2, 3], [3, 0]];
const TET_EDGES: [[u8; 2]; 6] = [[0, 1], [1, 2], [2, 0], [0, 3], [1, 3], [2, 3]];
const HEX_EDGES: [[u8; 2]; 12] = [
    [0, 1],
    [1, 2],
    [2, 3],
    [3, 0],
    [4, 5],
    [5, 6],
    [6, 7],
    [7, 4],
    [0, 4],
    [1, 5],
    [2, 6],
    [3, 7],
];
const PRISM_EDGES: [[u8; 2]; 9] = [
    [0, 1],
    [1, 2],
    [2, 0],
    [3, 4],
    [4, 5],
    [5, 3],
    [0, 3],
    [1, 4],
    [2, 5],
];
const PYRAMID_EDGES: [[u8; 2]; 8] = [
    [0, 1],
    [1, 2],
    [2, 3],
    [3, 0],
    [0, 4],
    [1, 4],
    [2, 4],
    [3, 4],
];

const QUAD_DIAGONALS: [[u8; 2]; 2] = [[0, 2], [1, 3]];
const HEX_DIAGONALS: [[u8; 2]; 12] = [
    [0, 2],
    [1, 3], // bottom 0123
    [4, 6],
    [5, 7], // top 4567
    [0, 5],
    [1, 4], // 0154
    [1, 6],
    [2, 5], // 1265
    [2, 7],
    [3, 6], // 2376
    [3, 4],
    [0, 7], // 3047
];
const PRISM_DIAGONALS: [[u8; 2]; 6] = [[0, 4], [1, 3], [1, 5], [2, 4], [2, 3], [0, 5]];

impl CellKind {
    /// Every kind, in VTK code order.
    pub const ALL: [CellKind; 7] = [
        CellKind::Line,
        CellKind::Triangle,
        CellKind::Quad,
        CellKind::Tetra,
        CellKind::Hexahedron,
        CellKind::Prism,
        CellKind::Pyramid,
    ];

    /// The kind for a VTK type code, if the kernel knows it.
    #[inline]
    pub fn from_vtk(code: u8) -> Option<CellKind> {
        Some(match code {
            3 => CellKind::Line,
            5 => CellKind::Triangle,
            9 => CellKind::Quad,
            10 => CellKind::Tetra,
            12 => CellKind::Hexahedron,
            13 => CellKind::Prism,
            14 => CellKind::Pyramid,
            _ => return None,
        })
    }

    /// The VTK type code.
    #[inline]
    pub fn vtk_code(self) -> u8 {
        self as u8
    }

    /// Number of nodes.
    #[inline]
    pub fn node_count(self) -> usize {
        match self {
            CellKind::Line => 2,
            CellKind::Triangle => 3,
            CellKind::Quad | CellKind::Tetra => 4,
            CellKind::Pyramid => 5,
            CellKind::Prism => 6,
            CellKind::Hexahedron => 8,
        }
    }

    /// Topological dimension (1, 2 or 3).
    #[inline]
    pub fn dimension(self) -> usize {
        match self {
            CellKind::Line => 1,
            CellKind::Triangle | CellKind::Quad => 2,
            _ => 3,
        }
    }

    /// The cell's edges as pairs of local node numbers (VTK order).
    #[inline]
    pub fn edges(self) -> &'static [[u8; 2]] {
        match self {
            CellKind::Line => &LINE_EDGES,
            CellKind::Triangle => &TRI_EDGES,
            CellKind::Quad => &QUAD_EDGES,
            CellKind::Tetra => &TET_EDGES,
            CellKind::Hexahedron => &HEX_EDGES,
            CellKind::Prism => &PRISM_EDGES,
            CellKind::Pyramid => &PYRAMID_EDGES,
        }
    }

    /// Diagonals of the cell's quadrilateral faces (local node pairs); empty for kinds
    /// without quadrilateral faces. Adding them stiffens quad/hex trusses that would otherwise
    /// be mechanisms under axial springs.
    #[inline]
    pub fn face_diagonals(self) -> &'static [[u8; 2]] {
        match self {
            CellKind::Quad | CellKind::Pyramid => &QUAD_DIAGONALS,
            CellKind::Hexahedron => &HEX_DIAGONALS,
            CellKind::Prism => &PRISM_DIAGONALS,
            _ => &[],
        }
    }
}

/// A validated mixed-element cell list over caller-owned arrays.
///
/// Guarantees after construction: `offsets.len() == kinds.len() + 1`, offsets start at 0,
/// never decrease and end at `nodes.len()`; every kind is known and has the right node count;
/// every node index is `< node_count`; no cell lists a node twice.
#[derive(Clone, Copy, Debug)]
pub struct Cells<'a> {
    node_count: usize,
    offsets: &'a [u32],
    nodes: &'a [u32],
    kinds: &'a [u8],
}

impl<'a> Cells<'a> {
    /// Wraps arrays that [`Cells::new`] accepted before (a prepared plan's copies): no check.
    #[inline]
    pub(crate) fn trusted(
        node_count: usize,
        offsets: &'a [u32],
        nodes: &'a [u32],
        kinds: &'a [u8],
    ) -> Self {
        Cells {
            node_count,
            offsets,
            nodes,
            kinds,
        }
    }

    /// Validates and wraps the arrays. `node_count` is the number of mesh points.
    ///
    /// # Errors
    /// `node_count` or `nodes.len()` above `u32::MAX` ([`Error::TooLarge`]); offsets that do
    /// not start at 0, decrease or do not end at `nodes.len()` ([`Error::BadOffsets`]); a kind
    /// code the kernel does not know ([`Error::UnknownCellKind`]); a cell with the wrong number
    /// of nodes for its kind ([`Error::WrongNodeCount`]); a node index `>= node_count`
    /// ([`Error::IndexOutOfRange`]); a node repeated within a cell ([`Error::RepeatedNode`]).
    pub fn new(
        node_count: usize,
        offsets: &'a [u32],
        nodes: &'a [u32],
        kinds: &'a [u8],
    ) -> Result<Self> {
        if u32::try_from(node_count).is_err() {
            return Err(Error::TooLarge {
                arg: "node_count",
                value: node_count,
            });
        }
        if u32::try_from(nodes.len()).is_err() {
            return Err(Error::TooLarge {
                arg: "nodes",
                value: nodes.len(),
            });
        }
        check::len("offsets", offsets.len(), kinds.len().wrapping_add(1))?;
        if offsets.first() != Some(&0) {
            return Err(Error::BadOffsets {
                arg: "offsets",
                position: 0,
            });
        }
        for (c, (w, &code)) in offsets.windows(2).zip(kinds).enumerate() {
            let [a, b] = *w else { continue };
            if b < a || b as usize > nodes.len() {
                return Err(Error::BadOffsets {
                    arg: "offsets",
                    position: c + 1,
                });
            }
            let Some(kind) = CellKind::from_vtk(code) else {
                return Err(Error::UnknownCellKind {
                    cell: c,
                    kind: code,
                });
            };
            let cell = nodes.get(a as usize..b as usize).unwrap_or(&[]);
            if cell.len() != kind.node_count() {
                return Err(Error::WrongNodeCount {
                    cell: c,
                    kind: code,
                    expected: kind.node_count(),
                    actual: cell.len(),
                });
            }
            for (k, &v) in cell.iter().enumerate() {
                if v as usize >= node_count {
                    return Err(Error::IndexOutOfRange {
                        arg: "nodes",
                        position: a as usize + k,
                        index: v as usize,
                        bound: node_count,
                    });
                }
                if cell.iter().take(k).any(|&u| u == v) {
                    return Err(Error::RepeatedNode {
                        cell: c,
                        node: v as usize,
                    });
                }
            }
        }
        if offsets.last().map(|&l| l as usize) != Some(nodes.len()) {
            return Err(Error::BadOffsets {
                arg: "offsets",
                position: kinds.len(),
            });
        }
        Ok(Cells {
            node_count,
            offsets,
            nodes,
            kinds,
        })
    }

    /// Number of mesh points the cells index into.
    #[inline]
    pub fn node_count(&self) -> usize {
        self.node_count
    }

    /// Number of cells.
    #[inline]
    pub fn len(&self) -> usize {
        self.kinds.len()
    }

    /// `true` when there are no cells.
    #[inline]
    pub fn is_empty(&self) -> bool {
        self.kinds.is_empty()
    }

    /// The offsets array.
    #[inline]
    pub fn offsets(&self) -> &'a [u32] {
        self.offsets
    }

    /// The concatenated node lists.
    #[inline]
    pub fn nodes(&self) -> &'a [u32] {
        self.nodes
    }

    /// The VTK kind codes.
    #[inline]
    pub fn kinds(&self) -> &'a [u8] {
        self.kinds
    }

    /// Cell `c`'s kind and nodes (`None` when `c` is out of range).
    #[inline]
    pub fn cell(&self, c: usize) -> Option<(CellKind, &'a [u32])> {
        let kind = CellKind::from_vtk(*self.kinds.get(c)?)?;
        let a = *self.offsets.get(c)? as usize;
        let b = *self.offsets.get(c + 1)? as usize;
        Some((kind, self.nodes.get(a..b)?))
    }

    /// Iterates over `(kind, nodes)` of every cell in order.
    #[inline]
    pub fn iter(&self) -> impl Iterator<Item = (CellKind, &'a [u32])> + 'a {
        let nodes = self.nodes;
        self.offsets
            .windows(2)
            .zip(self.kinds)
            .filter_map(move |(w, &code)| {
                let kind = CellKind::from_vtk(code)?;
                let [a, b] = *w else { return None };
                Some((kind, nodes.get(a as usize..b as usize)?))
            })
    }
}
