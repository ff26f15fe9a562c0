//! Building a plan: validate the spec once, size the pools, fill them.

use super::layout::{self, set_hw, w, word, Counts, Sections, SolverKind, HEADER};
use super::{PlanCounts, PlanMethod, PlanSizes, PlanSolver, PlanSpec, PlanStiffness, PlanWork};
use crate::check;
use crate::error::{Error, Result};
use crate::graph::Graph;
use crate::quaternion::check_elements;
use crate::real::Real;
use crate::spring::constraints::NodeKind;
use crate::spring::{
    amg_cg_scratch_len, amg_setup_work_len, batina_stiffness, check_omega,
    solve_linear_scratch_len, AmgHierarchy, LinearMethod, Preconditioner, SpringSystem,
};

/// Transient work lengths.
pub(super) fn work_sizes<T: Real, const D: usize>(spec: &PlanSpec<'_, T, D>) -> PlanSizes {
    work_sizes_of(spec.graph.node_count(), spec.graph.edge_count())
}

/// The length checks on a spec that need no work buffers (see
/// [`Plan::work_sizes`](super::Plan::work_sizes)).
pub(super) fn check_lengths<T: Real, const D: usize>(spec: &PlanSpec<'_, T, D>) -> Result<()> {
    let n = spec.graph.node_count();
    check::len("points", spec.points.len(), n)?;
    if spec.boundary.is_empty() {
        return Err(Error::InvalidParameter {
            arg: "boundary",
            reason: "must not be empty",
        });
    }
    if let PlanStiffness::Given(k) = spec.stiffness {
        check::len("stiffness", k.len(), spec.graph.edge_count())?;
    }
    if let Some(c) = &spec.constraints {
        check::len("constraints", c.len(), n)?;
    }
    Ok(())
}

/// Transient work lengths for `n` nodes and `e` directed edges: `e` reals (the stiffness),
/// `max(4 (n + e) + 64, n)` indices (anchoring search, the hierarchy's symbolic pass), `n`
/// bytes (the fixed mask).
pub(super) const fn work_sizes_of(n: usize, e: usize) -> PlanSizes {
    let amg = amg_setup_work_len(n, e);
    PlanSizes {
        reals: e,
        indices: if amg > n { amg } else { n },
        bytes: n,
    }
}

/// The stored solver code of a solver.
fn solver_kind<T: Real>(s: &PlanSolver<T>) -> (SolverKind, T) {
    match *s {
        PlanSolver::Amg(_) => (SolverKind::Amg, T::ZERO),
        PlanSolver::Method(m) => (
            SolverKind::of_method(&m),
            match m {
                LinearMethod::Sor { omega }
                | LinearMethod::Cg {
                    preconditioner: Preconditioner::Ssor { omega },
                } => omega,
                _ => T::ZERO,
            },
        ),
    }
}

/// The pool sizes of a plan with a one-level solver, from counts alone (see
/// [`Plan::capacity`](super::Plan::capacity)); the arithmetic of [`sizes`].
pub(super) const fn one_level_sizes<T>(
    counts: &PlanCounts,
    d: usize,
    method: PlanMethod,
    solver: &LinearMethod<T>,
) -> Option<PlanSizes> {
    let counts = Counts::of(
        counts,
        d,
        method,
        SolverKind::of_method(solver),
        (0, 0),
        solve_linear_scratch_len(solver, counts.nodes),
    );
    match Sections::layout(&counts) {
        Ok(s) => Some(s.sizes),
        Err(_) => None,
    }
}

/// Validates the spec; leaves the stiffness in `work.reals` (Batina) and the fixed mask in
/// `work.bytes`; returns the counts (with the hierarchy's exact sizes).
fn prepare<T: Real, const D: usize>(
    spec: &PlanSpec<'_, T, D>,
    work: &mut PlanWork<'_, T>,
) -> Result<Counts> {
    check::mesh_dim::<D>();
    let n = spec.graph.node_count();
    let e = spec.graph.edge_count();
    let b = spec.boundary.len();
    let need = work_sizes(spec);
    for (arg, have, needed) in [
        ("work.reals", work.reals.len(), need.reals),
        ("work.indices", work.indices.len(), need.indices),
        ("work.bytes", work.bytes.len(), need.bytes),
    ] {
        check::buffer(arg, have, needed)?;
    }
    check_lengths(spec)?;
    if let Some(p) = crate::real::first_non_finite(spec.points) {
        return Err(Error::NonFinite {
            arg: "points",
            position: p,
        });
    }
    // The fixed mask, with the duplicate and range checks of the boundary list.
    let mask = work.bytes.get_mut(..n).unwrap_or(&mut []);
    mask.fill(0);
    for (position, &node) in spec.boundary.iter().enumerate() {
        match mask.get_mut(node as usize) {
            None => {
                return Err(Error::IndexOutOfRange {
                    arg: "boundary",
                    position,
                    index: node as usize,
                    bound: n,
                })
            }
            Some(m) if *m != 0 => {
                return Err(Error::DuplicateNode {
                    arg: "boundary",
                    position,
                    node: node as usize,
                })
            }
            Some(m) => *m = 1,
        }
    }
    if let Some(c) = &spec.constraints {
        for (&k, &m) in c.kinds().iter().zip(mask.iter()) {
            match NodeKind::from_code(k) {
                Some(NodeKind::Free) | Some(NodeKind::Fixed) => {}
                _ => {
                    return Err(Error::InvalidParameter {
                        arg: "constraints",
                        reason: "sliding nodes (plane, line) are not supported by plans yet",
                    })
                }
            }
            if (k == NodeKind::Fixed.code()) != (m != 0) {
                return Err(Error::InvalidParameter {
                    arg: "constraints",
                    reason: "must mark exactly the boundary nodes fixed",
                });
            }
        }
    }
    if let (Some(el), PlanMethod::QuaternionSpring) = (&spec.elements, spec.method) {
        check_elements::<D>(el, b)?;
    }
    spec.options.check()?;
    let (kind, omega) = solver_kind(&spec.solver);
    if matches!(kind, SolverKind::Sor | SolverKind::CgSsor) {
        check_omega(omega)?;
    }
    let stiffness: &[T] = match spec.stiffness {
        PlanStiffness::Given(k) => k,
        PlanStiffness::Batina { exponent } => {
            let k = work.reals.get_mut(..e).unwrap_or(&mut []);
            batina_stiffness(&spec.graph, spec.points, exponent, k)?;
            k
        }
    };
    let mask: &[u8] = work.bytes.get(..n).unwrap_or(&[]);
    let sys = SpringSystem::new(spec.graph, stiffness, mask, work.indices)?;
    let (amg_index, amg_values, scratch) = match &spec.solver {
        PlanSolver::Amg(opts) => {
            let s = AmgHierarchy::setup_len(&sys, opts, work.indices)?;
            let scratch = amg_cg_scratch_len(n, s.coarse_unknowns).unwrap_or(usize::MAX);
            (s.index, s.values, scratch)
        }
        PlanSolver::Method(m) => (0, 0, solve_linear_scratch_len(m, n)),
    };
    let mesh = PlanCounts {
        nodes: n,
        edges: e,
        boundary: b,
        elements: spec.elements.map(|el| (el.len(), el.nodes().len())),
    };
    Ok(Counts::of(
        &mesh,
        D,
        spec.method,
        kind,
        (amg_index, amg_values),
        scratch,
    ))
}

/// The exact pool sizes.
pub(super) fn sizes<T: Real, const D: usize>(
    spec: &PlanSpec<'_, T, D>,
    work: &mut PlanWork<'_, T>,
) -> Result<(PlanSizes, Counts)> {
    let counts = prepare(spec, work)?;
    let sec = Sections::new(&counts)?;
    Ok((sec.sizes, counts))
}

/// Copies `src` into `dst[range]`.
fn put<X: Copy>(dst: &mut [X], range: core::ops::Range<usize>, src: &[X]) {
    if let Some(d) = dst.get_mut(range) {
        for (a, b) in d.iter_mut().zip(src) {
            *a = *b;
        }
    }
}

/// Fills the pools (see [`Plan::init`](super::Plan::init)).
pub(super) fn init<T: Real, const D: usize>(
    spec: &PlanSpec<'_, T, D>,
    work: &mut PlanWork<'_, T>,
    reals: &mut [T],
    indices: &mut [u32],
    bytes: &mut [u8],
) -> Result<()> {
    let (sizes, counts) = sizes(spec, work)?;
    for (arg, have, needed) in [
        ("reals", reals.len(), sizes.reals),
        ("indices", indices.len(), sizes.indices),
        ("bytes", bytes.len(), sizes.bytes),
    ] {
        check::buffer(arg, have, needed)?;
    }
    let sec = Sections::new(&counts)?;
    let k_first = spec
        .boundary
        .iter()
        .enumerate()
        .min_by_key(|(_, &node)| node)
        .map_or(0, |(k, _)| k);
    let (_, omega) = solver_kind(&spec.solver);
    let max_iter = spec.options.max_iterations as u64;
    let header: [(usize, u32); 21] = [
        (w::VERSION, layout::VERSION),
        (w::SCALAR, word("T", core::mem::size_of::<T>())?),
        (w::DIM, word("D", D)?),
        (
            w::METHOD,
            match counts.method {
                PlanMethod::Spring => 1,
                PlanMethod::QuaternionSpring => 2,
            },
        ),
        (w::SOLVER, counts.solver as u32),
        (w::N, word("points", counts.n)?),
        (w::E, word("graph", counts.e)?),
        (w::B, word("boundary", counts.b)?),
        (w::HAS_ELEMENTS, u32::from(counts.has_elements)),
        (w::C, word("elements", counts.c)?),
        (w::CN, word("elements", counts.cn)?),
        (w::K_FIRST, word("boundary", k_first)?),
        (w::MAX_ITER_LO, max_iter as u32),
        (w::MAX_ITER_HI, (max_iter >> 32) as u32),
        (w::AMG_INDEX, word("plan", counts.amg_index)?),
        (w::AMG_VALUES, word("plan", counts.amg_values)?),
        (w::SCRATCH, word("plan", counts.scratch)?),
        (w::SLIDING, 0),
        (w::REALS, word("plan", sizes.reals)?),
        (w::INDICES, word("plan", sizes.indices)?),
        (w::BYTES, word("plan", sizes.bytes)?),
    ];
    // Everything is validated: from here on the pools are written. The magic goes last.
    if let Some(h) = indices.get_mut(..HEADER) {
        h.fill(0);
    }
    for (i, x) in header {
        set_hw(indices, i, x);
    }
    put(indices, sec.offs.clone(), spec.graph.offsets());
    put(indices, sec.targets.clone(), spec.graph.targets());
    put(indices, sec.boundary.clone(), spec.boundary);
    if let (true, Some(el)) = (counts.has_elements, &spec.elements) {
        put(indices, sec.cell_offs.clone(), el.offsets());
        put(indices, sec.cell_nodes.clone(), el.nodes());
        put(bytes, sec.cell_kinds.clone(), el.kinds());
    }
    let mask = work.bytes.get(..counts.n).unwrap_or(&[]);
    put(bytes, sec.mask.clone(), mask);
    match &spec.constraints {
        Some(c) => put(bytes, sec.kinds.clone(), c.kinds()),
        None => put(bytes, sec.kinds.clone(), mask),
    }
    if let Some(p) = reals.get_mut(sec.points.clone()) {
        for (d, s) in p.iter_mut().zip(spec.points.iter().flatten()) {
            *d = *s;
        }
    }
    match spec.stiffness {
        PlanStiffness::Given(k) => put(reals, sec.stiffness.clone(), k),
        PlanStiffness::Batina { .. } => put(
            reals,
            sec.stiffness.clone(),
            work.reals.get(..counts.e).unwrap_or(&[]),
        ),
    }
    let mut params = [T::ZERO; layout::PARAMS];
    if let Some(p) = params.get_mut(layout::P_RESIDUAL) {
        *p = spec.options.residual_tol;
    }
    if let Some(p) = params.get_mut(layout::P_UPDATE) {
        *p = spec.options.update_tol;
    }
    if let Some(p) = params.get_mut(layout::P_OMEGA) {
        *p = omega;
    }
    put(reals, sec.params.clone(), &params);
    if let Some(s) = reals.get_mut(sec.state.start..sec.sizes.reals) {
        s.fill(T::ZERO);
    }
    if let PlanSolver::Amg(opts) = &spec.solver {
        let (ilo, ihi) = indices
            .split_at_mut_checked(sec.amg_words.start)
            .unwrap_or_default();
        let (rlo, rhi) = reals
            .split_at_mut_checked(sec.amg_weights.start)
            .unwrap_or_default();
        let graph = Graph::trusted(
            ilo.get(sec.offs.clone()).unwrap_or(&[]),
            ilo.get(sec.targets.clone()).unwrap_or(&[]),
        );
        let stiffness = rlo.get(sec.stiffness.clone()).unwrap_or(&[]);
        let mask = bytes.get(sec.mask.clone()).unwrap_or(&[]);
        let sys = SpringSystem::trusted(graph, stiffness, mask);
        let (words, amg_index) = ihi
            .split_at_mut_checked(sec.amg_words.len())
            .unwrap_or_default();
        let (weights, amg_values) = rhi
            .split_at_mut_checked(sec.amg_weights.len())
            .unwrap_or_default();
        let h = AmgHierarchy::setup(&sys, opts, work.indices, amg_index, amg_values)?;
        let (layout, wts, sweeps) = h.parts();
        layout::write_amg_words(&layout, sweeps, words)?;
        for (d, s) in weights.iter_mut().zip(wts.iter().flatten()) {
            *d = *s;
        }
    }
    set_hw(indices, w::MAGIC, layout::MAGIC);
    let sum = layout::checksum(&sec, reals, indices, bytes);
    set_hw(indices, w::SUM_LO, sum as u32);
    set_hw(indices, w::SUM_HI, (sum >> 32) as u32);
    Ok(())
}
