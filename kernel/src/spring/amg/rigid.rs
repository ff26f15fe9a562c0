//! Smoothed aggregation for linear elasticity with the rigid-body modes as near-null space
//! (pyamg's `smoothed_aggregation_solver(A, B=rigid_modes)`): the vector problem is coarsened
//! as a whole, `D` unknowns per fine node and `K = D(D+1)/2` per aggregate (3 in 2D, 6 in 3D).
//!
//! - **Structure**: the aggregates, prolongator and Galerkin sparsity of the scalar hierarchy
//!   of a [`SpringSystem`] on the same graph and fixed mask (its symbolic pass, θ = 0: every
//!   connection strong), now with one `b × K` block per prolongator entry and one `K × K`
//!   block per coarse entry.
//! - **Tentative prolongator**: on each aggregate the rigid-body modes `B` (translations and
//!   rotations about the mesh centre) are orthonormalised by modified Gram–Schmidt, `B = Q R`;
//!   `T = Q`, and `R` is the next level's near-null space (pyamg's `fit_candidates`). A mode
//!   that is dependent on an aggregate (fewer unknowns than modes) gives a zero column: that
//!   coarse unknown is inactive (zero row and column, skipped by the smoother, unit pivot in
//!   the dense coarsest solve).
//! - **Smoothed prolongator** `P = (I − ω D⁻¹ A) T` with the point diagonal `D` and
//!   `ω = (4/3)/ρ`, `ρ` the Gershgorin bound of `ρ(D⁻¹A)`; Galerkin `Pᵀ A P`, symmetrised
//!   exactly; the coarsest level by dense Cholesky.
//! - **V-cycle** ([`rigid_cycle`](super::rigid_cycle)): point-Jacobi or Chebyshev smoothing as
//!   the scalar hierarchy's, the same before and after (symmetric, so CG stays valid).
//!
//! Every sum runs in a fixed order given by the structure: the same bits on every platform.

use super::{seg, seg_mut, setup, AmgOptions, Layout, AMG_MAX_LEVELS, AMG_MAX_SWEEPS};
use crate::check;
use crate::error::{Error, Result};
use crate::graph::Graph;
use crate::real::Real;
use crate::spring::system::SpringSystem;

/// Largest block: the six rigid-body modes of 3D.
pub(crate) const MAX_B: usize = 6;

/// Rigid-body modes of dimension `d` (3 in 2D, 6 in 3D; 0 otherwise).
pub const fn rigid_mode_count(d: usize) -> usize {
    match d {
        2 => 3,
        3 => 6,
        _ => 0,
    }
}

/// Exact buffer sizes of a rigid-mode hierarchy ([`RigidAmg::setup_len`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RigidAmgSizes {
    /// `u32` entries of the `index` buffer.
    pub index: usize,
    /// `T` entries of the `values` buffer.
    pub values: usize,
    /// Number of levels (1 = the smoother alone).
    pub levels: usize,
    /// Scalar unknowns on all coarse levels together (the V-cycle needs three vectors of them).
    pub coarse_scalars: usize,
}

/// Where the values of each level live (offsets into `values`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct Values {
    /// Prolongator blocks `b_l × K` of level `l` (levels below the last).
    pub p: [usize; AMG_MAX_LEVELS],
    /// Diagonal blocks `K × K` (levels ≥ 1).
    pub diag: [usize; AMG_MAX_LEVELS],
    /// Off-diagonal blocks `K × K` (levels ≥ 1).
    pub a: [usize; AMG_MAX_LEVELS],
    /// Point diagonal, `n_l b_l` scalars.
    pub pd: [usize; AMG_MAX_LEVELS],
    /// Near-null space `B_l`, `n_l` blocks `b_l × K`.
    pub modes: [usize; AMG_MAX_LEVELS],
    /// Tentative prolongator of the level being built (`max n_l b_l K`).
    pub t: usize,
    /// Accumulator (`acc_len K²`).
    pub acc: usize,
    /// Dense coarsest factor (`dense_n²`).
    pub dense: usize,
    /// Scalar size of the dense coarsest factor (0: the coarsest level is smoothed).
    pub dense_n: usize,
    /// Entries used.
    pub len: usize,
}

/// The fine operator: `D × D` blocks of the elasticity stiffness, flattened row-major, one per
/// node (`diag`) and one per directed edge of `graph` (`off`), with the fixed mask.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Fine<'s, T> {
    pub graph: Graph<'s>,
    pub diag: &'s [T],
    pub off: &'s [T],
    pub fixed: &'s [u8],
    pub d: usize,
    /// Sliding nodes (kind codes and flattened directions of
    /// [`Constraints`](crate::spring::constraints::Constraints)): the hierarchy is built for
    /// `K + s Σ N_i`, with `N_i` the projector across node `i`'s allowed motion and `s` its
    /// diagonal block's mean diagonal entry, whose inverse approaches the constrained
    /// operator's on the allowed motions.
    pub slide: Option<(&'s [u8], &'s [T])>,
}

impl<T: Real> Fine<'_, T> {
    #[inline]
    pub fn is_fixed(&self, i: usize) -> bool {
        self.fixed
            .get(i)
            .is_some_and(|&m| crate::spring::is_fixed(m))
    }

    /// `blk += s N_i` at a sliding node (`N = n nᵀ/|n|²` on a plane, `I − t tᵀ/|t|²` on a
    /// line); nothing elsewhere.
    pub fn add_slide(&self, i: usize, blk: &mut [T]) {
        let Some((kinds, dirs)) = self.slide else {
            return;
        };
        let d = self.d;
        let kind = kinds.get(i).copied().unwrap_or(0);
        let v = seg(dirs, i * d, d);
        let vv = v.iter().fold(T::ZERO, |s, &x| s + x * x);
        if (kind != 2 && kind != 3) || vv <= T::ZERO || !vv.is_finite() {
            return;
        }
        let tr = (0..d).fold(T::ZERO, |s, r| s + get(blk, r * d + r));
        let s = tr * T::from_f64(10.0) / T::from_usize(d);
        for r in 0..d {
            for c in 0..d {
                let nn = get(v, r) * get(v, c) / vv;
                let m = match (kind, r == c) {
                    (2, _) => nn,
                    (_, true) => T::ONE - nn,
                    _ => -nn,
                };
                if let Some(o) = blk.get_mut(r * d + c) {
                    *o += s * m;
                }
            }
        }
    }
}

/// A smoothed-aggregation hierarchy of the elasticity operator with the rigid-body modes as
/// near-null space, in caller buffers: the preconditioner of
/// [`ElasticSystem::solve_rigid_amg`](crate::elasticity::ElasticSystem::solve_rigid_amg).
#[derive(Clone, Copy, Debug)]
pub struct RigidAmg<'a, T: Real> {
    pub(crate) layout: Layout,
    pub(crate) vals: Values,
    pub(crate) d: usize,
    pub(crate) k: usize,
    pub(crate) weights: [[T; AMG_MAX_SWEEPS]; AMG_MAX_LEVELS],
    pub(crate) sweeps: usize,
    pub(crate) index: &'a [u32],
    pub(crate) values: &'a [T],
}

/// Block size of level `l`.
#[inline]
pub(crate) fn block(d: usize, k: usize, l: usize) -> usize {
    if l == 0 {
        d
    } else {
        k
    }
}

/// The values layout of a structure (`None` on overflow).
fn values_layout(layout: &Layout, d: usize, k: usize) -> Option<Values> {
    let mut v = Values::default();
    let mut vc = 0usize;
    let bump = |vc: &mut usize, len: usize| -> Option<usize> {
        let at = *vc;
        *vc = vc.checked_add(len)?;
        Some(at)
    };
    let mut tmax = 0usize;
    // Per level: its own blocks, point diagonal and modes, then its prolongator (so the
    // numeric pass reads everything below the prolongator while it writes above).
    for l in 0..layout.count {
        let lv = layout.level(l);
        let b = block(d, k, l);
        let bk = b.checked_mul(k)?;
        if l >= 1 {
            *v.diag.get_mut(l)? = bump(&mut vc, lv.n.checked_mul(k * k)?)?;
            *v.a.get_mut(l)? = bump(&mut vc, lv.a_nnz.checked_mul(k * k)?)?;
        }
        *v.pd.get_mut(l)? = bump(&mut vc, lv.n.checked_mul(b)?)?;
        *v.modes.get_mut(l)? = bump(&mut vc, lv.n.checked_mul(bk)?)?;
        tmax = tmax.max(lv.n.checked_mul(bk)?);
        if l + 1 < layout.count {
            *v.p.get_mut(l)? = bump(&mut vc, lv.p_nnz.checked_mul(bk)?)?;
        }
    }
    v.t = bump(&mut vc, tmax)?;
    v.acc = bump(&mut vc, layout.acc_len.checked_mul(k * k)?)?;
    if layout.dense_n > 0 {
        v.dense_n = layout.dense_n.checked_mul(k)?;
        v.dense = bump(&mut vc, v.dense_n.checked_mul(v.dense_n)?)?;
    }
    v.len = vc;
    Some(v)
}

impl<'a, T: Real> RigidAmg<'a, T> {
    /// The symbolic pass for `D`-dimensional elasticity (`dim` 2 or 3) on the graph and fixed
    /// mask of `spring` (its weights are not used): the exact buffer sizes. `work` needs
    /// [`AmgHierarchy::setup_work_len`](super::AmgHierarchy::setup_work_len) entries.
    ///
    /// # Errors
    /// Those of [`AmgHierarchy::setup_len`](super::AmgHierarchy::setup_len); `dim` not 2 or 3
    /// ([`Error::InvalidParameter`]); sizes that overflow ([`Error::TooLarge`]).
    pub fn setup_len(
        spring: &SpringSystem<'_, T>,
        dim: usize,
        options: &AmgOptions<T>,
        work: &mut [u32],
    ) -> Result<RigidAmgSizes> {
        let (layout, vals) = Self::symbolic(spring, dim, options, work)?;
        let k = rigid_mode_count(dim);
        let coarse = (1..layout.count).fold(0usize, |s, l| {
            s.saturating_add(layout.level(l).n.saturating_mul(k))
        });
        Ok(RigidAmgSizes {
            index: layout.index_len,
            values: vals.len,
            levels: layout.count,
            coarse_scalars: coarse,
        })
    }

    fn symbolic(
        spring: &SpringSystem<'_, T>,
        dim: usize,
        options: &AmgOptions<T>,
        work: &mut [u32],
    ) -> Result<(Layout, Values)> {
        let k = rigid_mode_count(dim);
        if k == 0 {
            return Err(Error::InvalidParameter {
                arg: "dim",
                reason: "must be 2 or 3",
            });
        }
        let opts = AmgOptions {
            strength_theta: T::ZERO,
            ..*options
        };
        let layout = setup::symbolic(spring, &opts, work)?;
        let vals = values_layout(&layout, dim, k).ok_or(Error::TooLarge {
            arg: "hierarchy",
            value: layout.index_len,
        })?;
        Ok((layout, vals))
    }

    /// Builds the hierarchy of `fine` (the elasticity blocks) with the rigid-body modes of
    /// `points` (flattened, `dim` coordinates per node), into `index` and `values` of at least
    /// the [`RigidAmgSizes`] of [`setup_len`](Self::setup_len).
    ///
    /// # Errors
    /// Those of [`setup_len`](Self::setup_len); a fixed mask or graph other than `spring`'s
    /// ([`Error::InvalidParameter`], [`Error::LengthMismatch`]); short buffers
    /// ([`Error::BufferTooSmall`], nothing written); a coarse operator that is not positive
    /// definite in floating point ([`Error::SingularSystem`], `iteration: 0`).
    pub(crate) fn setup(
        fine: &Fine<'_, T>,
        spring: &SpringSystem<'_, T>,
        points: &[T],
        options: &AmgOptions<T>,
        work: &mut [u32],
        index: &'a mut [u32],
        values: &'a mut [T],
    ) -> Result<Self> {
        let n = fine.graph.node_count();
        check::len("spring", spring.node_count(), n)?;
        check::len(
            "spring",
            spring.graph().edge_count(),
            fine.graph.edge_count(),
        )?;
        check::len("points", points.len(), n.saturating_mul(fine.d))?;
        if (0..n).any(|i| spring.is_fixed(i) != fine.is_fixed(i)) {
            return Err(Error::InvalidParameter {
                arg: "spring",
                reason: "must have the same fixed nodes",
            });
        }
        let (layout, vals) = Self::symbolic(spring, fine.d, options, work)?;
        check::buffer("index", index.len(), layout.index_len)?;
        check::buffer("values", values.len(), vals.len)?;
        let index = index.get_mut(..layout.index_len).unwrap_or(&mut []);
        let values = values.get_mut(..vals.len).unwrap_or(&mut []);
        for (d, &s) in index.iter_mut().zip(work.iter()) {
            *d = s;
        }
        let mut h = RigidAmg {
            layout,
            vals,
            d: fine.d,
            k: rigid_mode_count(fine.d),
            weights: [[T::ZERO; AMG_MAX_SWEEPS]; AMG_MAX_LEVELS],
            sweeps: options.sweeps,
            index: &[],
            values: &[],
        };
        let rho = super::rigid_numeric::numeric(&h, fine, points, index, values)?;
        h.weights = setup::smoothing_weights(&rho, options.smoother, options.sweeps);
        h.index = index;
        h.values = values;
        Ok(h)
    }

    /// Number of levels.
    #[inline]
    pub fn levels(&self) -> usize {
        self.layout.count
    }

    /// Scalar unknowns on level `l` (0 beyond the last).
    pub fn level_unknowns(&self, l: usize) -> usize {
        if l < self.layout.count {
            self.layout
                .level(l)
                .n
                .saturating_mul(block(self.d, self.k, l))
        } else {
            0
        }
    }

    /// Scalar unknowns on all coarse levels.
    pub fn coarse_scalars(&self) -> usize {
        (1..self.layout.count).fold(0usize, |s, l| s.saturating_add(self.level_unknowns(l)))
    }

    /// Nodes of the system it was built for.
    pub fn node_count(&self) -> usize {
        self.layout.nodes
    }
}

/// `values[start + i]` or zero.
#[inline]
pub(crate) fn get<T: Real>(v: &[T], i: usize) -> T {
    v.get(i).copied().unwrap_or(T::ZERO)
}

/// The block of `b_r × b_c` scalars at block index `i` of a flat array starting at `start`.
#[inline]
pub(crate) fn blk<T>(v: &[T], start: usize, i: usize, size: usize) -> &[T] {
    seg(v, start.saturating_add(i.saturating_mul(size)), size)
}

/// Mutable [`blk`].
#[inline]
pub(crate) fn blk_mut<T>(v: &mut [T], start: usize, i: usize, size: usize) -> &mut [T] {
    seg_mut(v, start.saturating_add(i.saturating_mul(size)), size)
}
