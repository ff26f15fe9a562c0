//! Tangent and adjoint of the quaternion deformation with inverse-distance propagation
//! (`deform_idw_tangent`, `deform_idw_adjoint`), its fast tree-based variant
//! (`deform_idw_fast_tangent`, `deform_idw_fast_adjoint`) and transfinite interpolation of
//! structured blocks (`deform_tfi_tangent`, `deform_tfi_adjoint`), checked against what they
//! linearise:
//!
//! - central finite differences of `deform_idw` itself, with a step study (the error falls as
//!   `h²` until rounding; print with `-- --nocapture`);
//! - the dot-product test `⟨J v, w⟩ = ⟨v, Jᵀ w⟩` for random `v`, `w`, 2D and 3D, `f32` and
//!   `f64`, every rotation source;
//! - a dense reference: the whole Jacobian column by column (tangent), row by row (adjoint)
//!   and by finite differences, entry by entry;
//! - exact rigid motion: the deformation of a rigid motion of the whole boundary is that
//!   motion, so its tangent along a further rigid motion is the rigid tangent field.
//!
//! Meshes: a body (2D: a closed polygon; 3D: a cube surface of quadrilaterals) inside a fixed
//! far field (2D: a square loop; 3D: an octahedron of triangles), field points scattered
//! between them (inverse distance needs no cells); for TFI a curved structured block whose
//! whole boundary (its faces) moves.

use deform_kernel::quaternion::{
    deform_idw, deform_idw_adjoint, deform_idw_fast, deform_idw_fast_adjoint,
    deform_idw_fast_sensitivity_scratch_len, deform_idw_fast_tangent, deform_idw_scratch_len,
    deform_idw_sensitivity_scratch_len, deform_idw_tangent, deform_tfi, deform_tfi_adjoint,
    deform_tfi_scratch_len, deform_tfi_sensitivity_scratch_len, deform_tfi_tangent,
    propagate_idw_fast_index_len, propagate_idw_fast_scratch_len, BoundaryMotion, IdwFastOptions,
    RotationSource,
};
use deform_kernel::{Block, Cells, Directions, Error, Quat, Real};
use std::collections::BTreeMap;

/// A deterministic pseudo-random value in `[-1, 1)` (splitmix64).
fn rnd(seed: &mut u64) -> f64 {
    *seed = seed.wrapping_add(0x9E37_79B9_7F4A_7C15);
    let mut z = *seed;
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^= z >> 31;
    (z >> 11) as f64 / (1u64 << 52) as f64 - 1.0
}

/// The deformation under test.
#[derive(Clone, Copy, Debug)]
enum Method {
    /// `deform_idw`.
    Idw,
    /// `deform_idw_fast` with this opening parameter `θ` (tolerance 0.1).
    Fast(f64),
    /// `deform_tfi` on this block and these directions.
    Tfi(Block, Directions),
}

/// A test case: mesh points, boundary nodes (the first `body` of them move), boundary elements
/// (indexing boundary positions), the method.
#[derive(Clone)]
struct Case<const D: usize> {
    points: Vec<[f64; D]>,
    boundary: Vec<u32>,
    body: usize,
    offsets: Vec<u32>,
    nodes: Vec<u32>,
    kinds: Vec<u8>,
    method: Method,
}

impl<const D: usize> Case<D> {
    /// The same case deformed by `method`.
    fn with(&self, method: Method) -> Self {
        Case {
            method,
            ..self.clone()
        }
    }

    fn elements(&self) -> Cells<'_> {
        Cells::new(self.boundary.len(), &self.offsets, &self.nodes, &self.kinds).unwrap()
    }

    fn push(&mut self, kind: u8, el: &[u32]) {
        self.nodes.extend_from_slice(el);
        self.offsets.push(self.nodes.len() as u32);
        self.kinds.push(kind);
    }

    /// Adds `count` field points in the box `[-r, r]^D` outside the ball of radius `inner`.
    fn scatter(&mut self, count: usize, inner: f64, r: f64, seed: &mut u64) {
        while self.points.len() < self.boundary.len() + count {
            let p: [f64; D] = core::array::from_fn(|_| r * rnd(seed));
            if p.iter().map(|x| x * x).sum::<f64>().sqrt() > inner {
                self.points.push(p);
            }
        }
    }
}

/// 2D: a body polygon of `m` points (an ellipse, counter-clockwise) and a fixed square far
/// field of side 8 (4 points a side), then `field` scattered points.
fn case2(m: usize, field: usize) -> Case<2> {
    let mut c = Case {
        points: Vec::new(),
        boundary: Vec::new(),
        body: m,
        offsets: vec![0],
        nodes: Vec::new(),
        kinds: Vec::new(),
        method: Method::Idw,
    };
    for k in 0..m {
        let a = 2.0 * std::f64::consts::PI * k as f64 / m as f64;
        c.points.push([1.0 * a.cos() + 0.1, 0.5 * a.sin() - 0.05]);
    }
    for k in 0..m as u32 {
        c.push(3, &[k, (k + 1) % m as u32]);
    }
    let corners = [[-4.0, -4.0], [4.0, -4.0], [4.0, 4.0], [-4.0, 4.0]];
    for s in 0..4 {
        let (a, b): ([f64; 2], [f64; 2]) = (corners[s], corners[(s + 1) % 4]);
        for t in 0..4 {
            let f = t as f64 / 4.0;
            c.points
                .push([a[0] + f * (b[0] - a[0]), a[1] + f * (b[1] - a[1])]);
        }
    }
    for k in 0..16u32 {
        c.push(3, &[m as u32 + k, m as u32 + (k + 1) % 16]);
    }
    c.boundary = (0..c.points.len() as u32).collect();
    c.scatter(field, 1.1, 3.9, &mut 11);
    c
}

/// 3D: a body cube surface `[-1, 1]³` of `s × s` quadrilaterals per face (outward), a fixed
/// octahedron far field of radius 6 (triangles), then `field` scattered points.
fn case3(s: usize, field: usize) -> Case<3> {
    let mut c = Case {
        points: Vec::new(),
        boundary: Vec::new(),
        body: 0,
        offsets: vec![0],
        nodes: Vec::new(),
        kinds: Vec::new(),
        method: Method::Idw,
    };
    let mut ids: BTreeMap<[i64; 3], u32> = BTreeMap::new();
    let mut id = |c: &mut Case<3>, g: [i64; 3]| -> u32 {
        *ids.entry(g).or_insert_with(|| {
            c.points.push(g.map(|x| 2.0 * x as f64 / s as f64 - 1.0));
            c.points.len() as u32 - 1
        })
    };
    let s_i = s as i64;
    for a in 0..3 {
        let (b, cc) = ((a + 1) % 3, (a + 2) % 3);
        for side in [0, s_i] {
            for i in 0..s_i {
                for j in 0..s_i {
                    let g = |di: i64, dj: i64| {
                        let mut g = [0i64; 3];
                        g[a] = side;
                        g[b] = i + di;
                        g[cc] = j + dj;
                        g
                    };
                    let mut q = [
                        id(&mut c, g(0, 0)),
                        id(&mut c, g(1, 0)),
                        id(&mut c, g(1, 1)),
                        id(&mut c, g(0, 1)),
                    ];
                    if side == 0 {
                        q.reverse();
                    }
                    c.push(9, &q);
                }
            }
        }
    }
    let m = c.points.len() as u32;
    c.body = m as usize;
    for a in 0..3 {
        for sg in [-6.0, 6.0] {
            let mut p = [0.0; 3];
            p[a] = sg;
            c.points.push(p);
        }
    }
    // Octahedron vertices m + 2a + (sign > 0): faces per octant, outward.
    for sx in 0..2u32 {
        for sy in 0..2u32 {
            for sz in 0..2u32 {
                let t = [m + sx, m + 2 + sy, m + 4 + sz];
                if (sx + sy + sz) % 2 == 1 {
                    c.push(5, &t);
                } else {
                    c.push(5, &[t[0], t[2], t[1]]);
                }
            }
        }
    }
    c.boundary = (0..c.points.len() as u32).collect();
    c.scatter(field, 1.9, 4.0, &mut 23);
    c
}

/// 2D TFI: a curved `ni × nj` block (an annular sector, radii graded), both directions
/// active; its whole perimeter is the boundary (a closed loop of segments) and moves.
fn block2(ni: usize, nj: usize) -> Case<2> {
    let block = Block::new([ni, nj, 1]).unwrap();
    let mut points = Vec::new();
    for j in 0..nj {
        for i in 0..ni {
            let (u, v) = (i as f64 / (ni - 1) as f64, j as f64 / (nj - 1) as f64);
            let (r, a) = (
                1.0 + 2.0 * v.powf(1.3),
                0.2 + 2.0 * u + 0.1 * (3.0 * v).sin(),
            );
            points.push([r * a.cos(), r * a.sin()]);
        }
    }
    let mut ring: Vec<[usize; 2]> = (0..ni).map(|i| [i, 0]).collect();
    ring.extend((1..nj).map(|j| [ni - 1, j]));
    ring.extend((0..ni - 1).rev().map(|i| [i, nj - 1]));
    ring.extend((1..nj - 1).rev().map(|j| [0, j]));
    let mut c = Case {
        points,
        boundary: ring
            .iter()
            .map(|&[i, j]| block.index(i, j, 0) as u32)
            .collect(),
        body: ring.len(),
        offsets: vec![0],
        nodes: Vec::new(),
        kinds: Vec::new(),
        method: Method::Tfi(block, Directions::ALL.without(deform_kernel::Direction::K)),
    };
    let b = ring.len() as u32;
    for k in 0..b {
        c.push(3, &[k, (k + 1) % b]);
    }
    c
}

/// 3D TFI: a curved `n × n × n` block, all directions active; its whole surface is the
/// boundary (outward quadrilaterals) and moves.
fn block3(n: usize) -> Case<3> {
    let block = Block::new([n, n, n]).unwrap();
    let g = |i: usize| 2.0 * (i as f64 / (n - 1) as f64).powf(1.2) - 1.0;
    let mut points = Vec::new();
    for k in 0..n {
        for j in 0..n {
            for i in 0..n {
                let (u, v, w) = (g(i), g(j), g(k));
                points.push([
                    u + 0.15 * (2.0 * v).sin(),
                    v + 0.1 * w * w,
                    w + 0.1 * u.sin(),
                ]);
            }
        }
    }
    let on_surface = |c: [usize; 3]| c.iter().any(|&x| x == 0 || x == n - 1);
    let boundary: Vec<u32> = (0..block.point_count())
        .filter(|&p| on_surface(block.ijk(p)))
        .map(|p| p as u32)
        .collect();
    let position: BTreeMap<u32, u32> = boundary
        .iter()
        .enumerate()
        .map(|(k, &p)| (p, k as u32))
        .collect();
    let mut c = Case {
        points,
        body: boundary.len(),
        boundary,
        offsets: vec![0],
        nodes: Vec::new(),
        kinds: Vec::new(),
        method: Method::Tfi(block, Directions::ALL),
    };
    for a in 0..3 {
        let (b, cc) = ((a + 1) % 3, (a + 2) % 3);
        for side in [0, n - 1] {
            for i in 0..n - 1 {
                for j in 0..n - 1 {
                    let at = |di: usize, dj: usize| {
                        let mut x = [0usize; 3];
                        x[a] = side;
                        x[b] = i + di;
                        x[cc] = j + dj;
                        position[&(block.index(x[0], x[1], x[2]) as u32)]
                    };
                    let mut q = [at(0, 0), at(1, 0), at(1, 1), at(0, 1)];
                    if side == 0 {
                        q.reverse();
                    }
                    c.push(9, &q);
                }
            }
        }
    }
    c
}

/// The body's deformed shape: a rotation about `z` (2D) or a tilted axis (3D) by `angle`, a
/// translation and a smooth non-rigid bulge; the far field stays.
fn deformed<const D: usize>(c: &Case<D>, angle: f64) -> Vec<[f64; D]> {
    let q = if D == 2 {
        Quat::from_rotation_z(angle)
    } else {
        Quat::from_axis_angle([0.3, -0.5, 1.0], angle).unwrap()
    };
    (0..c.boundary.len())
        .map(|k| {
            let p = c.points[c.boundary[k] as usize];
            if k >= c.body {
                return p;
            }
            let mut v = [0.0; 3];
            v[..D].copy_from_slice(&p);
            let r = q.rotate(v);
            core::array::from_fn(|i| {
                r[i] + 0.1 * (i as f64 + 1.0) + 0.05 * (2.0 * v[(i + 1) % D]).sin()
            })
        })
        .collect()
}

/// Rotation sources under test.
#[derive(Clone, Copy, Debug)]
enum Source {
    Shape,
    Rigid,
    PerNode,
}

/// A motion of the case: the deformed boundary `d` (in `T`), the source and origin.
struct Setup<T, const D: usize> {
    points: Vec<[T; D]>,
    d: Vec<[T; D]>,
    per_node: Vec<Quat<T>>,
    source: Source,
    origin: Option<[T; D]>,
}

impl<T: Real, const D: usize> Setup<T, D> {
    fn new(c: &Case<D>, d: &[[f64; D]], source: Source, origin: Option<[f64; D]>) -> Self {
        let mut seed = 5;
        let per_node = (0..c.boundary.len())
            .map(|_| {
                let a = 0.2 * rnd(&mut seed);
                let q = if D == 2 {
                    Quat::from_rotation_z(a)
                } else {
                    Quat::from_axis_angle([rnd(&mut seed), rnd(&mut seed), 1.0], a).unwrap()
                };
                Quat::new(
                    T::from_f64(q.w),
                    T::from_f64(q.x),
                    T::from_f64(q.y),
                    T::from_f64(q.z),
                )
            })
            .collect();
        Setup {
            points: c.points.iter().map(|p| p.map(T::from_f64)).collect(),
            d: d.iter().map(|p| p.map(T::from_f64)).collect(),
            per_node,
            source,
            origin: origin.map(|o| o.map(T::from_f64)),
        }
    }

    fn motion<'a>(&'a self, c: &'a Case<D>, d: &'a [[T; D]]) -> BoundaryMotion<'a, T, D> {
        let angle = T::from_f64(0.3);
        BoundaryMotion {
            nodes: &c.boundary,
            deformed: d,
            elements: Some(c.elements()),
            rotations: match self.source {
                Source::Shape => RotationSource::Shape,
                Source::Rigid => RotationSource::Rigid(if D == 2 {
                    Quat::from_rotation_z(angle)
                } else {
                    Quat::from_axis_angle([T::ZERO, T::ZERO, T::ONE], angle).unwrap()
                }),
                Source::PerNode => RotationSource::PerNode(&self.per_node),
            },
            origin: self.origin,
        }
    }

    /// The deformation for boundary positions `d`.
    fn deform(&self, c: &Case<D>, d: &[[T; D]]) -> Vec<[T; D]> {
        let (n, b) = (self.points.len(), d.len());
        let mut tr = vec![[T::ZERO; D]; n];
        let mut rot = vec![Quat::identity(); n];
        let mut out = vec![[T::ZERO; D]; n];
        let motion = self.motion(c, d);
        let p = &self.points;
        let e = T::from_f64(3.0);
        match c.method {
            Method::Idw => {
                let mut scratch = vec![T::ZERO; deform_idw_scratch_len::<D>(n, b)];
                deform_idw(p, &motion, e, &mut tr, &mut rot, &mut scratch, &mut out).map(|_| ())
            }
            Method::Fast(theta) => {
                let mut scratch = vec![T::ZERO; deform_idw_scratch_len::<D>(n, b)];
                let (mut index, mut tree) = fast_buffers::<T, D>(b);
                deform_idw_fast(
                    p,
                    &motion,
                    e,
                    &fast_options(theta),
                    &mut tr,
                    &mut rot,
                    &mut scratch,
                    &mut index,
                    &mut tree,
                    &mut out,
                )
                .map(|_| ())
            }
            Method::Tfi(block, dirs) => {
                let mut scratch = vec![T::ZERO; deform_tfi_scratch_len::<D>(&block, b)];
                deform_tfi(
                    &block,
                    dirs,
                    p,
                    &motion,
                    &mut tr,
                    &mut rot,
                    &mut scratch,
                    &mut out,
                )
                .map(|_| ())
            }
        }
        .unwrap();
        out
    }

    fn tangent(&self, c: &Case<D>, v: &[[T; D]]) -> Vec<[T; D]> {
        let n = self.points.len();
        let mut out = vec![[T::ZERO; D]; n];
        self.sensitivity(c, v, &mut out).unwrap();
        out
    }

    fn adjoint(&self, c: &Case<D>, w: &[[T; D]]) -> Vec<[T; D]> {
        let mut out = vec![[T::ZERO; D]; self.d.len()];
        self.sensitivity(c, w, &mut out).unwrap();
        out
    }

    /// The tangent (`input` one per boundary point) or the adjoint (`input` one per mesh
    /// point) of `c.method` into `out`.
    fn sensitivity(&self, c: &Case<D>, input: &[[T; D]], out: &mut [[T; D]]) -> Result<(), Error> {
        let (n, b) = (self.points.len(), self.d.len());
        let tangent = input.len() == b && out.len() == n;
        let motion = self.motion(c, &self.d);
        let p = &self.points;
        let e = T::from_f64(3.0);
        match c.method {
            Method::Idw => {
                let mut scratch = vec![T::ZERO; deform_idw_sensitivity_scratch_len::<D>(n, b)];
                if tangent {
                    deform_idw_tangent(p, &motion, e, input, &mut scratch, out)
                } else {
                    deform_idw_adjoint(p, &motion, e, input, &mut scratch, out)
                }
            }
            Method::Fast(theta) => {
                let len = deform_idw_fast_sensitivity_scratch_len::<D>(n, b);
                let mut scratch = vec![T::ZERO; len];
                let (mut tr, mut rot) = (vec![[T::ZERO; D]; n], vec![Quat::identity(); n]);
                let (mut index, mut tree) = fast_buffers::<T, D>(b);
                let o = fast_options(theta);
                let f = if tangent {
                    deform_idw_fast_tangent
                } else {
                    deform_idw_fast_adjoint
                };
                let (s, ix, tr2) = (&mut scratch, &mut index, &mut tree);
                f(p, &motion, e, &o, input, &mut tr, &mut rot, s, ix, tr2, out)
            }
            Method::Tfi(block, dirs) => {
                let len = deform_tfi_sensitivity_scratch_len::<D>(&block, b);
                let mut scratch = vec![T::ZERO; len];
                let f = if tangent {
                    deform_tfi_tangent
                } else {
                    deform_tfi_adjoint
                };
                f(&block, dirs, p, &motion, input, &mut scratch, out)
            }
        }
    }
}

/// The fast IDW's options under test: `θ`, tolerance 0.1 (the default).
fn fast_options<T: Real>(theta: f64) -> IdwFastOptions<T> {
    IdwFastOptions {
        theta: T::from_f64(theta),
        tolerance: T::from_f64(0.1),
    }
}

/// The fast IDW's `index` and `tree` buffers for `b` boundary nodes.
fn fast_buffers<T: Real, const D: usize>(b: usize) -> (Vec<u32>, Vec<T>) {
    (
        vec![0; propagate_idw_fast_index_len(b)],
        vec![T::ZERO; propagate_idw_fast_scratch_len::<D>(b)],
    )
}

/// Random vectors, `scale` in the first `body` entries and `rest` after them.
fn random<T: Real, const D: usize>(len: usize, body: usize, rest: f64, seed: u64) -> Vec<[T; D]> {
    let mut s = seed;
    (0..len)
        .map(|k| {
            let f = if k < body { 1.0 } else { rest };
            core::array::from_fn(|_| T::from_f64(f * rnd(&mut s)))
        })
        .collect()
}

fn dot<T: Real, const D: usize>(a: &[[T; D]], b: &[[T; D]]) -> f64 {
    a.iter()
        .flatten()
        .zip(b.iter().flatten())
        .map(|(x, y)| x.to_f64() * y.to_f64())
        .sum()
}

fn norm<T: Real, const D: usize>(a: &[[T; D]]) -> f64 {
    dot(a, a).sqrt()
}

/// The largest `|a − b|` over all components, in f64.
fn max_diff<T: Real, const D: usize>(a: &[[T; D]], b: &[[f64; D]]) -> f64 {
    a.iter()
        .flatten()
        .zip(b.iter().flatten())
        .map(|(x, y)| (x.to_f64() - y).abs())
        .fold(0.0, f64::max)
}

/// Central differences `(R(d + h v) − R(d − h v)) / 2h` in f64.
fn central<const D: usize>(
    s: &Setup<f64, D>,
    c: &Case<D>,
    v: &[[f64; D]],
    h: f64,
) -> Vec<[f64; D]> {
    let shift = |sg: f64| -> Vec<[f64; D]> {
        s.d.iter()
            .zip(v)
            .map(|(d, v)| core::array::from_fn(|i| d[i] + sg * h * v[i]))
            .collect()
    };
    let (p, m) = (s.deform(c, &shift(1.0)), s.deform(c, &shift(-1.0)));
    p.iter()
        .zip(&m)
        .map(|(a, b)| core::array::from_fn(|i| (a[i] - b[i]) / (2.0 * h)))
        .collect()
}

/// Step study: prints the table, asserts the `h²` regime and the accuracy at the best step.
/// With `affine` (rotations that do not depend on `d`: the deformation is affine in `d`) the
/// differences have no truncation error, and the largest step must agree to rounding.
fn step_study<const D: usize>(
    c: &Case<D>,
    s: &Setup<f64, D>,
    v: &[[f64; D]],
    label: &str,
    affine: bool,
) {
    let t = s.tangent(c, v);
    let scale = t.iter().flatten().fold(0.0f64, |a, x| a.max(x.abs()));
    println!("{label}: max |δR| = {scale:.3e}\n       h      max|FD − tangent| / max|δR|");
    let mut errs = Vec::new();
    for e in 1..=8 {
        let h = 10f64.powi(-e);
        let err = max_diff(&t, &central(s, c, v, h)) / scale;
        println!("  {h:8.0e}   {err:10.3e}");
        errs.push(err);
    }
    if affine {
        assert!(
            errs[0] < 1e-13,
            "{label}: an affine map differs from its FD: {errs:?}"
        );
        return;
    }
    let best = errs.iter().copied().fold(f64::INFINITY, f64::min);
    assert!(best < 1e-8, "{label}: best FD agreement {best:e}");
    // h² regime: the first decade where the error is truncation-dominated falls ~100×.
    let ratio = errs[1] / errs[2];
    assert!(
        (30.0..300.0).contains(&ratio),
        "{label}: error ratio 1e-2 → 1e-3 is {ratio}"
    );
}

/// The step study of every method on `cases` (shape rotations, default and given origin).
fn central_differences<const D: usize>(cases: &[Case<D>], angle: f64, origin: [f64; D]) {
    for c in cases {
        let d = deformed(c, angle);
        for origin in [None, Some(origin)] {
            let s = Setup::<f64, D>::new(c, &d, Source::Shape, origin);
            // With the default origin only moving points are perturbed (the origin's point
            // set is then unchanged); with a given origin the far field too.
            let rest = if origin.is_some() { 0.3 } else { 0.0 };
            let v = random::<f64, D>(c.boundary.len(), c.body, rest, 3 + D as u64);
            let label = format!("{D}D {:?} shape, origin {origin:?}", c.method);
            step_study(c, &s, &v, &label, false);
        }
    }
}

#[test]
fn tangent_matches_central_differences_2d() {
    let c = case2(24, 120);
    central_differences(
        &[c.with(Method::Fast(0.5)), block2(9, 6), c],
        0.4,
        [0.3, -0.2],
    );
}

#[test]
fn tangent_matches_central_differences_3d() {
    let c = case3(3, 150);
    let cases = [c.with(Method::Fast(0.5)), block3(5), c];
    central_differences(&cases, 0.5, [0.2, 0.1, -0.3]);
}

#[test]
fn tangent_matches_central_differences_other_sources() {
    let (c2, c3) = (case2(16, 60), case3(2, 60));
    let cases2 = [c2.with(Method::Fast(0.5)), block2(6, 5), c2];
    let cases3 = [case3(3, 100).with(Method::Fast(0.5)), block3(4), c3];
    for source in [Source::Rigid, Source::PerNode] {
        for c2 in &cases2 {
            let s = Setup::<f64, 2>::new(c2, &deformed(c2, 0.3), source, Some([0.1, 0.0]));
            let v = random::<f64, 2>(c2.boundary.len(), c2.body, 0.0, 8);
            step_study(c2, &s, &v, &format!("2D {:?} {source:?}", c2.method), true);
        }
        for c3 in &cases3 {
            let s = Setup::<f64, 3>::new(c3, &deformed(c3, 0.3), source, Some([0.1, 0.0, 0.2]));
            let v = random::<f64, 3>(c3.boundary.len(), c3.body, 0.0, 9);
            step_study(c3, &s, &v, &format!("3D {:?} {source:?}", c3.method), true);
        }
    }
}

/// `|⟨J v, w⟩ − ⟨v, Jᵀ w⟩| / (|J v| |w| + |v| |Jᵀ w|)` for random `v`, `w`.
fn dot_test<T: Real, const D: usize>(c: &Case<D>, source: Source, origin: Option<[f64; D]>) -> f64 {
    let d = deformed(c, 0.35);
    let s = Setup::<T, D>::new(c, &d, source, origin);
    let mut worst = 0.0f64;
    for seed in 0..3 {
        let v = random::<T, D>(c.boundary.len(), c.boundary.len(), 1.0, 100 + seed);
        let w = random::<T, D>(c.points.len(), c.points.len(), 1.0, 200 + seed);
        let jv = s.tangent(c, &v);
        let jtw = s.adjoint(c, &w);
        let (a, b) = (dot(&jv, &w), dot(&v, &jtw));
        let den = norm(&jv) * norm(&w) + norm(&v) * norm(&jtw);
        worst = worst.max((a - b).abs() / den);
    }
    worst
}

fn dot_tests<T: Real>(tol: f64) {
    let (c2, c3) = (case2(20, 80), case3(2, 80));
    let cases = [
        (
            c2.with(Method::Fast(0.5)),
            case3(3, 100).with(Method::Fast(0.5)),
        ),
        (block2(8, 6), block3(4)),
        (c2, c3),
    ];
    for (c2, c3) in &cases {
        for source in [Source::Shape, Source::Rigid, Source::PerNode] {
            for (o2, o3) in [(None, None), (Some([0.2, 0.1]), Some([0.2, 0.1, -0.1]))] {
                let e2 = dot_test::<T, 2>(c2, source, o2);
                let e3 = dot_test::<T, 3>(c3, source, o3);
                println!(
                    "{} {:?} {source:?} origin {:?}: 2D {e2:.2e}, 3D {e3:.2e}",
                    core::any::type_name::<T>(),
                    c2.method,
                    o2.is_some()
                );
                assert!(
                    e2 < tol && e3 < tol,
                    "{:?} {source:?}: {e2:e} {e3:e}",
                    c2.method
                );
            }
        }
    }
}

#[test]
fn dot_product_test_f64() {
    dot_tests::<f64>(1e-14);
}

#[test]
fn dot_product_test_f32() {
    dot_tests::<f32>(2e-6);
}

/// The whole Jacobian three ways on a small case: tangent columns, adjoint rows, central
/// differences (`h = 1e-5`).
fn dense<const D: usize>(c: &Case<D>, d: &[[f64; D]]) {
    let s = Setup::<f64, D>::new(c, d, Source::Shape, None);
    let (n, b) = (c.points.len(), c.boundary.len());
    let mut by_tangent = vec![vec![0.0; b * D]; n * D];
    let mut by_fd = vec![vec![0.0; b * D]; n * D];
    for col in 0..b * D {
        let mut v = vec![[0.0; D]; b];
        v[col / D][col % D] = 1.0;
        let t = s.tangent(c, &v);
        // Perturbing a resting point changes the default origin: difference only movers.
        let fd = if col / D < c.body {
            central(&s, c, &v, 1e-5)
        } else {
            t.clone()
        };
        for row in 0..n * D {
            by_tangent[row][col] = t[row / D][row % D];
            by_fd[row][col] = fd[row / D][row % D];
        }
    }
    let big = by_tangent
        .iter()
        .flatten()
        .fold(0.0f64, |a, x| a.max(x.abs()));
    let (mut e_adj, mut e_fd) = (0.0f64, 0.0f64);
    for row in 0..n * D {
        let mut w = vec![[0.0; D]; n];
        w[row / D][row % D] = 1.0;
        let a = s.adjoint(c, &w);
        for col in 0..b * D {
            e_adj = e_adj.max((a[col / D][col % D] - by_tangent[row][col]).abs());
            e_fd = e_fd.max((by_fd[row][col] - by_tangent[row][col]).abs());
        }
    }
    println!(
        "{D}D {:?} dense {}×{}: max |J| {big:.3e}, adjoint {:.2e}, FD {:.2e}",
        c.method,
        n * D,
        b * D,
        e_adj / big,
        e_fd / big
    );
    assert!(e_adj < 1e-14 * big, "adjoint vs tangent {e_adj:e}");
    assert!(e_fd < 1e-8 * big, "FD vs tangent {e_fd:e}");
}

#[test]
fn dense_jacobian_three_ways() {
    let c2 = case2(10, 30);
    let c3 = case3(1, 20);
    // The fast IDW on cases with clusters (see `fast_idw_cases_use_clusters`).
    let (f2, f3) = (case2(16, 60), case3(3, 100));
    for c2 in [f2.with(Method::Fast(0.5)), block2(5, 4), c2] {
        dense(&c2, &deformed(&c2, 0.5));
    }
    for c3 in [f3.with(Method::Fast(0.5)), block3(3), c3] {
        dense(&c3, &deformed(&c3, 0.5));
    }
}

/// The case without its far field: the body points, the body elements, the field points.
fn body_only<const D: usize>(c: &Case<D>) -> Case<D> {
    let body = Case::<D> {
        points: c
            .points
            .iter()
            .take(c.body)
            .copied()
            .chain(c.points.iter().skip(c.boundary.len()).copied())
            .collect(),
        boundary: (0..c.body as u32).collect(),
        body: c.body,
        offsets: Vec::new(),
        nodes: Vec::new(),
        kinds: Vec::new(),
        method: c.method,
    };
    // The body's elements are the first ones (they only index body points).
    let ne = c
        .kinds
        .iter()
        .zip(c.offsets.windows(2))
        .take_while(|(_, w)| {
            c.nodes[w[0] as usize..w[1] as usize]
                .iter()
                .all(|&v| (v as usize) < c.body)
        })
        .count();
    Case {
        offsets: c.offsets[..=ne].to_vec(),
        nodes: c.nodes[..c.offsets[ne] as usize].to_vec(),
        kinds: c.kinds[..ne].to_vec(),
        ..body
    }
}

/// A rigid motion of the whole boundary (the body alone, no far field) deforms the mesh
/// rigidly; the tangent along a further infinitesimal rotation `ω` and translation `τ` is
/// `ω × (R − c) + τ` at every point.
fn rigid<T: Real, const D: usize>(c: &Case<D>, tol: f64) -> f64 {
    let body = if c.body == c.boundary.len() {
        c.clone()
    } else {
        body_only(c)
    };
    let q = if D == 2 {
        Quat::from_rotation_z(0.7)
    } else {
        Quat::from_axis_angle([1.0, 2.0, -0.5], 0.7).unwrap()
    };
    let (cen, tr) = ([0.3, -0.2, 0.1], [0.5, 0.25, -0.4]);
    let d: Vec<[f64; D]> = body
        .boundary
        .iter()
        .map(|&k| body.points[k as usize])
        .map(|p| {
            let mut v = [0.0; 3];
            for i in 0..D {
                v[i] = p[i] - cen[i];
            }
            let r = q.rotate(v);
            core::array::from_fn(|i| r[i] + cen[i] + tr[i])
        })
        .collect();
    let s = Setup::<T, D>::new(&body, &d, Source::Shape, None);
    let omega = if D == 2 {
        [0.0, 0.0, 0.8]
    } else {
        [0.4, -0.7, 0.5]
    };
    let tau = [0.3, -0.1, 0.2];
    let field = |x: &[f64; D]| -> [f64; D] {
        let mut r = [0.0; 3];
        for i in 0..D {
            r[i] = x[i] - cen[i];
        }
        let w = [
            omega[1] * r[2] - omega[2] * r[1],
            omega[2] * r[0] - omega[0] * r[2],
            omega[0] * r[1] - omega[1] * r[0],
        ];
        core::array::from_fn(|i| w[i] + tau[i])
    };
    let v: Vec<[T; D]> =
        s.d.iter()
            .map(|p| field(&p.map(|x| x.to_f64())).map(T::from_f64))
            .collect();
    let moved = s.deform(&body, &s.d);
    let expect: Vec<[f64; D]> = moved
        .iter()
        .map(|p| field(&p.map(|x| x.to_f64())))
        .collect();
    let t = s.tangent(&body, &v);
    let err = max_diff(&t, &expect) / expect.iter().flatten().fold(0.0f64, |a, x| a.max(x.abs()));
    println!(
        "{} {D}D {:?} rigid tangent: relative error {err:.2e}",
        core::any::type_name::<T>(),
        c.method
    );
    assert!(err < tol, "{err:e}");
    err
}

#[test]
fn rigid_motion_tangent_is_rigid() {
    let (c2, c3) = (case2(24, 100), case3(3, 100));
    for c2 in [c2.with(Method::Fast(0.5)), block2(9, 6), c2] {
        rigid::<f64, 2>(&c2, 1e-12);
        rigid::<f32, 2>(&c2, 1e-4);
    }
    for c3 in [c3.with(Method::Fast(0.5)), block3(5), c3] {
        rigid::<f64, 3>(&c3, 1e-12);
        rigid::<f32, 3>(&c3, 1e-4);
    }
}

#[test]
fn bad_input_is_a_typed_error_and_out_is_unchanged() {
    let c = case2(8, 10);
    let d = deformed(&c, 0.2);
    let s = Setup::<f64, 2>::new(&c, &d, Source::Shape, None);
    let (n, b) = (c.points.len(), c.boundary.len());
    let motion = s.motion(&c, &s.d);
    let mut scratch = vec![0.0; deform_idw_sensitivity_scratch_len::<2>(n, b)];
    let mut out = vec![[7.0; 2]; n];
    let mut v = vec![[0.0; 2]; b];
    v[3][1] = f64::NAN;
    let e = deform_idw_tangent(&s.points, &motion, 3.0, &v, &mut scratch, &mut out);
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
    let e = deform_idw_tangent(&s.points, &motion, 3.0, &v[1..], &mut scratch, &mut out);
    assert!(matches!(e, Err(Error::LengthMismatch { .. })), "{e:?}");
    let e = deform_idw_tangent(
        &s.points,
        &motion,
        -1.0,
        &vec![[0.0; 2]; b],
        &mut scratch,
        &mut out,
    );
    assert!(
        matches!(
            e,
            Err(Error::InvalidParameter {
                arg: "exponent",
                ..
            })
        ),
        "{e:?}"
    );
    let short = &mut scratch[..b];
    let e = deform_idw_tangent(&s.points, &motion, 3.0, &vec![[0.0; 2]; b], short, &mut out);
    assert!(matches!(e, Err(Error::BufferTooSmall { .. })), "{e:?}");
    assert!(out.iter().flatten().all(|&x| x == 7.0));
    let mut back = vec![[7.0; 2]; b];
    let mut w = vec![[0.0; 2]; n];
    w[n - 1][0] = f64::INFINITY;
    let e = deform_idw_adjoint(&s.points, &motion, 3.0, &w, &mut scratch, &mut back);
    assert!(
        matches!(e, Err(Error::NonFinite { arg: "weights", .. })),
        "{e:?}"
    );
    assert!(back.iter().flatten().all(|&x| x == 7.0));
}

/// With `θ = 0` the fast IDW uses no cluster: it is the exact IDW up to summation order, and
/// so are its tangent and adjoint.
#[test]
fn fast_idw_with_theta_zero_is_the_exact_idw() {
    fn check<const D: usize>(c: &Case<D>) {
        let d = deformed(c, 0.4);
        let exact = Setup::<f64, D>::new(c, &d, Source::Shape, None);
        let fast_case = c.with(Method::Fast(0.0));
        let (b, n) = (c.boundary.len(), c.points.len());
        let v = random::<f64, D>(b, c.body, 0.0, 31);
        let w = random::<f64, D>(n, n, 1.0, 32);
        let (t0, t1) = (exact.tangent(c, &v), exact.tangent(&fast_case, &v));
        let (a0, a1) = (exact.adjoint(c, &w), exact.adjoint(&fast_case, &w));
        let rel = |x: &[[f64; D]], y: &[[f64; D]]| max_diff(x, y) / norm(y);
        let (et, ea) = (rel(&t1, &t0), rel(&a1, &a0));
        println!("{D}D θ = 0 fast vs exact: tangent {et:.2e}, adjoint {ea:.2e}");
        assert!(et < 1e-13 && ea < 1e-13, "{et:e} {ea:e}");
        // And θ = 0.5 is not the exact method here (clusters are used).
        let t5 = exact.tangent(&c.with(Method::Fast(0.5)), &v);
        assert!(rel(&t5, &t0) > 1e-9, "θ = 0.5 used no cluster");
    }
    check(&case2(24, 120));
    check(&case3(3, 150));
}

/// The cases above exercise the clusters of the fast IDW: the deformation uses some.
#[test]
fn fast_idw_cases_use_clusters() {
    fn clusters<const D: usize>(c: &Case<D>) -> u64 {
        let s = Setup::<f64, D>::new(c, &deformed(c, 0.4), Source::Shape, None);
        let (n, b) = (c.points.len(), c.boundary.len());
        let (mut tr, mut rot) = (vec![[0.0; D]; n], vec![Quat::identity(); n]);
        let mut scratch = vec![0.0; deform_idw_scratch_len::<D>(n, b)];
        let (mut index, mut tree) = fast_buffers::<f64, D>(b);
        let mut out = vec![[0.0; D]; n];
        let (_, report) = deform_idw_fast(
            &s.points,
            &s.motion(c, &s.d),
            3.0,
            &fast_options(0.5),
            &mut tr,
            &mut rot,
            &mut scratch,
            &mut index,
            &mut tree,
            &mut out,
        )
        .unwrap();
        report.clusters
    }
    for c in [case2(16, 60), case2(20, 80), case2(24, 100), case2(24, 120)] {
        let k = clusters(&c);
        println!(
            "2D B = {}, N = {}: {k} clusters",
            c.boundary.len(),
            c.points.len()
        );
        assert!(k > 0);
    }
    for c in [case3(3, 100), case3(3, 150)] {
        let k = clusters(&c);
        println!(
            "3D B = {}, N = {}: {k} clusters",
            c.boundary.len(),
            c.points.len()
        );
        assert!(k > 0);
    }
}

/// Bad input to the fast IDW's and TFI's sensitivities: typed errors, `out` unchanged.
#[test]
fn fast_idw_and_tfi_bad_input_is_a_typed_error_and_out_is_unchanged() {
    for c in [case2(8, 10).with(Method::Fast(0.5)), block2(5, 4)] {
        let s = Setup::<f64, 2>::new(&c, &deformed(&c, 0.2), Source::Shape, None);
        let (n, b) = (c.points.len(), c.boundary.len());
        let mut out = vec![[7.0; 2]; n];
        let mut v = vec![[0.0; 2]; b];
        v[3][1] = f64::NAN;
        let e = s.sensitivity(&c, &v, &mut out);
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
        let mut back = vec![[7.0; 2]; b];
        let mut w = vec![[0.0; 2]; n];
        w[n - 1][0] = f64::INFINITY;
        let e = s.sensitivity(&c, &w, &mut back);
        assert!(
            matches!(e, Err(Error::NonFinite { arg: "weights", .. })),
            "{e:?}"
        );
        let e = s.sensitivity(&c, &w[1..], &mut back);
        assert!(matches!(e, Err(Error::LengthMismatch { .. })), "{e:?}");
        assert!(out.iter().chain(&back).flatten().all(|&x| x == 7.0));
    }
    // θ out of range; scratch too short.
    let c = case2(8, 10);
    let s = Setup::<f64, 2>::new(&c, &deformed(&c, 0.2), Source::Shape, None);
    let (n, b) = (c.points.len(), c.boundary.len());
    let motion = s.motion(&c, &s.d);
    let (mut tr, mut rot) = (vec![[0.0; 2]; n], vec![Quat::identity(); n]);
    let (mut index, mut tree) = fast_buffers::<f64, 2>(b);
    let mut scratch = vec![0.0; deform_idw_fast_sensitivity_scratch_len::<2>(n, b)];
    let mut out = vec![[7.0; 2]; n];
    let v = vec![[0.1; 2]; b];
    for (theta, len) in [(1.0, scratch.len()), (0.5, scratch.len() - 1)] {
        let e = deform_idw_fast_tangent(
            &s.points,
            &motion,
            3.0,
            &fast_options(theta),
            &v,
            &mut tr,
            &mut rot,
            &mut scratch[..len],
            &mut index,
            &mut tree,
            &mut out,
        );
        assert!(
            matches!(
                e,
                Err(Error::InvalidParameter {
                    arg: "options.theta",
                    ..
                }) | Err(Error::BufferTooSmall { .. })
            ),
            "{e:?}"
        );
    }
    assert!(out.iter().flatten().all(|&x| x == 7.0));
    // TFI: a face point missing from the motion.
    let c = block2(5, 4);
    let s = Setup::<f64, 2>::new(&c, &deformed(&c, 0.2), Source::Rigid, None);
    let Method::Tfi(block, dirs) = c.method else {
        unreachable!()
    };
    let b = c.boundary.len() - 1;
    let motion = BoundaryMotion {
        nodes: &c.boundary[..b],
        deformed: &s.d[..b],
        elements: None,
        rotations: RotationSource::Rigid(Quat::identity()),
        origin: None,
    };
    let mut scratch = vec![0.0; deform_tfi_sensitivity_scratch_len::<2>(&block, b)];
    let mut out = vec![[7.0; 2]; c.points.len()];
    let e = deform_tfi_tangent(
        &block,
        dirs,
        &s.points,
        &motion,
        &v[..b],
        &mut scratch,
        &mut out,
    );
    let missing = c.boundary[b] as usize;
    assert!(
        matches!(e, Err(Error::Unanchored { node }) if node == missing),
        "{e:?}"
    );
    assert!(out.iter().flatten().all(|&x| x == 7.0));
}
