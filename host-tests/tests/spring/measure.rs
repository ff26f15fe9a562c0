//! The ~20k-node NACA 2412 mesh (meshgen `preset_20k`, triangulated, first layer 1e-5 chords)
//! with the airfoil rotated 10° about the quarter chord: the fast solvers must reach a relative
//! residual of 1e-10. Iteration counts are printed (`--nocapture`), never timed. The other
//! methods (Jacobi, Gauss–Seidel, SOR, plain CG, the angle-inclusion solvers) take too long in
//! a debug build; they are measured by
//! `cargo run --release -p deform-host-tests --example spring_iterations`.

use deform_kernel::spring::{
    batina_stiffness, solve_linear_scratch_len, LinearMethod, Preconditioner, SolveOptions,
    SpringSystem,
};
use deform_kernel::{graph_from_cells, graph_from_cells_len, Graph};
use deform_meshgen::{naca_triangulated, rotate_markers2, AirfoilGrid};

#[test]
fn fast_solvers_converge_on_20k_airfoil_mesh() {
    let mesh = naca_triangulated(&AirfoilGrid::preset_20k()).unwrap();
    let n = mesh.node_count();
    assert!(n >= 20_000);
    let cells = mesh.cells().unwrap();
    let mut offsets = vec![0u32; n + 1];
    let mut targets = vec![0u32; graph_from_cells_len(&cells, false)];
    let used = graph_from_cells(&cells, false, &mut offsets, &mut targets).unwrap();
    let g = Graph::new(&offsets, &targets[..used]).unwrap();
    let mut k = vec![0.0f64; g.edge_count()];
    batina_stiffness(&g, &mesh.points, 1.0, &mut k).unwrap();
    let fixed = mesh.boundary_mask();
    let mut s = vec![0u32; n];
    let sys = SpringSystem::new(g, &k, &fixed, &mut s).unwrap();
    let rot = rotate_markers2(&mesh, &["airfoil"], AirfoilGrid::quarter_chord(), 10.0).unwrap();
    let x0 = rot.to_field(n);
    let opts = SolveOptions {
        residual_tol: 1e-10,
        max_iterations: 20_000,
        update_tol: 0.0,
    };
    let mut counts = vec![];
    for (name, m) in [
        (
            "CG+Jacobi",
            LinearMethod::Cg {
                preconditioner: Preconditioner::Jacobi,
            },
        ),
        (
            "CG+SSOR 1.0",
            LinearMethod::Cg {
                preconditioner: Preconditioner::Ssor { omega: 1.0 },
            },
        ),
        (
            "CG+SSOR 1.5",
            LinearMethod::Cg {
                preconditioner: Preconditioner::Ssor { omega: 1.5 },
            },
        ),
    ] {
        let mut x = x0.clone();
        let mut scratch = vec![[0.0; 2]; solve_linear_scratch_len(&m, n)];
        let rep = sys.solve_linear(&mut x, m, &opts, &mut scratch).unwrap();
        println!(
            "{name:12} {:>6} iterations, relative residual {:.2e}",
            rep.iterations, rep.residual
        );
        assert!(rep.converged, "{name}: {rep:?}");
        assert!(rep.residual <= 1e-10);
        assert_eq!(sys.relative_residual(&x).unwrap(), rep.residual);
        counts.push(rep.iterations);
    }
    println!("iterations: {counts:?}");
}
