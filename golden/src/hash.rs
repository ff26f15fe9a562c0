//! FNV-1a-64 over output bit patterns.

use deform_kernel::{Error, Quat, Real};

/// FNV-1a 64-bit offset basis.
const OFFSET_BASIS: u64 = 0xcbf2_9ce4_8422_2325;
/// FNV-1a 64-bit prime.
const PRIME: u64 = 0x0000_0100_0000_01b3;

/// An FNV-1a-64 hasher. Multi-byte values are fed little-endian, so the hash does not depend
/// on the platform's byte order.
#[derive(Clone, Copy, Debug)]
pub struct Fnv(u64);

impl Default for Fnv {
    fn default() -> Self {
        Fnv::new()
    }
}

impl Fnv {
    /// A fresh hasher (state = the FNV offset basis).
    pub const fn new() -> Self {
        Fnv(OFFSET_BASIS)
    }

    /// Feeds one byte.
    #[inline]
    pub fn byte(&mut self, b: u8) {
        self.0 ^= b as u64;
        self.0 = self.0.wrapping_mul(PRIME);
    }

    /// Feeds a byte string.
    pub fn bytes(&mut self, bs: &[u8]) {
        for &b in bs {
            self.byte(b);
        }
    }

    /// Feeds a `u32` (4 bytes, little-endian).
    pub fn u32(&mut self, x: u32) {
        self.bytes(&x.to_le_bytes());
    }

    /// Feeds a `u64` (8 bytes, little-endian).
    pub fn u64(&mut self, x: u64) {
        self.bytes(&x.to_le_bytes());
    }

    /// Feeds a `usize` as a `u64`.
    pub fn usize(&mut self, x: usize) {
        self.u64(x as u64);
    }

    /// Feeds a scalar's bit pattern (`to_bits`, widened to `u64`).
    pub fn real<T: Real>(&mut self, x: T) {
        self.u64(x.to_bits_u64());
    }

    /// Feeds every component of a small array.
    pub fn reals<T: Real, const N: usize>(&mut self, v: [T; N]) {
        for x in v {
            self.real(x);
        }
    }

    /// Feeds a slice of `u32` indices.
    pub fn u32s(&mut self, v: &[u32]) {
        self.usize(v.len());
        for &x in v {
            self.u32(x);
        }
    }

    /// Feeds the four components of a quaternion, `w` first.
    pub fn quat<T: Real>(&mut self, q: Quat<T>) {
        self.reals(q.to_array());
    }

    /// Feeds an error: a tag byte and the variant's [`error_code`].
    pub fn error(&mut self, e: &Error) {
        self.byte(0xEE);
        self.u32(error_code(e));
    }

    /// Feeds a `Result` of a quaternion: tag 1 and the components, or the error.
    pub fn result_quat<T: Real>(&mut self, r: deform_kernel::Result<Quat<T>>) {
        match r {
            Ok(q) => {
                self.byte(1);
                self.quat(q);
            }
            Err(e) => self.error(&e),
        }
    }

    /// The hash of everything fed so far.
    pub fn finish(&self) -> u64 {
        self.0
    }
}

/// A stable number per error variant (new variants map to 0 until listed here; listing one
/// changes the hashes of cases that produce it, which is then a deliberate update).
pub fn error_code(e: &Error) -> u32 {
    match e {
        Error::LengthMismatch { .. } => 1,
        Error::BufferTooSmall { .. } => 2,
        Error::IndexOutOfRange { .. } => 3,
        Error::TooLarge { .. } => 4,
        Error::BadOffsets { .. } => 5,
        Error::SelfLoop { .. } => 6,
        Error::NotSymmetric { .. } => 7,
        Error::UnknownCellKind { .. } => 8,
        Error::WrongNodeCount { .. } => 9,
        Error::RepeatedNode { .. } => 10,
        Error::NonFinite { .. } => 11,
        Error::InvalidParameter { .. } => 12,
        Error::ZeroLength { .. } => 13,
        Error::ZeroLengthEdge { .. } => 14,
        Error::SingularNode { .. } => 15,
        Error::SingularSystem { .. } => 16,
        Error::Unanchored { .. } => 17,
        Error::FoldedLine { .. } => 18,
        Error::BadDimensions { .. } => 19,
        Error::IsolatedNode { .. } => 20,
        Error::DuplicateNode { .. } => 21,
        Error::NonPositive { .. } => 22,
        _ => 0,
    }
}
