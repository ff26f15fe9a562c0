//! Target 11: sliding boundaries on arbitrary small 2D graphs with arbitrary kind bytes,
//! directions, stiffnesses and values: no panic; invalid tables are typed errors; a
//! constrained solve either fails with the values untouched or returns finite values whose
//! sliding nodes moved only along their lines (`|n · d| ≤ 1e-12` of the larger of
//! `|d|` and the input values; positions: of `16 |x|` plus the
//! unprojected move); `fit_plane` and
//! `slide_points` keep their promises. The angle springs run the direct method, the node-block
//! CG and the multigrid-preconditioned CG.
#![no_main]

use arbitrary::Arbitrary;
use deform_kernel::spring::constraints::{fit_plane, slide_points, Constraints, NodeKind};
use deform_kernel::spring::{
    solve_linear_sliding_scratch_len, AmgHierarchy, AmgOptions, AngleMethod, AngleSystem,
    LinearMethod, LinearSolver, Preconditioner, SolveOptions, SpringSystem,
};
use deform_kernel::{graph_from_edges, graph_from_edges_len, Graph};
use libfuzzer_sys::fuzz_target;

#[derive(Arbitrary, Debug)]
struct Input {
    node_count: u8,
    edges: Vec<[u8; 2]>,
    kinds: Vec<u8>,
    angles: Vec<i16>,
    raw_dir: Option<(u16, [f64; 2])>,
    values: Vec<i16>,
    points: Vec<[i16; 2]>,
    method: u8,
    tolerance: f64,
}

fn bits(v: &[[f64; 2]]) -> Vec<[u64; 2]> {
    v.iter().map(|x| x.map(f64::to_bits)).collect()
}

fuzz_target!(|inp: Input| {
    let n = (inp.node_count % 20) as usize + 2;
    let kinds: Vec<u8> = (0..n)
        .map(|i| inp.kinds.get(i).copied().unwrap_or(u8::from(i == 0)) % 6)
        .collect();
    let mut dirs: Vec<[f64; 2]> = (0..n)
        .map(|i| {
            let a = f64::from(inp.angles.get(i).copied().unwrap_or(0)) / 1000.0;
            [a.cos(), a.sin()]
        })
        .collect();
    if let Some((i, d)) = inp.raw_dir {
        dirs[i as usize % n] = d;
    }
    let points: Vec<[f64; 2]> = (0..n)
        .map(|i| {
            let p = inp
                .points
                .get(i)
                .copied()
                .unwrap_or([i as i16, (i * i) as i16]);
            [f64::from(p[0]) / 16.0, f64::from(p[1]) / 16.0]
        })
        .collect();

    // Plane fit: a typed error or a unit normal within the tolerance.
    let nodes: Vec<u32> = (0..n as u32).collect();
    if let Ok(fit) = fit_plane(&points, &nodes, inp.tolerance) {
        let len = (fit.normal[0] * fit.normal[0] + fit.normal[1] * fit.normal[1]).sqrt();
        assert!((len - 1.0).abs() < 1e-12);
        assert!(fit.residual <= inp.tolerance * fit.extent);
    }

    let c = match Constraints::new(&kinds, &dirs) {
        Ok(c) => c,
        Err(_) => {
            assert!(
                kinds.iter().any(|&k| k > 3)
                    || kinds.iter().zip(&dirs).any(|(&k, d)| {
                        // Not unit, NaN included.
                        let e = (d[0] * d[0] + d[1] * d[1] - 1.0).abs();
                        (k == 2 || k == 3) && (e.is_nan() || e > f64::EPSILON.sqrt())
                    })
            );
            return;
        }
    };
    // `scale`: the magnitude the rounding is relative to (|d|, or |x| for positions).
    let on_line = |i: usize, d: [f64; 2], scale: f64| -> bool {
        let m = d[0].abs().max(d[1].abs()).max(scale);
        let t = dirs[i];
        let off = match NodeKind::from_code(kinds[i]) {
            Some(NodeKind::Plane) => t[0] * d[0] + t[1] * d[1],
            Some(NodeKind::Line) => t[0] * d[1] - t[1] * d[0],
            _ => 0.0,
        };
        off.abs() <= 1e-12 * m + 1e-300
    };

    // slide_points.
    let mut moved: Vec<[f64; 2]> = points.iter().map(|p| [p[0] + 0.5, p[1] - 0.25]).collect();
    let before = bits(&moved);
    match slide_points(&c, &points, &mut moved) {
        Ok(()) => {
            for i in 0..n {
                let d = [moved[i][0] - points[i][0], moved[i][1] - points[i][1]];
                // Relative to |x| and to the unprojected move |(0.5, −0.25)| < 1.
                let x = points[i][0].abs().max(points[i][1].abs());
                assert!(on_line(i, d, 16.0 * x + 1.0) || kinds[i] < 2, "{i}: {d:?}");
            }
        }
        Err(_) => assert_eq!(before, bits(&moved)),
    }

    let edges: Vec<[u32; 2]> = inp
        .edges
        .iter()
        .map(|&[a, b]| [(a as usize % n) as u32, (b as usize % n) as u32])
        .filter(|e| e[0] != e[1])
        .collect();
    let mut offsets = vec![0u32; n + 1];
    let mut targets = vec![0u32; graph_from_edges_len(&edges)];
    let Ok(used) = graph_from_edges(n, &edges, &mut offsets, &mut targets) else {
        return;
    };
    targets.truncate(used);
    let k = vec![1.0f64; used];
    let mut mask = vec![0u8; n];
    c.fixed_mask(&mut mask).unwrap();
    let graph = Graph::new(&offsets, &targets).unwrap();
    let mut scratch = vec![0u32; n];
    let Ok(sys) = SpringSystem::new(graph, &k, &mask, &mut scratch) else {
        return;
    };
    let mut values: Vec<[f64; 2]> = (0..n)
        .map(|i| {
            let v = f64::from(inp.values.get(i).copied().unwrap_or(0)) / 64.0;
            [v, 0.5 - v]
        })
        .collect();
    let before = bits(&values);
    // Rounding is relative to the problem's scale (a solution near 0 keeps the iterates' ulps).
    let scale = values.iter().flatten().fold(0.0f64, |m, x| m.max(x.abs()));
    let opts = SolveOptions {
        max_iterations: 200,
        ..SolveOptions::default()
    };
    let result = if inp.method % 5 == 4 {
        let Ok(a) = AngleSystem::new(sys, &points, 0.05) else {
            return;
        };
        match inp.method / 5 % 3 {
            2 => {
                // CG preconditioned by the scalar multigrid V-cycle per component.
                let amg_opts = AmgOptions::default();
                let mut setup = vec![0u32; AmgHierarchy::setup_work_len(&sys)];
                let Ok(sizes) = AmgHierarchy::setup_len(&sys, &amg_opts, &mut setup) else {
                    return;
                };
                let mut index = vec![0u32; sizes.index];
                let mut weights = vec![0.0f64; sizes.values];
                // The sizes query promised these lengths: setup must succeed.
                let h = AmgHierarchy::setup(&sys, &amg_opts, &mut setup, &mut index, &mut weights)
                    .unwrap();
                let mut work = vec![[0.0; 2]; a.solve_angle_sliding_amg_scratch_len(&h)];
                a.solve_angle_sliding_amg(&c, &mut values, &h, &opts, &mut work)
            }
            m => {
                let m = [AngleMethod::DirectGaussSeidel, AngleMethod::Cg][usize::from(m)];
                let mut work = vec![[0.0; 2]; a.solve_angle_sliding_scratch_len(m)];
                a.solve_angle_sliding(&c, &mut values, m, 1.2, &opts, &mut work)
            }
        }
    } else {
        let solver: LinearSolver<'_, f64> = [
            LinearMethod::Jacobi,
            LinearMethod::GaussSeidel,
            LinearMethod::Cg {
                preconditioner: Preconditioner::Jacobi,
            },
            LinearMethod::Cg {
                preconditioner: Preconditioner::Ssor { omega: 1.3 },
            },
        ][usize::from(inp.method % 4)]
        .into();
        let mut work = vec![[0.0; 2]; solve_linear_sliding_scratch_len(&solver, n)];
        sys.solve_linear_sliding(&c, &mut values, solver, &opts, &mut work)
    };
    match result {
        Ok(r) => {
            assert!(r.residual.is_finite() || !r.converged);
            for (i, v) in values.iter().enumerate() {
                assert!(v[0].is_finite() && v[1].is_finite());
                if kinds[i] == 1 {
                    assert_eq!(v.map(f64::to_bits), before[i]);
                } else {
                    assert!(on_line(i, *v, scale), "{i}: {v:?}");
                }
            }
        }
        Err(_) => assert_eq!(before, bits(&values)),
    }
});
