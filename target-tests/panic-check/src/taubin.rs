//! Panic-check calls for the kernel's Taubin / Alter entry points: parameters, the structured
//! filter and sweep, the coarse-grid variant, the graph filter, sweep and weights, the line
//! tools and the whole-grid driver.
//!
//! Every input is black-boxed and every output is black-boxed. Generic items are instantiated
//! for `f32` and `f64`; point-generic ones for `D` = 2 and 3; the graph filter for `V` = 1, 3
//! and 4.

use core::hint::black_box;
use deform_kernel::Direction;
use deform_kernel::Directions;

use deform_kernel::taubin::{
    arclength, check_lines_increasing, coarse_dims, graph_scratch_len, graph_sweep,
    inverse_distance_weights, max_stretching, mu_from_pass_band, redistribute,
    redistribute_scratch_len, smooth_arclength, smooth_arclength_scratch_len, smooth_graph,
    smooth_structured, smooth_structured_coarse, stretching, structured_coarse_scratch_len,
    structured_scratch_len, structured_sweep, BlockRegion, Coarse, GraphOptions, LineEnd,
    Prolongation, SmoothOptions, StructuredOptions, TaubinParams,
};
use deform_kernel::{Block, Graph, Real};

/// Points in the test block (`4 × 3 × 2`), with room to spare.
const N: usize = 24;
/// Scratch size, larger than any query for this block.
const S: usize = 256;

/// Calls every Taubin entry point with opaque inputs.
pub fn exercise() {
    params::<f32>();
    params::<f64>();
    structured::<f32>();
    structured::<f64>();
    graph::<f32, 1>();
    graph::<f32, 3>();
    graph::<f64, 3>();
    graph::<f64, 4>();
    lines::<f32, 2>();
    lines::<f32, 3>();
    lines::<f64, 2>();
    lines::<f64, 3>();
    driver::<f32, 2>();
    driver::<f32, 3>();
    driver::<f64, 2>();
    driver::<f64, 3>();
}

/// An opaque value.
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

/// An opaque block (its dimensions are black-boxed, so `new` is checked too).
#[inline(always)]
fn block() -> Option<Block> {
    match Block::new(bb([4, 3, 2])) {
        Ok(b) => Some(bb(b)),
        Err(e) => {
            keep(e);
            None
        }
    }
}

#[inline(never)]
fn params<T: Real>() {
    let p = TaubinParams::<T>::paper();
    keep(p);
    keep(TaubinParams::<T>::default());
    keep(TaubinParams::from_pass_band(r::<T>(0.33), r(0.1)));
    keep(mu_from_pass_band(r::<T>(0.33), r(0.1)));
    let q = bb(TaubinParams {
        lambda: r::<T>(0.5),
        mu: r(-0.6),
    });
    keep(q.validate());
    keep(q.transfer(r(0.7)));
    keep(q.pass_band());
    keep(
        bb(TaubinParams {
            lambda: r::<T>(0.5),
            mu: T::ZERO,
        })
        .pass_band(),
    );
}

#[inline(never)]
fn structured<T: Real>() {
    let Some(b) = block() else { return };
    let mut field = [T::ZERO; N];
    for (i, x) in field.iter_mut().enumerate() {
        *x = T::from_usize(i);
    }
    let mut field = bb(field);
    let mut scratch = bb([T::ZERO; S]);
    let pins: &[u8] = bb(&[0u8; N]);
    let opts = bb(StructuredOptions {
        fixed: Some(pins),
        mirror: bb(Directions::from_flags([true, false, true])),
    });
    let params = bb(TaubinParams::<T>::paper());
    let iterations: usize = bb(3);
    keep(structured_scratch_len(&b));
    keep(smooth_structured(
        &b,
        &mut field[..],
        params,
        iterations,
        &opts,
        &mut scratch[..],
    ));
    keep(&field);

    let src = bb(field);
    let mut dst = bb([T::ZERO; N]);
    let region = bb(BlockRegion {
        lo: bb([0, 1, 0]),
        hi: bb([4, 3, 2]),
    });
    keep(BlockRegion::all(&b));
    keep(structured_sweep(
        &b,
        &src[..],
        &mut dst[..],
        r(0.33),
        &opts,
        &region,
    ));
    keep(&dst);

    let coarse = bb(Coarse {
        factor: bb([2, 2, 1]),
        prolongation: bb(Prolongation::Correction),
    });
    keep(coarse_dims(&b, coarse.factor));
    keep(structured_coarse_scratch_len(&b, &coarse));
    keep(smooth_structured_coarse(
        &b,
        &mut field[..],
        &coarse,
        params,
        iterations,
        &opts,
        &mut scratch[..],
    ));
    let values_coarse = bb(Coarse {
        factor: bb([3, 1, 2]),
        prolongation: Prolongation::Values,
    });
    keep(smooth_structured_coarse(
        &b,
        &mut field[..],
        &values_coarse,
        params,
        iterations,
        &StructuredOptions::default(),
        &mut scratch[..],
    ));
    keep(&field);
}

#[inline(never)]
fn graph<T: Real, const V: usize>() {
    let offsets: &[u32] = bb(&[0, 2, 4, 6]);
    let targets: &[u32] = bb(&[1, 2, 0, 2, 0, 1]);
    let Ok(g) = Graph::new(offsets, targets) else {
        return;
    };
    let g = bb(g);
    let mut values = bb([[T::ZERO; V]; 3]);
    for (i, v) in values.iter_mut().enumerate() {
        *v = [T::from_usize(i); V];
    }
    let points: [[T; 3]; 3] = bb([[T::ZERO; 3], [T::ONE; 3], [T::TWO; 3]]);
    let mut weights = bb([T::ONE; 6]);
    keep(inverse_distance_weights(&g, &points[..], &mut weights[..]));
    let fixed: &[u8] = bb(&[1, 0, 0]);
    let opts = bb(GraphOptions {
        weights: Some(&weights[..]),
        fixed: Some(fixed),
    });
    let mut scratch = bb([[T::ZERO; V]; 3]);
    keep(graph_scratch_len(&g));
    keep(smooth_graph(
        &g,
        &mut values[..],
        bb(TaubinParams::paper()),
        bb(4),
        &opts,
        &mut scratch[..],
    ));
    keep(smooth_graph(
        &g,
        &mut values[..],
        bb(TaubinParams::paper()),
        bb(2),
        &GraphOptions::default(),
        &mut scratch[..],
    ));
    let src = bb(values);
    let mut dst = bb([[T::ZERO; V]; 3]);
    let lo: usize = bb(1);
    let hi: usize = bb(3);
    keep(graph_sweep(
        &g,
        &src[..],
        &mut dst[..],
        r(-0.34),
        &opts,
        lo..hi,
    ));
    keep(&values);
    keep(&dst);
}

/// Opaque points of the test block.
#[inline(always)]
fn points<T: Real, const D: usize>() -> [[T; D]; N] {
    let mut p = [[T::ZERO; D]; N];
    for (i, x) in p.iter_mut().enumerate() {
        for (c, v) in x.iter_mut().enumerate() {
            *v = T::from_usize(i * (c + 1) % 7);
        }
    }
    bb(p)
}

#[inline(never)]
fn lines<T: Real, const D: usize>() {
    let Some(b) = block() else { return };
    let pts = points::<T, D>();
    let dir = bb(Direction::J);
    let mut out = bb([T::ZERO; N]);
    keep(arclength(&b, &pts[..], dir, bb(true), &mut out[..]));
    keep(arclength(
        &b,
        &pts[..],
        bb(Direction::K),
        bb(false),
        &mut out[..],
    ));
    keep(check_lines_increasing(
        &b,
        &out[..],
        dir,
        bb(5),
        Some(&pts[..]),
    ));
    keep(check_lines_increasing::<T, D>(
        &b,
        &out[..],
        dir,
        bb(5),
        None,
    ));
    let mut moved = bb(pts);
    let mut scratch = bb([T::ZERO; S]);
    keep(redistribute_scratch_len::<D>(&b, dir));
    keep(redistribute(
        &b,
        &mut moved[..],
        dir,
        &out[..],
        bb(false),
        &mut scratch[..],
    ));
    keep(redistribute(
        &b,
        &mut moved[..],
        bb(Direction::I),
        &out[..],
        bb(true),
        &mut scratch[..],
    ));
    keep(&moved);
    let mut st = bb([T::ZERO; N]);
    keep(stretching(&b, &pts[..], dir, &mut st[..]));
    keep(&st);
    keep(max_stretching(&b, &pts[..], bb(Direction::I)));
}

#[inline(never)]
fn driver<T: Real, const D: usize>() {
    let Some(b) = block() else { return };
    let mut pts = points::<T, D>();
    let pins: &[u8] = bb(&[0u8; N]);
    let mut opts = SmoothOptions::<T>::new(bb(Direction::K));
    opts.normalised = bb(true);
    opts.fixed = Some(pins);
    opts.mirror = bb(Directions::from_flags([true, true, false]));
    opts.iterations = bb(3);
    opts.coarse = bb(Some(Coarse {
        factor: bb([2, 2, 1]),
        prolongation: bb(Prolongation::Values),
    }));
    opts.coarse_iterations = bb(2);
    opts.ends = bb([LineEnd::Fixed, LineEnd::Free]);
    let opts = bb(opts);
    let mut scratch = bb([T::ZERO; S]);
    keep(smooth_arclength_scratch_len::<D>(
        &b,
        opts.direction,
        opts.coarse.as_ref(),
    ));
    keep(smooth_arclength(&b, &mut pts[..], &opts, &mut scratch[..]));
    keep(smooth_arclength(
        &b,
        &mut pts[..],
        &bb(SmoothOptions::new(bb(Direction::I))),
        &mut scratch[..],
    ));
    keep(&pts);
}
