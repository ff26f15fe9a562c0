//! Reproduction of Yang & Özgen's rotating-airfoil experiment (§3): NACA 2412 pitched about
//! the quarter chord by 10°, 25° and 50°, on an inviscid triangle mesh and a viscous hybrid
//! mesh, deformed by linear springs and by angle-inclusion springs (direct and indirect).
//! Writes `docs/spring-reproduction.md`.
//!
//! `cargo run --release -p deform-host-tests --example spring_reproduction`

use std::fmt::Write as _;

use deform_kernel::quality::{compare, wall_angle_scratch_len, Wall};
use deform_kernel::spring::{
    batina_stiffness, solve_linear_scratch_len, AngleMethod, AngleSystem, LinearMethod,
    Preconditioner, SolveOptions, SolveReport, SpringSystem,
};
use deform_kernel::{graph_from_cells, graph_from_cells_len, Graph};
use deform_meshgen::{naca_hybrid, naca_triangulated, AirfoilGrid, Mesh2};

/// One spring method of the table.
#[derive(Clone, Copy)]
enum Method {
    Linear,
    Angle(AngleMethod, f64),
}

impl Method {
    fn label(self) -> String {
        match self {
            Method::Linear => "linear (Batina), CG+SSOR".to_string(),
            Method::Angle(AngleMethod::DirectGaussSeidel, e) => {
                format!("angle direct (GS), ε = {e}")
            }
            Method::Angle(AngleMethod::DirectJacobi, e) => {
                format!("angle direct (Jacobi), ε = {e}")
            }
            Method::Angle(AngleMethod::Cg, e) => format!("angle indirect (CG), ε = {e}"),
        }
    }
}

fn solve(
    sys: &SpringSystem<'_, f64>,
    points: &[[f64; 2]],
    method: Method,
    x: &mut [[f64; 2]],
) -> Result<SolveReport<f64>, String> {
    let n = x.len();
    match method {
        Method::Linear => {
            let m = LinearMethod::Cg {
                preconditioner: Preconditioner::Ssor { omega: 1.5 },
            };
            let opts = SolveOptions {
                residual_tol: 1e-10,
                max_iterations: 100_000,
                update_tol: 0.0,
            };
            let mut scratch = vec![[0.0; 2]; solve_linear_scratch_len(&m, n)];
            sys.solve_linear(x, m, &opts, &mut scratch)
                .map_err(|e| e.to_string())
        }
        Method::Angle(m, eps) => {
            let a = AngleSystem::new(*sys, points, eps).map_err(|e| e.to_string())?;
            let max_iterations = if m == AngleMethod::Cg {
                100_000
            } else {
                20_000
            };
            let opts = SolveOptions {
                residual_tol: 1e-10,
                max_iterations,
                update_tol: 0.0,
            };
            let mut scratch = vec![[0.0; 2]; a.angle_scratch_len(m)];
            a.solve_angle(x, m, &opts, &mut scratch)
                .map_err(|e| e.to_string())
        }
    }
}

/// Deformed points, the last step's report and the total iterations.
type Deformed = (Vec<[f64; 2]>, SolveReport<f64>, usize);

/// Deforms `mesh` by rotating the airfoil `deg` degrees in `steps` equal increments: each
/// step recomputes stiffness (and, for angle springs, edge directions) on the current mesh and
/// solves for the increment. Returns the deformed points, the last report and the total
/// iterations.
fn deform(
    mesh: &Mesh2,
    g: Graph<'_>,
    fixed: &[u8],
    wall_nodes: &[u32],
    method: Method,
    deg: f64,
    steps: usize,
) -> Result<Deformed, String> {
    let n = mesh.node_count();
    let mut pts = mesh.points.clone();
    let mut k = vec![0.0f64; g.edge_count()];
    let mut s = vec![0u32; n];
    let (sn, cs) = (deg / steps as f64).to_radians().sin_cos();
    let c = AirfoilGrid::quarter_chord();
    let mut total = 0;
    let mut last = None;
    for _ in 0..steps {
        batina_stiffness(&g, &pts, 1.0, &mut k).map_err(|e| e.to_string())?;
        let sys = SpringSystem::new(g, &k, fixed, &mut s).map_err(|e| e.to_string())?;
        let mut x = vec![[0.0; 2]; n];
        for &w in wall_nodes {
            let p = pts[w as usize];
            let (dx, dy) = (p[0] - c[0], p[1] - c[1]);
            x[w as usize] = [
                c[0] + cs * dx - sn * dy - p[0],
                c[1] + sn * dx + cs * dy - p[1],
            ];
        }
        let rep = solve(&sys, &pts, method, &mut x)?;
        total += rep.iterations;
        for (p, d) in pts.iter_mut().zip(&x) {
            p[0] += d[0];
            p[1] += d[1];
        }
        last = Some(rep);
    }
    last.map(|r| (pts, r, total))
        .ok_or_else(|| "no step".to_string())
}

fn table(
    out: &mut String,
    label: &str,
    mesh: &Mesh2,
    diagonals: bool,
    methods: &[(Method, usize)],
) {
    let n = mesh.node_count();
    let cells = mesh.cells().unwrap();
    let mut offsets = vec![0u32; n + 1];
    let mut targets = vec![0u32; graph_from_cells_len(&cells, diagonals)];
    let used = graph_from_cells(&cells, diagonals, &mut offsets, &mut targets).unwrap();
    targets.truncate(used);
    let g = Graph::new(&offsets, &targets).unwrap();
    let fixed = mesh.boundary_mask();
    let marker = mesh.require_marker("airfoil").unwrap();
    let wall = Wall::new(marker.cells(n).unwrap(), g).unwrap();
    let mut scratch = vec![[0.0; 2]; wall_angle_scratch_len(n)];
    let _ = writeln!(
        out,
        "\n### {label}\n\n{n} nodes, {} cells, {} edges{}.\n\n| pitch | method | solver | inverted | folded | min area ratio | max wall-angle change |\n|---:|---|---|---:|---:|---:|---:|",
        mesh.cell_count(),
        g.edge_count() / 2,
        if diagonals { " (quad face diagonals added)" } else { "" }
    );
    for deg in [10.0, 25.0, 50.0] {
        for &(m, steps) in methods {
            let t = std::time::Instant::now();
            let label = if steps > 1 {
                format!("{}, {steps} steps", m.label())
            } else {
                m.label()
            };
            let row = match deform(mesh, g, &fixed, &marker.node_list, m, deg, steps) {
                Ok((deformed, rep, total)) => {
                    let q = compare(&cells, &mesh.points, &deformed, Some(&wall), &mut scratch)
                        .unwrap();
                    let w = q.wall.map_or(f64::NAN, |w| w.max_change.to_degrees());
                    format!(
                        "| {deg}° | {label} | {total} it., res {:.1e}{} | {} | {} | {:.3} | {:.2}° |",
                        rep.residual,
                        if rep.converged {
                            ""
                        } else {
                            " **not converged**"
                        },
                        q.inverted_cells,
                        q.folded_cells,
                        q.min_measure_ratio,
                        w
                    )
                }
                Err(e) => format!("| {deg}° | {label} | error: {e} | – | – | – | – |"),
            };
            eprintln!("{row}  ({:.1} s)", t.elapsed().as_secs_f64());
            let _ = writeln!(out, "{row}");
        }
    }
}

const PREAMBLE: &str = "# Spring analogy on NACA 2412: reproduction of Yang & Özgen §3

The airfoil wall (marker `airfoil`) is rotated rigidly about the quarter chord `(0.25, 0)` by
10°, 25° and 50°; the far field (20 chords) is fixed. Meshes from `deform-meshgen`:
*inviscid* = `naca_triangulated(AirfoilGrid::inviscid())` (160 × 56, first layer 2e-3 chords,
every quad split into two triangles), *viscous* = `naca_hybrid(AirfoilGrid::viscous())`
(160 × 64, first layer 1e-5 chords, 24 quad layers at the wall, triangles outside).

Methods (`deform_kernel::spring`), all with Batina stiffness `k = 1/|e|` on the cell-edge graph,
solved to a relative residual of 1e-10:
- *linear (Batina)*: every displacement component solves the weighted Laplacian (Yang & Özgen
  §2.1), preconditioned CG (SSOR, ω = 1.5).
- *angle direct*: angle-inclusion springs (eq. 2), node-wise 2×2 Cramer solves in Gauss–Seidel
  order (§2.2.1), capped at 20 000 sweeps (it converges slowly: see the findings).
- *angle indirect*: the same operator by conjugate gradients (§2.2.2, eq. 4), block-Jacobi
  preconditioned.
- ε is the regularisation (`ε × linear spring` added to each edge block; kernel default 0.01).
  ε = 0 is the paper's operator; the kernel then proves the system non-singular first (rigidity
  probe) and reports `SingularSystem` otherwise.

Columns (`deform_kernel::quality::compare`): *inverted* = cells whose signed area changed sign;
*folded* = cells with a non-positive corner Jacobian; *min area ratio* = smallest
deformed/undeformed cell area; *max wall-angle change* = largest change of the first off-wall
grid line's angle at the airfoil (`quality::wall_angle_change`). *solver* = iterations (sweeps
or CG iterations) and the true relative residual reached.

*N steps*: the rotation applied in N equal increments, stiffness and edge directions
recomputed on the current mesh before each increment (the paper does not say whether it
steps; one step is a linear model of a finite rotation). The iteration count is the total.

Regenerate (a few minutes in release):

```
cargo run --release -p deform-host-tests --example spring_reproduction
```
";

fn main() {
    let mut out = String::from(PREAMBLE);
    let inviscid = naca_triangulated(&AirfoilGrid::inviscid()).unwrap();
    let viscous = naca_hybrid(&AirfoilGrid::viscous()).unwrap();
    let all = [
        (Method::Linear, 1),
        (Method::Angle(AngleMethod::Cg, 0.01), 1),
        (Method::Angle(AngleMethod::Cg, 0.0), 1),
        (Method::Angle(AngleMethod::DirectGaussSeidel, 0.01), 1),
        (Method::Linear, 10),
        (Method::Angle(AngleMethod::Cg, 0.01), 10),
    ];
    table(&mut out, "Inviscid triangles", &inviscid, false, &all);
    table(
        &mut out,
        "Viscous hybrid (quad boundary layer + triangles)",
        &viscous,
        false,
        &all,
    );
    let diag = [
        (Method::Linear, 1),
        (Method::Angle(AngleMethod::Cg, 0.01), 1),
        (Method::Angle(AngleMethod::Cg, 0.0), 1),
        (Method::Angle(AngleMethod::Cg, 0.01), 10),
    ];
    table(
        &mut out,
        "Viscous hybrid with quad diagonals (`graph_from_cells(.., true)`)",
        &viscous,
        true,
        &diag,
    );
    out.push_str(include_str!("spring_reproduction_notes.md"));
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../docs/spring-reproduction.md"
    );
    std::fs::write(path, out).unwrap();
    eprintln!("wrote {path}");
}
