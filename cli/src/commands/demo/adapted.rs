//! The demo's Alter case (his figures 5–8): a solution-adapted volume grid whose outer
//! boundary is rough, smoothed along k with the outer end free; pictures of the
//! outer-boundary arclength and of a cut through the volume grid, before and after.

use deform_kernel::Direction;

use super::{Files, SmoothRow};
use crate::engine::{quality, smooth_block, structured_cells};
use crate::error::CliError;
use crate::formats::vtk::{write_vts, VtkEncoding};
use crate::formats::CellList;
use crate::plot::{bounding_window, Picture, Shading, Window};

/// The k-arclength at the outer boundary, `S(i, j)` (i fastest).
fn outer_arclength(dims: [usize; 3], p: &[[f64; 3]]) -> Vec<f64> {
    let [ni, nj, nk] = dims;
    let face = ni * nj;
    (0..face)
        .map(|l| {
            (1..nk)
                .map(|k| {
                    let (a, b) = (p[l + face * (k - 1)], p[l + face * k]);
                    ((b[0] - a[0]).powi(2) + (b[1] - a[1]).powi(2) + (b[2] - a[2]).powi(2)).sqrt()
                })
                .sum()
        })
        .collect()
}

/// RMS over the interior of the 5-point (i, j) Laplacian of `s`: the roughness measure.
fn roughness(s: &[f64], ni: usize, nj: usize) -> f64 {
    let mut sum = 0.0;
    for j in 1..nj - 1 {
        for i in 1..ni - 1 {
            let c = i + ni * j;
            let l = s[c - 1] + s[c + 1] + s[c - ni] + s[c + ni] - 4.0 * s[c];
            sum += l * l;
        }
    }
    (sum / ((ni - 2) * (nj - 2)) as f64).sqrt()
}

/// Per cell of the (i, j) face, the mean of `S − mean_j S` at its four corners: the part of
/// the outer-boundary arclength that varies across the body (noise, and what is left of it).
fn deviation_cells(s: &[f64], ni: usize, nj: usize) -> Vec<f64> {
    let mean: Vec<f64> = (0..ni)
        .map(|i| (0..nj).map(|j| s[i + ni * j]).sum::<f64>() / nj as f64)
        .collect();
    let d = |i: usize, j: usize| s[i + ni * j] - mean[i];
    let mut out = Vec::new();
    for j in 0..nj - 1 {
        for i in 0..ni - 1 {
            out.push(0.25 * (d(i, j) + d(i + 1, j) + d(i, j + 1) + d(i + 1, j + 1)));
        }
    }
    out
}

/// The plane `j` of the volume grid as a 2D grid `[ni, nk]` in its (x, z) coordinates (the
/// generated grid's middle plane `φ = π/2` lies in y = 0).
fn plane(dims: [usize; 3], p: &[[f64; 3]], j: usize) -> Vec<[f64; 3]> {
    let [ni, nj, nk] = dims;
    (0..nk)
        .flat_map(|k| (0..ni).map(move |i| i + ni * (j + nj * k)))
        .map(|q| [p[q][0], p[q][2], 0.0])
        .collect()
}

/// Writes the pictures of one state (`tag`: before or after).
fn pictures(
    files: &mut Files<'_>,
    dims: [usize; 3],
    pts: &[[f64; 3]],
    tag: &str,
    range: f64,
) -> Result<(), CliError> {
    let [ni, nj, _] = dims;
    let none_face = vec![false; (ni - 1) * (nj - 1)];
    let empty: [&CellList; 0] = [];
    // Outer-boundary arclength over the (i, j) index plane (Alter's figures 6 and 7).
    let s = outer_arclength(dims, pts);
    let shade = deviation_cells(&s, ni, nj);
    let face: Vec<[f64; 3]> = (0..ni * nj)
        .map(|l| {
            [
                (l % ni) as f64 / (ni - 1) as f64 * 1.5,
                (l / ni) as f64 / (nj - 1) as f64,
                0.0,
            ]
        })
        .collect();
    let face_cells = structured_cells([ni, nj, 1], &face, 2);
    let label = "outer-boundary arclength S(i, j) minus its mean over j";
    let title = format!("adapted grid {tag}: {label}; i across, j up");
    let pic = Picture {
        points: &face,
        cells: &face_cells,
        boundaries: &empty,
        highlight: &none_face,
        title: &title,
        shading: Some(Shading {
            values: &shade,
            range: [-range, range],
            label,
        }),
    };
    let mut window = bounding_window(&face);
    window[1] -= 0.25 * (window[3] - window[1]);
    files.picture(
        &format!("smooth4_adapted_outer_arclength_{tag}"),
        &pic,
        window,
    )?;
    // The middle j plane of the volume grid (his figures 5 and 8).
    let cut = plane(dims, pts, nj / 2);
    let cut_dims = [ni, dims[2], 1];
    let cut_cells = structured_cells(cut_dims, &cut, 2);
    let none = vec![false; (ni - 1) * (dims[2] - 1)];
    let title = format!("adapted grid {tag}: the plane j = {} (x, z)", nj / 2 + 1);
    let pic = Picture {
        points: &cut,
        cells: &cut_cells,
        boundaries: &empty,
        highlight: &none,
        title: &title,
        shading: None,
    };
    let window: Window = bounding_window(&cut);
    files.picture(&format!("smooth4_adapted_grid_{tag}"), &pic, window)?;
    let mut v = Vec::new();
    write_vts(&mut v, dims, pts, &[], &[], VtkEncoding::Base64)
        .map_err(|e| CliError::Invalid(e.to_string()))?;
    files.put(&format!("smooth4_adapted_{tag}.vts"), &v)
}

/// Generates the adapted grid, smooths it along k with a free outer end (30 iterations, the
/// paper's λ, μ), writes the pictures and returns the table row.
pub(super) fn adapted_case(quick: bool, files: &mut Files<'_>) -> Result<SmoothRow, CliError> {
    let spec = deform_meshgen::AdaptedSpec {
        dims: if quick { [33, 25, 33] } else { [65, 49, 65] },
        ..deform_meshgen::AdaptedSpec::default()
    };
    let dims = spec.dims;
    let before =
        deform_meshgen::adapted_block(&spec).map_err(|e| CliError::Invalid(e.to_string()))?;
    let mut after = before.clone();
    let r = smooth_block(
        3,
        dims,
        &mut after,
        Direction::K,
        (false, true),
        30,
        0.330,
        -0.334,
        None,
        None,
    )?;
    let cells = structured_cells(dims, &after, 3);
    let q = quality(3, &cells, &after, Some(&before), None)?;
    let (s0, s1) = (
        outer_arclength(dims, &before),
        outer_arclength(dims, &after),
    );
    let (r0, r1) = (
        roughness(&s0, dims[0], dims[1]),
        roughness(&s1, dims[0], dims[1]),
    );
    let range = deviation_cells(&s0, dims[0], dims[1])
        .iter()
        .fold(0.0f64, |m, v| m.max(v.abs()));
    pictures(files, dims, &before, "before", range)?;
    pictures(files, dims, &after, "after", range)?;
    Ok(SmoothRow {
        grid: format!("adapted {}×{}×{}", dims[0], dims[1], dims[2]),
        settings: format!(
            "k lines, dimensional, free outer end (kmax), 30 iterations; outer-boundary roughness (RMS ∇²S) {r0:.3e} → {r1:.3e} ({:.1}× smoother)",
            r0 / r1
        ),
        iterations: r.iterations,
        max_stretching_before: r.max_stretching_before,
        max_stretching_after: r.max_stretching_after,
        max_point_move: r.max_point_move,
        folded_cells: q.folded_cells,
    })
}
