//! Partition-independent aggregation: a distance-2 maximal independent set (MIS-2) by rounds,
//! then aggregates around its roots, every decision a function of the graph and the global
//! ids alone. A partitioned run ([`aggregate_mis2_partitioned`]) gives every owned node the
//! aggregate the serial run ([`aggregate_mis2`]) gives it, whatever the partition and the
//! ghost depth (docs/amg.md, "Partition-independent aggregation").
//!
//! **Order.** Node keys are `(state, p(g))`, compared lexicographically, with `state` out <
//! undecided < root, `g` the global id and `p` a fixed hash that is a bijection of the 62-bit
//! integers ([`priority`]: xor-shifts and odd multiplications modulo `2^62`), so two nodes
//! never tie. A key is one `u64` (state in the top two bits) and compares as one.
//!
//! **Rounds** (Luby's MIS on the square of the graph, as in Bell, Dalton and Olson 2012):
//! every node takes the largest key over itself and its neighbours (`m1`), then the largest
//! `m1` over itself and its neighbours (`m2`, the largest key within distance 2). An undecided
//! node whose `m2` is a root becomes out; one whose `m2` is itself becomes a root. The
//! undecided node with the globally largest key becomes a root each round, so the rounds end;
//! with hashed keys they are about `log n`. Roots end at distance ≥ 3 from each other and
//! every other active node within distance 2 of a root.
//!
//! **Aggregates.** A root's aggregate is named by its global id. A neighbour of a root joins
//! it (it has exactly one: roots are 3 apart); a node at distance 2 joins, among its
//! neighbours that joined a root, the root with the largest key. Fixed nodes and free nodes
//! without a free neighbour are in no aggregate ([`MIS2_NONE`]), as in the serial hierarchy.
//!
//! **Partitioned.** Owned nodes compute from their rows; ghosts take their owner's `key`,
//! `m1` and aggregate through the halo exchange (two exchanges and one `sum_words` per round,
//! two exchanges at the end), so any ghost depth ≥ 1 gives the same answer.

use crate::check;
use crate::error::{Error, PartitionFault, Result};
use crate::graph::Graph;
use crate::partition::{agree, Exchange, Partition};
use crate::real::Real;

/// "In no aggregate": fixed, or free without a free neighbour.
pub const MIS2_NONE: u64 = u64::MAX;
/// Global ids must be below this (the two top bits of a key hold its state).
const ID_LIMIT: u64 = 1 << 62;
/// Mask of a key's priority (and of a global id).
const ID_MASK: u64 = ID_LIMIT - 1;
/// Key states (the top two bits).
const OUT: u64 = 0;
const UNDECIDED: u64 = 1;
const ROOT: u64 = 2;
/// An aggregate not yet found (phase A) / joined at distance 2 (phase B marker bit).
const PENDING: u64 = u64::MAX - 1;
const JOINED: u64 = ID_LIMIT;
/// Reals per node in a halo exchange: a `u64` as four 16-bit digits (exact in `f32`).
const DIGITS: usize = 4;

/// What an aggregation did.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Mis2Report {
    /// Aggregates (roots), over all processes.
    pub aggregates: u64,
    /// Rounds of the MIS-2.
    pub rounds: u32,
}

/// Length of the `u64` scratch of [`aggregate_mis2`] and [`aggregate_mis2_partitioned`]: two
/// words per local node.
pub const fn mis2_scratch_len(local_count: usize) -> usize {
    local_count.saturating_mul(2)
}

/// Length of the real scratch of [`aggregate_mis2_partitioned`] (the halo exchange's field):
/// four reals per local node.
pub const fn mis2_exchange_len(local_count: usize) -> usize {
    local_count.saturating_mul(DIGITS)
}

/// The priority of global id `g < 2^62`: a bijection of `0..2^62` (each step is one), the
/// splitmix64 finaliser's steps cut to 62 bits.
#[inline]
fn priority(g: u64) -> u64 {
    let mut x = g & ID_MASK;
    x ^= x >> 31;
    x = x.wrapping_mul(0xbf58_476d_1ce4_e5b9) & ID_MASK;
    x ^= x >> 29;
    x = x.wrapping_mul(0x94d0_49bb_1331_11eb) & ID_MASK;
    x ^ (x >> 32)
}

/// The key of global id `g` in `state`.
#[inline]
fn key_of(state: u64, g: u64) -> u64 {
    (state << 62) | priority(g)
}

/// A graph to aggregate: which nodes are free, and the free neighbours of a node.
pub(crate) trait Adjacency {
    /// Whether `i` is free (fixed nodes are in no aggregate and no one's neighbour).
    fn free(&self, i: usize) -> bool;
    /// Calls `f(j)` for every free neighbour `j ≠ i` of `i`.
    fn each(&self, i: usize, f: impl FnMut(usize));
    /// Whether `i` is free with a free neighbour (in the aggregation).
    fn member(&self, i: usize) -> bool {
        let mut any = false;
        self.each(i, |_| any = true);
        self.free(i) && any
    }
}

/// The graph of the public entry points: free neighbours of free nodes.
struct Active<'g> {
    graph: &'g Graph<'g>,
    fixed: &'g [u8],
}

impl Adjacency for Active<'_> {
    #[inline]
    fn free(&self, i: usize) -> bool {
        self.fixed.get(i) == Some(&0)
    }

    #[inline]
    fn each(&self, i: usize, mut f: impl FnMut(usize)) {
        for &j in self.graph.neighbors(i) {
            let j = j as usize;
            if j != i && self.free(j) {
                f(j);
            }
        }
    }
}

/// What the rounds need from the processes: ghosts made equal to their owners, and a global
/// "any" (the serial run has neither to do).
trait Processes {
    /// Every ghost of `v` takes its owner's value.
    fn sync(&mut self, v: &mut [u64]);
    /// Sum over the processes.
    fn total(&mut self, count: u64) -> u64;
}

/// The serial run: no ghosts, one process.
struct Alone;

impl Processes for Alone {
    fn sync(&mut self, _: &mut [u64]) {}
    fn total(&mut self, count: u64) -> u64 {
        count
    }
}

/// A partition's exchanges, `u64`s carried as 16-bit digits in `buf`.
struct Halos<'p, 'a, T, E: ?Sized> {
    part: &'p Partition<'a>,
    exchange: &'p E,
    buf: &'p mut [T],
}

impl<T: Real, E: Exchange<T> + ?Sized> Processes for Halos<'_, '_, T, E> {
    fn sync(&mut self, v: &mut [u64]) {
        let halo = self.part.halo();
        for &i in halo.send_entries() {
            let x = v.get(i as usize).copied().unwrap_or(0);
            let at = (i as usize).saturating_mul(DIGITS);
            for (d, slot) in self.buf.iter_mut().skip(at).take(DIGITS).enumerate() {
                *slot = T::from_u32(((x >> (16 * d)) & 0xffff) as u32);
            }
        }
        self.exchange.exchange(halo, self.buf, DIGITS);
        for &i in halo.receive_entries() {
            let at = (i as usize).saturating_mul(DIGITS);
            let mut x = 0u64;
            for (d, slot) in self.buf.iter().skip(at).take(DIGITS).enumerate() {
                // Saturating cast: a digit out of range cannot wrap into another.
                x |= ((slot.to_f64() as u64) & 0xffff) << (16 * d);
            }
            if let Some(t) = v.get_mut(i as usize) {
                *t = x;
            }
        }
    }

    fn total(&mut self, count: u64) -> u64 {
        let mut w = [count as i64];
        self.exchange.sum_words(&mut w);
        w[0] as u64
    }
}

/// Serial MIS-2 aggregation of the free nodes of `graph` (`fixed[i] != 0`: fixed), with
/// global id = node index: `agg[i]` is the node index of the root of `i`'s aggregate, or
/// [`MIS2_NONE`]. `scratch`: [`mis2_scratch_len`] words.
///
/// # Errors
/// [`Error::LengthMismatch`] when `fixed` or `agg` is not one entry per node,
/// [`Error::BufferTooSmall`] for `scratch`. Only `agg` and `scratch` are written.
pub fn aggregate_mis2(
    graph: &Graph<'_>,
    fixed: &[u8],
    agg: &mut [u64],
    scratch: &mut [u64],
) -> Result<Mis2Report> {
    let n = graph.node_count();
    check::len("fixed", fixed.len(), n)?;
    check::len("agg", agg.len(), n)?;
    check::buffer("scratch", scratch.len(), mis2_scratch_len(n))?;
    let act = Active { graph, fixed };
    run(&act, n, &|i| i as u64, &mut Alone, agg, scratch)
}

/// The partitioned MIS-2 aggregation: on every process, `agg[i]` of every local node (owned
/// and ghost) is the global id of the root of `i`'s aggregate, or [`MIS2_NONE`]: for owned
/// nodes (and ghosts alike) exactly what [`aggregate_mis2`] gives on the whole graph in global
/// numbering. **Collective** over `exchange`.
///
/// `graph` is the local graph (local numbering, as
/// [`PartitionedSprings`](crate::spring::PartitionedSprings) builds it from the local cells):
/// every owned node's row complete, ghosts' rows may be partial. `fixed`: one flag per local
/// node. `scratch`: [`mis2_scratch_len`] words, `reals`: [`mis2_exchange_len`] reals.
///
/// # Errors
/// On every process together (one `sum_words` before any exchange): the length errors of
/// [`aggregate_mis2`] for `graph`, `fixed`, `agg`, `scratch` and `reals`, and
/// [`Error::InvalidParameter`] for a global count past `2^62`, or [`PartitionFault::OtherProcess`].
/// [`PartitionFault::Rows`] when the rounds outlast the global node count (rows that disagree
/// between processes). Only `agg`, `scratch` and `reals` are written.
pub fn aggregate_mis2_partitioned<T: Real, E: Exchange<T> + ?Sized>(
    part: &Partition<'_>,
    graph: &Graph<'_>,
    fixed: &[u8],
    exchange: &E,
    agg: &mut [u64],
    scratch: &mut [u64],
    reals: &mut [T],
) -> Result<Mis2Report> {
    let local = check_lengths(part, graph, fixed, agg.len(), (scratch.len(), reals.len()));
    agree(exchange, local, &mut [0i64; 1])?;
    let act = Active { graph, fixed };
    let ids = part.global_ids();
    let gid = |i: usize| ids.get(i).copied().unwrap_or(0);
    let mut procs = Halos {
        part,
        exchange,
        buf: reals,
    };
    let report = run(&act, part.owned(), &gid, &mut procs, agg, scratch)?;
    let cap = part.global_count().saturating_add(1);
    if u64::from(report.rounds) > cap {
        return Err(crate::partition::fault(PartitionFault::Rows, 0));
    }
    Ok(report)
}

/// `u64` scratch of [`hierarchy_aggregates`] on `n` nodes: keys, `m1` and root ids.
pub(crate) const fn hierarchy_scratch_len(n: usize) -> usize {
    n.saturating_mul(3)
}

/// The MIS-2 aggregation of one hierarchy level (serial, global id = node index) as the
/// hierarchy numbers aggregates: `agg[i]` in `0..nc` by increasing root index, or `none`.
/// Returns `nc`; 0 when `scratch` is shorter than [`hierarchy_scratch_len`].
#[inline(never)]
pub(crate) fn hierarchy_aggregates<A: Adjacency>(
    adj: &A,
    agg: &mut [u32],
    none: u32,
    scratch: &mut [u64],
) -> usize {
    let n = agg.len();
    let Some(scratch) = scratch.get_mut(..hierarchy_scratch_len(n)) else {
        return 0;
    };
    let (work, roots) = scratch.split_at_mut(mis2_scratch_len(n));
    if run(adj, n, &|i| i as u64, &mut Alone, roots, work).is_err() {
        return 0;
    }
    let mut nc = 0u32;
    for (i, (a, &r)) in agg.iter_mut().zip(roots.iter()).enumerate() {
        *a = none;
        if r == i as u64 {
            *a = nc;
            nc += 1;
        }
    }
    for (i, &r) in roots.iter().enumerate() {
        if r != MIS2_NONE && r != i as u64 {
            let number = agg.get(r as usize).copied().unwrap_or(none);
            if let Some(a) = agg.get_mut(i) {
                *a = number;
            }
        }
    }
    nc as usize
}

/// The checks of [`aggregate_mis2_partitioned`] one process makes alone.
fn check_lengths(
    part: &Partition<'_>,
    graph: &Graph<'_>,
    fixed: &[u8],
    agg: usize,
    (scratch, reals): (usize, usize),
) -> Result<()> {
    let n = part.local_count();
    check::len("graph", graph.node_count(), n)?;
    check::len("fixed", fixed.len(), n)?;
    check::len("agg", agg, n)?;
    check::buffer("scratch", scratch, mis2_scratch_len(n))?;
    check::buffer("reals", reals, mis2_exchange_len(n))?;
    if part.global_count() > ID_LIMIT {
        return Err(Error::InvalidParameter {
            arg: "global_count",
            reason: "must be at most 2^62 for the aggregation",
        });
    }
    Ok(())
}

/// The rounds, then the aggregates, on local nodes `0..owned` (the rest ghosts).
fn run<A: Adjacency, P: Processes>(
    act: &A,
    owned: usize,
    gid: &dyn Fn(usize) -> u64,
    procs: &mut P,
    agg: &mut [u64],
    scratch: &mut [u64],
) -> Result<Mis2Report> {
    let n = agg.len();
    let (key, rest) = scratch.split_at_mut(n.min(scratch.len()));
    let m1 = rest.get_mut(..n).unwrap_or(&mut []);
    for (i, k) in key.iter_mut().enumerate().take(owned) {
        let state = if act.member(i) { UNDECIDED } else { OUT };
        *k = key_of(state, gid(i));
    }
    // A bound no consistent run reaches (one root per round at least).
    let cap = procs.total(owned as u64).saturating_add(1);
    let mut rounds = 0u32;
    loop {
        procs.sync(key);
        let open = key.iter().take(owned).filter(|&&k| k >> 62 == UNDECIDED);
        if procs.total(open.count() as u64) == 0 || u64::from(rounds) > cap {
            break;
        }
        rounds = rounds.saturating_add(1);
        spread(act, owned, key, m1);
        procs.sync(m1);
        decide(act, owned, key, m1);
    }
    join(act, owned, gid, procs, key, agg);
    let roots = key.iter().take(owned).filter(|&&k| k >> 62 == ROOT);
    let aggregates = procs.total(roots.count() as u64);
    Ok(Mis2Report { aggregates, rounds })
}

/// `m1[i]`: the largest key over `i` and its neighbours, for owned `i`.
fn spread<A: Adjacency>(act: &A, owned: usize, key: &[u64], m1: &mut [u64]) {
    for (i, m) in m1.iter_mut().enumerate().take(owned) {
        let mut best = key.get(i).copied().unwrap_or(0);
        act.each(i, |j| best = best.max(key.get(j).copied().unwrap_or(0)));
        *m = best;
    }
}

/// Every undecided owned node: out when a root is within distance 2, a root when it is the
/// largest key there.
fn decide<A: Adjacency>(act: &A, owned: usize, key: &mut [u64], m1: &[u64]) {
    for i in 0..owned {
        let Some(&k) = key.get(i) else { break };
        if k >> 62 != UNDECIDED {
            continue;
        }
        let mut m2 = m1.get(i).copied().unwrap_or(0);
        act.each(i, |j| m2 = m2.max(m1.get(j).copied().unwrap_or(0)));
        let next = if m2 >> 62 == ROOT {
            OUT
        } else if m2 == k {
            ROOT
        } else {
            continue;
        };
        if let Some(t) = key.get_mut(i) {
            *t = (next << 62) | (k & ID_MASK);
        }
    }
}

/// Aggregates from the roots in `key` (ghosts synced): phase A roots and their neighbours,
/// phase B the rest through a neighbour of phase A; ghosts synced at the end.
fn join<A: Adjacency, P: Processes>(
    act: &A,
    owned: usize,
    gid: &dyn Fn(usize) -> u64,
    procs: &mut P,
    key: &[u64],
    agg: &mut [u64],
) {
    let state = |j: usize| key.get(j).map_or(OUT, |&k| k >> 62);
    for (i, a) in agg.iter_mut().enumerate().take(owned) {
        *a = if !act.member(i) {
            MIS2_NONE
        } else if state(i) == ROOT {
            gid(i)
        } else {
            let mut best: Option<(u64, usize)> = None;
            act.each(i, |j| {
                let k = key.get(j).copied().unwrap_or(0);
                if k >> 62 == ROOT && best.is_none_or(|(b, _)| k > b) {
                    best = Some((k, j));
                }
            });
            best.map_or(PENDING, |(_, j)| gid(j))
        };
    }
    procs.sync(agg);
    for i in 0..owned {
        if agg.get(i) != Some(&PENDING) {
            continue;
        }
        let mut best: Option<(u64, u64)> = None;
        act.each(i, |j| {
            if let Some(&r) = agg.get(j).filter(|&&r| r < ID_LIMIT) {
                let k = priority(r);
                if best.is_none_or(|(b, _)| k > b) {
                    best = Some((k, r));
                }
            }
        });
        // No neighbour in phase A cannot happen in a consistent run (every node out has a
        // root within distance 2); the node then stands alone.
        let root = best.map_or(gid(i), |(_, r)| r);
        if let Some(a) = agg.get_mut(i) {
            *a = root | JOINED;
        }
    }
    for a in agg.iter_mut().take(owned) {
        if *a != MIS2_NONE {
            *a &= !JOINED;
        }
    }
    procs.sync(agg);
}
