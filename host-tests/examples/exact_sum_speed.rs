//! The cost of an exact sum per term (issue 27 item 6): the three reductions of a 2D CG
//! iteration (`pᵀq` and `rᵀz` per component, `Σ r²`) over `[f64; 2]` vectors, summed exactly
//! ([`ExactSum`], as the kernel does) and with plain `f64` accumulators (not reproducible).
//! Speed is measured here, never asserted. Deterministic instruction counts:
//!
//! `valgrind --tool=callgrind target/release/examples/exact_sum_speed exact` (or `gathered`,
//! `plain`)
//!
//! `cargo run --release -p deform-host-tests --example exact_sum_speed [-- exact|gathered|plain|both] [N] [REPS]`

use std::hint::black_box;
use std::time::Instant;

use deform_kernel::exact_sum::{ExactSum, Gather};

/// Deterministic values in [-1, 1).
fn lcg(state: &mut u64) -> f64 {
    *state = state
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    (*state >> 11) as f64 / (1u64 << 52) as f64 - 1.0
}

/// Vectors like CG's: smooth magnitudes varying over a few decades along the node order.
fn field(n: usize, seed: u64) -> Vec<[f64; 2]> {
    let mut s = seed;
    (0..n)
        .map(|i| {
            let scale = 10f64.powf(-3.0 * (i as f64 / n as f64));
            [lcg(&mut s) * scale, lcg(&mut s) * scale]
        })
        .collect()
}

/// One iteration's exact reductions: `[pᵀq, rᵀz]` per component and `Σ r²`.
fn exact(p: &[[f64; 2]], q: &[[f64; 2]], r: &[[f64; 2]], z: &[[f64; 2]]) -> f64 {
    let mut pq = [ExactSum::new(); 2];
    let mut rz = [ExactSum::new(); 2];
    let mut rr = ExactSum::new();
    for (((p, q), r), z) in p.iter().zip(q).zip(r).zip(z) {
        for c in 0..2 {
            pq[c].add(p[c] * q[c]);
            rr.add(r[c] * r[c]);
            rz[c].add(r[c] * z[c]);
        }
    }
    pq.iter().chain(&rz).map(|s| s.value::<f64>()).sum::<f64>() + rr.value::<f64>()
}

/// The same exact reductions gathered a node at a time ([`Gather`], as the kernel's CG loops
/// add their terms: a stack block per sum instead of one buffered add per term).
fn gathered(p: &[[f64; 2]], q: &[[f64; 2]], r: &[[f64; 2]], z: &[[f64; 2]]) -> f64 {
    let (mut pq, mut rz, mut rr) = ([ExactSum::new(); 2], [ExactSum::new(); 2], ExactSum::new());
    {
        let (mut gpq, mut grz) = (Gather::lanes(&mut pq), Gather::lanes(&mut rz));
        let mut grr = Gather::<2>::one(&mut rr);
        for (((p, q), r), z) in p.iter().zip(q).zip(r).zip(z) {
            gpq.push([p[0] * q[0], p[1] * q[1]]);
            grr.push([r[0] * r[0], r[1] * r[1]]);
            grz.push([r[0] * z[0], r[1] * z[1]]);
        }
    }
    pq.iter().chain(&rz).map(|s| s.value::<f64>()).sum::<f64>() + rr.value::<f64>()
}

/// The same reductions with plain `f64` accumulators.
fn plain(p: &[[f64; 2]], q: &[[f64; 2]], r: &[[f64; 2]], z: &[[f64; 2]]) -> f64 {
    let (mut pq, mut rz, mut rr) = ([0.0f64; 2], [0.0f64; 2], 0.0f64);
    for (((p, q), r), z) in p.iter().zip(q).zip(r).zip(z) {
        for c in 0..2 {
            pq[c] += p[c] * q[c];
            rr += r[c] * r[c];
            rz[c] += r[c] * z[c];
        }
    }
    pq.iter().chain(&rz).sum::<f64>() + rr
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let which = args.first().map_or("both", String::as_str);
    let n: usize = args.get(1).and_then(|s| s.parse().ok()).unwrap_or(100_000);
    let reps: usize = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(10);
    let (p, q, r, z) = (field(n, 1), field(n, 2), field(n, 3), field(n, 4));
    let terms = (6 * n * reps) as f64;
    for (name, f) in [
        ("exact", exact as fn(&_, &_, &_, &_) -> f64),
        ("gathered", gathered),
        ("plain", plain),
    ] {
        if which != "both" && which != name {
            continue;
        }
        let t = Instant::now();
        let mut acc = 0.0;
        for _ in 0..reps {
            acc += f(black_box(&p), black_box(&q), black_box(&r), black_box(&z));
        }
        let s = t.elapsed().as_secs_f64();
        println!(
            "{name}: {:.3} ns per term ({n} nodes × 6 terms × {reps}; checksum {acc:e})",
            s * 1e9 / terms
        );
    }
}
