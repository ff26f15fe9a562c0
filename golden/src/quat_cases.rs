//! Golden cases for [`Quat`] and [`QuatAverage`]. Each function is generic over the scalar
//! and returns the hash of all its output bits.

use deform_kernel::{Quat, QuatAverage, Real};

use crate::{Fnv, XorShift};

/// Number of random samples per case.
const N: usize = 64;

/// Hamilton products, conjugates, dot products, norms and inverses of random (non-unit)
/// quaternions.
pub fn products<T: Real>() -> u64 {
    let mut rng = XorShift::new(0x5157_0001);
    let mut h = Fnv::new();
    for _ in 0..N {
        let a: Quat<T> = rng.quat();
        let b: Quat<T> = rng.quat();
        h.quat(a * b);
        h.quat(b * a);
        h.quat(a.conjugate());
        h.real(a.dot(b));
        h.real(a.norm());
        h.result_quat(a.inverse());
        h.quat(a + b);
        h.quat(a - b);
        h.quat(-a);
        h.quat(a.scale(T::from_f64(0.75)));
    }
    h.finish()
}

/// Rotation of random vectors by random unit quaternions (3D, 2D and the matrix form), and
/// composition.
pub fn rotate<T: Real>() -> u64 {
    let mut rng = XorShift::new(0x5157_0002);
    let mut h = Fnv::new();
    for _ in 0..N {
        let q: Quat<T> = rng.unit_quat();
        let p: Quat<T> = rng.unit_quat();
        let v: [T; 3] = rng.vec3(-10.0, 10.0);
        h.reals(q.rotate(v));
        h.reals(q.rotate_2d([v[0], v[1]]));
        for row in q.to_matrix() {
            h.reals(row);
        }
        h.reals((p * q).rotate(v));
        h.reals(p.rotate(q.rotate(v)));
    }
    h.finish()
}

/// Rotation arcs between random directions, plus parallel, antiparallel, nearly parallel,
/// nearly antiparallel, 90° and degenerate (zero, non-finite) inputs.
pub fn rotation_arc<T: Real>() -> u64 {
    let mut rng = XorShift::new(0x5157_0003);
    let mut h = Fnv::new();
    for i in 0..N {
        let u: [T; 3] = rng.vec3(-1.0, 1.0);
        let w: [T; 3] = rng.vec3(-1.0, 1.0);
        let tiny = T::from_f64(1e-3 * rng.unit_f64()).powf(T::from_u32((i % 4) as u32 + 1));
        let near = [u[0] + tiny * w[0], u[1] + tiny * w[1], u[2] + tiny * w[2]];
        let anti = [-near[0], -near[1], -near[2]];
        let exact_anti = [-u[0], -u[1], -u[2]];
        for (from, to) in [(u, w), (u, u), (u, near), (u, anti), (u, exact_anti)] {
            let r = Quat::rotation_arc(from, to);
            h.result_quat(r);
            if let Ok(q) = r {
                h.reals(q.rotate(from));
            }
        }
    }
    let z = T::ZERO;
    let one = T::ONE;
    let special: [([T; 3], [T; 3]); 6] = [
        ([one, z, z], [z, one, z]),
        ([one, z, z], [-one, z, z]),
        ([z, z, one], [z, z, -one]),
        ([z, z, z], [one, z, z]),
        ([one, z, z], [z, z, z]),
        ([T::INFINITY, z, z], [one, z, z]),
    ];
    for (from, to) in special {
        h.result_quat(Quat::rotation_arc(from, to));
    }
    h.finish()
}

/// Slerp and nlerp between random unit quaternions at several parameters, including the end
/// points, nearly equal and opposite-hemisphere pairs.
pub fn slerp<T: Real>() -> u64 {
    let mut rng = XorShift::new(0x5157_0004);
    let mut h = Fnv::new();
    let ts = [0.0, 1.0, 0.5, 0.25, 0.9, -0.5, 1.5];
    for i in 0..N {
        let a: Quat<T> = rng.unit_quat();
        let b: Quat<T> = if i % 4 == 3 {
            // Nearly equal: exercises the small-angle fallback.
            let d: Quat<T> = rng.quat();
            (a + d.scale(T::from_f64(1e-7))).normalize().unwrap_or(a)
        } else {
            rng.unit_quat()
        };
        let b = if i % 2 == 1 { -b } else { b };
        for t in ts {
            let t = T::from_f64(t);
            h.result_quat(Quat::slerp(a, b, t));
            h.result_quat(Quat::nlerp(a, b, t));
        }
    }
    h.result_quat(Quat::slerp(
        Quat::identity(),
        Quat::new(T::ZERO, T::ZERO, T::ZERO, T::INFINITY),
        T::HALF,
    ));
    h.finish()
}

/// Axis-angle construction and decomposition, the angle, and the z rotations.
pub fn axis_angle<T: Real>() -> u64 {
    let mut rng = XorShift::new(0x5157_0005);
    let mut h = Fnv::new();
    for _ in 0..N {
        let axis: [T; 3] = rng.vec3(-1.0, 1.0);
        let angle: T = rng.uniform(-7.0, 7.0);
        let r = Quat::from_axis_angle(axis, angle);
        h.result_quat(r);
        if let Ok(q) = r {
            let (ax, an) = q.to_axis_angle();
            h.reals(ax);
            h.real(an);
            h.real(q.angle());
        }
        let qz = Quat::from_rotation_z(angle);
        h.quat(qz);
        h.real(qz.rotation_z_angle());
        h.reals(qz.rotate_2d([axis[0], axis[1]]));
    }
    let z = T::ZERO;
    h.result_quat(Quat::from_axis_angle([z, z, z], T::ONE));
    h.result_quat(Quat::from_axis_angle([T::ONE, z, z], T::INFINITY));
    let (ax, an) = Quat::<T>::identity().to_axis_angle();
    h.reals(ax);
    h.real(an);
    h.finish()
}

/// Weighted hemisphere-aligned averages of clustered rotations, some given as `−q`.
pub fn average<T: Real>() -> u64 {
    let mut rng = XorShift::new(0x5157_0006);
    let mut h = Fnv::new();
    for _ in 0..N {
        let centre: Quat<T> = rng.unit_quat();
        let mut avg = QuatAverage::new();
        let mut avg_ref = QuatAverage::with_reference(-centre);
        for k in 0..6 {
            let d: Quat<T> = rng.quat();
            let q = (centre + d.scale(T::from_f64(0.2)))
                .normalize()
                .unwrap_or(centre);
            let q = if k % 3 == 1 { -q } else { q };
            let w: T = rng.uniform(0.1, 2.0);
            avg.add(q, w);
            avg_ref.add(q, w);
        }
        h.real(avg.total_weight());
        h.result_quat(avg.result());
        h.result_quat(avg_ref.result());
    }
    h.result_quat(QuatAverage::<T>::new().result());
    let mut cancel = QuatAverage::<T>::new();
    cancel.add(Quat::identity(), T::ONE);
    cancel.add(Quat::identity(), -T::ONE);
    h.result_quat(cancel.result());
    h.finish()
}

/// Normalisation and inversion of random, tiny, huge, zero and non-finite quaternions.
pub fn normalize<T: Real>() -> u64 {
    let mut rng = XorShift::new(0x5157_0007);
    let mut h = Fnv::new();
    for i in 0..N {
        let q: Quat<T> = rng.quat();
        let s = match i % 4 {
            0 => T::ONE,
            1 => T::from_f64(1e-20),
            2 => T::from_f64(1e15),
            _ => T::from_f64(3.0),
        };
        let q = q.scale(s);
        h.result_quat(q.normalize());
        h.result_quat(q.inverse());
        if let Ok(u) = q.normalize() {
            h.real(u.norm());
            h.quat(u * u.conjugate());
        }
    }
    let z = T::ZERO;
    let nan = T::from_f64(f64::NAN);
    for q in [
        Quat::new(z, z, z, z),
        Quat::new(T::MIN_POSITIVE, z, z, z),
        Quat::new(nan, z, z, z),
        Quat::new(T::ONE, T::INFINITY, z, z),
        Quat::new(T::MAX, T::MAX, z, z),
    ] {
        h.result_quat(q.normalize());
        h.result_quat(q.inverse());
    }
    h.finish()
}
