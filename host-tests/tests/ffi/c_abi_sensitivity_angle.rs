//! The angle-spring sensitivities through the C ABI: builds `libdeform_kernel` (static and
//! shared), compiles `ffi/tests/sensitivity_angle.c` (the adjoint with block-Jacobi CG and the
//! tangent through `dk_spring_solve_angle`, f64 with `ε = 0`, f32 with `ε = 0.01`, bad input
//! that must return its status and write nothing), runs it, and compares the printed bits with
//! the kernel's `angle_adjoint` and `angle_tangent` on the same inputs. Needs `gcc` on PATH.

#[path = "../support/mod.rs"]
mod support;

use support::c_build::*;

use deform_kernel::sensitivity::{
    angle_adjoint, angle_adjoint_scratch_len, angle_tangent, AngleSolver,
};
use deform_kernel::spring::{
    batina_stiffness, AngleMethod, AngleSystem, SolveOptions, SpringSystem,
};
use deform_kernel::{Graph, Real};

const S: usize = 6;
const N: usize = S * S;

/// sensitivity_angle.c's graph (4 neighbours and one diagonal per quad) and boundary mask.
fn mesh() -> (Vec<u32>, Vec<u32>, Vec<u8>) {
    let (mut offsets, mut targets, mut fixed) = (vec![0u32], vec![], vec![]);
    for j in 0..S as i64 {
        for i in 0..S as i64 {
            let b = i == 0 || j == 0 || i == S as i64 - 1 || j == S as i64 - 1;
            fixed.push(b as u8);
            for (di, dj) in [(-1, -1), (0, -1), (-1, 0), (1, 0), (0, 1), (1, 1)] {
                let (a, c) = (i + di, j + dj);
                if (0..S as i64).contains(&a) && (0..S as i64).contains(&c) {
                    targets.push((a + S as i64 * c) as u32);
                }
            }
            offsets.push(targets.len() as u32);
        }
    }
    (offsets, targets, fixed)
}

fn pairs<T: Real>(flat: &[f64]) -> Vec<[T; 2]> {
    flat.chunks(2)
        .map(|c| [T::from_f64(c[0]), T::from_f64(c[1])])
        .collect()
}

/// The kernel's adjoint and tangent on the C program's inputs, printed as it prints them.
fn expected<T: Real>(
    tag: &str,
    inputs: [&[f64]; 3],
    eps: f64,
    tol: f64,
    hex: fn(&str, &[T]) -> String,
) -> String {
    let [points, w, v] = inputs.map(pairs::<T>);
    let (offsets, targets, fixed) = mesh();
    let graph = Graph::new(&offsets, &targets).unwrap();
    let mut k = vec![T::ZERO; targets.len()];
    batina_stiffness(&graph, &points, T::ONE, &mut k).unwrap();
    let mut anchor = vec![0u32; N];
    let base = SpringSystem::new(graph, &k, &fixed, &mut anchor).unwrap();
    let sys = AngleSystem::new(base, &points, T::from_f64(eps)).unwrap();
    let opts = SolveOptions {
        residual_tol: T::from_f64(tol),
        ..SolveOptions::default()
    };
    let solver = AngleSolver::Method(AngleMethod::Cg);
    let mut s = vec![[T::ZERO; 2]; angle_adjoint_scratch_len(&sys, &solver)];
    let mut g = vec![[T::ZERO; 2]; N];
    let r = angle_adjoint(&sys, solver, &opts, &w, &mut g, &mut s).unwrap();
    let mut jv = v;
    angle_tangent(&sys, solver, &opts, &mut jv, &mut s).unwrap();
    let flat = |x: &[[T; 2]]| x.iter().flatten().copied().collect::<Vec<T>>();
    hex(&format!("angle adjoint {tag}"), &flat(&g))
        + &format!(
            "angle adjoint {tag} report {} {}\n",
            r.iterations, r.converged as i32
        )
        + &hex(&format!("angle tangent {tag}"), &flat(&jv))
}

#[test]
fn angle_sensitivities_from_c_equal_the_kernel_bit_for_bit() {
    for (link, name) in [
        (Link::Static, "sensitivity_angle_c_static"),
        (Link::Shared, "sensitivity_angle_c_shared"),
    ] {
        let printed = run_c_test("sensitivity_angle", name, link);
        let lines: Vec<&str> = printed.lines().collect();
        assert_eq!(
            lines.last(),
            Some(&"sensitivity_angle: every check held"),
            "{name}: {printed}"
        );
        let points = parse_hex64(lines[0], "points");
        let w = parse_hex64(lines[1], "w");
        let v = parse_hex64(lines[2], "v");
        let inputs = [&points[..], &w, &v];
        let tol32 = SolveOptions::<f32>::default().residual_tol as f64;
        let want = expected::<f64>("f64", inputs, 0.0, 1e-13, hex64)
            + &expected::<f32>("f32", inputs, 0.01, tol32, hex32);
        let got = lines[3..9].join("\n") + "\n";
        assert_eq!(got, want, "{name}");
    }
}
