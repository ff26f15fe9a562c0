//! Golden case of the rigid wall layer (`elasticity::rigid_layer`): the bottom row of the
//! jittered triangle mesh of [`mesh_cases`](crate::mesh_cases) turned 20° (its displacement
//! and one rotation per wall node), the rest of the perimeter fixed, a layer of 0.9 (the
//! second row joins it). The hash covers the count, the mask and every displacement, then the
//! error of a negative thickness.

use deform_kernel::elasticity::rigid_layer;
use deform_kernel::{Quat, Real};

use crate::mesh_cases::{boundary_displacement, hash_points, mesh, N, NX};
use crate::Fnv;

/// The layer of the turned bottom row.
pub fn rigid_wall_layer<T: Real>() -> u64 {
    let m = mesh::<T>();
    let mut disp = boundary_displacement(&m);
    let mut fixed = [0u8; N];
    for &b in &m.boundary {
        if let Some(f) = fixed.get_mut(b as usize) {
            *f = 1;
        }
    }
    let wall: [u32; NX] = core::array::from_fn(|i| i as u32);
    let rotations = [Quat::from_rotation_z(T::from_f64(20f64.to_radians())); NX];
    let mut h = Fnv::new();
    match rigid_layer(
        &m.points,
        &wall,
        &rotations,
        T::from_f64(0.9),
        &mut fixed,
        &mut disp,
    ) {
        Ok(added) => h.usize(added),
        Err(e) => h.error(&e),
    }
    h.bytes(&fixed);
    hash_points(&mut h, &disp);
    if let Err(e) = rigid_layer(&m.points, &wall, &rotations, -T::ONE, &mut fixed, &mut disp) {
        h.error(&e);
    }
    h.finish()
}
