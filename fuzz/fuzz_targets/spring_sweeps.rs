//! Target 3: linear-spring sweeps and solves on arbitrary small graphs, stiffnesses and fixed
//! masks: no panic; a Jacobi sweep is bitwise equal to the naive host reference; from finite
//! input, no NaN; Gauss–Seidel keeps every value within the range of the fixed values
//! (maximum principle).
#![no_main]

use arbitrary::Arbitrary;
use deform_host_tests::spring_ref::{jacobi_sweep as ref_jacobi, Net};
use deform_kernel::spring::{LinearMethod, SolveOptions, SpringSystem};
use deform_kernel::{graph_from_edges, graph_from_edges_len};
use libfuzzer_sys::fuzz_target;

#[derive(Arbitrary, Debug)]
struct Input {
    node_count: u8,
    edges: Vec<([u8; 2], u16)>,
    fixed: Vec<bool>,
    values: Vec<i16>,
}

fuzz_target!(|inp: Input| {
    let n = (inp.node_count % 24) as usize + 2;
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
    // Symmetric stiffness: a weight per unordered pair, from the first edge naming it.
    let weight = |i: u32, j: u32| -> f64 {
        let (a, b) = (i.min(j), i.max(j));
        inp.edges
            .iter()
            .find(|&&([x, y], _)| {
                let (x, y) = ((x as usize % n) as u32, (y as usize % n) as u32);
                (x.min(y), x.max(y)) == (a, b)
            })
            .map_or(1.0, |&(_, w)| 0.125 + f64::from(w) / 64.0)
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
    let values: Vec<[f64; 2]> = (0..n)
        .map(|i| {
            let v = f64::from(inp.values.get(i).copied().unwrap_or(0)) / 64.0;
            [v, -v * 0.5]
        })
        .collect();
    let graph = deform_kernel::Graph::new(&offsets, &targets).unwrap();
    let mut scratch = vec![0u32; n];
    let sys = match SpringSystem::new(graph, &k, &fixed, &mut scratch) {
        Ok(s) => s,
        Err(_) => return, // unanchored free nodes etc.: a typed error is the right answer
    };

    // Jacobi sweep: bitwise parity with the reference.
    let mut out = vec![[0.0f64; 2]; n];
    sys.jacobi_sweep(0..n, &values, &mut out).unwrap();
    let net = Net {
        offsets: offsets.clone(),
        targets: targets.clone(),
        k: k.clone(),
        fixed: fixed.clone(),
    };
    let x: Vec<Vec<f64>> = values.iter().map(|v| v.to_vec()).collect();
    let want = ref_jacobi(&net, &x, 0..n);
    for (o, w) in out.iter().zip(&want) {
        assert_eq!(o[0].to_bits(), w[0].to_bits());
        assert_eq!(o[1].to_bits(), w[1].to_bits());
    }

    // Gauss–Seidel from free values set to a fixed value: maximum principle.
    let first_fixed = fixed.iter().position(|&f| f != 0).unwrap();
    let mut v = values.clone();
    for i in 0..n {
        if fixed[i] == 0 {
            v[i] = values[first_fixed];
        }
    }
    let opts = SolveOptions {
        max_iterations: 50,
        ..SolveOptions::default()
    };
    let mut ws = vec![[0.0f64; 2]; n];
    let report = sys
        .solve_linear(&mut v, LinearMethod::GaussSeidel, &opts, &mut ws)
        .unwrap();
    assert!(report.residual.is_finite());
    for c in 0..2 {
        let (lo, hi) = (0..n)
            .filter(|&i| fixed[i] != 0)
            .map(|i| values[i][c])
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| {
                (a.min(x), b.max(x))
            });
        let tol = 1e-12 * (hi - lo).abs().max(1.0);
        for value in &v {
            assert!(value[c].is_finite());
            assert!(
                value[c] >= lo - tol && value[c] <= hi + tol,
                "{} not in [{lo}, {hi}]",
                value[c]
            );
        }
    }
});
