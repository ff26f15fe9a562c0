//! The C ABI's stateless multigrid solves and sliding boundaries on target, f32 and f64, on the
//! 30-node mesh: `dk_spring_solve_{linear,angle}_amg` (with `dk_amg_options_default`,
//! `dk_spring_amg_work_len` and the `*_pool_sizes` queries), `dk_fit_plane`,
//! `dk_constraints_fixed_mask`, `dk_slide_points`, `dk_spring_solve_{linear,angle}_sliding`
//! (with their `_scratch_len`) and `dk_spring_solve_{linear,angle}_sliding_amg` (with their
//! `_pool_sizes`) give the kernel's bits and sizes; pools one short are
//! `DK_ERR_BUFFER_TOO_SMALL` and a non-unit sliding direction `DK_ERR_NOT_UNIT`, each with the
//! outputs untouched. (tests/c_abi.rs and tests/c_abi_methods.rs cover the other families.)
#![no_std]
#![no_main]

use deform_on_target as _;

use deform_kernel::spring::constraints::{fit_plane, slide_points, Constraints, NodeKind};
use deform_kernel::spring::{
    batina_stiffness, solve_linear_amg_scratch_len, solve_linear_sliding_scratch_len, AmgHierarchy,
    AmgOptions, AngleMethod, AngleSystem, LinearMethod, LinearSolver, Preconditioner, SolveOptions,
    SpringSystem, DEFAULT_ANGLE_EPSILON,
};
use deform_kernel::Real;
use deform_kernel_ffi::plan::{dk_plan_pools, dk_plan_pools_f32, dk_plan_sizes};
use deform_kernel_ffi::spring::{
    dk_amg_options, dk_amg_options_default, dk_constraints, dk_constraints_f32,
    dk_spring_amg_work_len, dk_spring_angle_options, dk_spring_solve_options,
    dk_spring_solve_report, dk_spring_system, dk_spring_system_f32,
};
use deform_kernel_ffi::status::dk_status;
use deform_on_target::abi::graph;
use deform_on_target::mesh::{Mesh, N, NE, NX, NY};

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

/// Boundary data: the bottom row (corners included) moves by (0.25, 0.125) − its x / 16 in y,
/// the top row +0.5 along x; zero elsewhere (the initial guess).
fn data<T: Real>(m: &Mesh<T>) -> [[T; 2]; N] {
    let mut d = [[T::ZERO; 2]; N];
    for (v, p) in d.iter_mut().zip(&m.points).take(NX) {
        *v = [
            T::from_f64(0.25),
            T::from_f64(0.125) - p[0] * T::from_f64(0.0625),
        ];
    }
    for v in d.iter_mut().skip(NX * (NY - 1)) {
        *v = [T::HALF, T::ZERO];
    }
    d
}

/// Sliding data: the top row +0.5 along x, the rest zero.
fn slide_data<T: Real>() -> [[T; 2]; N] {
    let mut d = [[T::ZERO; 2]; N];
    for v in d.iter_mut().skip(NX * (NY - 1)) {
        *v = [T::HALF, T::ZERO];
    }
    d
}

/// The bottom row without its corners, the sliding nodes.
fn bottom() -> [u32; NX - 2] {
    core::array::from_fn(|i| (i + 1) as u32)
}

/// Multigrid options with a coarse level on this small system (`max_coarse` 4).
fn kernel_amg<T: Real>() -> AmgOptions<T> {
    AmgOptions {
        max_coarse: 4,
        ..AmgOptions::default()
    }
}

fn c_amg() -> dk_amg_options {
    let mut a = core::mem::MaybeUninit::uninit();
    // SAFETY: one writable struct.
    defmt::assert!(unsafe { dk_amg_options_default(a.as_mut_ptr()) } == dk_status::DK_OK);
    // SAFETY: the defaults call initialised it.
    let mut a = unsafe { a.assume_init() };
    let k = AmgOptions::<f64>::default();
    defmt::assert!(a.strength_theta.to_bits() == k.strength_theta.to_bits());
    defmt::assert!(a.max_levels == k.max_levels);
    defmt::assert!(a.max_coarse == k.max_coarse);
    defmt::assert!(a.sweeps == k.sweeps);
    a.max_coarse = 4;
    a
}

fn report() -> dk_spring_solve_report {
    dk_spring_solve_report {
        iterations: 0,
        residual: 0.0,
        max_update: 0.0,
        converged: false,
    }
}

/// A sentinel no call writes by accident.
const SENTINEL: f64 = 7.25;

macro_rules! solver_cases {
    ($t:ty, [$amg:ident, $sliding:ident], $system_ty:ident, $pools_ty:ident, $cons_ty:ident,
     [$opts_default:path, $angle_default:path,
      $lin_sizes:path, $lin_amg:path, $ang_sizes:path, $ang_amg:path,
      $mask_fn:path, $slide_fn:path, $fit_fn:path,
      $lin_sl_len:path, $lin_sl:path, $ang_sl_len:path, $ang_sl:path,
      $lin_sl_sizes:path, $lin_sl_amg:path, $ang_sl_sizes:path, $ang_sl_amg:path]) => {
        fn options() -> (dk_spring_solve_options, dk_spring_angle_options) {
            let mut o = core::mem::MaybeUninit::uninit();
            let mut a = core::mem::MaybeUninit::uninit();
            // SAFETY: one writable struct each.
            unsafe {
                defmt::assert!($opts_default(o.as_mut_ptr()) == dk_status::DK_OK);
                defmt::assert!($angle_default(a.as_mut_ptr()) == dk_status::DK_OK);
                // The defaults calls initialised them.
                (o.assume_init(), a.assume_init())
            }
        }

        /// The multigrid solves: sizes, the kernel's bits, pools one short.
        pub fn $amg() {
            let m = Mesh::<$t>::new(0.25);
            let g = m.graph();
            let mut k = [0.0 as $t; NE];
            let k = &mut k[..m.used];
            batina_stiffness(&g, &m.points, 1.0, k).unwrap();
            let k: &[$t] = k;
            let mut seen = [0u32; N];
            let sys = SpringSystem::new(g, k, &m.fixed, &mut seen).unwrap();
            let kopts = kernel_amg::<$t>();
            let stop = SolveOptions::<$t>::default();
            let given = data(&m);

            // The kernel: sizes, hierarchy, both solves.
            let work_len = AmgHierarchy::setup_work_len(&sys);
            let mut kwork = [0u32; 4 * (N + NE) + 64];
            let sizes = AmgHierarchy::setup_len(&sys, &kopts, &mut kwork[..work_len]).unwrap();
            let mut kindex = [0u32; 512];
            let mut kvals = [0.0 as $t; 512];
            let h = AmgHierarchy::setup(
                &sys,
                &kopts,
                &mut kwork[..work_len],
                &mut kindex[..sizes.index],
                &mut kvals[..sizes.values],
            )
            .unwrap();
            defmt::assert!(h.levels() >= 2);
            let mut scratch = [[0.0 as $t; 2]; 8 * N];
            let mut lin = given;
            let lr = sys
                .solve_linear_amg(&h, &mut lin, &stop, &mut scratch)
                .unwrap();
            let asys = AngleSystem::new(sys, &m.points, DEFAULT_ANGLE_EPSILON as $t).unwrap();
            let mut ang = given;
            let ar = asys
                .solve_angle_amg(&h, &mut ang, &stop, &mut scratch)
                .unwrap();
            defmt::assert!(lr.converged && ar.converged);
            let lin_reals = sizes.values + 2 * solve_linear_amg_scratch_len(&h);
            let ang_reals = sizes.values + 2 * asys.angle_amg_scratch_len(&h);
            let indices = work_len + sizes.index;

            // The C side.
            let amg = c_amg();
            let (copts, aopts) = options();
            let mut wl = 0usize;
            // SAFETY: one writable `usize`.
            let s = unsafe { dk_spring_amg_work_len(N, m.used, &mut wl) };
            defmt::assert!(s == dk_status::DK_OK && wl == work_len);
            let system = $system_ty {
                graph: graph(&m.graph_offsets, &m.targets[..m.used]),
                stiffness: k.as_ptr(),
                stiffness_len: k.len(),
                fixed: m.fixed.as_ptr(),
                fixed_len: N,
            };
            let mut work = [0u32; 4 * (N + NE) + 64];
            let mut ls = dk_plan_sizes {
                reals: 0,
                indices: 0,
                bytes: 0,
            };
            let mut as_ = ls;
            // SAFETY: every array is valid for the length passed with it.
            unsafe {
                defmt::assert!(
                    $lin_sizes(&system, 2, &amg, work.as_mut_ptr(), wl, &mut ls)
                        == dk_status::DK_OK
                );
                defmt::assert!(
                    $ang_sizes(&system, 2, &amg, work.as_mut_ptr(), wl, &mut as_)
                        == dk_status::DK_OK
                );
            }
            defmt::assert_eq!(ls.reals, lin_reals);
            defmt::assert_eq!(ls.indices, indices);
            defmt::assert_eq!(ls.bytes, 0);
            defmt::assert_eq!(as_.reals, ang_reals);
            defmt::assert_eq!(as_.indices, indices);
            defmt::assert_eq!(as_.bytes, 0);

            let mut reals = [0.0 as $t; 1024];
            let mut index = [0u32; 1024];
            let mut pools = |r: usize, i: usize| $pools_ty {
                reals: reals.as_mut_ptr(),
                reals_len: r,
                indices: index.as_mut_ptr(),
                indices_len: i,
                bytes: core::ptr::null_mut(),
                bytes_len: 0,
            };
            let p = flat(&m.points);
            let mut rep = report();
            for (reals_len, angle) in [(ls.reals, false), (as_.reals, true)] {
                for (short, pl) in [
                    (true, pools(reals_len - 1, indices)),
                    (true, pools(reals_len, indices - 1)),
                    (false, pools(reals_len, indices)),
                ] {
                    let mut values = [[SENTINEL as $t; 2]; N];
                    values.copy_from_slice(&given);
                    let v = flat_mut(&mut values);
                    // SAFETY: every array (the system's and the pools' too) is valid for the
                    // length passed with it; the pools do not overlap.
                    let s = unsafe {
                        if angle {
                            $ang_amg(
                                &system,
                                p.as_ptr(),
                                p.len(),
                                2,
                                &aopts,
                                &amg,
                                v.as_mut_ptr(),
                                v.len(),
                                &pl,
                                &mut rep,
                            )
                        } else {
                            $lin_amg(
                                &system,
                                &copts,
                                &amg,
                                2,
                                v.as_mut_ptr(),
                                v.len(),
                                &pl,
                                &mut rep,
                            )
                        }
                    };
                    if short {
                        defmt::assert!(s == dk_status::DK_ERR_BUFFER_TOO_SMALL);
                        defmt::assert!(same(flat(&values), flat(&given)));
                    } else {
                        defmt::assert!(s == dk_status::DK_OK);
                        let (expect, r) = if angle { (&ang, &ar) } else { (&lin, &lr) };
                        defmt::assert!(same(flat(&values), flat(expect)));
                        defmt::assert!(rep.iterations == r.iterations && rep.converged);
                    }
                }
            }
        }

        /// The sliding family: fit, mask, projection, the four solves; non-unit directions
        /// and pools one short.
        pub fn $sliding() {
            let m = Mesh::<$t>::new(0.25);
            let nodes = bottom();
            let fit = fit_plane(&m.points, &nodes, 1e-6).unwrap();
            // dk_fit_plane with 1-based nodes.
            let nodes1: [u32; NX - 2] = core::array::from_fn(|i| nodes[i] + 1);
            let mut iscr = [0u32; NX - 2];
            let mut normal = [SENTINEL as $t; 2];
            let mut point = [SENTINEL as $t; 2];
            let (mut res, mut ext) = (SENTINEL as $t, SENTINEL as $t);
            let p = flat(&m.points);
            // SAFETY: every array is valid for the length passed with it.
            let s = unsafe {
                $fit_fn(
                    p.as_ptr(),
                    p.len(),
                    2,
                    nodes1.as_ptr(),
                    nodes1.len(),
                    1,
                    1e-6,
                    iscr.as_mut_ptr(),
                    iscr.len(),
                    normal.as_mut_ptr(),
                    2,
                    point.as_mut_ptr(),
                    2,
                    &mut res,
                    &mut ext,
                )
            };
            defmt::assert!(s == dk_status::DK_OK);
            defmt::assert!(same(&normal, &fit.normal) && same(&point, &fit.point));
            defmt::assert!(same(&[res, ext], &[fit.residual, fit.extent]));

            // The table: bottom row (no corners) on the fitted line, the rest of the perimeter
            // fixed; a copy with one direction of length 1.5.
            let mut kinds = [NodeKind::Free.code(); N];
            let mut dirs = [[0.0 as $t; 2]; N];
            for (i, kd) in kinds.iter_mut().enumerate() {
                if m.fixed[i] != 0 {
                    *kd = NodeKind::Fixed.code();
                }
                if (1..NX - 1).contains(&i) {
                    *kd = NodeKind::Plane.code();
                    dirs[i] = normal;
                }
            }
            let mut bad_dirs = dirs;
            bad_dirs[2] = [0.0, 1.5];
            let c = Constraints::new(&kinds, &dirs).unwrap();
            let cons = |d: &[[$t; 2]; N]| $cons_ty {
                kinds: kinds.as_ptr(),
                kinds_len: N,
                directions: flat(d).as_ptr(),
                directions_len: 2 * N,
            };
            let good = cons(&dirs);
            let bad = cons(&bad_dirs);

            // dk_constraints_fixed_mask.
            let mut kmask = [0u8; N];
            c.fixed_mask(&mut kmask).unwrap();
            let mut mask = [9u8; N];
            // SAFETY: the struct's arrays and `mask` are valid for their lengths.
            unsafe {
                defmt::assert!(
                    $mask_fn(&bad, 2, mask.as_mut_ptr(), N) == dk_status::DK_ERR_NOT_UNIT
                );
                defmt::assert!(mask.iter().all(|&x| x == 9));
                defmt::assert!($mask_fn(&good, 2, mask.as_mut_ptr(), N) == dk_status::DK_OK);
            }
            defmt::assert!(mask == kmask);

            // dk_slide_points.
            let mut moved = m.points;
            for q in moved.iter_mut() {
                *q = [q[0] + 0.125, q[1] + 0.25];
            }
            let mut kmoved = moved;
            slide_points(&c, &m.points, &mut kmoved).unwrap();
            let before = moved;
            let o = flat(&m.points);
            // SAFETY: the struct's arrays, `original` and `points` are valid for their lengths.
            unsafe {
                let q = flat_mut(&mut moved);
                let s = $slide_fn(&bad, 2, o.as_ptr(), o.len(), q.as_mut_ptr(), q.len());
                defmt::assert!(s == dk_status::DK_ERR_NOT_UNIT);
                defmt::assert!(same(flat(&moved), flat(&before)));
                let q = flat_mut(&mut moved);
                let s = $slide_fn(&good, 2, o.as_ptr(), o.len(), q.as_mut_ptr(), q.len());
                defmt::assert!(s == dk_status::DK_OK);
            }
            defmt::assert!(same(flat(&moved), flat(&kmoved)));

            // The kernel's sliding solves on the masked system.
            let g = m.graph();
            let mut k = [0.0 as $t; NE];
            let k = &mut k[..m.used];
            batina_stiffness(&g, &m.points, 1.0, k).unwrap();
            let k: &[$t] = k;
            let mut seen = [0u32; N];
            let sys = SpringSystem::new(g, k, &kmask, &mut seen).unwrap();
            let given = slide_data::<$t>();
            let stop = SolveOptions::<$t>::default();
            let kopts = kernel_amg::<$t>();
            let mut kscratch = [[0.0 as $t; 2]; 8 * N];
            let cgj = LinearSolver::Method(LinearMethod::Cg {
                preconditioner: Preconditioner::Jacobi,
            });
            let lin_len = solve_linear_sliding_scratch_len(&cgj, N);
            let mut lin = given;
            let lr = sys
                .solve_linear_sliding(&c, &mut lin, cgj, &stop, &mut kscratch[..lin_len])
                .unwrap();
            let asys = AngleSystem::new(sys, &m.points, DEFAULT_ANGLE_EPSILON as $t).unwrap();
            let ang_len = asys.solve_angle_sliding_scratch_len(AngleMethod::DirectGaussSeidel);
            let mut ang = given;
            let ar = asys
                .solve_angle_sliding(
                    &c,
                    &mut ang,
                    AngleMethod::DirectGaussSeidel,
                    1.0,
                    &stop,
                    &mut kscratch[..ang_len],
                )
                .unwrap();
            let work_len = AmgHierarchy::setup_work_len(&sys);
            let mut kwork = [0u32; 4 * (N + NE) + 64];
            let sizes = AmgHierarchy::setup_len(&sys, &kopts, &mut kwork[..work_len]).unwrap();
            let mut kindex = [0u32; 512];
            let mut kvals = [0.0 as $t; 512];
            let h = AmgHierarchy::setup(
                &sys,
                &kopts,
                &mut kwork[..work_len],
                &mut kindex[..sizes.index],
                &mut kvals[..sizes.values],
            )
            .unwrap();
            defmt::assert!(h.levels() >= 2);
            let lamg_len = solve_linear_sliding_scratch_len(&LinearSolver::Amg(&h), N);
            let mut lamg = given;
            let lar = sys
                .solve_linear_sliding(
                    &c,
                    &mut lamg,
                    LinearSolver::Amg(&h),
                    &stop,
                    &mut kscratch[..lamg_len],
                )
                .unwrap();
            let aamg_len = asys.solve_angle_sliding_amg_scratch_len(&h);
            let mut aamg = given;
            let aar = asys
                .solve_angle_sliding_amg(&c, &mut aamg, &h, &stop, &mut kscratch[..aamg_len])
                .unwrap();
            defmt::assert!(lr.converged && ar.converged && lar.converged && aar.converged);

            // The C side: scratch lengths and pool sizes.
            let (copts, aopts) = options();
            let amg = c_amg();
            let (mut l1, mut l2) = (0usize, 0usize);
            // SAFETY: one readable struct, one writable `usize` each.
            unsafe {
                defmt::assert!($lin_sl_len(N, 2, &copts, &mut l1) == dk_status::DK_OK);
                defmt::assert!($ang_sl_len(N, 2, &aopts, &mut l2) == dk_status::DK_OK);
            }
            defmt::assert_eq!(l1, 2 * lin_len);
            defmt::assert_eq!(l2, 2 * ang_len);
            let system = $system_ty {
                graph: graph(&m.graph_offsets, &m.targets[..m.used]),
                stiffness: k.as_ptr(),
                stiffness_len: k.len(),
                fixed: mask.as_ptr(),
                fixed_len: N,
            };
            let mut work = [0u32; 4 * (N + NE) + 64];
            let mut ls = dk_plan_sizes {
                reals: 0,
                indices: 0,
                bytes: 0,
            };
            let mut as_ = ls;
            // SAFETY: every array is valid for the length passed with it.
            unsafe {
                defmt::assert!(
                    $lin_sl_sizes(&system, 2, &amg, work.as_mut_ptr(), work_len, &mut ls)
                        == dk_status::DK_OK
                );
                defmt::assert!(
                    $ang_sl_sizes(&system, 2, &amg, work.as_mut_ptr(), work_len, &mut as_)
                        == dk_status::DK_OK
                );
            }
            let indices = work_len + sizes.index;
            defmt::assert_eq!(ls.reals, sizes.values + 2 * lamg_len);
            defmt::assert_eq!(as_.reals, sizes.values + 2 * aamg_len);
            defmt::assert!(ls.indices == indices && as_.indices == indices);
            defmt::assert!(ls.bytes == 0 && as_.bytes == 0);

            // The four solves: 0 linear, 1 angle, 2 linear AMG, 3 angle AMG; each with the
            // non-unit table, with pools one short (AMG), then with everything right.
            let mut scratch = [0.0 as $t; 16 * N];
            let mut index = [0u32; N];
            let mut reals = [0.0 as $t; 1024];
            let mut pindex = [0u32; 1024];
            let mut rep = report();
            let expects = [(&lin, &lr), (&ang, &ar), (&lamg, &lar), (&aamg, &aar)];
            for (which, &(expect, r)) in expects.iter().enumerate() {
                let need = if which == 2 { ls.reals } else { as_.reals };
                let mut cases: [(&$cons_ty, usize, dk_status); 3] = [
                    (&bad, need, dk_status::DK_ERR_NOT_UNIT),
                    (&good, need - 1, dk_status::DK_ERR_BUFFER_TOO_SMALL),
                    (&good, need, dk_status::DK_OK),
                ];
                if which < 2 {
                    cases[1] = cases[0];
                }
                for (cn, reals_len, want) in cases {
                    let mut values = given;
                    let v = flat_mut(&mut values);
                    let pl = $pools_ty {
                        reals: reals.as_mut_ptr(),
                        reals_len,
                        indices: pindex.as_mut_ptr(),
                        indices_len: indices,
                        bytes: core::ptr::null_mut(),
                        bytes_len: 0,
                    };
                    // SAFETY: every array (the structs' too) is valid for the length passed
                    // with it; nothing overlaps.
                    let s = unsafe {
                        match which {
                            0 => $lin_sl(
                                &system,
                                cn,
                                &copts,
                                2,
                                v.as_mut_ptr(),
                                v.len(),
                                scratch.as_mut_ptr(),
                                l1,
                                index.as_mut_ptr(),
                                N,
                                &mut rep,
                            ),
                            1 => $ang_sl(
                                &system,
                                p.as_ptr(),
                                p.len(),
                                2,
                                cn,
                                &aopts,
                                1.0,
                                v.as_mut_ptr(),
                                v.len(),
                                scratch.as_mut_ptr(),
                                l2,
                                index.as_mut_ptr(),
                                N,
                                &mut rep,
                            ),
                            2 => $lin_sl_amg(
                                &system,
                                cn,
                                &copts,
                                &amg,
                                2,
                                v.as_mut_ptr(),
                                v.len(),
                                &pl,
                                &mut rep,
                            ),
                            _ => $ang_sl_amg(
                                &system,
                                p.as_ptr(),
                                p.len(),
                                2,
                                cn,
                                &aopts,
                                &amg,
                                v.as_mut_ptr(),
                                v.len(),
                                &pl,
                                &mut rep,
                            ),
                        }
                    };
                    defmt::assert!(s == want);
                    if want == dk_status::DK_OK {
                        defmt::assert!(same(flat(&values), flat(expect)));
                        defmt::assert!(rep.iterations == r.iterations && rep.converged);
                    } else {
                        defmt::assert!(same(flat(&values), flat(&given)));
                    }
                }
            }
        }
    };
}

mod f64_cases {
    use super::*;
    solver_cases!(
        f64,
        [amg, sliding],
        dk_spring_system,
        dk_plan_pools,
        dk_constraints,
        [
            deform_kernel_ffi::spring::dk_spring_solve_options_default,
            deform_kernel_ffi::spring::dk_spring_angle_options_default,
            deform_kernel_ffi::spring::dk_spring_solve_linear_amg_pool_sizes,
            deform_kernel_ffi::spring::dk_spring_solve_linear_amg,
            deform_kernel_ffi::spring::dk_spring_solve_angle_amg_pool_sizes,
            deform_kernel_ffi::spring::dk_spring_solve_angle_amg,
            deform_kernel_ffi::spring::dk_constraints_fixed_mask,
            deform_kernel_ffi::spring::dk_slide_points,
            deform_kernel_ffi::spring::dk_fit_plane,
            deform_kernel_ffi::spring::dk_spring_solve_linear_sliding_scratch_len,
            deform_kernel_ffi::spring::dk_spring_solve_linear_sliding,
            deform_kernel_ffi::spring::dk_spring_solve_angle_sliding_scratch_len,
            deform_kernel_ffi::spring::dk_spring_solve_angle_sliding,
            deform_kernel_ffi::spring::dk_spring_solve_linear_sliding_amg_pool_sizes,
            deform_kernel_ffi::spring::dk_spring_solve_linear_sliding_amg,
            deform_kernel_ffi::spring::dk_spring_solve_angle_sliding_amg_pool_sizes,
            deform_kernel_ffi::spring::dk_spring_solve_angle_sliding_amg
        ]
    );
}

mod f32_cases {
    use super::*;
    solver_cases!(
        f32,
        [amg, sliding],
        dk_spring_system_f32,
        dk_plan_pools_f32,
        dk_constraints_f32,
        [
            deform_kernel_ffi::spring::dk_spring_solve_options_default_f32,
            deform_kernel_ffi::spring::dk_spring_angle_options_default_f32,
            deform_kernel_ffi::spring::dk_spring_solve_linear_amg_pool_sizes_f32,
            deform_kernel_ffi::spring::dk_spring_solve_linear_amg_f32,
            deform_kernel_ffi::spring::dk_spring_solve_angle_amg_pool_sizes_f32,
            deform_kernel_ffi::spring::dk_spring_solve_angle_amg_f32,
            deform_kernel_ffi::spring::dk_constraints_fixed_mask_f32,
            deform_kernel_ffi::spring::dk_slide_points_f32,
            deform_kernel_ffi::spring::dk_fit_plane_f32,
            deform_kernel_ffi::spring::dk_spring_solve_linear_sliding_scratch_len,
            deform_kernel_ffi::spring::dk_spring_solve_linear_sliding_f32,
            deform_kernel_ffi::spring::dk_spring_solve_angle_sliding_scratch_len_f32,
            deform_kernel_ffi::spring::dk_spring_solve_angle_sliding_f32,
            deform_kernel_ffi::spring::dk_spring_solve_linear_sliding_amg_pool_sizes_f32,
            deform_kernel_ffi::spring::dk_spring_solve_linear_sliding_amg_f32,
            deform_kernel_ffi::spring::dk_spring_solve_angle_sliding_amg_pool_sizes_f32,
            deform_kernel_ffi::spring::dk_spring_solve_angle_sliding_amg_f32
        ]
    );
}

#[defmt_test::tests]
mod tests {
    #[test]
    fn amg_solves_f64() {
        super::f64_cases::amg();
    }

    #[test]
    fn amg_solves_f32() {
        super::f32_cases::amg();
    }

    #[test]
    fn sliding_f64() {
        super::f64_cases::sliding();
    }

    #[test]
    fn sliding_f32() {
        super::f32_cases::sliding();
    }
}
