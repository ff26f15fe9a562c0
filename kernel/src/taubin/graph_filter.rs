//! Taubin λ|μ fairing on a CSR graph: the classic unstructured-mesh variant.

use core::ops::Range;

use crate::error::{Error, Result};
use crate::graph::Graph;
use crate::real::Real;
use crate::vector;

use super::structured::{check_mask, FilterReport};
use super::TaubinParams;

/// Optional inputs of the graph filter.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct GraphOptions<'a, T> {
    /// Per-directed-edge weights `w_ij > 0` (length `graph.edge_count()`), or `None` for
    /// uniform weights (`w_ij = 1`). See [`inverse_distance_weights`].
    pub weights: Option<&'a [T]>,
    /// Optional fixed mask (`node_count` bytes, nonzero = the node keeps its value).
    pub fixed: Option<&'a [u8]>,
}

/// Scratch length (in `[T; V]` items) for [`smooth_graph`]: `node_count`.
pub fn graph_scratch_len(graph: &Graph<'_>) -> usize {
    graph.node_count()
}

/// Fills `weights[e] = 1 / |x_i − x_j|` for every directed edge `e = i → j` (Fujiwara's
/// inverse-distance weights: the filter then approximates the arclength Laplacian on meshes
/// with uneven edge lengths).
///
/// # Errors
/// `LengthMismatch` (`points`, `weights`), `NonFinite` (`points`), `ZeroLengthEdge` when two
/// neighbours coincide (or the inverse overflows).
pub fn inverse_distance_weights<T: Real, const D: usize>(
    graph: &Graph<'_>,
    points: &[[T; D]],
    weights: &mut [T],
) -> Result<()> {
    let n = graph.node_count();
    if points.len() != n {
        return Err(Error::LengthMismatch {
            arg: "points",
            expected: n,
            actual: points.len(),
        });
    }
    if weights.len() != graph.edge_count() {
        return Err(Error::LengthMismatch {
            arg: "weights",
            expected: graph.edge_count(),
            actual: weights.len(),
        });
    }
    if let Some(position) = crate::real::first_non_finite(points) {
        return Err(Error::NonFinite {
            arg: "points",
            position,
        });
    }
    // Validate every edge before writing.
    for (i, _, row) in graph.rows() {
        let Some(&xi) = points.get(i) else { continue };
        for &j in row {
            let Some(&xj) = points.get(j as usize) else {
                continue;
            };
            let w = T::ONE / vector::distance(xi, xj);
            if !w.is_finite() {
                return Err(Error::ZeroLengthEdge {
                    from: i,
                    to: j as usize,
                });
            }
        }
    }
    for (i, first, row) in graph.rows() {
        let Some(&xi) = points.get(i) else { continue };
        for (e, &j) in (first..).zip(row) {
            let Some(&xj) = points.get(j as usize) else {
                continue;
            };
            if let Some(w) = weights.get_mut(e) {
                *w = T::ONE / vector::distance(xi, xj);
            }
        }
    }
    Ok(())
}

/// Validates the options against the graph.
fn check_options<T: Real>(graph: &Graph<'_>, options: &GraphOptions<'_, T>) -> Result<()> {
    if let Some(w) = options.weights {
        if w.len() != graph.edge_count() {
            return Err(Error::LengthMismatch {
                arg: "options.weights",
                expected: graph.edge_count(),
                actual: w.len(),
            });
        }
        for (position, &x) in w.iter().enumerate() {
            if !x.is_finite() {
                return Err(Error::NonFinite {
                    arg: "options.weights",
                    position,
                });
            }
            if x <= T::ZERO {
                return Err(Error::NonPositive {
                    arg: "options.weights",
                    position,
                });
            }
        }
    }
    check_mask(options.fixed, graph.node_count(), "options.fixed")
}

/// One Jacobi pass over `nodes` (no validation). Returns the largest component change.
///
/// The "weights given?" and "fixed mask given?" decisions are taken once here, not per edge
/// and node: each of the four combinations runs its own loop ([`sweep_rows`]).
fn sweep_core<T: Real, const V: usize>(
    graph: &Graph<'_>,
    options: &GraphOptions<'_, T>,
    src: &[[T; V]],
    dst: &mut [[T; V]],
    weight: T,
    nodes: Range<usize>,
) -> T {
    let pinned = |f: &[u8], i: usize| f.get(i).is_some_and(|&b| b != 0);
    match (options.weights, options.fixed) {
        (Some(w), Some(f)) => sweep_rows(graph, src, dst, weight, nodes, Some(w), |i| pinned(f, i)),
        (Some(w), None) => sweep_rows(graph, src, dst, weight, nodes, Some(w), |_| false),
        (None, Some(f)) => sweep_rows(graph, src, dst, weight, nodes, None, |i| pinned(f, i)),
        (None, None) => sweep_rows(graph, src, dst, weight, nodes, None, |_| false),
    }
}

/// The loop of [`sweep_core`] for one combination: `weights` per directed edge (row slices
/// fetched once per node) or uniform (`w = 1`, the same arithmetic: `1 · x` is `x`), and
/// `fixed(i)`.
#[inline(always)]
fn sweep_rows<T: Real, const V: usize, F: Fn(usize) -> bool>(
    graph: &Graph<'_>,
    src: &[[T; V]],
    dst: &mut [[T; V]],
    weight: T,
    nodes: Range<usize>,
    weights: Option<&[T]>,
    fixed: F,
) -> T {
    let offsets = graph.offsets();
    let targets = graph.targets();
    let mut max_change = T::ZERO;
    for i in nodes {
        let Some(&x) = src.get(i) else { continue };
        let mut new = x;
        if !fixed(i) {
            let (Some(&a), Some(&b)) = (offsets.get(i), offsets.get(i + 1)) else {
                continue;
            };
            let (a, b) = (a as usize, b as usize);
            let row = targets.get(a..b).unwrap_or(&[]);
            let mut sum = [T::ZERO; V];
            let mut wsum = T::ZERO;
            let mut add = |w: T, j: u32| {
                if let Some(xj) = src.get(j as usize) {
                    wsum += w;
                    for (s, &c) in sum.iter_mut().zip(xj) {
                        *s += w * c;
                    }
                }
            };
            match weights {
                Some(ws) => {
                    let wrow = ws.get(a..b).unwrap_or(&[]);
                    for (&j, &w) in row.iter().zip(wrow) {
                        add(w, j);
                    }
                }
                None => {
                    for &j in row {
                        add(T::ONE, j);
                    }
                }
            }
            if wsum > T::ZERO {
                for ((y, &s), &c) in new.iter_mut().zip(&sum).zip(&x) {
                    *y = c + weight * (s / wsum - c);
                }
            }
        }
        for (&y, &c) in new.iter().zip(&x) {
            let change = (y - c).abs();
            if change > max_change {
                max_change = change;
            }
        }
        if let Some(out) = dst.get_mut(i) {
            *out = new;
        }
    }
    max_change
}

/// Taubin fairing of per-node values `[T; V]` (coordinates, displacements, any vector field)
/// on a CSR graph: `iterations` λ|μ iterations, each two Jacobi passes
///
/// ```text
/// x'_i = x_i + λ (Σ_j w_ij x_j / Σ_j w_ij − x_i)
/// x″_i = x'_i + μ (Σ_j w_ij x'_j / Σ_j w_ij − x'_i)
/// ```
///
/// over the neighbours `j` of `i` (Taubin 1995, the scheme Alter applies on structured
/// blocks). Fixed nodes and nodes without neighbours keep their values. `scratch` needs
/// [`graph_scratch_len`] items; its contents afterwards are unspecified. On `Err` nothing is
/// written.
///
/// # Errors
/// `LengthMismatch` (`values`, `options.weights`, `options.fixed`), `BufferTooSmall`
/// (`scratch`), `NonFinite` (`values`, `options.weights`, `lambda`, `mu`), `NonPositive`
/// (`options.weights`), `InvalidParameter` (`lambda ≤ 0`, `mu > 0`).
pub fn smooth_graph<T: Real, const V: usize>(
    graph: &Graph<'_>,
    values: &mut [[T; V]],
    params: TaubinParams<T>,
    iterations: usize,
    options: &GraphOptions<'_, T>,
    scratch: &mut [[T; V]],
) -> Result<FilterReport<T>> {
    let n = graph.node_count();
    if values.len() != n {
        return Err(Error::LengthMismatch {
            arg: "values",
            expected: n,
            actual: values.len(),
        });
    }
    if scratch.len() < n {
        return Err(Error::BufferTooSmall {
            arg: "scratch",
            needed: n,
            actual: scratch.len(),
        });
    }
    check_options(graph, options)?;
    params.validate()?;
    if let Some(position) = crate::real::first_non_finite(values) {
        return Err(Error::NonFinite {
            arg: "values",
            position,
        });
    }
    let mut last_change = T::ZERO;
    for _ in 0..iterations {
        let a = sweep_core(graph, options, values, scratch, params.lambda, 0..n);
        let b = sweep_core(graph, options, scratch, values, params.mu, 0..n);
        last_change = a.max(b);
    }
    Ok(FilterReport {
        iterations,
        last_change,
    })
}

/// One Jacobi pass over the nodes in `nodes` only: `dst_i = src_i + weight · (avg_i(src) −
/// src_i)` for every free node `i` in the range (`dst_i = src_i` for fixed nodes); `dst`
/// outside the range is not touched. Returns the largest component `|dst − src|` in the range.
/// For MPI codes: sweep the owned nodes, exchange halos of `src`, repeat with `μ`.
///
/// # Errors
/// `LengthMismatch` (`src`, `dst`, options), `IndexOutOfRange` (`nodes`), `NonFinite`
/// (`weight`, `src`, `options.weights`), `NonPositive` (`options.weights`).
pub fn graph_sweep<T: Real, const V: usize>(
    graph: &Graph<'_>,
    src: &[[T; V]],
    dst: &mut [[T; V]],
    weight: T,
    options: &GraphOptions<'_, T>,
    nodes: Range<usize>,
) -> Result<T> {
    let n = graph.node_count();
    if src.len() != n {
        return Err(Error::LengthMismatch {
            arg: "src",
            expected: n,
            actual: src.len(),
        });
    }
    if dst.len() != n {
        return Err(Error::LengthMismatch {
            arg: "dst",
            expected: n,
            actual: dst.len(),
        });
    }
    if nodes.end > n {
        return Err(Error::IndexOutOfRange {
            arg: "nodes.end",
            position: 0,
            index: nodes.end,
            bound: n + 1,
        });
    }
    if nodes.start > nodes.end {
        return Err(Error::IndexOutOfRange {
            arg: "nodes.start",
            position: 0,
            index: nodes.start,
            bound: nodes.end + 1,
        });
    }
    check_options(graph, options)?;
    if !weight.is_finite() {
        return Err(Error::NonFinite {
            arg: "weight",
            position: 0,
        });
    }
    if let Some(position) = crate::real::first_non_finite(src) {
        return Err(Error::NonFinite {
            arg: "src",
            position,
        });
    }
    Ok(sweep_core(graph, options, src, dst, weight, nodes))
}
