//! Node orders for memory locality: `dk_order_*` (reverse Cuthill–McKee, Hilbert curve,
//! applying and undoing a permutation, the index distance across a graph's edges).
//!
//! A permutation is a [`dk_permutation`]: `order[new] = old` and `inverse[old] = new`, both
//! 0-based (the library writes them, as it writes CSR graphs; Fortran adds 1 to index with
//! them). Every function that takes one checks it in `O(n)` (`inverse[order[k]] == k`). To
//! undo a permutation, pass the same struct with `order` and `inverse` swapped.
#![allow(unsafe_code)] // a `dk_permutation`'s arrays become `In` tokens (`In::new`) here.

use deform_kernel::order::{
    gather, hilbert_order, index_distance, permute, permute_graph, rcm_order, Permutation,
};
use deform_kernel::Real;
use deform_kernel_ffi_export::export;

use crate::args::{assert_layout, check_base, read_one, read_points, zero_based, Components, Dim};
use crate::graph::{dk_graph, read_graph};
use crate::slice::{chunks, chunks_mut, input, out_one, output, In, Out};
use crate::status::dk_status;

/// A permutation of `n` nodes: `order[new] = old` and `inverse[old] = new`, `n` entries
/// each, 0-based, as `dk_order_rcm` and `dk_order_hilbert` write them. Borrowed for the call.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
#[allow(non_camel_case_types)]
pub struct dk_permutation {
    /// Old index of each new position.
    pub order: *const u32,
    /// Entries of `order`.
    pub order_len: usize,
    /// New position of each old index.
    pub inverse: *const u32,
    /// Entries of `inverse`.
    pub inverse_len: usize,
}
assert_layout!(dk_permutation, 32; order = 0, order_len = 8, inverse = 16, inverse_len = 24);

/// Reads and checks the caller's permutation; `None` when both arrays are NULL with length 0
/// (where a function allows it).
fn read_perm(p: In<'_, dk_permutation>) -> Result<Option<Permutation<'_>>, dk_status> {
    let s = read_one(p)?;
    // SAFETY: a token for a `dk_permutation` carries the contract of the functions that take
    // one: its arrays are readable for their lengths while the token is.
    let (order, inverse) = unsafe {
        (
            In::new(s.order, s.order_len),
            In::new(s.inverse, s.inverse_len),
        )
    };
    if order.is_absent() && inverse.is_absent() {
        return Ok(None);
    }
    Permutation::new(input(order)?, input(inverse)?)
        .map(Some)
        .map_err(dk_status::from)
}

/// A permutation that must be given.
fn required_perm(p: In<'_, dk_permutation>) -> Result<Permutation<'_>, dk_status> {
    read_perm(p)?.ok_or(dk_status::DK_ERR_NULL_POINTER)
}

/// Reverse Cuthill–McKee order of the graph's nodes into `order` and `inverse` (`node_count`
/// entries each): every connected component breadth-first from a pseudo-peripheral node,
/// neighbours by increasing degree (ties: lower index), the whole order reversed. Errors
/// (nothing written): graph errors, `DK_ERR_LENGTH_MISMATCH`, pointer errors.
#[export(graph[1])]
pub(crate) fn dk_order_rcm(
    graph: In<'_, dk_graph>,
    order: Out<'_, u32>,
    inverse: Out<'_, u32>,
) -> Result<(), dk_status> {
    let g = read_graph(graph)?;
    rcm_order(&g, output(order)?, output(inverse)?).map_err(dk_status::from)
}

/// Hilbert-curve order of `points` (`node_count * dim` scalars, `dim` 2 or 3) into `order`
/// and `inverse` (`node_count` entries each); `keys` is scratch of at least `node_count`
/// entries (on return `keys[old]` is node `old`'s curve key). Integer keys on the bounding
/// box (32 bits an axis in 2D, 21 in 3D), ties by index. Errors (nothing written):
/// `DK_ERR_NON_FINITE`, `DK_ERR_INVALID_PARAMETER` (`dim`), `DK_ERR_BUFFER_TOO_SMALL`
/// (`keys`), length and pointer errors.
#[export(twin)]
pub(crate) fn dk_order_hilbert<T: Real, const D: usize>(
    points: In<'_, T>,
    _dim: Dim<D>,
    order: Out<'_, u32>,
    inverse: Out<'_, u32>,
    keys: Out<'_, u64>,
) -> Result<(), dk_status> {
    let p = read_points::<T, D>(points)?;
    Ok(hilbert_order(
        p,
        output(order)?,
        output(inverse)?,
        output(keys)?,
    )?)
}

/// Index distance across the graph's directed edges: the largest `|i - j|` (the bandwidth)
/// into `*max_out` and their sum into `*sum_out` (divide by `targets_len` for the mean), in
/// the graph's numbering (`perm` with both arrays NULL, lengths 0) or in the numbering `perm`
/// gives. Errors (nothing written): graph and permutation errors, `DK_ERR_LENGTH_MISMATCH`,
/// pointer errors.
#[export(graph[1], perm[1], max_out[1], sum_out[1])]
pub(crate) fn dk_order_index_distance(
    graph: In<'_, dk_graph>,
    perm: In<'_, dk_permutation>,
    max_out: Out<'_, u32>,
    sum_out: Out<'_, u64>,
) -> Result<(), dk_status> {
    let g = read_graph(graph)?;
    let p = read_perm(perm)?;
    let d = index_distance(&g, p)?;
    let (m, s) = (out_one(max_out)?, out_one(sum_out)?);
    *m = d.max;
    *s = d.sum;
    Ok(())
}

/// Per-node values in the new numbering: `dst[new] = src[order[new]]`, `width` scalars a node
/// (1 to 7: a field, 2D or 3D points, ...), `src` and `dst` `node_count * width` scalars each.
/// With `order` and `inverse` swapped it puts them back. Errors (nothing written): permutation
/// errors, `DK_ERR_INVALID_PARAMETER` (`width`), length and pointer errors.
#[export(twin, perm[1])]
pub(crate) fn dk_order_permute<T: Real, const V: usize>(
    perm: In<'_, dk_permutation>,
    _width: Components<V>,
    src: In<'_, T>,
    dst: Out<'_, T>,
) -> Result<(), dk_status> {
    let p = required_perm(perm)?;
    let s = chunks::<T, V>(src)?;
    Ok(permute(p, s, chunks_mut::<T, V>(dst)?)?)
}

/// Node indices in the new numbering, in place: `i` becomes `inverse[i]` (cell node lists,
/// marker lists), read and written in `index_base` (0 or 1). With `order` and `inverse`
/// swapped it puts them back. Errors (nothing written): permutation errors,
/// `DK_ERR_INDEX_OUT_OF_RANGE`, `DK_ERR_BAD_INDEX_BASE`, pointer errors.
#[export(perm[1])]
pub(crate) fn dk_order_renumber(
    perm: In<'_, dk_permutation>,
    index_base: u32,
    indices: Out<'_, u32>,
) -> Result<(), dk_status> {
    check_base(index_base)?;
    let p = required_perm(perm)?;
    let idx = output(indices)?;
    if idx
        .iter()
        .any(|&i| zero_based(i, index_base) as usize >= p.len())
    {
        return Err(dk_status::DK_ERR_INDEX_OUT_OF_RANGE);
    }
    for i in idx.iter_mut() {
        let new = p
            .inverse()
            .get(zero_based(*i, index_base) as usize)
            .copied();
        *i = new.unwrap_or(0).wrapping_add(index_base);
    }
    Ok(())
}

/// The graph in the new numbering into `offsets` (`node_count + 1` entries) and `targets`
/// (`targets_len` of the graph): row `new` is old row `order[new]`, targets renumbered and
/// sorted. `edge_map` (NULL with length 0, or `targets_len` entries) receives the old
/// directed-edge index of each new one, for `dk_order_gather` of per-edge data. Errors
/// (nothing written): graph and permutation errors, length and pointer errors.
#[export(perm[1], graph[1])]
pub(crate) fn dk_order_permute_graph(
    perm: In<'_, dk_permutation>,
    graph: In<'_, dk_graph>,
    offsets: Out<'_, u32>,
    targets: Out<'_, u32>,
    edge_map: Out<'_, u32>,
) -> Result<(), dk_status> {
    let p = required_perm(perm)?;
    let g = read_graph(graph)?;
    let map = output(edge_map)?;
    let map = if map.is_empty() { None } else { Some(map) };
    permute_graph(p, &g, output(offsets)?, output(targets)?, map).map_err(dk_status::from)
}

/// `dst[k] = src[map[k]]` (per-edge data such as stiffness after `dk_order_permute_graph`,
/// with its `edge_map`); `dst` has `map_len` entries. Errors (nothing written):
/// `DK_ERR_INDEX_OUT_OF_RANGE`, length and pointer errors.
#[export(twin)]
pub(crate) fn dk_order_gather<T: Real>(
    map: In<'_, u32>,
    src: In<'_, T>,
    dst: Out<'_, T>,
) -> Result<(), dk_status> {
    gather(input(map)?, input(src)?, output(dst)?).map_err(dk_status::from)
}
