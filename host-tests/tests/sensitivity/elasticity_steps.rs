//! Tangent and adjoint of multi-step linear elasticity (`deform_incremental`, the stiffness
//! re-assembled on the moved mesh before each step): central differences of the
//! deformation itself with a step study (the error falls as h² until rounding), the
//! dot-product identity (triangles and quadrilaterals, tetrahedra, hexahedra, prisms and
//! pyramids; every modulus; f32 and f64; block Jacobi and multigrid), one step equal to the
//! single-step tangent, affine (rigid) motions reproduced exactly, and typed errors.

#[path = "../support/sensitivity_common.rs"]
mod common;
#[path = "../support/mod.rs"]
mod support;

use common::*;
use deform_kernel::elasticity::{
    deform_incremental, ElasticSystem, IncrementBuffers, Increments, Modulus,
};
use deform_kernel::sensitivity::{
    elastic_incremental_adjoint, elastic_incremental_adjoint_scratch_len,
    elastic_incremental_tangent, elastic_incremental_tangent_scratch_len, elastic_tangent,
    elastic_tangent_scratch_len, ElasticPreconditioner, IncrementProblem,
};
use deform_kernel::spring::{AmgOptions, SpringSystem};
use deform_kernel::{Error, Real};
use support::elasticity::{assembled, grid2, grid3, Assembled, Kind, Mesh};
use support::spring::{AmgBuffers, Lcg};

/// A mesh with its graph, fixed mask and the owned buffers of the increments.
struct Case<T: Real, const D: usize> {
    mesh: Mesh<D>,
    a: Assembled<T, D>,
    fixed: Vec<u8>,
    points: Vec<[T; D]>,
    wall: Vec<T>,
}

/// Owned [`IncrementBuffers`].
struct Owned<T: Real, const D: usize> {
    moduli: Vec<T>,
    diag: Vec<[[T; D]; D]>,
    off: Vec<[[T; D]; D]>,
    current: Vec<[T; D]>,
    step: Vec<[T; D]>,
}

impl<T: Real, const D: usize> Owned<T, D> {
    fn buffers(&mut self) -> IncrementBuffers<'_, T, D> {
        IncrementBuffers {
            moduli: &mut self.moduli,
            diag: &mut self.diag,
            off: &mut self.off,
            current: &mut self.current,
            step: &mut self.step,
        }
    }
}

impl<T: Real, const D: usize> Case<T, D> {
    fn new(mesh: Mesh<D>) -> Self {
        let points = mesh.points_as::<T>();
        let a = assembled(&mesh, &points, Modulus::Constant, None, T::from_f64(0.3));
        let fixed = mesh.boundary.iter().map(|&b| b as u8).collect();
        // Wall distance: from the bottom face (y = 0), as a reference-mesh field.
        let wall = mesh.points.iter().map(|p| T::from_f64(p[1])).collect();
        Case {
            mesh,
            a,
            fixed,
            points,
            wall,
        }
    }
    fn n(&self) -> usize {
        self.points.len()
    }
    fn owned(&self) -> Owned<T, D> {
        let n = self.n();
        Owned {
            moduli: vec![T::ZERO; self.mesh.kinds.len()],
            diag: vec![[[T::ZERO; D]; D]; n],
            off: vec![[[T::ZERO; D]; D]; self.a.targets.len()],
            current: vec![[T::ZERO; D]; n],
            step: vec![[T::ZERO; D]; n],
        }
    }
    fn params(&self, modulus: Modulus, steps: usize) -> Increments<'_, T> {
        Increments {
            modulus,
            wall_distance: Some(&self.wall),
            poisson: T::from_f64(0.3),
            steps,
        }
    }
    /// The deformed mesh for displacement `d` (block-Jacobi CG, tight).
    fn deform(&self, d: &[[T; D]], modulus: Modulus, steps: usize) -> Vec<[T; D]> {
        let mut o = self.owned();
        let mut x = self.points.clone();
        let mut s = vec![[T::ZERO; D]; 4 * self.n()];
        let cells = self.mesh.cells();
        let r = deform_incremental(
            &cells,
            &self.a.graph(),
            &self.fixed,
            &self.params(modulus, steps),
            &mut x,
            d,
            o.buffers(),
            |sys: &ElasticSystem<'_, T, D>, u: &mut [[T; D]]| sys.solve(u, &tight(), &mut s),
        )
        .expect("deform");
        assert!(r.converged);
        x
    }
}

/// Runs `f` on the problem of `case` with displacement `d`.
fn with_problem<T: Real, const D: usize, R>(
    case: &Case<T, D>,
    d: &[[T; D]],
    (modulus, steps): (Modulus, usize),
    pre: ElasticPreconditioner<'_, T>,
    f: impl FnOnce(&IncrementProblem<'_, T, D>) -> R,
) -> R {
    let cells = case.mesh.cells();
    let graph = case.a.graph();
    let params = case.params(modulus, steps);
    let p = IncrementProblem {
        cells: &cells,
        graph: &graph,
        fixed: &case.fixed,
        params: &params,
        points: &case.points,
        displacement: d,
        pre,
        options: tight(),
    };
    f(&p)
}

fn tangent<T: Real, const D: usize>(
    case: &Case<T, D>,
    d: &[[T; D]],
    v: &[[T; D]],
    ms: (Modulus, usize),
    pre: ElasticPreconditioner<'_, T>,
) -> Vec<[T; D]> {
    with_problem(case, d, ms, pre, |p| {
        let mut o = case.owned();
        let mut s = vec![[T::ZERO; D]; elastic_incremental_tangent_scratch_len(&pre, case.n())];
        let mut jv = v.to_vec();
        let r = elastic_incremental_tangent(p, &mut jv, o.buffers(), &mut s).expect("tangent");
        assert!(r.converged && r.steps == ms.1, "{r:?}");
        jv
    })
}

fn adjoint<T: Real, const D: usize>(
    case: &Case<T, D>,
    d: &[[T; D]],
    w: &[[T; D]],
    ms: (Modulus, usize),
    pre: ElasticPreconditioner<'_, T>,
) -> Vec<[T; D]> {
    with_problem(case, d, ms, pre, |p| {
        let mut o = case.owned();
        let len = elastic_incremental_adjoint_scratch_len(&pre, case.n(), ms.1);
        let mut s = vec![[T::ZERO; D]; len];
        let mut g = vec![[T::ZERO; D]; case.n()];
        let r = elastic_incremental_adjoint(p, w, &mut g, o.buffers(), &mut s).expect("adjoint");
        assert!(r.converged && r.steps == ms.1, "{r:?}");
        g
    })
}

/// A finite boundary motion: a rotation by `deg` about the centre, a stretch and a random
/// wobble, at every node (read at fixed nodes only).
fn motion<T: Real, const D: usize>(m: &Mesh<D>, deg: f64, seed: u64) -> Vec<[T; D]> {
    let (s, c) = deg.to_radians().sin_cos();
    let mut rng = Lcg(seed);
    m.points
        .iter()
        .map(|p| {
            let (x, y) = (p[0] - 0.5, p[1] - 0.5);
            let mut d = [0.0; D];
            d[0] = c * x - s * y - x + 0.1 * x * y + 0.02 * rng.next();
            d[1] = s * x + c * y - y - 0.05 * x * x + 0.02 * rng.next();
            if D == 3 {
                d[2] = 0.08 * x * p[2] + 0.02 * rng.next();
            }
            d.map(T::from_f64)
        })
        .collect()
}

fn boundary_field<T: Real, const D: usize>(m: &Mesh<D>, seed: u64) -> Vec<[T; D]> {
    random(m.points.len(), &mut Lcg(seed), |i| m.boundary[i])
}

fn dot_case<T: Real, const D: usize>(mesh: Mesh<D>, ms: (Modulus, usize), tol: f64) {
    let case = Case::<T, D>::new(mesh);
    let d = motion::<T, D>(&case.mesh, 20.0, 3);
    let v = boundary_field::<T, D>(&case.mesh, 5);
    let w = random(case.n(), &mut Lcg(7), |_| true);
    let what = format!("{D}D {:?} {ms:?}", case.mesh.kinds[0]);
    let pre = ElasticPreconditioner::Blocks;
    let jv = tangent(&case, &d, &v, ms, pre);
    let g = adjoint(&case, &d, &w, ms, pre);
    check_dot(&jv, &w, &v, &g, tol, &what);
    assert!(g
        .iter()
        .zip(&case.mesh.boundary)
        .all(|(g, &b)| b || *g == [T::ZERO; D]));
}

#[test]
fn dot_product_f64() {
    let t = 1e-10;
    dot_case::<f64, 2>(grid2(6, Kind::Mixed, 0.25), (Modulus::InverseVolume, 3), t);
    dot_case::<f64, 2>(grid2(6, Kind::Box, 0.25), (Modulus::Constant, 2), t);
    dot_case::<f64, 2>(grid2(6, Kind::Simplex, 0.25), (Modulus::WallDistance, 4), t);
    dot_case::<f64, 3>(grid3(3, Kind::Simplex, 0.2), (Modulus::InverseVolume, 3), t);
    dot_case::<f64, 3>(grid3(3, Kind::Box, 0.2), (Modulus::InverseVolume, 2), t);
    dot_case::<f64, 3>(grid3(3, Kind::Mixed, 0.2), (Modulus::InverseVolume, 2), t);
}

#[test]
fn dot_product_f32() {
    dot_case::<f32, 2>(
        grid2(6, Kind::Mixed, 0.25),
        (Modulus::InverseVolume, 3),
        1e-4,
    );
    dot_case::<f32, 3>(
        grid3(3, Kind::Simplex, 0.2),
        (Modulus::InverseVolume, 2),
        1e-4,
    );
}

/// The multigrid preconditioner (a hierarchy of the undeformed mesh, used at every step):
/// the same derivative as block Jacobi, and the identity holds.
#[test]
fn multigrid_matches_block_jacobi() {
    let case = Case::<f64, 2>::new(grid2(8, Kind::Mixed, 0.25));
    let mut k = vec![0.0; case.a.targets.len()];
    case.a.system(&case.fixed).amg_weights(&mut k).unwrap();
    let mut anchor = vec![0u32; case.n()];
    let spring = SpringSystem::new(case.a.graph(), &k, &case.fixed, &mut anchor).unwrap();
    let opts = AmgOptions::default();
    let mut b = AmgBuffers::new(&spring, &opts);
    let h = b.build(&spring, &opts);
    let amg = ElasticPreconditioner::Amg(&spring, &h);
    let ms = (Modulus::InverseVolume, 3);
    let d = motion::<f64, 2>(&case.mesh, 25.0, 11);
    let v = boundary_field(&case.mesh, 13);
    let w = random(case.n(), &mut Lcg(17), |_| true);
    let jv = tangent(&case, &d, &v, ms, amg);
    let g = adjoint(&case, &d, &w, ms, amg);
    check_dot(&jv, &w, &v, &g, 1e-10, "2D mixed multigrid");
    let jb = tangent(&case, &d, &v, ms, ElasticPreconditioner::Blocks);
    assert!(rel_err(&jv, &jb) <= 1e-10, "{:e}", rel_err(&jv, &jb));
}

/// Central differences of `deform_incremental` along `v` at steps 10⁻¹ … 10⁻⁶: the error
/// falls as h² (a factor 100 per decade) until rounding and the solver tolerance take over.
fn step_study<const D: usize>(mesh: Mesh<D>, ms: (Modulus, usize)) {
    let case = Case::<f64, D>::new(mesh);
    let d = motion::<f64, D>(&case.mesh, 25.0, 19);
    let v = boundary_field::<f64, D>(&case.mesh, 23);
    let jv = tangent(&case, &d, &v, ms, ElasticPreconditioner::Blocks);
    let mut errs = vec![];
    for k in 1..=6 {
        let h = 10f64.powi(-k);
        let shifted = |sgn: f64| -> Vec<[f64; D]> {
            d.iter()
                .zip(&v)
                .map(|(a, b)| std::array::from_fn(|c| a[c] + sgn * h * b[c]))
                .collect()
        };
        let (p, q) = (
            case.deform(&shifted(1.0), ms.0, ms.1),
            case.deform(&shifted(-1.0), ms.0, ms.1),
        );
        let fd: Vec<[f64; D]> = p
            .iter()
            .zip(&q)
            .map(|(p, q)| std::array::from_fn(|c| (p[c] - q[c]) / (2.0 * h)))
            .collect();
        errs.push((h, rel_err(&fd, &jv)));
    }
    println!(
        "{D}D {:?} {ms:?}: (h, rel. error) {errs:?}",
        case.mesh.kinds[0]
    );
    // Nonlinear: the larger steps show the h² term, not rounding (10⁻¹ can be past it).
    assert!(errs[1].1 > 1e-7, "{errs:?}");
    for w in errs.windows(2).skip(1).take(3) {
        let ratio = w[1].1 / w[0].1;
        assert!((0.005..=0.02).contains(&ratio), "not h²: {errs:?}");
    }
    let best = errs.iter().map(|e| e.1).fold(f64::MAX, f64::min);
    assert!(best <= 1e-8, "{errs:?}");
}

#[test]
fn tangent_matches_central_differences_2d() {
    step_study(grid2(6, Kind::Mixed, 0.25), (Modulus::InverseVolume, 4));
    step_study(grid2(5, Kind::Simplex, 0.25), (Modulus::WallDistance, 3));
}

#[test]
fn tangent_matches_central_differences_3d() {
    step_study(grid3(3, Kind::Simplex, 0.2), (Modulus::InverseVolume, 3));
    step_study(grid3(2, Kind::Box, 0.2), (Modulus::InverseVolume, 2));
}

/// With one step the derivative is the single-step one: one solve on the undeformed mesh.
#[test]
fn one_step_is_the_single_step_tangent() {
    let case = Case::<f64, 3>::new(grid3(3, Kind::Box, 0.2));
    let a = assembled(&case.mesh, &case.points, Modulus::InverseVolume, None, 0.3);
    let sys = a.system(&case.fixed);
    let v = boundary_field::<f64, 3>(&case.mesh, 29);
    let mut one = v.clone();
    let pre = ElasticPreconditioner::Blocks;
    let mut s = vec![[0.0; 3]; elastic_tangent_scratch_len(&pre, case.n())];
    elastic_tangent(&sys, pre, &tight(), &mut one, &mut s).unwrap();
    let d = motion::<f64, 3>(&case.mesh, 30.0, 31);
    let jv = tangent(&case, &d, &v, (Modulus::InverseVolume, 1), pre);
    assert!(rel_err(&jv, &one) <= 1e-11, "{:e}", rel_err(&jv, &one));
}

/// A rigid perturbation `v = t + W (x − c)` (`W` skew) about centre `c`.
fn rigid<const D: usize>(p: &[f64; D]) -> [f64; D] {
    let (t, om) = ([0.1, -0.2, 0.05], [0.3, 0.7, -0.4]);
    let q = [
        p[0] - 0.5,
        p[1] - 0.5,
        if D == 3 { p[D - 1] - 0.5 } else { 0.0 },
    ];
    let w = [
        om[1] * q[2] - om[2] * q[1],
        om[2] * q[0] - om[0] * q[2],
        om[0] * q[1] - om[1] * q[0],
    ];
    std::array::from_fn(|k| t[k] + w[k])
}

/// The tangent at displacement `d` along the boundary values of `rigid` is `rigid` at every
/// node.
fn reproduces_rigid<const D: usize>(
    mesh: Mesh<D>,
    d: impl Fn(&[f64; D]) -> [f64; D],
    ms: (Modulus, usize),
) {
    let case = Case::<f64, D>::new(mesh);
    let d: Vec<[f64; D]> = case.mesh.points.iter().map(d).collect();
    let exact: Vec<[f64; D]> = case.mesh.points.iter().map(rigid).collect();
    let v: Vec<[f64; D]> = exact
        .iter()
        .zip(&case.mesh.boundary)
        .map(|(e, &b)| if b { *e } else { [0.0; D] })
        .collect();
    let jv = tangent(&case, &d, &v, ms, ElasticPreconditioner::Blocks);
    let e = rel_err(&jv, &exact);
    assert!(e <= 1e-11, "{D}D {ms:?}: {e:e}");
}

/// A finite rotation by 40° about the centre (an affine field, not stress-free).
fn rotation<const D: usize>(p: &[f64; D]) -> [f64; D] {
    let (s, c) = 40f64.to_radians().sin_cos();
    let (x, y) = (p[0] - 0.5, p[1] - 0.5);
    std::array::from_fn(|k| match k {
        0 => c * x - s * y - x,
        1 => s * x + c * y - y,
        _ => 0.0,
    })
}

/// With a uniform modulus every step reproduces affine data exactly (the patch test), so
/// the deformation of affine boundary data is the affine field and its derivative along an
/// affine (here rigid) direction is that field at every node: exact about a finite 40°
/// rotation. With a modulus that varies from cell to cell only stress-free data are
/// reproduced (linear elasticity is not rotation-invariant), so there the check is about a
/// translation of the whole boundary (the mesh translates, `∂K/∂x` along a rigid field is
/// zero): exact for every modulus.
#[test]
fn rigid_motion_derivative_is_exact() {
    reproduces_rigid(
        grid2(6, Kind::Mixed, 0.25),
        rotation,
        (Modulus::Constant, 4),
    );
    reproduces_rigid(
        grid3(3, Kind::Simplex, 0.2),
        rotation,
        (Modulus::Constant, 3),
    );
    reproduces_rigid(grid3(2, Kind::Box, 0.2), rotation, (Modulus::Constant, 2));
    let shift = |_: &[f64; 2]| [0.3, -0.2];
    reproduces_rigid(
        grid2(6, Kind::Mixed, 0.25),
        shift,
        (Modulus::InverseVolume, 4),
    );
    let shift = |_: &[f64; 3]| [0.3, -0.2, 0.1];
    reproduces_rigid(
        grid3(3, Kind::Mixed, 0.2),
        shift,
        (Modulus::InverseVolume, 3),
    );
}

#[test]
fn bad_input_is_a_typed_error_and_writes_nothing() {
    let case = Case::<f64, 2>::new(grid2(4, Kind::Mixed, 0.2));
    let n = case.n();
    let d = motion::<f64, 2>(&case.mesh, 10.0, 37);
    let pre = ElasticPreconditioner::Blocks;
    let tlen = elastic_incremental_tangent_scratch_len(&pre, n);
    let alen = elastic_incremental_adjoint_scratch_len(&pre, n, 2);
    let run = |d: &[[f64; 2]], steps: usize, dx: &mut [[f64; 2]], short: usize| {
        with_problem(&case, d, (Modulus::InverseVolume, steps), pre, |p| {
            let mut o = case.owned();
            let mut s = vec![[0.0; 2]; tlen - short];
            elastic_incremental_tangent(p, dx, o.buffers(), &mut s).map(|_| ())
        })
    };
    let mut dx = vec![[0.5; 2]; n];
    let r = run(&d, 2, &mut dx, 1);
    assert!(matches!(r, Err(Error::BufferTooSmall { .. })), "{r:?}");
    let r = run(&d, 0, &mut dx, 0);
    assert!(matches!(
        r,
        Err(Error::InvalidParameter { arg: "steps", .. })
    ));
    let r = run(&d, 2, &mut dx[1..], 0);
    assert!(matches!(r, Err(Error::LengthMismatch { arg: "dx", .. })));
    dx[3][1] = f64::NAN;
    let r = run(&d, 2, &mut dx, 0);
    assert!(matches!(r, Err(Error::NonFinite { arg: "dx", .. })));
    dx[3][1] = 0.5;
    assert!(dx.iter().all(|x| *x == [0.5; 2]));
    // The adjoint: a short scratch, a mis-sized g, a non-finite w, the flip.
    let mut g = vec![[5.0; 2]; n];
    let w = vec![[1.0; 2]; n];
    let adj = |d: &[[f64; 2]], w: &[[f64; 2]], g: &mut [[f64; 2]], short: usize| {
        with_problem(&case, d, (Modulus::InverseVolume, 2), pre, |p| {
            let mut o = case.owned();
            let mut s = vec![[0.0; 2]; alen - short];
            elastic_incremental_adjoint(p, w, g, o.buffers(), &mut s).map(|_| ())
        })
    };
    let r = adj(&d, &w, &mut g, 1);
    assert!(matches!(r, Err(Error::BufferTooSmall { .. })), "{r:?}");
    let r = adj(&d, &w, &mut g[1..], 0);
    assert!(matches!(r, Err(Error::LengthMismatch { arg: "g", .. })));
    let mut bad = w.clone();
    bad[0][0] = f64::INFINITY;
    let r = adj(&d, &bad, &mut g, 0);
    assert!(matches!(r, Err(Error::NonFinite { arg: "w", .. })));
    assert!(g.iter().all(|x| *x == [5.0; 2]));
}

/// Every node fixed, moved onto the line `x = 0` after the first of two steps: the second
/// step's assembly meets degenerate cells (an error half-way), and nothing is written.
#[test]
fn a_mesh_that_collapses_on_the_way_is_an_error_and_writes_nothing() {
    let mut case = Case::<f64, 2>::new(grid2(3, Kind::Mixed, 0.2));
    let n = case.n();
    case.fixed = vec![1; n];
    let flat: Vec<[f64; 2]> = case.points.iter().map(|p| [-2.0 * p[0], 0.0]).collect();
    let pre = ElasticPreconditioner::Blocks;
    let ms = (Modulus::Constant, 2);
    let mut dx = vec![[0.5; 2]; n];
    let mut g = vec![[5.0; 2]; n];
    let w = vec![[1.0; 2]; n];
    let (r, q) = with_problem(&case, &flat, ms, pre, |p| {
        let mut o = case.owned();
        let mut s = vec![[0.0; 2]; elastic_incremental_adjoint_scratch_len(&pre, n, 2)];
        (
            elastic_incremental_tangent(p, &mut dx, o.buffers(), &mut s),
            elastic_incremental_adjoint(p, &w, &mut g, o.buffers(), &mut s),
        )
    });
    assert!(
        matches!(r, Err(Error::NonPositive { arg: "cells", .. })),
        "{r:?}"
    );
    assert!(
        matches!(q, Err(Error::NonPositive { arg: "cells", .. })),
        "{q:?}"
    );
    assert!(dx.iter().all(|x| *x == [0.5; 2]) && g.iter().all(|x| *x == [5.0; 2]));
}

/// The cost probe of docs/sensitivities.md: the deformation, the tangent and the adjoint once
/// each on a 25 × 25 node mixed square (3 steps, inverse volume, tolerance 1e-13), for
/// `valgrind --tool=callgrind --toggle-collect='*deform_incremental*'` (and
/// `'*elastic_incremental_tangent*'`, `'*elastic_incremental_adjoint*'`). Checks that every
/// solve converged and the identity.
#[test]
#[ignore = "a callgrind probe (docs/sensitivities.md, Cost)"]
fn cost_probe() {
    let case = Case::<f64, 2>::new(grid2(24, Kind::Mixed, 0.25));
    let ms = (Modulus::InverseVolume, 3);
    let d = motion::<f64, 2>(&case.mesh, 20.0, 41);
    let v = boundary_field::<f64, 2>(&case.mesh, 43);
    let w = random(case.n(), &mut Lcg(47), |_| true);
    let x = case.deform(&d, ms.0, ms.1);
    assert!(x.iter().flatten().all(|x| x.is_finite()));
    let pre = ElasticPreconditioner::Blocks;
    let jv = tangent(&case, &d, &v, ms, pre);
    let g = adjoint(&case, &d, &w, ms, pre);
    check_dot(&jv, &w, &v, &g, 1e-8, "cost probe");
}
