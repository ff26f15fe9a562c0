//! Mesh sensitivities (`deform_kernel::sensitivity`, issue 30) on arbitrary small 2D graphs:
//! the linear springs' tangent and adjoint (CG with no, Jacobi or SSOR preconditioning) and
//! the IDW tangent and adjoint, with NaN injections and scratch one item short.
//!
//! - An error leaves every output bit-identical.
//! - Springs: when both solves converge and the free-node operator is well conditioned, the
//!   tangent equals `A⁻¹ B v` and the adjoint `w_b + Bᵀ A⁻¹ w_f` of an independent dense
//!   Gauss–Jordan reference written here (so `⟨J v, w⟩ = ⟨v, Jᵀ w⟩` follows).
//! - IDW: `⟨J v, w⟩ = ⟨v, Jᵀ w⟩` to rounding (every row of `J` is a convex combination, so the
//!   bound is `max|v| Σ|w|` times a small multiple of ε).
#![no_main]

use arbitrary::Arbitrary;
use deform_kernel::sensitivity::{
    idw_adjoint, idw_tangent, spring_adjoint, spring_adjoint_scratch_len, spring_tangent,
};
use deform_kernel::spring::{
    batina_stiffness, solve_linear_with_scratch_len, LinearMethod, LinearSolver, Preconditioner,
    SolveOptions, SpringSystem,
};
use deform_kernel::{graph_from_edges, graph_from_edges_len, Graph};
use libfuzzer_sys::fuzz_target;

#[derive(Arbitrary, Debug)]
struct Input {
    points: Vec<[i8; 2]>,
    edges: Vec<[u8; 2]>,
    fixed: Vec<bool>,
    v: Vec<[i8; 2]>,
    w: Vec<[i8; 2]>,
    preconditioner: u8,
    exponent: u8,
    /// Bit 0: a NaN in `w`; bit 1: a NaN in `v`; bit 2: scratch one item short.
    faults: u8,
    nan_at: u8,
}

fuzz_target!(|inp: Input| {
    let n = inp.points.len().clamp(3, 16);
    let points: Vec<[f64; 2]> = (0..n)
        .map(|i| {
            let p = inp.points.get(i).copied().unwrap_or([i as i8, 0]);
            [f64::from(p[0]) / 8.0, f64::from(p[1]) / 8.0]
        })
        .collect();
    let fixed: Vec<u8> = (0..n)
        .map(|i| u8::from(inp.fixed.get(i).copied().unwrap_or(i < 2)))
        .collect();
    let field = |src: &[[i8; 2]], nan: bool| -> Vec<[f64; 2]> {
        (0..n)
            .map(|i| {
                let m = src.get(i).copied().unwrap_or([1, -1]);
                if nan && i == usize::from(inp.nan_at) % n {
                    [f64::NAN, 0.0]
                } else {
                    [f64::from(m[0]) / 16.0, f64::from(m[1]) / 16.0]
                }
            })
            .collect()
    };
    let v = field(&inp.v, inp.faults & 2 != 0);
    let w = field(&inp.w, inp.faults & 1 != 0);
    idw(&inp, &points, &fixed, &v, &w);
    springs(&inp, &points, &fixed, &v, &w);
});

/// IDW tangent and adjoint with the fixed nodes as the boundary.
fn idw(inp: &Input, points: &[[f64; 2]], fixed: &[u8], v: &[[f64; 2]], w: &[[f64; 2]]) {
    let boundary: Vec<u32> = (0..points.len() as u32)
        .filter(|&i| fixed[i as usize] != 0)
        .collect();
    let exponent = match inp.exponent % 4 {
        0 => 2.0,
        1 => 3.0,
        2 => 0.5 + f64::from(inp.exponent) / 64.0,
        _ => -1.0, // invalid
    };
    let mut dx: Vec<[f64; 2]> = v
        .iter()
        .zip(fixed)
        .map(|(x, &f)| if f != 0 { *x } else { [7.0, 7.0] })
        .collect();
    let before = dx.clone();
    let tangent = idw_tangent(points, &boundary, exponent, &mut dx);
    let mut g = vec![[5.0f64; 2]; points.len()];
    let adjoint = idw_adjoint(points, &boundary, exponent, w, &mut g);
    if tangent.is_err() {
        assert_eq!(bits(&dx), bits(&before), "idw tangent wrote on error");
    }
    if adjoint.is_err() {
        assert_eq!(
            bits(&g),
            bits(&[[5.0; 2]].repeat(points.len())),
            "idw adjoint wrote"
        );
    }
    if tangent.is_err() || adjoint.is_err() {
        return;
    }
    let lhs = dot(&dx, w);
    let rhs: f64 = boundary
        .iter()
        .map(|&b| dot_one(v[b as usize], g[b as usize]))
        .sum();
    let vmax = v.iter().flatten().fold(0.0f64, |m, x| m.max(x.abs()));
    let wsum: f64 = w.iter().flatten().map(|x| x.abs()).sum();
    let bound = 1e-12 * vmax * wsum * (points.len() + boundary.len()) as f64;
    assert!(
        (lhs - rhs).abs() <= bound + 1e-300,
        "idw dot product: {lhs} vs {rhs} (bound {bound})"
    );
}

/// Linear-spring tangent and adjoint against the dense reference.
fn springs(inp: &Input, points: &[[f64; 2]], fixed: &[u8], v: &[[f64; 2]], w: &[[f64; 2]]) {
    let n = points.len();
    let edges: Vec<[u32; 2]> = inp
        .edges
        .iter()
        .map(|e| [(e[0] as usize % n) as u32, (e[1] as usize % n) as u32])
        .filter(|e| e[0] != e[1])
        .collect();
    let mut offsets = vec![0u32; n + 1];
    let mut targets = vec![0u32; graph_from_edges_len(&edges)];
    let Ok(used) = graph_from_edges(n, &edges, &mut offsets, &mut targets) else {
        return;
    };
    targets.truncate(used);
    let g = Graph::new(&offsets, &targets).unwrap();
    let mut k = vec![0.0; used];
    if batina_stiffness(&g, points, 1.0, &mut k).is_err() {
        return; // coincident points: a typed error of the stiffness, not of this target
    }
    let mut seen = vec![0u32; n];
    let Ok(sys) = SpringSystem::new(g, &k, fixed, &mut seen) else {
        return;
    };
    let preconditioner = match inp.preconditioner % 4 {
        0 => Preconditioner::None,
        1 => Preconditioner::Jacobi,
        2 => Preconditioner::Ssor { omega: 1.2 },
        _ => Preconditioner::Ssor { omega: 2.5 }, // invalid
    };
    let solver = LinearSolver::Method(LinearMethod::Cg { preconditioner });
    let options = SolveOptions {
        residual_tol: 1e-13,
        max_iterations: 4000,
        ..SolveOptions::default()
    };
    let short = usize::from(inp.faults & 4 != 0);
    let mut dx: Vec<[f64; 2]> = v
        .iter()
        .zip(fixed)
        .map(|(x, &f)| if f != 0 { *x } else { [0.0, 0.0] })
        .collect();
    let before = dx.clone();
    let mut scratch = vec![[0.0f64; 2]; solve_linear_with_scratch_len(&solver, n) - short];
    let tangent = spring_tangent(&sys, solver, &options, &mut dx, &mut scratch);
    let mut gb = vec![[5.0f64; 2]; n];
    let len = spring_adjoint_scratch_len::<f64, 2>(&solver, n);
    let mut scratch = vec![[0.0f64; 2]; len.saturating_sub(short)];
    let adjoint = spring_adjoint(&sys, solver, &options, w, &mut gb, &mut scratch);
    if tangent.is_err() {
        assert_eq!(bits(&dx), bits(&before), "spring tangent wrote on error");
    }
    if adjoint.is_err() {
        assert_eq!(
            bits(&gb),
            bits(&[[5.0; 2]].repeat(n)),
            "spring adjoint wrote"
        );
    }
    let (Ok(t), Ok(a)) = (tangent, adjoint) else {
        return;
    };
    assert!(dx.iter().chain(&gb).flatten().all(|x| x.is_finite()));
    if t.converged && a.converged {
        compare_dense(&sys_parts(&offsets, &targets, &k), fixed, v, w, &dx, &gb);
    }
}

/// The graph as `(row, column, stiffness)` triples.
fn sys_parts(offsets: &[u32], targets: &[u32], k: &[f64]) -> Vec<(usize, usize, f64)> {
    let mut out = Vec::new();
    for i in 0..offsets.len() - 1 {
        for e in offsets[i] as usize..offsets[i + 1] as usize {
            out.push((i, targets[e] as usize, k[e]));
        }
    }
    out
}

/// Tangent and adjoint against `A = D − K_ff`, `B = K_fb` by dense Gauss–Jordan, when the
/// 1-norm condition number of `A` is at most 1e6 (then the converged solves' errors are far
/// below the bound).
fn compare_dense(
    triples: &[(usize, usize, f64)],
    fixed: &[u8],
    v: &[[f64; 2]],
    w: &[[f64; 2]],
    dx: &[[f64; 2]],
    g: &[[f64; 2]],
) {
    let n = fixed.len();
    let free: Vec<usize> = (0..n).filter(|&i| fixed[i] == 0).collect();
    let slot = |i: usize| free.iter().position(|&f| f == i);
    let m = free.len();
    let mut a = vec![vec![0.0f64; m]; m];
    for &(i, j, kij) in triples {
        if let Some(r) = slot(i) {
            a[r][r] += kij;
            if let Some(c) = slot(j) {
                a[r][c] -= kij;
            }
        }
    }
    let Some(inv) = inverse(&a) else { return };
    let norm1 = |x: &[Vec<f64>]| {
        (0..m)
            .map(|c| x.iter().map(|row| row[c].abs()).sum::<f64>())
            .fold(0.0, f64::max)
    };
    if m == 0 || norm1(&a) * norm1(&inv) > 1e6 {
        return;
    }
    let scale = v
        .iter()
        .chain(w)
        .flatten()
        .fold(1e-300f64, |s, x| s.max(x.abs()));
    for c in 0..2 {
        // Tangent: x_f = A⁻¹ B v_b.
        let rhs: Vec<f64> = free
            .iter()
            .map(|&i| pull(triples, fixed, i, |j| v[j][c]))
            .collect();
        for (r, &i) in free.iter().enumerate() {
            let x: f64 = (0..m).map(|s| inv[r][s] * rhs[s]).sum();
            assert!(
                (x - dx[i][c]).abs() <= 1e-6 * scale,
                "tangent {x} vs {}",
                dx[i][c]
            );
        }
        // Adjoint: λ = A⁻¹ w_f, g_b = w_b + Σ_i k_ib λ_i.
        let lambda: Vec<f64> = (0..m)
            .map(|r| (0..m).map(|s| inv[r][s] * w[free[s]][c]).sum())
            .collect();
        let lmax = lambda.iter().fold(scale, |s, x| s.max(x.abs()));
        for b in (0..n).filter(|&b| fixed[b] != 0) {
            let mut reference = w[b][c];
            let mut ksum = 1.0;
            for &(i, _, kij) in triples.iter().filter(|t| t.1 == b) {
                if let Some(r) = slot(i) {
                    reference += kij * lambda[r];
                    ksum += kij;
                }
            }
            let bound = 1e-6 * ksum * lmax;
            assert!(
                (reference - g[b][c]).abs() <= bound,
                "adjoint {reference} vs {}",
                g[b][c]
            );
        }
        for &i in &free {
            assert_eq!(g[i][c], 0.0, "adjoint nonzero at a free node");
        }
    }
}

/// `Σ_{j fixed} k_ij value(j)` for the free node `i`.
fn pull(
    triples: &[(usize, usize, f64)],
    fixed: &[u8],
    i: usize,
    value: impl Fn(usize) -> f64,
) -> f64 {
    triples
        .iter()
        .filter(|t| t.0 == i && fixed[t.1] != 0)
        .map(|t| t.2 * value(t.1))
        .sum()
}

/// Gauss–Jordan inverse with partial pivoting; `None` when a pivot vanishes.
fn inverse(a: &[Vec<f64>]) -> Option<Vec<Vec<f64>>> {
    let m = a.len();
    let mut l: Vec<Vec<f64>> = a.to_vec();
    let mut r: Vec<Vec<f64>> = (0..m)
        .map(|i| (0..m).map(|j| f64::from(u8::from(i == j))).collect())
        .collect();
    for c in 0..m {
        let p = (c..m).max_by(|&x, &y| l[x][c].abs().total_cmp(&l[y][c].abs()))?;
        if l[p][c].abs() < 1e-300 {
            return None;
        }
        l.swap(c, p);
        r.swap(c, p);
        let d = l[c][c];
        for j in 0..m {
            l[c][j] /= d;
            r[c][j] /= d;
        }
        for i in (0..m).filter(|&i| i != c) {
            let f = l[i][c];
            for j in 0..m {
                l[i][j] -= f * l[c][j];
                r[i][j] -= f * r[c][j];
            }
        }
    }
    Some(r)
}

fn dot(a: &[[f64; 2]], b: &[[f64; 2]]) -> f64 {
    a.iter().zip(b).map(|(x, y)| dot_one(*x, *y)).sum()
}

fn dot_one(a: [f64; 2], b: [f64; 2]) -> f64 {
    a[0] * b[0] + a[1] * b[1]
}

fn bits(a: &[[f64; 2]]) -> Vec<[u64; 2]> {
    a.iter().map(|x| x.map(f64::to_bits)).collect()
}
