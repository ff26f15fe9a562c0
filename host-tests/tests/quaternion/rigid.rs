//! Rigid motion through every quaternion-deformation pipeline (Samareh): when all boundaries
//! move by one rotation and translation, every mesh point must follow that rigid motion, in
//! 2D and 3D, `f32` and `f64`, for inverse distance, TFI and linear springs, and boundary
//! points must equal the prescribed `r^d` bit for bit.
//!
//! Errors are measured in units of `ε · L` (`ε` the type's machine epsilon, `L` the largest
//! coordinate of the deformed mesh) against the rigid motion evaluated in `f64` with the same
//! (rounded) quaternion the kernel was given. Print with `-- --nocapture`.
//!
//! - `Rigid(q)` source: the kernel uses exactly `q`; the bound is 16 ε L.
//! - `Shape` source: the rotations are re-derived from the boundary geometry (normals, edge
//!   directions), whose rounding is amplified by the short boundary edges relative to the
//!   coordinates; the bound is 64 ε L (measured worst: about 8 ε L).

#[path = "../support/mod.rs"]
mod support;

use deform_kernel::quaternion::{
    deform_idw, deform_idw_scratch_len, deform_spring, deform_spring_scratch_len, deform_tfi,
    deform_tfi_scratch_len, propagate_spring_scratch_len, BoundaryMotion, RotationSource,
};
use deform_kernel::spring::{
    batina_stiffness, LinearMethod, Preconditioner, SolveOptions, SpringSystem,
};
use deform_kernel::Directions;
use deform_kernel::{graph_from_cells, graph_from_cells_len, Graph, Quat, Real};
use support::quaternion::{bits, block2, block3, max_err, scale, Rigid, TestMesh};

#[derive(Clone, Copy, Debug)]
enum Method {
    Idw,
    Tfi,
    Spring,
}

#[derive(Clone, Copy, Debug)]
enum Source {
    Rigid,
    Shape,
}

/// Runs one pipeline; returns the deformed mesh.
fn run<T: Real, const D: usize>(
    mesh: &TestMesh<D>,
    deformed: &[[T; D]],
    q: Quat<T>,
    method: Method,
    source: Source,
) -> Vec<[T; D]> {
    let points = mesh.points_t::<T>();
    let n = points.len();
    let b = mesh.boundary.len();
    let motion = BoundaryMotion {
        nodes: &mesh.boundary,
        deformed,
        elements: Some(mesh.elements()),
        rotations: match source {
            Source::Rigid => RotationSource::Rigid(q),
            Source::Shape => RotationSource::Shape,
        },
        origin: None,
    };
    let mut t = vec![[T::ZERO; D]; n];
    let mut r = vec![Quat::identity(); n];
    let mut out = vec![[T::ZERO; D]; n];
    match method {
        Method::Idw => {
            let mut s = vec![T::ZERO; deform_idw_scratch_len::<D>(n, b)];
            deform_idw(
                &points,
                &motion,
                T::from_f64(3.0),
                &mut t,
                &mut r,
                &mut s,
                &mut out,
            )
            .unwrap();
        }
        Method::Tfi => {
            let block = mesh.block();
            let mut s = vec![T::ZERO; deform_tfi_scratch_len::<D>(&block, b)];
            let dirs = [true, true, D == 3];
            deform_tfi(
                &block,
                Directions::from_flags(dirs),
                &points,
                &motion,
                &mut t,
                &mut r,
                &mut s,
                &mut out,
            )
            .unwrap();
        }
        Method::Spring => {
            let cells = mesh.cells();
            let mut offsets = vec![0u32; n + 1];
            let mut targets = vec![0u32; graph_from_cells_len(&cells, true)];
            let used = graph_from_cells(&cells, true, &mut offsets, &mut targets).unwrap();
            let graph = Graph::new(&offsets, &targets[..used]).unwrap();
            let mut k = vec![T::ZERO; used];
            batina_stiffness(&graph, &points, T::ONE, &mut k).unwrap();
            let mut fixed = vec![0u8; n];
            for &i in &mesh.boundary {
                fixed[i as usize] = 1;
            }
            let mut sscratch = vec![0u32; SpringSystem::<T>::scratch_len(n)];
            let sys = SpringSystem::new(graph, &k, &fixed, &mut sscratch).unwrap();
            let method = LinearMethod::Cg {
                preconditioner: Preconditioner::Jacobi,
            };
            let options = SolveOptions::default();
            let mut s = vec![T::ZERO; deform_spring_scratch_len::<D>(n, b)];
            let mut values = vec![T::ZERO; propagate_spring_scratch_len::<D>(&method, n)];
            let (_, report) = deform_spring(
                &points,
                &motion,
                &sys,
                method,
                &options,
                &mut t,
                &mut r,
                &mut s,
                &mut values,
                &mut out,
            )
            .unwrap();
            assert!(report.converged, "{report:?}");
        }
    }
    out
}

/// Checks one case; returns the error in units of `ε L`.
fn check<T: Real, const D: usize>(
    mesh: &TestMesh<D>,
    q64: [f64; 4],
    c: [f64; 3],
    tr: [f64; 3],
    method: Method,
    source: Source,
) -> f64 {
    let q = Quat::new(
        T::from_f64(q64[0]),
        T::from_f64(q64[1]),
        T::from_f64(q64[2]),
        T::from_f64(q64[3]),
    );
    // The exact motion uses the rounded quaternion the kernel sees.
    let motion = Rigid::new(
        [q.w.to_f64(), q.x.to_f64(), q.y.to_f64(), q.z.to_f64()],
        c,
        tr,
    );
    let points_t = mesh.points_t::<T>();
    let exact: Vec<[f64; D]> = points_t
        .iter()
        .map(|p| motion.apply(p.map(|x| x.to_f64())))
        .collect();
    let deformed: Vec<[T; D]> = mesh
        .boundary
        .iter()
        .map(|&i| exact[i as usize].map(T::from_f64))
        .collect();
    let out = run::<T, D>(mesh, &deformed, q, method, source);
    let got_b: Vec<[T; D]> = mesh.boundary.iter().map(|&i| out[i as usize]).collect();
    assert_eq!(bits(&got_b), bits(&deformed), "boundary not bitwise");
    let l = scale(&exact);
    let e = max_err(&out, &exact) / (T::EPSILON.to_f64() * l);
    let bound = match source {
        Source::Rigid => 16.0,
        Source::Shape => 64.0,
    };
    println!(
        "{}D {:>3} {:?} {:?}: max error {:.2} eps*L",
        D,
        core::any::type_name::<T>(),
        method,
        source,
        e
    );
    assert!(
        e <= bound,
        "{D}D {method:?} {source:?}: {e} eps*L > {bound}"
    );
    e
}

fn quat_z(angle: f64) -> [f64; 4] {
    [(angle / 2.0).cos(), 0.0, 0.0, (angle / 2.0).sin()]
}

fn quat_axis(axis: [f64; 3], angle: f64) -> [f64; 4] {
    let n = (axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]).sqrt();
    let s = (angle / 2.0).sin() / n;
    [(angle / 2.0).cos(), axis[0] * s, axis[1] * s, axis[2] * s]
}

fn all_2d<T: Real>() {
    let mesh = block2(13, 9);
    for angle in [0.9, -2.5, 3.0] {
        for method in [Method::Idw, Method::Tfi, Method::Spring] {
            for source in [Source::Rigid, Source::Shape] {
                check::<T, 2>(
                    &mesh,
                    quat_z(angle),
                    [0.8, 0.3, 0.0],
                    [0.3, -0.2, 0.0],
                    method,
                    source,
                );
            }
        }
    }
}

fn all_3d<T: Real>() {
    let mesh = block3(7, 6, 5);
    for (axis, angle) in [([1.0, 2.0, 3.0], 0.7), ([-0.3, 1.0, 0.2], 2.6)] {
        for method in [Method::Idw, Method::Tfi, Method::Spring] {
            for source in [Source::Rigid, Source::Shape] {
                check::<T, 3>(
                    &mesh,
                    quat_axis(axis, angle),
                    [0.5, 0.6, 0.4],
                    [0.3, -0.2, 0.5],
                    method,
                    source,
                );
            }
        }
    }
}

#[test]
fn rigid_motion_2d_f64() {
    all_2d::<f64>();
}

#[test]
fn rigid_motion_2d_f32() {
    all_2d::<f32>();
}

#[test]
fn rigid_motion_3d_f64() {
    all_3d::<f64>();
}

#[test]
fn rigid_motion_3d_f32() {
    all_3d::<f32>();
}

/// A half turn flips every normal (antiparallel undeformed/deformed normals): the 3D shape
/// rotations must still recover the rigid motion (the twist completes the arbitrary-axis
/// half-turn of the normal alignment).
#[test]
fn half_turn_3d_shape() {
    let mesh = block3(5, 5, 4);
    for method in [Method::Idw, Method::Tfi] {
        check::<f64, 3>(
            &mesh,
            quat_axis([0.0, 0.0, 1.0], std::f64::consts::PI),
            [0.5, 0.6, 0.4],
            [0.1, 0.0, 0.0],
            method,
            Source::Shape,
        );
    }
}

/// Property (Samareh: a rigid boundary motion is reproduced exactly): for random rotations,
/// centres and translations, every node of the small test meshes follows the rigid motion to
/// within the bounds above, with IDW and TFI, both rotation sources, 2D and 3D, `f64`.
#[test]
fn rigid_motion_property() {
    use proptest::prelude::*;
    use proptest::test_runner::{Config, TestRunner};
    let m2 = block2(9, 7);
    let m3 = block3(5, 4, 4);
    let mut runner = TestRunner::new(Config {
        cases: 48,
        ..Config::default()
    });
    let unit = -1.0f64..1.0;
    let strategy = (
        [unit.clone(), unit.clone(), unit.clone()],
        -3.1f64..3.1,
        [unit.clone(), unit.clone(), unit.clone()],
        [unit.clone(), unit.clone(), unit],
    );
    runner
        .run(&strategy, |(axis, angle, c, t)| {
            prop_assume!(axis.iter().map(|a| a * a).sum::<f64>() > 0.01);
            for method in [Method::Idw, Method::Tfi] {
                for source in [Source::Rigid, Source::Shape] {
                    check::<f64, 2>(&m2, quat_z(angle), c, [t[0], t[1], 0.0], method, source);
                    check::<f64, 3>(&m3, quat_axis(axis, angle), c, t, method, source);
                }
            }
            Ok(())
        })
        .unwrap();
}
