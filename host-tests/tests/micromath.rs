//! The kernel's `micromath` fast paths against the exact ones, over many inputs: the measured
//! error bounds the documentation states hold, the fast paths are used by nothing else (the
//! exact routines and golden bits are unchanged), and f64 is exact. Needs
//! `--features deform-kernel/micromath`.

use deform_golden::XorShift;
use deform_kernel::quat::NORMALIZE_FAST_F32_MAX_NORM_ERROR;
use deform_kernel::real::FAST_INV_SQRT_F32_MAX_REL_ERROR;
use deform_kernel::spring::{batina_stiffness, batina_stiffness_fast};
use deform_kernel::{graph_from_edges, Graph, Quat, Real};

fn rel_error(x: f32) -> f64 {
    let exact = 1.0 / (x as f64).sqrt();
    ((x.fast_inv_sqrt() as f64) - exact).abs() / exact
}

#[test]
fn fast_inv_sqrt_bound_holds_for_every_f32_in_two_binades_and_is_tight() {
    let worst = (1.0f32.to_bits()..4.0f32.to_bits())
        .map(|b| rel_error(f32::from_bits(b)))
        .fold(0.0, f64::max);
    println!("fast_inv_sqrt f32: max relative error over [1, 4) = {worst:.4e}");
    assert!(worst <= FAST_INV_SQRT_F32_MAX_REL_ERROR);
    assert!(worst >= 0.9 * FAST_INV_SQRT_F32_MAX_REL_ERROR);
}

#[test]
fn fast_inv_sqrt_bound_holds_across_the_normal_range() {
    let mut worst = 0.0f64;
    let mut b = f32::MIN_POSITIVE.to_bits();
    while b < f32::MAX.to_bits() {
        worst = worst.max(rel_error(f32::from_bits(b)));
        b += 997;
    }
    println!("fast_inv_sqrt f32: max relative error over the normal range = {worst:.4e}");
    assert!(worst <= FAST_INV_SQRT_F32_MAX_REL_ERROR);
}

#[test]
fn fast_inv_sqrt_f64_is_the_exact_one() {
    let mut rng = XorShift::new(0xFA57_0001);
    for _ in 0..100_000 {
        let x = (rng.unit_f64() * 40.0 - 20.0).exp();
        assert_eq!(x.fast_inv_sqrt().to_bits(), (1.0 / x.sqrt()).to_bits());
    }
}

#[test]
fn normalize_fast_norm_error_bound() {
    let mut rng = XorShift::new(0xFA57_0002);
    let mut worst = 0.0f64;
    let mut worst_exact = 0.0f64;
    for _ in 0..1_000_000 {
        let scale = 10f64.powf(rng.unit_f64() * 6.0 - 3.0);
        let q: Quat<f32> = Quat::new(
            rng.uniform(-scale, scale),
            rng.uniform(-scale, scale),
            rng.uniform(-scale, scale),
            rng.uniform(-scale, scale),
        );
        let (Ok(f), Ok(e)) = (q.normalize_fast(), q.normalize()) else {
            continue;
        };
        let norm = |p: Quat<f32>| {
            (p.to_array()
                .iter()
                .map(|&c| (c as f64).powi(2))
                .sum::<f64>())
            .sqrt()
        };
        worst = worst.max((norm(f) - 1.0).abs());
        worst_exact = worst_exact.max((norm(e) - 1.0).abs());
        // Same direction as the exact result, to the same relative accuracy.
        for (a, b) in f.to_array().into_iter().zip(e.to_array()) {
            assert!(((a - b) as f64).abs() <= 2.0 * NORMALIZE_FAST_F32_MAX_NORM_ERROR);
        }
    }
    println!(
        "normalize_fast f32: max | |q| - 1 | = {worst:.4e} (exact normalize: {worst_exact:.4e})"
    );
    assert!(worst <= NORMALIZE_FAST_F32_MAX_NORM_ERROR);
    // Errors and the exact fallback behave as `normalize`.
    let zero = Quat::<f32>::new(0.0, 0.0, 0.0, 0.0);
    assert_eq!(zero.normalize_fast(), zero.normalize());
    let huge = Quat::<f32>::new(3e30, -2e30, 1e30, 0.0);
    assert_eq!(huge.normalize_fast(), huge.normalize());
    let nan = Quat::<f32>::new(f32::NAN, 0.0, 0.0, 0.0);
    assert_eq!(nan.normalize_fast(), nan.normalize());
    // f64: identical to the exact path's scaling by 1/sqrt.
    let q = Quat::<f64>::new(0.3, -1.2, 2.5, 0.7);
    let f = q.normalize_fast().unwrap();
    assert!((f.norm() - 1.0).abs() <= 4.0 * f64::EPSILON);
}

#[test]
fn batina_stiffness_fast_within_the_bound_and_symmetric() {
    // A random point cloud with a ring of edges plus chords.
    const N: usize = 400;
    let mut rng = XorShift::new(0xFA57_0003);
    let points: Vec<[f32; 2]> = (0..N)
        .map(|_| [rng.uniform(-50.0, 50.0), rng.uniform(-50.0, 50.0)])
        .collect();
    let edges: Vec<[u32; 2]> = (0..N as u32)
        .flat_map(|i| [[i, (i + 1) % N as u32], [i, (i + 37) % N as u32]])
        .collect();
    let mut offsets = vec![0u32; N + 1];
    let mut targets = vec![0u32; 4 * edges.len()];
    let used = graph_from_edges(N, &edges, &mut offsets, &mut targets).unwrap();
    let g = Graph::new(&offsets, &targets[..used]).unwrap();
    let mut exact = vec![0f32; used];
    let mut fast = vec![0f32; used];
    batina_stiffness(&g, &points, 1.0, &mut exact).unwrap();
    batina_stiffness_fast(&g, &points, 1.0, &mut fast).unwrap();
    let mut worst = 0.0f64;
    for (a, b) in fast.iter().zip(&exact) {
        worst = worst.max(((a - b) as f64).abs() / (*b as f64));
    }
    println!("batina_stiffness_fast f32 (p = 1): max relative difference {worst:.4e}");
    // The exact k is itself rounded (1/sqrt: up to ~1 ulp), so allow one f32 ulp on top.
    assert!(worst <= FAST_INV_SQRT_F32_MAX_REL_ERROR + 1.2e-7);
    for (i, first, row) in g.rows() {
        for (o, &j) in row.iter().enumerate() {
            let back = g.find_edge(j as usize, i).unwrap();
            assert_eq!(fast[first + o].to_bits(), fast[back].to_bits());
        }
    }
    // Other exponents are the exact formulas.
    for p in [0.0f32, 2.0, 1.5] {
        batina_stiffness(&g, &points, p, &mut exact).unwrap();
        batina_stiffness_fast(&g, &points, p, &mut fast).unwrap();
        assert_eq!(exact, fast);
    }
    // f64: identical.
    let p64: Vec<[f64; 2]> = points.iter().map(|p| [p[0] as f64, p[1] as f64]).collect();
    let mut e64 = vec![0f64; used];
    let mut f64s = vec![0f64; used];
    batina_stiffness(&g, &p64, 1.0, &mut e64).unwrap();
    batina_stiffness_fast(&g, &p64, 1.0, &mut f64s).unwrap();
    assert_eq!(e64, f64s);
    // Same errors.
    let mut dup = points.clone();
    dup[1] = dup[0];
    assert_eq!(
        batina_stiffness(&g, &dup, 1.0, &mut exact),
        batina_stiffness_fast(&g, &dup, 1.0, &mut fast)
    );
}
