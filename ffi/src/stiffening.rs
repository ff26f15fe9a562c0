//! Stiffness choices beyond Batina's `1/L`, as SU2's `DEFORM_STIFFNESS_TYPE`:
//! `dk_spring_wall_distances`, `dk_spring_wall_distance_factors` (`WALL_DISTANCE`),
//! `dk_spring_dual_volumes`, `dk_spring_inverse_volume_factors` (`INVERSE_VOLUME`) and
//! `dk_spring_scale_stiffness`, which multiplies a stiffness by the nodes' factors (the
//! kernel's `spring::stiffening`). The scaled stiffness goes to the solvers, `dk_deform_spring`
//! or a plan (`dk_plan_init`'s `stiffness`).
//!
//! Wall nodes and cells are read in `index_base` 0 or 1; with 1 the 0-based copies go to the
//! caller's `uint32_t` `index_scratch` (`wall_len`, or `cells->offsets_len + cells->nodes_len`
//! entries).
#![allow(unsafe_code)] // `#[no_mangle] unsafe extern "C"`; raw pointers are only read via crate::slice.

use deform_kernel::spring::{
    dual_volumes, inverse_volume_factors, scale_stiffness, wall_distance_factors, wall_distances,
};
use deform_kernel::Real;

use crate::args::{by_dim, done, read_points, rebase};
use crate::graph::{dk_cells, dk_graph, read_graph, CellsIn};
use crate::slice::{input, output, In, Out};
use crate::status::dk_status;

fn wall_distances_d<T: Real, const D: usize>(
    points: In<'_, T>,
    wall: In<'_, u32>,
    index_base: u32,
    index_scratch: Out<'_, u32>,
    out: Out<'_, T>,
) -> Result<(), dk_status> {
    let p = read_points::<T, D>(points)?;
    let (w, _) = rebase(input(wall)?, index_base, output(index_scratch)?)?;
    wall_distances(p, w, output(out)?).map_err(dk_status::from)
}

fn dual_volumes_d<T: Real, const D: usize>(
    cells: In<'_, dk_cells>,
    index_base: u32,
    index_scratch: Out<'_, u32>,
    points: In<'_, T>,
    out: Out<'_, T>,
    scratch: Out<'_, T>,
) -> Result<(), dk_status> {
    let p = read_points::<T, D>(points)?;
    let s = output(index_scratch)?;
    let (c, _) = CellsIn::read(cells)?.cells(p.len(), index_base, s)?;
    dual_volumes(&c, p, output(out)?, output(scratch)?).map_err(dk_status::from)
}

/// `values ← factors(values)` in place with `f` (the wall-distance or inverse-volume rule).
fn factors<T: Real>(
    values: Out<'_, T>,
    exponent: T,
    f: fn(&mut [T], T) -> deform_kernel::Result<()>,
) -> dk_status {
    done(output(values).and_then(|v| f(v, exponent).map_err(dk_status::from)))
}

mod abi;
pub use abi::*;
