//! The springs' adjoint solves only the lanes of `w` that are not zero at every free node.
//!
//! The adjoint solve `A λ = w_f` runs every lane with the same matrix and no coupling, from a
//! zero start. A lane whose right-hand side is `±0` at every free node has the exact solution
//! `+0`, and CG leaves it there bit for bit (its residual, preconditioned residual and search
//! direction stay `±0`, its step is `+0`): solving it only costs a lane of every operator
//! application, V-cycle and update. The quaternion method's 2D adjoint has two such lanes of
//! six (the rotation axes `x` and `y`).
//!
//! So the solve packs the other `W` lanes into `[T; W]` items inside the caller's scratch,
//! solves those and pulls back with `+0` in the dropped lanes. The other lanes never read a
//! dropped one; the stopping rule's norms sum its exact zeros, which change no sum, and the
//! common power of two they are summed at scales them exactly (as for the Dirichlet solves,
//! `spring::zero_components`), so the iterations, the bits and the report are those of the
//! full solve. Only on 64-bit hosts: the packed instances enlarge the stack frames, which the
//! Cortex-M4F's 64 KiB cannot spare (32-bit targets run the full solve, with the same bits).
#![cfg_attr(not(target_pointer_width = "64"), allow(dead_code))]

use super::adjoint_parts;
use super::springs::{adjoint_solve, pull_back, spring_adjoint_scratch_len};
use crate::error::Result;
use crate::real::Real;
use crate::spring::{LinearSolver, SolveOptions, SolveReport, SpringSystem};

/// Solves only the lanes of `w` not `±0` at every free node, when some are and some are not
/// and `scratch` (at least the full solve's length) holds the packed right-hand side and the
/// packed solve's scratch; `None` otherwise (the caller runs the full solve). `g` is written
/// only on `Ok`. The caller has validated everything else.
#[cfg(target_pointer_width = "64")]
pub(super) fn adjoint_nonzero<T: Real, const V: usize>(
    sys: &SpringSystem<'_, T>,
    solver: LinearSolver<'_, T>,
    options: &SolveOptions<T>,
    w: &[[T; V]],
    g: &mut [[T; V]],
    scratch: &mut [[T; V]],
) -> Option<Result<SolveReport<T>>> {
    if scratch.len() < spring_adjoint_scratch_len::<T, V>(&solver, w.len()) {
        return None; // the full solve's error, with its own numbers, whatever the lanes
    }
    let mut zero = [true; V];
    for (i, wi) in w.iter().enumerate() {
        if !sys.is_fixed(i) {
            for (z, &x) in zero.iter_mut().zip(wi) {
                *z &= x == T::ZERO;
            }
        }
    }
    let mut lanes = [0usize; V];
    let mut k = 0;
    for (c, _) in zero.iter().enumerate().filter(|(_, &z)| !z) {
        *lanes.get_mut(k)? = c;
        k += 1;
    }
    let s = Solve {
        sys,
        solver,
        options,
        lanes: lanes.get(..k)?,
    };
    match k {
        1 => s.packed::<V, 1>(w, g, scratch),
        2 => s.packed::<V, 2>(w, g, scratch),
        3 => s.packed::<V, 3>(w, g, scratch),
        4 => s.packed::<V, 4>(w, g, scratch),
        5 => s.packed::<V, 5>(w, g, scratch),
        _ => None, // none to drop, all zero (the full solve returns at once), or too many
    }
}

/// On 32-bit targets the full solve always runs (see the module docs).
#[cfg(not(target_pointer_width = "64"))]
#[inline(always)]
pub(super) fn adjoint_nonzero<T: Real, const V: usize>(
    _sys: &SpringSystem<'_, T>,
    _solver: LinearSolver<'_, T>,
    _options: &SolveOptions<T>,
    _w: &[[T; V]],
    _g: &mut [[T; V]],
    _scratch: &mut [[T; V]],
) -> Option<Result<SolveReport<T>>> {
    None
}

/// The solve and the lanes it keeps.
struct Solve<'a, 's, T: Real> {
    sys: &'a SpringSystem<'s, T>,
    solver: LinearSolver<'a, T>,
    options: &'a SolveOptions<T>,
    lanes: &'a [usize],
}

impl<T: Real> Solve<'_, '_, T> {
    /// [`adjoint_nonzero`] with the `W < V` lanes `self.lanes` packed.
    fn packed<const V: usize, const W: usize>(
        &self,
        w: &[[T; V]],
        g: &mut [[T; V]],
        scratch: &mut [[T; V]],
    ) -> Option<Result<SolveReport<T>>> {
        if W >= V || self.lanes.len() != W {
            return None;
        }
        let n = w.len();
        let needed = spring_adjoint_scratch_len::<T, W>(&self.solver, n);
        let (front, rest) = scratch
            .as_flattened_mut()
            .split_at_mut_checked(n.checked_mul(W)?)?;
        let rhs = front.as_chunks_mut::<W>().0;
        let rest = rest.as_chunks_mut::<W>().0;
        if needed == usize::MAX || rest.len() < needed {
            return None;
        }
        for (r, wi) in rhs.iter_mut().zip(w) {
            for (r, &c) in r.iter_mut().zip(self.lanes) {
                *r = wi.get(c).copied().unwrap_or(T::ZERO);
            }
        }
        let (lambda, v, rest) = adjoint_parts(rest, n, needed).ok()?;
        let report = adjoint_solve(self.sys, self.solver, self.options, rhs, lambda, v, rest);
        Some(report.inspect(|_| {
            let lambda: &[[T; W]] = lambda;
            pull_back(self.sys, w, |i| self.unpack::<V, W>(lambda.get(i)), g);
        }))
    }

    /// The full lane vector of a packed item, `+0` in the dropped lanes.
    fn unpack<const V: usize, const W: usize>(&self, p: Option<&[T; W]>) -> [T; V] {
        let mut full = [T::ZERO; V];
        if let Some(p) = p {
            for (&x, &c) in p.iter().zip(self.lanes) {
                if let Some(f) = full.get_mut(c) {
                    *f = x;
                }
            }
        }
        full
    }
}
