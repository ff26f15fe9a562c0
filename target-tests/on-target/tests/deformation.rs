//! The quaternion deformation (Samareh) on target, in f32 and f64, on a small jittered
//! triangle mesh / 6 × 5 structured block: `deform_idw`, `deform_tfi` and `deform_spring`
//! reproduce a rigid motion of the whole boundary within a few ε·L (also with rotations taken
//! from the boundary shape), reproduce every boundary node bit for bit under a non-rigid
//! motion, and reject bad input with typed errors, leaving `out` untouched. The fast IDW
//! (`propagate_idw_fast`) stays within its reported bound of the exact IDW, equals it to
//! rounding at `θ = 0`, reproduces a uniform translation, and rejects a bad `θ`.
#![no_std]
#![no_main]

use deform_kernel::Directions;
use deform_on_target as _;

use deform_kernel::quaternion::{
    deform_idw, deform_idw_scratch_len, deform_spring, deform_spring_scratch_len, deform_tfi,
    deform_tfi_scratch_len, propagate_idw, propagate_idw_fast, propagate_idw_fast_index_len,
    propagate_idw_fast_scratch_len, propagate_spring_scratch_len, BoundaryMotion, IdwFastOptions,
    RotationSource,
};
use deform_kernel::spring::{
    batina_stiffness, LinearMethod, Preconditioner, SolveOptions, SpringSystem,
};
use deform_kernel::{Cells, Error, Quat, Real};
use deform_on_target::mesh::{block, Mesh, N, NB, NE, NX, NY};
use deform_on_target::{max_diff, precision, same_bits};

/// Scratch large enough for every pipeline here.
const S: usize = 16 * N;

/// The three pipelines.
#[derive(Clone, Copy, PartialEq)]
enum Pipeline {
    Idw,
    Tfi,
    Spring,
}

/// Runs `pipeline` on mesh `m` with `motion`; returns the output or the error.
fn run<T: Real>(
    pipeline: Pipeline,
    m: &Mesh<T>,
    motion: &BoundaryMotion<'_, T, 2>,
    out: &mut [[T; 2]],
) -> Result<(), Error> {
    let mut translations = [[T::ZERO; 2]; N];
    let mut rotations = [Quat::identity(); N];
    let mut scratch = [T::ZERO; S];
    match pipeline {
        Pipeline::Idw => {
            let len = deform_idw_scratch_len::<2>(N, motion.nodes.len());
            deform_idw(
                &m.points,
                motion,
                T::TWO,
                &mut translations,
                &mut rotations,
                &mut scratch[..len],
                out,
            )?;
        }
        Pipeline::Tfi => {
            let b = block();
            let len = deform_tfi_scratch_len::<2>(&b, motion.nodes.len());
            deform_tfi(
                &b,
                Directions::from_flags([true, true, false]),
                &m.points,
                motion,
                &mut translations,
                &mut rotations,
                &mut scratch[..len],
                out,
            )?;
        }
        Pipeline::Spring => {
            let g = m.graph();
            let mut k = [T::ZERO; NE];
            let k = &mut k[..m.used];
            batina_stiffness(&g, &m.points, T::ONE, k)?;
            let k: &[T] = k;
            let mut seen = [0u32; N];
            let sys = SpringSystem::new(g, k, &m.fixed, &mut seen)?;
            let method = LinearMethod::Cg {
                preconditioner: Preconditioner::Jacobi,
            };
            let mut values = [T::ZERO; 36 * N];
            let vlen = propagate_spring_scratch_len::<2>(&method, N);
            let len = deform_spring_scratch_len::<2>(N, motion.nodes.len());
            let (_, r) = deform_spring(
                &m.points,
                motion,
                &sys,
                method,
                &SolveOptions::default(),
                &mut translations,
                &mut rotations,
                &mut scratch[..len],
                &mut values[..vlen],
                out,
            )?;
            defmt::assert!(r.converged);
        }
    }
    Ok(())
}

/// Perimeter segments in boundary numbering (counter-clockwise loop), as VTK lines.
struct Segments {
    offsets: [u32; NB + 1],
    nodes: [u32; 2 * NB],
    kinds: [u8; NB],
}

fn segments<T: Real>(m: &Mesh<T>) -> Segments {
    let mut loop_nodes = [0u32; NB];
    let mut k = 0;
    let mut push = |p: usize| {
        loop_nodes[k] = p as u32;
        k += 1;
    };
    (0..NX).for_each(&mut push);
    (1..NY).for_each(|j| push(NX - 1 + NX * j));
    (0..NX - 1).rev().for_each(|i| push(i + NX * (NY - 1)));
    (1..NY - 1).rev().for_each(|j| push(NX * j));
    let local = |p: u32| m.boundary.iter().position(|&b| b == p).unwrap() as u32;
    let mut s = Segments {
        offsets: [0; NB + 1],
        nodes: [0; 2 * NB],
        kinds: [3; NB],
    };
    for e in 0..NB {
        s.nodes[2 * e] = local(loop_nodes[e]);
        s.nodes[2 * e + 1] = local(loop_nodes[(e + 1) % NB]);
        s.offsets[e + 1] = 2 * (e as u32 + 1);
    }
    s
}

/// A rigid motion of the whole boundary (turn by 25° about `c`, then translate by `t`) is
/// reproduced at every node within a few ε·L, by every pipeline, with the rotation given
/// (`Rigid`) or derived from the boundary shape (`Shape`, IDW and TFI).
fn rigid_motion<T: Real>() {
    let m = Mesh::<T>::new(0.25);
    let q = Quat::from_rotation_z(T::from_f64(25f64.to_radians()));
    let c = [T::from_f64(1.5), T::from_f64(0.5)];
    let t = [T::from_f64(0.75), T::from_f64(-0.25)];
    let rigid = |p: [T; 2]| {
        let r = q.rotate_2d([p[0] - c[0], p[1] - c[1]]);
        [r[0] + c[0] + t[0], r[1] + c[1] + t[1]]
    };
    let mut expected = [[T::ZERO; 2]; N];
    for (e, p) in expected.iter_mut().zip(&m.points) {
        *e = rigid(*p);
    }
    let mut deformed = [[T::ZERO; 2]; NB];
    for (d, &b) in deformed.iter_mut().zip(&m.boundary) {
        *d = expected[b as usize];
    }
    let seg = segments(&m);
    let elements = Cells::new(NB, &seg.offsets, &seg.nodes, &seg.kinds).unwrap();
    // L: the size of the moved domain.
    let l = T::from_f64(8.0);
    for (pipeline, shape) in [
        (Pipeline::Idw, false),
        (Pipeline::Idw, true),
        (Pipeline::Tfi, false),
        (Pipeline::Tfi, true),
        (Pipeline::Spring, false),
    ] {
        let motion = BoundaryMotion {
            nodes: &m.boundary,
            deformed: &deformed,
            elements: Some(elements),
            rotations: if shape {
                RotationSource::Shape
            } else {
                RotationSource::Rigid(q)
            },
            origin: None,
        };
        let mut out = [[T::ZERO; 2]; N];
        run(pipeline, &m, &motion, &mut out).unwrap();
        let err = max_diff(&out, &expected);
        defmt::info!(
            "{=str} rigid motion, pipeline {=u8}, shape {=bool}: max error {=f64} eps*L",
            precision::<T>(),
            pipeline as u8,
            shape,
            (err / (T::EPSILON * l)).to_f64()
        );
        // Every propagation blends identical Δ and Q (a uniform field is a bit-exact fixed
        // point of the spring sweeps), so only the update's rounding remains.
        let bound = T::from_f64(16.0) * T::EPSILON * l;
        defmt::assert!(err <= bound);
    }
}

/// Under a non-rigid motion (the bottom row turns by 5°, the rest of the perimeter stays),
/// every boundary node of the output has exactly the caller's bits, and no cell inverts.
fn boundary_exact<T: Real>() {
    let m = Mesh::<T>::new(0.25);
    let q = Quat::from_rotation_z(T::from_f64(5f64.to_radians()));
    let c = [T::from_f64((NX - 1) as f64 * 0.5), T::ZERO];
    let mut deformed = [[T::ZERO; 2]; NB];
    let mut rot = [Quat::identity(); NB];
    for ((d, r), &b) in deformed.iter_mut().zip(rot.iter_mut()).zip(&m.boundary) {
        let p = m.points[b as usize];
        *d = p;
        if (b as usize) < NX {
            let v = q.rotate_2d([p[0] - c[0], p[1] - c[1]]);
            *d = [v[0] + c[0], v[1] + c[1]];
            *r = q;
        }
    }
    let motion = BoundaryMotion {
        nodes: &m.boundary,
        deformed: &deformed,
        elements: None,
        rotations: RotationSource::PerNode(&rot),
        origin: None,
    };
    for pipeline in [Pipeline::Idw, Pipeline::Tfi, Pipeline::Spring] {
        let mut out = [[T::ZERO; 2]; N];
        run(pipeline, &m, &motion, &mut out).unwrap();
        for (d, &b) in deformed.iter().zip(&m.boundary) {
            defmt::assert!(same_bits(&[out[b as usize]], &[*d]));
        }
        let inverted = deform_kernel::quality::inverted_cells(&m.cells(), &m.points, &out).unwrap();
        defmt::assert_eq!(inverted, 0);
    }
}

fn typed_errors<T: Real>() {
    let m = Mesh::<T>::new(0.25);
    let mut deformed = [[T::ZERO; 2]; NB];
    for (d, &b) in deformed.iter_mut().zip(&m.boundary) {
        *d = m.points[b as usize];
    }
    let sentinel = [[T::from_f64(7.0); 2]; N];
    let check = |pipeline: Pipeline, motion: &BoundaryMotion<'_, T, 2>, f: fn(&Error) -> bool| {
        let mut out = sentinel;
        let e = run(pipeline, &m, motion, &mut out).unwrap_err();
        defmt::assert!(f(&e), "unexpected error {}", e);
        defmt::assert!(same_bits(&out, &sentinel));
    };
    let base = BoundaryMotion {
        nodes: &m.boundary,
        deformed: &deformed,
        elements: None,
        rotations: RotationSource::Rigid(Quat::identity()),
        origin: None,
    };
    let mut dup = m.boundary;
    dup[3] = dup[2];
    for p in [Pipeline::Idw, Pipeline::Tfi, Pipeline::Spring] {
        check(
            p,
            &BoundaryMotion {
                nodes: &dup,
                ..base
            },
            |e| matches!(e, Error::DuplicateNode { .. }),
        );
        check(
            p,
            &BoundaryMotion {
                nodes: &[],
                deformed: &[],
                ..base
            },
            |e| matches!(e, Error::InvalidParameter { .. }),
        );
        check(
            p,
            &BoundaryMotion {
                rotations: RotationSource::Shape,
                ..base
            },
            |e| matches!(e, Error::InvalidParameter { .. }),
        );
        check(
            p,
            &BoundaryMotion {
                deformed: &deformed[..NB - 1],
                ..base
            },
            |e| matches!(e, Error::LengthMismatch { .. }),
        );
        check(
            p,
            &BoundaryMotion {
                rotations: RotationSource::Rigid(Quat::new(T::ZERO, T::ZERO, T::ZERO, T::ZERO)),
                ..base
            },
            |e| !matches!(e, Error::DuplicateNode { .. }),
        );
    }
    // TFI: every point on an active face must be listed.
    check(
        Pipeline::Tfi,
        &BoundaryMotion {
            nodes: &m.boundary[1..],
            deformed: &deformed[1..],
            ..base
        },
        |e| matches!(e, Error::Unanchored { node: 0 }),
    );
    // A NaN in the deformed boundary.
    let mut bad = deformed;
    bad[5][0] = T::from_f64(f64::NAN);
    check(
        Pipeline::Idw,
        &BoundaryMotion {
            deformed: &bad,
            ..base
        },
        |e| matches!(e, Error::NonFinite { .. }),
    );
    // Wrong output length.
    let mut short = [[T::ZERO; 2]; N - 1];
    defmt::assert!(matches!(
        run(Pipeline::Idw, &m, &base, &mut short),
        Err(Error::LengthMismatch { arg: "out", .. })
    ));
}

/// Scratch for the fast IDW on the perimeter (`NB` boundary nodes).
const FS: usize = 512;

/// Fast against exact IDW on the jittered mesh with non-uniform boundary values.
fn idw_fast<T: Real>() {
    defmt::assert!(propagate_idw_fast_scratch_len::<2>(NB) <= FS);
    defmt::assert!(propagate_idw_fast_index_len(NB) == NB);
    let m = Mesh::<T>::new(0.25);
    let mut t0 = [[T::ZERO; 2]; N];
    let mut q0 = [Quat::identity(); N];
    for (k, &b) in m.boundary.iter().enumerate() {
        let s = T::from_usize(k) * T::from_f64(0.37);
        t0[b as usize] = [s.sin(), (s * T::TWO).cos() * T::HALF];
        q0[b as usize] = Quat::from_rotation_z(s * T::from_f64(0.1));
    }
    let (mut te, mut qe) = (t0, q0);
    propagate_idw(&m.points, &m.boundary, T::TWO, &mut te, &mut qe).unwrap();
    let mut index = [0u32; NB];
    let mut scratch = [T::ZERO; FS];
    let mut eta = [T::ZERO; N];
    let eps = T::EPSILON;
    let slack = T::from_f64(4.0 * NB as f64) * eps * T::TWO;
    let mut any_cluster = false;
    for theta in [0.0, 0.5, 0.8] {
        let (mut t, mut q) = (t0, q0);
        let options = IdwFastOptions {
            theta: T::from_f64(theta),
            tolerance: T::INFINITY,
        };
        let report = propagate_idw_fast(
            &m.points,
            &m.boundary,
            T::TWO,
            &options,
            &mut index,
            &mut scratch,
            &mut t,
            &mut q,
            Some(&mut eta),
        )
        .unwrap();
        any_cluster |= report.clusters > 0;
        let mut worst = T::ZERO;
        for i in 0..N {
            if m.fixed[i] != 0 {
                defmt::assert!(same_bits(&t[i..=i], &t0[i..=i]));
                continue;
            }
            // The spread max_k |Δ_k − Δ(x)| at this point, from the exact value.
            let mut spread = T::ZERO;
            for &b in &m.boundary {
                let d = [t0[b as usize][0] - te[i][0], t0[b as usize][1] - te[i][1]];
                spread = spread.max((d[0] * d[0] + d[1] * d[1]).sqrt());
            }
            let d = [t[i][0] - te[i][0], t[i][1] - te[i][1]];
            let err = (d[0] * d[0] + d[1] * d[1]).sqrt();
            defmt::assert!(err <= eta[i] * spread + slack);
            if theta == 0.0 {
                defmt::assert!(eta[i] == T::ZERO && err <= slack);
            }
            worst = worst.max(err);
        }
        defmt::info!(
            "{=str} fast IDW θ {=f64}: max error {=f64}, max bound {=f64}, {=u64} clusters",
            precision::<T>(),
            theta,
            worst.to_f64(),
            report.max_bound.to_f64(),
            report.clusters
        );
    }
    defmt::assert!(any_cluster);
    // A uniform translation is reproduced to rounding.
    let mut t = t0;
    let mut q = q0;
    let shift = [T::from_f64(0.75), T::from_f64(-0.25)];
    for &b in &m.boundary {
        t[b as usize] = shift;
    }
    let options = IdwFastOptions {
        theta: T::from_f64(0.8),
        tolerance: T::INFINITY,
    };
    propagate_idw_fast(
        &m.points,
        &m.boundary,
        T::TWO,
        &options,
        &mut index,
        &mut scratch,
        &mut t,
        &mut q,
        None,
    )
    .unwrap();
    let expected = [shift; N];
    defmt::assert!(max_diff(&t, &expected) <= T::from_f64(64.0) * eps);
    // A bad θ: typed error, outputs untouched.
    let (mut t, mut q) = (t0, q0);
    let bad = IdwFastOptions {
        theta: T::ONE,
        tolerance: T::INFINITY,
    };
    let r = propagate_idw_fast(
        &m.points,
        &m.boundary,
        T::TWO,
        &bad,
        &mut index,
        &mut scratch,
        &mut t,
        &mut q,
        None,
    );
    defmt::assert!(matches!(
        r,
        Err(Error::InvalidParameter {
            arg: "options.theta",
            ..
        })
    ));
    defmt::assert!(same_bits(&t, &t0));
}

#[defmt_test::tests]
mod tests {
    use super::*;

    #[test]
    fn rigid_motion_f64() {
        rigid_motion::<f64>();
    }

    #[test]
    fn rigid_motion_f32() {
        rigid_motion::<f32>();
    }

    #[test]
    fn boundary_bitwise_exact_f64() {
        boundary_exact::<f64>();
    }

    #[test]
    fn boundary_bitwise_exact_f32() {
        boundary_exact::<f32>();
    }

    #[test]
    fn idw_fast_within_bound_f64() {
        idw_fast::<f64>();
    }

    #[test]
    fn idw_fast_within_bound_f32() {
        idw_fast::<f32>();
    }

    #[test]
    fn typed_errors_leave_out_untouched() {
        typed_errors::<f64>();
        typed_errors::<f32>();
    }
}
