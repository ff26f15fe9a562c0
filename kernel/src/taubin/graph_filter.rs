//! Taubin λ|μ fairing on a CSR graph: the classic unstructured-mesh variant.

use core::ops::Range;

use crate::check;
use crate::error::{Error, Result};
use crate::graph::Graph;
use crate::real::Real;
use crate::vector;

use super::structured::FilterReport;
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
    check::len("points", points.len(), n)?;
    check::len("weights", weights.len(), graph.edge_count())?;
    check::finite_items("points", points)?;
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
        check::len("options.weights", w.len(), graph.edge_count())?;
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
    check::mask("options.fixed", options.fixed, graph.node_count())
}

/// One Jacobi pass: the graph, the options, the pass weight (λ or μ) and whether the largest
/// change is wanted (only the last iteration's is reported, so earlier passes skip it).
#[derive(Clone, Copy)]
struct Pass<'a, T> {
    graph: &'a Graph<'a>,
    options: &'a GraphOptions<'a, T>,
    weight: T,
    track: bool,
}

/// One Jacobi pass over `nodes` (no validation). Returns the largest component change
/// (zero when `pass.track` is off).
///
/// The "weights given?", "fixed mask given?" and "change wanted?" decisions are taken once
/// here, not per edge and node: each combination runs its own loop ([`sweep_rows`]).
fn sweep_core<T: Real, const V: usize>(
    pass: Pass<'_, T>,
    src: &[[T; V]],
    dst: &mut [[T; V]],
    nodes: Range<usize>,
) -> T {
    if pass.track {
        sweep_fixed::<T, V, true>(pass, src, dst, nodes)
    } else {
        sweep_fixed::<T, V, false>(pass, src, dst, nodes)
    }
}

/// [`sweep_core`] for one value of `TRACK`: picks the weights / fixed-mask loop.
#[inline(always)]
fn sweep_fixed<T: Real, const V: usize, const TRACK: bool>(
    pass: Pass<'_, T>,
    src: &[[T; V]],
    dst: &mut [[T; V]],
    nodes: Range<usize>,
) -> T {
    let (g, w) = (pass.graph, pass.weight);
    let free = core::iter::repeat(false);
    let range = nodes.clone();
    match (pass.options.weights, pass.options.fixed) {
        (Some(ws), Some(f)) => sweep_rows::<_, V, _, TRACK>(
            g,
            src,
            dst,
            w,
            range,
            Some(ws),
            mask_flags(f, nodes.clone()),
        ),
        (Some(ws), None) => sweep_rows::<_, V, _, TRACK>(g, src, dst, w, range, Some(ws), free),
        (None, Some(f)) => {
            sweep_rows::<_, V, _, TRACK>(g, src, dst, w, range, None, mask_flags(f, nodes.clone()))
        }
        (None, None) => sweep_rows::<_, V, _, TRACK>(g, src, dst, w, range, None, free),
    }
}

/// The fixed mask as one flag per node from `nodes.start` on (false beyond the mask's end,
/// as `get` would say), so the loop needs no node index.
fn mask_flags(mask: &[u8], nodes: Range<usize>) -> impl Iterator<Item = bool> + '_ {
    mask.get(nodes.start..)
        .unwrap_or(&[])
        .iter()
        .map(|&b| b != 0)
        .chain(core::iter::repeat(false))
}

/// `count` ones summed in `T`, as the weighted loop sums uniform weights: `count` while it
/// is exactly representable, and `2^p` beyond (adding 1 to `2^p` rounds back to `2^p`: f32
/// rows of more than 2²⁴ neighbours).
#[inline(always)]
fn ones_sum<T: Real>(count: usize) -> T {
    let limit = usize::try_from(1u64 << T::MANTISSA_DIGITS).unwrap_or(usize::MAX);
    T::from_usize(count.min(limit))
}

/// The loop of [`sweep_core`] for one combination: `weights` per directed edge (row slices
/// fetched once per node) or uniform (`w = 1`: the weight sum is the neighbour count and
/// `1 · x` is `x`, so the loop only adds), and `fixed` (one flag per node of the range). Offsets,
/// values and outputs are walked as contiguous slices of the range; the largest change is
/// kept per component and reduced at the end (a maximum: the order does not matter), or not
/// at all without `TRACK`.
#[inline(always)]
fn sweep_rows<T: Real, const V: usize, F: Iterator<Item = bool>, const TRACK: bool>(
    graph: &Graph<'_>,
    src: &[[T; V]],
    dst: &mut [[T; V]],
    weight: T,
    nodes: Range<usize>,
    weights: Option<&[T]>,
    fixed: F,
) -> T {
    let targets = graph.targets();
    let mut max_change = [T::ZERO; V];
    let (Some(offsets), Some(xs), Some(out)) = (
        graph
            .offsets()
            .get(nodes.start..nodes.end.saturating_add(1)),
        src.get(nodes.clone()),
        dst.get_mut(nodes.clone()),
    ) else {
        return T::ZERO;
    };
    for ((pinned, (pair, &x)), y) in fixed.zip(offsets.windows(2).zip(xs)).zip(out.iter_mut()) {
        let mut new = x;
        if let (false, &[a, b]) = (pinned, pair) {
            let (a, b) = (a as usize, b as usize);
            let row = targets.get(a..b).unwrap_or(&[]);
            let mut sum = [T::ZERO; V];
            let wsum = match weights {
                Some(ws) => {
                    let wrow = ws.get(a..b).unwrap_or(&[]);
                    let mut wsum = T::ZERO;
                    for (&j, &w) in row.iter().zip(wrow) {
                        if let Some(xj) = src.get(j as usize) {
                            wsum += w;
                            for (s, &c) in sum.iter_mut().zip(xj) {
                                *s += w * c;
                            }
                        }
                    }
                    wsum
                }
                None => {
                    let mut missing = 0usize;
                    for &j in row {
                        match src.get(j as usize) {
                            Some(xj) => {
                                for (s, &c) in sum.iter_mut().zip(xj) {
                                    *s += c;
                                }
                            }
                            None => missing += 1,
                        }
                    }
                    ones_sum(row.len() - missing)
                }
            };
            if wsum > T::ZERO {
                for ((n, &s), &c) in new.iter_mut().zip(&sum).zip(&x) {
                    *n = c + weight * (s / wsum - c);
                }
            }
        }
        if TRACK {
            for ((&n, &c), m) in new.iter().zip(&x).zip(&mut max_change) {
                let change = (n - c).abs();
                *m = if change > *m { change } else { *m };
            }
        }
        *y = new;
    }
    max_change
        .iter()
        .fold(T::ZERO, |m, &c| if c > m { c } else { m })
}

/// Candidate lags of the fused λ|μ iteration (rows), smallest first: the plan takes the first
/// one that leaves few deferred rows. The largest keeps the rows in flight (values, scratch
/// and graph rows of the lag) within a typical L2 cache.
const LAGS: [usize; 10] = [16, 32, 64, 128, 256, 512, 1024, 2048, 4096, 8192];

/// The smallest candidate lag.
const FIRST_LAG: usize = 16;

/// Runs of deferred rows a fused plan can hold (on the stack: no allocation).
const MAX_RUNS: usize = 16;

/// λ rows swept per step of the fused iteration before the μ pass catches up.
const BLOCK: usize = 256;

/// How one λ|μ iteration is fused for a graph (see [`plan_fused`]).
struct FusedPlan {
    /// The μ pass runs `lag` rows behind the λ pass.
    lag: usize,
    /// Sorted, disjoint runs `[start, end)` of deferred rows: rows with a neighbour more than
    /// `lag` rows ahead. Their μ update waits for the end of the λ pass.
    runs: [(usize, usize); MAX_RUNS],
    run_count: usize,
}

impl FusedPlan {
    fn runs(&self) -> &[(usize, usize)] {
        self.runs.get(..self.run_count).unwrap_or(&[])
    }
}

/// The smallest and largest neighbour of a row (`(u32::MAX, 0)` for an empty row).
fn row_span(row: &[u32]) -> (usize, usize) {
    let (lo, hi) = row
        .iter()
        .fold((u32::MAX, 0), |(lo, hi), &j| (lo.min(j), hi.max(j)));
    (lo as usize, hi as usize)
}

/// The number of candidate lags below `reach` (those for which a row of that reach is
/// deferred). The candidates are `16 · 2^c`.
fn lag_bucket(reach: usize) -> usize {
    if reach <= FIRST_LAG {
        0
    } else {
        ((usize::BITS - ((reach - 1) >> 4).leading_zeros()) as usize).min(LAGS.len())
    }
}

/// Plans the fused λ|μ iteration, or `None` when the numbering is not banded enough (or the
/// graph too small) for it to pay.
///
/// With the μ pass `lag` rows behind the λ pass, μ row `m` may run once the λ pass has done
/// every row up to `m + lag`, if (a) all neighbours of `m` are at most `m + lag` (else `m` is
/// *deferred* to the end of the iteration), and (b) no row beyond `m + lag`, still to be read
/// by the λ pass, has `m` as a neighbour (its old value would be overwritten). (b) holds for
/// symmetric graphs by (a); for any graph it is checked here: every neighbour `j < k − lag` of
/// a row `k` must be deferred, else there is no plan. Two reads of the graph, once per call.
fn plan_fused(graph: &Graph<'_>) -> Option<FusedPlan> {
    let n = graph.node_count();
    // Pass 1: for every candidate lag, the deferred rows and the runs they form. Row `i` is
    // deferred for the candidates below `bucket(reach)`; a run starts for the candidates
    // deferred at `i` but not at `i − 1` (counted as a difference, summed afterwards).
    let mut deferred = [0usize; LAGS.len() + 1];
    let mut run_starts = [0isize; LAGS.len() + 1];
    let mut previous = 0usize;
    for (i, _, row) in graph.rows() {
        let b = lag_bucket(row_span(row).1.saturating_sub(i));
        if let Some(d) = deferred.get_mut(b) {
            *d += 1;
        }
        if b > previous {
            if let Some(r) = run_starts.get_mut(previous) {
                *r += 1;
            }
            if let Some(r) = run_starts.get_mut(b) {
                *r -= 1;
            }
        }
        previous = b;
    }
    // Candidate c defers the rows of buckets above c.
    let mut lag = None;
    let (mut rows_above, mut runs) = (n, 0isize);
    for (c, &candidate) in LAGS.iter().enumerate() {
        rows_above -= deferred.get(c).copied().unwrap_or(0);
        runs += run_starts.get(c).copied().unwrap_or(0);
        if runs <= MAX_RUNS as isize && rows_above <= n / 8 && n >= 4 * (candidate + BLOCK) {
            lag = Some(candidate);
            break;
        }
    }
    let lag = lag?;
    // Pass 2: record the runs and check (b).
    let mut plan = FusedPlan {
        lag,
        runs: [(0, 0); MAX_RUNS],
        run_count: 0,
    };
    let mut open: Option<usize> = None;
    for (k, _, row) in graph.rows() {
        let (lo, hi) = row_span(row);
        let far = hi.saturating_sub(k) > lag;
        match (far, open) {
            (true, None) => open = Some(k),
            (false, Some(start)) => {
                *plan.runs.get_mut(plan.run_count)? = (start, k);
                plan.run_count += 1;
                open = None;
            }
            _ => {}
        }
        // Neighbours more than `lag` rows behind must be deferred rows.
        if lo.saturating_add(lag) < k {
            for &j in row {
                let j = j as usize;
                if j.saturating_add(lag) < k
                    && open.is_none_or(|s| j < s)
                    && !plan.runs().iter().any(|&(s, e)| (s..e).contains(&j))
                {
                    return None;
                }
            }
        }
    }
    if let Some(start) = open {
        *plan.runs.get_mut(plan.run_count)? = (start, n);
        plan.run_count += 1;
    }
    Some(plan)
}

/// The μ pass (`scratch → values`) over `nodes`, skipping the deferred runs.
fn mu_outside_runs<T: Real, const V: usize>(
    mu: Pass<'_, T>,
    scratch: &[[T; V]],
    values: &mut [[T; V]],
    plan: &FusedPlan,
    nodes: Range<usize>,
) -> T {
    let mut change = T::ZERO;
    let mut at = nodes.start;
    for &(s, e) in plan.runs() {
        if e <= at {
            continue;
        }
        if s >= nodes.end {
            break;
        }
        if s > at {
            change = change.max(sweep_core(mu, scratch, values, at..s));
        }
        at = e;
    }
    if at < nodes.end {
        change = change.max(sweep_core(mu, scratch, values, at..nodes.end));
    }
    change
}

/// One λ|μ iteration with the graph read once: the μ pass follows the λ pass `plan.lag` rows
/// behind, so the rows it needs are still in cache; deferred rows get their μ update at the
/// end. Every row is updated by the same arithmetic from the same inputs as in two separate
/// passes: the results are bit-identical. Returns the largest changes of the two passes.
fn fused_iteration<T: Real, const V: usize>(
    lambda: Pass<'_, T>,
    mu: Pass<'_, T>,
    values: &mut [[T; V]],
    scratch: &mut [[T; V]],
    plan: &FusedPlan,
) -> (T, T) {
    let n = lambda.graph.node_count();
    let (mut a, mut b) = (T::ZERO, T::ZERO);
    let mut m = 0;
    let mut k0 = 0;
    while k0 < n {
        let k1 = k0.saturating_add(BLOCK).min(n);
        a = a.max(sweep_core(lambda, values, scratch, k0..k1));
        k0 = k1;
        // λ has done rows < k1: μ row m is ready when m + lag < k1.
        let ready = k1.saturating_sub(plan.lag);
        if k1 < n && ready > m {
            b = b.max(mu_outside_runs(mu, scratch, values, plan, m..ready));
            m = ready;
        }
    }
    // The λ pass is complete: the rest, then the deferred rows the stream skipped.
    b = b.max(sweep_core(mu, scratch, values, m..n));
    for &(s, e) in plan.runs() {
        let e = e.min(m);
        if s < e {
            b = b.max(sweep_core(mu, scratch, values, s..e));
        }
    }
    (a, b)
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
    check::len("values", values.len(), n)?;
    check::buffer("scratch", scratch.len(), n)?;
    check_options(graph, options)?;
    params.validate()?;
    check::finite_items("values", values)?;
    let mut last_change = T::ZERO;
    let plan = if iterations >= 2 {
        plan_fused(graph)
    } else {
        None
    };
    for it in 0..iterations {
        // Only the last iteration's change is reported.
        let track = it + 1 == iterations;
        let pass = |weight| Pass {
            graph,
            options,
            weight,
            track,
        };
        let (lambda, mu) = (pass(params.lambda), pass(params.mu));
        let (a, b) = match &plan {
            Some(plan) => fused_iteration(lambda, mu, values, scratch, plan),
            None => (
                sweep_core(lambda, values, scratch, 0..n),
                sweep_core(mu, scratch, values, 0..n),
            ),
        };
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
    check::len("src", src.len(), n)?;
    check::len("dst", dst.len(), n)?;
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
    check::scalar("weight", weight)?;
    check::finite_items("src", src)?;
    let pass = Pass {
        graph,
        options,
        weight,
        track: true,
    };
    Ok(sweep_core(pass, src, dst, nodes))
}

#[cfg(test)]
mod tests {
    use super::*;

    const N: usize = 1200;

    /// A ring `0 – 1 – … – n−1 – 0` (`n ≤ N`; the offsets are `..=n`); without `closing`,
    /// row 0 does not list `n − 1` (but `n − 1` still lists 0: not symmetric).
    fn ring(n: usize, closing: bool) -> ([u32; N + 1], [u32; 2 * N], usize) {
        let mut offsets = [0u32; N + 1];
        let mut targets = [0u32; 2 * N];
        let mut e = 0;
        for i in 0..n {
            let prev = (i + n - 1) % n;
            let next = (i + 1) % n;
            for j in [prev, next] {
                if closing || !(i == 0 && j == n - 1) {
                    targets[e] = j as u32;
                    e += 1;
                }
            }
            offsets[i + 1] = e as u32;
        }
        (offsets, targets, e)
    }

    #[test]
    fn a_ring_is_fused_with_its_closing_row_deferred() {
        let (offsets, targets, e) = ring(N, true);
        let graph = Graph::new(&offsets, &targets[..e]).unwrap();
        let plan = plan_fused(&graph).unwrap();
        assert_eq!(plan.lag, FIRST_LAG);
        assert_eq!(plan.runs(), &[(0, 1)]);
        // Too small a graph is not worth planning.
        let (offsets, targets, e) = ring(100, true);
        let small = Graph::new(&offsets[..101], &targets[..e]).unwrap();
        assert!(plan_fused(&small).is_none());
    }

    #[test]
    fn a_far_one_way_edge_to_an_undeferred_row_prevents_fusion() {
        let (offsets, targets, e) = ring(N, false);
        let graph = Graph::new(&offsets, &targets[..e]).unwrap();
        assert!(plan_fused(&graph).is_none());
    }

    #[test]
    fn lag_buckets_count_the_candidates_below_the_reach() {
        assert_eq!(lag_bucket(0), 0);
        assert_eq!(lag_bucket(16), 0);
        assert_eq!(lag_bucket(17), 1);
        assert_eq!(lag_bucket(32), 1);
        assert_eq!(lag_bucket(33), 2);
        assert_eq!(lag_bucket(8192), LAGS.len() - 1);
        assert_eq!(lag_bucket(8193), LAGS.len());
        assert_eq!(lag_bucket(usize::MAX), LAGS.len());
        for reach in 0..20_000 {
            let below = LAGS.iter().filter(|&&l| l < reach).count();
            assert_eq!(lag_bucket(reach), below, "reach {reach}");
        }
    }

    #[test]
    fn ones_sum_matches_repeated_addition() {
        let mut s = 0.0f32;
        for count in 0..=(1usize << 24) + 3 {
            if count % 4096 == 0 || count > (1 << 24) - 3 {
                assert_eq!(ones_sum::<f32>(count).to_bits(), s.to_bits(), "{count}");
            }
            s += 1.0;
        }
        assert_eq!(ones_sum::<f64>(1 << 30), (1u64 << 30) as f64);
    }
}
