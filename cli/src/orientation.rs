//! Mesh orientation: which way each connected region of a mesh turns.
//!
//! A mesh whose cells are all clockwise (2D) or left-handed (3D) is as valid as a
//! counter-clockwise one, and so is a mesh with some cells listed the other way: SU2 accepts
//! both and reorders such cells one by one. Folds are decided per cell from the geometry
//! ([`crate::validity`]), and every cell is measured relative to its own orientation in the
//! reference mesh; the regions found here say which way a mesh turns (for reports) and which of
//! two overlapping cells to blame.
//!
//! Regions are the connected components of the cells (two cells are connected when they share a
//! node). A region's orientation is the sign that most of its cells' signed measures have in the
//! reference mesh (ties and all-zero regions count as positive). *Canonical* coordinates mirror
//! the points of negative regions in `x` (`x → −x`); mirroring is exact in floating point (every
//! signed area, volume and corner Jacobian is negated bit for bit, every length and angle is
//! unchanged).

use serde::Serialize;

use crate::formats::CellList;

/// The orientation of one connected region.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Sense {
    /// Counter-clockwise (2D) or right-handed (3D) cells: positive signed measures.
    Positive,
    /// Clockwise (2D) or left-handed (3D) cells: negative signed measures.
    Negative,
}

/// What [`Orientation::of`] found, for reports.
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize)]
pub struct OrientationSummary {
    /// Connected regions of cells.
    pub regions: usize,
    /// Regions whose cells are counter-clockwise / right-handed.
    pub positive_regions: usize,
    /// Regions whose cells are clockwise / left-handed.
    pub negative_regions: usize,
    /// Cells whose reference measure has the sign opposite to their region's majority (listed
    /// the other way; folded only if their geometry is, see [`crate::validity`]).
    pub cells_against_region: usize,
    /// Valid cells listed clockwise (2D) or mirrored (3D), i.e. against the SU2/VTK convention:
    /// SU2 reorders them, `deform convert --reorient` rewrites them.
    pub cells_listed_reversed: usize,
}

impl OrientationSummary {
    /// `"counter-clockwise"`, `"clockwise"` or `"mixed (2 regions ccw, 1 cw)"`, with 3D words
    /// for `dim == 3`.
    pub fn describe(&self, dim: usize) -> String {
        let (pos, neg) = if dim == 3 {
            ("right-handed", "left-handed")
        } else {
            ("counter-clockwise", "clockwise")
        };
        match (self.positive_regions, self.negative_regions) {
            (_, 0) => pos.to_string(),
            (0, _) => neg.to_string(),
            (p, n) => format!("mixed ({p} regions {pos}, {n} {neg})"),
        }
    }

    /// `"listed clockwise"` (2D) or `"listed left-handed"` (3D, mirrored): the words for
    /// [`OrientationSummary::cells_listed_reversed`].
    pub fn reversed_words(dim: usize) -> &'static str {
        if dim == 3 {
            "listed left-handed"
        } else {
            "listed clockwise"
        }
    }
}

/// Per-region orientation of a mesh, and the per-point mirror that makes every region positive.
#[derive(Clone, Debug)]
pub struct Orientation {
    /// Per point: lies in a negative region (points in no cell are never mirrored).
    mirrored: Vec<bool>,
    /// Counts for reports.
    pub summary: OrientationSummary,
}

impl Orientation {
    /// Finds the regions of `cells` and their orientation from the reference `measures` (one
    /// signed measure per cell, in the reference mesh). `node_count` bounds every cell node
    /// (the caller validated the cells against it).
    pub fn of(cells: &CellList, node_count: usize, measures: &[f64]) -> Orientation {
        let mut parent: Vec<u32> = (0..node_count as u32).collect();
        for c in 0..cells.len() {
            let nodes = cell_nodes(cells, c);
            if let Some((&first, rest)) = nodes.split_first() {
                for &n in rest {
                    union(&mut parent, first, n);
                }
            }
        }
        // Votes per region root: (positive cells, negative cells).
        let mut votes = vec![(0usize, 0usize); node_count];
        let mut cell_root = vec![u32::MAX; cells.len()];
        for (c, root_slot) in cell_root.iter_mut().enumerate() {
            let Some(&first) = cell_nodes(cells, c).first() else {
                continue;
            };
            let root = find(&mut parent, first);
            *root_slot = root;
            let m = measures.get(c).copied().unwrap_or(0.0);
            let v = &mut votes[root as usize];
            if m > 0.0 {
                v.0 += 1;
            } else if m < 0.0 {
                v.1 += 1;
            }
        }
        let mut summary = OrientationSummary::default();
        let mut seen = vec![false; node_count];
        for &root in cell_root.iter().filter(|&&r| r != u32::MAX) {
            let r = root as usize;
            if !seen[r] {
                seen[r] = true;
                summary.regions += 1;
                let (p, n) = votes[r];
                if n > p {
                    summary.negative_regions += 1;
                    summary.cells_against_region += p;
                } else {
                    summary.positive_regions += 1;
                    summary.cells_against_region += n;
                }
            }
        }
        let mut mirrored = vec![false; node_count];
        for (node, m) in mirrored.iter_mut().enumerate() {
            let root = find(&mut parent, node as u32) as usize;
            let (p, n) = votes[root];
            *m = n > p;
        }
        Orientation { mirrored, summary }
    }

    /// Per cell: its reference `measures[c]` has the sign opposite to its region's majority.
    pub fn against(&self, cells: &CellList, measures: &[f64]) -> Vec<bool> {
        (0..cells.len())
            .map(|c| {
                let m = measures.get(c).copied().unwrap_or(0.0);
                match cell_nodes(cells, c).first() {
                    Some(&n) if self.sense(n as usize) == Sense::Negative => m > 0.0,
                    Some(_) => m < 0.0,
                    None => false,
                }
            })
            .collect()
    }

    /// The orientation of the region that `point` lies in.
    pub fn sense(&self, point: usize) -> Sense {
        if self.mirrored.get(point).copied().unwrap_or(false) {
            Sense::Negative
        } else {
            Sense::Positive
        }
    }

    /// True when no region is negative (canonical coordinates are the input coordinates).
    pub fn all_positive(&self) -> bool {
        self.summary.negative_regions == 0
    }

    /// Canonical coordinates of `points` (same numbering as the cells): `x → −x` for the points
    /// of negative regions, exact.
    pub fn canonical<const D: usize>(&self, points: &[[f64; D]]) -> Vec<[f64; D]> {
        points
            .iter()
            .zip(self.mirrored.iter().chain(core::iter::repeat(&false)))
            .map(|(p, &m)| {
                let mut q = *p;
                if m {
                    q[0] = -q[0];
                }
                q
            })
            .collect()
    }
}

fn cell_nodes(cells: &CellList, c: usize) -> &[u32] {
    let (Some(&a), Some(&b)) = (cells.offsets.get(c), cells.offsets.get(c + 1)) else {
        return &[];
    };
    cells.nodes.get(a as usize..b as usize).unwrap_or(&[])
}

/// Union–find root with path halving; deterministic (no ranks that depend on anything but order).
fn find(parent: &mut [u32], mut x: u32) -> u32 {
    while parent[x as usize] != x {
        let grand = parent[parent[x as usize] as usize];
        parent[x as usize] = grand;
        x = grand;
    }
    x
}

/// Joins the sets of `a` and `b`; the smaller root index becomes the root.
fn union(parent: &mut [u32], a: u32, b: u32) {
    let (ra, rb) = (find(parent, a), find(parent, b));
    if ra < rb {
        parent[rb as usize] = ra;
    } else if rb < ra {
        parent[ra as usize] = rb;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn two_triangles(second_clockwise: bool) -> CellList {
        let mut cells = CellList::new();
        cells.offsets = vec![0, 3, 6];
        cells.nodes = if second_clockwise {
            vec![0, 1, 2, 3, 5, 4]
        } else {
            vec![0, 1, 2, 3, 4, 5]
        };
        cells.kinds = vec![5, 5];
        cells
    }

    #[test]
    fn separate_regions_get_their_own_sense() {
        let cells = two_triangles(true);
        let o = Orientation::of(&cells, 6, &[0.5, -0.5]);
        assert_eq!(o.summary.regions, 2);
        assert_eq!(o.summary.positive_regions, 1);
        assert_eq!(o.summary.negative_regions, 1);
        assert_eq!(o.summary.cells_against_region, 0);
        assert_eq!(o.sense(0), Sense::Positive);
        assert_eq!(o.sense(4), Sense::Negative);
        let pts = [[1.5f64, 2.0]; 6];
        let c = o.canonical(&pts);
        assert_eq!(c[0], [1.5, 2.0]);
        assert_eq!(c[3], [-1.5, 2.0]);
    }

    #[test]
    fn a_minority_cell_in_a_connected_region_is_against_it() {
        let mut cells = CellList::new();
        cells.offsets = vec![0, 3, 6, 9];
        cells.nodes = vec![0, 1, 2, 1, 3, 2, 2, 3, 4];
        cells.kinds = vec![5, 5, 5];
        let o = Orientation::of(&cells, 5, &[-1.0, -1.0, 1.0]);
        assert_eq!(o.summary.regions, 1);
        assert_eq!(o.summary.negative_regions, 1);
        assert_eq!(o.summary.cells_against_region, 1);
        assert_eq!(o.summary.describe(2), "clockwise");
    }
}
