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

use crate::args::{done, rebase, write_len};
use crate::slice::{input, out_one, output, In};
use crate::status::dk_status;

/// A caller's cell arrays, 0-based: offsets and nodes (the caller's arrays with `index_base`
/// 0, converted copies in `index_scratch` with 1) and kinds.
pub(crate) type RawCells<'a> = (&'a [u32], &'a [u32], &'a [u8]);

/// Reads a cell list (offsets and node indices in `index_base`); with base 1 the 0-based
/// copies take `cell_offsets_len + cell_nodes_len` entries at the front of `scratch`, whose
/// rest is returned. Shared with the quality module, which takes cells the same way.
pub(crate) fn read_cells<'a>(
    cell_offsets: In<'a, u32>,
    cell_nodes: In<'a, u32>,
    cell_kinds: In<'a, u8>,
    index_base: u32,
    scratch: &'a mut [u32],
) -> Result<(RawCells<'a>, &'a mut [u32]), dk_status> {
    let offs = input(cell_offsets)?;
    let nodes = input(cell_nodes)?;
    let kinds = input(cell_kinds)?;
    // Offsets are positions in `cell_nodes`; with index_base 1 they are 1-based too.
    let (offs, scratch) = rebase(offs, index_base, scratch)?;
    let (nodes, scratch) = rebase(nodes, index_base, scratch)?;
    Ok(((offs, nodes, kinds), scratch))
}

mod abi;
pub use abi::*;
