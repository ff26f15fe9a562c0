//! Target 4: angle-inclusion springs (direct Gauss–Seidel, direct Jacobi, CG; ε = 0.01 and the
//! paper's ε = 0) on arbitrary small 2D meshes, colinear and degenerate ones included: no
//! panic; singular node or global systems come back as typed errors; a result returned as
//! converged is finite and meets its tolerance. Every input also runs the
//! multigrid-preconditioned CG (`solve_angle_amg`, a hierarchy of the base system; smoother
//! and coarsest size from `method`) under the same checks, and a scratch one item short or a
//! hierarchy of another system is a typed error that leaves the values alone.
#![no_main]

use arbitrary::Arbitrary;
use deform_kernel::spring::{
    batina_stiffness, AmgHierarchy, AmgOptions, AmgSmoother, AngleMethod, AngleSystem,
    SolveOptions, SolveReport, SpringSystem,
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
    let result = asys.solve_angle(&mut values, method, &opts, &mut scratch);
    check(result, &values, &before, &fixed, &opts);

    // The same problem by the multigrid-preconditioned CG.
    let amg_opts = AmgOptions {
        smoother: if inp.method & 4 == 0 {
            AmgSmoother::Chebyshev
        } else {
            AmgSmoother::Jacobi
        },
        max_coarse: usize::from(inp.method >> 4) % 4 + 1,
        ..AmgOptions::default()
    };
    let mut work = vec![0u32; AmgHierarchy::setup_work_len(&sys)];
    let sizes = AmgHierarchy::setup_len(&sys, &amg_opts, &mut work).unwrap();
    let mut index = vec![0u32; sizes.index];
    let mut hvalues = vec![0.0f64; sizes.values];
    let h = match AmgHierarchy::setup(&sys, &amg_opts, &mut work, &mut index, &mut hvalues) {
        Ok(h) => h,
        Err(Error::SingularSystem { .. }) => return,
        Err(e) => panic!("unexpected setup error {e:?}"),
    };
    let need = asys.angle_amg_scratch_len(&h);
    let mut values = before.clone();
    let mut scratch = vec![[0.0f64; 2]; need];
    assert!(matches!(
        asys.solve_angle_amg(&h, &mut values, &opts, &mut scratch[..need - 1]),
        Err(Error::BufferTooSmall { .. })
    ));
    assert_eq!(values, before);
    let result = asys.solve_angle_amg(&h, &mut values, &opts, &mut scratch);
    check(result, &values, &before, &fixed, &opts);

    // A hierarchy of a system with one more node (an extra fixed node on a new edge).
    let mut edges2 = edges.clone();
    edges2.push([0, n as u32]);
    let mut offsets2 = vec![0u32; n + 2];
    let mut targets2 = vec![0u32; graph_from_edges_len(&edges2)];
    let used2 = graph_from_edges(n + 1, &edges2, &mut offsets2, &mut targets2).unwrap();
    targets2.truncate(used2);
    let g2 = Graph::new(&offsets2, &targets2).unwrap();
    let k2 = vec![1.0; used2];
    let mut fixed2 = fixed.clone();
    fixed2.push(1);
    let mut seen2 = vec![0u32; n + 1];
    if let Ok(sys2) = SpringSystem::new(g2, &k2, &fixed2, &mut seen2) {
        let mut work2 = vec![0u32; AmgHierarchy::setup_work_len(&sys2)];
        let sizes2 = AmgHierarchy::setup_len(&sys2, &amg_opts, &mut work2).unwrap();
        let mut index2 = vec![0u32; sizes2.index];
        let mut values2 = vec![0.0f64; sizes2.values];
        if let Ok(h2) = AmgHierarchy::setup(&sys2, &amg_opts, &mut work2, &mut index2, &mut values2)
        {
            let mut values = before.clone();
            let mut big = vec![[0.0f64; 2]; asys.angle_amg_scratch_len(&h2) + need];
            assert!(matches!(
                asys.solve_angle_amg(&h2, &mut values, &opts, &mut big),
                Err(Error::LengthMismatch {
                    arg: "hierarchy",
                    ..
                })
            ));
            assert_eq!(values, before);
        }
    }
});

/// The checks every solve's outcome must pass: converged results are finite and meet the
/// tolerance, fixed values keep their bits, errors are the singular kinds and leave `values`
/// as they were.
fn check(
    result: deform_kernel::Result<SolveReport<f64>>,
    values: &[[f64; 2]],
    before: &[[f64; 2]],
    fixed: &[u8],
    opts: &SolveOptions<f64>,
) {
    match result {
        Ok(r) => {
            assert!(values.iter().all(|v| v[0].is_finite() && v[1].is_finite()));
            if r.converged {
                assert!(r.residual <= opts.residual_tol || r.max_update <= opts.update_tol);
            }
            for i in 0..values.len() {
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
}
