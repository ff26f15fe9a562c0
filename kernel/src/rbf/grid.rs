//! A uniform bucket grid over a point subset for fixed-radius searches, in caller memory:
//! `offsets` (`cells + 1`) and `items` (one per point), filled by a counting sort. The cell
//! side is at least the search radius and grows (by doubling) until there are at most as many
//! cells as points, so a query visits at most `3^D` cells plus the points in them.

use crate::real::Real;

/// A built grid: borrowed offsets and items (point positions in the subset, cell by cell,
/// each cell in subset order).
pub(super) struct Grid<'a, T, const D: usize> {
    lo: [T; D],
    h: T,
    dims: [usize; D],
    offsets: &'a [u32],
    items: &'a [u32],
}

/// `u32`s a grid over `n` points needs: `n + 2` offsets (at least two) and `n` items.
pub(super) const fn grid_len(n: usize) -> usize {
    n.saturating_mul(2).saturating_add(2)
}

/// Cell coordinate of `v` along an axis (clamped into `-1 ..= dims`, so far points stay
/// outside without overflow).
fn cell_of<T: Real>(v: T, lo: T, h: T, dims: usize) -> i64 {
    let c = ((v - lo) / h)
        .floor()
        .clamp_to(-T::ONE, T::from_usize(dims));
    c.to_f64() as i64
}

impl<'a, T: Real, const D: usize> Grid<'a, T, D> {
    /// Builds the grid over `pos(0) … pos(n−1)` (finite) for searches of radius `radius > 0`
    /// into `buf` ([`grid_len`]`(n)` entries at least).
    pub(super) fn build(
        n: usize,
        radius: T,
        pos: impl Fn(usize) -> [T; D],
        buf: &'a mut [u32],
    ) -> Self {
        let (lo, hi) = super::model::bounds((0..n).map(&pos));
        let mut h = radius;
        let dims = loop {
            if !h.is_finite() {
                // Coordinates beyond the floating-point range of a cell side: one cell.
                break [1usize; D];
            }
            let mut dims = [1usize; D];
            let mut cells = 1usize;
            for a in 0..D {
                let span = ((hi[a] - lo[a]) / h).floor();
                dims[a] = if span < T::from_usize(n) {
                    span.to_f64() as usize + 1
                } else {
                    n + 1
                };
                cells = cells.saturating_mul(dims[a]);
            }
            if cells <= n.max(1) {
                break dims;
            }
            h *= T::TWO;
        };
        let cells = dims
            .iter()
            .fold(1usize, |c, &d| c.saturating_mul(d))
            .min(n.max(1));
        let (offsets, rest) = buf.split_at_mut((cells + 1).min(buf.len()));
        let items = rest.get_mut(..n).unwrap_or(&mut []);
        let mut g = Grid {
            lo,
            h,
            dims,
            offsets: &[],
            items: &[],
        };
        offsets.iter_mut().for_each(|o| *o = 0);
        for i in 0..n {
            if let Some(o) = offsets.get_mut(g.cell(pos(i)) + 1) {
                *o += 1;
            }
        }
        for c in 1..offsets.len() {
            let prev = offsets.get(c - 1).copied().unwrap_or(0);
            if let Some(o) = offsets.get_mut(c) {
                *o += prev;
            }
        }
        // Place each point at its cell's next free slot (`offsets[c]` runs ahead, then is
        // shifted back by one cell).
        for i in 0..n {
            let c = g.cell(pos(i));
            if let Some(o) = offsets.get_mut(c) {
                if let Some(slot) = items.get_mut(*o as usize) {
                    *slot = i as u32;
                }
                *o += 1;
            }
        }
        for c in (1..offsets.len()).rev() {
            let prev = offsets.get(c - 1).copied().unwrap_or(0);
            if let Some(o) = offsets.get_mut(c) {
                *o = prev;
            }
        }
        if let Some(o) = offsets.first_mut() {
            *o = 0;
        }
        g.offsets = offsets;
        g.items = items;
        g
    }

    /// Linear cell index of a point inside the grid's box.
    fn cell(&self, p: [T; D]) -> usize {
        let mut c = 0usize;
        for a in (0..D).rev() {
            // max/min, not `Ord::clamp` (whose bound assertion would be a panic path).
            let k = cell_of(p[a], self.lo[a], self.h, self.dims[a])
                .min(self.dims[a] as i64 - 1)
                .max(0);
            c = c * self.dims[a] + k as usize;
        }
        c
    }

    /// Calls `f` with every point (subset position) in the cells that meet the ball of
    /// radius `r` about `x` (a superset of the points within `r`; the caller tests distance).
    pub(super) fn for_near(&self, x: [T; D], r: T, mut f: impl FnMut(usize)) {
        if self.dims.iter().all(|&d| d == 1) {
            // One cell: every point (no cell arithmetic that could round or overflow).
            self.items.iter().for_each(|&i| f(i as usize));
            return;
        }
        let mut from = [0usize; D];
        let mut to = [0usize; D];
        for a in 0..D {
            let lo = cell_of(x[a] - r, self.lo[a], self.h, self.dims[a]);
            let hi = cell_of(x[a] + r, self.lo[a], self.h, self.dims[a]);
            if hi < 0 || lo >= self.dims[a] as i64 {
                return;
            }
            from[a] = lo.max(0) as usize;
            to[a] = (hi as usize).min(self.dims[a] - 1);
        }
        let mut at = from;
        loop {
            let mut c = 0usize;
            for a in (0..D).rev() {
                c = c * self.dims[a] + at[a];
            }
            let s = self.offsets.get(c).copied().unwrap_or(0) as usize;
            let e = self.offsets.get(c + 1).copied().unwrap_or(0) as usize;
            for &i in self.items.get(s..e).unwrap_or(&[]) {
                f(i as usize);
            }
            // Next cell of the box, first axis fastest.
            let mut a = 0;
            loop {
                if a == D {
                    return;
                }
                if at[a] < to[a] {
                    at[a] += 1;
                    break;
                }
                at[a] = from[a];
                a += 1;
            }
        }
    }
}
