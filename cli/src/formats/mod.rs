//! Mesh and grid file formats: SU2 native ASCII (one or several zones), Plot3D whole grids,
//! CGNS (`--features cgns`), VTK XML output.
//!
//! Readers take the whole file as bytes and never panic, whatever the bytes: every problem is a
//! [`FormatError`] naming the line (text) or byte offset (binary) and what was expected.
//! Writers take any [`std::io::Write`].

pub mod base64;
#[cfg(feature = "cgns")]
pub mod cgns;
pub mod displacements;
pub mod error;
mod float_exp;
pub(crate) mod line;
pub mod listdirected;
pub mod motions;
pub mod plot3d;
pub mod su2;
pub mod su2_config;
pub mod su2_ffd;
pub mod su2_zones;
pub mod vtk;

pub use error::{FormatError, FormatErrorKind, Location};

use deform_kernel::CellKind;

/// A mixed-element cell list in the kernel's layout: cell `c` has VTK type code `kinds[c]` and
/// nodes `nodes[offsets[c]..offsets[c + 1]]` (0-based point indices).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct CellList {
    /// `len() + 1` offsets into `nodes`, starting at 0.
    pub offsets: Vec<u32>,
    /// Node indices of all cells, one after the other.
    pub nodes: Vec<u32>,
    /// VTK type code of each cell.
    pub kinds: Vec<u8>,
}

impl CellList {
    /// An empty list.
    pub fn new() -> Self {
        CellList {
            offsets: vec![0],
            nodes: Vec::new(),
            kinds: Vec::new(),
        }
    }

    /// Number of cells.
    pub fn len(&self) -> usize {
        self.kinds.len()
    }

    /// True when there are no cells.
    pub fn is_empty(&self) -> bool {
        self.kinds.is_empty()
    }

    /// Appends a cell. Returns `false` (and appends nothing) when the node array would outgrow
    /// `u32` offsets.
    pub fn push(&mut self, kind: CellKind, nodes: &[u32]) -> bool {
        self.push_code(kind.vtk_code(), nodes)
    }

    /// Appends a cell by its VTK code (also codes the kernel has no [`CellKind`] for, such as
    /// the polygons of a picture's section). Returns `false` as [`CellList::push`] does.
    pub fn push_code(&mut self, code: u8, nodes: &[u32]) -> bool {
        let Some(end) = self
            .nodes
            .len()
            .checked_add(nodes.len())
            .and_then(|e| u32::try_from(e).ok())
        else {
            return false;
        };
        if self.offsets.is_empty() {
            self.offsets.push(0);
        }
        self.nodes.extend_from_slice(nodes);
        self.offsets.push(end);
        self.kinds.push(code);
        true
    }

    /// Cell `c`: its VTK code and its nodes (empty when `c` is out of range).
    pub fn cell(&self, c: usize) -> (u8, &[u32]) {
        let code = self.kinds.get(c).copied().unwrap_or(0);
        let a = self.offsets.get(c).copied().unwrap_or(0) as usize;
        let b = self.offsets.get(c + 1).copied().unwrap_or(0) as usize;
        (code, self.nodes.get(a..b).unwrap_or(&[]))
    }

    /// Iterates over `(code, nodes)` of every cell.
    pub fn iter(&self) -> impl Iterator<Item = (u8, &[u32])> + '_ {
        (0..self.len()).map(move |c| self.cell(c))
    }
}
