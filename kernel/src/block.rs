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

    /// Distance in the linear numbering between neighbours along `direction`: 1, `ni`, or
    /// `ni · nj`.
    #[inline]
    pub fn stride(&self, direction: Direction) -> usize {
        match direction {
            Direction::I => 1,
            Direction::J => self.dims[0],
            Direction::K => self.dims[0] * self.dims[1],
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

/// A family of grid lines of a structured block: along `i`, `j` or `k`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Direction {
    /// Along `i` (the fastest index).
    I,
    /// Along `j`.
    J,
    /// Along `k`.
    K,
}

impl Direction {
    /// `I`, `J`, `K`.
    pub const ALL: [Direction; 3] = [Direction::I, Direction::J, Direction::K];

    /// 0, 1 or 2 (the position in `[ni, nj, nk]`).
    #[inline]
    pub const fn index(self) -> usize {
        match self {
            Direction::I => 0,
            Direction::J => 1,
            Direction::K => 2,
        }
    }

    /// The direction at position 0, 1 or 2; `None` otherwise.
    #[inline]
    pub const fn from_index(index: usize) -> Option<Self> {
        match index {
            0 => Some(Direction::I),
            1 => Some(Direction::J),
            2 => Some(Direction::K),
            _ => None,
        }
    }
}

/// A set of [`Direction`]s: the directions a TFI interpolates along, the faces a smoothing
/// mirrors.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Directions {
    bits: u8,
}

impl Directions {
    /// The empty set.
    pub const NONE: Directions = Directions { bits: 0 };
    /// `I`, `J` and `K`.
    pub const ALL: Directions = Directions { bits: 0b111 };

    /// The set holding only `d`.
    #[inline]
    pub const fn only(d: Direction) -> Self {
        Directions {
            bits: 1 << d.index(),
        }
    }

    /// This set with `d` added.
    #[inline]
    #[must_use]
    pub const fn with(self, d: Direction) -> Self {
        Directions {
            bits: self.bits | (1 << d.index()),
        }
    }

    /// This set without `d`.
    #[inline]
    #[must_use]
    pub const fn without(self, d: Direction) -> Self {
        Directions {
            bits: self.bits & !(1 << d.index()),
        }
    }

    /// Whether `d` is in the set.
    #[inline]
    pub const fn contains(self, d: Direction) -> bool {
        self.bits & (1 << d.index()) != 0
    }

    /// Whether the set is empty.
    #[inline]
    pub const fn is_empty(self) -> bool {
        self.bits == 0
    }

    /// From a bit mask (bit 0 = `I`, bit 1 = `J`, bit 2 = `K`, as the C ABI's); `None` when
    /// a higher bit is set.
    #[inline]
    pub const fn from_bits(bits: u32) -> Option<Self> {
        if bits & !0b111 == 0 {
            Some(Directions { bits: bits as u8 })
        } else {
            None
        }
    }

    /// The bit mask (bit 0 = `I`, bit 1 = `J`, bit 2 = `K`).
    #[inline]
    pub const fn bits(self) -> u32 {
        self.bits as u32
    }

    /// One flag per direction, `[i, j, k]`.
    #[inline]
    pub const fn flags(self) -> [bool; 3] {
        [
            self.contains(Direction::I),
            self.contains(Direction::J),
            self.contains(Direction::K),
        ]
    }

    /// The set whose flags (`[i, j, k]`) are `flags`.
    #[inline]
    pub const fn from_flags(flags: [bool; 3]) -> Self {
        Directions {
            bits: flags[0] as u8 | (flags[1] as u8) << 1 | (flags[2] as u8) << 2,
        }
    }
}

impl From<Direction> for Directions {
    fn from(d: Direction) -> Self {
        Directions::only(d)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn directions_round_trip_through_indices_bits_and_flags() {
        for (k, d) in Direction::ALL.into_iter().enumerate() {
            assert_eq!(d.index(), k);
            assert_eq!(Direction::from_index(k), Some(d));
        }
        assert_eq!(Direction::from_index(3), None);
        for bits in 0..8u32 {
            let set = Directions::from_bits(bits).unwrap();
            assert_eq!(set.bits(), bits);
            assert_eq!(Directions::from_flags(set.flags()), set);
            for d in Direction::ALL {
                let on = bits & (1 << d.index()) != 0;
                assert_eq!(set.contains(d), on);
                assert!(set.with(d).contains(d) && !set.without(d).contains(d));
            }
            assert_eq!(set.is_empty(), bits == 0);
        }
        assert_eq!(Directions::from_bits(8), None);
        assert_eq!(Directions::from_bits(u32::MAX), None);
        assert_eq!(
            Directions::ALL,
            Directions::only(Direction::I)
                .with(Direction::J)
                .with(Direction::K)
        );
        assert_eq!(Directions::default(), Directions::NONE);
    }

    #[test]
    fn strides_follow_the_i_fastest_numbering() {
        let b = Block::new([4, 3, 2]).unwrap();
        assert_eq!(b.stride(Direction::I), 1);
        assert_eq!(b.stride(Direction::J), 4);
        assert_eq!(b.stride(Direction::K), 12);
        let p = b.index(1, 2, 1);
        assert_eq!(b.ijk(p + b.stride(Direction::I)), [2, 2, 1]);
        assert_eq!(b.ijk(p - b.stride(Direction::J)), [1, 1, 1]);
        assert_eq!(b.ijk(p - b.stride(Direction::K)), [1, 2, 0]);
    }
}
