//! `RotationSource::Rigid` for a rigid body inside a fixed far field (the C ABI's
//! `DK_ROTATIONS_RIGID`): the body's nodes get the rotation, the far-field nodes that stay in
//! place get the identity, so the result equals the per-node rotations `deform move` builds
//! (rotation on the moved marker, identity elsewhere) bit for bit. Before, the far field was
//! rotated too, which on this O-grid moved interior nodes by up to 0.07 chords.
//!
//! Nodes that stay in place because they are on the rotation axis (or at the origin) are part
//! of the body and keep the rotation.

use deform_kernel::quaternion::{
    deform_idw, deform_idw_scratch_len, BoundaryMotion, RotationSource,
};
use deform_kernel::{Quat, Real};

/// An O-grid annulus: `NI` nodes around, `NJ` rings from radius 0.5 (the body) to 10 (the far
/// field); node `i + NI j`.
const NI: usize = 48;
const NJ: usize = 16;

fn o_grid<T: Real>() -> Vec<[T; 2]> {
    let mut p = Vec::with_capacity(NI * NJ);
    for j in 0..NJ {
        let r = 0.5 * 20f64.powf(j as f64 / (NJ - 1) as f64);
        for i in 0..NI {
            let a = 2.0 * std::f64::consts::PI * i as f64 / NI as f64;
            p.push([T::from_f64(r * a.cos()), T::from_f64(r * a.sin())]);
        }
    }
    p
}

/// IDW deformation of `points` with the boundary `nodes` moved to `deformed`.
fn idw<T: Real, const D: usize>(
    points: &[[T; D]],
    nodes: &[u32],
    deformed: &[[T; D]],
    rotations: RotationSource<'_, T>,
    origin: Option<[T; D]>,
) -> Vec<[T; D]> {
    let n = points.len();
    let motion = BoundaryMotion {
        nodes,
        deformed,
        elements: None,
        rotations,
        origin,
    };
    let mut t = vec![[T::ZERO; D]; n];
    let mut r = vec![Quat::identity(); n];
    let mut s = vec![T::ZERO; deform_idw_scratch_len::<D>(n, nodes.len())];
    let mut out = vec![[T::ZERO; D]; n];
    deform_idw(
        points,
        &motion,
        T::from_f64(2.0),
        &mut t,
        &mut r,
        &mut s,
        &mut out,
    )
    .unwrap();
    out
}

fn bits<T: Real, const D: usize>(a: &[[T; D]]) -> Vec<u64> {
    a.iter().flatten().map(|x| x.to_bits_u64()).collect()
}

fn max_diff<T: Real, const D: usize>(a: &[[T; D]], b: &[[T; D]]) -> f64 {
    a.iter()
        .flatten()
        .zip(b.iter().flatten())
        .map(|(x, y)| (x.to_f64() - y.to_f64()).abs())
        .fold(0.0, f64::max)
}

/// The O-grid's wall pitched by 10° about `pivot` (the far field fixed): `Rigid` equals the
/// per-node rotations with the identity on the far field, not the old all-rotated field
/// (returned: `Rigid`, the per-node rotations, everything rotated).
fn pitch<T: Real>(pivot: [f64; 2], origin: Option<[T; 2]>) -> [Vec<[T; 2]>; 3] {
    let points = o_grid::<T>();
    let wall: Vec<u32> = (0..NI as u32).collect();
    let far: Vec<u32> = ((NI * (NJ - 1)) as u32..(NI * NJ) as u32).collect();
    let nodes: Vec<u32> = wall.iter().chain(&far).copied().collect();
    let q = Quat::from_rotation_z(T::from_f64(10f64.to_radians()));
    let c = [T::from_f64(pivot[0]), T::from_f64(pivot[1])];
    let deformed: Vec<[T; 2]> = nodes
        .iter()
        .map(|&i| {
            let p = points[i as usize];
            if (i as usize) < NI {
                if p == c {
                    return p; // the pivot stays exactly where it is
                }
                let r = q.rotate_2d([p[0] - c[0], p[1] - c[1]]);
                [r[0] + c[0], r[1] + c[1]]
            } else {
                p
            }
        })
        .collect();
    let rigid = idw(&points, &nodes, &deformed, RotationSource::Rigid(q), origin);
    let body: Vec<Quat<T>> = nodes
        .iter()
        .map(|&i| {
            if (i as usize) < NI {
                q
            } else {
                Quat::identity()
            }
        })
        .collect();
    let per_node = idw(
        &points,
        &nodes,
        &deformed,
        RotationSource::PerNode(&body),
        origin,
    );
    let all = vec![q; nodes.len()];
    let all_rotated = idw(
        &points,
        &nodes,
        &deformed,
        RotationSource::PerNode(&all),
        origin,
    );
    [rigid, per_node, all_rotated]
}

fn far_field_is_not_rotated<T: Real>() {
    let [rigid, per_node, all_rotated] = pitch::<T>([0.25, 0.0], None);
    assert_eq!(
        bits(&rigid),
        bits(&per_node),
        "Rigid = wall q, far field identity"
    );
    let d = max_diff(&rigid, &all_rotated);
    println!(
        "{}: rotating the far field too moves nodes by up to {d:.3}",
        if T::MANTISSA_DIGITS == 24 {
            "f32"
        } else {
            "f64"
        }
    );
    assert!(
        d > 1e-2,
        "the far field's rotation must matter on this grid: {d}"
    );
}

#[test]
fn rigid_rotation_leaves_a_fixed_far_field_unrotated_f64() {
    far_field_is_not_rotated::<f64>();
}

#[test]
fn rigid_rotation_leaves_a_fixed_far_field_unrotated_f32() {
    far_field_is_not_rotated::<f32>();
}

/// Pitching about a wall node (the origin): that node stays in place but is part of the body.
#[test]
fn a_wall_node_at_the_origin_keeps_the_rotation() {
    let pivot = o_grid::<f64>()[0];
    let [rigid, per_node, _] = pitch::<f64>(pivot, Some(pivot));
    assert_eq!(bits(&rigid), bits(&per_node));
}

/// 3D: a body whose nodes on the z axis stay in place under a turn about z keeps the rotation
/// on them; the fixed outer box gets the identity.
#[test]
fn nodes_on_the_rotation_axis_keep_the_rotation_3d() {
    let mut points: Vec<[f64; 3]> = Vec::new();
    // Body: a column of nodes on the z axis and a ring around it.
    for k in 0..5 {
        points.push([0.0, 0.0, k as f64 * 0.25]);
    }
    for a in 0..12 {
        let t = a as f64 * std::f64::consts::PI / 6.0;
        points.push([0.3 * t.cos(), 0.3 * t.sin(), 0.5]);
    }
    let body = points.len();
    // Far field: points of a box, none on the axis (a fixed node exactly on the axis could not
    // be told from the body: it would keep the rotation).
    for &x in &[-4.0, 0.0, 4.0] {
        for &y in &[-4.0, 0.0, 4.0] {
            for &z in &[-4.0, 4.5] {
                if x != 0.0 || y != 0.0 {
                    points.push([x, y, z]);
                }
            }
        }
    }
    let boundary = points.len();
    // Interior nodes.
    for k in 0..40 {
        let t = k as f64 * 0.7;
        let r = 0.6 + 0.08 * k as f64;
        points.push([r * t.cos(), r * t.sin(), -2.0 + 0.1 * k as f64]);
    }
    let nodes: Vec<u32> = (0..boundary as u32).collect();
    let q = Quat::from_axis_angle([0.0, 0.0, 1.0], 15f64.to_radians()).unwrap();
    let deformed: Vec<[f64; 3]> = points[..boundary]
        .iter()
        .enumerate()
        .map(|(k, &p)| {
            if k < body && (p[0] != 0.0 || p[1] != 0.0) {
                q.rotate(p)
            } else {
                p
            }
        })
        .collect();
    let rigid = idw(
        &points,
        &nodes,
        &deformed,
        RotationSource::Rigid(q),
        Some([0.0; 3]),
    );
    let per: Vec<Quat<f64>> = (0..boundary)
        .map(|k| if k < body { q } else { Quat::identity() })
        .collect();
    let per_node = idw(
        &points,
        &nodes,
        &deformed,
        RotationSource::PerNode(&per),
        Some([0.0; 3]),
    );
    assert_eq!(bits(&rigid), bits(&per_node));
}
