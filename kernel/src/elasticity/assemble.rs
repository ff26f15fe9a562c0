//! Assembly of the global stiffness into node blocks: one `D×D` block per node (the
//! diagonal) and one per directed edge of the cell-pair graph ([`elasticity_graph`]),
//! indexed like the graph's `targets`. Cells are added in their order, so the sums are the
//! same on every platform; block `i → j` is the exact transpose of block `j → i`.

use super::element::{self, MAX_NODES, MAX_PAIRS};
use crate::cells::Cells;
use crate::check;
use crate::error::{Error, Result};
use crate::graph::Graph;
use crate::real::Real;

/// A `D×D` block of the stiffness matrix.
pub type Block<T, const D: usize> = [[T; D]; D];

/// Directed entries [`elasticity_graph`] may need: `Σ n_c (n_c − 1)` over the cells
/// (saturating).
pub fn elasticity_graph_len(cells: &Cells<'_>) -> usize {
    cells.iter().fold(0usize, |s, (_, nodes)| {
        s.saturating_add(nodes.len().saturating_mul(nodes.len().saturating_sub(1)))
    })
}

/// The graph of every pair of nodes that share a cell (the sparsity of the stiffness
/// matrix; a hexahedron couples all its 8 nodes, body diagonals included), as a symmetric,
/// sorted, deduplicated CSR into `offsets` (`node_count + 1`) and `targets` (at least
/// [`elasticity_graph_len`]); returns the entries used.
///
/// # Errors
/// Nothing is written on error: `offsets` of the wrong length ([`Error::LengthMismatch`]),
/// `targets` too short ([`Error::BufferTooSmall`]), too many entries for `u32`
/// ([`Error::TooLarge`]).
pub fn elasticity_graph(
    cells: &Cells<'_>,
    offsets: &mut [u32],
    targets: &mut [u32],
) -> Result<usize> {
    let needed = elasticity_graph_len(cells);
    crate::graph_builder::graph_from_cell_pairs(cells, needed, offsets, targets)
}

/// Assembles the stiffness of isotropic linear elasticity (plane strain in 2D) with Young's
/// modulus `moduli[c]` per cell (see [`cell_moduli`](super::cell_moduli)) and Poisson ratio
/// `poisson` into `diag` (one block per node) and `off` (one per directed edge of `graph`).
///
/// # Errors
/// Nothing is written on error: `points`, `moduli`, `diag` or `off` of the wrong length
/// ([`Error::LengthMismatch`]); a non-finite coordinate or modulus ([`Error::NonFinite`]); a
/// modulus `≤ 0` ([`Error::NonPositive`]); `poisson` not finite, `≤ −1` or `½` (see `check_poisson`)
/// ([`Error::InvalidParameter`]); a cell of the wrong dimension ([`Error::CellDimension`]);
/// two nodes of a cell that are not neighbours in `graph` ([`Error::NotSymmetric`] naming
/// them: build the graph with [`elasticity_graph`]); a degenerate cell (a singular Jacobian
/// at a Gauss point: [`Error::NonPositive`], `"cells"`).
pub fn assemble<T: Real, const D: usize>(
    cells: &Cells<'_>,
    points: &[[T; D]],
    graph: &Graph<'_>,
    moduli: &[T],
    poisson: T,
    diag: &mut [Block<T, D>],
    off: &mut [Block<T, D>],
) -> Result<()> {
    check::mesh_dim::<D>();
    super::check_mesh(cells, points)?;
    check::len("graph", graph.node_count(), points.len())?;
    check::len("moduli", moduli.len(), cells.len())?;
    check::len("diag", diag.len(), points.len())?;
    check::len("off", off.len(), graph.edge_count())?;
    check::finite("moduli", moduli)?;
    if let Some(position) = moduli.iter().position(|&e| e <= T::ZERO) {
        return Err(Error::NonPositive {
            arg: "moduli",
            position,
        });
    }
    super::check_poisson(poisson)?;
    check_cells(cells, points, graph)?;
    diag.iter_mut().for_each(|b| *b = [[T::ZERO; D]; D]);
    off.iter_mut().for_each(|b| *b = [[T::ZERO; D]; D]);
    let mut k = [[[T::ZERO; D]; D]; MAX_PAIRS];
    for ((kind, nodes), &e) in cells.iter().zip(moduli) {
        let (lambda, mu) = element::lame(e, poisson);
        let x = gather(nodes, points);
        let Some(x) = x.get(..nodes.len()) else {
            continue;
        };
        if element::stiffness(kind, x, lambda, mu, &mut k).is_none() {
            continue; // excluded by check_cells
        }
        scatter(graph, nodes, &k, diag, off);
    }
    Ok(())
}

/// Every cell's node pairs are graph edges and its Jacobian is regular at every Gauss
/// point.
fn check_cells<T: Real, const D: usize>(
    cells: &Cells<'_>,
    points: &[[T; D]],
    graph: &Graph<'_>,
) -> Result<()> {
    for (c, (kind, nodes)) in cells.iter().enumerate() {
        for (k, &a) in nodes.iter().enumerate() {
            for &b in nodes.iter().skip(k + 1) {
                if graph.find_edge(a as usize, b as usize).is_none()
                    || graph.find_edge(b as usize, a as usize).is_none()
                {
                    return Err(Error::NotSymmetric {
                        from: a as usize,
                        to: b as usize,
                    });
                }
            }
        }
        let x = gather(nodes, points);
        let x = x.get(..nodes.len()).unwrap_or(&[]);
        for g in 0..element::point_count(kind) {
            if element::gauss_point(kind, x, g).is_none() {
                return Err(Error::NonPositive {
                    arg: "cells",
                    position: c,
                });
            }
        }
    }
    Ok(())
}

/// The cell's node coordinates.
fn gather<T: Real, const D: usize>(nodes: &[u32], points: &[[T; D]]) -> [[T; D]; MAX_NODES] {
    let mut x = [[T::ZERO; D]; MAX_NODES];
    for (x, &n) in x.iter_mut().zip(nodes) {
        *x = points.get(n as usize).copied().unwrap_or([T::ZERO; D]);
    }
    x
}

/// Adds the element blocks `k` (pairs `a ≤ b`) into the global blocks: `a = b` into
/// `diag`, `a < b` into edge `n_a → n_b` and its transpose into `n_b → n_a`.
fn scatter<T: Real, const D: usize>(
    graph: &Graph<'_>,
    nodes: &[u32],
    k: &[Block<T, D>; MAX_PAIRS],
    diag: &mut [Block<T, D>],
    off: &mut [Block<T, D>],
) {
    for (b, &nb) in nodes.iter().enumerate() {
        for (a, &na) in nodes.iter().enumerate().take(b + 1) {
            let Some(blk) = k.get(element::pair_index(a, b)) else {
                continue;
            };
            if a == b {
                if let Some(d) = diag.get_mut(na as usize) {
                    add(d, blk, false);
                }
                continue;
            }
            let (na, nb) = (na as usize, nb as usize);
            if let Some(e) = graph.find_edge(na, nb).and_then(|e| off.get_mut(e)) {
                add(e, blk, false);
            }
            if let Some(e) = graph.find_edge(nb, na).and_then(|e| off.get_mut(e)) {
                add(e, blk, true);
            }
        }
    }
}

/// `out += blk` (or `blkᵀ`).
#[inline]
fn add<T: Real, const D: usize>(out: &mut Block<T, D>, blk: &Block<T, D>, transpose: bool) {
    for (i, row) in out.iter_mut().enumerate() {
        for (j, o) in row.iter_mut().enumerate() {
            let (r, c) = if transpose { (j, i) } else { (i, j) };
            *o += blk
                .get(r)
                .and_then(|x| x.get(c))
                .copied()
                .unwrap_or(T::ZERO);
        }
    }
}
