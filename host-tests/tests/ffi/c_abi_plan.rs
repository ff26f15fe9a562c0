//! Prepared plans from C and Fortran: `ffi/examples/plan_pitching.{c,f90}` step a pitching
//! O-grid 20 times through one plan (checkpointed halfway); the Fortran program must print
//! exactly what the C one prints, and the Rust `Plan` API on the same input must give the same
//! iterations, warm/extrapolated choices and final mesh, bit for bit. The examples fail
//! unless warm starts take fewer iterations than cold ones. Renumbered plans
//! (`ffi/tests/plan_order.c`) against the Rust plan. Needs `gcc` and `gfortran`.

#[path = "../support/mod.rs"]
mod support;

use support::c_build::*;

use deform_kernel::plan::{
    Plan, PlanMethod, PlanMotion, PlanOrder, PlanSolver, PlanSpec, PlanStiffness, PlanWork, Start,
};
use deform_kernel::quaternion::RotationSource;
use deform_kernel::spring::{AmgOptions, LinearMethod, Preconditioner, SolveOptions};
use deform_kernel::{graph_from_cells, graph_from_cells_len, Cells, Graph, Quat};

const NI: usize = 48;
const NJ: usize = 16;
const N: usize = NI * NJ;
const B: usize = 2 * NI;
const STEPS: usize = 20;

fn parse_hex(line: &str, name: &str) -> Vec<f64> {
    let rest = line
        .strip_prefix(name)
        .unwrap_or_else(|| panic!("expected {name}: {line}"));
    rest.split_whitespace()
        .map(|h| f64::from_bits(u64::from_str_radix(h, 16).expect("hex")))
        .collect()
}

fn pairs(v: &[f64]) -> Vec<[f64; 2]> {
    v.chunks_exact(2).map(|c| [c[0], c[1]]).collect()
}

#[test]
fn c_plan_steps_equal_the_rust_plan_bit_for_bit() {
    let src = workspace().join("ffi/examples/plan_pitching.c");
    let flags = c_flags();
    let flags: Vec<&str> = flags.iter().map(String::as_str).collect();
    let exe = tmp("plan_pitching_c");
    compile(
        "gcc",
        std::slice::from_ref(&src),
        &flags,
        Link::Static,
        &exe,
    );
    let printed = run(&exe);

    let module = workspace().join("ffi/generated/deform_kernel.f90");
    let fsrc = workspace().join("ffi/examples/plan_pitching.f90");
    let moddir = tmp("plan_pitching_f_mod");
    std::fs::create_dir_all(&moddir).unwrap();
    let jflag = format!("-J{}", moddir.display());
    let fexe = tmp("plan_pitching_f");
    compile(
        "gfortran",
        &[module, fsrc],
        &["-std=f2008", "-Wall", "-Werror", &jflag],
        Link::Static,
        &fexe,
    );
    assert!(
        run(&fexe) == printed,
        "the Fortran example printed something else than the C one"
    );
    let mut lines = printed.lines();

    // The same mesh, graph, boundary and elements as the C program builds.
    let points = pairs(&parse_hex(lines.next().unwrap(), "points"));
    assert_eq!(points.len(), N);
    let mut co = Vec::new();
    let mut cn = Vec::new();
    for j in 0..NJ - 1 {
        for i in 0..NI {
            let i1 = (i + 1) % NI;
            co.push(cn.len() as u32);
            cn.extend(
                [j * NI + i, j * NI + i1, (j + 1) * NI + i1, (j + 1) * NI + i].map(|x| x as u32),
            );
        }
    }
    co.push(cn.len() as u32);
    let ck = vec![9u8; co.len() - 1];
    let cells = Cells::new(N, &co, &cn, &ck).unwrap();
    let mut offsets = vec![0u32; N + 1];
    let mut targets = vec![0u32; graph_from_cells_len(&cells, true)];
    let used = graph_from_cells(&cells, true, &mut offsets, &mut targets).unwrap();
    let graph = Graph::new(&offsets, &targets[..used]).unwrap();
    let boundary: Vec<u32> = (0..NI)
        .map(|i| i as u32)
        .chain((0..NI).map(|i| ((NJ - 1) * NI + i) as u32))
        .collect();
    let eo: Vec<u32> = (0..=B).map(|i| 2 * i as u32).collect();
    let en: Vec<u32> = (0..B)
        .flat_map(|i| {
            let (ring, k) = (i / NI, i % NI);
            [(ring * NI + k) as u32, (ring * NI + (k + 1) % NI) as u32]
        })
        .collect();
    let ek = vec![3u8; B];
    let elements = Cells::new(B, &eo, &en, &ek).unwrap();
    let spec = PlanSpec {
        points: &points,
        graph,
        boundary: &boundary,
        elements: Some(elements),
        constraints: None,
        method: PlanMethod::QuaternionSpring,
        stiffness: PlanStiffness::Batina { exponent: 1.0 },
        solver: PlanSolver::Amg(AmgOptions::default()),
        options: SolveOptions::default(),
        renumber: PlanOrder::AsGiven,
    };
    let ws = Plan::<f64, 2>::work_sizes(&spec).unwrap();
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
    let sizes = Plan::<f64, 2>::sizes(&spec, &mut work).unwrap();
    let (mut reals, mut indices, mut bytes) = (
        vec![0.0; sizes.reals],
        vec![0u32; sizes.indices],
        vec![0u8; sizes.bytes],
    );
    let mut plan = Plan::init(&spec, &mut work, &mut reals, &mut indices, &mut bytes).unwrap();
    let header = lines.next().unwrap();
    assert!(
        header.starts_with(&format!(
            "plan: {N} nodes, {B} boundary points, {} multigrid levels, pools {} + {} + {}",
            plan.amg_levels(),
            sizes.reals,
            sizes.indices,
            sizes.bytes
        )),
        "{header}"
    );

    let mut out = vec![[0.0f64; 2]; N];
    for n in 1..=STEPS {
        let deformed = pairs(&parse_hex(
            lines.next().unwrap(),
            &format!("step {n} deformed"),
        ));
        assert_eq!(deformed.len(), B);
        let r = plan.step(&PlanMotion::new(&deformed), &mut out).unwrap();
        assert_eq!(
            lines.next().unwrap(),
            format!(
                "step {n} iterations {} warm {} extrapolated {}",
                r.solve.iterations,
                u8::from(r.warm),
                u8::from(r.extrapolated)
            )
        );
    }
    let c_final = parse_hex(lines.next().unwrap(), "final");
    let rust_final: Vec<f64> = out.iter().flatten().copied().collect();
    assert_eq!(c_final.len(), rust_final.len());
    let differ = c_final
        .iter()
        .zip(&rust_final)
        .filter(|(a, b)| a.to_bits() != b.to_bits())
        .count();
    assert_eq!(differ, 0, "final meshes differ in {differ} scalars");
    let totals = lines.next().unwrap();
    assert!(totals.starts_with("iterations: warm "), "{totals}");
}

#[test]
fn c_plan_f32_twins_and_bad_input() {
    let src = workspace().join("ffi/tests/plan.c");
    let flags = c_flags();
    let flags: Vec<&str> = flags.iter().map(String::as_str).collect();
    for (link, name) in [
        (Link::Static, "plan_c_static"),
        (Link::Shared, "plan_c_shared"),
    ] {
        let exe = tmp(name);
        compile("gcc", std::slice::from_ref(&src), &flags, link, &exe);
        assert_eq!(run(&exe), "plan: every check held\n", "{name}");
    }
}

/// The plans' edge cases from C (`ffi/tests/plan_edges.c`): one-level hierarchies, the work
/// sizes' validation, the spring method ignoring `rotation_source`.
#[test]
fn c_plan_edge_cases() {
    assert_eq!(
        run_c_test("plan_edges", "plan_edges_c", Link::Static),
        "plan_edges: every check held\n"
    );
}

/// Renumbered plans from C (`ffi/tests/plan_order.c`, which checks them against plain plans on
/// the mesh it renumbers itself): each method's final mesh is the Rust plan's with
/// `PlanOrder::Rcm` on the same input, bit for bit.
#[test]
fn c_renumbered_plans_equal_the_rust_plan_bit_for_bit() {
    let printed = run_c_test("plan_order", "plan_order_c", Link::Static);
    let mut lines = printed.lines();
    let mut next = |name: &str| lines.next().unwrap_or_else(|| panic!("{name}: {printed}"));
    let ints = |line: &str, name: &str| -> Vec<u32> {
        let rest = line
            .strip_prefix(name)
            .unwrap_or_else(|| panic!("{name}: {line}"));
        rest.split_whitespace()
            .map(|x| x.parse().unwrap())
            .collect()
    };
    let points = pairs(&parse_hex(next("points"), "points"));
    let offsets = ints(next("offsets"), "offsets");
    let targets = ints(next("targets"), "targets");
    let boundary = ints(next("boundary"), "boundary");
    let deformed = pairs(&parse_hex(next("deformed"), "deformed"));
    let rotation = Quat::new(0.9987502603949663, 0.0, 0.0, 0.04997916927067833);
    for (method, solver, name) in [
        (
            PlanMethod::Spring,
            PlanSolver::Amg(AmgOptions::default()),
            "spring",
        ),
        (
            PlanMethod::QuaternionSpring,
            PlanSolver::Method(LinearMethod::Cg {
                preconditioner: Preconditioner::Jacobi,
            }),
            "quaternion",
        ),
    ] {
        let spec = PlanSpec {
            points: &points,
            graph: Graph::new(&offsets, &targets).unwrap(),
            boundary: &boundary,
            elements: None,
            constraints: None,
            method,
            stiffness: PlanStiffness::Batina { exponent: 1.0 },
            solver,
            options: SolveOptions::default(),
            renumber: PlanOrder::Rcm,
        };
        let (mut pools, _) = support::plan::Pools::build(&spec).unwrap();
        let mut plan = pools.open::<2>().unwrap();
        let mut out = vec![[0.0; 2]; points.len()];
        for start in [Start::Cold, Start::Warm] {
            let motion = PlanMotion {
                rotations: RotationSource::Rigid(rotation),
                start,
                ..PlanMotion::new(&deformed)
            };
            plan.step(&motion, &mut out).unwrap();
        }
        let c_final = parse_hex(next(name), name);
        let rust: Vec<u64> = out.iter().flatten().map(|x| x.to_bits()).collect();
        assert_eq!(
            c_final.iter().map(|x| x.to_bits()).collect::<Vec<_>>(),
            rust,
            "{name}"
        );
    }
    assert_eq!(next("end"), "plan_order: every check held");
}

/// The derivative of a plan's last step from C (`ffi/tests/plan_sensitivity.c`):
/// `dk_plan_tangent` and `dk_plan_adjoint` (and the `_f32` twins) after a cold step equal bit
/// for bit the stateless C calls of the same kernel (`dk_deform_spring_tangent` / `_adjoint`,
/// `dk_sensitivity_spring_adjoint`) on the same mesh and solver; bad calls write nothing.
#[test]
fn c_plan_derivatives_equal_the_stateless_calls() {
    assert_eq!(
        run_c_test("plan_sensitivity", "plan_sensitivity_c", Link::Static),
        "plan_sensitivity: every check held\n"
    );
}
