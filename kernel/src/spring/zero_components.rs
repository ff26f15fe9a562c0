//! Components that are provably zero are not solved.
//!
//! The linear springs solve every value component with the same matrix and no coupling (one
//! CG lane each). A component whose Dirichlet data are all `±0` and whose initial guess is
//! `+0` at every free node has the exact solution zero, and CG leaves it there bit for bit:
//! its residual, preconditioned residual and search direction are all `±0`, so its `rᵀz` is
//! zero, its step `α` is `+0`, and `+0 + α p` stays `+0`. Solving it costs a lane of every
//! operator application, V-cycle and update (the third component of a rotation about `z`,
//! or the quaternion method's unused rotation axes and translations).
//!
//! So the serial CG and multigrid-CG solves pack the other `W` components into `[T; W]`
//! items inside the caller's scratch, solve those, and unpack. The other lanes never read the
//! dropped one; the stopping rule's norms sum its exact zeros, which change no sum; only the
//! common power of two the norms are summed at (the largest component exponent) may differ,
//! and powers of two scale the sums, their square roots and the relative residual exactly
//! (see `norms`), so the iterations, the bits and the report are those of the full solve.
//!
//! Only on 64-bit hosts: the packed instances enlarge the solves' stack frames, and on a
//! Cortex-M4F with 64 KiB of RAM the footprint run's solves no longer fitted (32-bit targets
//! run the full solve, with the same bits).
#![cfg_attr(not(target_pointer_width = "64"), allow(dead_code))]

use super::amg::{solve_amg_on, solve_linear_amg_scratch_len, AmgHierarchy};
use super::distributed::{Collective, Serial};
use super::linear::solve_linear_on;
use super::system::{LinearMethod, SolveOptions, SolveReport, SpringSystem};
use crate::error::Result;
use crate::real::Real;

/// The serial CG-type solve to run on the packed components.
#[derive(Clone, Copy)]
pub(crate) enum Packed<'h, 'a, T: Real> {
    /// [`solve_linear`](SpringSystem::solve_linear) with `LinearMethod::Cg`.
    Cg(LinearMethod<T>),
    /// [`solve_linear_amg`](SpringSystem::solve_linear_amg).
    Amg(&'h AmgHierarchy<'a, T>),
}

/// Component `c` is provably zero: every fixed value `±0`, every free value `+0`. `None` when
/// `values` has the wrong length or a non-finite entry (the full solve reports it).
fn zero_components<T: Real, const V: usize>(
    sys: &SpringSystem<'_, T>,
    values: &[[T; V]],
) -> Option<[bool; V]> {
    if values.len() != sys.node_count() {
        return None;
    }
    let mut zero = [true; V];
    for (i, v) in values.iter().enumerate() {
        let fixed = sys.is_fixed(i);
        for (z, &x) in zero.iter_mut().zip(v) {
            if !x.is_finite() {
                return None;
            }
            *z &= x == T::ZERO && (fixed || !x.is_sign_negative());
        }
    }
    Some(zero)
}

/// Solves only the components that are not provably zero, when some are and some are not and
/// `scratch` (at least the full solve's length) holds the packed values and the packed
/// solve's scratch; `None` otherwise (the caller runs the full solve). `values` is written
/// only on `Ok`.
#[cfg(target_pointer_width = "64")]
pub(crate) fn solve_nonzero<T: Real, const V: usize>(
    sys: &SpringSystem<'_, T>,
    values: &mut [[T; V]],
    solve: Packed<'_, '_, T>,
    options: &SolveOptions<T>,
    scratch: &mut [[T; V]],
) -> Option<Result<SolveReport<T>>> {
    let n = sys.node_count();
    let full = match solve {
        Packed::Cg(_) => n.checked_mul(4)?.checked_add(n.div_ceil(V.max(1)))?,
        Packed::Amg(h) => solve_linear_amg_scratch_len(h),
    };
    if scratch.len() < full {
        return None; // the full solve's error, with its own numbers
    }
    let zero = zero_components(sys, values)?;
    let mut comps = [0usize; V];
    let mut w = 0;
    for (c, _) in zero.iter().enumerate().filter(|(_, &z)| !z) {
        *comps.get_mut(w)? = c;
        w += 1;
    }
    let comps = comps.get(..w)?;
    match w {
        1 => packed::<T, V, 1>(sys, values, comps, solve, options, scratch),
        2 => packed::<T, V, 2>(sys, values, comps, solve, options, scratch),
        3 => packed::<T, V, 3>(sys, values, comps, solve, options, scratch),
        4 => packed::<T, V, 4>(sys, values, comps, solve, options, scratch),
        5 => packed::<T, V, 5>(sys, values, comps, solve, options, scratch),
        _ => None, // none to drop, all zero (the full solve returns at once), or too many
    }
}

/// On 32-bit targets the full solve always runs (see the module docs).
#[cfg(not(target_pointer_width = "64"))]
#[inline(always)]
pub(crate) fn solve_nonzero<T: Real, const V: usize>(
    _sys: &SpringSystem<'_, T>,
    _values: &mut [[T; V]],
    _solve: Packed<'_, '_, T>,
    _options: &SolveOptions<T>,
    _scratch: &mut [[T; V]],
) -> Option<Result<SolveReport<T>>> {
    None
}

/// [`solve_nonzero`] with `W < V` components `comps` packed.
fn packed<T: Real, const V: usize, const W: usize>(
    sys: &SpringSystem<'_, T>,
    values: &mut [[T; V]],
    comps: &[usize],
    solve: Packed<'_, '_, T>,
    options: &SolveOptions<T>,
    scratch: &mut [[T; V]],
) -> Option<Result<SolveReport<T>>> {
    if W >= V || comps.len() != W {
        return None;
    }
    let n = values.len();
    let flat = scratch.as_flattened_mut();
    let (front, rest) = flat.split_at_mut_checked(n.checked_mul(W)?)?;
    let packed = front.as_chunks_mut::<W>().0;
    let rest = rest.as_chunks_mut::<W>().0;
    let needed = match solve {
        Packed::Cg(_) => n.checked_mul(4)?.checked_add(n.div_ceil(W))?,
        Packed::Amg(h) => solve_linear_amg_scratch_len(h),
    };
    if rest.len() < needed {
        return None;
    }
    for (p, v) in packed.iter_mut().zip(values.iter()) {
        for (p, &c) in p.iter_mut().zip(comps) {
            *p = v.get(c).copied().unwrap_or(T::ZERO);
        }
    }
    let report = match solve {
        Packed::Cg(m) => solve_linear_on(sys, packed, m, options, rest, None),
        Packed::Amg(h) => {
            let comm = Serial::new(n);
            solve_amg_on(sys, h, packed, options, rest, &comm as &dyn Collective<T>)
        }
    };
    if report.is_ok() {
        for (v, p) in values.iter_mut().zip(packed.iter()) {
            for (&x, &c) in p.iter().zip(comps) {
                if let Some(v) = v.get_mut(c) {
                    *v = x;
                }
            }
        }
    }
    Some(report)
}
