//! `deform move`'s linear solvers: the multigrid-preconditioned CG (the default) and the
//! one-level CG variants solve the same problem, for the spring and the quaternion methods, in
//! 2D and 3D.

mod common;

use common::mesh_2d;
use deform_cli::engine::{run_move, Motion, MoveInput, MoveMethod, MoveSolver, Stiffness};
use deform_cli::formats::su2::{Su2Marker, Su2Mesh};
use deform_cli::formats::CellList;
use deform_kernel::CellKind;

/// An `n³`-node hexahedral block (slightly sheared), marker "bottom" (z = 0) and "rest" (the
/// other five faces).
fn block_3d(n: usize) -> Su2Mesh {
    let id = |i: usize, j: usize, k: usize| (i + n * (j + n * k)) as u32;
    let mut points = Vec::new();
    for k in 0..n {
        for j in 0..n {
            for i in 0..n {
                let (x, y, z) = (i as f64, j as f64, k as f64 * 0.8);
                points.push([x + 0.1 * z, y + 0.05 * x, z]);
            }
        }
    }
    let mut elements = CellList::new();
    let (mut bottom, mut rest) = (CellList::new(), CellList::new());
    for k in 0..n - 1 {
        for j in 0..n - 1 {
            for i in 0..n - 1 {
                elements.push(
                    CellKind::Hexahedron,
                    &[
                        id(i, j, k),
                        id(i + 1, j, k),
                        id(i + 1, j + 1, k),
                        id(i, j + 1, k),
                        id(i, j, k + 1),
                        id(i + 1, j, k + 1),
                        id(i + 1, j + 1, k + 1),
                        id(i, j + 1, k + 1),
                    ],
                );
            }
        }
    }
    let m = n - 1;
    for a in 0..m {
        for b in 0..m {
            bottom.push(
                CellKind::Quad,
                &[
                    id(a, b, 0),
                    id(a, b + 1, 0),
                    id(a + 1, b + 1, 0),
                    id(a + 1, b, 0),
                ],
            );
            rest.push(
                CellKind::Quad,
                &[
                    id(a, b, m),
                    id(a + 1, b, m),
                    id(a + 1, b + 1, m),
                    id(a, b + 1, m),
                ],
            );
            rest.push(
                CellKind::Quad,
                &[
                    id(0, a, b),
                    id(0, a, b + 1),
                    id(0, a + 1, b + 1),
                    id(0, a + 1, b),
                ],
            );
            rest.push(
                CellKind::Quad,
                &[
                    id(m, a, b),
                    id(m, a + 1, b),
                    id(m, a + 1, b + 1),
                    id(m, a, b + 1),
                ],
            );
            rest.push(
                CellKind::Quad,
                &[
                    id(a, 0, b),
                    id(a + 1, 0, b),
                    id(a + 1, 0, b + 1),
                    id(a, 0, b + 1),
                ],
            );
            rest.push(
                CellKind::Quad,
                &[
                    id(a, m, b),
                    id(a, m, b + 1),
                    id(a + 1, m, b + 1),
                    id(a + 1, m, b),
                ],
            );
        }
    }
    Su2Mesh {
        dim: 3,
        points,
        elements,
        markers: vec![
            Su2Marker {
                name: "bottom".into(),
                elements: bottom,
            },
            Su2Marker {
                name: "rest".into(),
                elements: rest,
            },
        ],
        passthrough: Vec::new(),
        text: Default::default(),
    }
}

fn run(mesh: &Su2Mesh, moved: &str, method: MoveMethod, solver: MoveSolver) -> Vec<[f64; 3]> {
    run_with(mesh, moved, (method, solver), 0.0)
}

/// [`run`] with the multigrid strength threshold `theta`.
fn run_with(
    mesh: &Su2Mesh,
    moved: &str,
    (method, solver): (MoveMethod, MoveSolver),
    theta: f64,
) -> Vec<[f64; 3]> {
    let moved_list: Vec<_> = mesh
        .markers
        .iter()
        .filter(|m| m.name == moved)
        .map(|m| &m.elements)
        .collect();
    let fixed: Vec<_> = mesh
        .markers
        .iter()
        .filter(|m| m.name != moved)
        .map(|m| &m.elements)
        .collect();
    let input = MoveInput {
        split: None,
        graph: None,
        dim: mesh.dim,
        points: &mesh.points,
        cells: &mesh.elements,
        moved: moved_list,
        fixed,
        motion: Motion::Rotate {
            degrees: 4.0,
            axis: [0.0, 0.0, 1.0],
            center: None,
        },
        method,
        solver,
        amg_strength: theta,
        tol: 1e-12,
        max_iter: 10_000,
        idw_exponent: 2.0,
        stiffness: Stiffness::Batina,
        idw_fast: None,
        reach: None,
    };
    let r = run_move(&input).expect("move");
    assert!(r.converged, "{method:?}/{solver:?} did not converge");
    if solver == MoveSolver::Amg {
        assert!(r.iterations > 0);
    }
    r.deformed
}

fn assert_close(a: &[[f64; 3]], b: &[[f64; 3]], what: &str) {
    let worst = a
        .iter()
        .zip(b)
        .flat_map(|(p, q)| p.iter().zip(q).map(|(x, y)| (x - y).abs()))
        .fold(0.0f64, f64::max);
    assert!(worst < 1e-8, "{what}: solutions differ by {worst:e}");
}

#[test]
fn every_solver_gives_the_same_deformation() {
    let m2 = mesh_2d(14, 9);
    let m3 = block_3d(8);
    for (mesh, moved) in [(&m2, "wall"), (&m3, "bottom")] {
        for method in [MoveMethod::Spring, MoveMethod::Quaternion] {
            let amg = run(mesh, moved, method, MoveSolver::Amg);
            for solver in [MoveSolver::Cg, MoveSolver::CgSsor] {
                let other = run(mesh, moved, method, solver);
                assert_close(&amg, &other, &format!("{method:?} amg vs {solver:?}"));
            }
        }
    }
}

/// `--amg-strength` reaches the hierarchy (other bits) and changes only the solver, not the
/// deformation (the same answer to the tolerance). These meshes are nearly isotropic, so the
/// default θ = 0.25 keeps every spring strong; θ = 0.9 drops the softer ones.
#[test]
fn amg_strength_changes_the_hierarchy_not_the_answer() {
    let m2 = mesh_2d(14, 9);
    let m3 = block_3d(8);
    for (mesh, moved) in [(&m2, "wall"), (&m3, "bottom")] {
        for method in [MoveMethod::Spring, MoveMethod::Quaternion] {
            let how = (method, MoveSolver::Amg);
            let plain = run_with(mesh, moved, how, 0.0);
            let strong = run_with(mesh, moved, how, 0.9);
            assert_close(&plain, &strong, &format!("{method:?} θ = 0 vs 0.9"));
            let bits = |v: &[[f64; 3]]| v.iter().flatten().map(|x| x.to_bits()).collect::<Vec<_>>();
            assert_ne!(bits(&plain), bits(&strong), "{method:?}: θ was not used");
        }
    }
}

/// `--amg-strength` outside [0, 1), or where no multigrid is built, is refused before
/// anything is written (`deform move` and `deform adjoint`).
#[test]
fn amg_strength_is_checked_and_only_for_multigrid() {
    let d = common::tmp_dir("move-amg-strength-bad");
    common::naca_mesh(&d, "inviscid", 32, 8, "m.su2");
    for (extra, needle) in [
        (&["--method", "idw"][..], "applies to --solver amg"),
        (&["--method", "elasticity"][..], "applies to --solver amg"),
        (
            &["--method", "spring", "--solver", "cg"][..],
            "applies to --solver amg",
        ),
        (&["--method", "spring"][..], "[0, 1)"),
    ] {
        let theta = if needle == "[0, 1)" { "1" } else { "0.1" };
        let mut args = vec!["move", "m.su2", "--marker", "airfoil", "--rotate", "3"];
        args.extend_from_slice(extra);
        args.extend_from_slice(&["--amg-strength", theta, "--out", "o.su2"]);
        common::deform_refused(&d, &args, 1, needle, "o.su2");
    }
    common::deform_refused(
        &d,
        &[
            "adjoint",
            "m.su2",
            "--sensitivity",
            "s.csv",
            "--method",
            "idw",
            "--amg-strength",
            "0.1",
            "--out",
            "g.csv",
        ],
        1,
        "--amg-strength applies to --method spring, quaternion or angle",
        "g.csv",
    );
}
