//! Linear-spring propagation of `(Δ, Q)`: one solve with `V = D + 4` values per node. `V` is
//! internal: callers pass a flat scalar workspace, sized by the `_scratch_len` functions.

use super::propagate::check_boundary_entries;
use crate::check;
use crate::error::{Error, Result};
use crate::quat::Quat;
use crate::real::Real;
use crate::spring::{
    solve_linear_with_scratch_len, LinearMethod, LinearSolver, SolveOptions, SolveReport,
    SpringSystem,
};

/// Scalars of scratch [`propagate_spring`] needs in dimension `D`: `D + 4` per item, `N` items
/// for the packed `(Δ, Q)` values plus
/// [`solve_linear_scratch_len`](crate::spring::solve_linear_scratch_len) for the solver.
/// Call as `propagate_spring_scratch_len::<2>(&method, n)`.
#[inline]
pub fn propagate_spring_scratch_len<const D: usize>(
    method: &LinearMethod<impl Real>,
    node_count: usize,
) -> usize {
    propagate_spring_with_scratch_len::<D>(&LinearSolver::Method(*method), node_count)
}

/// Scalars of scratch [`propagate_spring_with`] needs in dimension `D`: `D + 4` per item, `N`
/// items for the packed values plus [`solve_linear_with_scratch_len`] for the solver.
#[inline]
pub fn propagate_spring_with_scratch_len<const D: usize>(
    solver: &LinearSolver<'_, impl Real>,
    node_count: usize,
) -> usize {
    check::mesh_dim::<D>();
    node_count
        .saturating_add(solve_linear_with_scratch_len(solver, node_count))
        .saturating_mul(D + 4)
}

/// Propagates translations and rotations through a linear spring network (Samareh: "the
/// translation vectors and quaternions are propagated into the field mesh by … the spring
/// analogy"; Batina's springs, Samareh eq. 2): `Δ` and the four quaternion components are
/// packed into one `[T; V]` field (`V = D + 4`) and solved together by
/// [`solve_linear`](crate::spring::SpringSystem::solve_linear) with `method` and `options`.
///
/// On entry `translations` and `rotations` hold the boundary values at the *fixed* nodes of
/// `sys` (other entries are ignored). The fixed quaternions are flipped into the hemisphere of
/// the first fixed node's (`q` and `−q` are one rotation, and the springs average components),
/// the free nodes start from the mean of the fixed values, and after the solve every free
/// node's quaternion is renormalised. Fixed entries are never written.
///
/// `scratch` needs [`propagate_spring_scratch_len`] scalars. Returns the solver's report
/// (check `converged`).
///
/// # Errors
/// Length mismatches, a short `scratch`, no fixed node, non-finite or zero boundary values,
/// the solver's errors, and [`Error::ZeroLength`] (`"rotations"`, position = node) if a solved
/// quaternion cancels to zero. On error `translations` and `rotations` are unchanged.
pub fn propagate_spring<T: Real, const D: usize>(
    sys: &SpringSystem<'_, T>,
    method: LinearMethod<T>,
    options: &SolveOptions<T>,
    translations: &mut [[T; D]],
    rotations: &mut [Quat<T>],
    scratch: &mut [T],
) -> Result<SolveReport<T>> {
    propagate_spring_with(
        sys,
        LinearSolver::Method(method),
        options,
        translations,
        rotations,
        scratch,
    )
}

/// [`propagate_spring`] with any linear-spring solver, e.g. the multigrid-preconditioned CG
/// ([`LinearSolver::Amg`], hierarchy built for `sys`). `scratch` needs
/// [`propagate_spring_with_scratch_len`] scalars; otherwise identical.
///
/// # Errors
/// Those of [`propagate_spring`], and a hierarchy built for another system.
pub fn propagate_spring_with<T: Real, const D: usize>(
    sys: &SpringSystem<'_, T>,
    solver: LinearSolver<'_, T>,
    options: &SolveOptions<T>,
    translations: &mut [[T; D]],
    rotations: &mut [Quat<T>],
    scratch: &mut [T],
) -> Result<SolveReport<T>> {
    check::mesh_dim::<D>();
    let n = sys.node_count();
    check::len("translations", translations.len(), n)?;
    check::len("rotations", rotations.len(), n)?;
    check::buffer(
        "scratch",
        scratch.len(),
        propagate_spring_with_scratch_len::<D>(&solver, n),
    )?;
    // The packed solve has `V = D + 4` values per node: a compile-time choice per `D`.
    if D == 2 {
        propagate_packed::<T, D, 6>(sys, solver, options, translations, rotations, scratch)
    } else {
        propagate_packed::<T, D, 7>(sys, solver, options, translations, rotations, scratch)
    }
}

/// [`propagate_spring_with`] on `V = D + 4` values per node, after its length checks.
fn propagate_packed<T: Real, const D: usize, const V: usize>(
    sys: &SpringSystem<'_, T>,
    solver: LinearSolver<'_, T>,
    options: &SolveOptions<T>,
    translations: &mut [[T; D]],
    rotations: &mut [Quat<T>],
    scratch: &mut [T],
) -> Result<SolveReport<T>> {
    let n = sys.node_count();
    let scratch = scratch.as_chunks_mut::<V>().0;
    // Validate the fixed entries.
    let mut first_fixed = None;
    for (i, &m) in sys.fixed().iter().enumerate() {
        if crate::spring::is_fixed(m) {
            if first_fixed.is_none() {
                first_fixed = Some(i);
            }
            if let Ok(index) = u32::try_from(i) {
                check_boundary_entries(core::slice::from_ref(&index), translations, rotations)?;
            }
        }
    }
    let Some(first) = first_fixed else {
        return Err(Error::InvalidParameter {
            arg: "sys",
            reason: "needs at least one fixed node",
        });
    };
    let reference = rotations.get(first).copied().unwrap_or(Quat::identity());

    let (values, solver_scratch) = match scratch.split_at_mut_checked(n) {
        Some(p) => p,
        None => {
            return Err(Error::BufferTooSmall {
                arg: "scratch",
                needed: n,
                actual: scratch.len(),
            })
        }
    };
    // Pack the fixed values (hemisphere-aligned); the free nodes start at their mean.
    for (i, v) in values.iter_mut().enumerate() {
        if !sys.is_fixed(i) {
            continue;
        }
        let t = translations.get(i).copied().unwrap_or([T::ZERO; D]);
        let q = rotations.get(i).copied().unwrap_or(reference);
        let q = if q.dot(reference) < T::ZERO { -q } else { q };
        *v = pack(t, q);
    }
    start_at_fixed_mean(sys, values);
    let report = sys.solve_linear_with(values, solver, options, solver_scratch)?;
    check_rotations::<T, D, V>(sys, values)?;
    for (i, ((v, t), r)) in values
        .iter()
        .zip(translations.iter_mut())
        .zip(rotations.iter_mut())
        .enumerate()
    {
        if sys.is_fixed(i) {
            continue;
        }
        let (tv, qv) = unpack::<T, D, V>(v);
        *t = tv;
        *r = qv.normalize().unwrap_or(reference);
    }
    Ok(report)
}

/// `[Δ, w, x, y, z]`.
#[inline]
pub(crate) fn pack<T: Real, const D: usize, const V: usize>(t: [T; D], q: Quat<T>) -> [T; V] {
    let mut v = [T::ZERO; V];
    for (a, b) in v.iter_mut().zip(t.iter().chain(q.to_array().iter())) {
        *a = *b;
    }
    v
}

/// Inverse of [`pack`].
#[inline]
pub(crate) fn unpack<T: Real, const D: usize, const V: usize>(v: &[T; V]) -> ([T; D], Quat<T>) {
    let mut t = [T::ZERO; D];
    for (a, b) in t.iter_mut().zip(v.iter()) {
        *a = *b;
    }
    let mut q = [T::ZERO; 4];
    for (a, b) in q.iter_mut().zip(v.iter().skip(D)) {
        *a = *b;
    }
    (t, Quat::from_array(q))
}

/// The cold start of a packed solve: every free node gets the mean of the fixed nodes'
/// values (summed in node order), which is returned.
pub(crate) fn start_at_fixed_mean<T: Real, const V: usize>(
    sys: &SpringSystem<'_, T>,
    values: &mut [[T; V]],
) -> [T; V] {
    let mut mean = [T::ZERO; V];
    let mut count = 0usize;
    for (i, v) in values.iter().enumerate() {
        if sys.is_fixed(i) {
            for (m, x) in mean.iter_mut().zip(v.iter()) {
                *m += *x;
            }
            count += 1;
        }
    }
    let c = T::from_usize(count.max(1));
    for m in mean.iter_mut() {
        *m /= c;
    }
    for (i, v) in values.iter_mut().enumerate() {
        if !sys.is_fixed(i) {
            *v = mean;
        }
    }
    mean
}

/// Checks that every free node's solved quaternion normalises, before anything is written.
///
/// # Errors
/// [`Error::ZeroLength`] on `rotations` at the first node whose quaternion does not.
pub(crate) fn check_rotations<T: Real, const D: usize, const V: usize>(
    sys: &SpringSystem<'_, T>,
    values: &[[T; V]],
) -> Result<()> {
    for (i, v) in values.iter().enumerate() {
        if !sys.is_fixed(i) && unpack::<T, D, V>(v).1.normalize().is_err() {
            return Err(Error::ZeroLength {
                arg: "rotations",
                position: i,
            });
        }
    }
    Ok(())
}
