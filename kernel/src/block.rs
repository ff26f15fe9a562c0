//! Structured blocks: dimensions `[ni, nj, nk]` and the point numbering `i + ni (j + nj k)`
//! (i fastest: Plot3D and Fortran order). A 2D block has `nk = 1`, a 1D block `nj = nk = 1`.

use crate::error::{Error, Result};

/// Validated dimensions of a structured block (every dimension ≥ 1, the point count fits in
/// `u32`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Block {
    dims: [usize; 3],
}

impl Block {
    /// Validates `[ni, nj, nk]`.
    ///
    /// # Errors
    /// A zero dimension, or more than `u32::MAX` points ([`Error::BadDimensions`]).
    pub fn new(dims: [usize; 3]) -> Result<Self> {
        if dims.contains(&0) {
            return Err(Error::BadDimensions { arg: "dims" });
        }
        let n = dims[0]
            .checked_mul(dims[1])
            .and_then(|p| p.checked_mul(dims[2]))
            .ok_or(Error::BadDimensions { arg: "dims" })?;
        if u32::try_from(n).is_err() {
            return Err(Error::BadDimensions { arg: "dims" });
        }
        Ok(Block { dims })
    }

    /// `[ni, nj, nk]`.
    #[inline]
    pub fn dims(&self) -> [usize; 3] {
        self.dims
    }

    /// `ni · nj · nk`.
    #[inline]
    pub fn point_count(&self) -> usize {
        self.dims[0] * self.dims[1] * self.dims[2]
    }

    /// Number of dimensions larger than one (0 for a single point).
    #[inline]
    pub fn rank(&self) -> usize {
        self.dims.iter().filter(|&&d| d > 1).count()
    }

    /// Linear index of `(i, j, k)`: `i + ni (j + nj k)`. The caller keeps the indices in range.
    #[inline]
    pub fn index(&self, i: usize, j: usize, k: usize) -> usize {
        i + self.dims[0] * (j + self.dims[1] * k)
    }

    /// Distance in the linear numbering between neighbours along `direction` (0 = i, 1 = j,
    /// 2 = k): 1, `ni`, or `ni · nj`.
    #[inline]
    pub fn stride(&self, direction: usize) -> usize {
        match direction {
            0 => 1,
            1 => self.dims[0],
            _ => self.dims[0] * self.dims[1],
        }
    }

    /// `(i, j, k)` of a linear index.
    #[inline]
    pub fn ijk(&self, index: usize) -> [usize; 3] {
        let ni = self.dims[0];
        let nj = self.dims[1];
        // Dimensions are validated to be >= 1, so these divisions cannot be by zero; `max(1)`
        // makes that visible to the optimiser.
        let i = index % ni.max(1);
        let rest = index / ni.max(1);
        [i, rest % nj.max(1), rest / nj.max(1)]
    }
}
