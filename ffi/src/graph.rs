//! Graph and cell builders: `dk_graph_*`, `dk_cells_check`.
//!
//! Mesh node indices coming from the caller (edge lists, cell node lists) are read with
//! `index_base` 0 (C: read in place, no copy; `index_scratch` may be NULL with length 0) or 1
//! (Fortran: converted into the caller's `uint32_t` `index_scratch`, which needs as many
//! entries as the index arrays read: `edges_len`, or `cells->offsets_len + cells->nodes_len`; no
//! allocation); the CSR graph the kernel writes
//! (`offsets`, `targets`) is always 0-based, because callers hand it back to other `dk_`
//! functions unchanged and never index it themselves.
#![allow(unsafe_code)] // a parameter struct's arrays become `In`/`Out` tokens (`In::new`) here.

use deform_kernel::{
    graph_from_cells, graph_from_cells_len, graph_from_edges, graph_from_edges_len, Cells, Graph,
};
use deform_kernel_ffi_export::export;

use crate::args::{assert_layout, check_base, done, read_one, rebase, write_len};
use crate::slice::{input, out_one, output, In, Out};
use crate::status::dk_status;

/// A CSR graph for the functions that take one: `offsets` (`node_count + 1` row starts into
/// `targets`) and `targets` (the neighbour of each directed edge), both 0-based, as
/// `dk_graph_from_edges` / `dk_graph_from_cells` write them. The arrays are borrowed for the
/// call that receives the struct; the library never keeps the pointers.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
#[allow(non_camel_case_types)]
pub struct dk_graph {
    /// Row starts, `node_count + 1` entries.
    pub offsets: *const u32,
    /// Entries of `offsets`.
    pub offsets_len: usize,
    /// Neighbour of each directed edge.
    pub targets: *const u32,
    /// Entries of `targets` (directed edges).
    pub targets_len: usize,
}
assert_layout!(dk_graph, 32; offsets = 0, offsets_len = 8, targets = 16, targets_len = 24);

/// Cells or boundary elements in VTK node order: `offsets` (cell count + 1 entries into
/// `nodes`), `nodes` and one VTK code per cell in `kinds`. Offsets and node indices are read in
/// the `index_base` of the function that takes the struct. Borrowed for the call, as
/// [`dk_graph`]; all three arrays empty (NULL with length 0) means "no cells" where a function
/// says they are optional.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
#[allow(non_camel_case_types)]
pub struct dk_cells {
    /// Start of each cell in `nodes`, and the end (cell count + 1 entries).
    pub offsets: *const u32,
    /// Entries of `offsets`.
    pub offsets_len: usize,
    /// The cells' nodes.
    pub nodes: *const u32,
    /// Entries of `nodes`.
    pub nodes_len: usize,
    /// VTK cell type of each cell.
    pub kinds: *const u8,
    /// Entries of `kinds` (the cell count).
    pub kinds_len: usize,
}
assert_layout!(dk_cells, 48; offsets = 0, nodes = 16, kinds = 32, kinds_len = 40);

/// The arrays of a [`dk_graph`] as tokens.
#[derive(Clone, Copy)]
pub(crate) struct GraphIn<'a> {
    offsets: In<'a, u32>,
    targets: In<'a, u32>,
}

/// The arrays of a [`dk_cells`] as tokens.
#[derive(Clone, Copy)]
pub(crate) struct CellsIn<'a> {
    pub(crate) offsets: In<'a, u32>,
    pub(crate) nodes: In<'a, u32>,
    kinds: In<'a, u8>,
}

impl dk_graph {
    /// The arrays as tokens.
    ///
    /// # Safety
    /// The arrays are NULL or readable for their lengths for `'a` (the contract of every
    /// function that takes the struct).
    pub(crate) unsafe fn tokens<'a>(&self) -> GraphIn<'a> {
        // SAFETY: forwarded from the caller.
        unsafe {
            GraphIn {
                offsets: In::new(self.offsets, self.offsets_len),
                targets: In::new(self.targets, self.targets_len),
            }
        }
    }
}

impl dk_cells {
    /// No cells: every array NULL with length 0.
    pub(crate) const NONE: dk_cells = dk_cells {
        offsets: core::ptr::null(),
        offsets_len: 0,
        nodes: core::ptr::null(),
        nodes_len: 0,
        kinds: core::ptr::null(),
        kinds_len: 0,
    };

    /// The arrays as tokens.
    ///
    /// # Safety
    /// As [`dk_graph::tokens`].
    pub(crate) unsafe fn tokens<'a>(&self) -> CellsIn<'a> {
        // SAFETY: forwarded from the caller.
        unsafe {
            CellsIn {
                offsets: In::new(self.offsets, self.offsets_len),
                nodes: In::new(self.nodes, self.nodes_len),
                kinds: In::new(self.kinds, self.kinds_len),
            }
        }
    }
}

impl<'a> GraphIn<'a> {
    /// Reads the caller's struct.
    pub(crate) fn read(p: In<'a, dk_graph>) -> Result<Self, dk_status> {
        let g = read_one(p)?;
        // SAFETY: a token for a `dk_graph` carries the contract of the functions that take
        // one: its arrays are readable for their lengths while the token is.
        Ok(unsafe { g.tokens() })
    }

    /// Borrows and validates the graph.
    pub(crate) fn graph(self) -> Result<Graph<'a>, dk_status> {
        let o = input(self.offsets)?;
        let t = input(self.targets)?;
        Graph::new(o, t).map_err(dk_status::from)
    }

    /// Whether both arrays are left out (NULL with length 0).
    pub(crate) fn is_absent(&self) -> bool {
        self.offsets.is_absent() && self.targets.is_absent()
    }
}

/// Reads, borrows and validates the caller's graph.
pub(crate) fn read_graph(p: In<'_, dk_graph>) -> Result<Graph<'_>, dk_status> {
    GraphIn::read(p)?.graph()
}

impl<'a> CellsIn<'a> {
    /// Reads the caller's struct.
    pub(crate) fn read(p: In<'a, dk_cells>) -> Result<Self, dk_status> {
        let c = read_one(p)?;
        // SAFETY: as in `GraphIn::read`, for a `dk_cells`.
        Ok(unsafe { c.tokens() })
    }

    /// Whether all three arrays are left out (NULL with length 0).
    pub(crate) fn is_absent(&self) -> bool {
        self.offsets.is_absent() && self.nodes.is_absent() && self.kinds.is_absent()
    }

    /// Reads and validates the cells over `node_count` nodes: offsets and node indices in
    /// `index_base`; with base 1 their 0-based copies take `offsets_len + nodes_len` entries
    /// at the front of `scratch`, whose rest is returned. Shared by every function that takes
    /// cells (graph, quality, stiffening, deformation, plans).
    pub(crate) fn cells(
        self,
        node_count: usize,
        index_base: u32,
        scratch: &'a mut [u32],
    ) -> Result<(Cells<'a>, &'a mut [u32]), dk_status> {
        let offs = input(self.offsets)?;
        let nodes = input(self.nodes)?;
        let kinds = input(self.kinds)?;
        // Offsets are positions in `nodes`; with index_base 1 they are 1-based too.
        let (offs, scratch) = rebase(offs, index_base, scratch)?;
        let (nodes, scratch) = rebase(nodes, index_base, scratch)?;
        let cells = Cells::new(node_count, offs, nodes, kinds)?;
        Ok((cells, scratch))
    }

    /// [`Self::cells`] of an optional list: `None` when all three arrays are empty (some
    /// empty, some not, is `DK_ERR_LENGTH_MISMATCH`).
    pub(crate) fn optional_cells(
        self,
        node_count: usize,
        index_base: u32,
        scratch: &'a mut [u32],
    ) -> Result<(Option<Cells<'a>>, &'a mut [u32]), dk_status> {
        check_base(index_base)?;
        if self.offsets.len() == 0 {
            if self.nodes.len() != 0 || self.kinds.len() != 0 {
                return Err(dk_status::DK_ERR_LENGTH_MISMATCH);
            }
            return Ok((None, scratch));
        }
        let (cells, rest) = self.cells(node_count, index_base, scratch)?;
        Ok((Some(cells), rest))
    }
}

// ---------------------------------------------------------------------------------------------
// The C functions (`cargo xtask codegen` exports each, see ffi/README.md).
// ---------------------------------------------------------------------------------------------

/// Length `targets` needs for [`dk_graph_from_edges`]: `edges_len` (two entries per edge).
#[export(len_out[1])]
pub(crate) fn dk_graph_from_edges_len(
    edges_len: usize,
    len_out: Out<'_, usize>,
) -> Result<(), dk_status> {
    if edges_len % 2 != 0 {
        return Err(dk_status::DK_ERR_LENGTH_MISMATCH);
    }
    write_len(len_out, edges_len)
}

/// Builds the symmetric, sorted, deduplicated CSR graph of an undirected edge list.
///
/// `edges` holds `edges_len / 2` pairs `(a, b)` of node indices in `index_base` (0 or 1);
/// with `index_base` 1, `index_scratch` needs `edges_len` entries (it receives the 0-based
/// copy; with 0 it may be NULL with length 0). `offsets` must have `node_count + 1` entries;
/// `targets` at least `edges_len` entries. On success `*used_out` is the number of `targets`
/// entries used (entries past it are unspecified). Nothing but `index_scratch` is written on
/// failure.
#[export(used_out[1])]
pub(crate) fn dk_graph_from_edges(
    node_count: usize,
    edges: In<'_, u32>,
    index_base: u32,
    index_scratch: Out<'_, u32>,
    offsets: Out<'_, u32>,
    targets: Out<'_, u32>,
    used_out: Out<'_, usize>,
) -> dk_status {
    let edges_len = edges.len();
    done((|| {
        if edges_len % 2 != 0 {
            return Err(dk_status::DK_ERR_LENGTH_MISMATCH);
        }
        let e = input(edges)?;
        let (e, _) = rebase(e, index_base, output(index_scratch)?)?;
        let pairs = e.as_chunks::<2>().0;
        let o = output(offsets)?;
        let t = output(targets)?;
        let used = out_one(used_out)?;
        if graph_from_edges_len(pairs) != edges_len {
            return Err(dk_status::DK_ERR_LENGTH_MISMATCH);
        }
        *used = graph_from_edges(node_count, pairs, o, t)?;
        Ok(())
    })())
}

/// Validates a mixed-element cell list (`*cells`): `offsets` has one entry per cell plus one,
/// `kinds` holds VTK codes (3 line, 5 tri, 9 quad, 10 tet, 12 hex, 13 prism, 14 pyramid),
/// node indices are below `node_count`. With `index_base` 1, offsets and node indices are
/// 1-based (Fortran), and `index_scratch` needs `cells->offsets_len + cells->nodes_len` entries
/// (their 0-based copies); with 0 it may be NULL with length 0.
#[export(cells[1])]
pub(crate) fn dk_cells_check(
    node_count: usize,
    cells: In<'_, dk_cells>,
    index_base: u32,
    index_scratch: Out<'_, u32>,
) -> Result<(), dk_status> {
    let scratch = output(index_scratch)?;
    CellsIn::read(cells)?.cells(node_count, index_base, scratch)?;
    Ok(())
}

/// Length `targets` needs for [`dk_graph_from_cells`] (validates the cells first;
/// `index_scratch` as in [`dk_cells_check`]).
#[export(cells[1], len_out[1])]
pub(crate) fn dk_graph_from_cells_len(
    node_count: usize,
    cells: In<'_, dk_cells>,
    index_base: u32,
    index_scratch: Out<'_, u32>,
    face_diagonals: bool,
    len_out: Out<'_, usize>,
) -> Result<(), dk_status> {
    let scratch = output(index_scratch)?;
    let (cells, _) = CellsIn::read(cells)?.cells(node_count, index_base, scratch)?;
    write_len(len_out, graph_from_cells_len(&cells, face_diagonals))
}

/// Builds the edge graph of a mixed-element mesh (cell edges, plus quadrilateral-face
/// diagonals when `face_diagonals` is true) as a symmetric, sorted, deduplicated CSR graph.
/// `offsets` must have `node_count + 1` entries, `targets` at least the length from
/// [`dk_graph_from_cells_len`]; `*used_out` receives the number of `targets` entries used.
/// `index_scratch` as in [`dk_cells_check`].
#[export(cells[1], used_out[1])]
pub(crate) fn dk_graph_from_cells(
    node_count: usize,
    cells: In<'_, dk_cells>,
    index_base: u32,
    index_scratch: Out<'_, u32>,
    face_diagonals: bool,
    offsets: Out<'_, u32>,
    targets: Out<'_, u32>,
    used_out: Out<'_, usize>,
) -> Result<(), dk_status> {
    let scratch = output(index_scratch)?;
    let (cells, _) = CellsIn::read(cells)?.cells(node_count, index_base, scratch)?;
    let o = output(offsets)?;
    let t = output(targets)?;
    let used = out_one(used_out)?;
    *used = graph_from_cells(&cells, face_diagonals, o, t)?;
    Ok(())
}

/// Validates a 0-based CSR graph (`graph->offsets`: node count + 1 entries; `targets`); with
/// `require_symmetric` also checks that every edge has its reverse.
#[export(graph[1])]
pub(crate) fn dk_graph_check(
    graph: In<'_, dk_graph>,
    require_symmetric: bool,
) -> Result<(), dk_status> {
    let g = read_graph(graph)?;
    if require_symmetric {
        g.check_symmetric()?;
    }
    Ok(())
}
