//! Target 13: prepared plans on arbitrary small 2D meshes (random graph, points, boundary
//! subset, method, solver) and arbitrary steps: no panic; the size query is exact (pools of
//! exactly that size work, one entry less is a typed error that leaves the pools untouched);
//! cold steps give the bits of the stateless calls (`solve_linear_with` from zero,
//! `deform_spring_with` with rigid rotations); a failing step (NaN or wrong-length input, or a
//! numerical failure) leaves `out` untouched and the plan as it was (the next step gives the
//! bits of a copy taken before); copied pools resume with the same bits; a flipped bit in the
//! header or in an immutable index section is `BadPlan`.
#![no_main]

use arbitrary::Arbitrary;
use deform_kernel::plan::{
    Plan, PlanCounts, PlanMethod, PlanMotion, PlanSizes, PlanSolver, PlanSpec, PlanStiffness,
    PlanWork, Start,
};
use deform_kernel::quaternion::{
    deform_spring_scratch_len, deform_spring_with, propagate_spring_with_scratch_len,
    BoundaryMotion, RotationSource,
};
use deform_kernel::spring::{
    batina_stiffness, solve_linear_with_scratch_len, AmgHierarchy, AmgOptions, LinearMethod,
    LinearSolver, Preconditioner, SolveOptions, SpringSystem,
};
use deform_kernel::{graph_from_edges, graph_from_edges_len, Error, Graph, Quat};
use libfuzzer_sys::fuzz_target;

#[derive(Arbitrary, Debug)]
struct Step {
    moves: Vec<(u8, i8, i8)>,
    angle: i8,
    cold: bool,
    nan: bool,
    short: bool,
}

#[derive(Arbitrary, Debug)]
struct Input {
    node_count: u8,
    edges: Vec<[u8; 2]>,
    coords: Vec<[i8; 2]>,
    boundary: Vec<u8>,
    quaternion: bool,
    solver: u8,
    steps: Vec<Step>,
    flip: (u16, u8),
}

#[derive(Clone)]
struct Pools {
    reals: Vec<f64>,
    indices: Vec<u32>,
    bytes: Vec<u8>,
}

impl Pools {
    fn zeros(s: PlanSizes) -> Self {
        Pools {
            reals: vec![0.0; s.reals],
            indices: vec![0; s.indices],
            bytes: vec![0; s.bytes],
        }
    }

    fn same(&self, o: &Pools) -> bool {
        self.indices == o.indices
            && self.bytes == o.bytes
            && self
                .reals
                .iter()
                .zip(&o.reals)
                .all(|(a, b)| a.to_bits() == b.to_bits())
    }
}

fn bits(v: &[[f64; 2]]) -> Vec<u64> {
    v.iter().flatten().map(|x| x.to_bits()).collect()
}

fuzz_target!(|inp: Input| {
    let n = (inp.node_count % 24) as usize + 2;
    let edges: Vec<[u32; 2]> = inp
        .edges
        .iter()
        .map(|&[a, b]| [(a as usize % n) as u32, (b as usize % n) as u32])
        .filter(|e| e[0] != e[1])
        .collect();
    let mut offsets = vec![0u32; n + 1];
    let mut targets = vec![0u32; graph_from_edges_len(&edges)];
    let Ok(used) = graph_from_edges(n, &edges, &mut offsets, &mut targets) else {
        return;
    };
    targets.truncate(used);
    let Ok(graph) = Graph::new(&offsets, &targets) else {
        return;
    };
    let points: Vec<[f64; 2]> = (0..n)
        .map(|i| {
            let c = inp
                .coords
                .get(i)
                .copied()
                .unwrap_or([i as i8, (i * 7 % 5) as i8]);
            [f64::from(c[0]) / 8.0 + i as f64, f64::from(c[1]) / 8.0]
        })
        .collect();
    let mut boundary: Vec<u32> = inp
        .boundary
        .iter()
        .map(|&b| (b as usize % n) as u32)
        .collect();
    boundary.truncate(n);
    let method = if inp.quaternion {
        PlanMethod::QuaternionSpring
    } else {
        PlanMethod::Spring
    };
    let solver = match inp.solver % 3 {
        0 => PlanSolver::Amg(AmgOptions {
            max_coarse: 2,
            ..AmgOptions::default()
        }),
        1 => PlanSolver::Method(LinearMethod::Cg {
            preconditioner: Preconditioner::Jacobi,
        }),
        _ => PlanSolver::Method(LinearMethod::GaussSeidel),
    };
    let options = SolveOptions {
        max_iterations: 400,
        ..SolveOptions::default()
    };
    let spec = PlanSpec {
        points: &points,
        graph,
        boundary: &boundary,
        elements: None,
        constraints: None,
        method,
        stiffness: PlanStiffness::Batina { exponent: 1.0 },
        solver,
        options,
        renumber: deform_kernel::plan::PlanOrder::AsGiven,
    };
    let ws = match Plan::<f64, 2>::work_sizes(&spec) {
        Ok(ws) => ws,
        Err(_) => return, // an empty boundary
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
    let sizes = match Plan::<f64, 2>::sizes(&spec, &mut work) {
        Ok(s) => s,
        Err(_) => return, // duplicate or empty boundary, unanchored node, zero-length edge
    };
    // The compile-time capacity from the counts alone is exactly what the plan uses.
    let counts = PlanCounts {
        nodes: n,
        edges: spec.graph.edge_count(),
        boundary: boundary.len(),
        elements: None,
    };
    assert_eq!(Plan::<f64, 2>::work_capacity(&counts), ws);
    if let PlanSolver::Method(m) = solver {
        assert_eq!(Plan::<f64, 2>::capacity(&counts, method, &m), Some(sizes));
    }
    // One entry short: typed error, nothing written.
    for short in 0..3 {
        let mut s = sizes;
        match short {
            0 => s.reals -= 1,
            1 => s.indices -= 1,
            _ if s.bytes > 0 => s.bytes -= 1,
            _ => continue,
        }
        let mut p = Pools::zeros(s);
        let before = p.clone();
        let e = Plan::init(&spec, &mut work, &mut p.reals, &mut p.indices, &mut p.bytes);
        assert!(matches!(e, Err(Error::BufferTooSmall { .. })), "{e:?}");
        assert!(p.same(&before));
    }
    let mut pools = Pools::zeros(sizes);
    if Plan::init(
        &spec,
        &mut work,
        &mut pools.reals,
        &mut pools.indices,
        &mut pools.bytes,
    )
    .is_err()
    {
        return; // the hierarchy setup broke down in floating point
    }

    // The stateless side.
    let mut k = vec![0.0; used];
    batina_stiffness(&graph, &points, 1.0, &mut k).unwrap();
    let mut fixed = vec![0u8; n];
    for &b in &boundary {
        fixed[b as usize] = 1;
    }
    let mut seen = vec![0u32; n];
    let sys = SpringSystem::new(graph, &k, &fixed, &mut seen).unwrap();
    let (mut hw, mut hi, mut hv) = (
        vec![0u32; AmgHierarchy::setup_work_len(&sys)],
        vec![],
        vec![],
    );
    let h;
    let ls = match solver {
        PlanSolver::Amg(o) => {
            let s = AmgHierarchy::setup_len(&sys, &o, &mut hw).unwrap();
            hi.resize(s.index, 0);
            hv.resize(s.values, 0.0);
            h = AmgHierarchy::setup(&sys, &o, &mut hw, &mut hi, &mut hv).unwrap();
            LinearSolver::Amg(&h)
        }
        PlanSolver::Method(m) => LinearSolver::Method(m),
    };

    for step in inp.steps.iter().take(4) {
        let mut deformed: Vec<[f64; 2]> = boundary.iter().map(|&b| points[b as usize]).collect();
        for &(b, dx, dy) in &step.moves {
            let l = deformed.len();
            if let Some(d) = deformed.get_mut(b as usize % l) {
                d[0] += f64::from(dx) / 64.0;
                d[1] += f64::from(dy) / 64.0;
            }
        }
        if step.nan {
            deformed[0][1] = f64::NAN;
        }
        let given = if step.short {
            &deformed[1..]
        } else {
            &deformed[..]
        };
        let q = Quat::from_rotation_z(f64::from(step.angle) / 100.0);
        let motion = PlanMotion {
            deformed: given,
            rotations: RotationSource::Rigid(q),
            origin: None,
            start: if step.cold { Start::Cold } else { Start::Warm },
        };
        let before = pools.clone();
        let mut out = vec![[0.5; 2]; n];
        let r = {
            let mut plan =
                Plan::<f64, 2>::open(&mut pools.reals, &mut pools.indices, &mut pools.bytes)
                    .unwrap();
            plan.step(&motion, &mut out)
        };
        let rep = match r {
            Err(e) => {
                if step.nan || step.short {
                    assert!(
                        matches!(e, Error::NonFinite { .. } | Error::LengthMismatch { .. }),
                        "{e:?}"
                    );
                    assert!(pools.same(&before));
                }
                assert!(out.iter().all(|p| *p == [0.5, 0.5]));
                // The state is as before: the next step from here equals one from the copy.
                let ok = PlanMotion {
                    deformed: &boundary
                        .iter()
                        .map(|&b| points[b as usize])
                        .collect::<Vec<_>>(),
                    rotations: RotationSource::Rigid(Quat::identity()),
                    origin: None,
                    start: Start::Warm,
                };
                let mut copy = before;
                let mut o1 = vec![[0.0; 2]; n];
                let mut o2 = vec![[0.0; 2]; n];
                let r1 =
                    Plan::<f64, 2>::open(&mut pools.reals, &mut pools.indices, &mut pools.bytes)
                        .unwrap()
                        .step(&ok, &mut o1);
                let r2 = Plan::<f64, 2>::open(&mut copy.reals, &mut copy.indices, &mut copy.bytes)
                    .unwrap()
                    .step(&ok, &mut o2);
                assert_eq!(r1.is_ok(), r2.is_ok());
                assert_eq!(bits(&o1), bits(&o2));
                pools = copy;
                continue;
            }
            Ok(rep) => rep,
        };
        assert!(!step.nan && !step.short);
        // Copied pools resume with the same bits.
        let mut copy = pools.clone();
        Plan::<f64, 2>::open(&mut copy.reals, &mut copy.indices, &mut copy.bytes).unwrap();
        assert!(copy.same(&pools));
        if rep.warm {
            continue;
        }
        // A cold step equals the stateless call.
        let mut expect = vec![[0.0; 2]; n];
        let erep = match method {
            PlanMethod::Spring => {
                let mut x = vec![[0.0; 2]; n];
                for (&b, d) in boundary.iter().zip(&deformed) {
                    let p = points[b as usize];
                    x[b as usize] = [d[0] - p[0], d[1] - p[1]];
                }
                let mut sc = vec![[0.0; 2]; solve_linear_with_scratch_len(&ls, n)];
                let r = sys
                    .solve_linear_with(&mut x, ls, &options, &mut sc)
                    .unwrap();
                for ((e, p), v) in expect.iter_mut().zip(&points).zip(&x) {
                    *e = [p[0] + v[0], p[1] + v[1]];
                }
                for (&b, d) in boundary.iter().zip(&deformed) {
                    expect[b as usize] = *d;
                }
                r
            }
            PlanMethod::QuaternionSpring => {
                let bm = BoundaryMotion {
                    nodes: &boundary,
                    deformed: &deformed,
                    elements: None,
                    rotations: RotationSource::Rigid(q),
                    origin: None,
                };
                let mut t = vec![[0.0; 2]; n];
                let mut r = vec![Quat::identity(); n];
                let mut sc = vec![0.0; deform_spring_scratch_len::<2>(n, boundary.len())];
                let mut v = vec![0.0; propagate_spring_with_scratch_len::<2>(&ls, n)];
                deform_spring_with::<f64, 2>(
                    &points,
                    &bm,
                    &sys,
                    ls,
                    &options,
                    &mut t,
                    &mut r,
                    &mut sc,
                    &mut v,
                    &mut expect,
                )
                .unwrap()
                .1
            }
        };
        assert_eq!(bits(&out), bits(&expect));
        assert_eq!(rep.solve.iterations, erep.iterations);
    }

    // A flipped bit in the header or an immutable index section is refused.
    let (pos, bit) = inp.flip;
    let pos = pos as usize % pools.indices.len();
    if !(40..48).contains(&pos) {
        let mut bad = pools.clone();
        bad.indices[pos] ^= 1 << (bit % 32);
        let before = bad.clone();
        let e = Plan::<f64, 2>::open(&mut bad.reals, &mut bad.indices, &mut bad.bytes);
        assert!(matches!(e, Err(Error::BadPlan { .. })), "word {pos}");
        assert!(bad.same(&before));
    }
});
