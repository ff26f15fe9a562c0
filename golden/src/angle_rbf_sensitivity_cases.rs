//! Golden cases for the adjoints of the angle-inclusion springs (`angle_adjoint`, block CG,
//! `ε = 0.01`) and of the RBF deformation (`rbf_adjoint`, thin-plate splines with greedy
//! centres and the wall correction, linearised about the 20° motion) on the jittered triangle
//! mesh of [`mesh_cases`](crate::mesh_cases). The hashes cover every output value and the
//! report.

use deform_kernel::rbf::{rbf_index_len, rbf_scratch_len, RbfKernel, RbfOptions};
use deform_kernel::sensitivity::{
    angle_adjoint, angle_adjoint_scratch_len, rbf_adjoint, AngleSolver,
};
use deform_kernel::spring::{AngleMethod, AngleSystem, SolveOptions};
use deform_kernel::Real;

use crate::mesh_cases::{
    boundary_displacement, hash_points, hash_report, mesh, with_system, N, NB,
};
use crate::{Fnv, XorShift};

/// A random volume sensitivity `w` (one item per node).
fn sensitivity<T: Real>(seed: u64) -> [[T; 2]; N] {
    let mut rng = XorShift::new(seed);
    core::array::from_fn(|_| [rng.uniform(-1.0, 1.0), rng.uniform(-1.0, 1.0)])
}

/// Adjoint of the angle springs for a random volume sensitivity.
pub fn angle_spring_adjoint<T: Real>() -> u64 {
    let m = mesh::<T>();
    let w = sensitivity::<T>(0x5EED_0032);
    let mut h = Fnv::new();
    let mut g = [[T::ZERO; 2]; N];
    let ok = with_system(&m, |sys, _| {
        let asys = match AngleSystem::new(*sys, &m.points, T::from_f64(0.01)) {
            Ok(a) => a,
            Err(e) => return h.error(&e),
        };
        let solver = AngleSolver::Method(AngleMethod::Cg);
        let mut scratch = [[T::ZERO; 2]; 5 * N];
        let len = angle_adjoint_scratch_len(&asys, &solver).min(5 * N);
        let s = scratch.get_mut(..len).unwrap_or(&mut []);
        match angle_adjoint(&asys, solver, &SolveOptions::default(), &w, &mut g, s) {
            Ok(r) => hash_report(&mut h, &r),
            Err(e) => h.error(&e),
        }
    });
    if ok.is_none() {
        return 0;
    }
    hash_points(&mut h, &g);
    h.finish()
}

/// Adjoint of the RBF deformation (thin-plate, greedy, corrected) at the 20° motion.
pub fn rbf_adjoint_tps<T: Real>() -> u64 {
    let m = mesh::<T>();
    let disp = boundary_displacement(&m);
    let motion: [[T; 2]; NB] = core::array::from_fn(|k| {
        m.boundary
            .get(k)
            .and_then(|&b| disp.get(b as usize))
            .copied()
            .unwrap_or([T::ZERO; 2])
    });
    let w = sensitivity::<T>(0x5EED_0033);
    let o = RbfOptions {
        kernel: RbfKernel::ThinPlate,
        tolerance: T::from_f64(1e-3),
        max_centres: NB / 2,
        correction_radius: T::from_f64(0.5),
    };
    let mut index = [0u32; 8 * NB];
    let mut scratch = [T::ZERO; 2 * NB * NB];
    let il = rbf_index_len::<T, 2>(NB, &o).min(index.len());
    let sl = rbf_scratch_len::<T, 2>(NB, &o).min(scratch.len());
    let idx = index.get_mut(..il).unwrap_or(&mut []);
    let s = scratch.get_mut(..sl).unwrap_or(&mut []);
    let mut g = [[T::ZERO; 2]; NB];
    let mut h = Fnv::new();
    match rbf_adjoint(&m.points, &m.boundary, &motion, &o, idx, s, &w, &mut g) {
        Ok(r) => {
            h.usize(r.centres);
            h.real(r.max_error);
        }
        Err(e) => h.error(&e),
    }
    hash_points(&mut h, &g);
    h.finish()
}
