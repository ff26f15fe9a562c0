//! Regression tests for what fuzzing found (issue #8: every finding becomes a test here). Each
//! test names the fuzz target and the kernel line that was wrong; the crash inputs themselves
//! are kept in `fuzz/seeds/<target>/` so the CI smoke run replays them too.

use deform_host_tests::spring_ref::{solve_linear_dense, Net};
use deform_kernel::spring::{
    batina_stiffness, solve_linear_amg_scratch_len, solve_linear_scratch_len, LinearMethod,
    Preconditioner, SolveOptions, SpringSystem,
};
use deform_kernel::taubin::{redistribute, redistribute_scratch_len};
use deform_kernel::vector::{norm, norm_robust};
use deform_kernel::Direction;
use deform_kernel::{Block, Error, Graph};

/// `c_abi` fuzzing: `redistribute` reported a max displacement of +∞ for a finite move longer
/// than √MAX (|d|² overflowed in `vector::distance`; `taubin/lines.rs`).
#[test]
fn redistribute_reports_a_finite_move_beyond_sqrt_max() {
    let block = Block::new([2, 1, 1]).unwrap();
    let mut points = [[0.0f64, 0.0], [1.0, 0.0]];
    let targets = [0.0, 1e300];
    let mut scratch = vec![0.0; redistribute_scratch_len::<2>(&block, Direction::I)];
    let moved = redistribute(
        &block,
        &mut points,
        Direction::I,
        &targets,
        false,
        &mut scratch,
    )
    .unwrap();
    assert_eq!(points[1], [1e300, 0.0]);
    assert!(moved.is_finite(), "max displacement {moved}");
    assert!((moved - 1e300).abs() <= 1e300 * f64::EPSILON);
}

/// `norm_robust` is `norm` bit for bit wherever `norm` is exact, and finite beyond.
#[test]
fn norm_robust_equals_norm_in_range_and_survives_overflow() {
    for v in [[3.0f64, 4.0], [1e-150, 2e-150], [1e150, -1e150], [0.0, 0.0]] {
        assert_eq!(norm_robust(v).to_bits(), norm(v).to_bits(), "{v:?}");
    }
    // Beyond that, within a few ulps (the rescaling rounds once more).
    let close = |a: f64, b: f64| (a - b).abs() <= 4.0 * f64::EPSILON * b;
    assert!(close(norm_robust([3e200f64, 4e200]), 5e200));
    assert!(close(norm_robust([3e-200f64, 4e-200]), 5e-200));
    let r32 = norm_robust([3e30f32, 4e30]);
    assert!((r32 - 5e30).abs() <= 4.0 * f32::EPSILON * 5e30, "{r32}");
    assert!(norm_robust([f64::INFINITY, 0.0]).is_infinite());
    assert!(norm_robust([f64::NAN, 0.0]).is_nan());
}

/// Found while triaging the above: an edge longer than √MAX got stiffness 1/∞ = 0 and
/// `batina_stiffness` returned Ok, so every solver then rejected the system
/// (`spring/stiffness.rs`). Now long edges get their tiny stiffness, and one whose stiffness
/// underflows to zero is a typed error with nothing written.
#[test]
fn batina_stiffness_of_edges_beyond_sqrt_max() {
    let offsets = [0u32, 1, 2];
    let targets = [1u32, 0];
    let graph = Graph::new(&offsets, &targets).unwrap();
    let points = [[0.0f64, 0.0], [1e200, 0.0]];
    let mut k = [-1.0f64; 2];
    batina_stiffness(&graph, &points, 1.0, &mut k).unwrap();
    assert_eq!(k, [1e-200, 1e-200]);
    let mut k = [-1.0f64; 2];
    assert!(matches!(
        batina_stiffness(&graph, &points, 2.0, &mut k),
        Err(Error::NonPositive {
            arg: "stiffness",
            position: 0
        })
    ));
    assert_eq!(k, [-1.0, -1.0], "nothing written on error");
    // In range nothing changed: 1/|d| exactly as before.
    let points = [[0.0f64, 0.0], [3.0, 4.0]];
    batina_stiffness(&graph, &points, 1.0, &mut k).unwrap();
    assert_eq!(k, [0.2, 0.2]);
}

/// `c_abi` fuzzing: CG turned a fixed node's −0.0 into +0.0 (`x += α·p` with `p = 0` at fixed
/// nodes; `spring/linear.rs`). Every method must return fixed values bit for bit.
#[test]
fn every_linear_method_keeps_fixed_values_bitwise() {
    let offsets = [0u32, 1, 3, 4];
    let targets = [1u32, 0, 2, 1];
    let graph = Graph::new(&offsets, &targets).unwrap();
    let stiffness = [1.0f64; 4];
    let fixed = [1u8, 0, 1];
    let mut index = [0u32; 3];
    let sys = SpringSystem::new(graph, &stiffness, &fixed, &mut index).unwrap();
    let cg = |preconditioner| LinearMethod::Cg { preconditioner };
    for method in [
        LinearMethod::Jacobi,
        LinearMethod::GaussSeidel,
        LinearMethod::Sor { omega: 1.5 },
        cg(Preconditioner::None),
        cg(Preconditioner::Jacobi),
        cg(Preconditioner::Ssor { omega: 1.2 }),
    ] {
        let mut values = [[-0.0f64], [0.0], [1.0]];
        let mut scratch = vec![[0.0f64; 1]; solve_linear_scratch_len(&method, 3)];
        let options = SolveOptions {
            residual_tol: 1e-14,
            ..SolveOptions::default()
        };
        sys.solve_linear(&mut values, method, &options, &mut scratch)
            .unwrap();
        assert_eq!(values[0][0].to_bits(), (-0.0f64).to_bits(), "{method:?}");
        assert_eq!(values[2][0].to_bits(), 1.0f64.to_bits(), "{method:?}");
        assert!((values[1][0] - 0.5).abs() < 1e-12, "{method:?}");
    }
}

/// `amg_setup_cycle` fuzzing (CI, stop 42): a valid six-node system whose three free nodes
/// hang on fixed ones by springs of 2⁻¹⁰ … 2⁻⁸ made the two-level set-up report
/// `SingularSystem` (`spring/amg/setup.rs`). The hierarchy must set up, and AMG-CG must agree
/// with the plain CG solve.
#[test]
fn amg_setup_accepts_weak_springs_to_fixed_nodes() {
    use deform_kernel::spring::{AmgHierarchy, AmgOptions, AmgSmoother};
    let p = |e: i32| 2f64.powi(e);
    // (a, b, stiffness); nodes 0, 1, 2 fixed, 3, 4, 5 free.
    let springs = [
        (0u32, 4u32, p(-8)),
        (1, 3, p(-8)),
        (2, 1, p(-9)),
        (3, 5, p(-10)),
        (0, 5, p(-8)),
        (0, 1, p(-10)),
        (2, 4, p(-9)),
        (1, 5, p(-9)),
        (0, 3, p(-9)),
    ];
    let n = 6;
    let edges: Vec<[u32; 2]> = springs.iter().map(|&(a, b, _)| [a, b]).collect();
    let mut offsets = vec![0u32; n + 1];
    let mut targets = vec![0u32; deform_kernel::graph_from_edges_len(&edges)];
    let used = deform_kernel::graph_from_edges(n, &edges, &mut offsets, &mut targets).unwrap();
    targets.truncate(used);
    let mut k = Vec::new();
    for i in 0..n {
        for &t in &targets[offsets[i] as usize..offsets[i + 1] as usize] {
            let (a, b) = ((i as u32).min(t), (i as u32).max(t));
            let w = springs
                .iter()
                .find(|s| (s.0.min(s.1), s.0.max(s.1)) == (a, b));
            k.push(w.unwrap().2);
        }
    }
    let fixed = [1u8, 1, 1, 0, 0, 0];
    let graph = Graph::new(&offsets, &targets).unwrap();
    let mut s = vec![0u32; n];
    let sys = SpringSystem::new(graph, &k, &fixed, &mut s).unwrap();
    let opts = AmgOptions {
        strength_theta: 0.02,
        max_levels: 2,
        max_coarse: 2,
        smoother: AmgSmoother::Chebyshev,
        sweeps: 3,
    };
    let mut work = vec![0u32; AmgHierarchy::setup_work_len(&sys)];
    let sizes = AmgHierarchy::setup_len(&sys, &opts, &mut work).unwrap();
    let mut index = vec![0u32; sizes.index];
    let mut values = vec![0.0f64; sizes.values];
    let h = AmgHierarchy::setup(&sys, &opts, &mut work, &mut index, &mut values).unwrap();
    assert_eq!(h.levels(), 2);
    let x0: Vec<[f64; 2]> = (0..n)
        .map(|i| {
            if fixed[i] != 0 {
                [i as f64, 1.0 - i as f64]
            } else {
                [0.0; 2]
            }
        })
        .collect();
    let mut x = x0.clone();
    let mut ws = vec![[0.0f64; 2]; solve_linear_amg_scratch_len(&h)];
    let stop = SolveOptions {
        max_iterations: 100,
        residual_tol: 1e-12,
        update_tol: 0.0,
    };
    let rep = sys.solve_linear_amg(&h, &mut x, &stop, &mut ws).unwrap();
    assert!(rep.converged, "{rep:?}");
    let net = Net {
        offsets: offsets.clone(),
        targets: targets.clone(),
        k: k.clone(),
        fixed: fixed.to_vec(),
    };
    let start: Vec<Vec<f64>> = x0.iter().map(|v| v.to_vec()).collect();
    let exact = solve_linear_dense(&net, &start).unwrap();
    for (e, v) in exact.iter().zip(&x) {
        for c in 0..2 {
            assert!((e[c] - v[c]).abs() <= 1e-10, "{} vs dense {}", v[c], e[c]);
        }
    }
}
