//! Mesh quality on target, in f32 and f64: exact measures of reference cells (2D and 3D), the
//! measures of a jittered triangle mesh summing to the domain area, `compare` under a rigid
//! motion (no inversion, measure ratio 1, wall angle unchanged) and under a fold, and typed
//! errors for cells that do not fit the point dimension.
#![no_std]
#![no_main]

use deform_on_target as _;

use deform_kernel::quality::{
    cell_measures, cell_quality, compare, folded_cells, inverted_cells, min_corner_jacobians,
    wall_angle_change, wall_angle_scratch_len, Wall,
};
use deform_kernel::{CellKind, Cells, Error, Quat, Real};
use deform_on_target::mesh::{Mesh, DY, N, NT, NX, NY};

fn reference_cells<T: Real>() {
    let f = T::from_f64;
    let sq = [
        [f(0.0), f(0.0)],
        [f(1.0), f(0.0)],
        [f(1.0), f(1.0)],
        [f(0.0), f(1.0)],
    ];
    let q = cell_quality(CellKind::Quad, &sq).unwrap();
    defmt::assert!(q.measure == T::ONE && q.min_scaled_jacobian == T::ONE);
    let tri = [[f(0.0), f(0.0)], [f(2.0), f(0.0)], [f(0.0), f(2.0)]];
    let q = cell_quality(CellKind::Triangle, &tri).unwrap();
    defmt::assert!(q.measure == T::TWO);
    let s45 = f(core::f64::consts::FRAC_1_SQRT_2);
    defmt::assert!((q.min_scaled_jacobian - s45).abs() <= T::from_f64(4.0) * T::EPSILON);
    let tet = [
        [f(0.0), f(0.0), f(0.0)],
        [f(1.0), f(0.0), f(0.0)],
        [f(0.0), f(1.0), f(0.0)],
        [f(0.0), f(0.0), f(1.0)],
    ];
    let q = cell_quality(CellKind::Tetra, &tet).unwrap();
    defmt::assert!((q.measure - f(1.0 / 6.0)).abs() <= T::EPSILON);
    let mut hex = [[T::ZERO; 3]; 8];
    for (c, h) in hex.iter_mut().enumerate() {
        let (x, y) = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)][c % 4];
        *h = [f(x), f(y), f((c / 4) as f64)];
    }
    let q = cell_quality(CellKind::Hexahedron, &hex).unwrap();
    defmt::assert!((q.measure - T::ONE).abs() <= T::from_f64(4.0) * T::EPSILON);
    defmt::assert!((q.min_scaled_jacobian - T::ONE).abs() <= T::from_f64(4.0) * T::EPSILON);
    // A bow-tie quad is folded although its net area is zero; an inverted triangle is negative.
    let bow = [
        [f(0.0), f(0.0)],
        [f(1.0), f(1.0)],
        [f(1.0), f(0.0)],
        [f(0.0), f(1.0)],
    ];
    defmt::assert!(cell_quality(CellKind::Quad, &bow).unwrap().min_jacobian <= T::ZERO);
    let flipped = [tri[0], tri[2], tri[1]];
    defmt::assert!(cell_quality(CellKind::Triangle, &flipped).unwrap().measure < T::ZERO);
    // Typed errors.
    defmt::assert!(matches!(
        cell_quality(CellKind::Tetra, &sq),
        Err(Error::CellDimension { .. })
    ));
    defmt::assert!(matches!(
        cell_quality(CellKind::Quad, &tri),
        Err(Error::LengthMismatch { .. })
    ));
}

fn mesh_quality<T: Real>() {
    let m = Mesh::<T>::new(0.25);
    let cells = m.cells();
    let mut area = [T::ZERO; NT];
    cell_measures(&cells, &m.points, &mut area).unwrap();
    defmt::assert!(area.iter().all(|&a| a > T::ZERO));
    let total = area.iter().fold(T::ZERO, |s, &a| s + a);
    let domain = T::from_f64((NX - 1) as f64 * (NY - 1) as f64 * DY);
    defmt::assert!((total - domain).abs() <= T::from_f64(64.0) * T::EPSILON * domain);
    let mut jac = [T::ZERO; NT];
    min_corner_jacobians(&cells, &m.points, true, &mut jac).unwrap();
    defmt::assert!(jac.iter().all(|&j| j > T::ZERO && j <= T::ONE));
    // A rigid motion: nothing inverts, ratios are 1, the wall angle does not change.
    let q = Quat::from_rotation_z(T::from_f64(0.6));
    let mut moved = m.points;
    for p in moved.iter_mut() {
        let r = q.rotate_2d(*p);
        *p = [r[0] + T::from_f64(3.0), r[1] - T::ONE];
    }
    let wall_nodes: [u32; 2 * (NX - 1)] = core::array::from_fn(|k| (k / 2 + k % 2) as u32);
    let wall_offsets: [u32; NX] = core::array::from_fn(|e| 2 * e as u32);
    let wall_kinds = [CellKind::Line.vtk_code(); NX - 1];
    let wall_cells = Cells::new(N, &wall_offsets, &wall_nodes, &wall_kinds).unwrap();
    let wall = Wall::new(wall_cells, m.graph()).unwrap();
    let mut scratch = [[T::ZERO; 2]; 2 * N];
    let len = wall_angle_scratch_len(N);
    let r = compare(&cells, &m.points, &moved, Some(&wall), &mut scratch[..len]).unwrap();
    let tol = T::from_f64(64.0) * T::EPSILON;
    defmt::assert_eq!((r.cells, r.inverted_cells, r.folded_cells), (NT, 0, 0));
    defmt::assert!((r.min_measure_ratio - T::ONE).abs() <= tol);
    defmt::assert!((r.max_measure_ratio - T::ONE).abs() <= tol);
    let w = r.wall.unwrap();
    defmt::assert_eq!(w.measured, NX);
    defmt::assert!(w.max_change <= tol);
    let w2 = wall_angle_change(&wall, &m.points, &moved, &mut scratch[..len]).unwrap();
    defmt::assert!(w2.max_change == w.max_change);
    // Push an interior node through its neighbours: cells invert and fold.
    let mut bad = m.points;
    bad[NX + 1] = [T::from_f64(3.5), T::from_f64(2.9)];
    let inv = inverted_cells(&cells, &m.points, &bad).unwrap();
    let fold = folded_cells(&cells, &bad).unwrap();
    defmt::assert!(inv > 0 && fold >= inv);
    let r = compare(&cells, &m.points, &bad, None, &mut []).unwrap();
    defmt::assert_eq!((r.inverted_cells, r.folded_cells), (inv, fold));
    defmt::assert!(r.min_measure_ratio < T::ZERO);
    // Typed errors: 2D cells with 3D points, wrong lengths, NaN.
    let p3 = [[T::ZERO; 3]; N];
    defmt::assert!(matches!(
        cell_measures(&cells, &p3, &mut area),
        Err(Error::CellDimension { .. })
    ));
    defmt::assert!(matches!(
        cell_measures(&cells, &m.points, &mut area[..NT - 1]),
        Err(Error::LengthMismatch { .. })
    ));
    let mut nan = m.points;
    nan[4][1] = T::from_f64(f64::NAN);
    defmt::assert!(matches!(
        compare(&cells, &m.points, &nan, None, &mut []),
        Err(Error::NonFinite { position: 4, .. })
    ));
}

#[defmt_test::tests]
mod tests {
    use super::*;

    #[test]
    fn reference_cells_f64() {
        reference_cells::<f64>();
    }

    #[test]
    fn reference_cells_f32() {
        reference_cells::<f32>();
    }

    #[test]
    fn mesh_quality_f64() {
        mesh_quality::<f64>();
    }

    #[test]
    fn mesh_quality_f32() {
        mesh_quality::<f32>();
    }
}
