//! Taubin fairing on a CSR graph: bitwise parity with the naive reference, the no-shrinkage
//! property on a closed curve (λ|μ versus λ-only), sweeps and input errors.

use std::collections::BTreeSet;

use deform_host_tests::taubin_ref;
use deform_kernel::taubin::{
    graph_scratch_len, graph_sweep, inverse_distance_weights, smooth_graph, GraphOptions,
    TaubinParams,
};
use deform_kernel::{Error, Graph};
use proptest::prelude::*;

/// Symmetric CSR from an undirected edge list (neighbours sorted).
fn csr(n: usize, edges: &[(usize, usize)]) -> (Vec<u32>, Vec<u32>) {
    let mut adj = vec![BTreeSet::new(); n];
    for &(a, b) in edges {
        if a != b {
            adj[a].insert(b as u32);
            adj[b].insert(a as u32);
        }
    }
    let mut offsets = vec![0u32];
    let mut targets = Vec::new();
    for row in &adj {
        targets.extend(row.iter().copied());
        offsets.push(targets.len() as u32);
    }
    (offsets, targets)
}

fn ring(n: usize) -> (Vec<u32>, Vec<u32>) {
    let edges: Vec<(usize, usize)> = (0..n).map(|i| (i, (i + 1) % n)).collect();
    csr(n, &edges)
}

fn polygon_area(p: &[[f64; 2]]) -> f64 {
    let n = p.len();
    (0..n)
        .map(|i| {
            let a = p[i];
            let b = p[(i + 1) % n];
            a[0] * b[1] - b[0] * a[1]
        })
        .sum::<f64>()
        / 2.0
}

#[test]
fn closed_curve_keeps_its_area_with_lambda_mu_and_shrinks_with_lambda_only() {
    let n = 256;
    let (offsets, targets) = ring(n);
    let graph = Graph::new(&offsets, &targets).unwrap();
    let circle: Vec<[f64; 2]> = (0..n)
        .map(|i| {
            let t = 2.0 * std::f64::consts::PI * i as f64 / n as f64;
            [t.cos(), t.sin()]
        })
        .collect();
    let a0 = polygon_area(&circle);
    let mut scratch = vec![[0.0; 2]; graph_scratch_len(&graph)];
    let run = |params: TaubinParams<f64>, scratch: &mut Vec<[f64; 2]>| {
        let mut p = circle.clone();
        smooth_graph(
            &graph,
            &mut p,
            params,
            30,
            &GraphOptions::default(),
            scratch,
        )
        .unwrap();
        (polygon_area(&p) - a0) / a0
    };
    let taubin = run(TaubinParams::paper(), &mut scratch);
    let lambda_only = run(
        TaubinParams {
            lambda: 0.330,
            mu: 0.0,
        },
        &mut scratch,
    );
    println!(
        "ring of {n}: relative area change after 30 iterations: λ|μ {taubin:+.3e}, λ-only {lambda_only:+.3e}"
    );
    assert!(taubin.abs() <= 1e-4);
    assert!(lambda_only < -1e-3);
}

#[test]
fn noise_on_a_closed_curve_is_removed_without_shrinking() {
    let n = 256;
    let (offsets, targets) = ring(n);
    let graph = Graph::new(&offsets, &targets).unwrap();
    // Alternating radial noise (the highest frequency, k = 2).
    let noisy: Vec<[f64; 2]> = (0..n)
        .map(|i| {
            let t = 2.0 * std::f64::consts::PI * i as f64 / n as f64;
            let r = 1.0 + if i % 2 == 0 { 0.01 } else { -0.01 };
            [r * t.cos(), r * t.sin()]
        })
        .collect();
    let radial_dev = |p: &[[f64; 2]]| {
        p.iter()
            .map(|q| ((q[0] * q[0] + q[1] * q[1]).sqrt() - 1.0).abs())
            .fold(0.0, f64::max)
    };
    let mut p = noisy.clone();
    let mut scratch = vec![[0.0; 2]; n];
    smooth_graph(
        &graph,
        &mut p,
        TaubinParams::paper(),
        10,
        &GraphOptions::default(),
        &mut scratch,
    )
    .unwrap();
    println!(
        "radial noise {:.3e} -> {:.3e} after 10 iterations",
        radial_dev(&noisy),
        radial_dev(&p)
    );
    // k = 2 mode: f(2) = (1 − 2λ)(1 − 2μ) = 0.34 · 1.668 = 0.567 per iteration, so 10
    // iterations leave 0.34 % of the noise (plus the tiny pass-band change of the circle).
    let f2 = TaubinParams::<f64>::paper().transfer(2.0);
    assert!(radial_dev(&p) < 1.5 * f2.powi(10) * radial_dev(&noisy));
}

fn random_graph(n: usize, m: usize, seed: u64) -> (Vec<u32>, Vec<u32>) {
    let mut s = seed;
    let mut next = || {
        s = s
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (s >> 33) as usize
    };
    let edges: Vec<(usize, usize)> = (0..m).map(|_| (next() % n, next() % n)).collect();
    csr(n, &edges)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// Bitwise parity with the reference for random graphs (isolated nodes included), random
    /// fixed masks, uniform / random / inverse-distance weights, f64 and f32.
    #[test]
    fn parity_with_reference(
        n in 1usize..40, m in 0usize..120, seed in any::<u64>(),
        weighting in 0u8..3, use_fixed in any::<bool>(),
        lambda in 0.05f64..0.9, mu in -0.95f64..0.0, iterations in 0usize..6,
        values in prop::collection::vec(prop::array::uniform3(-5.0f64..5.0), 40),
    ) {
        let (offsets, targets) = random_graph(n, m, seed);
        let graph = Graph::new(&offsets, &targets).unwrap();
        let values = &values[..n];
        let fixed: Vec<u8> = (0..n).map(|i| u8::from((i as u64 ^ seed) % 4 == 0)).collect();
        let fixed_opt = use_fixed.then_some(&fixed[..]);
        let weights: Option<Vec<f64>> = match weighting {
            0 => None,
            1 => Some((0..targets.len()).map(|e| 0.1 + ((e as u64 * 7919 + seed) % 97) as f64 / 10.0).collect()),
            _ => {
                // Inverse distance needs distinct neighbours: the values are random reals.
                let mut w = vec![0.0; targets.len()];
                if inverse_distance_weights(&graph, values, &mut w).is_err() {
                    return Ok(());
                }
                for (i, first, row) in graph.rows() {
                    for (k, &j) in row.iter().enumerate() {
                        let want = 1.0 / taubin_ref::dist(values[i], values[j as usize]);
                        prop_assert_eq!(w[first + k].to_bits(), want.to_bits());
                    }
                }
                Some(w)
            }
        };
        let opts = GraphOptions { weights: weights.as_deref(), fixed: fixed_opt };
        let mut got = values.to_vec();
        let mut scratch = vec![[0.0; 3]; n];
        smooth_graph(&graph, &mut got, TaubinParams { lambda, mu }, iterations, &opts, &mut scratch).unwrap();
        let want = taubin_ref::graph_filter(&offsets, &targets, weights.as_deref(), fixed_opt, values, lambda, mu, iterations);
        for (i, (a, b)) in got.iter().zip(&want).enumerate() {
            for c in 0..3 {
                prop_assert_eq!(a[c].to_bits(), b[c].to_bits(), "node {} comp {}", i, c);
            }
        }

        // f32, V = 1.
        let v32: Vec<[f32; 1]> = values.iter().map(|v| [v[0] as f32]).collect();
        let w32: Option<Vec<f32>> = weights.as_ref().map(|w| w.iter().map(|&x| x as f32).collect());
        let opts32 = GraphOptions { weights: w32.as_deref(), fixed: fixed_opt };
        let mut got32 = v32.clone();
        let mut scratch32 = vec![[0.0f32; 1]; n];
        let (l32, m32) = (lambda as f32, mu as f32);
        smooth_graph(&graph, &mut got32, TaubinParams { lambda: l32, mu: m32 }, iterations, &opts32, &mut scratch32).unwrap();
        let want32 = taubin_ref::graph_filter(&offsets, &targets, w32.as_deref(), fixed_opt, &v32, l32, m32, iterations);
        for (a, b) in got32.iter().zip(&want32) {
            prop_assert_eq!(a[0].to_bits(), b[0].to_bits());
        }
    }

    /// Sweeping two node ranges equals one sweep over all nodes; dst outside the range is left
    /// alone; fixed nodes are copied.
    #[test]
    fn sweep_over_ranges(n in 2usize..30, m in 0usize..80, seed in any::<u64>(), cut in 0usize..30, w in -0.5f64..0.5) {
        let (offsets, targets) = random_graph(n, m, seed);
        let graph = Graph::new(&offsets, &targets).unwrap();
        let cut = cut.min(n);
        let src: Vec<[f64; 2]> = (0..n).map(|i| [i as f64 * 0.37 % 1.3, (i * i) as f64 % 2.1]).collect();
        let fixed: Vec<u8> = (0..n).map(|i| u8::from(i % 5 == 1)).collect();
        let opts = GraphOptions { weights: None, fixed: Some(&fixed) };
        let mut a = vec![[9.0; 2]; n];
        let c1 = graph_sweep(&graph, &src, &mut a, w, &opts, 0..cut).unwrap();
        for x in &a[cut..] {
            prop_assert_eq!(*x, [9.0; 2]);
        }
        let c2 = graph_sweep(&graph, &src, &mut a, w, &opts, cut..n).unwrap();
        let mut b = vec![[9.0; 2]; n];
        let c = graph_sweep(&graph, &src, &mut b, w, &opts, 0..n).unwrap();
        prop_assert_eq!(&a, &b);
        prop_assert_eq!(c, c1.max(c2));
        for i in 0..n {
            if fixed[i] != 0 {
                prop_assert_eq!(a[i], src[i]);
            }
        }
    }
}

/// A `nu × nv` grid with the diagonal of a triangulation, periodic in `i` and/or `j` (a
/// torus numbers its last band next to its first: far edges both ways), plus `extra` edges
/// between random nodes: symmetric, or (`one_way`) only from the later node to the earlier
/// one, so a row reads a far earlier node that reads nothing far (a non-symmetric graph).
#[allow(clippy::too_many_arguments)]
fn banded_graph(
    nu: usize,
    nv: usize,
    wrap_i: bool,
    wrap_j: bool,
    extra: usize,
    one_way: bool,
    seed: u64,
) -> (Vec<u32>, Vec<u32>) {
    let n = nu * nv;
    let mut adj = vec![BTreeSet::new(); n];
    let id = |i: usize, j: usize| (i % nu) + nu * (j % nv);
    for j in 0..nv {
        for i in 0..nu {
            let a = id(i, j);
            let mut link = |b: usize| {
                if a != b {
                    adj[a].insert(b as u32);
                    adj[b].insert(a as u32);
                }
            };
            if i + 1 < nu || wrap_i {
                link(id(i + 1, j));
            }
            if j + 1 < nv || wrap_j {
                link(id(i, j + 1));
                if i + 1 < nu || wrap_i {
                    link(id(i + 1, j + 1));
                }
            }
        }
    }
    let mut s = seed;
    for _ in 0..extra {
        let mut next = || {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (s >> 33) as usize % n
        };
        let (a, b) = (next(), next());
        if a != b {
            let (lo, hi) = (a.min(b), a.max(b));
            adj[hi].insert(lo as u32);
            if !one_way {
                adj[lo].insert(hi as u32);
            }
        }
    }
    let mut offsets = vec![0u32];
    let mut targets = Vec::new();
    for row in &adj {
        // Unsorted rows: the filter must not rely on sorted neighbours.
        let mut r: Vec<u32> = row.iter().copied().collect();
        r.reverse();
        targets.extend(r);
        offsets.push(targets.len() as u32);
    }
    (offsets, targets)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]

    /// Graphs large and banded enough for the fused λ|μ iteration (the μ pass running a few
    /// rows behind the λ pass, rows with far neighbours deferred), and non-symmetric ones where
    /// it must not be used: values bitwise equal to the reference, and the reported change
    /// equal to the one of two separate sweeps in the last iteration.
    #[test]
    fn banded_graphs_parity_with_reference_and_sweeps(
        nu in 4usize..70, rows in 1300usize..2600, wrap_i in any::<bool>(), wrap_j in any::<bool>(),
        extra in 0usize..12, one_way in any::<bool>(), seed in any::<u64>(),
        weighting in 0u8..2, use_fixed in any::<bool>(), iterations in 0usize..5,
    ) {
        let nv = rows.div_ceil(nu).max(2);
        let (offsets, targets) = banded_graph(nu, nv, wrap_i, wrap_j, extra, one_way, seed);
        let graph = Graph::new(&offsets, &targets).unwrap();
        let n = graph.node_count();
        let values: Vec<[f64; 3]> = (0..n)
            .map(|i| {
                let t = (i as u64).wrapping_mul(2654435761) ^ seed;
                [(t % 1000) as f64 / 300.0, ((t >> 10) % 777) as f64 / 100.0, i as f64 * 1e-3]
            })
            .collect();
        let fixed: Vec<u8> = (0..n).map(|i| u8::from((i as u64 ^ seed) % 7 == 0)).collect();
        let fixed_opt = use_fixed.then_some(&fixed[..]);
        let weights: Option<Vec<f64>> = (weighting == 1)
            .then(|| (0..targets.len()).map(|e| 0.1 + ((e as u64 * 7919 + seed) % 97) as f64 / 10.0).collect());
        let opts = GraphOptions { weights: weights.as_deref(), fixed: fixed_opt };
        let (lambda, mu) = (0.33, -0.34);
        let mut got = values.clone();
        let mut scratch = vec![[0.0; 3]; n];
        let report = smooth_graph(&graph, &mut got, TaubinParams { lambda, mu }, iterations, &opts, &mut scratch).unwrap();
        let want = taubin_ref::graph_filter(&offsets, &targets, weights.as_deref(), fixed_opt, &values, lambda, mu, iterations);
        for (i, (a, b)) in got.iter().zip(&want).enumerate() {
            for c in 0..3 {
                prop_assert_eq!(a[c].to_bits(), b[c].to_bits(), "node {} comp {}", i, c);
            }
        }
        let mut x = values.clone();
        let mut y = vec![[0.0; 3]; n];
        let mut last = 0.0f64;
        for _ in 0..iterations {
            let a = graph_sweep(&graph, &x, &mut y, lambda, &opts, 0..n).unwrap();
            let b = graph_sweep(&graph, &y, &mut x, mu, &opts, 0..n).unwrap();
            last = a.max(b);
        }
        prop_assert_eq!(&x, &got);
        prop_assert_eq!(report.last_change.to_bits(), last.to_bits());
        prop_assert_eq!(report.iterations, iterations);

        // f32, V = 1.
        let v32: Vec<[f32; 1]> = values.iter().map(|v| [v[0] as f32]).collect();
        let w32: Option<Vec<f32>> = weights.as_ref().map(|w| w.iter().map(|&x| x as f32).collect());
        let opts32 = GraphOptions { weights: w32.as_deref(), fixed: fixed_opt };
        let mut got32 = v32.clone();
        let mut scratch32 = vec![[0.0f32; 1]; n];
        smooth_graph(&graph, &mut got32, TaubinParams { lambda: 0.33f32, mu: -0.34f32 }, iterations, &opts32, &mut scratch32).unwrap();
        let want32 = taubin_ref::graph_filter(&offsets, &targets, w32.as_deref(), fixed_opt, &v32, 0.33f32, -0.34f32, iterations);
        for (a, b) in got32.iter().zip(&want32) {
            prop_assert_eq!(a[0].to_bits(), b[0].to_bits());
        }
    }
}

#[test]
fn bad_inputs_give_typed_errors_and_leave_buffers_unchanged() {
    let (offsets, targets) = ring(6);
    let graph = Graph::new(&offsets, &targets).unwrap();
    let good: Vec<[f64; 2]> = (0..6).map(|i| [i as f64, 1.0]).collect();
    let p = TaubinParams::<f64>::paper();
    let run = |values: &[[f64; 2]],
               params: TaubinParams<f64>,
               opts: &GraphOptions<f64>,
               scratch_len: usize| {
        let mut v = values.to_vec();
        let mut s = vec![[0.5; 2]; scratch_len];
        let r = smooth_graph(&graph, &mut v, params, 2, opts, &mut s);
        let bits = |x: &[[f64; 2]]| x.iter().flatten().map(|c| c.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&v), bits(values));
        assert!(s.iter().all(|x| *x == [0.5; 2]));
        r.unwrap_err()
    };
    let o = GraphOptions::default();
    let mut nan = good.clone();
    nan[4][1] = f64::NAN;
    assert_eq!(
        run(&nan, p, &o, 6),
        Error::NonFinite {
            arg: "values",
            position: 4
        }
    );
    assert_eq!(
        run(&good[..5], p, &o, 6),
        Error::LengthMismatch {
            arg: "values",
            expected: 6,
            actual: 5
        }
    );
    assert_eq!(
        run(&good, p, &o, 2),
        Error::BufferTooSmall {
            arg: "scratch",
            needed: 6,
            actual: 2
        }
    );
    let mut w = vec![1.0; 12];
    w[7] = 0.0;
    assert_eq!(
        run(
            &good,
            p,
            &GraphOptions {
                weights: Some(&w),
                fixed: None
            },
            6
        ),
        Error::NonPositive {
            arg: "options.weights",
            position: 7
        }
    );
    w[7] = f64::INFINITY;
    assert_eq!(
        run(
            &good,
            p,
            &GraphOptions {
                weights: Some(&w),
                fixed: None
            },
            6
        ),
        Error::NonFinite {
            arg: "options.weights",
            position: 7
        }
    );
    assert_eq!(
        run(
            &good,
            p,
            &GraphOptions {
                weights: Some(&w[..3]),
                fixed: None
            },
            6
        ),
        Error::LengthMismatch {
            arg: "options.weights",
            expected: 12,
            actual: 3
        }
    );
    let fixed = [1u8; 2];
    assert_eq!(
        run(
            &good,
            p,
            &GraphOptions {
                weights: None,
                fixed: Some(&fixed)
            },
            6
        ),
        Error::LengthMismatch {
            arg: "options.fixed",
            expected: 6,
            actual: 2
        }
    );
    assert!(matches!(
        run(
            &good,
            TaubinParams {
                lambda: -0.1,
                mu: -0.2
            },
            &o,
            6
        ),
        Error::InvalidParameter { arg: "lambda", .. }
    ));

    // Inverse-distance weights: coincident neighbours.
    let mut pts = good.clone();
    pts[3] = pts[2];
    let mut weights = vec![-1.0; 12];
    assert!(matches!(
        inverse_distance_weights(&graph, &pts, &mut weights),
        Err(Error::ZeroLengthEdge { .. })
    ));
    assert!(weights.iter().all(|&x| x == -1.0));
    assert_eq!(
        inverse_distance_weights(&graph, &nan, &mut weights),
        Err(Error::NonFinite {
            arg: "points",
            position: 4
        })
    );
    assert!(weights.iter().all(|&x| x == -1.0));

    // Sweep range errors.
    let mut dst = vec![[3.0; 2]; 6];
    assert!(matches!(
        graph_sweep(&graph, &good, &mut dst, 0.3, &o, 2..7),
        Err(Error::IndexOutOfRange {
            arg: "nodes.end",
            index: 7,
            ..
        })
    ));
    #[allow(clippy::reversed_empty_ranges)]
    let reversed = 4..2;
    assert!(matches!(
        graph_sweep(&graph, &good, &mut dst, 0.3, &o, reversed),
        Err(Error::IndexOutOfRange {
            arg: "nodes.start",
            ..
        })
    ));
    assert_eq!(
        graph_sweep(&graph, &good, &mut dst, f64::NAN, &o, 0..6),
        Err(Error::NonFinite {
            arg: "weight",
            position: 0
        })
    );
    assert!(dst.iter().all(|x| *x == [3.0; 2]));
}
