//! The kernel's `micromath` fast paths on target (hardware f32): the documented error bounds
//! of `Real::fast_inv_sqrt`, `Quat::normalize_fast` and `batina_stiffness_fast` hold on the
//! Cortex-M4F as on the host, f64 stays exact, and the exact routines are untouched (the golden
//! binary of this suite is built with the feature on). Speed: the DWT cycle counter is read
//! around both paths and printed when QEMU counts cycles (it does not emulate `CYCCNT`, which
//! then reads 0); timing is never asserted.
#![no_std]
#![no_main]

use deform_on_target as _;

use deform_golden::XorShift;
use deform_kernel::quat::NORMALIZE_FAST_F32_MAX_NORM_ERROR;
use deform_kernel::real::FAST_INV_SQRT_F32_MAX_REL_ERROR;
use deform_kernel::spring::{batina_stiffness, batina_stiffness_fast};
use deform_kernel::{Quat, Real};
use deform_on_target::mesh::{Mesh, NE};

fn rel_error(x: f32) -> f64 {
    let exact = 1.0 / (x as f64).sqrt();
    ((x.fast_inv_sqrt() as f64) - exact).abs() / exact
}

#[defmt_test::tests]
mod tests {
    use super::*;

    #[test]
    fn fast_inv_sqrt_bound() {
        // Every 101st f32 in [1, 4) (the error pattern's period), then a sweep of the normal
        // range.
        let mut worst = 0.0f64;
        let mut b = 1.0f32.to_bits();
        while b < 4.0f32.to_bits() {
            worst = worst.max(rel_error(f32::from_bits(b)));
            b += 101;
        }
        let mut b = f32::MIN_POSITIVE.to_bits();
        while b < f32::MAX.to_bits() {
            worst = worst.max(rel_error(f32::from_bits(b)));
            b += 65_537;
        }
        defmt::println!(
            "fast_inv_sqrt f32 on target: max relative error {=f64} (bound {=f64})",
            worst,
            FAST_INV_SQRT_F32_MAX_REL_ERROR
        );
        defmt::assert!(worst <= FAST_INV_SQRT_F32_MAX_REL_ERROR);
        defmt::assert!(worst >= 0.9 * FAST_INV_SQRT_F32_MAX_REL_ERROR);
        for x in [1e-300f64, 0.3, 2.0, 7.5e12] {
            defmt::assert!(x.fast_inv_sqrt() == 1.0 / x.sqrt());
        }
    }

    #[test]
    fn normalize_fast_bound() {
        let mut rng = XorShift::new(0xFA57_0002);
        let mut worst = 0.0f64;
        for _ in 0..20_000 {
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
            let n: f64 = f.to_array().iter().map(|&c| (c as f64) * (c as f64)).sum();
            worst = worst.max((n.sqrt() - 1.0).abs());
            for (a, b) in f.to_array().into_iter().zip(e.to_array()) {
                defmt::assert!(((a - b) as f64).abs() <= 2.0 * NORMALIZE_FAST_F32_MAX_NORM_ERROR);
            }
        }
        defmt::println!(
            "normalize_fast f32 on target: max | |q| - 1 | {=f64} (bound {=f64})",
            worst,
            NORMALIZE_FAST_F32_MAX_NORM_ERROR
        );
        defmt::assert!(worst <= NORMALIZE_FAST_F32_MAX_NORM_ERROR);
        let zero = Quat::<f32>::new(0.0, 0.0, 0.0, 0.0);
        defmt::assert!(zero.normalize_fast() == zero.normalize());
    }

    #[test]
    fn batina_stiffness_fast_bound_and_symmetry() {
        let m = Mesh::<f32>::new(0.25);
        let g = m.graph();
        let mut exact = [0f32; NE];
        let mut fast = [0f32; NE];
        batina_stiffness(&g, &m.points, 1.0, &mut exact[..m.used]).unwrap();
        batina_stiffness_fast(&g, &m.points, 1.0, &mut fast[..m.used]).unwrap();
        let mut worst = 0.0f64;
        for (a, b) in fast.iter().zip(&exact).take(m.used) {
            worst = worst.max(((a - b) as f64).abs() / (*b as f64));
        }
        defmt::println!(
            "batina_stiffness_fast f32 on target: max relative difference {=f64}",
            worst
        );
        defmt::assert!(worst <= FAST_INV_SQRT_F32_MAX_REL_ERROR + 1.2e-7);
        for (i, first, row) in g.rows() {
            for (o, &j) in row.iter().enumerate() {
                let back = g.find_edge(j as usize, i).unwrap();
                defmt::assert!(fast[first + o].to_bits() == fast[back].to_bits());
            }
        }
        let m64 = Mesh::<f64>::new(0.25);
        let mut e64 = [0f64; NE];
        let mut f64s = [0f64; NE];
        batina_stiffness(&g, &m64.points, 1.0, &mut e64[..m.used]).unwrap();
        batina_stiffness_fast(&g, &m64.points, 1.0, &mut f64s[..m.used]).unwrap();
        defmt::assert!(e64 == f64s);
    }

    #[test]
    fn cycles_if_counted() {
        let Some(mut p) = cortex_m::Peripherals::take() else {
            return;
        };
        p.DCB.enable_trace();
        p.DWT.enable_cycle_counter();
        let xs: [f32; 64] = core::array::from_fn(|i| 0.5 + i as f32 * 0.37);
        let c0 = cortex_m::peripheral::DWT::cycle_count();
        let mut s = 0.0f32;
        for &x in &xs {
            s += core::hint::black_box(x).fast_inv_sqrt();
        }
        let c1 = cortex_m::peripheral::DWT::cycle_count();
        for &x in &xs {
            s += 1.0 / core::hint::black_box(x).sqrt();
        }
        let c2 = cortex_m::peripheral::DWT::cycle_count();
        defmt::assert!(s.is_finite());
        if c1 == c0 && c2 == c1 {
            defmt::println!("DWT CYCCNT does not count under this emulator: no cycle figures");
        } else {
            defmt::println!(
                "64 x fast_inv_sqrt: {=u32} cycles; 64 x 1/sqrtf (libm): {=u32} cycles",
                c1.wrapping_sub(c0),
                c2.wrapping_sub(c1)
            );
        }
    }
}
