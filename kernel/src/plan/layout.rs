//! The plan's storage format: header words, the sections of the three pools (a pure function
//! of the counts in the header, so no offset is stored), the checksum and [`open`].

use core::ops::Range;

use super::{PlanCounts, PlanMethod, PlanOrder, PlanSizes, AMG_LAYOUT_WORDS, AMG_WEIGHTS};
use crate::error::{Error, Result};
use crate::real::Real;
use crate::spring::{
    amg_cg_scratch_len, Layout, Level, LinearMethod, Preconditioner, AMG_MAX_LEVELS, AMG_MAX_SWEEPS,
};

/// `"DPLN"` (deform plan), little end first.
pub(super) const MAGIC: u32 = 0x4E4C_5044;
/// Format version; bump on any layout change.
pub(super) const VERSION: u32 = 1;
/// Header words at the start of the index pool.
pub(super) const HEADER: usize = 48;

/// Header word positions.
pub(super) mod w {
    pub const MAGIC: usize = 0;
    pub const VERSION: usize = 1;
    pub const SCALAR: usize = 2;
    pub const DIM: usize = 3;
    pub const METHOD: usize = 4;
    pub const SOLVER: usize = 5;
    pub const N: usize = 6;
    pub const E: usize = 7;
    pub const B: usize = 8;
    pub const HAS_ELEMENTS: usize = 9;
    pub const C: usize = 10;
    pub const CN: usize = 11;
    pub const K_FIRST: usize = 12;
    pub const MAX_ITER_LO: usize = 13;
    pub const MAX_ITER_HI: usize = 14;
    pub const AMG_INDEX: usize = 15;
    pub const AMG_VALUES: usize = 16;
    pub const SCRATCH: usize = 17;
    /// Reserved for sliding constraints (0: free/fixed only).
    pub const SLIDING: usize = 18;
    pub const REALS: usize = 19;
    pub const INDICES: usize = 20;
    pub const BYTES: usize = 21;
    /// The node order (0: the caller's, 1: RCM, 2: Hilbert); 0 in every plan built before
    /// the option, so their header and checksum are unchanged.
    pub const ORDER: usize = 22;
    /// Words `0..CHECKED` are covered by the checksum.
    pub const CHECKED: usize = 40;
    pub const SUM_LO: usize = 40;
    pub const SUM_HI: usize = 41;
    /// Mutable state (not checksummed): solutions stored (0, 1, 2), steps.
    pub const HAS_STATE: usize = 42;
    pub const STEPS_LO: usize = 43;
    pub const STEPS_HI: usize = 44;
}

/// Real parameters stored in the `params` section.
pub(super) const PARAMS: usize = 4;
/// `params[0]`: residual tolerance, `[1]`: update tolerance, `[2]`: ω (SOR / SSOR).
pub(super) const P_RESIDUAL: usize = 0;
pub(super) const P_UPDATE: usize = 1;
pub(super) const P_OMEGA: usize = 2;

/// The linear-spring solver, as stored.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum SolverKind {
    Jacobi = 1,
    GaussSeidel = 2,
    Sor = 3,
    CgNone = 4,
    CgJacobi = 5,
    CgSsor = 6,
    Amg = 7,
}

impl SolverKind {
    /// The stored code of a one-level method.
    pub(super) const fn of_method<T>(m: &LinearMethod<T>) -> Self {
        match m {
            LinearMethod::Jacobi => SolverKind::Jacobi,
            LinearMethod::GaussSeidel => SolverKind::GaussSeidel,
            LinearMethod::Sor { .. } => SolverKind::Sor,
            LinearMethod::Cg { preconditioner } => match preconditioner {
                Preconditioner::None => SolverKind::CgNone,
                Preconditioner::Jacobi => SolverKind::CgJacobi,
                Preconditioner::Ssor { .. } => SolverKind::CgSsor,
            },
        }
    }

    fn from_code(c: u32) -> Option<Self> {
        Some(match c {
            1 => SolverKind::Jacobi,
            2 => SolverKind::GaussSeidel,
            3 => SolverKind::Sor,
            4 => SolverKind::CgNone,
            5 => SolverKind::CgJacobi,
            6 => SolverKind::CgSsor,
            7 => SolverKind::Amg,
            _ => return None,
        })
    }
}

/// The stored code of a node order (header word [`w::ORDER`]).
pub(super) const fn order_code(o: PlanOrder) -> u32 {
    match o {
        PlanOrder::AsGiven => 0,
        PlanOrder::Rcm => 1,
        PlanOrder::Hilbert => 2,
    }
}

/// The counts a layout is computed from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct Counts {
    pub method: PlanMethod,
    pub solver: SolverKind,
    pub d: usize,
    pub n: usize,
    pub e: usize,
    pub b: usize,
    pub has_elements: bool,
    pub c: usize,
    pub cn: usize,
    pub amg_index: usize,
    pub amg_values: usize,
    /// Solver scratch items of `V` values.
    pub scratch: usize,
    /// The node order (a renumbered plan stores its permutation).
    pub order: PlanOrder,
}

impl Counts {
    /// The counts of a plan over `mesh`: its elements count only for the quaternion method
    /// (the one rule both [`Plan::sizes`](super::Plan::sizes) and
    /// [`Plan::capacity`](super::Plan::capacity) size by). `amg` is the hierarchy's (index,
    /// values) lengths, `scratch` the solver's scratch items.
    pub(super) const fn of(
        mesh: &PlanCounts,
        (d, method, order): (usize, PlanMethod, PlanOrder),
        solver: SolverKind,
        amg: (usize, usize),
        scratch: usize,
    ) -> Self {
        let (has_elements, c, cn) = match (mesh.elements, method) {
            (Some((c, cn)), PlanMethod::QuaternionSpring) => (true, c, cn),
            _ => (false, 0, 0),
        };
        Counts {
            method,
            solver,
            d,
            n: mesh.nodes,
            e: mesh.edges,
            b: mesh.boundary,
            has_elements,
            c,
            cn,
            amg_index: amg.0,
            amg_values: amg.1,
            scratch,
            order,
        }
    }

    /// Whether the plan stores a permutation.
    pub const fn ordered(&self) -> bool {
        !matches!(self.order, PlanOrder::AsGiven)
    }

    /// Values per node of the solve.
    pub const fn v(&self) -> usize {
        match self.method {
            PlanMethod::Spring => self.d,
            PlanMethod::QuaternionSpring => self.d.saturating_add(4),
        }
    }

    const fn quaternion(&self) -> bool {
        matches!(self.method, PlanMethod::QuaternionSpring)
    }
}

/// Where every section lives.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub(super) struct Sections {
    // index pool
    pub offs: Range<usize>,
    pub targets: Range<usize>,
    pub boundary: Range<usize>,
    pub cell_offs: Range<usize>,
    pub cell_nodes: Range<usize>,
    pub amg_words: Range<usize>,
    pub amg_index: Range<usize>,
    /// `order` then `inverse` (`2 N`) of a renumbered plan, empty otherwise.
    pub perm: Range<usize>,
    // byte pool
    pub kinds: Range<usize>,
    pub mask: Range<usize>,
    pub cell_kinds: Range<usize>,
    // real pool: immutable
    pub points: Range<usize>,
    pub stiffness: Range<usize>,
    pub params: Range<usize>,
    pub directions: Range<usize>,
    pub amg_weights: Range<usize>,
    pub amg_values: Range<usize>,
    // real pool: state
    pub state: Range<usize>,
    pub state_ref: Range<usize>,
    pub state2: Range<usize>,
    pub state2_ref: Range<usize>,
    // real pool: step workspaces
    pub work: Range<usize>,
    pub scratch: Range<usize>,
    pub rot: Range<usize>,
    pub bq: Range<usize>,
    pub sizes: PlanSizes,
}

/// Hands out the next `len` entries of a pool whose cursor is `$cur` (a `usize` variable):
/// the range, or `Err(usize::MAX)` from the enclosing function on overflow. A macro, not a
/// method, so [`Sections::layout`] stays a `const fn`.
macro_rules! take {
    ($cur:ident, $len:expr) => {{
        let end = match $len {
            Some(len) => $cur.checked_add(len),
            None => None,
        };
        match end {
            Some(end) => {
                let r = $cur..end;
                $cur = end;
                r
            }
            None => return Err(usize::MAX),
        }
    }};
}

impl Sections {
    /// The layout for `c` (fails only on arithmetic overflow).
    pub fn new(c: &Counts) -> Result<Self> {
        Sections::layout(c).map_err(|value| Error::TooLarge { arg: "plan", value })
    }

    /// The layout for `c`, or the first size that does not fit (`usize::MAX` on arithmetic
    /// overflow, or a pool length beyond `u32`). `const`, so [`Plan::capacity`](super::Plan::capacity)
    /// sizes static storage at compile time from the same arithmetic `init` uses.
    pub(super) const fn layout(c: &Counts) -> core::result::Result<Self, usize> {
        let amg = matches!(c.solver, SolverKind::Amg);
        let q = c.quaternion();
        let v = c.v();
        let el = q && c.has_elements;
        let mut i = HEADER;
        let offs = take!(i, c.n.checked_add(1));
        let targets = take!(i, Some(c.e));
        let boundary = take!(i, Some(c.b));
        let cell_offs = take!(i, if el { c.c.checked_add(1) } else { Some(0) });
        let cell_nodes = take!(i, Some(if el { c.cn } else { 0 }));
        let amg_words = take!(i, Some(if amg { AMG_LAYOUT_WORDS } else { 0 }));
        let amg_index = take!(i, Some(if amg { c.amg_index } else { 0 }));
        let perm = take!(
            i,
            if c.ordered() {
                c.n.checked_mul(2)
            } else {
                Some(0)
            }
        );
        let mut y: usize = 0;
        let kinds = take!(y, Some(c.n));
        let mask = take!(y, Some(c.n));
        let cell_kinds = take!(y, Some(if el { c.c } else { 0 }));
        let mut r: usize = 0;
        let points = take!(r, c.n.checked_mul(c.d));
        let stiffness = take!(r, Some(c.e));
        let params = take!(r, Some(PARAMS));
        let directions = take!(r, Some(0));
        let amg_weights = take!(r, Some(if amg { AMG_WEIGHTS } else { 0 }));
        let amg_values = take!(r, Some(if amg { c.amg_values } else { 0 }));
        let state = take!(r, c.n.checked_mul(v));
        let state_ref = take!(r, Some(4));
        let state2 = take!(r, c.n.checked_mul(v));
        let state2_ref = take!(r, Some(4));
        let work = take!(r, c.n.checked_mul(v));
        let scratch = take!(r, c.scratch.checked_mul(v));
        let rot = take!(
            r,
            if el {
                c.b.checked_mul(if c.d == 2 { 3 } else { 13 })
            } else {
                Some(0)
            }
        );
        let bq = take!(r, if q { c.b.checked_mul(4) } else { Some(0) });
        // Every count is stored in one u32 header word.
        let sizes = PlanSizes {
            reals: r,
            indices: i,
            bytes: y,
        };
        if r > u32::MAX as usize {
            return Err(r);
        }
        if i > u32::MAX as usize {
            return Err(i);
        }
        if y > u32::MAX as usize {
            return Err(y);
        }
        Ok(Sections {
            offs,
            targets,
            boundary,
            cell_offs,
            cell_nodes,
            amg_words,
            amg_index,
            perm,
            kinds,
            mask,
            cell_kinds,
            points,
            stiffness,
            params,
            directions,
            amg_weights,
            amg_values,
            state,
            state_ref,
            state2,
            state2_ref,
            work,
            scratch,
            rot,
            bq,
            sizes,
        })
    }

    /// End of the immutable real sections (checksummed).
    pub fn reals_fixed_end(&self) -> usize {
        self.amg_values.end
    }
}

/// The parsed header.
#[derive(Clone, Debug)]
pub(super) struct Meta {
    pub counts: Counts,
    pub sec: Sections,
    pub sizes: PlanSizes,
    pub method: PlanMethod,
    pub solver: SolverKind,
    pub n: usize,
    pub b: usize,
    pub k_first: usize,
    pub max_iterations: usize,
    /// Solutions stored (0, 1 or 2: the last and the one before).
    pub stored: u32,
    pub steps: u64,
}

/// The hierarchy's small parts kept beside its buffers.
#[derive(Clone, Copy, Debug)]
pub(super) struct AmgParts<T> {
    pub layout: Layout,
    pub weights: [[T; AMG_MAX_SWEEPS]; AMG_MAX_LEVELS],
    pub sweeps: usize,
}

/// 64-bit FNV-1a over 32-bit words.
#[derive(Clone, Copy)]
pub(super) struct Checksum(u64);

impl Checksum {
    pub fn new() -> Self {
        Checksum(0xcbf2_9ce4_8422_2325)
    }

    #[inline]
    pub fn word(&mut self, x: u32) {
        self.0 = (self.0 ^ u64::from(x)).wrapping_mul(0x0000_0100_0000_01b3);
    }

    pub fn words(&mut self, xs: &[u32]) {
        for &x in xs {
            self.word(x);
        }
    }

    pub fn bytes(&mut self, xs: &[u8]) {
        for &x in xs {
            self.word(u32::from(x));
        }
    }

    pub fn reals<T: Real>(&mut self, xs: &[T]) {
        for &x in xs {
            let b = x.to_bits_u64();
            self.word(b as u32);
            self.word((b >> 32) as u32);
        }
    }

    pub fn value(self) -> u64 {
        self.0
    }
}

/// The checksum of a plan's immutable parts.
pub(super) fn checksum<T: Real>(sec: &Sections, reals: &[T], indices: &[u32], bytes: &[u8]) -> u64 {
    let mut h = Checksum::new();
    h.words(indices.get(..w::CHECKED).unwrap_or(&[]));
    h.words(indices.get(HEADER..sec.sizes.indices).unwrap_or(&[]));
    h.bytes(bytes.get(..sec.sizes.bytes).unwrap_or(&[]));
    h.reals(reals.get(..sec.reals_fixed_end()).unwrap_or(&[]));
    h.value()
}

/// Header word `i` (0 when out of range).
#[inline]
pub(super) fn hw(indices: &[u32], i: usize) -> u32 {
    indices.get(i).copied().unwrap_or(0)
}

/// Writes header word `i`.
#[inline]
pub(super) fn set_hw(indices: &mut [u32], i: usize, x: u32) {
    if let Some(s) = indices.get_mut(i) {
        *s = x;
    }
}

/// `x` as a `u32` header word.
pub(super) fn word(arg: &'static str, x: usize) -> Result<u32> {
    u32::try_from(x).map_err(|_| Error::TooLarge { arg, value: x })
}

/// The fields of one level, in storage order.
fn level_fields(l: &Level) -> [usize; 14] {
    [
        l.n, l.diag, l.a_offs, l.a_cols, l.a_nnz, l.a_vals, l.agg, l.p_offs, l.p_cols, l.p_nnz,
        l.p_vals, l.pt_offs, l.pt_rows, l.pt_pos,
    ]
}

/// Serialises a hierarchy's layout and sweep count into `out` ([`AMG_LAYOUT_WORDS`] words).
pub(super) fn write_amg_words(layout: &Layout, sweeps: usize, out: &mut [u32]) -> Result<()> {
    let mut it = out.iter_mut();
    let mut put = |x: usize| -> Result<()> {
        let v = word("plan", x)?;
        if let Some(s) = it.next() {
            *s = v;
        }
        Ok(())
    };
    for l in layout.levels.iter() {
        for x in level_fields(l) {
            put(x)?;
        }
    }
    for x in [
        layout.count,
        layout.index_len,
        layout.values_len,
        layout.dense,
        layout.dense_n,
        layout.acc,
        layout.acc_len,
        layout.nodes,
        layout.edges,
        sweeps,
        0,
    ] {
        put(x)?;
    }
    Ok(())
}

/// Inverse of [`write_amg_words`] (no checks here; see [`check_amg`]).
fn read_amg_words(words: &[u32]) -> (Layout, usize) {
    let mut it = words.iter().map(|&x| x as usize);
    let mut next = || it.next().unwrap_or(0);
    let mut levels = [Level::default(); AMG_MAX_LEVELS];
    for l in levels.iter_mut() {
        *l = Level {
            n: next(),
            diag: next(),
            a_offs: next(),
            a_cols: next(),
            a_nnz: next(),
            a_vals: next(),
            agg: next(),
            p_offs: next(),
            p_cols: next(),
            p_nnz: next(),
            p_vals: next(),
            pt_offs: next(),
            pt_rows: next(),
            pt_pos: next(),
        };
    }
    let layout = Layout {
        levels,
        count: next(),
        index_len: next(),
        values_len: next(),
        dense: next(),
        dense_n: next(),
        acc: next(),
        acc_len: next(),
        nodes: next(),
        edges: next(),
    };
    let sweeps = next();
    (layout, sweeps)
}

/// Bad-plan error.
fn bad(reason: &'static str) -> Error {
    Error::BadPlan { reason }
}

/// `start + len <= bound` without overflow.
fn within(start: usize, len: usize, bound: usize) -> bool {
    start.checked_add(len).is_some_and(|e| e <= bound)
}

/// Structural checks of a stored hierarchy layout (every array inside its buffer), so that a
/// plan whose checksum was forged still cannot index outside the hierarchy's buffers in a
/// meaningful way (every access is bounds-checked anyway).
fn check_amg(layout: &Layout, sweeps: usize, c: &Counts) -> Result<()> {
    if layout.count == 0 || layout.count > AMG_MAX_LEVELS {
        return Err(bad("multigrid level count out of range"));
    }
    if sweeps == 0 || sweeps > AMG_MAX_SWEEPS {
        return Err(bad("multigrid sweep count out of range"));
    }
    if layout.index_len != c.amg_index || layout.values_len != c.amg_values {
        return Err(bad("multigrid buffer sizes disagree with the header"));
    }
    if layout.nodes != c.n || layout.edges != c.e {
        return Err(bad("multigrid hierarchy built for another graph"));
    }
    let vi = layout.index_len;
    let vv = layout.values_len;
    for (i, l) in layout.levels.iter().take(layout.count).enumerate() {
        let n1 = l.n.saturating_add(1);
        // Every level has a diagonal and off-diagonal entries (level 0 reads its operator
        // from the system: a_nnz 0); all but the coarsest an aggregate map and a
        // prolongator (the coarsest has none: a one-level hierarchy is its fine level).
        let coarsest = i + 1 == layout.count;
        let ok = within(l.diag, l.n, vv)
            && within(l.a_vals, l.a_nnz, vv)
            && within(l.a_cols, l.a_nnz, vi)
            && (coarsest
                || within(l.p_vals, l.p_nnz, vv)
                    && within(l.agg, l.n, vi)
                    && within(l.p_offs, n1, vi)
                    && within(l.p_cols, l.p_nnz, vi)
                    && within(l.pt_rows, l.p_nnz, vi)
                    && within(l.pt_pos, l.p_nnz, vi));
        if !ok {
            return Err(bad("multigrid level outside its buffers"));
        }
    }
    if !within(
        layout.dense,
        layout.dense_n.saturating_mul(layout.dense_n),
        vv,
    ) || !within(layout.acc, layout.acc_len, vv)
    {
        return Err(bad("multigrid coarse factor outside its buffers"));
    }
    let coarse = layout.coarse_unknowns();
    if c.scratch != amg_cg_scratch_len(c.n, coarse).unwrap_or(usize::MAX) {
        return Err(bad("solver scratch size disagrees with the hierarchy"));
    }
    Ok(())
}

/// Parses and checks a plan's pools (see [`Plan::open`](super::Plan::open)).
pub(super) fn open<T: Real, const D: usize>(
    reals: &[T],
    indices: &[u32],
    bytes: &[u8],
) -> Result<(Meta, Option<AmgParts<T>>)> {
    if indices.len() < HEADER {
        return Err(bad("index pool shorter than the header"));
    }
    let h = |i| hw(indices, i) as usize;
    if hw(indices, w::MAGIC) != MAGIC {
        return Err(bad("no plan magic"));
    }
    if hw(indices, w::VERSION) != VERSION {
        return Err(bad("unsupported plan version"));
    }
    if h(w::SCALAR) != core::mem::size_of::<T>() {
        return Err(bad("plan built for another scalar type"));
    }
    if h(w::DIM) != D {
        return Err(bad("plan built for another dimension"));
    }
    let method = match hw(indices, w::METHOD) {
        1 => PlanMethod::Spring,
        2 => PlanMethod::QuaternionSpring,
        _ => return Err(bad("unknown method code")),
    };
    let solver = SolverKind::from_code(hw(indices, w::SOLVER)).ok_or(bad("unknown solver code"))?;
    let has_elements = match hw(indices, w::HAS_ELEMENTS) {
        0 => false,
        1 => true,
        _ => return Err(bad("bad elements flag")),
    };
    if hw(indices, w::SLIDING) != 0 {
        return Err(bad("sliding constraints are not supported by this version"));
    }
    let counts = Counts {
        method,
        solver,
        d: D,
        n: h(w::N),
        e: h(w::E),
        b: h(w::B),
        has_elements,
        c: h(w::C),
        cn: h(w::CN),
        amg_index: h(w::AMG_INDEX),
        amg_values: h(w::AMG_VALUES),
        scratch: h(w::SCRATCH),
        order: match hw(indices, w::ORDER) {
            0 => PlanOrder::AsGiven,
            1 => PlanOrder::Rcm,
            2 => PlanOrder::Hilbert,
            _ => return Err(bad("unknown node order code")),
        },
    };
    let sec = Sections::new(&counts).map_err(|_| bad("counts overflow"))?;
    let sizes = sec.sizes;
    if h(w::REALS) != sizes.reals || h(w::INDICES) != sizes.indices || h(w::BYTES) != sizes.bytes {
        return Err(bad("stored pool sizes disagree with the counts"));
    }
    if reals.len() < sizes.reals || indices.len() < sizes.indices || bytes.len() < sizes.bytes {
        return Err(bad("a pool is shorter than the plan"));
    }
    if counts.b == 0 || counts.b > counts.n || h(w::K_FIRST) >= counts.b {
        return Err(bad("bad boundary counts"));
    }
    let stored = u64::from(hw(indices, w::SUM_LO)) | (u64::from(hw(indices, w::SUM_HI)) << 32);
    if checksum(&sec, reals, indices, bytes) != stored {
        return Err(bad("checksum mismatch"));
    }
    let stored = hw(indices, w::HAS_STATE);
    if stored > 2 {
        return Err(bad("bad state flag"));
    }
    for (r, needed) in [
        (sec.state.start..sec.state_ref.end, 1),
        (sec.state2.start..sec.state2_ref.end, 2),
    ] {
        let state = reals.get(r).unwrap_or(&[]);
        if stored >= needed && state.iter().any(|x| !x.is_finite()) {
            return Err(bad("stored solution is not finite"));
        }
    }
    if counts.ordered() && super::order::stored(&sec, indices).is_none() {
        return Err(bad("stored node order is not a permutation"));
    }
    let amg = if solver == SolverKind::Amg {
        let (layout, sweeps) = read_amg_words(indices.get(sec.amg_words.clone()).unwrap_or(&[]));
        check_amg(&layout, sweeps, &counts)?;
        let mut weights = [[T::ZERO; AMG_MAX_SWEEPS]; AMG_MAX_LEVELS];
        let stored = reals.get(sec.amg_weights.clone()).unwrap_or(&[]);
        for (d, s) in weights.iter_mut().flatten().zip(stored) {
            *d = *s;
        }
        Some(AmgParts {
            layout,
            weights,
            sweeps,
        })
    } else {
        None
    };
    let steps = u64::from(hw(indices, w::STEPS_LO)) | (u64::from(hw(indices, w::STEPS_HI)) << 32);
    let max_iterations = (u64::from(hw(indices, w::MAX_ITER_LO))
        | (u64::from(hw(indices, w::MAX_ITER_HI)) << 32))
        .try_into()
        .unwrap_or(usize::MAX);
    Ok((
        Meta {
            counts,
            sizes,
            method,
            solver,
            n: counts.n,
            b: counts.b,
            k_first: h(w::K_FIRST),
            max_iterations,
            stored,
            steps,
            sec,
        },
        amg,
    ))
}
