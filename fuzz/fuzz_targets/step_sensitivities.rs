//! Derivatives that follow a sequence of solves (issue 30): the tangent and adjoint of
//! multi-step elasticity (`elastic_incremental_tangent` / `_adjoint`: re-assembled load
//! increments, every modulus, Poisson ratios in and out of range, 0–3 steps) on jittered
//! triangulated grids, and of a prepared plan's last step (`Plan::tangent` / `Plan::adjoint`,
//! linear or quaternion springs, multigrid or CG), with NaN injections, scratch one short and
//! the plan asked before its first step or at another motion.
//!
//! - An error leaves the output bit-identical (`dx` holds the direction at fixed nodes and
//!   sentinels elsewhere); a NaN, a short scratch, zero steps, a Poisson ratio out of range,
//!   a derivative before the first step and another motion are errors.
//! - On `Ok` every output is finite.
//! - When every solve converged (to 10⁻¹³) and no point was collapsed, with `J` assembled
//!   column by column from tangents of unit vectors and `S = Σ |w_i| |J_ik| |v_k|`: the
//!   tangent is linear and `|⟨J v, w⟩ − ⟨v, Jᵀ w⟩| ≤ 10⁻⁶ S` (solver tolerance times the
//!   condition of a small jittered grid's operator, with a wide margin).
#![no_main]

use arbitrary::Arbitrary;
use deform_kernel::elasticity::{
    elasticity_graph, elasticity_graph_len, IncrementBuffers, Increments, Modulus,
};
use deform_kernel::plan::{
    Plan, PlanMethod, PlanMotion, PlanOrder, PlanSolver, PlanSpec, PlanStiffness, PlanWork, Start,
};
use deform_kernel::quaternion::RotationSource;
use deform_kernel::sensitivity::{
    elastic_incremental_adjoint, elastic_incremental_adjoint_scratch_len,
    elastic_incremental_tangent, elastic_incremental_tangent_scratch_len, ElasticPreconditioner,
    IncrementProblem,
};
use deform_kernel::spring::{AmgOptions, LinearMethod, Preconditioner, SolveOptions};
use deform_kernel::{Cells, Error, Graph, Quat};
use libfuzzer_sys::fuzz_target;

#[derive(Arbitrary, Debug)]
struct Input {
    dims: [u8; 2],
    jitter: Vec<[i8; 2]>,
    moves: Vec<[i8; 2]>,
    v: Vec<[i8; 2]>,
    w: Vec<[i8; 2]>,
    /// Elasticity: modulus (bits 0–1), steps (2–3); plan: quaternion (bit 4), CG (bit 5).
    choice: u8,
    poisson: i8,
    angle: i8,
    /// Bit 0: NaN in `w`; 1: NaN in `v`; 2: scratch one short; 3: plan asked before its
    /// step or at another motion; 4: point `at` collapsed onto point 0.
    faults: u8,
    at: u8,
}

const OPTIONS: SolveOptions<f64> = SolveOptions {
    max_iterations: 4000,
    residual_tol: 1e-13,
    update_tol: 0.0,
};

fuzz_target!(|inp: Input| {
    let g = Grid::new(&inp);
    elasticity(&inp, &g);
    plan(&inp, &g);
});

/// A jittered `ni × nj` grid, two triangles a square, its perimeter fixed and moved.
struct Grid {
    ni: usize,
    points: Vec<[f64; 2]>,
    boundary: Vec<u32>,
    disp: Vec<[f64; 2]>,
    v: Vec<[f64; 2]>,
    w: Vec<[f64; 2]>,
}

impl Grid {
    fn new(inp: &Input) -> Self {
        let (ni, nj) = (
            usize::from(inp.dims[0] % 3) + 2,
            usize::from(inp.dims[1] % 3) + 2,
        );
        let n = ni * nj;
        let mut points: Vec<[f64; 2]> = (0..n)
            .map(|p| {
                let j = inp.jitter.get(p).copied().unwrap_or([0; 2]);
                let c = [(p % ni) as f64, (p / ni) as f64];
                core::array::from_fn(|d| c[d] + f64::from(j[d]) / 400.0)
            })
            .collect();
        if inp.faults & 16 != 0 {
            points[usize::from(inp.at) % n] = points[0];
        }
        let on_edge = |p: usize| p % ni == 0 || p % ni == ni - 1 || p / ni == 0 || p / ni == nj - 1;
        let boundary: Vec<u32> = (0..n).filter(|&p| on_edge(p)).map(|p| p as u32).collect();
        let field = |src: &[[i8; 2]], k: usize, nan: bool| -> [f64; 2] {
            let m = src.get(k).copied().unwrap_or([1, -1]);
            let nan = nan && k == usize::from(inp.at) % n;
            [
                if nan {
                    f64::NAN
                } else {
                    f64::from(m[0]) / 16.0
                },
                f64::from(m[1]) / 16.0,
            ]
        };
        let (a, q) = (f64::from(inp.angle) / 300.0, &inp.moves);
        let disp = (0..n)
            .map(|k| {
                let [x, y] = points[k];
                let m = field(q, k, false);
                [m[0] / 4.0 - a * y, m[1] / 4.0 + a * x]
            })
            .collect();
        Grid {
            ni,
            disp,
            v: (0..n)
                .map(|k| field(&inp.v, k, inp.faults & 2 != 0))
                .collect(),
            w: (0..n)
                .map(|k| field(&inp.w, k, inp.faults & 1 != 0))
                .collect(),
            points,
            boundary,
        }
    }
}

/// Checks `(tangent of v, adjoint of w)` and, when `cols` (the tangents of unit boundary
/// vectors) are given, linearity and the dot-product identity to `1e-6 S`; `v` and `g` are
/// per boundary node, `jv` and `w` per node.
fn dot_test(
    cols: &[Vec<[f64; 2]>],
    v: &[[f64; 2]],
    w: &[[f64; 2]],
    jv: &[[f64; 2]],
    g: &[[f64; 2]],
) {
    let vk = |k: usize| v[k / 2][k % 2];
    let mut s = 0.0f64;
    for (k, col) in cols.iter().enumerate() {
        s += col
            .iter()
            .zip(w)
            .map(|(c, x)| (c[0] * x[0]).abs() + (c[1] * x[1]).abs())
            .sum::<f64>()
            * vk(k).abs();
    }
    let mut lin = 0.0f64;
    for (i, x) in jv.iter().enumerate() {
        for d in 0..2 {
            let combo: f64 = cols.iter().enumerate().map(|(k, c)| c[i][d] * vk(k)).sum();
            lin += ((x[d] - combo) * w[i][d]).abs();
        }
    }
    assert!(
        lin <= 1e-6 * s + 1e-300,
        "tangent not linear: {lin} (S = {s})"
    );
    let lhs: f64 = jv
        .iter()
        .zip(w)
        .map(|(x, y)| x[0] * y[0] + x[1] * y[1])
        .sum();
    let rhs: f64 = v
        .iter()
        .zip(g)
        .map(|(x, y)| x[0] * y[0] + x[1] * y[1])
        .sum();
    assert!(
        (lhs - rhs).abs() <= 1e-6 * s + 1e-300,
        "dot product: {lhs} vs {rhs} (S = {s})"
    );
}

/// The derivative columns `J e_k` of a tangent `t(v_b) -> Some(J v)` (None: not converged).
fn columns(
    b: usize,
    mut t: impl FnMut(&[[f64; 2]]) -> Option<Vec<[f64; 2]>>,
) -> Option<Vec<Vec<[f64; 2]>>> {
    (0..2 * b)
        .map(|k| {
            let mut e = vec![[0.0; 2]; b];
            e[k / 2][k % 2] = 1.0;
            t(&e)
        })
        .collect()
}

/// Asserts the outcome rules: untouched on error (sentinel `fill`), finite on success, an
/// error when `expect_error`.
fn outcome<R: core::fmt::Debug>(
    r: &Result<R, Error>,
    out: &[[f64; 2]],
    fill: f64,
    expect_error: bool,
) {
    match r {
        Err(_) => assert!(
            out.iter().flatten().all(|x| x.to_bits() == fill.to_bits()),
            "wrote on error"
        ),
        Ok(_) => {
            assert!(!expect_error, "no error: {r:?}");
            assert!(out.iter().flatten().all(|x| x.is_finite()), "non-finite");
        }
    }
}

fn elasticity(inp: &Input, g: &Grid) {
    let (n, ni) = (g.points.len(), g.ni);
    let (mut offsets, mut nodes) = (vec![0u32], Vec::new());
    for p in (0..n).filter(|&p| p % ni + 1 < ni && p + ni < n) {
        let a = p as u32;
        for t in [
            [a, a + 1, a + 1 + ni as u32],
            [a, a + 1 + ni as u32, a + ni as u32],
        ] {
            nodes.extend(t);
            offsets.push(nodes.len() as u32);
        }
    }
    let kinds = vec![5u8; offsets.len() - 1];
    let cells = Cells::new(n, &offsets, &nodes, &kinds).unwrap();
    let mut goffs = vec![0u32; n + 1];
    let mut targets = vec![0u32; elasticity_graph_len(&cells)];
    let used = elasticity_graph(&cells, &mut goffs, &mut targets).unwrap();
    let graph = Graph::new(&goffs, &targets[..used]).unwrap();
    let mut fixed = vec![0u8; n];
    g.boundary.iter().for_each(|&b| fixed[b as usize] = 1);
    let steps = usize::from(inp.choice >> 2 & 3);
    let poisson = f64::from(inp.poisson) / 200.0;
    let modulus = [
        Modulus::Constant,
        Modulus::InverseVolume,
        Modulus::InverseVolume,
    ][usize::from(inp.choice & 3) % 3];
    let params = Increments {
        modulus,
        wall_distance: None,
        poisson,
        steps,
    };
    let p = IncrementProblem {
        cells: &cells,
        graph: &graph,
        fixed: &fixed,
        params: &params,
        points: &g.points,
        displacement: &g.disp,
        pre: ElasticPreconditioner::Blocks,
        options: OPTIONS,
    };
    let short = usize::from(inp.faults & 4 != 0);
    let run = |tangent: bool, x: &[[f64; 2]], out: &mut [[f64; 2]], short: usize| {
        let len = if tangent {
            elastic_incremental_tangent_scratch_len(&p.pre, n)
        } else {
            elastic_incremental_adjoint_scratch_len(&p.pre, n, steps)
        };
        let (mut m, mut dg, mut off) = (
            vec![0.0; kinds.len()],
            vec![[[0.0; 2]; 2]; n],
            vec![[[0.0; 2]; 2]; used],
        );
        let (mut cur, mut st, mut s) = (
            vec![[0.0; 2]; n],
            vec![[0.0; 2]; n],
            vec![[0.0; 2]; len - short],
        );
        let b = IncrementBuffers {
            moduli: &mut m,
            diag: &mut dg,
            off: &mut off,
            current: &mut cur,
            step: &mut st,
        };
        if tangent {
            elastic_incremental_tangent(&p, out, b, &mut s)
        } else {
            elastic_incremental_adjoint(&p, x, out, b, &mut s)
        }
    };
    // dx: the direction at fixed nodes, sentinels at free ones.
    let spread = |vb: &[[f64; 2]]| -> Vec<[f64; 2]> {
        let mut dx = vec![[7.0; 2]; n];
        g.boundary
            .iter()
            .zip(vb)
            .for_each(|(&b, x)| dx[b as usize] = *x);
        dx
    };
    let vb: Vec<[f64; 2]> = g.boundary.iter().map(|&b| g.v[b as usize]).collect();
    let mut jv = spread(&vb);
    let before = jv.clone();
    let t = run(true, &[], &mut jv, short);
    let mut gr = vec![[5.0; 2]; n];
    let a = run(false, &g.w, &mut gr, short);
    let bad = short == 1 || steps == 0 || poisson == 0.5;
    let nan_v = vb.iter().flatten().any(|x| x.is_nan());
    if t.is_err() {
        assert!(
            jv.iter()
                .zip(&before)
                .all(|(x, y)| x.map(f64::to_bits) == y.map(f64::to_bits)),
            "tangent wrote on error"
        );
    } else {
        outcome(&t, &jv, 0.0, bad || nan_v);
    }
    outcome(&a, &gr, 5.0, bad || inp.faults & 1 != 0);
    let (Ok(tr), Ok(ar)) = (t, a) else { return };
    // Near-incompressible or auxetic-beyond-reason moduli condition the operator badly.
    let conditioned = (-0.5..=0.45).contains(&poisson);
    if !tr.converged || !ar.converged || inp.faults & 16 != 0 || !conditioned {
        return;
    }
    let cols = columns(vb.len(), |e| {
        let mut dx = spread(e);
        run(true, &[], &mut dx, 0)
            .ok()
            .filter(|r| r.converged)
            .map(|_| dx)
    });
    let gb: Vec<[f64; 2]> = g.boundary.iter().map(|&b| gr[b as usize]).collect();
    if let Some(cols) = cols {
        dot_test(&cols, &vb, &g.w, &jv, &gb);
    }
}

fn plan(inp: &Input, g: &Grid) {
    let (n, ni) = (g.points.len(), g.ni);
    let mut edges = Vec::new();
    for p in 0..n {
        if p % ni + 1 < ni {
            edges.push([p as u32, p as u32 + 1]);
        }
        if p + ni < n {
            edges.push([p as u32, (p + ni) as u32]);
        }
    }
    let mut offsets = vec![0u32; n + 1];
    let mut targets = vec![0u32; 2 * edges.len()];
    let used = deform_kernel::graph_from_edges(n, &edges, &mut offsets, &mut targets).unwrap();
    let graph = Graph::new(&offsets, &targets[..used]).unwrap();
    let quaternion = inp.choice & 16 != 0;
    let solver = if inp.choice & 32 != 0 {
        PlanSolver::Method(LinearMethod::Cg {
            preconditioner: Preconditioner::Jacobi,
        })
    } else {
        PlanSolver::Amg(AmgOptions {
            max_coarse: 2,
            ..AmgOptions::default()
        })
    };
    let spec = PlanSpec {
        points: &g.points,
        graph,
        boundary: &g.boundary,
        elements: None,
        constraints: None,
        method: if quaternion {
            PlanMethod::QuaternionSpring
        } else {
            PlanMethod::Spring
        },
        stiffness: PlanStiffness::Batina { exponent: 1.0 },
        solver,
        options: OPTIONS,
        renumber: PlanOrder::AsGiven,
    };
    let Ok(ws) = Plan::<f64, 2>::work_sizes(&spec) else {
        return;
    };
    let (mut wr, mut wi, mut wb) = (
        vec![0.0; ws.reals],
        vec![0u32; ws.indices],
        vec![0u8; ws.bytes],
    );
    let mut work = PlanWork {
        reals: &mut wr,
        indices: &mut wi,
        bytes: &mut wb,
    };
    let Ok(sizes) = Plan::<f64, 2>::sizes(&spec, &mut work) else {
        return;
    };
    let (mut r, mut ix, mut by) = (
        vec![0.0; sizes.reals],
        vec![0u32; sizes.indices],
        vec![0u8; sizes.bytes],
    );
    let Ok(mut p) = Plan::init(&spec, &mut work, &mut r, &mut ix, &mut by) else {
        return;
    };
    let deformed: Vec<[f64; 2]> = g
        .boundary
        .iter()
        .map(|&b| {
            let (x, d) = (g.points[b as usize], g.disp[b as usize]);
            [x[0] + d[0], x[1] + d[1]]
        })
        .collect();
    let q = Quat::from_rotation_z(f64::from(inp.angle) / 300.0);
    let motion = PlanMotion {
        deformed: &deformed,
        rotations: RotationSource::Rigid(q),
        origin: None,
        start: Start::Cold,
    };
    let mut s = vec![
        0.0;
        p.sensitivity_scratch_len()
            .saturating_sub(usize::from(inp.faults & 4 != 0))
    ];
    let vb: Vec<[f64; 2]> = g.boundary.iter().map(|&b| g.v[b as usize]).collect();
    let mut jv = vec![[7.0; 2]; n];
    let early = inp.faults & 8 != 0 && inp.moves.len() % 2 == 0;
    if early {
        let t = p.tangent(&motion, &vb, &mut s, &mut jv);
        outcome(&t, &jv, 7.0, true);
    }
    let mut out = vec![[0.0; 2]; n];
    if p.step(&motion, &mut out).is_err() {
        return;
    }
    let other: Vec<[f64; 2]> = deformed.iter().map(|x| [x[0] + 0.5, x[1]]).collect();
    let wrong = inp.faults & 8 != 0 && !early;
    let m2 = PlanMotion {
        deformed: if wrong { &other } else { &deformed },
        ..motion
    };
    let nan_v = vb.iter().flatten().any(|x| x.is_nan());
    let t = p.tangent(&m2, &vb, &mut s, &mut jv);
    let mut gb = vec![[5.0; 2]; g.boundary.len()];
    let a = p.adjoint(&m2, &g.w, &mut s, &mut gb);
    let bad = inp.faults & 4 != 0 || wrong;
    outcome(&t, &jv, 7.0, bad || nan_v);
    outcome(&a, &gb, 5.0, bad || inp.faults & 1 != 0);
    let (Ok(tr), Ok(ar)) = (t, a) else { return };
    if !tr.converged || !ar.converged || inp.faults & 16 != 0 {
        return;
    }
    let mut s = vec![0.0; p.sensitivity_scratch_len()];
    let cols = columns(vb.len(), |e| {
        let mut col = vec![[0.0; 2]; n];
        p.tangent(&motion, e, &mut s, &mut col)
            .ok()
            .filter(|r| r.converged)
            .map(|_| col)
    });
    if let Some(cols) = cols {
        dot_test(&cols, &vb, &g.w, &jv, &gb);
    }
}
