//! The C ABI's method families on target, f32 and f64: quaternions, mesh quality, graph
//! Taubin smoothing, the linear spring solve and the IDW quaternion deformation, each called
//! the way a C or Fortran solver on a Cortex-M4F would call it, give the Rust API's bits; one
//! bad argument per family gives its documented `dk_status` and leaves every output as it was.
//! (tests/c_abi.rs covers graphs, plans and the stiffness choices.)
#![no_std]
#![no_main]

use deform_on_target as _;

use deform_kernel::quality::cell_measures;
use deform_kernel::quaternion::RotationSource;
use deform_kernel::quaternion::{deform_idw, deform_idw_scratch_len, BoundaryMotion};
use deform_kernel::spring::{
    batina_stiffness, LinearMethod, Preconditioner, SolveOptions, SpringSystem,
};
use deform_kernel::taubin::{smooth_graph, GraphOptions, TaubinParams};
use deform_kernel::{Quat, Real};
use deform_kernel_ffi::spring::{dk_spring_system, dk_spring_system_f32};
use deform_kernel_ffi::status::dk_status;
use deform_on_target::abi::{cells, graph};
use deform_on_target::mesh::{turned_bottom_row, Mesh, N, NB, NE, NT};

/// The same bits, element by element.
fn same<T: Real>(a: &[T], b: &[T]) -> bool {
    a.len() == b.len()
        && a.iter()
            .zip(b)
            .all(|(x, y)| x.to_bits_u64() == y.to_bits_u64())
}

fn flat<T, const D: usize>(a: &[[T; D]]) -> &[T] {
    a.as_flattened()
}

fn flat_mut<T, const D: usize>(a: &mut [[T; D]]) -> &mut [T] {
    a.as_flattened_mut()
}

/// A sentinel no call writes by accident.
const SENTINEL: f64 = 7.25;

/// One family's test for f64 (`$t = f64`, `$m` = the f64 ABI functions) or f32.
macro_rules! abi_cases {
    ($t:ty, [$quat:ident, $quality:ident, $taubin:ident, $spring:ident, $deform:ident],
     [$quat_fn:path, $quat2_fn:path, $quality_fn:path, $taubin_fn:path, $spring_fn:path, $deform_fn:path],
     $motion_default:path, $motion_ty:ty, $options_default:path,
     $system_ty:ident) => {
        /// `dk_quat_rotate_points`: `q` normalised, then `Quat::rotate` of every point; an
        /// `out` of the wrong length is `DK_ERR_LENGTH_MISMATCH`, `out` untouched. Then
        /// `dk_quat_rotate_points_2d`.
        fn $quat() {
            let q: [$t; 4] = [0.9, 0.1, -0.3, 0.2];
            let points: [[$t; 3]; 4] = [
                [1.0, 0.0, 0.0],
                [0.25, -2.0, 0.5],
                [3.0, 1.5, -0.75],
                [-1e3, 2e-3, 7.0],
            ];
            let rust = Quat::from_array(q).normalize().unwrap();
            let expect: [[$t; 3]; 4] = core::array::from_fn(|i| rust.rotate(points[i]));
            let mut out = [[SENTINEL as $t; 3]; 4];
            let p = flat(&points);
            // SAFETY: `q` holds 4 scalars; every array is valid for the length passed.
            let s = unsafe {
                $quat_fn(
                    q.as_ptr(),
                    p.as_ptr(),
                    p.len(),
                    flat_mut(&mut out).as_mut_ptr(),
                    9,
                )
            };
            defmt::assert!(s == dk_status::DK_ERR_LENGTH_MISMATCH);
            defmt::assert!(flat(&out).iter().all(|&x| x == SENTINEL as $t));
            let o = flat_mut(&mut out);
            // SAFETY: as above, with the full length.
            let s = unsafe { $quat_fn(q.as_ptr(), p.as_ptr(), p.len(), o.as_mut_ptr(), o.len()) };
            defmt::assert!(s == dk_status::DK_OK);
            defmt::assert!(same(flat(&out), flat(&expect)));

            // `dk_quat_rotate_points_2d`: the 3D bits on (x, y, 0) for a rotation about z; a
            // tilted `q` is `DK_ERR_INVALID_PARAMETER`, `out` untouched.
            let about_z: [$t; 4] = [0.9, 0.0, 0.0, -0.4];
            let rz = Quat::from_array(about_z).normalize().unwrap();
            let plane: [[$t; 2]; 3] = [[1.0, 0.0], [0.25, -2.0], [-1e3, 2e-3]];
            let expect2: [[$t; 2]; 3] = core::array::from_fn(|i| {
                let r = rz.rotate([plane[i][0], plane[i][1], 0.0]);
                [r[0], r[1]]
            });
            let mut out2 = [[SENTINEL as $t; 2]; 3];
            let p2 = flat(&plane);
            let o2 = flat_mut(&mut out2);
            // SAFETY: `q` holds 4 scalars; every array is valid for the length passed.
            let s =
                unsafe { $quat2_fn(q.as_ptr(), p2.as_ptr(), p2.len(), o2.as_mut_ptr(), o2.len()) };
            defmt::assert!(s == dk_status::DK_ERR_INVALID_PARAMETER);
            defmt::assert!(flat(&out2).iter().all(|&x| x == SENTINEL as $t));
            let o2 = flat_mut(&mut out2);
            // SAFETY: as above.
            let s = unsafe {
                $quat2_fn(
                    about_z.as_ptr(),
                    p2.as_ptr(),
                    p2.len(),
                    o2.as_mut_ptr(),
                    o2.len(),
                )
            };
            defmt::assert!(s == dk_status::DK_OK);
            defmt::assert!(same(flat(&out2), flat(&expect2)));
        }

        /// `dk_quality_cell_measures` with 1-based cells: the kernel's signed areas; a
        /// `dim` of 4 is `DK_ERR_INVALID_PARAMETER`, `out` untouched.
        fn $quality() {
            let m = Mesh::<$t>::new(0.25);
            let mut expect = [0.0 as $t; NT];
            cell_measures(&m.cells(), &m.points, &mut expect).unwrap();
            let mut offsets1 = m.offsets;
            let mut nodes1 = m.nodes;
            for x in offsets1.iter_mut().chain(nodes1.iter_mut()) {
                *x += 1;
            }
            let mut scratch = [0u32; NT + 1 + 3 * NT];
            let mut out = [SENTINEL as $t; NT];
            let p = flat(&m.points);
            let c = cells(&offsets1, &nodes1, &m.kinds);
            let mut call = |dim: u32, out: &mut [$t; NT]| {
                // SAFETY: every array (the cells' too) is valid for the length passed with it.
                unsafe {
                    $quality_fn(
                        &c,
                        1,
                        scratch.as_mut_ptr(),
                        scratch.len(),
                        p.as_ptr(),
                        p.len(),
                        dim,
                        out.as_mut_ptr(),
                        out.len(),
                    )
                }
            };
            defmt::assert!(call(4, &mut out) == dk_status::DK_ERR_INVALID_PARAMETER);
            defmt::assert!(out.iter().all(|&x| x == SENTINEL as $t));
            defmt::assert!(call(2, &mut out) == dk_status::DK_OK);
            defmt::assert!(same(&out, &expect));
        }

        /// `dk_taubin_smooth_graph` on the mesh points (2 components, the boundary fixed,
        /// uniform weights, 5 iterations): the kernel's bits and report; a short scratch is
        /// `DK_ERR_BUFFER_TOO_SMALL`, values and report untouched.
        fn $taubin() {
            let m = Mesh::<$t>::new(0.25);
            let params = TaubinParams::<$t>::paper();
            let mut expect = m.points;
            let mut scratch = [[0.0 as $t; 2]; N];
            let options = GraphOptions {
                weights: None,
                fixed: Some(&m.fixed),
            };
            let r =
                smooth_graph(&m.graph(), &mut expect, params, 5, &options, &mut scratch).unwrap();
            let mut values = m.points;
            let mut flat_scratch = [0.0 as $t; 2 * N];
            let mut report = deform_kernel_ffi::taubin::dk_filter_report {
                iterations: 99,
                last_change: SENTINEL,
            };
            let g = graph(&m.graph_offsets, &m.targets[..m.used]);
            let mut call =
                |len: usize,
                 values: &mut [[$t; 2]; N],
                 report: &mut deform_kernel_ffi::taubin::dk_filter_report| {
                    let v = flat_mut(values);
                    // SAFETY: every array (the graph's too) is valid for the length passed with
                    // it.
                    unsafe {
                        $taubin_fn(
                            &g,
                            core::ptr::null(),
                            0,
                            m.fixed.as_ptr(),
                            N,
                            params.lambda.into(),
                            params.mu.into(),
                            5,
                            2,
                            v.as_mut_ptr(),
                            v.len(),
                            flat_scratch.as_mut_ptr(),
                            len,
                            report,
                        )
                    }
                };
            let s = call(2 * N - 1, &mut values, &mut report);
            defmt::assert!(s == dk_status::DK_ERR_BUFFER_TOO_SMALL);
            defmt::assert!(values == m.points && report.iterations == 99);
            let s = call(2 * N, &mut values, &mut report);
            defmt::assert!(s == dk_status::DK_OK);
            defmt::assert!(same(flat(&values), flat(&expect)));
            defmt::assert!(report.iterations == r.iterations);
            defmt::assert!(report.last_change == f64::from(r.last_change));
        }

        /// `dk_spring_solve_linear` with the default options (CG + Jacobi) and Batina's
        /// stiffness: the bottom row turned, the kernel's displacements and iterations; a
        /// NaN value is `DK_ERR_NON_FINITE`, values untouched.
        fn $spring() {
            let m = Mesh::<$t>::new(0.25);
            let mut k = [0.0 as $t; NE];
            let k = &mut k[..m.used];
            batina_stiffness(&m.graph(), &m.points, 1.0, k).unwrap();
            let mut seen = [0u32; N];
            let sys = SpringSystem::new(m.graph(), k, &m.fixed, &mut seen).unwrap();
            // Prescribed displacements: the turned bottom row minus the reference.
            let turned = turned_bottom_row(&m, 1);
            let mut start = [[0.0 as $t; 2]; N];
            for (b, &node) in m.boundary.iter().enumerate() {
                let i = node as usize;
                start[i] = [turned[b][0] - m.points[i][0], turned[b][1] - m.points[i][1]];
            }
            let options = SolveOptions::<$t>::default();
            let mut expect = start;
            let mut rs = [[0.0 as $t; 2]; 5 * N];
            let cg = LinearMethod::Cg {
                preconditioner: Preconditioner::Jacobi,
            };
            let report = sys
                .solve_linear(&mut expect, cg, &options, &mut rs)
                .unwrap();

            let mut copts = core::mem::MaybeUninit::uninit();
            // SAFETY: one writable struct.
            defmt::assert!(unsafe { $options_default(copts.as_mut_ptr()) } == dk_status::DK_OK);
            // SAFETY: the defaults call initialised it.
            let copts = unsafe { copts.assume_init() };
            let mut scratch = [0.0 as $t; 10 * N];
            let mut index = [0u32; N];
            let system = $system_ty {
                graph: graph(&m.graph_offsets, &m.targets[..m.used]),
                stiffness: k.as_ptr(),
                stiffness_len: k.len(),
                fixed: m.fixed.as_ptr(),
                fixed_len: N,
            };
            let mut run =
                |values: &mut [[$t; 2]; N],
                 out: &mut deform_kernel_ffi::spring::dk_spring_solve_report| {
                    let v = flat_mut(values);
                    // SAFETY: every array (the system's too) is valid for the length passed
                    // with it.
                    unsafe {
                        $spring_fn(
                            &system,
                            &copts,
                            2,
                            v.as_mut_ptr(),
                            v.len(),
                            scratch.as_mut_ptr(),
                            scratch.len(),
                            index.as_mut_ptr(),
                            N,
                            out,
                        )
                    }
                };
            let mut rep = deform_kernel_ffi::spring::dk_spring_solve_report {
                iterations: 0,
                residual: 0.0,
                max_update: 0.0,
                converged: false,
            };
            let mut bad = start;
            bad[7][1] = <$t>::NAN;
            let before = bad;
            defmt::assert!(run(&mut bad, &mut rep) == dk_status::DK_ERR_NON_FINITE);
            defmt::assert!(same(&flat(&bad)[..14], &flat(&before)[..14]));
            let mut values = start;
            defmt::assert!(run(&mut values, &mut rep) == dk_status::DK_OK);
            defmt::assert!(same(flat(&values), flat(&expect)));
            defmt::assert!(rep.iterations == report.iterations);
        }

        /// `dk_deform_idw` with a rigid rotation of the moving nodes
        /// (`DK_ROTATIONS_RIGID`): the kernel's mesh, translations, rotations and origin; a
        /// boundary node out of range is `DK_ERR_INDEX_OUT_OF_RANGE`, every output untouched.
        fn $deform() {
            let m = Mesh::<$t>::new(0.25);
            let turned = turned_bottom_row(&m, 1);
            let angle: $t = 0.1;
            let q = Quat::<$t>::new((angle / 2.0).cos(), 0.0, 0.0, (angle / 2.0).sin());
            let motion = BoundaryMotion {
                nodes: &m.boundary,
                deformed: &turned,
                elements: None,
                rotations: RotationSource::Rigid(q),
                origin: Some([0.0, 0.0]),
            };
            let mut tr = [[0.0 as $t; 2]; N];
            let mut rot = [Quat::<$t>::identity(); N];
            let mut sc = [0.0 as $t; 4 * N + 4 * NB + 16];
            let len = deform_idw_scratch_len::<2>(N, NB);
            let mut expect = [[0.0 as $t; 2]; N];
            let origin = deform_idw(
                &m.points,
                &motion,
                2.0,
                &mut tr,
                &mut rot,
                &mut sc[..len],
                &mut expect,
            )
            .unwrap();

            let mut cm = core::mem::MaybeUninit::<$motion_ty>::uninit();
            // SAFETY: one writable struct.
            defmt::assert!(unsafe { $motion_default(cm.as_mut_ptr()) } == dk_status::DK_OK);
            // SAFETY: the defaults call initialised it.
            let mut cm = unsafe { cm.assume_init() };
            let mut bad_nodes = m.boundary;
            bad_nodes[3] = N as u32;
            cm.nodes = m.boundary.as_ptr();
            cm.nodes_len = NB;
            cm.deformed = flat(&turned).as_ptr();
            cm.deformed_len = 2 * NB;
            cm.rotation_source = deform_kernel_ffi::deformation::DK_ROTATIONS_RIGID;
            cm.rigid_rotation = [q.w, q.x, q.y, q.z];
            cm.has_origin = 1;
            let mut ct = [SENTINEL as $t; 2 * N];
            let mut cr = [SENTINEL as $t; 4 * N];
            let mut co = [SENTINEL as $t; 2 * N];
            let mut corigin = [SENTINEL as $t; 2];
            let mut idx = [0u32; NB];
            let mut bad = cm;
            bad.nodes = bad_nodes.as_ptr();
            let mut run = |cm: &$motion_ty,
                           ct: &mut [$t; 2 * N],
                           cr: &mut [$t; 4 * N],
                           co: &mut [$t; 2 * N],
                           corigin: &mut [$t; 2]| {
                // SAFETY: every array is valid for the length passed with it; the motion's
                // arrays live as long as `cm`.
                unsafe {
                    $deform_fn(
                        flat(&m.points).as_ptr(),
                        2 * N,
                        2,
                        cm,
                        2.0,
                        sc.as_mut_ptr(),
                        len,
                        idx.as_mut_ptr(),
                        0,
                        ct.as_mut_ptr(),
                        ct.len(),
                        cr.as_mut_ptr(),
                        cr.len(),
                        co.as_mut_ptr(),
                        co.len(),
                        corigin.as_mut_ptr(),
                        2,
                    )
                }
            };
            let s = run(&bad, &mut ct, &mut cr, &mut co, &mut corigin);
            defmt::assert!(s == dk_status::DK_ERR_INDEX_OUT_OF_RANGE);
            defmt::assert!([&ct[..], &cr[..], &co[..], &corigin[..]]
                .iter()
                .all(|a| a.iter().all(|&x| x == SENTINEL as $t)));
            let s = run(&cm, &mut ct, &mut cr, &mut co, &mut corigin);
            defmt::assert!(s == dk_status::DK_OK);
            defmt::assert!(same(&co, flat(&expect)));
            defmt::assert!(same(&ct, flat(&tr)));
            let rq: [[$t; 4]; N] = core::array::from_fn(|i| rot[i].to_array());
            defmt::assert!(same(&cr, flat(&rq)));
            defmt::assert!(same(&corigin, &origin));
        }
    };
}

abi_cases!(
    f64,
    [quat_f64, quality_f64, taubin_f64, spring_f64, deform_f64],
    [
        deform_kernel_ffi::quat::dk_quat_rotate_points,
        deform_kernel_ffi::quat::dk_quat_rotate_points_2d,
        deform_kernel_ffi::quality::dk_quality_cell_measures,
        deform_kernel_ffi::taubin::dk_taubin_smooth_graph,
        deform_kernel_ffi::spring::dk_spring_solve_linear,
        deform_kernel_ffi::deformation::dk_deform_idw
    ],
    deform_kernel_ffi::deformation::dk_boundary_motion_default,
    deform_kernel_ffi::deformation::dk_boundary_motion,
    deform_kernel_ffi::spring::dk_spring_solve_options_default,
    dk_spring_system
);
abi_cases!(
    f32,
    [quat_f32, quality_f32, taubin_f32, spring_f32, deform_f32],
    [
        deform_kernel_ffi::quat::dk_quat_rotate_points_f32,
        deform_kernel_ffi::quat::dk_quat_rotate_points_2d_f32,
        deform_kernel_ffi::quality::dk_quality_cell_measures_f32,
        deform_kernel_ffi::taubin::dk_taubin_smooth_graph_f32,
        deform_kernel_ffi::spring::dk_spring_solve_linear_f32,
        deform_kernel_ffi::deformation::dk_deform_idw_f32
    ],
    deform_kernel_ffi::deformation::dk_boundary_motion_default_f32,
    deform_kernel_ffi::deformation::dk_boundary_motion_f32,
    deform_kernel_ffi::spring::dk_spring_solve_options_default_f32,
    dk_spring_system_f32
);

#[defmt_test::tests]
mod tests {
    #[test]
    fn quaternion_rotation_f64() {
        super::quat_f64();
    }

    #[test]
    fn quaternion_rotation_f32() {
        super::quat_f32();
    }

    #[test]
    fn cell_measures_1_based_f64() {
        super::quality_f64();
    }

    #[test]
    fn cell_measures_1_based_f32() {
        super::quality_f32();
    }

    #[test]
    fn graph_taubin_f64() {
        super::taubin_f64();
    }

    #[test]
    fn graph_taubin_f32() {
        super::taubin_f32();
    }

    #[test]
    fn linear_spring_solve_f64() {
        super::spring_f64();
    }

    #[test]
    fn linear_spring_solve_f32() {
        super::spring_f32();
    }

    #[test]
    fn idw_deformation_rigid_rotation_f64() {
        super::deform_f64();
    }

    #[test]
    fn idw_deformation_rigid_rotation_f32() {
        super::deform_f32();
    }
}
