//! Graph and cell builders: `dk_graph_*`, `dk_cells_check`.
//!
//! Mesh node indices coming from the caller (edge lists, cell node lists) are read with
//! `index_base` 0 (C: read in place, no copy; `index_scratch` may be NULL with length 0) or 1
//! (Fortran: converted into the caller's `uint32_t` `index_scratch`, which needs as many
//! entries as the index arrays read: `edges_len`, or `cell_offsets_len + cell_nodes_len`; no
//! allocation); the CSR graph the kernel writes
//! (`offsets`, `targets`) is always 0-based, because callers hand it back to other `dk_`
//! functions unchanged and never index it themselves.
#![allow(unsafe_code)] // `#[no_mangle] unsafe extern "C"`; raw pointers are only read via crate::slice.

use deform_kernel::{
    graph_from_cells, graph_from_cells_len, graph_from_edges, graph_from_edges_len, Cells, Graph,
};

use crate::args::{check_base, done, rebase, write_len};
use crate::slice::{input, out_one, output, In};
use crate::status::dk_status;

/// Reads and validates a cell list over `node_count` nodes: offsets and node indices in
/// `index_base`; with base 1 their 0-based copies take `cell_offsets_len + cell_nodes_len`
/// entries at the front of `scratch`, whose rest is returned. Shared by every function that
/// takes cells (graph, quality, stiffening, deformation, plans).
pub(crate) fn read_cells<'a>(
    node_count: usize,
    cell_offsets: In<'a, u32>,
    cell_nodes: In<'a, u32>,
    cell_kinds: In<'a, u8>,
    index_base: u32,
    scratch: &'a mut [u32],
) -> Result<(Cells<'a>, &'a mut [u32]), dk_status> {
    let offs = input(cell_offsets)?;
    let nodes = input(cell_nodes)?;
    let kinds = input(cell_kinds)?;
    // Offsets are positions in `cell_nodes`; with index_base 1 they are 1-based too.
    let (offs, scratch) = rebase(offs, index_base, scratch)?;
    let (nodes, scratch) = rebase(nodes, index_base, scratch)?;
    let cells = Cells::new(node_count, offs, nodes, kinds).map_err(dk_status::from)?;
    Ok((cells, scratch))
}

/// [`read_cells`] of an optional list: `None` when all three arrays are empty (some empty,
/// some not, is `DK_ERR_LENGTH_MISMATCH`).
pub(crate) fn read_optional_cells<'a>(
    node_count: usize,
    cell_offsets: In<'a, u32>,
    cell_nodes: In<'a, u32>,
    cell_kinds: In<'a, u8>,
    index_base: u32,
    scratch: &'a mut [u32],
) -> Result<(Option<Cells<'a>>, &'a mut [u32]), dk_status> {
    check_base(index_base)?;
    if cell_offsets.len() == 0 {
        if cell_nodes.len() != 0 || cell_kinds.len() != 0 {
            return Err(dk_status::DK_ERR_LENGTH_MISMATCH);
        }
        return Ok((None, scratch));
    }
    let (cells, rest) = read_cells(
        node_count,
        cell_offsets,
        cell_nodes,
        cell_kinds,
        index_base,
        scratch,
    )?;
    Ok((Some(cells), rest))
}

mod abi;
pub use abi::*;
