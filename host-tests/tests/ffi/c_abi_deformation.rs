//! The deformation C ABI seen from C and Fortran: compiles `ffi/examples/deform_and_smooth.{c,f90}`
//! and `ffi/tests/deformation.c` against the static and the shared library, runs them, and
//! compares the examples' printed bit patterns with the Rust API computing the same thing (the
//! same O-grid, generated here with the same operations). The bad-input checks live in
//! `deformation.c`: this crate forbids `unsafe`, so it cannot call the extern functions itself.
//! Needs `gcc` and `gfortran` on PATH.

#[path = "../support/mod.rs"]
mod support;

use deform_kernel::Direction;
use deform_kernel::Directions;
use support::c_build::*;

use deform_kernel::quaternion::{
    deform_idw, deform_idw_scratch_len, deform_spring, deform_spring_scratch_len, deform_tfi,
    deform_tfi_scratch_len, propagate_spring_scratch_len, BoundaryMotion, RotationSource,
};
use deform_kernel::spring::{
    batina_stiffness, LinearMethod, Preconditioner, SolveOptions, SpringSystem,
};
use deform_kernel::taubin::{smooth_arclength, smooth_arclength_scratch_len, SmoothOptions};
use deform_kernel::{graph_from_cells, graph_from_cells_len, Block, Cells, Graph, Quat, Real};

const NI: usize = 24;
const NJ: usize = 12;
const N: usize = NI * NJ;
const NB: usize = 2 * NI;

/// The example's O-grid (see `make_grid` in deform_and_smooth.c), same operations in the same
/// order.
fn grid() -> Vec<[f64; 2]> {
    let m = NI / 4;
    let mut p = vec![[0.0; 2]; N];
    for j in 0..NJ {
        let f = j as f64 / (NJ - 1) as f64;
        let s = f * f;
        for i in 0..NI {
            let t = (i % m) as f64 / m as f64;
            let c = (1.0 - t * t) / (1.0 + t * t);
            let d = (2.0 * t) / (1.0 + t * t);
            let (cx, cy) = match i / m {
                0 => (c, d),
                1 => (-d, c),
                2 => (-c, -d),
                _ => (d, -c),
            };
            let (wx, wy) = (cx, 0.4 * cy);
            let (fx, fy) = (8.0 * cx, 8.0 * cy);
            p[i + NI * j] = [wx + s * (fx - wx), wy + s * (fy - wy)];
        }
    }
    p
}

/// Everything the example builds before deforming: the boundary, its segments, the motion
/// data, the cells and the fixed mask.
struct Setup {
    points: Vec<[f64; 2]>,
    nodes: Vec<u32>,
    element_offsets: Vec<u32>,
    element_nodes: Vec<u32>,
    element_kinds: Vec<u8>,
    deformed: Vec<[f64; 2]>,
    node_rot: Vec<Quat<f64>>,
    cell_offsets: Vec<u32>,
    cell_nodes: Vec<u32>,
    cell_kinds: Vec<u8>,
    fixed: Vec<u8>,
}

fn setup() -> Setup {
    let points = grid();
    let mut nodes = vec![0u32; NB];
    for k in 0..NI {
        nodes[k] = k as u32;
        nodes[NI + k] = (NI * (NJ - 1) + k) as u32;
    }
    let mut element_offsets = vec![0u32; NB + 1];
    let mut element_nodes = vec![0u32; 2 * NB];
    for k in 0..NB {
        let lp = k / NI * NI;
        element_offsets[k] = (2 * k) as u32;
        element_nodes[2 * k] = k as u32;
        element_nodes[2 * k + 1] = (lp + (k + 1) % NI) as u32;
    }
    element_offsets[NB] = (2 * NB) as u32;
    let q = Quat::from_axis_angle([0.0, 0.0, 1.0], 0.15).unwrap();
    let qn = q.normalize().unwrap();
    let (pivot, shift) = ([0.25, 0.0], [0.05, 0.1]);
    let mut deformed = vec![[0.0; 2]; NB];
    let mut node_rot = vec![Quat::identity(); NB];
    for k in 0..NI {
        let p = points[k];
        let r = qn.rotate([p[0] - pivot[0], p[1] - pivot[1], 0.0]);
        deformed[k] = [(r[0] + pivot[0]) + shift[0], (r[1] + pivot[1]) + shift[1]];
        deformed[NI + k] = points[nodes[NI + k] as usize];
        node_rot[k] = q;
        node_rot[NI + k] = Quat::new(1.0, 0.0, 0.0, 0.0);
    }
    let nc = NI * (NJ - 1);
    let mut cell_offsets = vec![0u32; nc + 1];
    let mut cell_nodes = vec![0u32; 4 * nc];
    for k in 0..nc {
        let (i, j) = (k % NI, k / NI);
        cell_offsets[k] = (4 * k) as u32;
        cell_nodes[4 * k..4 * k + 4].copy_from_slice(&[
            (i + NI * j) as u32,
            ((i + 1) % NI + NI * j) as u32,
            ((i + 1) % NI + NI * (j + 1)) as u32,
            (i + NI * (j + 1)) as u32,
        ]);
    }
    cell_offsets[nc] = (4 * nc) as u32;
    let mut fixed = vec![0u8; N];
    for &n in &nodes {
        fixed[n as usize] = 1;
    }
    Setup {
        points,
        nodes,
        element_offsets,
        element_nodes,
        element_kinds: vec![3; NB],
        deformed,
        node_rot,
        cell_offsets,
        cell_nodes,
        cell_kinds: vec![9; nc],
        fixed,
    }
}

fn flat<T: Copy, const D: usize>(v: &[[T; D]]) -> Vec<T> {
    v.iter().flatten().copied().collect()
}

/// The three pipelines and the smoothing in precision `T`, as the example runs them. Returns
/// `(idw origin, idw, tfi, spring origin, spring, smoothed tfi, smoothing iterations,
/// spring converged)`.
#[allow(clippy::type_complexity)]
fn pipelines<T: Real>(
    s: &Setup,
    conv: impl Fn(f64) -> T,
) -> (
    [T; 2],
    Vec<[T; 2]>,
    Vec<[T; 2]>,
    [T; 2],
    Vec<[T; 2]>,
    Vec<[T; 2]>,
    usize,
    bool,
) {
    let points: Vec<[T; 2]> = s.points.iter().map(|p| p.map(&conv)).collect();
    let deformed: Vec<[T; 2]> = s.deformed.iter().map(|p| p.map(&conv)).collect();
    let node_rot: Vec<Quat<T>> = s
        .node_rot
        .iter()
        .map(|q| Quat::from_array(q.to_array().map(&conv)))
        .collect();
    let elements = Cells::new(NB, &s.element_offsets, &s.element_nodes, &s.element_kinds).unwrap();
    let mut motion = BoundaryMotion {
        nodes: &s.nodes,
        deformed: &deformed,
        elements: Some(elements),
        rotations: RotationSource::Shape,
        origin: None,
    };
    let mut t = vec![[T::ZERO; 2]; N];
    let mut r = vec![Quat::identity(); N];
    let mut scratch = vec![T::ZERO; deform_idw_scratch_len::<2>(N, NB)];
    let mut idw = vec![[T::ZERO; 2]; N];
    let idw_origin = deform_idw(
        &points,
        &motion,
        conv(3.0),
        &mut t,
        &mut r,
        &mut scratch,
        &mut idw,
    )
    .unwrap();

    let block = Block::new([NI, NJ, 1]).unwrap();
    motion.rotations = RotationSource::PerNode(&node_rot);
    motion.origin = Some([conv(0.25), conv(0.0)]);
    let mut scratch = vec![T::ZERO; deform_tfi_scratch_len::<2>(&block, NB)];
    let mut tfi = vec![[T::ZERO; 2]; N];
    deform_tfi(
        &block,
        Directions::from_flags([false, true, false]),
        &points,
        &motion,
        &mut t,
        &mut r,
        &mut scratch,
        &mut tfi,
    )
    .unwrap();

    let cells = Cells::new(N, &s.cell_offsets, &s.cell_nodes, &s.cell_kinds).unwrap();
    let mut offsets = vec![0u32; N + 1];
    let mut targets = vec![0u32; graph_from_cells_len(&cells, false)];
    let used = graph_from_cells(&cells, false, &mut offsets, &mut targets).unwrap();
    let g = Graph::new(&offsets, &targets[..used]).unwrap();
    let mut k = vec![T::ZERO; used];
    batina_stiffness(&g, &points, T::ONE, &mut k).unwrap();
    let mut sys_scratch = vec![0u32; N];
    let sys = SpringSystem::new(g, &k, &s.fixed, &mut sys_scratch).unwrap();
    motion.rotations = RotationSource::Shape;
    motion.origin = None;
    let method = LinearMethod::Cg {
        preconditioner: Preconditioner::Jacobi,
    };
    let mut scratch = vec![T::ZERO; deform_spring_scratch_len::<2>(N, NB)];
    let mut values = vec![T::ZERO; propagate_spring_scratch_len::<2>(&method, N)];
    let mut spring = vec![[T::ZERO; 2]; N];
    let (spring_origin, report) = deform_spring(
        &points,
        &motion,
        &sys,
        method,
        &SolveOptions::default(),
        &mut t,
        &mut r,
        &mut scratch,
        &mut values,
        &mut spring,
    )
    .unwrap();

    let mut smoothed = tfi.clone();
    let opts = SmoothOptions {
        normalised: true,
        iterations: 10,
        ..SmoothOptions::new(Direction::J)
    };
    let mut scratch = vec![T::ZERO; smooth_arclength_scratch_len::<2>(&block, Direction::J, None)];
    let rep = smooth_arclength(&block, &mut smoothed, &opts, &mut scratch).unwrap();
    (
        idw_origin,
        idw,
        tfi,
        spring_origin,
        spring,
        smoothed,
        rep.iterations,
        report.converged,
    )
}

/// What `ffi/examples/deform_and_smooth.{c,f90}` must print, computed with the Rust API.
fn expected_deform_and_smooth() -> String {
    let s = setup();
    let (o, idw, tfi, so, spring, smoothed, its, conv) = pipelines::<f64>(&s, |x| x);
    let mut out = String::new();
    out += &hex64("idw_origin", &o);
    out += &hex64("idw", &flat(&idw));
    out += &hex64("tfi", &flat(&tfi));
    out += &hex64("spring_origin", &so);
    out += &hex64("spring", &flat(&spring));
    out += &format!("spring_converged {}\n", u8::from(conv));
    out += &hex64("smoothed", &flat(&smoothed));
    out += &format!("smooth_iterations {its}\n");
    let (_, idw, tfi, _, spring, smoothed, _, _) = pipelines::<f32>(&s, |x| x as f32);
    out += &hex32("idw_f32", &flat(&idw));
    out += &hex32("tfi_f32", &flat(&tfi));
    out += &hex32("smoothed_f32", &flat(&smoothed));
    out += &hex32("spring_f32", &flat(&spring));
    out
}

fn c_flag_refs(flags: &[String]) -> Vec<&str> {
    flags.iter().map(String::as_str).collect()
}

#[test]
fn c_example_matches_rust_bit_for_bit() {
    let src = workspace().join("ffi/examples/deform_and_smooth.c");
    let flags = c_flags();
    let expected = expected_deform_and_smooth();
    for (link, name) in [
        (Link::Static, "deform_and_smooth_c_static"),
        (Link::Shared, "deform_and_smooth_c_shared"),
    ] {
        let exe = tmp(name);
        compile(
            "gcc",
            std::slice::from_ref(&src),
            &c_flag_refs(&flags),
            link,
            &exe,
        );
        let got = run(&exe);
        assert!(got == expected, "{name}: output differs from the Rust API");
    }
}

#[test]
fn fortran_example_matches_rust_bit_for_bit() {
    let module = workspace().join("ffi/generated/deform_kernel.f90");
    let src = workspace().join("ffi/examples/deform_and_smooth.f90");
    let expected = expected_deform_and_smooth();
    for (link, name) in [
        (Link::Static, "deform_and_smooth_f_static"),
        (Link::Shared, "deform_and_smooth_f_shared"),
    ] {
        let moddir = tmp(&format!("{name}_mod"));
        std::fs::create_dir_all(&moddir).unwrap();
        let jflag = format!("-J{}", moddir.display());
        let exe = tmp(name);
        compile(
            "gfortran",
            &[module.clone(), src.clone()],
            &["-std=f2008", "-Wall", "-Werror", &jflag],
            link,
            &exe,
        );
        let got = run(&exe);
        assert!(got == expected, "{name}: output differs from the Rust API");
    }
}

#[test]
fn deformation_c_checks_hold() {
    let src = workspace().join("ffi/tests/deformation.c");
    let flags = c_flags();
    for (link, name) in [
        (Link::Static, "deformation_c_static"),
        (Link::Shared, "deformation_c_shared"),
    ] {
        let exe = tmp(name);
        compile(
            "gcc",
            std::slice::from_ref(&src),
            &c_flag_refs(&flags),
            link,
            &exe,
        );
        assert_eq!(run(&exe), "deformation: every check held\n", "{name}");
    }
}
