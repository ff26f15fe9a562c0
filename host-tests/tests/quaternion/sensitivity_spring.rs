//! Tangent and adjoint of the quaternion deformation with linear-spring propagation
//! (`deform_spring_tangent`, `deform_spring_adjoint`; `deform move --method quaternion`),
//! checked against what they linearise:
//!
//! - central finite differences of `deform_spring_with` itself, with a step study (the error
//!   falls as `h²` until the solver tolerance and rounding; print with `-- --nocapture`);
//! - the dot-product test `⟨J v, w⟩ = ⟨v, Jᵀ w⟩` for random `v`, `w`, 2D and 3D, `f32` and
//!   `f64`, CG (Jacobi) and multigrid;
//! - exact rigid motion: a rigid motion of the whole boundary moves the mesh rigidly, so the
//!   tangent along a further rigid motion is the rigid field;
//! - typed errors that leave `out` unchanged.
//!
//! The solves are iterative: tangent and adjoint are the derivative of the exact solve to
//! the solver tolerance (`1e-13` in f64, `1e-6` in f32, as the linear-spring sensitivity
//! tests), so the identities hold to about that, not to rounding.
//!
//! Meshes (small, the tests run in debug builds): a triangulated annulus (2D, 192 nodes) and
//! a box of hexahedra with a cubic hole (3D, 342 nodes); the inner boundary moves (rotation,
//! translation and a bulge), the outer one rests.

#[path = "../support/sensitivity_common.rs"]
mod common;
#[path = "../support/mod.rs"]
mod support;

use common::{assert_dot, dot, norm, tight};
use deform_kernel::quaternion::{
    deform_spring_adjoint, deform_spring_scratch_len, deform_spring_sensitivity_scratch_len,
    deform_spring_tangent, deform_spring_with, propagate_spring_with_scratch_len, BoundaryMotion,
    RotationSource,
};
use deform_kernel::spring::{
    batina_stiffness, AmgOptions, LinearMethod, LinearSolver, Preconditioner, SolveOptions,
    SolveReport, SpringSystem,
};
use deform_kernel::{graph_from_cells, graph_from_cells_len, Cells, Error, Graph, Quat, Real};
use deform_meshgen::{annulus, box_with_inner_box3, Mesh};
use support::spring::{AmgBuffers, Case, Lcg};

/// A mesh with its edge graph and its boundary: the nodes of `"inner"` (the first `inner`
/// boundary points) then `"outer"`, elements in boundary-local numbering.
struct Fixture<const D: usize> {
    points: Vec<[f64; D]>,
    offsets: Vec<u32>,
    targets: Vec<u32>,
    nodes: Vec<u32>,
    inner: usize,
    el_offsets: Vec<u32>,
    el_nodes: Vec<u32>,
    el_kinds: Vec<u8>,
}

impl<const D: usize> Fixture<D> {
    fn new(mesh: &Mesh<D>) -> Self {
        let n = mesh.points.len();
        let cells = mesh.cells().unwrap();
        let mut offsets = vec![0u32; n + 1];
        let mut targets = vec![0u32; graph_from_cells_len(&cells, false)];
        let used = graph_from_cells(&cells, false, &mut offsets, &mut targets).unwrap();
        targets.truncate(used);
        let mut local = vec![u32::MAX; n];
        let mut f = Fixture {
            points: mesh.points.clone(),
            offsets,
            targets,
            nodes: Vec::new(),
            inner: 0,
            el_offsets: vec![0],
            el_nodes: Vec::new(),
            el_kinds: Vec::new(),
        };
        for name in ["inner", "outer"] {
            let m = mesh.marker(name).unwrap();
            for &i in &m.node_list {
                if local[i as usize] == u32::MAX {
                    local[i as usize] = f.nodes.len() as u32;
                    f.nodes.push(i);
                }
            }
            for e in 0..m.kinds.len() {
                let el = &m.nodes[m.offsets[e] as usize..m.offsets[e + 1] as usize];
                f.el_nodes.extend(el.iter().map(|&i| local[i as usize]));
                f.el_kinds.push(m.kinds[e]);
                f.el_offsets.push(f.el_nodes.len() as u32);
            }
            if name == "inner" {
                f.inner = f.nodes.len();
            }
        }
        f
    }

    fn elements(&self) -> Cells<'_> {
        Cells::new(
            self.nodes.len(),
            &self.el_offsets,
            &self.el_nodes,
            &self.el_kinds,
        )
        .unwrap()
    }

    /// The spring case in `T`: Batina stiffness `1/length`, the boundary fixed.
    fn case<T: Real>(&self) -> Case<T, D> {
        let points: Vec<[T; D]> = self.points.iter().map(|p| p.map(T::from_f64)).collect();
        let mut k = vec![T::ZERO; self.targets.len()];
        let g = Graph::new(&self.offsets, &self.targets).unwrap();
        batina_stiffness(&g, &points, T::ONE, &mut k).unwrap();
        let mut fixed = vec![0u8; points.len()];
        for &i in &self.nodes {
            fixed[i as usize] = 1;
        }
        Case {
            offsets: self.offsets.clone(),
            targets: self.targets.clone(),
            k,
            fixed,
            points,
        }
    }

    /// The inner boundary turned by `angle` about a tilted axis (`z` in 2D) through `(0.1,
    /// −0.05, 0.02)`, shifted and bulged; the outer boundary rests. With `all`, every
    /// boundary point moves rigidly (no bulge).
    fn deformed(&self, angle: f64, all: bool) -> Vec<[f64; D]> {
        let q = if D == 2 {
            Quat::from_rotation_z(angle)
        } else {
            Quat::from_axis_angle([0.3, -0.5, 1.0], angle).unwrap()
        };
        let c = [0.1, -0.05, 0.02];
        (0..self.nodes.len())
            .map(|k| {
                let p = self.points[self.nodes[k] as usize];
                if k >= self.inner && !all {
                    return p;
                }
                let mut v = [0.0; 3];
                for i in 0..D {
                    v[i] = p[i] - c[i];
                }
                let r = q.rotate(v);
                let bulge = if all { 0.0 } else { 0.03 };
                core::array::from_fn(|i| {
                    r[i] + c[i] + 0.04 * (i as f64 + 1.0) + bulge * (4.0 * v[(i + 1) % D]).sin()
                })
            })
            .collect()
    }
}

/// CG with the Jacobi preconditioner, or multigrid-preconditioned CG.
#[derive(Clone, Copy, Debug)]
enum Solver {
    Jacobi,
    Multigrid,
}

/// Runs `f` with the system of `case` and the solver.
fn with_solver<T: Real, const D: usize, R>(
    case: &Case<T, D>,
    which: Solver,
    f: impl FnOnce(&SpringSystem<'_, T>, LinearSolver<'_, T>) -> R,
) -> R {
    let sys = case.system();
    match which {
        Solver::Jacobi => f(
            &sys,
            LinearSolver::Method(LinearMethod::Cg {
                preconditioner: Preconditioner::Jacobi,
            }),
        ),
        Solver::Multigrid => {
            let opts = AmgOptions::default();
            let mut b = AmgBuffers::new(&sys, &opts);
            let h = b.build(&sys, &opts);
            f(&sys, LinearSolver::Amg(&h))
        }
    }
}

/// The signature `deform_spring_tangent` and `deform_spring_adjoint` share.
type Mode<T, const D: usize> = fn(
    &[[T; D]],
    &BoundaryMotion<'_, T, D>,
    &SpringSystem<'_, T>,
    LinearSolver<'_, T>,
    &SolveOptions<T>,
    &[[T; D]],
    &mut [T],
    &mut [[T; D]],
) -> deform_kernel::Result<SolveReport<T>>;

/// One linearisation point: the fixture, its system and solver, the deformed boundary.
struct Point<'a, T: Real, const D: usize> {
    fx: &'a Fixture<D>,
    points: &'a [[T; D]],
    sys: &'a SpringSystem<'a, T>,
    solver: LinearSolver<'a, T>,
    d: Vec<[T; D]>,
    origin: Option<[T; D]>,
}

impl<T: Real, const D: usize> Point<'_, T, D> {
    fn motion<'m>(&'m self, d: &'m [[T; D]]) -> BoundaryMotion<'m, T, D> {
        BoundaryMotion {
            nodes: &self.fx.nodes,
            deformed: d,
            elements: Some(self.fx.elements()),
            rotations: RotationSource::Shape,
            origin: self.origin,
        }
    }

    /// The deformation for boundary positions `d`.
    fn deform(&self, d: &[[T; D]]) -> Vec<[T; D]> {
        let (n, b) = (self.points.len(), d.len());
        let mut tr = vec![[T::ZERO; D]; n];
        let mut rot = vec![Quat::identity(); n];
        let mut scratch = vec![T::ZERO; deform_spring_scratch_len::<D>(n, b)];
        let mut values = vec![T::ZERO; propagate_spring_with_scratch_len::<D>(&self.solver, n)];
        let mut out = vec![[T::ZERO; D]; n];
        let (_, r) = deform_spring_with(
            self.points,
            &self.motion(d),
            self.sys,
            self.solver,
            &tight(),
            &mut tr,
            &mut rot,
            &mut scratch,
            &mut values,
            &mut out,
        )
        .unwrap();
        assert!(r.converged);
        out
    }

    fn scratch(&self) -> Vec<T> {
        let (n, b) = (self.points.len(), self.d.len());
        vec![T::ZERO; deform_spring_sensitivity_scratch_len::<T, D>(&self.solver, n, b)]
    }

    /// `J v` (tangent).
    fn tangent(&self, v: &[[T; D]]) -> Vec<[T; D]> {
        self.apply(deform_spring_tangent, v, self.points.len())
    }

    /// `Jᵀ w` (adjoint).
    fn adjoint(&self, w: &[[T; D]]) -> Vec<[T; D]> {
        self.apply(deform_spring_adjoint, w, self.d.len())
    }

    /// Runs one mode (`f`, the kernel's tangent or adjoint) on `input` into `len` items.
    fn apply(&self, f: Mode<T, D>, input: &[[T; D]], len: usize) -> Vec<[T; D]> {
        let mut out = vec![[T::ZERO; D]; len];
        let (m, opts, mut s) = (self.motion(&self.d), tight(), self.scratch());
        let r = f(
            self.points,
            &m,
            self.sys,
            self.solver,
            &opts,
            input,
            &mut s,
            &mut out,
        );
        assert!(r.unwrap().converged);
        out
    }
}

/// Runs `f` on the linearisation point of `fx` at the deformed boundary `d`.
fn at<T: Real, const D: usize, R>(
    fx: &Fixture<D>,
    d: &[[f64; D]],
    origin: Option<[f64; D]>,
    which: Solver,
    f: impl FnOnce(&Point<'_, T, D>) -> R,
) -> R {
    let case = fx.case::<T>();
    with_solver(&case, which, |sys, solver| {
        let p = Point {
            fx,
            points: &case.points,
            sys,
            solver,
            d: d.iter().map(|p| p.map(T::from_f64)).collect(),
            origin: origin.map(|o| o.map(T::from_f64)),
        };
        f(&p)
    })
}

/// Random vectors in `[-1, 1)`: `scale` in the first `moving` entries and `rest` after them.
fn random<T: Real, const D: usize>(len: usize, moving: usize, rest: f64, seed: u64) -> Vec<[T; D]> {
    let mut rng = Lcg(seed);
    (0..len)
        .map(|k| {
            let f = if k < moving { 1.0 } else { rest };
            core::array::from_fn(|_| T::from_f64(f * rng.next()))
        })
        .collect()
}

/// The largest `|a − b|` over every component.
fn max_diff<const D: usize>(a: &[[f64; D]], b: &[[f64; D]]) -> f64 {
    a.iter()
        .flatten()
        .zip(b.iter().flatten())
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

/// Central differences `(R(d + h v) − R(d − h v)) / 2h`.
fn central<const D: usize>(p: &Point<'_, f64, D>, v: &[[f64; D]], h: f64) -> Vec<[f64; D]> {
    let shift = |sg: f64| -> Vec<[f64; D]> {
        p.d.iter()
            .zip(v)
            .map(|(d, v)| core::array::from_fn(|i| d[i] + sg * h * v[i]))
            .collect()
    };
    let (a, b) = (p.deform(&shift(1.0)), p.deform(&shift(-1.0)));
    a.iter()
        .zip(&b)
        .map(|(a, b)| core::array::from_fn(|i| (a[i] - b[i]) / (2.0 * h)))
        .collect()
}

/// Step study: prints the table; asserts the `h²` regime (100× a decade from `1e-1` to
/// `1e-3`) and the agreement at the best step.
fn step_study<const D: usize>(p: &Point<'_, f64, D>, v: &[[f64; D]], label: &str) {
    let t = p.tangent(v);
    let scale = t.iter().flatten().fold(0.0f64, |a, x| a.max(x.abs()));
    println!("{label}: max |δR| = {scale:.3e}\n       h      max|FD − tangent| / max|δR|");
    let mut errs = Vec::new();
    for e in 1..=7 {
        let h = 10f64.powi(-e);
        let err = max_diff(&t, &central(p, v, h)) / scale;
        println!("  {h:8.0e}   {err:10.3e}");
        errs.push(err);
    }
    let best = errs.iter().copied().fold(f64::INFINITY, f64::min);
    assert!(best < 1e-8, "{label}: best FD agreement {best:e}");
    for i in 0..2 {
        let ratio = errs[i] / errs[i + 1];
        assert!(
            (30.0..300.0).contains(&ratio),
            "{label}: error ratio 1e-{} → 1e-{} is {ratio}",
            i + 1,
            i + 2
        );
    }
}

fn annulus_fixture() -> Fixture<2> {
    Fixture::new(&annulus(24, 8, 1.0, 4.0).unwrap())
}

fn box_fixture() -> Fixture<3> {
    Fixture::new(&box_with_inner_box3(6, 2).unwrap())
}

#[test]
fn tangent_matches_central_differences_2d() {
    let fx = annulus_fixture();
    let d = fx.deformed(0.4, false);
    // With the default origin only moving points are perturbed (its point set is then
    // unchanged); with a given origin the outer boundary too.
    for (origin, rest) in [(None, 0.0), (Some([0.3, -0.2]), 0.3)] {
        at::<f64, 2, _>(&fx, &d, origin, Solver::Multigrid, |p| {
            let v = random::<f64, 2>(fx.nodes.len(), fx.inner, rest, 3);
            step_study(p, &v, &format!("2D, origin {origin:?}"));
        });
    }
}

#[test]
fn tangent_matches_central_differences_3d() {
    let fx = box_fixture();
    let d = fx.deformed(0.3, false);
    for (origin, rest) in [(None, 0.0), (Some([0.2, 0.1, -0.3]), 0.3)] {
        at::<f64, 3, _>(&fx, &d, origin, Solver::Jacobi, |p| {
            let v = random::<f64, 3>(fx.nodes.len(), fx.inner, rest, 4);
            step_study(p, &v, &format!("3D, origin {origin:?}"));
        });
    }
}

/// The dot-product test for three random pairs `v`, `w`.
fn dot_test<T: Real, const D: usize>(fx: &Fixture<D>, which: Solver, tol: f64) {
    let d = fx.deformed(0.35, false);
    let (n, b) = (fx.points.len(), fx.nodes.len());
    for origin in [None, Some([0.2; D])] {
        at::<T, D, _>(fx, &d, origin, which, |p| {
            for seed in 0..2 {
                let v = random::<T, D>(b, b, 1.0, 100 + seed);
                let w = random::<T, D>(n, n, 1.0, 200 + seed);
                let (jv, jtw) = (p.tangent(&v), p.adjoint(&w));
                assert!(norm(&jtw) > 0.0);
                let what = format!(
                    "{} {D}D {which:?} origin {origin:?}",
                    core::any::type_name::<T>()
                );
                let rel = (dot(&jv, &w) - dot(&v, &jtw)).abs() / (norm(&jv) * norm(&w));
                println!("{what}: relative mismatch {rel:.2e}");
                assert_dot(&jv, &w, &v, &jtw, tol, &what);
            }
        });
    }
}

#[test]
fn dot_product_test_f64() {
    for which in [Solver::Jacobi, Solver::Multigrid] {
        dot_test::<f64, 2>(&annulus_fixture(), which, 1e-12);
        dot_test::<f64, 3>(&box_fixture(), which, 1e-12);
    }
}

#[test]
fn dot_product_test_f32() {
    for which in [Solver::Jacobi, Solver::Multigrid] {
        dot_test::<f32, 2>(&annulus_fixture(), which, 1e-6);
        dot_test::<f32, 3>(&box_fixture(), which, 1e-6);
    }
}

/// A rigid motion of the whole boundary (both markers) deforms the mesh rigidly; the tangent
/// along a further infinitesimal rotation `ω` about `c` and translation `τ` is
/// `ω × (R − c) + τ` at every point. Returns the relative error.
fn rigid<T: Real, const D: usize>(fx: &Fixture<D>) -> f64 {
    let d = fx.deformed(0.5, true);
    let omega = if D == 2 {
        [0.0, 0.0, 0.8]
    } else {
        [0.4, -0.7, 0.5]
    };
    let (c, tau) = ([0.3, -0.2, 0.1], [0.3, -0.1, 0.2]);
    let field = |x: [f64; D]| -> [f64; D] {
        let mut r = [0.0; 3];
        for i in 0..D {
            r[i] = x[i] - c[i];
        }
        let w = [
            omega[1] * r[2] - omega[2] * r[1],
            omega[2] * r[0] - omega[0] * r[2],
            omega[0] * r[1] - omega[1] * r[0],
        ];
        core::array::from_fn(|i| w[i] + tau[i])
    };
    at::<T, D, _>(fx, &d, None, Solver::Multigrid, |p| {
        let v: Vec<[T; D]> = d.iter().map(|x| field(*x).map(T::from_f64)).collect();
        let moved = p.deform(&p.d);
        let expect: Vec<[f64; D]> = moved.iter().map(|x| field(x.map(|c| c.to_f64()))).collect();
        let t: Vec<[f64; D]> = p
            .tangent(&v)
            .iter()
            .map(|x| x.map(|c| c.to_f64()))
            .collect();
        let scale = expect.iter().flatten().fold(0.0f64, |a, x| a.max(x.abs()));
        let err = max_diff(&t, &expect) / scale;
        println!(
            "{} {D}D rigid tangent: relative error {err:.2e}",
            core::any::type_name::<T>()
        );
        err
    })
}

#[test]
fn rigid_motion_tangent_is_rigid() {
    let (a, b) = (annulus_fixture(), box_fixture());
    for (e, tol) in [
        (rigid::<f64, 2>(&a), 1e-10),
        (rigid::<f64, 3>(&b), 1e-10),
        (rigid::<f32, 2>(&a), 1e-4),
        (rigid::<f32, 3>(&b), 1e-4),
    ] {
        assert!(e < tol, "{e:e} ≥ {tol:e}");
    }
}

#[test]
fn bad_input_is_a_typed_error_and_out_is_unchanged() {
    let fx = annulus_fixture();
    let d = fx.deformed(0.2, false);
    at::<f64, 2, _>(&fx, &d, None, Solver::Jacobi, |p| {
        let (n, b) = (fx.points.len(), fx.nodes.len());
        let motion = p.motion(&p.d);
        let mut s = p.scratch();
        let opts = tight();
        let mut out = vec![[7.0; 2]; n];
        let mut v = vec![[0.0; 2]; b];
        v[3][1] = f64::NAN;
        let tangent = |v: &[[f64; 2]], s: &mut [f64], out: &mut [[f64; 2]]| {
            deform_spring_tangent(p.points, &motion, p.sys, p.solver, &opts, v, s, out)
        };
        let e = tangent(&v, &mut s, &mut out);
        assert!(
            matches!(
                e,
                Err(Error::NonFinite {
                    arg: "direction",
                    position: 3
                })
            ),
            "{e:?}"
        );
        let e = tangent(&v[1..], &mut s, &mut out);
        assert!(matches!(e, Err(Error::LengthMismatch { .. })), "{e:?}");
        let e = tangent(&vec![[0.0; 2]; b], &mut s[..n], &mut out);
        assert!(matches!(e, Err(Error::BufferTooSmall { .. })), "{e:?}");
        // A motion that leaves a fixed node out does not match the system.
        let fewer = BoundaryMotion {
            nodes: &fx.nodes[1..],
            deformed: &p.d[1..],
            elements: None,
            rotations: RotationSource::Rigid(Quat::identity()),
            origin: None,
        };
        let e = deform_spring_tangent(
            p.points,
            &fewer,
            p.sys,
            p.solver,
            &opts,
            &v[1..].iter().map(|_| [0.0; 2]).collect::<Vec<_>>(),
            &mut s,
            &mut out,
        );
        assert!(
            matches!(e, Err(Error::InvalidParameter { arg: "sys", .. })),
            "{e:?}"
        );
        assert!(out.iter().flatten().all(|&x| x == 7.0));
        let mut back = vec![[7.0; 2]; b];
        let mut w = vec![[0.0; 2]; n];
        w[n - 1][0] = f64::INFINITY;
        let e = deform_spring_adjoint(
            p.points, &motion, p.sys, p.solver, &opts, &w, &mut s, &mut back,
        );
        assert!(
            matches!(e, Err(Error::NonFinite { arg: "weights", .. })),
            "{e:?}"
        );
        // The adjoint needs CG or multigrid.
        let jacobi = LinearSolver::Method(LinearMethod::Jacobi);
        let mut s2 = vec![0.0; deform_spring_sensitivity_scratch_len::<f64, 2>(&jacobi, n, b)];
        let e = deform_spring_adjoint(
            p.points,
            &motion,
            p.sys,
            jacobi,
            &opts,
            &vec![[0.0; 2]; n],
            &mut s2,
            &mut back,
        );
        assert!(
            matches!(e, Err(Error::InvalidParameter { arg: "solver", .. })),
            "{e:?}"
        );
        assert!(back.iter().flatten().all(|&x| x == 7.0));
    });
}
