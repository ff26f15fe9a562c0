//! Taubin λ|μ low-pass filtering and structured-grid tools (Alter).
//!
//! Alter (NASA Langley, Columbia accident investigation) smooths structured volume grids by
//! turning the coordinates along one computational direction into a *scalar* arclength field
//! `ΔS(i, j, k)`, low-pass filtering that field with Taubin's two-pass scheme, and moving every
//! point back onto its *original* grid line at the filtered arclength. Points only slide along
//! the lines they already lie on, so the shape of the grid is kept while the "noise" (rough
//! distributions, stretching peaks) is removed.
//!
//! One iteration is a forward (smoothing) pass and a backward (shape-recovering) pass, each a
//! Jacobi update from the previous field (Alter eqs. 5 and 6):
//!
//! ```text
//! ΔS_new       = ΔS     + λ (avg(ΔS)     − ΔS)        λ =  0.330
//! ΔS_corrected = ΔS_new + μ (avg(ΔS_new) − ΔS_new)    μ = −0.334
//! ```
//!
//! where `avg` is the paper's stencil (eqs. 2–4): the average of the 6 neighbours inside the
//! block, of the 4 in-plane neighbours on a face, of the 2 neighbours along an edge; corners do
//! not move. For a Laplacian eigenmode with eigenvalue `k` (`avg(x) − x = −k x`) one iteration
//! multiplies the mode by `f(k) = (1 − λk)(1 − μk)`: `f ≈ 1` below the pass-band frequency
//! `k_PB = 1/λ + 1/μ` and `|f| < 1` above it, a low-pass filter without the shrinkage of plain
//! Laplacian smoothing.
//!
//! Pieces (all `no_std`, allocation-free, generic over `f32`/`f64`):
//! - [`TaubinParams`]: λ, μ, the transfer function and the pass-band helper
//!   ([`mu_from_pass_band`]).
//! - [`smooth_structured`] / [`structured_sweep`]: the scalar filter on a 1D/2D/3D [`Block`]
//!   with a fixed-point mask and an optional mirror (Neumann) face mode; the sweep updates one index box
//!   so an MPI code can exchange halos between passes.
//! - [`smooth_structured_coarse`]: the coarse-grid variant (every m-th point, last index always
//!   kept; smoothing there; prolongation by interpolation).
//! - [`smooth_graph`] / [`graph_sweep`] / [`inverse_distance_weights`]: classic Taubin fairing of
//!   `[T; V]` values on a CSR [`Graph`](crate::Graph).
//! - [`arclength`], [`redistribute`], [`stretching`], [`max_stretching`],
//!   [`check_lines_increasing`]: the line tools.
//! - [`smooth_arclength`]: the whole-grid driver (arclength → filter → fold guard →
//!   redistribution) behind `deform smooth`; [`LineEnd`] says whether the last point of each
//!   line stays (default) or slides along the line (Alter's rough outer boundary).
//!
//! ```
//! use deform_kernel::taubin::{smooth_arclength, smooth_arclength_scratch_len, SmoothOptions};
//! use deform_kernel::{Block, Direction};
//! // One i-line of 6 points with an abrupt spacing jump (stretching 3 at point 3).
//! let block = Block::new([6, 1, 1])?;
//! let mut points = [[0.0, 0.0], [1.0, 0.0], [2.0, 0.0], [3.0, 0.0], [6.0, 0.0], [9.0, 0.0]];
//! let mut options = SmoothOptions::new(Direction::I); // lines along i, λ = 0.330, μ = −0.334, 30 its
//! options.normalised = true; // filter s = S / S_total: both ends stay put
//! let mut scratch = vec![0.0; smooth_arclength_scratch_len::<2>(&block, Direction::I, None)];
//! let report = smooth_arclength(&block, &mut points, &options, &mut scratch)?;
//! assert!(report.stretching_after.0 < report.stretching_before.0);
//! assert_eq!(points[5], [9.0, 0.0]);
//! # Ok::<(), deform_kernel::Error>(())
//! ```
//!
//! # Multi-block grids with point-matched interfaces
//!
//! With the paper's boundary rule a point on a block face is averaged only with its in-plane
//! neighbours, so the field on a face evolves as a 2D problem on that face alone. Two blocks
//! that share a whole face (same points, same index orientation) therefore produce bitwise
//! identical face values, and the redistribution of a line lying in the face uses the same
//! polyline and targets in both blocks: the interface stays point-matched with no
//! communication (this is what let Alter smooth each block on its own CPU). This does **not**
//! hold when (a) the smoothing direction crosses the interface (dimensional arclength on the
//! far face is filtered and the face points slide), (b) the mirror mode is on for the direction
//! normal to the interface, or (c) the interface covers only part of a face or the index
//! orientation differs (different summation order). In those cases pin the interface points
//! (the `fixed` mask) in every block that touches the interface, or filter the interface face
//! once as its own 2D block, copy the result to every block and pin it there.
//!
//! [`Block`]: crate::Block

mod coarse;
mod ends;
mod graph_filter;
mod grid;
mod lines;
mod structured;

pub use coarse::{
    coarse_dims, smooth_structured_coarse, structured_coarse_scratch_len, Coarse, Prolongation,
};
pub use ends::LineEnd;
pub use graph_filter::{
    graph_scratch_len, graph_sweep, inverse_distance_weights, smooth_graph, GraphOptions,
};
pub use grid::{smooth_arclength, smooth_arclength_scratch_len, SmoothOptions, SmoothReport};
pub use lines::{
    arclength, check_lines_increasing, max_stretching, redistribute, redistribute_scratch_len,
    stretching,
};
pub use structured::{
    smooth_structured, structured_scratch_len, structured_sweep, BlockRegion, FilterReport,
    StructuredOptions,
};

use crate::check;
use crate::error::{Error, Result};
use crate::real::Real;

/// The two relaxation factors of one Taubin iteration: the smoothing weight `λ > 0` (forward
/// pass) and the shape-recovering weight `μ ≤ 0` (backward pass).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct TaubinParams<T> {
    /// Forward (smoothing) relaxation factor, Alter's `ω_forward`. Must be finite and `> 0`.
    pub lambda: T,
    /// Backward (shape-recovery) relaxation factor, Alter's `ω_backward`. Must be finite and
    /// `≤ 0` (`μ = 0` gives plain λ-only Laplacian smoothing, for comparison).
    pub mu: T,
}

impl<T: Real> TaubinParams<T> {
    /// The values Alter took from Taubin: `λ = 0.330`, `μ = −0.334` (pass band
    /// `k_PB = 1/λ + 1/μ ≈ 0.0363`).
    pub fn paper() -> Self {
        TaubinParams {
            lambda: T::from_f64(0.330),
            mu: T::from_f64(-0.334),
        }
    }

    /// `λ` with `μ` derived from the pass-band frequency `k_PB` by `1/λ + 1/μ = k_PB`
    /// (see [`mu_from_pass_band`]).
    ///
    /// # Errors
    /// Those of [`mu_from_pass_band`].
    pub fn from_pass_band(lambda: T, pass_band: T) -> Result<Self> {
        Ok(TaubinParams {
            lambda,
            mu: mu_from_pass_band(lambda, pass_band)?,
        })
    }

    /// Checks `λ` finite and `> 0`, `μ` finite and `≤ 0`.
    ///
    /// # Errors
    /// A non-finite `λ` or `μ` ([`Error::NonFinite`]); `λ ≤ 0` or `μ > 0`
    /// ([`Error::InvalidParameter`]).
    pub fn validate(&self) -> Result<()> {
        check::scalar("lambda", self.lambda)?;
        check::scalar("mu", self.mu)?;
        if self.lambda <= T::ZERO {
            return Err(Error::InvalidParameter {
                arg: "lambda",
                reason: "must be > 0",
            });
        }
        if self.mu > T::ZERO {
            return Err(Error::InvalidParameter {
                arg: "mu",
                reason: "must be <= 0",
            });
        }
        Ok(())
    }

    /// The transfer function of one iteration, `f(k) = (1 − λk)(1 − μk)`: the factor by which
    /// one λ|μ iteration multiplies a Laplacian eigenmode with eigenvalue `k` (`k ∈ [0, 2]`
    /// for the averaging operators used here).
    pub fn transfer(&self, k: T) -> T {
        (T::ONE - self.lambda * k) * (T::ONE - self.mu * k)
    }

    /// The pass-band frequency `k_PB = 1/λ + 1/μ` (infinite when `μ = 0`).
    pub fn pass_band(&self) -> T {
        if self.mu == T::ZERO {
            T::INFINITY
        } else {
            T::ONE / self.lambda + T::ONE / self.mu
        }
    }
}

impl<T: Real> Default for TaubinParams<T> {
    /// [`TaubinParams::paper`].
    fn default() -> Self {
        Self::paper()
    }
}

/// Taubin's pass-band relation solved for `μ`: `1/λ + 1/μ = k_PB` ⇒ `μ = 1 / (k_PB − 1/λ)`.
///
/// Needs `λ > 0` and `0 < k_PB < 1/λ` (then `μ < −λ < 0`: the backward pass is slightly
/// stronger than the forward pass, which is what makes the filter low-pass). Taubin suggests
/// `k_PB` between 0.01 and 0.1.
///
/// # Errors
/// A non-finite `λ` or `k_PB` ([`Error::NonFinite`]); `λ ≤ 0`, or `k_PB` outside
/// `(0, 1/λ)` ([`Error::InvalidParameter`]).
pub fn mu_from_pass_band<T: Real>(lambda: T, pass_band: T) -> Result<T> {
    check::scalar("lambda", lambda)?;
    check::scalar("pass_band", pass_band)?;
    if lambda <= T::ZERO {
        return Err(Error::InvalidParameter {
            arg: "lambda",
            reason: "must be > 0",
        });
    }
    let inv_lambda = T::ONE / lambda;
    if pass_band <= T::ZERO || pass_band >= inv_lambda || !inv_lambda.is_finite() {
        return Err(Error::InvalidParameter {
            arg: "pass_band",
            reason: "must satisfy 0 < pass_band < 1/lambda",
        });
    }
    let mu = T::ONE / (pass_band - inv_lambda);
    if !mu.is_finite() {
        return Err(Error::InvalidParameter {
            arg: "pass_band",
            reason: "gives a non-finite mu",
        });
    }
    Ok(mu)
}
