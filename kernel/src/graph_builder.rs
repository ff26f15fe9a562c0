//! Builders that write a symmetric, deduplicated [`Graph`](crate::Graph) into caller buffers.
//!
//! LAPACK-workspace style: ask `*_len` how long `targets` must be (an upper bound: twice the
//! number of input edges), pass `offsets` of exactly `node_count + 1` entries, and the builder
//! returns how many `targets` entries it used. Rows come out sorted by neighbour index, so the
//! result is canonical: equal inputs up to edge order and duplication give equal bits.
//! Validation happens before anything is written.

use crate::cells::Cells;
use crate::check;
use crate::error::{Error, Result};

/// Where the undirected edges come from.
enum EdgeSource<'s, 'a> {
    List(&'s [[u32; 2]]),
    Cells(&'s Cells<'a>, bool),
    /// Every pair of nodes of every cell (the coupling of a finite-element matrix).
    Pairs(&'s Cells<'a>),
}

impl EdgeSource<'_, '_> {
    /// Calls `f(a, b)` for every undirected edge occurrence, in input order.
    fn for_each(&self, mut f: impl FnMut(u32, u32)) {
        match self {
            EdgeSource::List(edges) => edges.iter().for_each(|&[a, b]| f(a, b)),
            EdgeSource::Cells(cells, diagonals) => {
                for (kind, nodes) in cells.iter() {
                    let extra: &[[u8; 2]] = if *diagonals {
                        kind.face_diagonals()
                    } else {
                        &[]
                    };
                    for &[la, lb] in kind.edges().iter().chain(extra) {
                        if let (Some(&a), Some(&b)) =
                            (nodes.get(la as usize), nodes.get(lb as usize))
                        {
                            f(a, b);
                        }
                    }
                }
            }
            EdgeSource::Pairs(cells) => {
                for (_, nodes) in cells.iter() {
                    for (k, &a) in nodes.iter().enumerate() {
                        nodes.iter().skip(k + 1).for_each(|&b| f(a, b));
                    }
                }
            }
        }
    }
}

/// Length `targets` needs for [`graph_from_edges`]: `2 × edges.len()`.
#[inline]
pub fn graph_from_edges_len(edges: &[[u32; 2]]) -> usize {
    edges.len().saturating_mul(2)
}

/// Builds the symmetric CSR graph of an undirected edge list (either orientation, duplicates
/// allowed). Returns the number of `targets` entries used; entries past it are unspecified.
///
/// # Errors
/// `offsets.len() != node_count + 1`, `targets` shorter than
/// [`graph_from_edges_len`], an endpoint `>= node_count`, or an edge from a node to itself.
pub fn graph_from_edges(
    node_count: usize,
    edges: &[[u32; 2]],
    offsets: &mut [u32],
    targets: &mut [u32],
) -> Result<usize> {
    for (e, &[a, b]) in edges.iter().enumerate() {
        for (k, v) in [a, b].into_iter().enumerate() {
            if v as usize >= node_count {
                return Err(Error::IndexOutOfRange {
                    arg: "edges",
                    position: 2 * e + k,
                    index: v as usize,
                    bound: node_count,
                });
            }
        }
        if a == b {
            return Err(Error::SelfLoop { node: a as usize });
        }
    }
    build(
        node_count,
        graph_from_edges_len(edges),
        &EdgeSource::List(edges),
        offsets,
        targets,
    )
}

/// Length `targets` needs for [`graph_from_cells`]: twice the number of cell edges (plus
/// quadrilateral-face diagonals when `face_diagonals` is set).
pub fn graph_from_cells_len(cells: &Cells<'_>, face_diagonals: bool) -> usize {
    let mut n = 0usize;
    for (kind, _) in cells.iter() {
        n = n.saturating_add(kind.edges().len());
        if face_diagonals {
            n = n.saturating_add(kind.face_diagonals().len());
        }
    }
    n.saturating_mul(2)
}

/// Builds the symmetric CSR edge graph of a mixed-element mesh: two nodes are neighbours when
/// they share a cell edge (or, with `face_diagonals`, a diagonal of a quadrilateral face).
/// Returns the number of `targets` entries used; entries past it are unspecified.
///
/// # Errors
/// `offsets.len() != cells.node_count() + 1` or `targets` shorter than
/// [`graph_from_cells_len`].
pub fn graph_from_cells(
    cells: &Cells<'_>,
    face_diagonals: bool,
    offsets: &mut [u32],
    targets: &mut [u32],
) -> Result<usize> {
    let needed = graph_from_cells_len(cells, face_diagonals);
    build(
        cells.node_count(),
        needed,
        &EdgeSource::Cells(cells, face_diagonals),
        offsets,
        targets,
    )
}

/// Shared CSR construction: count, prefix-sum, scatter, then sort and deduplicate each row.
/// The source's indices are already validated.
/// Symmetric CSR of every pair of nodes that share a cell (the sparsity of a
/// finite-element matrix), `needed` directed entries at most; see
/// [`elasticity_graph`](crate::elasticity::elasticity_graph).
pub(crate) fn graph_from_cell_pairs(
    cells: &Cells<'_>,
    needed: usize,
    offsets: &mut [u32],
    targets: &mut [u32],
) -> Result<usize> {
    build(
        cells.node_count(),
        needed,
        &EdgeSource::Pairs(cells),
        offsets,
        targets,
    )
}

fn build(
    node_count: usize,
    needed: usize,
    source: &EdgeSource<'_, '_>,
    offsets: &mut [u32],
    targets: &mut [u32],
) -> Result<usize> {
    if u32::try_from(needed).is_err() {
        return Err(Error::TooLarge {
            arg: "edges",
            value: needed / 2,
        });
    }
    // Strictly below u32::MAX, so `node_count + 1` never wraps (usize may be 32 bits).
    if node_count >= u32::MAX as usize {
        return Err(Error::TooLarge {
            arg: "node_count",
            value: node_count,
        });
    }
    check::len("offsets", offsets.len(), node_count.wrapping_add(1))?;
    check::buffer("targets", targets.len(), needed)?;

    // 1. Degrees (with repetitions) into offsets[i + 1].
    offsets.iter_mut().for_each(|o| *o = 0);
    source.for_each(|a, b| {
        for v in [a, b] {
            if let Some(o) = offsets.get_mut(v as usize + 1) {
                *o += 1;
            }
        }
    });
    // 2. Inclusive prefix sum: offsets[i] = start of row i, offsets[i + 1] = its end.
    let mut acc = 0u32;
    for o in offsets.iter_mut() {
        acc = acc.wrapping_add(*o);
        *o = acc;
    }
    // 3. Scatter, using offsets[i] as row i's cursor (it ends at row i's end = next start).
    source.for_each(|a, b| {
        for (from, to) in [(a, b), (b, a)] {
            if let Some(cursor) = offsets.get_mut(from as usize) {
                if let Some(t) = targets.get_mut(*cursor as usize) {
                    *t = to;
                }
                *cursor += 1;
            }
        }
    });
    // Now offsets[i] = end of row i; shift back so offsets[i] = start, offsets[n] = total.
    // (`offsets` is empty only when `node_count + 1` wrapped; `rotate_right` asserts.)
    if !offsets.is_empty() {
        offsets.rotate_right(1);
    }
    if let Some(first) = offsets.first_mut() {
        *first = 0;
    }
    // 4. Sort and deduplicate each row, compacting towards the front.
    let mut write = 0usize;
    let mut row_start = 0usize;
    for i in 0..node_count {
        let row_end = offsets.get(i + 1).map_or(row_start, |&e| e as usize);
        let unique = targets.get_mut(row_start..row_end).map_or(0, sort_unique);
        // `write <= row_start`: a forward copy never overwrites what it has still to read.
        for k in 0..unique {
            if let Some(&v) = targets.get(row_start + k) {
                if let Some(t) = targets.get_mut(write + k) {
                    *t = v;
                }
            }
        }
        if let Some(o) = offsets.get_mut(i) {
            *o = write as u32;
        }
        write += unique;
        row_start = row_end;
    }
    if let Some(o) = offsets.get_mut(node_count) {
        *o = write as u32;
    }
    Ok(write)
}

/// Rows longer than this are sorted by [`heapsort`]; shorter ones by binary insertion.
const INSERTION_MAX: usize = 256;

/// Sorts `row` ascending and removes repeats, the distinct values ending at the front;
/// returns how many there are. A mesh row holds each neighbour once per cell around the edge
/// (about 70 entries for 14 neighbours in a tetrahedral mesh): binary insertion into the
/// growing distinct prefix touches each entry a few times where a heapsort of the whole row
/// moves it `log n` times. Longer rows (a hub) take the `O(n log n)` heapsort.
fn sort_unique(row: &mut [u32]) -> usize {
    if row.len() > INSERTION_MAX {
        heapsort(row);
        let mut unique = 0usize;
        for r in 0..row.len() {
            let v = row.get(r).copied();
            if unique == 0 || row.get(unique - 1).copied() != v {
                if let (Some(v), Some(t)) = (v, row.get_mut(unique)) {
                    *t = v;
                }
                unique += 1;
            }
        }
        return unique;
    }
    let mut unique = 0usize;
    for r in 0..row.len() {
        let Some(&v) = row.get(r) else { break };
        let Some(prefix) = row.get(..unique) else {
            break;
        };
        if let Err(at) = prefix.binary_search(&v) {
            // `at <= unique <= r`: the shift ends at `r`, whose value is held in `v`.
            for k in (at..unique).rev() {
                if let Some(&x) = row.get(k) {
                    if let Some(t) = row.get_mut(k + 1) {
                        *t = x;
                    }
                }
            }
            if let Some(t) = row.get_mut(at) {
                *t = v;
            }
            unique += 1;
        }
    }
    unique
}

/// In-place ascending heapsort (no allocation, no panic path, O(n log n) worst case).
fn heapsort(v: &mut [u32]) {
    let n = v.len();
    let mut start = n / 2;
    while start > 0 {
        start -= 1;
        sift_down(v, start, n);
    }
    let mut end = n;
    while end > 1 {
        end -= 1;
        if end < v.len() {
            v.swap(0, end);
        }
        sift_down(v, 0, end);
    }
}

fn sift_down(v: &mut [u32], mut root: usize, end: usize) {
    let end = end.min(v.len());
    loop {
        let mut child = 2 * root + 1;
        if child >= end {
            break;
        }
        if child + 1 < end {
            if let (Some(a), Some(b)) = (v.get(child), v.get(child + 1)) {
                if a < b {
                    child += 1;
                }
            }
        }
        match (v.get(root), v.get(child)) {
            (Some(r), Some(c)) if r < c => {
                if root < v.len() && child < v.len() {
                    v.swap(root, child);
                }
                root = child;
            }
            _ => break,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn heapsort_sorts() {
        let mut v = [5u32, 1, 4, 1, 5, 9, 2, 6, 5, 3, 5];
        heapsort(&mut v);
        assert_eq!(v, [1, 1, 2, 3, 4, 5, 5, 5, 5, 6, 9]);
    }

    /// Both paths of `sort_unique` (binary insertion up to `INSERTION_MAX` entries, heapsort
    /// beyond) give the sorted distinct values, checked against a sort-then-scan reference.
    #[test]
    fn sort_unique_both_paths() {
        let mut state = 0x9E37_79B9_7F4A_7C15u64;
        for len in [0usize, 1, 2, 7, 70, 255, 256, 257, 600] {
            for range in [1u32, 5, 40, 1000] {
                let mut row = [0u32; 600];
                for x in row.iter_mut().take(len) {
                    state ^= state << 13;
                    state ^= state >> 7;
                    state ^= state << 17;
                    *x = (state % u64::from(range)) as u32;
                }
                let mut want = row;
                heapsort(&mut want[..len]);
                let mut distinct = 0;
                for k in 0..len {
                    if k == 0 || want[k] != want[k - 1] {
                        want[distinct] = want[k];
                        distinct += 1;
                    }
                }
                let got = sort_unique(&mut row[..len]);
                assert_eq!(got, distinct, "len {len} range {range}");
                assert_eq!(row[..got], want[..distinct], "len {len} range {range}");
            }
        }
    }
}
