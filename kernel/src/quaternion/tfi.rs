//! Transfinite interpolation (TFI) on structured blocks with arclength blending (Soni).

use crate::block::{Block, Directions};
use crate::check;
use crate::error::{Error, Result};
use crate::quat::Quat;
use crate::real::Real;
use crate::vector::distance;

/// Length of the `scratch` slice [`propagate_tfi`] and [`displacement_tfi`] need: `D` per
/// block point (the normalised arclength of each point along its grid line in each direction).
#[inline]
pub fn tfi_scratch_len<const D: usize>(block: &Block) -> usize {
    block.point_count().saturating_mul(D)
}

/// At most 26 terms: 6 faces, 12 edges, 8 corners.
pub(super) const MAX_TERMS: usize = 26;

/// Validated TFI setup: block, active-direction bit mask.
pub(super) struct Setup {
    dims: [usize; 3],
    pub(super) n: usize,
    active: usize,
}

/// Checks the block shape and the active directions for `D` (no sizes).
pub(super) fn check_directions<const D: usize>(
    block: &Block,
    directions: Directions,
) -> Result<()> {
    check::mesh_dim::<D>();
    let directions = directions.flags();
    let dims = block.dims();
    if D == 2 && dims[2] != 1 {
        return Err(Error::BadDimensions { arg: "block" });
    }
    let mut any = false;
    for (d, (&on, &nd)) in directions.iter().zip(dims.iter()).enumerate() {
        if on {
            if d >= D || nd < 2 {
                return Err(Error::InvalidParameter {
                    arg: "directions",
                    reason: "an active direction must be a block direction with at least 2 points",
                });
            }
            any = true;
        }
    }
    if !any {
        return Err(Error::InvalidParameter {
            arg: "directions",
            reason: "at least one direction must be active",
        });
    }
    Ok(())
}

/// Validates the block, the directions and the sizes common to both TFI routines.
pub(super) fn setup<T: Real, const D: usize>(
    block: &Block,
    directions: Directions,
    points: &[[T; D]],
    values_len: usize,
    values_arg: &'static str,
    scratch_len: usize,
) -> Result<Setup> {
    check_directions::<D>(block, directions)?;
    let directions = directions.flags();
    let dims = block.dims();
    let n = block.point_count();
    let mut active = 0usize;
    for (d, &on) in directions.iter().enumerate() {
        if on {
            active |= 1 << d;
        }
    }
    check::len("points", points.len(), n)?;
    check::len(values_arg, values_len, n)?;
    check::buffer("scratch", scratch_len, tfi_scratch_len::<D>(block))?;
    check::finite_items("points", points)?;
    Ok(Setup { dims, n, active })
}

impl Setup {
    /// `(i, j, k)` of a linear index.
    #[inline]
    pub(super) fn ijk(&self, p: usize) -> [usize; 3] {
        let ni = self.dims[0].max(1);
        let nj = self.dims[1].max(1);
        [p % ni, (p / ni) % nj, p / ni / nj]
    }

    /// Linear index of `(i, j, k)`.
    #[inline]
    fn index(&self, c: [usize; 3]) -> usize {
        c[0] + self.dims[0] * (c[1] + self.dims[1] * c[2])
    }

    /// `true` when `p` lies on a face of an active direction (its value is given).
    #[inline]
    pub(super) fn on_face(&self, c: [usize; 3]) -> bool {
        c.iter()
            .zip(self.dims.iter())
            .enumerate()
            .any(|(d, (&x, &nd))| self.active & (1 << d) != 0 && (x == 0 || x + 1 == nd))
    }

    /// Normalised arclength (from the undeformed points) of every point along its grid line
    /// in each active direction, into `params[d · n + p]`. A zero-length line gets the uniform
    /// parameter `m / (n_d − 1)`.
    pub(super) fn arclength<T: Real, const D: usize>(&self, points: &[[T; D]], params: &mut [T]) {
        for d in 0..3 {
            if self.active & (1 << d) == 0 {
                continue;
            }
            let nd = self.dims.get(d).copied().unwrap_or(1);
            let stride = match d {
                0 => 1,
                1 => self.dims[0],
                _ => self.dims[0] * self.dims[1],
            };
            let at = |p: usize| points.get(p).copied().unwrap_or([T::ZERO; D]);
            for start in 0..self.n {
                if self.ijk(start).get(d) != Some(&0) {
                    continue;
                }
                let mut total = T::ZERO;
                for m in 1..nd {
                    let p = start + m * stride;
                    total += distance(at(p), at(p - stride));
                }
                let uniform = !(total.is_finite() && total > T::ZERO);
                let last = T::from_usize(nd - 1);
                let mut cum = T::ZERO;
                for m in 0..nd {
                    let p = start + m * stride;
                    if m > 0 {
                        cum += distance(at(p), at(p - stride));
                    }
                    let s = if uniform {
                        T::from_usize(m) / last
                    } else {
                        cum / total
                    };
                    if let Some(x) = params.get_mut(d * self.n + p) {
                        *x = s;
                    }
                }
            }
        }
    }

    /// The boolean-sum terms `(node, coefficient)` of interior point `p`: for every non-empty
    /// subset `S` of the active directions, sign `(−1)^(|S|+1)` times the tensor-product
    /// projector over `S` (weights `1 − s_d` at the low face, `s_d` at the high face). Returns
    /// the number of terms written.
    pub(super) fn terms<T: Real>(
        &self,
        p: usize,
        params: &[T],
        out: &mut [(usize, T); MAX_TERMS],
    ) -> usize {
        let c = self.ijk(p);
        let mut s = [T::ZERO; 3];
        for (d, x) in s.iter_mut().enumerate() {
            *x = params.get(d * self.n + p).copied().unwrap_or(T::ZERO);
        }
        let mut count = 0;
        for mask in 1..8usize {
            if mask & !self.active != 0 {
                continue;
            }
            let sign = if mask.count_ones() % 2 == 1 {
                T::ONE
            } else {
                -T::ONE
            };
            for corner in 0..8usize {
                if corner & !mask != 0 {
                    continue;
                }
                let mut w = sign;
                let mut q = c;
                for d in 0..3 {
                    if mask & (1 << d) == 0 {
                        continue;
                    }
                    let high = corner & (1 << d) != 0;
                    let sd = s.get(d).copied().unwrap_or(T::ZERO);
                    w *= if high { sd } else { T::ONE - sd };
                    if let Some(x) = q.get_mut(d) {
                        *x = if high {
                            self.dims.get(d).copied().unwrap_or(1) - 1
                        } else {
                            0
                        };
                    }
                }
                if let Some(slot) = out.get_mut(count) {
                    *slot = (self.index(q), w);
                    count += 1;
                }
            }
        }
        count
    }
}

/// Checks the given (face) values for finiteness.
fn check_face_values<T: Real, const V: usize>(
    s: &Setup,
    arg: &'static str,
    values: &[[T; V]],
) -> Result<()> {
    for (position, v) in values.iter().enumerate() {
        if s.on_face(s.ijk(position)) && !v.iter().all(|x| x.is_finite()) {
            return Err(Error::NonFinite { arg, position });
        }
    }
    Ok(())
}

/// Blends `D`-vectors at an interior point.
#[inline]
fn blend_vec<T: Real, const D: usize>(terms: &[(usize, T)], values: &[[T; D]]) -> [T; D] {
    let mut r = [T::ZERO; D];
    for &(node, w) in terms {
        if let Some(v) = values.get(node) {
            for (a, b) in r.iter_mut().zip(v) {
                *a += w * *b;
            }
        }
    }
    r
}

/// Blends quaternions at an interior point (hemisphere-aligned to the first term's), then
/// normalises.
#[inline]
fn blend_quat<T: Real>(terms: &[(usize, T)], values: &[Quat<T>]) -> Result<Quat<T>> {
    let reference = terms
        .first()
        .and_then(|&(node, _)| values.get(node))
        .copied()
        .unwrap_or(Quat::identity());
    let mut r = Quat::new(T::ZERO, T::ZERO, T::ZERO, T::ZERO);
    for &(node, w) in terms {
        if let Some(&q) = values.get(node) {
            let q = if q.dot(reference) < T::ZERO { -q } else { q };
            r = r + q.scale(w);
        }
    }
    r.normalize()
}

/// Transfinite interpolation of the translations `Δ` and rotations `Q` of a structured block
/// from its faces into its interior: the boolean sum of the linear projectors of the active
/// `directions` (2D: `P_i ⊕ P_j = P_i + P_j − P_i P_j`; 3D: the trilinear sum of faces minus
/// edges plus corners), with Soni's arclength blending: the weight of a point along direction
/// `d` is its normalised arclength along its own undeformed grid line. Quaternions are
/// hemisphere-aligned to a common reference per point before blending and renormalised after.
///
/// Values are read on the faces of the active directions (index 0 or `n_d − 1` in an active
/// direction) and written everywhere else. Activate only the directions whose faces carry
/// known motion: for an O-grid, `Directions::only(Direction::J)` interpolates between the
/// wall (`j = 0`) and the far field along the radial lines and ignores the cut. Boundary values are
/// reproduced exactly (they are never written); a uniform `(Δ, Q)` is reproduced to rounding.
///
/// `points` are the undeformed block points (`i` fastest), 2D blocks have `nk = 1`. `scratch`
/// needs [`tfi_scratch_len`] entries (contents unspecified afterwards).
///
/// # Errors
/// Bad dimensions or directions, length mismatches, non-finite points or face values,
/// zero face rotations, or (rare) a blended rotation that cancels to zero
/// ([`Error::ZeroLength`], `"rotations"`, position = point). On error the values are unchanged.
pub fn propagate_tfi<T: Real, const D: usize>(
    block: &Block,
    directions: Directions,
    points: &[[T; D]],
    translations: &mut [[T; D]],
    rotations: &mut [Quat<T>],
    scratch: &mut [T],
) -> Result<()> {
    let s = setup(
        block,
        directions,
        points,
        translations.len(),
        "translations",
        scratch.len(),
    )?;
    check::len("rotations", rotations.len(), s.n)?;
    check_face_values(&s, "translations", translations)?;
    for (position, q) in rotations.iter().enumerate() {
        if s.on_face(s.ijk(position)) {
            if !q.is_finite() {
                return Err(Error::NonFinite {
                    arg: "rotations",
                    position,
                });
            }
            if q.normalize().is_err() {
                return Err(Error::ZeroLength {
                    arg: "rotations",
                    position,
                });
            }
        }
    }
    s.arclength(points, scratch);
    let mut terms = [(0usize, T::ZERO); MAX_TERMS];
    // Dry run: every blended rotation must normalise before anything is written.
    for p in 0..s.n {
        if s.on_face(s.ijk(p)) {
            continue;
        }
        let m = s.terms(p, scratch, &mut terms);
        if blend_quat(terms.get(..m).unwrap_or(&[]), rotations).is_err() {
            return Err(Error::ZeroLength {
                arg: "rotations",
                position: p,
            });
        }
    }
    for p in 0..s.n {
        if s.on_face(s.ijk(p)) {
            continue;
        }
        let m = s.terms(p, scratch, &mut terms);
        let t = terms.get(..m).unwrap_or(&[]);
        let q = blend_quat(t, rotations).unwrap_or(Quat::identity());
        let v = blend_vec(t, translations);
        if let Some(x) = translations.get_mut(p) {
            *x = v;
        }
        if let Some(x) = rotations.get_mut(p) {
            *x = q;
        }
    }
    Ok(())
}

/// Plain displacement TFI (for comparison with [`propagate_tfi`], and for callers who want
/// it): the same arclength-blended boolean sum applied to displacements `δ = r^d − r^u`
/// (Samareh eq. 1) given on the faces of the active directions. New points are
/// `r^u + δ`. It reproduces translations but shears cells under rotation.
///
/// # Errors
/// As for [`propagate_tfi`]; on error `displacements` is unchanged.
pub fn displacement_tfi<T: Real, const D: usize>(
    block: &Block,
    directions: Directions,
    points: &[[T; D]],
    displacements: &mut [[T; D]],
    scratch: &mut [T],
) -> Result<()> {
    let s = setup(
        block,
        directions,
        points,
        displacements.len(),
        "displacements",
        scratch.len(),
    )?;
    check_face_values(&s, "displacements", displacements)?;
    s.arclength(points, scratch);
    let mut terms = [(0usize, T::ZERO); MAX_TERMS];
    for p in 0..s.n {
        if s.on_face(s.ijk(p)) {
            continue;
        }
        let m = s.terms(p, scratch, &mut terms);
        let v = blend_vec(terms.get(..m).unwrap_or(&[]), displacements);
        if let Some(x) = displacements.get_mut(p) {
            *x = v;
        }
    }
    Ok(())
}
