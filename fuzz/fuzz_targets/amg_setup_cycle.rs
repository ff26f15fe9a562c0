//! Target 10: the multigrid hierarchy and its V-cycle on arbitrary small spring systems and
//! options: no panic; the size query is exact (buffers of exactly that size work, one entry
//! less is a typed error that leaves both buffers untouched); the preconditioner is symmetric
//! and positive on the free nodes and zero on the fixed ones; the AMG-CG solution matches the
//! dense reference solve; repeated setups give the same bits.
#![no_main]

use arbitrary::Arbitrary;
use deform_host_tests::spring_ref::{solve_linear_dense, Net};
use deform_kernel::spring::{
    amg_precondition_scratch_len, solve_linear_amg_scratch_len, AmgHierarchy, AmgOptions,
    AmgSmoother, SolveOptions, SpringSystem,
};
use deform_kernel::{graph_from_edges, graph_from_edges_len, Error};
use libfuzzer_sys::fuzz_target;

#[derive(Arbitrary, Debug)]
struct Input {
    node_count: u8,
    edges: Vec<([u8; 2], u8)>,
    fixed: Vec<bool>,
    values: Vec<i16>,
    theta: u8,
    max_levels: u8,
    max_coarse: u8,
    sweeps: u8,
    chebyshev: bool,
}

fuzz_target!(|inp: Input| {
    let n = (inp.node_count % 48) as usize + 2;
    let edges: Vec<[u32; 2]> = inp
        .edges
        .iter()
        .map(|&([a, b], _)| [(a as usize % n) as u32, (b as usize % n) as u32])
        .filter(|e| e[0] != e[1])
        .collect();
    let mut offsets = vec![0u32; n + 1];
    let mut targets = vec![0u32; graph_from_edges_len(&edges)];
    let Ok(used) = graph_from_edges(n, &edges, &mut offsets, &mut targets) else {
        return;
    };
    targets.truncate(used);
    // Symmetric stiffness spanning 2^-10 .. 2^10, from the first edge naming the pair.
    let weight = |i: u32, j: u32| -> f64 {
        let (a, b) = (i.min(j), i.max(j));
        inp.edges
            .iter()
            .find(|&&([x, y], _)| {
                let (x, y) = ((x as usize % n) as u32, (y as usize % n) as u32);
                (x.min(y), x.max(y)) == (a, b)
            })
            .map_or(1.0, |&(_, w)| 2f64.powi(i32::from(w % 21) - 10))
    };
    let mut k = Vec::with_capacity(used);
    for i in 0..n {
        for &t in &targets[offsets[i] as usize..offsets[i + 1] as usize] {
            k.push(weight(i as u32, t));
        }
    }
    let fixed: Vec<u8> = (0..n)
        .map(|i| u8::from(inp.fixed.get(i).copied().unwrap_or(i == 0)))
        .collect();
    let graph = deform_kernel::Graph::new(&offsets, &targets).unwrap();
    let mut s = vec![0u32; n];
    let Ok(sys) = SpringSystem::new(graph, &k, &fixed, &mut s) else {
        return; // unanchored free nodes: a typed error is the right answer
    };
    let opts = AmgOptions {
        strength_theta: f64::from(inp.theta % 100) / 100.0,
        max_levels: (inp.max_levels % 5) as usize + 1,
        max_coarse: (inp.max_coarse % 9) as usize + 1,
        smoother: if inp.chebyshev {
            AmgSmoother::Chebyshev
        } else {
            AmgSmoother::Jacobi
        },
        sweeps: (inp.sweeps % 4) as usize + 1,
    };

    // Exact sizes.
    let mut work = vec![0u32; AmgHierarchy::setup_work_len(&sys)];
    let sizes = AmgHierarchy::setup_len(&sys, &opts, &mut work).unwrap();
    if sizes.index > 0 {
        let mut idx = vec![5u32; sizes.index - 1];
        let mut vals = vec![0.25f64; sizes.values];
        let e = AmgHierarchy::setup(&sys, &opts, &mut work, &mut idx, &mut vals).unwrap_err();
        assert!(matches!(e, Error::BufferTooSmall { arg: "index", .. }));
        assert!(idx.iter().all(|&x| x == 5) && vals.iter().all(|&x| x == 0.25));
    }
    {
        let mut idx = vec![5u32; sizes.index];
        let mut vals = vec![0.25f64; sizes.values - 1];
        let e = AmgHierarchy::setup(&sys, &opts, &mut work, &mut idx, &mut vals).unwrap_err();
        assert!(matches!(e, Error::BufferTooSmall { arg: "values", .. }));
        assert!(idx.iter().all(|&x| x == 5) && vals.iter().all(|&x| x == 0.25));
    }
    let mut index = vec![0u32; sizes.index];
    let mut values = vec![0.0f64; sizes.values];
    let h = AmgHierarchy::setup(&sys, &opts, &mut work, &mut index, &mut values).unwrap();
    assert_eq!(h.levels(), sizes.levels);
    assert!(h.levels() <= opts.max_levels);

    // The preconditioner: zero on fixed nodes, symmetric and positive on the free ones.
    let free: Vec<usize> = (0..n).filter(|&i| fixed[i] == 0).collect();
    let vec_of = |seed: usize| -> Vec<[f64; 1]> {
        (0..n)
            .map(|i| {
                let v = inp.values.get((i + seed) % n.max(1)).copied().unwrap_or(1);
                [f64::from(v) / 128.0 + if i % 3 == seed % 3 { 1.0 } else { 0.0 }]
            })
            .collect()
    };
    let mut scratch = vec![[0.0f64; 1]; amg_precondition_scratch_len(&h)];
    let apply = |r: &[[f64; 1]], scratch: &mut [[f64; 1]]| {
        let mut z = vec![[0.0f64; 1]; n];
        sys.amg_precondition(&h, r, &mut z, scratch).unwrap();
        z
    };
    let dot = |a: &[[f64; 1]], b: &[[f64; 1]]| free.iter().map(|&i| a[i][0] * b[i][0]).sum::<f64>();
    let (a, b) = (vec_of(0), vec_of(1));
    let (ma, mb) = (apply(&a, &mut scratch), apply(&b, &mut scratch));
    for &i in (0..n).filter(|&i| fixed[i] != 0).collect::<Vec<_>>().iter() {
        assert_eq!(ma[i][0], 0.0);
    }
    for z in ma.iter().chain(&mb) {
        assert!(z[0].is_finite());
    }
    let (aa, bb) = (dot(&ma, &a), dot(&mb, &b));
    let scale = aa.abs() + bb.abs();
    assert!(
        (dot(&ma, &b) - dot(&a, &mb)).abs() <= 1e-9 * scale,
        "not symmetric: {} vs {}",
        dot(&ma, &b),
        dot(&a, &mb)
    );
    if free.iter().any(|&i| a[i][0] != 0.0) {
        assert!(aa > 0.0, "not positive: {aa}");
    }

    // AMG-CG matches the dense solve.
    let x0: Vec<[f64; 2]> = (0..n)
        .map(|i| {
            let v = f64::from(inp.values.get(i).copied().unwrap_or(0)) / 64.0;
            if fixed[i] != 0 {
                [v, -v * 0.5]
            } else {
                [0.0, 0.0]
            }
        })
        .collect();
    let mut x = x0.clone();
    let mut ws = vec![[0.0f64; 2]; solve_linear_amg_scratch_len(&h)];
    // 1e-8: above the rounding floor of the relative residual for stiffness ratios up to 2^20
    // (about eps · 2^20); a wrong answer shows as a large difference to the dense solve.
    let stop = SolveOptions {
        max_iterations: 400,
        residual_tol: 1e-8,
        update_tol: 0.0,
    };
    let rep = sys.solve_linear_amg(&h, &mut x, &stop, &mut ws).unwrap();
    assert!(rep.converged, "{rep:?}");
    let net = Net {
        offsets: offsets.clone(),
        targets: targets.clone(),
        k: k.clone(),
        fixed: fixed.clone(),
    };
    // The converged claim is true: the relative residual, recomputed independently from the
    // reference net, is within the tolerance (up to rounding of the recomputation).
    let (mut rr, mut bb) = (0.0f64, 0.0f64);
    for i in (0..n).filter(|&i| fixed[i] == 0) {
        // `c` is a component index into two rows, `x[i]` and `x[j]`.
        #[allow(clippy::needless_range_loop)]
        for c in 0..2 {
            let (mut r, mut b) = (0.0, 0.0);
            for (j, kij) in net.row(i) {
                r += kij * (x[j][c] - x[i][c]);
                if fixed[j] != 0 {
                    b += kij * x[j][c];
                }
            }
            rr += r * r;
            bb += b * b;
        }
    }
    let rel = if bb > 0.0 {
        (rr / bb).sqrt()
    } else {
        rr.sqrt()
    };
    assert!(rel <= 2e-8 + 1e-12, "claimed converged, residual {rel:e}");
    // Well-conditioned systems (stiffness within a factor 4): the answer is the dense one.
    let (kmin, kmax) = k
        .iter()
        .fold((f64::INFINITY, 0.0f64), |(a, b), &v| (a.min(v), b.max(v)));
    let start: Vec<Vec<f64>> = x0.iter().map(|v| v.to_vec()).collect();
    if kmax <= 4.0 * kmin {
        if let Some(exact) = solve_linear_dense(&net, &start) {
            let size = x0.iter().flatten().fold(1.0f64, |m, v| m.max(v.abs()));
            for (e, v) in exact.iter().zip(&x) {
                for c in 0..2 {
                    assert!(
                        (e[c] - v[c]).abs() <= 1e-4 * size,
                        "{} vs reference {}",
                        v[c],
                        e[c]
                    );
                }
            }
        }
    }

    // A second setup in the used buffers gives the same bits.
    let first: Vec<u64> = x.iter().flatten().map(|v| v.to_bits()).collect();
    let h = AmgHierarchy::setup(&sys, &opts, &mut work, &mut index, &mut values).unwrap();
    let mut y = x0.clone();
    sys.solve_linear_amg(&h, &mut y, &stop, &mut ws).unwrap();
    assert_eq!(
        first,
        y.iter().flatten().map(|v| v.to_bits()).collect::<Vec<_>>()
    );
});
