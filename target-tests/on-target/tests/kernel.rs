//! The kernel's foundation on target, in f32 and f64: quaternion algebra and the graph and
//! cell builders behave as on the host (exact results where the algebra is exact, tight
//! tolerances elsewhere, typed errors for bad input).
#![no_std]
#![no_main]

use deform_on_target as _;

use deform_kernel::{Error, Quat, QuatAverage, Real};

/// Quaternion algebra identities in precision `T`.
fn quat_algebra<T: Real>() {
    let tol = T::EPSILON * T::from_f64(16.0);
    let q = Quat::from_axis_angle([T::ONE, T::TWO, T::from_f64(-0.5)], T::from_f64(0.7)).unwrap();
    defmt::assert!((q.norm() - T::ONE).abs() <= tol);
    let v = [T::from_f64(0.3), T::from_f64(-1.2), T::from_f64(2.5)];
    let r = q.rotate(v);
    let len = |a: [T; 3]| (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
    defmt::assert!((len(r) - len(v)).abs() <= tol * T::from_f64(4.0));
    let back = q.conjugate().rotate(r);
    for k in 0..3 {
        defmt::assert!((back[k] - v[k]).abs() <= tol * T::from_f64(4.0));
    }
    let one = q * q.inverse().unwrap();
    defmt::assert!((one.w - T::ONE).abs() <= tol);
    let arc = Quat::rotation_arc([T::ONE, T::ZERO, T::ZERO], [T::ZERO, T::ZERO, -T::ONE]).unwrap();
    let x = arc.rotate([T::ONE, T::ZERO, T::ZERO]);
    defmt::assert!((x[2] + T::ONE).abs() <= tol);
    let mut avg = QuatAverage::new();
    avg.add(q, T::ONE);
    avg.add(-q, T::TWO);
    let a = avg.result().unwrap();
    defmt::assert!((a.dot(q).abs() - T::ONE).abs() <= tol);
    defmt::assert!(matches!(
        Quat::<T>::new(T::ZERO, T::ZERO, T::ZERO, T::ZERO).normalize(),
        Err(Error::ZeroLength { .. })
    ));
}

#[defmt_test::tests]
mod tests {
    use super::quat_algebra;
    use deform_kernel::{
        graph_from_cells, graph_from_cells_len, graph_from_edges, Cells, Error, Graph,
    };

    #[test]
    fn quaternion_algebra_f64() {
        quat_algebra::<f64>();
    }

    #[test]
    fn quaternion_algebra_f32() {
        quat_algebra::<f32>();
    }

    #[test]
    fn graph_builders() {
        let offsets = [0u32, 4, 8];
        let nodes = [0u32, 1, 4, 3, 1, 2, 5, 4];
        let kinds = [9u8, 9];
        let cells = Cells::new(6, &offsets, &nodes, &kinds).unwrap();
        let mut g_offsets = [0u32; 7];
        let mut targets = [0u32; 32];
        defmt::assert!(graph_from_cells_len(&cells, true) <= targets.len());
        let used = graph_from_cells(&cells, true, &mut g_offsets, &mut targets).unwrap();
        let g = Graph::new(&g_offsets, &targets[..used]).unwrap();
        g.check_symmetric().unwrap();
        defmt::assert_eq!(g.neighbors(4), &[0, 1, 2, 3, 5]);
        let edges = [[0u32, 1], [1, 2], [2, 0], [1, 0]];
        let mut o = [9u32; 4];
        let mut t = [9u32; 8];
        let before = (o, t);
        defmt::assert!(matches!(
            graph_from_edges(2, &edges, &mut o, &mut t),
            Err(Error::LengthMismatch { .. }) | Err(Error::IndexOutOfRange { .. })
        ));
        defmt::assert_eq!((o, t), before);
        defmt::assert_eq!(graph_from_edges(3, &edges, &mut o, &mut t).unwrap(), 6);
        defmt::assert_eq!(o, [0, 2, 4, 6]);
    }

    /// Exact sums give the host's bits: cancellation across 600 binades, order and split
    /// independence, and the word protocol ranks merge with.
    #[test]
    fn exact_sums_are_order_independent() {
        use deform_kernel::exact_sum::ExactSum;
        let terms = [1e300, 1.0, -1e300, 0.1, 1e-300, -0.3, 2.5e-320, 0.2];
        let mut a = ExactSum::new();
        a.add_all(&terms);
        let mut b = ExactSum::new();
        for &t in terms.iter().rev() {
            b.add(t);
        }
        defmt::assert_eq!(a.value::<f64>().to_bits(), b.value::<f64>().to_bits());
        // The exact sum is 1 + 2.8e-17 (the binary 0.1 + 0.2 − 0.3 and the tiny terms): 1.0
        // rounded once (Python: float(sum(map(Fraction, terms)))).
        defmt::assert_eq!(a.value::<f64>().to_bits(), 0x3ff0_0000_0000_0000);
        let (lo, hi) = terms.split_at(3);
        let mut x = ExactSum::new();
        x.add_all(hi);
        let mut y = ExactSum::new();
        y.add_all(lo);
        let mut words = x.to_words();
        for (w, v) in words.iter_mut().zip(y.to_words()) {
            *w += v;
        }
        defmt::assert_eq!(
            ExactSum::from_words(words).value::<f64>().to_bits(),
            a.value::<f64>().to_bits()
        );
        let mut f = ExactSum::new();
        f.add_all(&[3.0e38f32, 1.0, -3.0e38]);
        defmt::assert_eq!(f.value::<f32>(), 1.0);
    }
}
