//! Graph and cell builders: `dk_graph_*`, `dk_cells_check`.
//!
//! Mesh node indices coming from the caller (edge lists, cell node lists) are read with
//! `index_base` 0 (C: read in place, no copy) or 1 (Fortran: converted into a temporary copy
//! that lives for the call); the CSR graph the kernel writes
//! (`offsets`, `targets`) is always 0-based, because callers hand it back to other `dk_`
//! functions unchanged and never index it themselves.
#![allow(unsafe_code)] // `#[no_mangle] unsafe extern "C"`; raw pointers are only read via crate::slice.

use std::borrow::Cow;
use std::vec::Vec;

use deform_kernel::{
    graph_from_cells, graph_from_cells_len, graph_from_edges, graph_from_edges_len, Cells, Graph,
};

use crate::args::{check_base, done, write_len, zero_based};
use crate::slice::{chunks, input, out_one, output, In};
use crate::status::dk_status;

/// Checks `index_base` and returns `indices` 0-based: the caller's array itself (no copy) with
/// base 0, a converted copy with base 1. An index below the base is out of range (reported as
/// `u32::MAX`, which every bound rejects).
fn rebase(indices: &[u32], index_base: u32) -> Result<Cow<'_, [u32]>, dk_status> {
    check_base(index_base)?;
    Ok(if index_base == 0 {
        Cow::Borrowed(indices)
    } else {
        Cow::Owned(indices.iter().map(|&i| zero_based(i, index_base)).collect())
    })
}

/// A caller's cell arrays, 0-based: offsets and nodes (borrowed as they are with `index_base`
/// 0, converted copies with 1) and kinds (always borrowed).
pub(crate) type OwnedCells<'a> = (Cow<'a, [u32]>, Cow<'a, [u32]>, &'a [u8]);

/// Reads a cell list (offsets and node indices in `index_base`); copies only for base 1.
/// Shared with the quality module, which takes cells the same way.
pub(crate) fn read_cells<'a>(
    cell_offsets: In<'a, u32>,
    cell_offsets_len: usize,
    cell_nodes: In<'a, u32>,
    cell_nodes_len: usize,
    cell_kinds: In<'a, u8>,
    cell_kinds_len: usize,
    index_base: u32,
) -> Result<OwnedCells<'a>, dk_status> {
    let offs = input(cell_offsets, cell_offsets_len)?;
    let nodes = input(cell_nodes, cell_nodes_len)?;
    let kinds = input(cell_kinds, cell_kinds_len)?;
    // Offsets are positions in `cell_nodes`; with index_base 1 they are 1-based too.
    Ok((rebase(offs, index_base)?, rebase(nodes, index_base)?, kinds))
}

mod abi;
pub use abi::*;
