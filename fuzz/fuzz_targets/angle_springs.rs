//! Target 4: angle-inclusion springs (direct Gauss–Seidel, direct Jacobi, CG; ε = 0.01 and the
//! paper's ε = 0) on arbitrary small 2D meshes, colinear and degenerate ones included: no
//! panic; singular node or global systems come back as typed errors; a result returned as
//! converged is finite and meets its tolerance.
#![no_main]

use arbitrary::Arbitrary;
use deform_kernel::spring::{
    batina_stiffness, AngleMethod, AngleSystem, SolveOptions, SpringSystem,
};
use deform_kernel::{graph_from_edges, graph_from_edges_len, Error, Graph};
use libfuzzer_sys::fuzz_target;

#[derive(Arbitrary, Debug)]
struct Input {
    points: Vec<[i8; 2]>,
    edges: Vec<[u8; 2]>,
    fixed: Vec<bool>,
    moves: Vec<[i8; 2]>,
    method: u8,
    paper_epsilon: bool,
}

fuzz_target!(|inp: Input| {
    let n = inp.points.len().clamp(3, 20);
    let points: Vec<[f64; 2]> = (0..n)
        .map(|i| {
            let p = inp.points.get(i).copied().unwrap_or([i as i8, 0]);
            [f64::from(p[0]) / 8.0, f64::from(p[1]) / 8.0]
        })
        .collect();
    let edges: Vec<[u32; 2]> = inp
        .edges
        .iter()
        .map(|e| [(e[0] as usize % n) as u32, (e[1] as usize % n) as u32])
        .filter(|e| e[0] != e[1])
        .collect();
    let mut offsets = vec![0u32; n + 1];
    let mut targets = vec![0u32; graph_from_edges_len(&edges)];
    let Ok(used) = graph_from_edges(n, &edges, &mut offsets, &mut targets) else {
        return;
    };
    targets.truncate(used);
    let g = Graph::new(&offsets, &targets).unwrap();
    let mut k = vec![0.0; used];
    if batina_stiffness(&g, &points, 1.0, &mut k).is_err() {
        return; // coincident points: ZeroLengthEdge, a typed error
    }
    let fixed: Vec<u8> = (0..n)
        .map(|i| u8::from(inp.fixed.get(i).copied().unwrap_or(i < 2)))
        .collect();
    let mut seen = vec![0u32; n];
    let Ok(sys) = SpringSystem::new(g, &k, &fixed, &mut seen) else {
        return;
    };
    let eps = if inp.paper_epsilon { 0.0 } else { 0.01 };
    let asys = match AngleSystem::new(sys, &points, eps) {
        Ok(a) => a,
        Err(Error::SingularNode { .. }) => return,
        Err(e) => panic!("unexpected error {e:?}"),
    };
    let mut values: Vec<[f64; 2]> = (0..n)
        .map(|i| {
            let m = inp.moves.get(i).copied().unwrap_or([0, 0]);
            if fixed[i] != 0 {
                [f64::from(m[0]) / 64.0, f64::from(m[1]) / 64.0]
            } else {
                [0.0, 0.0]
            }
        })
        .collect();
    let before = values.clone();
    let method = match inp.method % 3 {
        0 => AngleMethod::DirectGaussSeidel,
        1 => AngleMethod::DirectJacobi,
        _ => AngleMethod::Cg,
    };
    let opts = SolveOptions {
        max_iterations: 300,
        ..SolveOptions::default()
    };
    let mut scratch = vec![[0.0f64; 2]; asys.angle_scratch_len(method)];
    match asys.solve_angle(&mut values, method, &opts, &mut scratch) {
        Ok(r) => {
            assert!(values.iter().all(|v| v[0].is_finite() && v[1].is_finite()));
            if r.converged {
                assert!(r.residual <= opts.residual_tol || r.max_update <= opts.update_tol);
            }
            for i in 0..n {
                if fixed[i] != 0 {
                    assert_eq!(values[i].map(f64::to_bits), before[i].map(f64::to_bits));
                }
            }
        }
        Err(Error::SingularSystem { .. } | Error::SingularNode { .. }) => {
            assert_eq!(values, before, "values must be unchanged on error");
        }
        Err(e) => panic!("unexpected error {e:?}"),
    }
});
