//! Building a plan: validate the spec once, size the pools, fill them.

use super::layout::{self, order_code, set_hw, w, word, Counts, Sections, SolverKind, HEADER};
use super::order::{inverse_of, mesh, ordered_words, to_caller, Mesh};
use super::{
    PlanCounts, PlanMethod, PlanOrder, PlanSizes, PlanSolver, PlanSpec, PlanStiffness, PlanWork,
};
use crate::check;
use crate::error::{Error, Result};
use crate::graph::Graph;
use crate::quaternion::check_elements;
use crate::real::Real;
use crate::spring::constraints::NodeKind;
use crate::spring::{
    amg_cg_scratch_len, amg_setup_work_len, check_omega, solve_linear_scratch_len, AmgHierarchy,
    LinearMethod, Preconditioner, SpringSystem,
};

/// Transient work lengths.
pub(super) fn work_sizes<T: Real, const D: usize>(spec: &PlanSpec<'_, T, D>) -> PlanSizes {
    work_sizes_of(
        spec.graph.node_count(),
        spec.graph.edge_count(),
        D,
        spec.renumber,
    )
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
/// bytes (the fixed mask). Renumbered (`order`), `n d` reals more (the permuted points) and
/// [`ordered_words`] indices more before the scratch (which then holds at least `2 n`, the
/// Hilbert keys). Saturating: a size that overflows is refused by the buffer checks.
pub(super) const fn work_sizes_of(n: usize, e: usize, d: usize, order: PlanOrder) -> PlanSizes {
    let amg = amg_setup_work_len(n, e);
    let scratch = if amg > n { amg } else { n };
    match order {
        PlanOrder::AsGiven => PlanSizes {
            reals: e,
            indices: scratch,
            bytes: n,
        },
        PlanOrder::Rcm | PlanOrder::Hilbert => {
            let keys = n.saturating_mul(2);
            PlanSizes {
                reals: e.saturating_add(n.saturating_mul(d)),
                indices: ordered_words(n, e).saturating_add(if scratch > keys {
                    scratch
                } else {
                    keys
                }),
                bytes: n,
            }
        }
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
    order: PlanOrder,
) -> Option<PlanSizes> {
    let counts = Counts::of(
        counts,
        (d, method, order),
        SolverKind::of_method(solver),
        (0, 0),
        solve_linear_scratch_len(solver, counts.nodes),
    );
    match Sections::layout(&counts) {
        Ok(s) => Some(s.sizes),
        Err(_) => None,
    }
}

/// The fixed mask of the boundary list in the caller's numbering into `mask` (`N` bytes),
/// with the boundary's range and duplicate checks and the constraint table's.
fn fixed_mask<T: Real, const D: usize>(spec: &PlanSpec<'_, T, D>, mask: &mut [u8]) -> Result<()> {
    let n = mask.len();
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
    Ok(())
}

/// Validates the spec; returns the counts (with the hierarchy's exact sizes) and the mesh in
/// the plan's numbering (in `work` where computed: stiffness, fixed mask, permuted parts).
fn prepare<'m, T: Real, const D: usize>(
    spec: &PlanSpec<'m, T, D>,
    work: &'m mut PlanWork<'_, T>,
) -> Result<(Counts, Mesh<'m, T, D>)> {
    check::mesh_dim::<D>();
    let n = spec.graph.node_count();
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
    fixed_mask(spec, work.bytes.get_mut(..n).unwrap_or(&mut []))?;
    if let (Some(el), PlanMethod::QuaternionSpring) = (&spec.elements, spec.method) {
        check_elements::<D>(el, b)?;
    }
    spec.options.check()?;
    let (kind, omega) = solver_kind(&spec.solver);
    if matches!(kind, SolverKind::Sor | SolverKind::CgSsor) {
        check_omega(omega)?;
    }
    let m = mesh(spec, work)?;
    let sys = SpringSystem::new(m.graph, m.stiffness, m.mask, m.scratch)
        .map_err(|err| to_caller(err, m.perm, m.edge_map, true))?;
    let (amg_index, amg_values, scratch) = match &spec.solver {
        PlanSolver::Amg(opts) => {
            let s = AmgHierarchy::setup_len(&sys, opts, m.scratch)?;
            let scratch = amg_cg_scratch_len(n, s.coarse_unknowns).unwrap_or(usize::MAX);
            (s.index, s.values, scratch)
        }
        PlanSolver::Method(m) => (0, 0, solve_linear_scratch_len(m, n)),
    };
    let mesh_counts = PlanCounts {
        nodes: n,
        edges: spec.graph.edge_count(),
        boundary: b,
        elements: spec.elements.map(|el| (el.len(), el.nodes().len())),
    };
    let counts = Counts::of(
        &mesh_counts,
        (D, spec.method, spec.renumber),
        kind,
        (amg_index, amg_values),
        scratch,
    );
    Ok((counts, m))
}

/// The exact pool sizes.
pub(super) fn sizes<T: Real, const D: usize>(
    spec: &PlanSpec<'_, T, D>,
    work: &mut PlanWork<'_, T>,
) -> Result<(PlanSizes, Counts)> {
    let (counts, _) = prepare(spec, work)?;
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
    let (counts, mesh) = prepare(spec, work)?;
    let sec = Sections::new(&counts)?;
    let sizes = sec.sizes;
    for (arg, have, needed) in [
        ("reals", reals.len(), sizes.reals),
        ("indices", indices.len(), sizes.indices),
        ("bytes", bytes.len(), sizes.bytes),
    ] {
        check::buffer(arg, have, needed)?;
    }
    // The boundary nodes in the plan's numbering.
    let node = |old: u32| mesh.perm.map_or(Some(old), |p| inverse_of(p, old));
    let k_first = spec
        .boundary
        .iter()
        .enumerate()
        .min_by_key(|(_, &old)| node(old))
        .map_or(0, |(k, _)| k);
    let header = header::<T, D>(spec, &counts, k_first)?;
    // Everything is validated: from here on the pools are written. The magic goes last.
    if let Some(h) = indices.get_mut(..HEADER) {
        h.fill(0);
    }
    for (i, x) in header {
        set_hw(indices, i, x);
    }
    store_mesh(spec, &mesh, &sec, (reals, indices, bytes));
    if let Some(b) = indices.get_mut(sec.boundary.clone()) {
        for (d, &old) in b.iter_mut().zip(spec.boundary) {
            *d = node(old).unwrap_or(old);
        }
    }
    if let PlanSolver::Amg(opts) = &spec.solver {
        store_amg(opts, &sec, mesh.scratch, (reals, indices, bytes))?;
    }
    set_hw(indices, w::MAGIC, layout::MAGIC);
    let sum = layout::checksum(&sec, reals, indices, bytes);
    set_hw(indices, w::SUM_LO, sum as u32);
    set_hw(indices, w::SUM_HI, (sum >> 32) as u32);
    Ok(())
}

/// The header words of a plan with these counts (all but magic and checksum).
fn header<T: Real, const D: usize>(
    spec: &PlanSpec<'_, T, D>,
    counts: &Counts,
    k_first: usize,
) -> Result<[(usize, u32); 22]> {
    let sec = Sections::new(counts)?;
    let max_iter = spec.options.max_iterations as u64;
    Ok([
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
        (w::REALS, word("plan", sec.sizes.reals)?),
        (w::INDICES, word("plan", sec.sizes.indices)?),
        (w::BYTES, word("plan", sec.sizes.bytes)?),
        (w::ORDER, order_code(counts.order)),
    ])
}

/// Copies the mesh (in the plan's numbering), the constraint kinds, the permutation and the
/// parameters into the pools and zeroes the state (the boundary list is written by the
/// caller).
fn store_mesh<T: Real, const D: usize>(
    spec: &PlanSpec<'_, T, D>,
    mesh: &Mesh<'_, T, D>,
    sec: &Sections,
    (reals, indices, bytes): (&mut [T], &mut [u32], &mut [u8]),
) {
    put(indices, sec.offs.clone(), mesh.graph.offsets());
    put(indices, sec.targets.clone(), mesh.graph.targets());
    if let (Some(el), PlanMethod::QuaternionSpring) = (&spec.elements, spec.method) {
        put(indices, sec.cell_offs.clone(), el.offsets());
        put(indices, sec.cell_nodes.clone(), el.nodes());
        put(bytes, sec.cell_kinds.clone(), el.kinds());
    }
    if let Some(p) = mesh.perm {
        let n = p.len();
        put(indices, sec.perm.start..sec.perm.start + n, p.order());
        put(indices, sec.perm.start + n..sec.perm.end, p.inverse());
    }
    put(bytes, sec.mask.clone(), mesh.mask);
    match (
        &spec.constraints,
        mesh.perm,
        bytes.get_mut(sec.kinds.clone()),
    ) {
        (Some(c), Some(p), Some(kinds)) => {
            for (d, &old) in kinds.iter_mut().zip(p.order()) {
                *d = c.kinds().get(old as usize).copied().unwrap_or(0);
            }
        }
        (Some(c), None, Some(kinds)) => put(kinds, 0..kinds.len(), c.kinds()),
        (None, _, Some(kinds)) => put(kinds, 0..kinds.len(), mesh.mask),
        (_, _, None) => {}
    }
    if let Some(p) = reals.get_mut(sec.points.clone()) {
        for (d, s) in p.iter_mut().zip(mesh.points.iter().flatten()) {
            *d = *s;
        }
    }
    put(reals, sec.stiffness.clone(), mesh.stiffness);
    let (_, omega) = solver_kind(&spec.solver);
    let mut params = [T::ZERO; layout::PARAMS];
    for (i, x) in [
        (layout::P_RESIDUAL, spec.options.residual_tol),
        (layout::P_UPDATE, spec.options.update_tol),
        (layout::P_OMEGA, omega),
    ] {
        if let Some(p) = params.get_mut(i) {
            *p = x;
        }
    }
    put(reals, sec.params.clone(), &params);
    if let Some(s) = reals.get_mut(sec.state.start..sec.sizes.reals) {
        s.fill(T::ZERO);
    }
}

/// Sets the hierarchy up on the stored system (graph, stiffness and mask in the pools).
fn store_amg<T: Real>(
    opts: &crate::spring::AmgOptions<T>,
    sec: &Sections,
    scratch: &mut [u32],
    (reals, indices, bytes): (&mut [T], &mut [u32], &mut [u8]),
) -> Result<()> {
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
    let h = AmgHierarchy::setup(&sys, opts, scratch, amg_index, amg_values)?;
    let (layout, wts, sweeps) = h.parts();
    layout::write_amg_words(&layout, sweeps, words)?;
    for (d, s) in weights.iter_mut().zip(wts.iter().flatten()) {
        *d = *s;
    }
    Ok(())
}
