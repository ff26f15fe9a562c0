//! Quick test shapes: a triangulated annulus, and boxes with an inner box removed (2D
//! triangles, 3D hexes) for "rotate the inner body" tests.

use deform_kernel::CellKind;

use crate::{boundary_markers2, boundary_markers3, compact, invalid, Mesh2, Mesh3, Result};

/// A triangulated annulus `r_in ≤ r ≤ r_out` about the origin: `n_theta × n_r` points
/// (`n_theta` even ≥ 4, `n_r` ≥ 2, radii uniform), each quad split into two triangles with
/// alternating diagonals. Markers `"inner"` and `"outer"`. Point `(i, j)` (angle index `i`,
/// radius index `j`) has index `i + n_theta j`; the angle runs clockwise so cells are
/// counter-clockwise.
pub fn annulus(n_theta: usize, n_r: usize, r_in: f64, r_out: f64) -> Result<Mesh2> {
    if n_theta < 4 || n_theta % 2 != 0 || n_r < 2 {
        return invalid("annulus needs an even n_theta >= 4 and n_r >= 2");
    }
    if !(r_in > 0.0) || !(r_out > r_in) || !r_out.is_finite() {
        return invalid("annulus needs 0 < r_in < r_out (finite)");
    }
    if n_theta
        .checked_mul(n_r)
        .and_then(|n| u32::try_from(n).ok())
        .is_none()
    {
        return invalid("too many nodes for u32 indices");
    }
    let mut mesh = Mesh2::new();
    for j in 0..n_r {
        let r = r_in + (r_out - r_in) * j as f64 / (n_r - 1) as f64;
        for i in 0..n_theta {
            let t = -2.0 * core::f64::consts::PI * i as f64 / n_theta as f64;
            mesh.points.push([r * libm::cos(t), r * libm::sin(t)]);
        }
    }
    let id = |i: usize, j: usize| ((i % n_theta) + n_theta * j) as u32;
    for j in 0..n_r - 1 {
        for i in 0..n_theta {
            let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
            if (i + j) % 2 == 0 {
                mesh.push_cell(CellKind::Triangle, &[a, b, c]);
                mesh.push_cell(CellKind::Triangle, &[a, c, d]);
            } else {
                mesh.push_cell(CellKind::Triangle, &[a, b, d]);
                mesh.push_cell(CellKind::Triangle, &[b, c, d]);
            }
        }
    }
    let mid = 0.5 * (r_in + r_out);
    mesh.markers = boundary_markers2(&mesh, &["inner", "outer"], |p| {
        usize::from(libm::hypot(p[0], p[1]) > mid)
    });
    mesh.dims = Some([n_theta, n_r, 1]);
    mesh.periodic_i = true;
    Ok(mesh)
}

fn check_box(n: usize, inner: usize) -> Result<()> {
    if n < 4 || inner < 1 || inner + 2 > n || (n - inner) % 2 != 0 {
        return invalid(
            "box_with_inner_box needs n >= 4 cells, 1 <= inner <= n - 2 and n - inner even",
        );
    }
    if (n + 1)
        .checked_pow(3)
        .and_then(|t| u32::try_from(t).ok())
        .is_none()
    {
        return invalid("too many nodes for u32 indices");
    }
    Ok(())
}

/// The square `[−1, 1]²` cut into `n × n` uniform cells, minus the central `inner × inner`
/// cells (a square hole of half-width `inner / n`); each remaining cell is split into two
/// triangles (alternating diagonals). Markers `"inner"` (the hole) and `"outer"`.
pub fn box_with_inner_box2(n: usize, inner: usize) -> Result<Mesh2> {
    check_box(n, inner)?;
    let lo = (n - inner) / 2;
    let hi = lo + inner;
    let mut mesh = Mesh2::new();
    let coord = |i: usize| -1.0 + 2.0 * i as f64 / n as f64;
    for j in 0..=n {
        for i in 0..=n {
            mesh.points.push([coord(i), coord(j)]);
        }
    }
    let id = |i: usize, j: usize| (i + (n + 1) * j) as u32;
    for j in 0..n {
        for i in 0..n {
            if (lo..hi).contains(&i) && (lo..hi).contains(&j) {
                continue;
            }
            let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
            if (i + j) % 2 == 0 {
                mesh.push_cell(CellKind::Triangle, &[a, b, c]);
                mesh.push_cell(CellKind::Triangle, &[a, c, d]);
            } else {
                mesh.push_cell(CellKind::Triangle, &[a, b, d]);
                mesh.push_cell(CellKind::Triangle, &[b, c, d]);
            }
        }
    }
    compact(&mut mesh);
    let edge = 1.0 - 0.5 / n as f64;
    mesh.markers = boundary_markers2(&mesh, &["inner", "outer"], |p| {
        usize::from(p[0].abs() > edge || p[1].abs() > edge)
    });
    Ok(mesh)
}

/// The cube `[−1, 1]³` cut into `n³` uniform hexes, minus the central `inner³` hexes (a
/// cubic hole). Markers `"inner"` and `"outer"` (outward quads).
pub fn box_with_inner_box3(n: usize, inner: usize) -> Result<Mesh3> {
    check_box(n, inner)?;
    let lo = (n - inner) / 2;
    let hi = lo + inner;
    let mut mesh = Mesh3::new();
    let coord = |i: usize| -1.0 + 2.0 * i as f64 / n as f64;
    for k in 0..=n {
        for j in 0..=n {
            for i in 0..=n {
                mesh.points.push([coord(i), coord(j), coord(k)]);
            }
        }
    }
    let id = |i: usize, j: usize, k: usize| (i + (n + 1) * (j + (n + 1) * k)) as u32;
    for k in 0..n {
        for j in 0..n {
            for i in 0..n {
                if (lo..hi).contains(&i) && (lo..hi).contains(&j) && (lo..hi).contains(&k) {
                    continue;
                }
                mesh.push_cell(
                    CellKind::Hexahedron,
                    &[
                        id(i, j, k),
                        id(i + 1, j, k),
                        id(i + 1, j + 1, k),
                        id(i, j + 1, k),
                        id(i, j, k + 1),
                        id(i + 1, j, k + 1),
                        id(i + 1, j + 1, k + 1),
                        id(i, j + 1, k + 1),
                    ],
                );
            }
        }
    }
    compact(&mut mesh);
    let edge = 1.0 - 0.5 / n as f64;
    mesh.markers = boundary_markers3(&mesh, &["inner", "outer"], |p| {
        usize::from(p.iter().any(|x| x.abs() > edge))
    });
    Ok(mesh)
}
