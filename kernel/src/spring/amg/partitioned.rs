//! The distributed MIS-2 hierarchy, level by level (docs/amg.md, "Distributed hierarchy"). So
//! far: the fine level's smoothed prolongator on partitions ([`prolongator_partitioned`]),
//! every owned row bit for bit the row [`AmgHierarchy::setup_mis2`](super::AmgHierarchy::setup_mis2)
//! builds for that node.
//!
//! **Why the bits are the serial ones.** Row `i` of `P = (I − ω D⁻¹ A) T` reads only row `i`
//! of `A` (complete for an owned node, sorted by global id as the serial row is sorted by node
//! number: [`PartitionedSprings`]), the aggregates of `i`'s neighbours (ghosts carry their
//! owner's, [`aggregate_mis2_partitioned`](super::aggregate_mis2_partitioned)) and the weight
//! `ω = (4/3) / ρ`, whose Gershgorin bound `ρ` is a maximum of per-row values (one `max` over
//! the processes: a maximum does not depend on the order). The row's sums run over its
//! entries in the serial order, and its columns, named by the aggregates' root global ids,
//! sort as the serial coarse numbers do (those number aggregates by increasing root).

use super::mis2::MIS2_NONE;
use super::setup::jacobi_weight;
use crate::check;
use crate::error::{Error, Result};
use crate::partition::{agree, Exchange};
use crate::real::Real;
use crate::spring::PartitionedSprings;

/// Entries [`prolongator_partitioned`] may write (the length `columns` and `values` need):
/// per owned node, one for itself and one per neighbour.
pub fn prolongator_partitioned_len<T: Real>(springs: &PartitionedSprings<'_, T>) -> usize {
    let graph = springs.system().graph();
    (0..springs.partition().owned()).fold(0usize, |n, i| {
        n.saturating_add(graph.neighbors(i).len()).saturating_add(1)
    })
}

/// The fine level's smoothed prolongator on this process's owned rows: row `i` (owned) is
/// `columns[offsets[i]..offsets[i + 1]]` (the global ids of the aggregates' roots, increasing)
/// with `values` alike, bit for bit row `i` of the serial
/// [`AmgHierarchy::setup_mis2`](super::AmgHierarchy::setup_mis2) hierarchy on the whole mesh
/// (its level-0 prolongator; its columns are the coarse numbers, which sort as the roots do).
/// `agg` is what [`aggregate_mis2_partitioned`](super::aggregate_mis2_partitioned) gave on
/// this partition (every local node, ghosts included). Returns the entries written.
/// **Collective**: one `sum_words` (the verdict) and one `max` of one real.
///
/// # Errors
/// On every process together, before anything is written: `agg` not one entry per local
/// node or `offsets` not one more than the owned nodes ([`Error::LengthMismatch`]),
/// `columns` or `values` shorter than [`prolongator_partitioned_len`]
/// ([`Error::BufferTooSmall`]), an aggregate that is neither [`MIS2_NONE`] nor a global id
/// ([`Error::InvalidParameter`]), or [`PartitionFault::OtherProcess`](crate::error::PartitionFault::OtherProcess).
pub fn prolongator_partitioned<T: Real, E: Exchange<T> + ?Sized>(
    springs: &PartitionedSprings<'_, T>,
    agg: &[u64],
    exchange: &E,
    offsets: &mut [u32],
    columns: &mut [u64],
    values: &mut [T],
) -> Result<usize> {
    let local = check_args(springs, agg, offsets.len(), (columns.len(), values.len()));
    agree(exchange, local, &mut [0i64; 1])?;
    let mut rho = [fine_bound(springs)];
    exchange.max(&mut rho);
    let rho = if rho[0].is_finite() { rho[0] } else { T::ZERO };
    let w = jacobi_weight(rho);
    let mut pos = 0usize;
    for i in 0..springs.partition().owned() {
        if let Some(o) = offsets.get_mut(i) {
            *o = pos as u32;
        }
        let len = row_columns(springs, agg, i, columns.get_mut(pos..).unwrap_or(&mut []));
        let cols = columns.get(pos..pos.saturating_add(len)).unwrap_or(&[]);
        row_values(
            springs,
            agg,
            w,
            i,
            cols,
            values.get_mut(pos..).unwrap_or(&mut []),
        );
        pos = pos.saturating_add(len);
    }
    if let Some(o) = offsets.get_mut(springs.partition().owned()) {
        *o = pos as u32;
    }
    Ok(pos)
}

/// What one process can check of [`prolongator_partitioned`]'s arguments alone.
fn check_args<T: Real>(
    springs: &PartitionedSprings<'_, T>,
    agg: &[u64],
    offsets: usize,
    (columns, values): (usize, usize),
) -> Result<()> {
    let part = springs.partition();
    check::len("agg", agg.len(), part.local_count())?;
    check::len("offsets", offsets, part.owned().saturating_add(1))?;
    let len = prolongator_partitioned_len(springs);
    check::buffer("columns", columns, len)?;
    check::buffer("values", values, len)?;
    if u32::try_from(len).is_err() {
        return Err(Error::TooLarge {
            arg: "springs",
            value: len,
        });
    }
    if agg
        .iter()
        .any(|&a| a != MIS2_NONE && a >= part.global_count())
    {
        return Err(Error::InvalidParameter {
            arg: "agg",
            reason: "an aggregate is neither MIS2_NONE nor a global id",
        });
    }
    Ok(())
}

/// This process's part of the fine level's Gershgorin bound of `ρ(D⁻¹A)`: the largest
/// `(d_i + Σ |a_ij|) / d_i` over the owned free rows, each sum in the serial order (0 when
/// there is none).
fn fine_bound<T: Real>(springs: &PartitionedSprings<'_, T>) -> T {
    let sys = springs.system();
    let mut rho = T::ZERO;
    for i in 0..springs.partition().owned() {
        if sys.is_fixed(i) {
            continue;
        }
        let d = diag(springs, i);
        let mut s = d;
        for (j, k) in sys.row(i) {
            if !sys.is_fixed(j) {
                s += (-k).abs();
            }
        }
        rho = rho.max(s / d);
    }
    rho
}

/// The diagonal of owned row `i`: `Σ_j k_ij` over every neighbour, in row order.
fn diag<T: Real>(springs: &PartitionedSprings<'_, T>, i: usize) -> T {
    let mut d = T::ZERO;
    for (_, k) in springs.system().row(i) {
        d += k;
    }
    d
}

/// Writes the columns of owned row `i` into `out` (the aggregates of `i` and of its free
/// neighbours, distinct, increasing; none for a fixed node); returns how many.
fn row_columns<T: Real>(
    springs: &PartitionedSprings<'_, T>,
    agg: &[u64],
    i: usize,
    out: &mut [u64],
) -> usize {
    let sys = springs.system();
    if sys.is_fixed(i) {
        return 0;
    }
    let mut len = 0usize;
    let mut insert = |j: usize| {
        let a = agg.get(j).copied().unwrap_or(MIS2_NONE);
        if a == MIS2_NONE {
            return;
        }
        let row = out.get(..len).unwrap_or(&[]);
        let at = match row.binary_search(&a) {
            Ok(_) => return,
            Err(at) => at,
        };
        if len >= out.len() {
            return;
        }
        // Shift `out[at..len]` up by one and put `a` at `at`.
        let mut carry = a;
        for x in out.iter_mut().take(len + 1).skip(at) {
            core::mem::swap(x, &mut carry);
        }
        len += 1;
    };
    insert(i);
    for &j in sys.graph().neighbors(i) {
        if !sys.is_fixed(j as usize) {
            insert(j as usize);
        }
    }
    len
}

/// Writes the values of owned row `i` (columns `cols`) into `out`: `t_ic − (ω / d_i) s_c`, with
/// `s_c` the sum of row `i`'s entries (diagonal first, then the free neighbours in row order)
/// whose node is in aggregate `c`, as the serial numeric pass sums them.
fn row_values<T: Real>(
    springs: &PartitionedSprings<'_, T>,
    agg: &[u64],
    w: T,
    i: usize,
    cols: &[u64],
    out: &mut [T],
) {
    let sys = springs.system();
    let out = out.get_mut(..cols.len()).unwrap_or(&mut []);
    out.fill(T::ZERO);
    let mut add = |j: usize, a: T| {
        let c = agg.get(j).copied().unwrap_or(MIS2_NONE);
        if let Some(x) = cols.binary_search(&c).ok().and_then(|q| out.get_mut(q)) {
            *x += a;
        }
    };
    let d = diag(springs, i);
    add(i, d);
    for (j, k) in sys.row(i) {
        if !sys.is_fixed(j) {
            add(j, -k);
        }
    }
    let scale = w / d;
    let own = agg.get(i).copied().unwrap_or(MIS2_NONE);
    for (&c, x) in cols.iter().zip(out.iter_mut()) {
        let t = if c == own { T::ONE } else { T::ZERO };
        *x = t - scale * *x;
    }
}
