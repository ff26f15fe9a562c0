//! Panic-check calls for the kernel's foundation entry points: `real`, `vector`, `quat`,
//! `graph`, `graph_builder`, `reduce`, `cells`, `block` and `error` (Display and defmt).
//!
//! Not called: derived `Debug` impls and float `Display`/`Debug`. They are core's code, and
//! core's `<str as Debug>` (escape_debug) keeps panic paths that no optimisation removes.
//!
//! Every input is black-boxed and every output is black-boxed, so each call survives with all
//! of its paths live. Generic items are instantiated for `f32` and `f64`, and for `D` = 2 and
//! 3 (plus 4, the quaternion field width, for the `N`-generic helpers).

// `clone()` on `Copy` types is called on purpose: it is a public entry point too.
#![allow(clippy::clone_on_copy)]

use core::fmt::Write;
use core::hint::black_box;
use deform_kernel::{Direction, Directions};

use deform_kernel::real::{all_finite, first_non_finite};
use deform_kernel::vector;
use deform_kernel::{
    graph_from_cells, graph_from_cells_len, graph_from_edges, graph_from_edges_len, Block,
    CellKind, Cells, Error, Graph, Quat, QuatAverage, Real,
};

/// Calls every foundation entry point with opaque inputs.
pub fn exercise() {
    real::<f32>();
    real::<f64>();
    vectors::<f32, 2>();
    vectors::<f32, 3>();
    vectors::<f32, 4>();
    vectors::<f64, 2>();
    vectors::<f64, 3>();
    vectors::<f64, 4>();
    vectors_fixed::<f32>();
    vectors_fixed::<f64>();
    quat::<f32>();
    quat::<f64>();
    glam_interop();
    graph();
    reduce();
    cells();
    block();
    errors();
}

/// An opaque value of type `T`.
#[inline(always)]
fn bb<T>(x: T) -> T {
    black_box(x)
}

/// Keeps `x` alive.
#[inline(always)]
fn keep<T>(x: T) {
    black_box(x);
}

/// An opaque scalar.
#[inline(always)]
fn r<T: Real>(x: f64) -> T {
    bb(T::from_f64(x))
}

/// An opaque `[T; D]`.
#[inline(always)]
fn v<T: Real, const D: usize>(x: f64) -> [T; D] {
    bb([T::from_f64(x); D])
}

#[inline(never)]
fn real<T: Real>() {
    let a: T = r(0.3);
    let b: T = r(-1.7);
    keep((T::ZERO, T::ONE, T::TWO, T::HALF, T::PI, T::EPSILON));
    keep((T::MIN_POSITIVE, T::MAX, T::INFINITY, T::MANTISSA_DIGITS));
    keep(T::from_f64(bb(0.1)));
    keep(a.to_f64());
    keep(T::from_u32(bb(7)));
    keep(T::from_usize(bb(7)));
    keep(a.to_bits_u64());
    keep(a.sqrt());
    keep(b.abs());
    keep(a.sin());
    keep(a.cos());
    keep(a.sin_cos());
    keep(a.tan());
    keep(a.asin());
    keep(a.acos());
    keep(a.atan());
    keep(a.atan2(b));
    keep(a.hypot(b));
    keep(a.exp());
    keep(a.ln());
    keep(a.powf(b));
    keep(b.floor());
    keep(a.copysign(b));
    keep(a.is_finite());
    keep(a.is_nan());
    keep(b.is_sign_negative());
    keep(Real::min(a, b));
    keep(Real::max(a, b));
    keep(a.clamp_to(b, T::ONE));
    keep(a.sq());
    keep(a + b - a * b / b);
    let mut c = a;
    c += b;
    c -= b;
    c *= b;
    c /= b;
    keep(-c);
    keep(a == b);
    keep(a < b);
    keep(a.partial_cmp(&b));
    keep(T::default());
    // Display and Debug of scalars are core's float formatting, not kernel code: not called.

    let (b1, b3, b4) = ([[T::ZERO]; 3], [[T::ZERO; 3]; 3], [[T::ZERO; 4]; 3]);
    let values1: &[[T; 1]] = bb(&b1);
    let values3: &[[T; 3]] = bb(&b3);
    let values4: &[[T; 4]] = bb(&b4);
    keep(all_finite(values1));
    keep(all_finite(values3));
    keep(all_finite(values4));
    keep(first_non_finite(values1));
    keep(first_non_finite(values3));
    keep(first_non_finite(values4));
}

#[inline(never)]
fn vectors<T: Real, const D: usize>() {
    let a: [T; D] = v(0.5);
    let b: [T; D] = v(-2.0);
    let s: T = r(1.5);
    keep(vector::add(a, b));
    keep(vector::sub(a, b));
    keep(vector::scale(a, s));
    keep(vector::dot(a, b));
    keep(vector::norm_sq(a));
    keep(vector::norm(a));
    keep(vector::norm_robust(a));
    keep(vector::distance(a, b));
    keep(vector::normalize(a));
    keep(vector::lerp(a, b, s));
}

#[inline(never)]
fn vectors_fixed<T: Real>() {
    let a3: [T; 3] = v(0.5);
    let b3: [T; 3] = v(-2.0);
    let a2: [T; 2] = v(0.5);
    let b2: [T; 2] = v(-2.0);
    keep(vector::cross(a3, b3));
    keep(vector::cross2(a2, b2));
    keep(vector::to_3d(a2));
    keep(vector::any_orthogonal(a3));
}

#[inline(never)]
fn quat<T: Real>() {
    let p = Quat::new(r::<T>(0.9), r(0.1), r(-0.3), r(0.2));
    let q = Quat::<T>::from_array(v(0.5));
    let s: T = r(0.25);
    let u: [T; 3] = v(0.6);
    let w: [T; 3] = bb([T::ZERO, T::ONE, T::ZERO]);
    let u2: [T; 2] = v(0.6);

    keep(Quat::<T>::identity());
    keep(Quat::from_scalar_vector(s, u));
    keep(p.to_array());
    keep(p.vector());
    keep(p.conjugate());
    keep(p.dot(q));
    keep(p.norm_sq());
    keep(p.norm());
    keep(p.is_finite());
    keep(p.scale(s));
    keep(p.normalize());
    #[cfg(feature = "micromath")]
    keep(p.normalize_fast());
    #[cfg(feature = "micromath")]
    keep(s.fast_inv_sqrt());
    keep(p.inverse());
    keep(Quat::from_axis_angle(u, s));
    keep(Quat::from_rotation_z(s));
    keep(p.angle());
    keep(p.to_axis_angle());
    keep(p.rotation_z_angle());
    keep(Quat::rotation_arc(u, w));
    keep(p.rotate(u));
    keep(p.rotate_2d(u2));
    keep(p.to_matrix());
    keep(Quat::nlerp(p, q, s));
    keep(Quat::slerp(p, q, s));
    keep(p + q);
    keep(p - q);
    keep(-p);
    keep(p * q);
    keep(p == q);
    keep(Quat::<T>::default());
    keep(p.clone());

    let mut avg = QuatAverage::<T>::new();
    avg.add(p, s);
    avg.add(q, s);
    keep(avg.total_weight());
    keep(avg.result());
    let mut avg = bb(QuatAverage::with_reference(q));
    avg.add(p, s);
    keep(avg.total_weight());
    keep(avg.result());
    keep(QuatAverage::<T>::default().result());
}

#[inline(never)]
fn glam_interop() {
    let d: glam::DQuat = bb(glam::DQuat::from_xyzw(0.1, 0.2, 0.3, 0.9));
    let f: glam::Quat = bb(glam::Quat::from_xyzw(0.1, 0.2, 0.3, 0.9));
    let qd: Quat<f64> = d.into();
    let qf: Quat<f32> = f.into();
    keep(qd);
    keep(qf);
    keep(glam::DQuat::from(bb(qd)));
    keep(glam::Quat::from(bb(qf)));
}

#[inline(never)]
fn graph() {
    let offsets: &[u32] = bb(&[0, 2, 4, 6]);
    let targets: &[u32] = bb(&[1, 2, 0, 2, 0, 1]);
    let i: usize = bb(1);
    let j: usize = bb(2);
    if let Ok(g) = bb(Graph::new(offsets, targets)) {
        let g = bb(g);
        keep(g.node_count());
        keep(g.edge_count());
        keep(g.offsets());
        keep(g.targets());
        keep(g.edge_range(i));
        keep(g.neighbors(i));
        for row in g.rows() {
            keep(row);
        }
        keep(g.find_edge(i, j));
        keep(g.check_symmetric());
        keep(g.clone());
    }
    // Also check a graph built from black-boxed parts without going through `new` first.
    keep(Graph::new(bb(&[]), bb(&[])));

    let edges: &[[u32; 2]] = bb(&[[0, 1], [1, 2], [2, 0], [1, 0]]);
    let n: usize = bb(3);
    let mut offsets_out = [0u32; 4];
    let mut targets_out = [0u32; 8];
    keep(graph_from_edges_len(edges));
    keep(graph_from_edges(
        n,
        edges,
        bb(&mut offsets_out[..]),
        bb(&mut targets_out[..]),
    ));
    keep(&offsets_out);
    keep(&targets_out);
}

#[inline(never)]
fn cells() {
    for kind in CellKind::ALL {
        let kind = bb(kind);
        keep(kind.vtk_code());
        keep(kind.node_count());
        keep(kind.dimension());
        keep(kind.edges());
        keep(kind.face_diagonals());
        keep(kind == CellKind::Quad);
        keep(kind.clone());
    }
    keep(CellKind::from_vtk(bb(12)));

    // A tetrahedron and a pyramid sharing a face, and a triangle.
    let offsets: &[u32] = bb(&[0, 4, 9, 12]);
    let nodes: &[u32] = bb(&[0, 1, 2, 3, 0, 1, 4, 5, 3, 1, 2, 3]);
    let kinds: &[u8] = bb(&[10, 14, 5]);
    let n: usize = bb(6);
    let c: usize = bb(1);
    let diagonals: bool = bb(true);
    if let Ok(cells) = bb(Cells::new(n, offsets, nodes, kinds)) {
        let cells = bb(cells);
        keep(cells.node_count());
        keep(cells.len());
        keep(cells.is_empty());
        keep(cells.offsets());
        keep(cells.nodes());
        keep(cells.kinds());
        keep(cells.cell(c));
        for cell in cells.iter() {
            keep(cell);
        }
        keep(cells.clone());

        let mut offsets_out = [0u32; 7];
        let mut targets_out = [0u32; 64];
        keep(graph_from_cells_len(&cells, diagonals));
        keep(graph_from_cells(
            &cells,
            diagonals,
            bb(&mut offsets_out[..]),
            bb(&mut targets_out[..]),
        ));
        keep(&offsets_out);
        keep(&targets_out);
    }
}

#[inline(never)]
fn block() {
    let dims: [usize; 3] = bb([4, 3, 2]);
    let (i, j, k): (usize, usize, usize) = bb((1, 2, 1));
    let direction = bb(Direction::J);
    if let Ok(b) = bb(Block::new(dims)) {
        let b = bb(b);
        keep(b.dims());
        keep(b.point_count());
        keep(b.rank());
        keep(b.index(i, j, k));
        keep(b.stride(direction));
        keep(Direction::from_index(bb(2)).map(Direction::index));
        let set = bb(Directions::only(direction).with(Direction::K));
        keep((set.contains(direction), set.flags(), set.bits()));
        keep(Directions::from_bits(bb(5)).map(|d| d.without(Direction::I)));
        keep(b.ijk(bb(17)));
        keep(b == b.clone());
    }
}

/// A `core::fmt::Write` sink that checksums what it is given.
struct Sink(u32);

impl Write for Sink {
    fn write_str(&mut self, s: &str) -> core::fmt::Result {
        for &byte in s.as_bytes() {
            self.0 = self.0.rotate_left(5) ^ u32::from(byte);
        }
        Ok(())
    }
}

#[inline(never)]
fn errors() {
    // `black_box` makes the value opaque, so every match arm of `Display` and `defmt::Format`
    // is live whatever variant goes in: new variants are covered without listing them here.
    let some = [
        Error::IndexOutOfRange {
            arg: "a",
            position: 1,
            index: 9,
            bound: 3,
        },
        Error::InvalidParameter {
            arg: "a",
            reason: "must be positive",
        },
        Error::SelfLoop { node: 1 },
    ];
    let mut sink = Sink(0);
    for e in bb(some) {
        let e = bb(e);
        keep(write!(sink, "{e}"));
        keep(e == Error::SelfLoop { node: 0 });
        keep(e.clone());
        keep(core::error::Error::source(&e));
        defmt::info!("{}", e);
    }
    keep(sink.0);
}

/// `reduce::ExactSum`: adds of any `f32`/`f64` (non-finite included), merges, the word
/// protocol, the in-place exchange and the rounding to either type.
fn reduce() {
    use deform_kernel::exact_sum::{ExactSum, EXACT_SUM_WORDS};
    let mut a = ExactSum::new();
    a.add(black_box(1.5f64));
    a.add(black_box(-2.5f32));
    a.add_f64(black_box(f64::MIN_POSITIVE));
    a.add_all(black_box(&[1.0f32, 2.0][..]));
    a.add_all(black_box(&[1.0f64, f64::NAN][..]));
    let mut b = black_box(ExactSum::default());
    b.merge(black_box(&a));
    let words: [i64; EXACT_SUM_WORDS] = black_box(b.to_words());
    let c = ExactSum::from_words(words);
    black_box(c.value::<f32>());
    black_box(c.value::<f64>());
    black_box(c == a);
    // The all-reduce protocol, with opaque words from "the other processes".
    let mut d = black_box(c);
    d.exchange(|w| *w = black_box(*w));
    black_box(d.value::<f64>());
}
