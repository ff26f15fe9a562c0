//! Renumbered plans (`PlanSpec::renumber`, kernel/src/plan/order.rs): on a mesh numbered at
//! random (as a generator's numbering looks to a solver), a plan that renumbers itself (RCM,
//! Hilbert) writes, step after step (cold, warm, extrapolated), bit for bit the un-permuted
//! output of a plan without the option built on the mesh the caller renumbered with the same
//! permutation (`order::permute`, `permute_graph`), and the unordered plan's output to solver
//! tolerance; linear springs and the quaternion method, 2D and 3D, multigrid and CG. The
//! permutation is the public `rcm_order` / `hilbert_order`; it travels with copied pools and
//! is covered by the checksum; the pools are `2 N` indices larger; errors name the caller's
//! nodes.

#[path = "../support/mod.rs"]
mod support;

use deform_kernel::order::{hilbert_order, permute, permute_graph, rcm_order};
use deform_kernel::plan::{
    Plan, PlanCounts, PlanMethod, PlanMotion, PlanOrder, PlanSizes, PlanSolver, PlanSpec,
    PlanStiffness, PlanWork, Start,
};
use deform_kernel::spring::{AmgOptions, LinearMethod, Preconditioner, SolveOptions};
use deform_kernel::{Cells, Error, Graph};
use support::order::{OwnedGraph, OwnedPerm};
use support::plan::Pools;
use support::quaternion::{block2, block3, TestMesh};

/// A mesh numbered at random: points, graph, boundary (elements over the boundary order).
struct Scrambled<const D: usize> {
    points: Vec<[f64; D]>,
    graph: OwnedGraph,
    boundary: Vec<u32>,
    el: (Vec<u32>, Vec<u32>, Vec<u8>),
}

impl<const D: usize> Scrambled<D> {
    fn new(m: &TestMesh<D>, seed: u64) -> Self {
        let p = OwnedPerm::random(m.points.len(), seed);
        let (points, nodes) = support::order::renumbered(&m.points, &m.cell_nodes, &p);
        let cells = Cells::new(points.len(), &m.cell_offsets, &nodes, &m.cell_kinds).unwrap();
        Scrambled {
            graph: OwnedGraph::from_cells(&cells),
            points,
            boundary: m.boundary.iter().map(|&b| p.inverse[b as usize]).collect(),
            el: (m.el_offsets.clone(), m.el_nodes.clone(), m.el_kinds.clone()),
        }
    }

    /// The same mesh renumbered by `p` as a caller would (the kernel's public helpers).
    fn renumbered(&self, p: &OwnedPerm) -> Self {
        let n = self.points.len();
        let g = self.graph.graph();
        let mut graph = OwnedGraph {
            offsets: vec![0; n + 1],
            targets: vec![0; g.edge_count()],
        };
        permute_graph(p.view(), &g, &mut graph.offsets, &mut graph.targets, None).unwrap();
        let mut points = vec![[0.0; D]; n];
        permute(p.view(), &self.points, &mut points).unwrap();
        Scrambled {
            points,
            graph,
            boundary: self
                .boundary
                .iter()
                .map(|&b| p.inverse[b as usize])
                .collect(),
            el: self.el.clone(),
        }
    }

    fn spec(
        &self,
        method: PlanMethod,
        solver: PlanSolver<f64>,
        renumber: PlanOrder,
    ) -> Spec<'_, D> {
        PlanSpec {
            points: &self.points,
            graph: self.graph.graph(),
            boundary: &self.boundary,
            elements: Some(
                Cells::new(self.boundary.len(), &self.el.0, &self.el.1, &self.el.2).unwrap(),
            ),
            constraints: None,
            method,
            stiffness: PlanStiffness::Batina { exponent: 1.0 },
            solver,
            options: SolveOptions {
                residual_tol: 1e-12,
                ..SolveOptions::default()
            },
            renumber,
        }
    }

    /// Boundary positions at step `s`: a smooth non-rigid motion with a rotation.
    fn deformed(&self, s: usize) -> Vec<[f64; D]> {
        let a = 0.04 * (s as f64 + 1.0);
        let (sn, cs) = a.sin_cos();
        self.boundary
            .iter()
            .map(|&b| {
                let mut p = self.points[b as usize];
                let (x, y) = (p[0], p[1]);
                p[0] = cs * x - sn * y + 0.02 * (3.0 * y).sin();
                p[1] = sn * x + cs * y + 0.03 * a * x * x;
                p
            })
            .collect()
    }
}

type Spec<'a, const D: usize> = PlanSpec<'a, f64, D>;

fn bits<const D: usize>(v: &[[f64; D]]) -> Vec<[u64; D]> {
    v.iter().map(|p| p.map(f64::to_bits)).collect()
}

fn amg() -> PlanSolver<f64> {
    PlanSolver::Amg(AmgOptions {
        max_coarse: 16,
        ..AmgOptions::default()
    })
}

fn cg() -> PlanSolver<f64> {
    PlanSolver::Method(LinearMethod::Cg {
        preconditioner: Preconditioner::Jacobi,
    })
}

/// The permutation the public ordering routines give on the caller's mesh.
fn expected_order<const D: usize>(m: &Scrambled<D>, how: PlanOrder) -> Vec<u32> {
    let n = m.points.len();
    let (mut order, mut inverse) = (vec![0; n], vec![0; n]);
    match how {
        PlanOrder::Rcm => rcm_order(&m.graph.graph(), &mut order, &mut inverse).unwrap(),
        _ => hilbert_order(&m.points, &mut order, &mut inverse, &mut vec![0; n]).unwrap(),
    }
    order
}

/// Three steps (cold, warm, warm with extrapolation) of the ordered plan, the plan on the
/// caller-renumbered mesh and the unordered plan; the first two agree bit for bit once
/// un-permuted, the first and third to solver tolerance.
fn check<const D: usize>(
    m: &Scrambled<D>,
    method: PlanMethod,
    solver: PlanSolver<f64>,
    how: PlanOrder,
) {
    let n = m.points.len();
    let (mut ordered, sizes_o) = Pools::build(&m.spec(method, solver, how)).unwrap();
    let (mut plain, sizes_u) = Pools::build(&m.spec(method, solver, PlanOrder::AsGiven)).unwrap();
    let plan = ordered.open::<D>().unwrap();
    assert_eq!(plan.renumbering(), how);
    let p = OwnedPerm::from_order(plan.permutation().unwrap().order().to_vec());
    assert_eq!(p.order, expected_order(m, how), "{how:?}");
    assert!(!plan.permutation().unwrap().is_identity());
    let r = m.renumbered(&p);
    let (mut caller, sizes_r) = Pools::build(&r.spec(method, solver, PlanOrder::AsGiven)).unwrap();
    // The ordered plan is the renumbered one plus its permutation (2 N indices).
    let plus = PlanSizes {
        indices: sizes_r.indices + 2 * n,
        ..sizes_r
    };
    assert_eq!(sizes_o, plus);
    if matches!(solver, PlanSolver::Method(_)) {
        assert_eq!(sizes_u.indices + 2 * n, sizes_o.indices);
    }
    for (s, start) in [Start::Cold, Start::Warm, Start::Warm]
        .into_iter()
        .enumerate()
    {
        let deformed = m.deformed(s);
        let motion = PlanMotion {
            start,
            ..PlanMotion::new(&deformed)
        };
        let (mut out_o, mut out_r, mut out_u) =
            (vec![[0.0; D]; n], vec![[0.0; D]; n], vec![[0.0; D]; n]);
        let rep_o = ordered
            .open::<D>()
            .unwrap()
            .step(&motion, &mut out_o)
            .unwrap();
        let rep_r = caller
            .open::<D>()
            .unwrap()
            .step(&motion, &mut out_r)
            .unwrap();
        plain
            .open::<D>()
            .unwrap()
            .step(&motion, &mut out_u)
            .unwrap();
        assert_eq!(rep_o, rep_r, "step {s}");
        assert_eq!(rep_o.extrapolated, s == 2 && rep_o.warm);
        let back: Vec<[f64; D]> = (0..n).map(|old| out_r[p.inverse[old] as usize]).collect();
        assert_eq!(
            bits(&out_o),
            bits(&back),
            "{method:?} {how:?} D={D} step {s}"
        );
        let far = out_o
            .iter()
            .zip(&out_u)
            .flat_map(|(a, b)| a.iter().zip(b).map(|(x, y)| (x - y).abs()))
            .fold(0.0, f64::max);
        assert!(far < 1e-8, "{method:?} {how:?} D={D} step {s}: {far:e}");
        for (k, &b) in m.boundary.iter().enumerate() {
            assert_eq!(bits(&[out_o[b as usize]]), bits(&[deformed[k]]));
        }
    }
}

#[test]
fn ordered_plans_give_the_bits_of_the_caller_renumbered_mesh_2d() {
    let m = Scrambled::new(&block2(11, 8), 5);
    check(&m, PlanMethod::Spring, amg(), PlanOrder::Rcm);
    check(&m, PlanMethod::QuaternionSpring, cg(), PlanOrder::Rcm);
    check(&m, PlanMethod::QuaternionSpring, amg(), PlanOrder::Hilbert);
    check(&m, PlanMethod::Spring, cg(), PlanOrder::Hilbert);
}

#[test]
fn ordered_plans_give_the_bits_of_the_caller_renumbered_mesh_3d() {
    let m = Scrambled::new(&block3(5, 5, 4), 9);
    check(&m, PlanMethod::QuaternionSpring, amg(), PlanOrder::Rcm);
    check(&m, PlanMethod::Spring, cg(), PlanOrder::Hilbert);
}

#[test]
fn the_permutation_travels_with_the_pools_and_is_checksummed() {
    let m = Scrambled::new(&block2(9, 7), 3);
    let spec = m.spec(PlanMethod::QuaternionSpring, cg(), PlanOrder::Rcm);
    let (mut a, _) = Pools::build(&spec).unwrap();
    let n = m.points.len();
    let d0 = m.deformed(0);
    let mut out = vec![[0.0; 2]; n];
    a.open::<2>()
        .unwrap()
        .step(&PlanMotion::new(&d0), &mut out)
        .unwrap();
    // A copy resumes with the same bits.
    let mut b = Pools {
        reals: a.reals.clone(),
        indices: a.indices.clone(),
        bytes: a.bytes.clone(),
    };
    let d1 = m.deformed(1);
    let (mut oa, mut ob) = (vec![[0.0; 2]; n], vec![[0.0; 2]; n]);
    a.open::<2>()
        .unwrap()
        .step(&PlanMotion::new(&d1), &mut oa)
        .unwrap();
    b.open::<2>()
        .unwrap()
        .step(&PlanMotion::new(&d1), &mut ob)
        .unwrap();
    assert_eq!(bits(&oa), bits(&ob));
    // The permutation is the last 2 N words of the index pool: a changed word is refused.
    let at = b.indices.len() - 1;
    b.indices[at] ^= 1;
    assert!(matches!(b.open::<2>(), Err(Error::BadPlan { .. })));
    // An unordered plan has no permutation, and the order word is checked.
    let (mut u, _) = Pools::build(&m.spec(PlanMethod::Spring, cg(), PlanOrder::AsGiven)).unwrap();
    assert!(u.open::<2>().unwrap().permutation().is_none());
    u.indices[22] = 3;
    assert!(matches!(u.open::<2>(), Err(Error::BadPlan { .. })));
}

#[test]
fn capacity_and_work_sizes_count_the_permutation() {
    let m = Scrambled::new(&block2(9, 7), 4);
    let g = m.graph.graph();
    let counts = PlanCounts {
        nodes: m.points.len(),
        edges: g.edge_count(),
        boundary: m.boundary.len(),
        elements: None,
    };
    let lin = LinearMethod::Cg {
        preconditioner: Preconditioner::Jacobi,
    };
    for how in [PlanOrder::AsGiven, PlanOrder::Rcm, PlanOrder::Hilbert] {
        let mut spec = m.spec(PlanMethod::Spring, PlanSolver::Method(lin), how);
        spec.elements = None;
        let (_, sizes) = Pools::build(&spec).unwrap();
        assert_eq!(
            Plan::<f64, 2>::capacity_ordered(&counts, PlanMethod::Spring, &lin, how),
            Some(sizes)
        );
        assert_eq!(
            Plan::<f64, 2>::work_capacity_ordered(&counts, how),
            Plan::<f64, 2>::work_sizes(&spec).unwrap()
        );
        // One work index short is refused with the length needed.
        let ws = Plan::<f64, 2>::work_sizes(&spec).unwrap();
        let (mut wr, mut wi, mut wb) = (
            vec![0.0; ws.reals],
            vec![0; ws.indices - 1],
            vec![0; ws.bytes],
        );
        let mut work = PlanWork {
            reals: &mut wr,
            indices: &mut wi,
            bytes: &mut wb,
        };
        assert!(matches!(
            Plan::<f64, 2>::sizes(&spec, &mut work),
            Err(Error::BufferTooSmall { needed, .. }) if needed == ws.indices
        ));
    }
    assert_eq!(
        Plan::<f64, 2>::capacity(&counts, PlanMethod::Spring, &lin),
        Plan::<f64, 2>::capacity_ordered(&counts, PlanMethod::Spring, &lin, PlanOrder::AsGiven)
    );
}

/// Errors of a renumbered plan's validation name the caller's nodes and edges.
#[test]
fn errors_name_the_callers_nodes() {
    let m = Scrambled::new(&block2(9, 7), 6);
    // An isolated extra node (no edges, not on the boundary) cannot be anchored.
    let n = m.points.len();
    let mut iso = Scrambled {
        points: m.points.clone(),
        graph: OwnedGraph {
            offsets: m.graph.offsets.clone(),
            targets: m.graph.targets.clone(),
        },
        boundary: m.boundary.clone(),
        el: m.el.clone(),
    };
    iso.points.push([9.0, 9.0]);
    iso.graph.offsets.push(*iso.graph.offsets.last().unwrap());
    for how in [PlanOrder::AsGiven, PlanOrder::Rcm, PlanOrder::Hilbert] {
        let spec = iso.spec(PlanMethod::Spring, cg(), how);
        assert!(
            matches!(Pools::build(&spec), Err(Error::Unanchored { node }) if node == n),
            "{how:?}"
        );
    }
    // A given stiffness that is not symmetric on one edge, then not positive on one.
    let g: Graph<'_> = m.graph.graph();
    let i = m.boundary.len() / 2;
    let e = g.edge_range(i).start;
    let t = g.targets()[e] as usize;
    for (value, how) in [
        (2.0, PlanOrder::AsGiven),
        (2.0, PlanOrder::Rcm),
        (-1.0, PlanOrder::Hilbert),
    ] {
        let mut k = vec![1.0; g.edge_count()];
        k[e] = value;
        let mut spec = m.spec(PlanMethod::Spring, cg(), how);
        spec.stiffness = PlanStiffness::Given(&k);
        let err = Pools::build(&spec).err();
        let named = match err {
            Some(Error::NotSymmetric { from, to }) => [from, to] == [i, t] || [from, to] == [t, i],
            Some(Error::NonPositive {
                arg: "stiffness",
                position,
            }) => value < 0.0 && position == e,
            _ => false,
        };
        assert!(named, "{how:?}: {err:?}");
    }
}
