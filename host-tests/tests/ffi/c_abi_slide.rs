//! Sliding boundaries (symmetry planes) through the C ABI: builds `libdeform_kernel` (static
//! and shared), compiles `ffi/tests/slide.c` (a rotated 2D half annulus whose symmetry line
//! slides: `dk_fit_plane`, `dk_constraints_fixed_mask`, `dk_spring_solve_linear_sliding` with
//! CG + Jacobi and SOR, `dk_spring_solve_angle_sliding` with over-relaxed direct Gauss–Seidel
//! and CG, `dk_spring_solve_{linear,angle}_sliding_amg` with their pool-size queries and
//! `dk_slide_points`, f64 and f32, plus bad input that must return its status and write
//! nothing), runs it, and compares every printed fit, pool size, report and value with the
//! kernel (`slide::fit_plane`, `Constraints`, `solve_linear_sliding`, `solve_angle_sliding`,
//! `AmgHierarchy::setup` + `solve_linear_sliding` / `solve_angle_sliding_amg`, `slide_points`)
//! on the same inputs, bit for bit. Needs `gcc` on PATH.

#[path = "../support/mod.rs"]
mod support;

use support::c_build::*;

use deform_kernel::spring::constraints::{fit_plane, slide_points, Constraints};
use deform_kernel::spring::{
    batina_stiffness, solve_linear_sliding_scratch_len, AmgHierarchy, AmgOptions, AngleMethod,
    AngleSystem, LinearMethod, LinearSolver, Preconditioner, SolveOptions, SolveReport,
    SpringSystem,
};
use deform_kernel::{graph_from_edges, Graph, Real};

const NT: usize = 65;
const NR: usize = 17;
const N: usize = NT * NR;

/// The mesh of slide.c: CSR graph (edges in the C program's order), kinds (1 on both
/// circles, 2 on the symmetry line, else 0) and the symmetry line's nodes.
fn mesh() -> (Vec<u32>, Vec<u32>, Vec<u8>, Vec<u32>) {
    let mut e = Vec::new();
    let mut kinds = vec![0u8; N];
    let mut sym = Vec::new();
    for j in 0..NR {
        for i in 0..NT {
            let n = (i + NT * j) as u32;
            kinds[i + NT * j] = if j == 0 || j == NR - 1 {
                1
            } else if i == 0 || i == NT - 1 {
                2
            } else {
                0
            };
            if i == 0 || i == NT - 1 {
                sym.push(n);
            }
            if i + 1 < NT {
                e.push([n, n + 1]);
            }
            if j + 1 < NR {
                e.push([n, n + NT as u32]);
            }
            if i + 1 < NT && j + 1 < NR {
                e.push([n, n + NT as u32 + 1]);
            }
        }
    }
    let mut offsets = vec![0u32; N + 1];
    let mut targets = vec![0u32; 2 * e.len()];
    let used = graph_from_edges(N, &e, &mut offsets, &mut targets).unwrap();
    targets.truncate(used);
    (offsets, targets, kinds, sym)
}

/// The three lines slide.c prints for a solve.
fn solve_lines<T: Real>(
    what: &str,
    tag: &str,
    r: SolveReport<T>,
    v: &[[T; 2]],
    hex: fn(&str, &[T]) -> String,
) -> Vec<String> {
    let flat: Vec<T> = v.iter().flatten().copied().collect();
    vec![
        format!("{what}_{tag} {} {}", r.iterations, u8::from(r.converged)),
        hex64(
            &format!("{what}_report_{tag}"),
            &[r.residual.to_f64(), r.max_update.to_f64()],
        ),
        hex(&format!("{what}_values_{tag}"), &flat),
    ]
}

/// What slide.c prints for one precision, from the kernel called directly.
fn expected<T: Real>(
    tag: &str,
    points: &[f64],
    values0: &[f64],
    hex: fn(&str, &[T]) -> String,
) -> Vec<String> {
    let (offsets, targets, kinds, sym) = mesh();
    let g = Graph::new(&offsets, &targets).unwrap();
    let two = |s: &[f64]| -> Vec<[T; 2]> {
        s.chunks_exact(2)
            .map(|p| [T::from_f64(p[0]), T::from_f64(p[1])])
            .collect()
    };
    let pts = two(points);
    let v0 = two(values0);
    assert_eq!(pts.len(), N);
    let mut k = vec![T::ZERO; g.edge_count()];
    batina_stiffness(&g, &pts, T::ONE, &mut k).unwrap();
    let mut out = Vec::new();

    let fit = fit_plane(&pts, &sym, T::from_f64(1e-4)).unwrap();
    out.push(hex(
        &format!("fit_{tag}"),
        &[
            fit.normal[0],
            fit.normal[1],
            fit.point[0],
            fit.point[1],
            fit.residual,
            fit.extent,
        ],
    ));
    // Free and fixed nodes' directions are never read (C passes NaN and infinity).
    let dirs: Vec<[T; 2]> = kinds
        .iter()
        .map(|&k| if k == 2 { fit.normal } else { [T::ZERO; 2] })
        .collect();
    let c = Constraints::new(&kinds, &dirs).unwrap();
    let mut mask = vec![0u8; N];
    c.fixed_mask(&mut mask).unwrap();
    let mut idx = vec![0u32; N];
    let sys = SpringSystem::new(g, &k, &mask, &mut idx).unwrap();
    let stop = SolveOptions::<T>::default();

    for (what, method) in [
        (
            "lin_cg",
            LinearMethod::Cg {
                preconditioner: Preconditioner::Jacobi,
            },
        ),
        (
            "lin_sor",
            LinearMethod::Sor {
                omega: T::from_f64(1.7),
            },
        ),
    ] {
        let solver = LinearSolver::Method(method);
        let mut scratch = vec![[T::ZERO; 2]; solve_linear_sliding_scratch_len(&solver, N)];
        let mut v = v0.clone();
        let r = sys
            .solve_linear_sliding(&c, &mut v, solver, &stop, &mut scratch)
            .unwrap();
        out.extend(solve_lines(what, tag, r, &v, hex));
    }

    let asys = AngleSystem::new(sys, &pts, T::from_f64(0.1)).unwrap();
    for (what, method, omega) in [
        ("ang_sor", AngleMethod::DirectGaussSeidel, 1.5),
        ("ang_cg", AngleMethod::Cg, 1.0),
    ] {
        let mut scratch = vec![[T::ZERO; 2]; asys.solve_angle_sliding_scratch_len(method)];
        let mut v = v0.clone();
        let r = asys
            .solve_angle_sliding(&c, &mut v, method, T::from_f64(omega), &stop, &mut scratch)
            .unwrap();
        out.extend(solve_lines(what, tag, r, &v, hex));
    }

    let opts = AmgOptions::<T>::default();
    let mut work = vec![0u32; AmgHierarchy::setup_work_len(&sys)];
    let sizes = AmgHierarchy::setup_len(&sys, &opts, &mut work).unwrap();
    let mut index = vec![0u32; sizes.index];
    let mut hv = vec![T::ZERO; sizes.values];
    let h = AmgHierarchy::setup(&sys, &opts, &mut work, &mut index, &mut hv).unwrap();
    let solver = LinearSolver::Amg(&h);
    let items = solve_linear_sliding_scratch_len(&solver, N);
    assert_eq!(items, 6 * N + 3 * h.coarse_unknowns());
    out.push(format!(
        "sizes_{tag} {} {} {} 0",
        work.len(),
        sizes.values + 2 * items,
        work.len() + sizes.index
    ));
    let mut scratch = vec![[T::ZERO; 2]; items];
    let mut v = v0.clone();
    let r = sys
        .solve_linear_sliding(&c, &mut v, solver, &stop, &mut scratch)
        .unwrap();
    out.extend(solve_lines("lin_amg", tag, r, &v, hex));

    // A hierarchy set up again on the angle system's base, as the C entry does.
    let mut work = vec![0u32; AmgHierarchy::setup_work_len(asys.base())];
    let mut index = vec![0u32; sizes.index];
    let mut hv = vec![T::ZERO; sizes.values];
    let h = AmgHierarchy::setup(asys.base(), &opts, &mut work, &mut index, &mut hv).unwrap();
    assert_eq!(asys.solve_angle_sliding_amg_scratch_len(&h), items);
    let mut scratch = vec![[T::ZERO; 2]; items];
    let mut v = v0.clone();
    let r = asys
        .solve_angle_sliding_amg(&c, &mut v, &h, &stop, &mut scratch)
        .unwrap();
    out.extend(solve_lines("ang_amg", tag, r, &v, hex));

    let mut moved: Vec<[T; 2]> = pts
        .iter()
        .enumerate()
        .map(|(i, p)| {
            [
                p[0] + T::from_f64(0.01 * (i % 7) as f64),
                p[1] + T::from_f64(0.02 * (i % 5) as f64),
            ]
        })
        .collect();
    slide_points(&c, &pts, &mut moved).unwrap();
    let flat: Vec<T> = moved.iter().flatten().copied().collect();
    out.push(hex(&format!("slid_points_{tag}"), &flat));
    out.into_iter().map(|l| l.trim_end().to_string()).collect()
}

#[test]
fn sliding_from_c_equals_the_kernel_bit_for_bit() {
    let src = workspace().join("ffi/tests/slide.c");
    let mut flags = c_flags();
    // cargo's test runner puts its own target directories on LD_LIBRARY_PATH, which a RUNPATH
    // would not override (see c_abi_solvers.rs).
    flags.push("-Wl,--disable-new-dtags".to_string());
    let flags: Vec<&str> = flags.iter().map(String::as_str).collect();
    for (link, name) in [
        (Link::Static, "slide_static"),
        (Link::Shared, "slide_shared"),
    ] {
        let exe = tmp(name);
        compile("gcc", std::slice::from_ref(&src), &flags, link, &exe);
        let printed = run(&exe);
        let lines: Vec<&str> = printed.lines().collect();
        assert_eq!(lines.last(), Some(&"slide: every check held"), "{name}");
        let points = parse_hex64(lines[0], "points");
        let values0 = parse_hex64(lines[1], "values0");
        let mut want = expected::<f64>("f64", &points, &values0, hex64);
        want.extend(expected::<f32>("f32", &points, &values0, hex32));
        let got: Vec<&str> = lines[2..lines.len() - 1].to_vec();
        assert_eq!(got.len(), want.len(), "{name}: lines");
        for (g, e) in got.iter().zip(&want) {
            let head = |s: &str| s.split(' ').next().unwrap_or("").to_string();
            assert!(
                g == e,
                "{name}: {} differs from the kernel's {}",
                head(g),
                head(e)
            );
        }
        // Multigrid needs fewer iterations than the one-level CG on the same problems.
        let count = |prefix: &str| -> usize {
            let l = lines
                .iter()
                .find(|l| l.starts_with(&format!("{prefix} ")))
                .unwrap_or_else(|| panic!("{name}: no {prefix} line"));
            l.split(' ').nth(1).unwrap().parse().unwrap()
        };
        for t in ["f64", "f32"] {
            assert!(count(&format!("lin_amg_{t}")) < count(&format!("lin_cg_{t}")));
            assert!(count(&format!("ang_amg_{t}")) < count(&format!("ang_cg_{t}")));
        }
    }
}
