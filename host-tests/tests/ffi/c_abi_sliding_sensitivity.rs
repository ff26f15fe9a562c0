//! Sensitivities with sliding nodes through the C ABI: builds `libdeform_kernel` (static and
//! shared), compiles `ffi/tests/sliding_sensitivity.c` (`dk_sensitivity_spring_sliding_*` and
//! `dk_elasticity_sliding_*` and their `_f32` twins on a 2D square with a sliding edge and a
//! 3D cube with two sliding faces and their sliding common edge: the dot-product identity, the
//! forward solves' bits, the planes, bad input), runs it, and recomputes every printed result
//! with the kernel's `spring_sliding_tangent` / `_adjoint` and `elastic_sliding_tangent` /
//! `_adjoint` on the same inputs, bit for bit in both precisions. Also runs
//! `ffi/tests/sliding_sensitivity.f90` (the adjoint through the Fortran module). Needs `gcc` and
//! `gfortran` on PATH.

#[path = "../support/mod.rs"]
mod support;

use support::c_build::*;

use deform_kernel::elasticity::{
    assemble, cell_moduli, elasticity_graph, elasticity_graph_len, ElasticSystem, Modulus,
};
use deform_kernel::sensitivity::{
    elastic_sliding_adjoint, elastic_sliding_adjoint_scratch_len, elastic_sliding_tangent,
    elastic_sliding_tangent_scratch_len, spring_sliding_adjoint,
    spring_sliding_adjoint_scratch_len, spring_sliding_tangent, ElasticPreconditioner,
};
use deform_kernel::spring::constraints::Constraints;
use deform_kernel::spring::{
    solve_linear_sliding_scratch_len, LinearMethod, LinearSolver, Preconditioner, SolveOptions,
    SpringSystem,
};
use deform_kernel::{Cells, Graph, Real};

/// One mesh as the C program prints it.
struct Case {
    n: usize,
    offsets: Vec<u32>,
    nodes: Vec<u32>,
    cell_kinds: Vec<u8>,
    points: Vec<f64>,
    kinds: Vec<u8>,
    dirs: Vec<f64>,
    k: Vec<f64>,
    v: Vec<f64>,
    w: Vec<f64>,
}

/// The integers of a `name i i ...` line.
fn ints<I: std::str::FromStr>(line: &str, name: &str) -> Vec<I> {
    let rest = line
        .strip_prefix(name)
        .unwrap_or_else(|| panic!("expected {name}"));
    rest.split_whitespace()
        .map(|x| x.parse().ok().expect("integer"))
        .collect()
}

impl Case {
    /// The case whose `case` line is `lines[0]` (10 lines of inputs).
    fn parse(lines: &[&str]) -> Case {
        let head: Vec<usize> = ints(lines[0], "case");
        Case {
            n: head[1],
            offsets: ints(lines[1], "cell_offsets"),
            nodes: ints(lines[2], "cell_nodes"),
            cell_kinds: ints(lines[3], "cell_kinds"),
            points: parse_hex64(lines[4], "points"),
            kinds: ints(lines[5], "kinds"),
            dirs: parse_hex64(lines[6], "dirs"),
            k: parse_hex64(lines[7], "k"),
            v: parse_hex64(lines[8], "v"),
            w: parse_hex64(lines[9], "w"),
        }
    }
}

fn items<T: Real, const D: usize>(x: &[f64]) -> Vec<[T; D]> {
    x.chunks(D)
        .map(|c| std::array::from_fn(|k| T::from_f64(c[k])))
        .collect()
}

fn flat<T: Copy, const D: usize>(x: &[[T; D]]) -> Vec<T> {
    x.iter().flatten().copied().collect()
}

/// The four result lines (spring tangent and adjoint, elastic tangent and adjoint) the C
/// program prints for precision `T` (`tag` "" or "32"), computed by the kernel.
fn expected<T: Real, const D: usize>(
    c: &Case,
    residual_tol: f64,
    tag: &str,
    hex: fn(&str, &[T]) -> String,
) -> String {
    let n = c.n;
    let cells = Cells::new(n, &c.offsets, &c.nodes, &c.cell_kinds).unwrap();
    let mut goffs = vec![0u32; n + 1];
    let mut targets = vec![0u32; elasticity_graph_len(&cells)];
    let used = elasticity_graph(&cells, &mut goffs, &mut targets).unwrap();
    let graph = Graph::new(&goffs, &targets[..used]).unwrap();
    let mask: Vec<u8> = c.kinds.iter().map(|&k| u8::from(k == 1)).collect();
    let dirs = items::<T, D>(&c.dirs);
    let con = Constraints::new(&c.kinds, &dirs).unwrap();
    let (points, v, w) = (
        items::<T, D>(&c.points),
        items::<T, D>(&c.v),
        items::<T, D>(&c.w),
    );
    let opts = SolveOptions {
        max_iterations: 10_000,
        residual_tol: T::from_f64(residual_tol),
        update_tol: T::ZERO,
    };

    let k: Vec<T> = c.k.iter().map(|&x| T::from_f64(x)).collect();
    let mut iscr = vec![0u32; n];
    let springs = SpringSystem::new(graph, &k, &mask, &mut iscr).unwrap();
    let solver = LinearSolver::Method(LinearMethod::Cg {
        preconditioner: Preconditioner::Jacobi,
    });
    let mut sjv = v.clone();
    let mut s = vec![[T::ZERO; D]; solve_linear_sliding_scratch_len(&solver, n)];
    spring_sliding_tangent(&springs, &con, solver, &opts, &mut sjv, &mut s).unwrap();
    let mut sg = vec![[T::ZERO; D]; n];
    let mut s = vec![[T::ZERO; D]; spring_sliding_adjoint_scratch_len::<T, D>(&solver, n)];
    spring_sliding_adjoint(&springs, &con, solver, &opts, &w, &mut sg, &mut s).unwrap();

    let mut moduli = vec![T::ZERO; c.cell_kinds.len()];
    cell_moduli(&cells, &points, Modulus::InverseVolume, None, &mut moduli).unwrap();
    let mut diag = vec![[[T::ZERO; D]; D]; n];
    let mut off = vec![[[T::ZERO; D]; D]; used];
    let poisson = T::from_f64(0.3);
    assemble(
        &cells, &points, &graph, &moduli, poisson, &mut diag, &mut off,
    )
    .unwrap();
    let sys = ElasticSystem::new(graph, &diag, &off, &mask).unwrap();
    let pre = ElasticPreconditioner::Blocks;
    let mut ejv = v.clone();
    let mut s = vec![[T::ZERO; D]; elastic_sliding_tangent_scratch_len(&pre, n)];
    elastic_sliding_tangent(&sys, &con, pre, &opts, &mut ejv, &mut s).unwrap();
    let mut eg = vec![[T::ZERO; D]; n];
    let mut s = vec![[T::ZERO; D]; elastic_sliding_adjoint_scratch_len(&pre, n)];
    elastic_sliding_adjoint(&sys, &con, pre, &opts, &w, &mut eg, &mut s).unwrap();

    [
        ("spring_jv", sjv),
        ("spring_g", sg),
        ("elastic_jv", ejv),
        ("elastic_g", eg),
    ]
    .iter()
    .map(|(name, x)| hex(&format!("{name}{tag}"), &flat(x)))
    .collect()
}

/// Both precisions' result lines for the case.
fn expected_both<const D: usize>(c: &Case) -> String {
    expected::<f64, D>(c, 1e-13, "", hex64) + &expected::<f32, D>(c, 1e-6, "32", hex32)
}

#[test]
fn sliding_sensitivities_from_c_equal_the_kernel_bit_for_bit() {
    for (name, printed) in run_c_both("sliding_sensitivity") {
        let lines: Vec<&str> = printed.lines().collect();
        assert_eq!(
            lines.last(),
            Some(&"sliding_sensitivity: every check held"),
            "{name}: {printed}"
        );
        let starts: Vec<usize> = (0..lines.len())
            .filter(|&i| lines[i].starts_with("case "))
            .collect();
        assert_eq!(starts.len(), 2, "{name}: two cases");
        for (&at, dim) in starts.iter().zip([2, 3]) {
            let case = Case::parse(&lines[at..]);
            let want = match dim {
                2 => expected_both::<2>(&case),
                _ => expected_both::<3>(&case),
            };
            // After the inputs: two identity lines, four f64 lines, four f32 lines.
            let got: Vec<&str> = lines[at + 10..]
                .iter()
                .filter(|l| !l.contains("identity"))
                .take(8)
                .copied()
                .collect();
            assert_eq!(got.join("\n") + "\n", want, "{name}: {dim}D");
        }
    }
}

#[test]
fn sliding_adjoint_from_fortran_satisfies_the_dot_product_identity() {
    assert_eq!(
        fortran_test("sliding_sensitivity"),
        "sliding_sensitivity: every check held\n"
    );
}
