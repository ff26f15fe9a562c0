//! The cost of the fast IDW's and TFI's sensitivities against the deformation itself, for
//! callgrind instruction counts (deterministic under load): one deformation, tangent or
//! adjoint of an extruded NACA 2412 O-grid wing, twisted and bent (wall and far field the
//! boundary, one rigid rotation source, origin given).
//!
//! `cargo build --release -p deform-host-tests --example sensitivity_cost`, then
//! `valgrind --tool=callgrind target/release/examples/sensitivity_cost fast|tfi setup|deform|tangent|adjoint [SURFACE RADIAL LAYERS]`
//! (default `120 16 12`).

use deform_kernel::quaternion::{
    deform_idw_fast, deform_idw_fast_adjoint, deform_idw_fast_sensitivity_scratch_len,
    deform_idw_fast_tangent, deform_idw_scratch_len, deform_tfi, deform_tfi_adjoint,
    deform_tfi_scratch_len, deform_tfi_sensitivity_scratch_len, deform_tfi_tangent,
    propagate_idw_fast_index_len, propagate_idw_fast_scratch_len, BoundaryMotion, IdwFastOptions,
    RotationSource,
};
use deform_kernel::{Block, Direction, Directions, Quat};
use deform_meshgen::{extrude, naca_ogrid, twist_bend, AirfoilGrid, TwistBend};

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let usage =
        "usage: sensitivity_cost fast|tfi setup|deform|tangent|adjoint [SURFACE RADIAL LAYERS]";
    let (method, mode) = (args.first().expect(usage), args.get(1).expect(usage));
    let size: Vec<usize> = args
        .iter()
        .skip(2)
        .map(|a| a.parse().expect(usage))
        .collect();
    let (surface, radial, layers) = match size.as_slice() {
        [] => (120, 16, 12),
        [s, r, l] => (*s, *r, *l),
        _ => panic!("{usage}"),
    };
    let grid = AirfoilGrid {
        surface_points: surface,
        radial_points: radial,
        first_layer: 1e-3,
        ..AirfoilGrid::default()
    };
    let span = 3.0;
    let mesh = extrude(&naca_ogrid(&grid).unwrap(), span, layers - 1).unwrap();
    let map = TwistBend {
        span,
        tip_twist_deg: 10.0,
        tip_bend: 0.3,
        centre: [0.25, 0.0],
    };
    let moved = twist_bend(&mesh, &map).unwrap();
    let wall = &mesh.marker("airfoil").unwrap().node_list;
    let far = &mesh.marker("farfield").unwrap().node_list;
    let mut nodes: Vec<u32> = wall.clone();
    nodes.extend(far.iter().filter(|i| !wall.contains(i)));
    let (n, b) = (mesh.points.len(), nodes.len());
    let deformed: Vec<[f64; 3]> = nodes.iter().map(|&i| moved[i as usize]).collect();
    let motion = BoundaryMotion {
        nodes: &nodes,
        deformed: &deformed,
        elements: None,
        rotations: RotationSource::Rigid(Quat::from_rotation_z(0.1)),
        origin: Some([0.25, 0.0, 0.0]),
    };
    let p = &mesh.points;
    let (mut tr, mut rot) = (vec![[0.0; 3]; n], vec![Quat::identity(); n]);
    let mut out = vec![[0.0; 3]; n];
    let mut back = vec![[0.0; 3]; b];
    let dir: Vec<[f64; 3]> = (0..b).map(|k| [(k as f64).sin(), 0.5, 0.1]).collect();
    let w: Vec<[f64; 3]> = (0..n).map(|i| [(i as f64).cos(), 0.2, -0.3]).collect();
    let options = IdwFastOptions::default();
    let (mut index, mut tree) = (
        vec![0u32; propagate_idw_fast_index_len(b)],
        vec![0.0; propagate_idw_fast_scratch_len::<3>(b)],
    );
    let dims = mesh.dims.expect("a structured mesh");
    let block = Block::new(dims).unwrap();
    let dirs = Directions::only(Direction::J);
    let len = match method.as_str() {
        "fast" => deform_idw_scratch_len::<3>(n, b)
            .max(deform_idw_fast_sensitivity_scratch_len::<3>(n, b)),
        _ => deform_tfi_scratch_len::<3>(&block, b)
            .max(deform_tfi_sensitivity_scratch_len::<3>(&block, b)),
    };
    let mut s = vec![0.0; len];
    let (t, r, ix, tr2) = (&mut tr, &mut rot, &mut index, &mut tree);
    let m = &motion;
    match (method.as_str(), mode.as_str()) {
        ("fast", "deform") => {
            deform_idw_fast(p, m, 2.0, &options, t, r, &mut s, ix, tr2, &mut out).map(|_| ())
        }
        ("fast", "tangent") => {
            deform_idw_fast_tangent(p, m, 2.0, &options, &dir, t, r, &mut s, ix, tr2, &mut out)
        }
        ("fast", "adjoint") => {
            deform_idw_fast_adjoint(p, m, 2.0, &options, &w, t, r, &mut s, ix, tr2, &mut back)
        }
        (_, "setup") => Ok(()),
        ("tfi", "deform") => deform_tfi(&block, dirs, p, m, t, r, &mut s, &mut out).map(|_| ()),
        ("tfi", "tangent") => deform_tfi_tangent(&block, dirs, p, m, &dir, &mut s, &mut out),
        ("tfi", "adjoint") => deform_tfi_adjoint(&block, dirs, p, m, &w, &mut s, &mut back),
        _ => panic!("{usage}"),
    }
    .unwrap();
    let sum: f64 = out.iter().chain(&back).flatten().sum();
    println!("{method} {mode}: N = {n}, B = {b}, checksum {sum:.6e}");
}
