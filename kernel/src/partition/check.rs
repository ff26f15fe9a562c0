//! The checks of [`Partition::new`](super::Partition::new): what one process can check alone
//! ([`local`]), and the checksums only all processes together can ([`global`], on the summed
//! words).

use super::{fault, Partition};
use crate::check;
use crate::error::{Error, PartitionFault, Result};
use crate::order::sort::{heap_sort, ByKey};

/// Words of the one reduction: fault flag, owned count, `Σ g`, `Σ g²` (mod [`P`]), and the
/// pattern's two hash sums (mod [`P`]).
pub(crate) const WORDS: usize = 6;

/// The checksums' modulus, the prime `2^31 − 1`: residues of up to `2^32` processes add up
/// in an `i64` without overflow.
pub(crate) const P: u64 = (1 << 31) - 1;

/// The two hash seeds (two independent 31-bit residues per item).
pub(crate) const SEEDS: [u64; 2] = [0x9e37_79b9_7f4a_7c15, 0xd1b5_4a32_d192_ed03];

/// The splitmix64 finaliser: a bijection of `u64` that mixes every input bit into every output
/// bit.
#[inline]
fn mix(mut z: u64) -> u64 {
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// A hash of `parts` under `seed`, reduced mod [`P`].
#[inline]
pub(crate) fn hash(seed: u64, parts: &[u64]) -> u64 {
    parts.iter().fold(mix(seed), |h, &p| mix(h ^ p)) % P
}

/// `P − h` (mod [`P`]): the residue that cancels `h`.
#[inline]
pub(crate) fn negate(h: u64) -> u64 {
    (P - h % P) % P
}

/// What a process contributes to the one reduction.
pub(crate) struct Tally {
    owned: u64,
    sum: u64,
    sum_sq: u64,
    pattern: [u64; 2],
}

impl Tally {
    /// The reduction's words (the flag word left 0).
    pub(crate) fn words(&self) -> [i64; WORDS] {
        let [a, b] = self.pattern;
        // Residues are below 2^31 and the count is a node count: no wrap.
        [
            0,
            self.owned as i64,
            self.sum as i64,
            self.sum_sq as i64,
            a as i64,
            b as i64,
        ]
    }
}

/// Everything one process can check alone, and its tally.
pub(crate) fn local(part: &Partition<'_>, size: u32, scratch: &mut [u32]) -> Result<Tally> {
    let n = part.local_count();
    if part.rank >= size {
        return Err(Error::InvalidParameter {
            arg: "rank",
            reason: "must be below the process count",
        });
    }
    if u32::try_from(n).is_err() {
        return Err(Error::TooLarge {
            arg: "global_ids",
            value: n,
        });
    }
    check::buffer("scratch", scratch.len(), n)?;
    part.halo.check_shape()?;
    if part.owned == 0 {
        return Err(fault(PartitionFault::NoOwnedNodes, 0));
    }
    if part.owned > n {
        return Err(fault(PartitionFault::OwnedBeyondLocal, part.owned));
    }
    ids(part, scratch)?;
    lists(part, size, scratch)?;
    let (mut sum, mut sum_sq) = (0u64, 0u64);
    for &g in part.global_ids.get(..part.owned).unwrap_or(&[]) {
        let r = g % P;
        sum = (sum + r) % P;
        sum_sq = (sum_sq + r * r % P) % P;
    }
    Ok(Tally {
        owned: part.owned as u64,
        sum,
        sum_sq,
        pattern: SEEDS.map(|s| pattern_hash(part, s)),
    })
}

/// Global ids below the global count, and distinct (sorted through `scratch`).
fn ids(part: &Partition<'_>, scratch: &mut [u32]) -> Result<()> {
    let n = part.local_count();
    for (i, &g) in part.global_ids.iter().enumerate() {
        if g >= part.global_count {
            return Err(fault(PartitionFault::GlobalIdRange, i));
        }
    }
    let order = scratch.get_mut(..n).unwrap_or(&mut []);
    for (k, o) in order.iter_mut().enumerate() {
        *o = k as u32;
    }
    heap_sort(&mut ByKey {
        items: order,
        key: |i| (part.global_id(i as usize), i),
    });
    for w in order.windows(2) {
        if let [a, b] = *w {
            if part.global_id(a as usize) == part.global_id(b as usize) {
                return Err(fault(PartitionFault::DuplicateGlobalId, a.max(b) as usize));
            }
        }
    }
    Ok(())
}

/// Neighbour ranks (below `size`, not this process, distinct), send entries owned, receive
/// entries ghosts, every ghost received exactly once (counted in `scratch`).
fn lists(part: &Partition<'_>, size: u32, scratch: &mut [u32]) -> Result<()> {
    let halo = &part.halo;
    let ranks = (0..halo.neighbour_count()).filter_map(|k| halo.neighbour(k).map(|n| n.0));
    for (k, r) in ranks.clone().enumerate() {
        if r >= size || r == part.rank || ranks.clone().take(k).any(|q| q == r) {
            return Err(fault(PartitionFault::NeighbourRank, k));
        }
    }
    let (owned, n) = (part.owned, part.local_count());
    for (p, &i) in halo.send_entries().iter().enumerate() {
        if i as usize >= owned {
            return Err(fault(PartitionFault::SendNotOwned, p));
        }
    }
    let seen = scratch.get_mut(..n).unwrap_or(&mut []);
    seen.fill(0);
    for (p, &i) in halo.receive_entries().iter().enumerate() {
        let i = i as usize;
        if i < owned || i >= n {
            return Err(fault(PartitionFault::ReceiveNotGhost, p));
        }
        match seen.get_mut(i) {
            Some(s) if *s == 0 => *s = 1,
            _ => return Err(fault(PartitionFault::GhostReceivedTwice, p)),
        }
    }
    if let Some(g) = seen.iter().skip(owned).position(|&s| s == 0) {
        return Err(fault(PartitionFault::GhostNotReceived, owned + g));
    }
    Ok(())
}

/// `Σ_send H(me, to, q, g) + Σ_recv −H(from, me, q, g)` (mod [`P`]): over all processes, 0
/// when every send entry meets the receive entry at its position with the same global id.
fn pattern_hash(part: &Partition<'_>, seed: u64) -> u64 {
    let me = u64::from(part.rank);
    let mut h = 0u64;
    for (r, send, recv) in part.halo.neighbours() {
        let r = u64::from(r);
        for (q, &i) in send.iter().enumerate() {
            let g = part.global_id(i as usize);
            h = (h + hash(seed, &[me, r, q as u64, g])) % P;
        }
        for (q, &i) in recv.iter().enumerate() {
            let g = part.global_id(i as usize);
            h = (h + negate(hash(seed, &[r, me, q as u64, g]))) % P;
        }
    }
    h
}

/// The checks on the summed words (the same on every process).
pub(crate) fn global(words: &[i64; WORDS], global_count: u64) -> Result<()> {
    let [_, owned, sum, sum_sq, pa, pb] = *words;
    if owned as u64 != global_count {
        return Err(fault(PartitionFault::OwnedCount, 0));
    }
    // Σ_{g<N} g = N(N−1)/2 and Σ g² = (N−1)N(2N−1)/6, mod P (P prime: 6 has an inverse).
    let n = u128::from(global_count) % u128::from(P);
    let p = u128::from(P);
    let s1 = n * ((n + p - 1) % p) % p * inverse(2) % p;
    let s2 = n * ((n + p - 1) % p) % p * ((2 * n + p - 1) % p) % p * inverse(6) % p;
    let reduce = |w: i64| (w as u64 % P) as u128;
    if reduce(sum) != s1 || reduce(sum_sq) != s2 {
        return Err(fault(PartitionFault::OwnedIds, 0));
    }
    if reduce(pa) != 0 || reduce(pb) != 0 {
        return Err(fault(PartitionFault::Pattern, 0));
    }
    Ok(())
}

/// `x⁻¹ mod P` (Fermat: `x^(P−2)`).
fn inverse(x: u128) -> u128 {
    let p = u128::from(P);
    let (mut base, mut e, mut acc) = (x % p, p - 2, 1u128);
    while e > 0 {
        if e & 1 == 1 {
            acc = acc * base % p;
        }
        base = base * base % p;
        e >>= 1;
    }
    acc
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn closed_forms_match_the_sums() {
        for n in [1u64, 2, 7, 1000, 65_537] {
            let (mut a, mut b) = (0u64, 0u64);
            for g in 0..n {
                a = (a + g % P) % P;
                b = (b + (g % P) * (g % P) % P) % P;
            }
            let mut w = [0i64; WORDS];
            w[1] = n as i64;
            w[2] = a as i64;
            w[3] = b as i64;
            assert_eq!(global(&w, n), Ok(()), "n = {n}");
            w[2] += 1;
            assert!(global(&w, n).is_err());
        }
    }
}
