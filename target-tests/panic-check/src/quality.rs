//! Panic-check calls for the kernel's quality entry points: `cell_quality`, `cell_measures`,
//! `min_corner_jacobians`, `inverted_cells`, `folded_cells`, `compare`, `Wall`,
//! `wall_angle_change` and `wall_angle_scratch_len`, for `f32` and `f64`, 2D and 3D.

use core::hint::black_box;

use deform_kernel::quality::{
    cell_measures, cell_quality, compare, folded_cells, inverted_cells, min_corner_jacobians,
    wall_angle_change, wall_angle_scratch_len, CellQuality, QualityReport, Wall, WallAngleChange,
};
use deform_kernel::{CellKind, Cells, Graph, Real};

/// Calls every quality entry point with opaque inputs.
pub fn exercise() {
    planar::<f32>();
    planar::<f64>();
    solid::<f32>();
    solid::<f64>();
}

#[inline(always)]
fn bb<T>(x: T) -> T {
    black_box(x)
}

#[inline(always)]
fn keep<T>(x: T) {
    black_box(x);
}

/// Opaque points from `f64` coordinates.
#[inline(always)]
fn points<T: Real, const D: usize, const N: usize>(xs: [[f64; D]; N]) -> [[T; D]; N] {
    bb(xs.map(|p| p.map(T::from_f64)))
}

fn report<T: Real>(r: &QualityReport<T>) {
    keep(r.cells);
    keep(r.inverted_cells);
    keep(r.folded_cells);
    keep(r.folded_cells_undeformed);
    keep(r.degenerate_cells);
    keep(r.min_measure_ratio);
    keep(r.min_ratio_cell);
    keep(r.max_measure_ratio);
    keep(r.max_ratio_cell);
    keep(r.min_measure);
    keep(r.min_scaled_jacobian);
    keep(r.wall);
    keep(core::hint::black_box(*r) == *r);
}

fn cell<T: Real>(q: &CellQuality<T>) {
    keep(q.measure);
    keep(q.min_jacobian);
    keep(q.min_scaled_jacobian);
}

fn angle<T: Real>(w: &WallAngleChange<T>) {
    keep(w.max_change);
    keep(w.node);
    keep(w.measured);
    keep(w.skipped);
}

/// A quad and a triangle (2D), a wall of two lines, and a 5-node edge graph.
#[inline(never)]
fn planar<T: Real>() {
    let undeformed: [[T; 2]; 5] =
        points([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0], [2.0, 0.5]]);
    let deformed: [[T; 2]; 5] =
        points([[0.0, 0.1], [1.0, 0.0], [1.2, 1.0], [0.0, 1.0], [2.0, 0.4]]);
    let u: &[[T; 2]] = bb(&undeformed);
    let d: &[[T; 2]] = bb(&deformed);

    for kind in CellKind::ALL {
        if let Ok(q) = bb(cell_quality(bb(kind), bb(&undeformed[..4]))) {
            cell(&q);
        }
    }

    let offsets: &[u32] = bb(&[0, 4, 7]);
    let nodes: &[u32] = bb(&[0, 1, 2, 3, 1, 4, 2]);
    let kinds: &[u8] = bb(&[9, 5]);
    let Ok(cells) = bb(Cells::new(bb(5), offsets, nodes, kinds)) else {
        return;
    };
    let mut out = [T::ZERO; 2];
    keep(cell_measures(&cells, u, bb(&mut out[..])));
    keep(min_corner_jacobians(&cells, d, bb(true), bb(&mut out[..])));
    keep(min_corner_jacobians(&cells, d, bb(false), bb(&mut out[..])));
    keep(&out);
    keep(inverted_cells(&cells, u, d));
    keep(folded_cells(&cells, d));

    let w_offsets: &[u32] = bb(&[0, 2, 4]);
    let w_nodes: &[u32] = bb(&[0, 1, 1, 4]);
    let w_kinds: &[u8] = bb(&[3, 3]);
    let g_offsets: &[u32] = bb(&[0, 2, 5, 8, 10, 12]);
    let g_targets: &[u32] = bb(&[1, 3, 0, 2, 4, 1, 3, 4, 0, 2, 1, 2]);
    let (Ok(elements), Ok(graph)) = (
        bb(Cells::new(bb(5), w_offsets, w_nodes, w_kinds)),
        bb(Graph::new(g_offsets, g_targets)),
    ) else {
        return;
    };
    let Ok(wall) = bb(Wall::new(elements, graph)) else {
        return;
    };
    keep(wall.elements());
    keep(wall.graph());
    keep(wall_angle_scratch_len(bb(5)));
    let mut scratch = [[T::ZERO; 2]; 10];
    if let Ok(w) = bb(wall_angle_change(&wall, u, d, bb(&mut scratch[..]))) {
        angle(&w);
    }
    if let Ok(r) = bb(compare(&cells, u, d, Some(&wall), bb(&mut scratch[..]))) {
        report(&r);
    }
    if let Ok(r) = bb(compare(&cells, u, d, None, bb(&mut scratch[..0]))) {
        report(&r);
    }
    keep(&scratch);
}

/// One cell of each 3D kind sharing 8 points, a wall of a quad and a triangle.
#[inline(never)]
fn solid<T: Real>() {
    let undeformed: [[T; 3]; 9] = points([
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
        [1.0, 0.0, 1.0],
        [1.0, 1.0, 1.0],
        [0.0, 1.0, 1.0],
        [0.5, 0.5, 2.0],
    ]);
    let mut deformed = undeformed;
    deformed[6] = [T::from_f64(1.2), T::ONE, T::from_f64(0.9)];
    let u: &[[T; 3]] = bb(&undeformed);
    let d: &[[T; 3]] = bb(&deformed);

    for kind in CellKind::ALL {
        let corners = undeformed.get(..kind.node_count()).unwrap_or(&[]);
        if let Ok(q) = bb(cell_quality(bb(kind), bb(corners))) {
            cell(&q);
        }
    }

    // Hex, prism (VTK wedge), pyramid, tetrahedron.
    let offsets: &[u32] = bb(&[0, 8, 14, 19, 23]);
    let nodes: &[u32] = bb(&[
        0, 1, 2, 3, 4, 5, 6, 7, /* */ 0, 3, 1, 4, 7, 5, /* */ 4, 5, 6, 7, 8,
        /* */ 0, 1, 3, 4,
    ]);
    let kinds: &[u8] = bb(&[12, 13, 14, 10]);
    let Ok(cells) = bb(Cells::new(bb(9), offsets, nodes, kinds)) else {
        return;
    };
    let mut out = [T::ZERO; 4];
    keep(cell_measures(&cells, u, bb(&mut out[..])));
    keep(min_corner_jacobians(&cells, d, bb(true), bb(&mut out[..])));
    keep(min_corner_jacobians(&cells, d, bb(false), bb(&mut out[..])));
    keep(&out);
    keep(inverted_cells(&cells, u, d));
    keep(folded_cells(&cells, d));

    let w_offsets: &[u32] = bb(&[0, 4, 7]);
    let w_nodes: &[u32] = bb(&[0, 3, 2, 1, 0, 1, 4]);
    let w_kinds: &[u8] = bb(&[9, 5]);
    let g_offsets: &[u32] = bb(&[0, 3, 6, 9, 12, 16, 20, 24, 28, 32]);
    let g_targets: &[u32] = bb(&[
        1, 3, 4, 0, 2, 5, 1, 3, 6, 0, 2, 7, 0, 5, 7, 8, 1, 4, 6, 8, 2, 5, 7, 8, 3, 4, 6, 8, 4, 5,
        6, 7,
    ]);
    let (Ok(elements), Ok(graph)) = (
        bb(Cells::new(bb(9), w_offsets, w_nodes, w_kinds)),
        bb(Graph::new(g_offsets, g_targets)),
    ) else {
        return;
    };
    let Ok(wall) = bb(Wall::new(elements, graph)) else {
        return;
    };
    let mut scratch = [[T::ZERO; 3]; 18];
    if let Ok(w) = bb(wall_angle_change(&wall, u, d, bb(&mut scratch[..]))) {
        angle(&w);
    }
    if let Ok(r) = bb(compare(&cells, u, d, Some(&wall), bb(&mut scratch[..]))) {
        report(&r);
    }
    keep(&scratch);
}
