//! RBF mesh deformation (issue 28 items 2 and 4): the kernel's thin-plate-spline RBF with
//! every boundary node a centre (`tolerance` 0, so no greedy selection: the dense saddle-point
//! system, LU, then one evaluation pass over every node) on a NACA 2412 mesh like the spring
//! rows' (512 × 160 = 81,920 nodes and 1,024 centres; `--quick` 256 × 80), the airfoil
//! pitched 10° about the quarter chord and the far field fixed. The points, the boundary, its
//! motion and the kernel's displacements go to `DIR/rbf_*` for `bench/peers/rbf.py` (scipy's
//! `RBFInterpolator`, `thin_plate_spline`, degree 1, on the same centres).

use std::path::Path;
use std::time::Instant;

use deform_kernel::rbf::{rbf_deform, rbf_index_len, rbf_scratch_len, RbfKernel, RbfOptions};
use deform_meshgen::{naca_triangulated, rotate_markers2, AirfoilGrid};

use crate::{write_f64, write_u32, Figures};

/// Fit + evaluation, the median of `reps` runs (no warm-up: one run takes seconds at full size).
pub(crate) fn rbf(airfoil: [usize; 2], reps: usize, dir: &Path, fig: &mut Figures) {
    let [surface, radial] = airfoil;
    let grid = AirfoilGrid {
        surface_points: surface,
        radial_points: radial,
        first_layer: 1e-5,
        boundary_layers: 40,
        ..AirfoilGrid::default()
    };
    let mesh = naca_triangulated(&grid).expect("mesh");
    let n = mesh.node_count();
    let mask = mesh.boundary_mask();
    let boundary: Vec<u32> = (0..n as u32).filter(|&i| mask[i as usize] != 0).collect();
    let rot = rotate_markers2(&mesh, &["airfoil"], AirfoilGrid::quarter_chord(), -10.0)
        .expect("rotation");
    let field: Vec<[f64; 2]> = rot.to_field(n);
    let motion: Vec<[f64; 2]> = boundary.iter().map(|&b| field[b as usize]).collect();
    let opts = RbfOptions {
        kernel: RbfKernel::ThinPlate,
        tolerance: 0.0,
        max_centres: boundary.len(),
        correction_radius: 0.0,
    };
    println!(
        "rbf: NACA 2412 {surface} × {radial} = {n} nodes, {} centres (thin-plate spline)",
        boundary.len()
    );
    let mut index = vec![0u32; rbf_index_len::<f64, 2>(boundary.len(), &opts)];
    let mut scratch = vec![0.0f64; rbf_scratch_len::<f64, 2>(boundary.len(), &opts)];
    let mut out = vec![[0.0f64; 2]; n];
    let mut times: Vec<f64> = (0..reps.max(1))
        .map(|_| {
            let t = Instant::now();
            let pts = &mesh.points;
            rbf_deform(
                pts,
                &boundary,
                &motion,
                &opts,
                &mut index,
                &mut scratch,
                &mut out,
            )
            .expect("rbf");
            t.elapsed().as_secs_f64()
        })
        .collect();
    times.sort_by(f64::total_cmp);
    fig.put("rbf_nodes", n);
    fig.put("rbf_centres", boundary.len());
    fig.put("rbf_s", times[times.len() / 2]);
    let flat = |v: &[[f64; 2]]| v.iter().flatten().copied().collect::<Vec<f64>>();
    write_f64(&dir.join("rbf_points.f64"), flat(&mesh.points));
    write_u32(&dir.join("rbf_boundary.u32"), &boundary);
    write_f64(&dir.join("rbf_motion.f64"), flat(&motion));
    write_f64(&dir.join("rbf_result.f64"), flat(&out));
}
