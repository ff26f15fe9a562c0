//! What the quality table takes from the kernel's `quality::compare` (inverted cells, measure
//! ratios, wall angles), computed from cell measures the quality pass has already evaluated:
//! `compare` would evaluate every cell of both meshes again (half of the pass's cell work).

use deform_kernel::quality::{wall_angle_change, wall_angle_scratch_len, Wall, WallAngleChange};
use deform_kernel::Cells;

use super::{cells_view, edge_graph, kernel, WallInput};
use crate::error::CliError;

/// The measure part of the kernel's `QualityReport`, bit for bit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct MeasureRatios {
    /// Cells whose signed measure changed sign (`> 0` became `≤ 0`, `< 0` became `≥ 0`).
    pub inverted_cells: usize,
    /// Smallest after/before ratio over cells with a non-zero `before` (`+∞` when none).
    pub min_measure_ratio: f64,
    /// Largest such ratio (`−∞` when none).
    pub max_measure_ratio: f64,
}

/// [`MeasureRatios`] of per-cell measures `before` and `after`, in cell order: the same
/// comparisons, in the same order, as the kernel's `compare` on the points these measures were
/// evaluated at (a NaN ratio seen first stays, as there).
pub(super) fn measure_ratios(before: &[f64], after: &[f64]) -> MeasureRatios {
    let mut r = MeasureRatios {
        inverted_cells: 0,
        min_measure_ratio: f64::INFINITY,
        max_measure_ratio: f64::NEG_INFINITY,
    };
    let mut first = true;
    for (&u, &d) in before.iter().zip(after) {
        r.inverted_cells += usize::from((u > 0.0 && d <= 0.0) || (u < 0.0 && d >= 0.0));
        if u == 0.0 {
            continue;
        }
        let ratio = d / u;
        if first || ratio < r.min_measure_ratio {
            r.min_measure_ratio = ratio;
        }
        if first || ratio > r.max_measure_ratio {
            r.max_measure_ratio = ratio;
        }
        first = false;
    }
    r
}

/// The per-cell signed measures of `points` over `view`.
pub(super) fn measures<const D: usize>(
    view: &Cells<'_>,
    points: &[[f64; D]],
) -> Result<Vec<f64>, CliError> {
    let mut out = vec![0.0; view.len()];
    deform_kernel::quality::cell_measures(view, points, &mut out).map_err(kernel("quality"))?;
    Ok(out)
}

/// The wall-angle change of `compare` with a wall (`None` without one), on the same points.
pub(super) fn wall_angles<const D: usize>(
    view: &Cells<'_>,
    undeformed: &[[f64; D]],
    deformed: &[[f64; D]],
    wall: WallInput<'_>,
) -> Result<Option<WallAngleChange<f64>>, CliError> {
    let Some((w, given)) = wall else {
        return Ok(None);
    };
    let n = undeformed.len();
    let built;
    let graph = match given {
        Some(g) => g,
        None => {
            built = edge_graph(view, false)?;
            &built
        }
    };
    let wall_view = cells_view(w, n)?;
    let wall = Wall::new(wall_view, graph.view()?).map_err(kernel("wall"))?;
    let mut scratch = vec![[0.0; D]; wall_angle_scratch_len(n)];
    wall_angle_change(&wall, undeformed, deformed, &mut scratch)
        .map(Some)
        .map_err(kernel("quality"))
}

#[cfg(test)]
mod tests {
    use super::*;
    use deform_kernel::quality::compare;

    /// Pseudo-random tetrahedra over a jittered point cloud, some nodes collapsed onto others
    /// (zero measures) and some pushed through (sign changes), both measure arrays compared
    /// with the kernel's `compare` on the same points.
    #[test]
    fn ratios_are_the_kernels_compare() {
        let mut x = 0x2545_f491_4f6c_dd1du64;
        let mut next = move || {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            x
        };
        for round in 0..40 {
            let n = 60;
            let mut unit = || (next() >> 11) as f64 / (1u64 << 53) as f64 - 0.5;
            let mut before: Vec<[f64; 3]> = (0..n).map(|_| [unit(), unit(), unit()]).collect();
            let mut after = before.clone();
            for p in after.iter_mut() {
                for v in p.iter_mut() {
                    *v += 0.4 * unit();
                }
            }
            let mut nodes = Vec::new();
            while nodes.len() < 4 * 150 {
                let mut cell = [0u32; 4];
                for k in 0..4 {
                    cell[k] = (next() % n as u64) as u32;
                    while cell[..k].contains(&cell[k]) {
                        cell[k] = (cell[k] + 1) % n as u32;
                    }
                }
                nodes.extend(cell);
            }
            if round % 3 == 0 {
                // Two nodes at one place: the cells with both have measure exactly 0.
                nodes[..4].copy_from_slice(&[0, 1, 2, 3]);
                before[1] = before[0];
                after[1] = after[0];
            }
            let offsets: Vec<u32> = (0..=150).map(|c| 4 * c).collect();
            let kinds = vec![10u8; 150];
            let cells = Cells::new(n, &offsets, &nodes, &kinds).unwrap();
            let (mb, ma) = (
                measures(&cells, &before).unwrap(),
                measures(&cells, &after).unwrap(),
            );
            let r = compare(&cells, &before, &after, None, &mut []).unwrap();
            let m = measure_ratios(&mb, &ma);
            assert_eq!(m.inverted_cells, r.inverted_cells, "round {round}");
            assert!(r.inverted_cells > 0, "round {round} exercises inversions");
            assert_eq!(
                m.min_measure_ratio.to_bits(),
                r.min_measure_ratio.to_bits(),
                "round {round}"
            );
            assert_eq!(
                m.max_measure_ratio.to_bits(),
                r.max_measure_ratio.to_bits(),
                "round {round}"
            );
        }
        let none = measure_ratios(&[0.0, -0.0], &[1.0, 2.0]);
        assert_eq!(none.min_measure_ratio, f64::INFINITY);
        assert_eq!(none.max_measure_ratio, f64::NEG_INFINITY);
    }
}
