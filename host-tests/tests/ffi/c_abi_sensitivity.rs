//! Mesh sensitivities through the C ABI: builds `libdeform_kernel` (static and shared),
//! compiles `ffi/tests/sensitivity.c` (the spring adjoint with CG + Jacobi, the IDW tangent
//! and adjoint, f64 with 0-based and f32 with 1-based boundary nodes, plus bad input that
//! must return its status and write nothing), runs it, and compares the printed bits with the
//! kernel's `spring_adjoint`, `idw_tangent` and `idw_adjoint` on the same inputs; then the
//! quaternion method with spring propagation (`deform_spring_tangent`, `deform_spring_adjoint`,
//! shape rotations of the boundary loop). Needs `gcc` on PATH.

#[path = "../support/mod.rs"]
mod support;

use support::c_build::*;

use deform_kernel::quaternion::{
    deform_spring_adjoint, deform_spring_sensitivity_scratch_len, deform_spring_tangent,
    BoundaryMotion, RotationSource,
};
use deform_kernel::sensitivity::{
    idw_adjoint, idw_tangent, spring_adjoint, spring_adjoint_scratch_len,
};
use deform_kernel::spring::{
    batina_stiffness, LinearMethod, LinearSolver, Preconditioner, SolveOptions, SpringSystem,
};
use deform_kernel::{Cells, Graph, Real};

const S: usize = 6;
const N: usize = S * S;

/// The 4-neighbour CSR graph, boundary mask and boundary list of sensitivity.c.
fn mesh() -> (Vec<u32>, Vec<u32>, Vec<u8>, Vec<u32>) {
    let (mut offsets, mut targets, mut fixed, mut boundary) = (vec![0u32], vec![], vec![], vec![]);
    for j in 0..S {
        for i in 0..S {
            let n = i + S * j;
            let edge = i == 0 || j == 0 || i == S - 1 || j == S - 1;
            fixed.push(edge as u8);
            if edge {
                boundary.push(n as u32);
            }
            if j > 0 {
                targets.push((n - S) as u32);
            }
            if i > 0 {
                targets.push((n - 1) as u32);
            }
            if i + 1 < S {
                targets.push((n + 1) as u32);
            }
            if j + 1 < S {
                targets.push((n + S) as u32);
            }
            offsets.push(targets.len() as u32);
        }
    }
    (offsets, targets, fixed, boundary)
}

fn pairs<T: Real>(flat: &[f64]) -> Vec<[T; 2]> {
    flat.chunks(2)
        .map(|c| [T::from_f64(c[0]), T::from_f64(c[1])])
        .collect()
}

/// Runs `f` with the Batina spring system of sensitivity.c's mesh at `points`, CG + Jacobi
/// and the relative tolerance `tol`.
fn with_system<T: Real, R>(
    points: &[[T; 2]],
    tol: f64,
    f: impl FnOnce(&SpringSystem<'_, T>, LinearSolver<'_, T>, &SolveOptions<T>) -> R,
) -> R {
    let (offsets, targets, fixed, _) = mesh();
    let graph = Graph::new(&offsets, &targets).unwrap();
    let mut k = vec![T::ZERO; targets.len()];
    batina_stiffness(&graph, points, T::ONE, &mut k).unwrap();
    let mut anchor = vec![0u32; N];
    let sys = SpringSystem::new(graph, &k, &fixed, &mut anchor).unwrap();
    let solver = LinearSolver::Method(LinearMethod::Cg {
        preconditioner: Preconditioner::Jacobi,
    });
    let opts = SolveOptions {
        residual_tol: T::from_f64(tol),
        ..SolveOptions::default()
    };
    f(&sys, solver, &opts)
}

/// The kernel's results on the C program's inputs, printed as the C program prints them.
fn expected<T: Real>(
    tag: &str,
    inputs: [&[f64]; 3],
    tol: f64,
    hex: fn(&str, &[T]) -> String,
) -> (String, String) {
    let [points, w, v] = inputs.map(pairs::<T>);
    let boundary = mesh().3;
    let mut g = vec![[T::ZERO; 2]; N];
    let r = with_system(&points, tol, |sys, solver, opts| {
        let mut s = vec![[T::ZERO; 2]; spring_adjoint_scratch_len::<T, 2>(&solver, N)];
        spring_adjoint(sys, solver, opts, &w, &mut g, &mut s).unwrap()
    });
    let flat = |x: &[[T; 2]]| x.iter().flatten().copied().collect::<Vec<T>>();
    let springs = hex(&format!("spring {tag}"), &flat(&g))
        + &format!(
            "spring {tag} report {} {}\n",
            r.iterations, r.converged as i32
        );
    let mut jv = v.clone();
    idw_tangent(&points, &boundary, T::TWO, &mut jv).unwrap();
    let mut ga = vec![[T::ZERO; 2]; N];
    idw_adjoint(&points, &boundary, T::TWO, &w, &mut ga).unwrap();
    let idw = hex(&format!("idw tangent {tag}"), &flat(&jv))
        + &hex(&format!("idw adjoint {tag}"), &flat(&ga));
    (springs, idw)
}

/// The segments of sensitivity.c's boundary loop (counter-clockwise, positions in `boundary`).
fn segments(boundary: &[u32]) -> Vec<u32> {
    let local = |n: usize| boundary.iter().position(|&b| b as usize == n).unwrap() as u32;
    let ring: Vec<usize> = (0..S - 1)
        .chain((0..S - 1).map(|j| S - 1 + S * j))
        .chain((0..S - 1).map(|i| N - 1 - i))
        .chain((0..S - 1).map(|j| S * (S - 1 - j)))
        .collect();
    (0..ring.len())
        .flat_map(|i| [local(ring[i]), local(ring[(i + 1) % ring.len()])])
        .collect()
}

/// The kernel's quaternion-spring tangent and adjoint on sensitivity.c's inputs, printed as
/// the C program prints them.
fn expected_quaternion<T: Real>(
    tag: &str,
    inputs: [&[f64]; 4],
    tol: f64,
    hex: fn(&str, &[T]) -> String,
) -> String {
    let [points, w, deformed, direction] = inputs.map(pairs::<T>);
    let boundary = mesh().3;
    let seg = segments(&boundary);
    let offs: Vec<u32> = (0..=seg.len() as u32 / 2).map(|i| 2 * i).collect();
    let kinds = vec![3u8; seg.len() / 2];
    let motion = BoundaryMotion {
        nodes: &boundary,
        deformed: &deformed,
        elements: Some(Cells::new(boundary.len(), &offs, &seg, &kinds).unwrap()),
        rotations: RotationSource::Shape,
        origin: None,
    };
    let b = boundary.len();
    let (mut jv, mut g) = (vec![[T::ZERO; 2]; N], vec![[T::ZERO; 2]; b]);
    let (rt, ra) = with_system(&points, tol, |sys, solver, opts| {
        let len = deform_spring_sensitivity_scratch_len::<T, 2>(&solver, N, b);
        let mut s = vec![T::ZERO; len];
        let m = &motion;
        let t = deform_spring_tangent(&points, m, sys, solver, opts, &direction, &mut s, &mut jv);
        let a = deform_spring_adjoint(&points, m, sys, solver, opts, &w, &mut s, &mut g);
        (t.unwrap(), a.unwrap())
    });
    let flat = |x: &[[T; 2]]| x.iter().flatten().copied().collect::<Vec<T>>();
    let report = |mode: &str, r: deform_kernel::spring::SolveReport<T>| {
        format!(
            "qspring {mode} {tag} report {} {}\n",
            r.iterations, r.converged as i32
        )
    };
    hex(&format!("qspring tangent {tag}"), &flat(&jv))
        + &report("tangent", rt)
        + &hex(&format!("qspring adjoint {tag}"), &flat(&g))
        + &report("adjoint", ra)
}

#[test]
fn sensitivities_from_c_equal_the_kernel_bit_for_bit() {
    for (link, name) in [
        (Link::Static, "sensitivity_c_static"),
        (Link::Shared, "sensitivity_c_shared"),
    ] {
        let printed = run_c_test("sensitivity", name, link);
        let lines: Vec<&str> = printed.lines().collect();
        assert_eq!(
            lines.last(),
            Some(&"sensitivity: every check held"),
            "{name}: {printed}"
        );
        let points = parse_hex64(lines[0], "points");
        let w = parse_hex64(lines[1], "w");
        let v = parse_hex64(lines[2], "v");
        let (s64, i64) = expected::<f64>("f64", [&points, &w, &v], 1e-13, hex64);
        let tol32 = SolveOptions::<f32>::default().residual_tol as f64;
        let (s32, i32) = expected::<f32>("f32", [&points, &w, &v], tol32, hex32);
        let want = s64 + &s32 + &i64 + &i32;
        let got = lines[3..11].join("\n") + "\n";
        assert_eq!(got, want, "{name}");
        let deformed = parse_hex64(lines[11], "qdeformed");
        let direction = parse_hex64(lines[12], "qdirection");
        let inputs = [&points[..], &w, &deformed, &direction];
        let want = expected_quaternion::<f64>("f64", inputs, 1e-13, hex64)
            + &expected_quaternion::<f32>("f32", inputs, tol32, hex32);
        let got = lines[13..21].join("\n") + "\n";
        assert_eq!(got, want, "{name}: quaternion springs");
    }
}
