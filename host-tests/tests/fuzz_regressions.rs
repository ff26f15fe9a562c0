//! Regression tests for what fuzzing found (issue #8: every finding becomes a test here). Each
//! test names the fuzz target and the kernel line that was wrong; the crash inputs themselves
//! are kept in `fuzz/seeds/<target>/` so the CI smoke run replays them too.

use deform_kernel::spring::{
    batina_stiffness, solve_linear_scratch_len, LinearMethod, Preconditioner, SolveOptions,
    SpringSystem,
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
