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
use crate::slice::{chunks, input, out_one, output, In, Out};
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

/// Length `targets` needs for [`dk_graph_from_edges`]: `edges_len` (two entries per edge).
///
/// # Safety
/// `len_out` points to one writable `size_t`.
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_graph_from_edges_len(
    edges_len: usize,
    len_out: *mut usize,
) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let len_out = unsafe { Out::new(len_out, 1) };
    done((|| {
        if edges_len % 2 != 0 {
            return Err(dk_status::DK_ERR_LENGTH_MISMATCH);
        }
        write_len(len_out, edges_len)
    })())
}

/// Builds the symmetric, sorted, deduplicated CSR graph of an undirected edge list.
///
/// `edges` holds `edges_len / 2` pairs `(a, b)` of node indices in `index_base` (0 or 1);
/// `offsets` must have `node_count + 1` entries; `targets` at least `edges_len` entries. On
/// success `*used_out` is the number of `targets` entries used (entries past it are
/// unspecified). Nothing is written on failure.
///
/// # Safety
/// Every pointer is valid for its length (`edges`: `edges_len` reads; `offsets`:
/// `offsets_len` writes; `targets`: `targets_len` writes; `used_out`: one write), and the
/// output buffers do not overlap each other or the inputs.
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_graph_from_edges(
    node_count: usize,
    edges: *const u32,
    edges_len: usize,
    index_base: u32,
    offsets: *mut u32,
    offsets_len: usize,
    targets: *mut u32,
    targets_len: usize,
    used_out: *mut usize,
) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let (edges, offsets, targets, used_out) = unsafe {
        (
            In::new(edges, edges_len),
            Out::new(offsets, offsets_len),
            Out::new(targets, targets_len),
            Out::new(used_out, 1),
        )
    };
    done((|| {
        let e: &[[u32; 2]] = chunks(edges, edges_len)?;
        check_base(index_base)?;
        let pairs: Cow<'_, [[u32; 2]]> = if index_base == 0 {
            Cow::Borrowed(e)
        } else {
            Cow::Owned(
                e.iter()
                    .map(|p| p.map(|i| zero_based(i, index_base)))
                    .collect::<Vec<_>>(),
            )
        };
        let o = output(offsets, offsets_len)?;
        let t = output(targets, targets_len)?;
        let used = out_one(used_out)?;
        if graph_from_edges_len(&pairs) != edges_len {
            return Err(dk_status::DK_ERR_LENGTH_MISMATCH);
        }
        let n = graph_from_edges(node_count, &pairs, o, t).map_err(dk_status::from)?;
        *used = n;
        Ok(())
    })())
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

/// Validates a mixed-element cell list: `cell_offsets` has one entry per cell plus one,
/// `cell_kinds` holds VTK codes (3 line, 5 tri, 9 quad, 10 tet, 12 hex, 13 prism, 14 pyramid),
/// node indices are below `node_count`. With `index_base` 1, offsets and node indices are
/// 1-based (Fortran).
///
/// # Safety
/// Every pointer is valid for reading its length.
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_cells_check(
    node_count: usize,
    cell_offsets: *const u32,
    cell_offsets_len: usize,
    cell_nodes: *const u32,
    cell_nodes_len: usize,
    cell_kinds: *const u8,
    cell_kinds_len: usize,
    index_base: u32,
) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let (cell_offsets, cell_nodes, cell_kinds) = unsafe {
        (
            In::new(cell_offsets, cell_offsets_len),
            In::new(cell_nodes, cell_nodes_len),
            In::new(cell_kinds, cell_kinds_len),
        )
    };
    done((|| {
        let (o, n, k) = read_cells(
            cell_offsets,
            cell_offsets_len,
            cell_nodes,
            cell_nodes_len,
            cell_kinds,
            cell_kinds_len,
            index_base,
        )?;
        Cells::new(node_count, &o, &n, k).map_err(dk_status::from)?;
        Ok(())
    })())
}

/// Length `targets` needs for [`dk_graph_from_cells`] (validates the cells first).
///
/// # Safety
/// Every pointer is valid for its length; `len_out` points to one writable `size_t`.
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_graph_from_cells_len(
    node_count: usize,
    cell_offsets: *const u32,
    cell_offsets_len: usize,
    cell_nodes: *const u32,
    cell_nodes_len: usize,
    cell_kinds: *const u8,
    cell_kinds_len: usize,
    index_base: u32,
    face_diagonals: bool,
    len_out: *mut usize,
) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let (cell_offsets, cell_nodes, cell_kinds, len_out) = unsafe {
        (
            In::new(cell_offsets, cell_offsets_len),
            In::new(cell_nodes, cell_nodes_len),
            In::new(cell_kinds, cell_kinds_len),
            Out::new(len_out, 1),
        )
    };
    done((|| {
        let (o, n, k) = read_cells(
            cell_offsets,
            cell_offsets_len,
            cell_nodes,
            cell_nodes_len,
            cell_kinds,
            cell_kinds_len,
            index_base,
        )?;
        let cells = Cells::new(node_count, &o, &n, k).map_err(dk_status::from)?;
        write_len(len_out, graph_from_cells_len(&cells, face_diagonals))
    })())
}

/// Builds the edge graph of a mixed-element mesh (cell edges, plus quadrilateral-face
/// diagonals when `face_diagonals` is true) as a symmetric, sorted, deduplicated CSR graph.
/// `offsets` must have `node_count + 1` entries, `targets` at least the length from
/// [`dk_graph_from_cells_len`]; `*used_out` receives the number of `targets` entries used.
///
/// # Safety
/// Every pointer is valid for its length (reads for the cell arrays, writes for `offsets`,
/// `targets`, `used_out`), and the outputs do not overlap each other or the inputs.
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_graph_from_cells(
    node_count: usize,
    cell_offsets: *const u32,
    cell_offsets_len: usize,
    cell_nodes: *const u32,
    cell_nodes_len: usize,
    cell_kinds: *const u8,
    cell_kinds_len: usize,
    index_base: u32,
    face_diagonals: bool,
    offsets: *mut u32,
    offsets_len: usize,
    targets: *mut u32,
    targets_len: usize,
    used_out: *mut usize,
) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let (cell_offsets, cell_nodes, cell_kinds, offsets, targets, used_out) = unsafe {
        (
            In::new(cell_offsets, cell_offsets_len),
            In::new(cell_nodes, cell_nodes_len),
            In::new(cell_kinds, cell_kinds_len),
            Out::new(offsets, offsets_len),
            Out::new(targets, targets_len),
            Out::new(used_out, 1),
        )
    };
    done((|| {
        let (co, cn, ck) = read_cells(
            cell_offsets,
            cell_offsets_len,
            cell_nodes,
            cell_nodes_len,
            cell_kinds,
            cell_kinds_len,
            index_base,
        )?;
        let cells = Cells::new(node_count, &co, &cn, ck).map_err(dk_status::from)?;
        let o = output(offsets, offsets_len)?;
        let t = output(targets, targets_len)?;
        let used = out_one(used_out)?;
        *used = graph_from_cells(&cells, face_diagonals, o, t).map_err(dk_status::from)?;
        Ok(())
    })())
}

/// Validates a 0-based CSR graph (`offsets`: node count + 1 entries; `targets`); with
/// `require_symmetric` also checks that every edge has its reverse.
///
/// # Safety
/// `offsets` and `targets` are valid for reading their lengths.
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_graph_check(
    offsets: *const u32,
    offsets_len: usize,
    targets: *const u32,
    targets_len: usize,
    require_symmetric: bool,
) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let (offsets, targets) =
        unsafe { (In::new(offsets, offsets_len), In::new(targets, targets_len)) };
    done((|| {
        let o = input(offsets, offsets_len)?;
        let t = input(targets, targets_len)?;
        let g = Graph::new(o, t).map_err(dk_status::from)?;
        if require_symmetric {
            g.check_symmetric().map_err(dk_status::from)?;
        }
        Ok(())
    })())
}
