//! The cost of reproducible sums in a CG + Jacobi iteration (issue 27 item 6): the exact
//! reductions of one 2D iteration (`pᵀq` and `rᵀz` per component, `Σ r²`: 6 terms a node)
//! summed with `ExactSum` through `Gather`, as the kernel's CG does, against plain `f64` accumulators (not
//! reproducible) over the same vectors, as a fraction of the measured iteration time.

use std::hint::black_box;

use deform_kernel::exact_sum::{ExactSum, Gather};

use crate::{median, Figures};

/// One iteration's reductions, exact, gathered a node at a time as the kernel's CG does
/// (`Gather`: a stack block per sum, summed 64 terms at a time): `[pᵀq₀, pᵀq₁, rᵀz₀, rᵀz₁,
/// Σ r²]`.
fn exact(p: &[[f64; 2]], q: &[[f64; 2]], r: &[[f64; 2]], z: &[[f64; 2]]) -> [f64; 5] {
    let (mut pq, mut rz, mut rr) = ([ExactSum::new(); 2], [ExactSum::new(); 2], ExactSum::new());
    {
        let mut pq = Gather::lanes(&mut pq);
        let mut rz = Gather::lanes(&mut rz);
        let mut rr = Gather::<2>::one(&mut rr);
        for (((p, q), r), z) in p.iter().zip(q).zip(r).zip(z) {
            pq.push([p[0] * q[0], p[1] * q[1]]);
            rz.push([r[0] * z[0], r[1] * z[1]]);
            rr.push([r[0] * r[0], r[1] * r[1]]);
        }
    }
    let v = |s: &ExactSum| s.value::<f64>();
    [v(&pq[0]), v(&pq[1]), v(&rz[0]), v(&rz[1]), v(&rr)]
}

/// The same with plain `f64` accumulators.
fn plain(p: &[[f64; 2]], q: &[[f64; 2]], r: &[[f64; 2]], z: &[[f64; 2]]) -> [f64; 5] {
    let mut s = [0.0f64; 5];
    for (((p, q), r), z) in p.iter().zip(q).zip(r).zip(z) {
        for c in 0..2 {
            s[c] += p[c] * q[c];
            s[2 + c] += r[c] * z[c];
            s[4] += r[c] * r[c];
        }
    }
    s
}

/// Times both on CG-like vectors of the spring mesh: `p` the displacement of the CG + Jacobi
/// solution `y` from the initial field `x0`, `r` the difference of the two solvers' answers
/// (`x`, AMG-CG; an error-like field spanning many decades), `q` and `z` the same scaled by a
/// smooth per-node factor. Puts the cost of reproducibility per iteration.
pub fn cost(
    y: &[[f64; 2]],
    x: &[[f64; 2]],
    x0: &[[f64; 2]],
    iteration_s: f64,
    reps: usize,
    fig: &mut Figures,
) {
    let n = y.len();
    let p: Vec<[f64; 2]> = y
        .iter()
        .zip(x0)
        .map(|(a, b)| [a[0] - b[0], a[1] - b[1]])
        .collect();
    let r: Vec<[f64; 2]> = y
        .iter()
        .zip(x)
        .map(|(a, b)| [a[0] - b[0], a[1] - b[1]])
        .collect();
    let f = |i: usize| 1.0 + 0.5 * (i as f64 * 0.01).sin();
    let q: Vec<[f64; 2]> = p
        .iter()
        .enumerate()
        .map(|(i, v)| v.map(|v| v * f(i)))
        .collect();
    let z: Vec<[f64; 2]> = r
        .iter()
        .enumerate()
        .map(|(i, v)| v.map(|v| v / f(i)))
        .collect();
    // Many rounds per timing: one round is a fraction of a millisecond.
    let rounds = 20;
    type Reduce = fn(&[[f64; 2]], &[[f64; 2]], &[[f64; 2]], &[[f64; 2]]) -> [f64; 5];
    let time = |g: Reduce| {
        median(reps, || {
            for _ in 0..rounds {
                black_box(g(
                    black_box(&p),
                    black_box(&q),
                    black_box(&r),
                    black_box(&z),
                ));
            }
        }) / rounds as f64
    };
    let (t_exact, t_plain) = (time(exact), time(plain));
    // Timings on a shared machine: say how busy it was (1-minute load average, Linux).
    let load = std::fs::read_to_string("/proc/loadavg").unwrap_or_default();
    fig.put(
        "load_average_1min",
        load.split(' ').next().unwrap_or("unknown"),
    );
    fig.put("reduction_terms_per_iteration", 6 * n);
    fig.put("reduction_exact_s", format!("{t_exact:.3e}"));
    fig.put("reduction_plain_s", format!("{t_plain:.3e}"));
    fig.put(
        "reduction_exact_ns_per_term",
        format!("{:.2}", t_exact * 1e9 / (6 * n) as f64),
    );
    fig.put(
        "reproducibility_cost_of_cg_jacobi_iteration",
        format!("{:.3}", (t_exact - t_plain) / iteration_s),
    );
}
