//! Linear elasticity on target, in f32 and f64, on the small jittered triangle mesh: the
//! cell-pair graph, inverse-volume moduli, the assembly, the patch test (a linear field on
//! the perimeter reproduced inside) with block-Jacobi CG, and two load increments that end
//! exactly on the prescribed perimeter; bad input gives typed errors with buffers untouched.
#![no_std]
#![no_main]

use deform_on_target as _;

use deform_kernel::elasticity::{
    assemble, cell_moduli, deform_incremental, elasticity_graph, ElasticSystem, IncrementBuffers,
    Increments, Modulus,
};
use deform_kernel::spring::SolveOptions;
use deform_kernel::{Error, Graph, Real};
use deform_on_target::mesh::{Mesh, N, NE, NT};

/// The linear field `(0.1 x − 0.05 y + 0.01, 0.03 x + 0.07 y)`.
fn field<T: Real>(p: [T; 2]) -> [T; 2] {
    let f = T::from_f64;
    [
        f(0.1) * p[0] - f(0.05) * p[1] + f(0.01),
        f(0.03) * p[0] + f(0.07) * p[1],
    ]
}

fn elasticity<T: Real>() {
    let m = Mesh::<T>::new(0.25);
    let cells = m.cells();
    let (mut go, mut gt) = ([0u32; N + 1], [0u32; NE]);
    let used = elasticity_graph(&cells, &mut go, &mut gt).unwrap();
    let g = Graph::new(&go, &gt[..used]).unwrap();
    let mut e = [T::ZERO; NT];
    cell_moduli(&cells, &m.points, Modulus::InverseVolume, None, &mut e).unwrap();
    let (mut diag, mut off) = ([[[T::ZERO; 2]; 2]; N], [[[T::ZERO; 2]; 2]; NE]);
    let off = &mut off[..used];
    // A Poisson ratio of 1/2 is refused with every block untouched.
    defmt::assert!(matches!(
        assemble(&cells, &m.points, &g, &e, T::HALF, &mut diag, off),
        Err(Error::InvalidParameter { arg: "poisson", .. })
    ));
    defmt::assert!(diag.iter().flatten().flatten().all(|&x| x == T::ZERO));
    // Patch test with uniform moduli.
    let one = [T::ONE; NT];
    assemble(
        &cells,
        &m.points,
        &g,
        &one,
        T::from_f64(0.3),
        &mut diag,
        off,
    )
    .unwrap();
    let sys = ElasticSystem::new(g, &diag, off, &m.fixed).unwrap();
    let mut u = [[T::ZERO; 2]; N];
    for (i, u) in u.iter_mut().enumerate() {
        if m.fixed[i] != 0 {
            *u = field(m.points[i]);
        }
    }
    let mut cg = [[T::ZERO; 2]; 4 * N];
    let options = SolveOptions::<T>::default();
    defmt::assert!(sys.solve(&mut u, &options, &mut cg).unwrap().converged);
    let tol = T::from_f64(if T::MANTISSA_DIGITS == 24 { 1e-4 } else { 1e-9 });
    for (p, u) in m.points.iter().zip(&u) {
        let w = field(*p);
        defmt::assert!((w[0] - u[0]).abs() <= tol && (w[1] - u[1]).abs() <= tol);
    }
    // Two increments of a shear of the perimeter: it ends exactly there.
    let mut disp = [[T::ZERO; 2]; N];
    for (d, p) in disp.iter_mut().zip(&m.points) {
        *d = [T::from_f64(0.2) * p[1], T::ZERO];
    }
    let mut points = m.points;
    let (mut cur, mut step) = ([[T::ZERO; 2]; N], [[T::ZERO; 2]; N]);
    let buffers = IncrementBuffers {
        moduli: &mut e,
        diag: &mut diag,
        off,
        current: &mut cur,
        step: &mut step,
    };
    let params = Increments {
        modulus: Modulus::InverseVolume,
        wall_distance: None,
        poisson: T::from_f64(0.3),
        steps: 2,
    };
    let r = deform_incremental(
        &cells,
        &g,
        &m.fixed,
        &params,
        &mut points,
        &disp,
        buffers,
        |s, u| s.solve(u, &options, &mut cg),
    )
    .unwrap();
    defmt::assert!(r.converged && r.steps == 2);
    for i in 0..N {
        if m.fixed[i] != 0 {
            defmt::assert!(points[i][0] == m.points[i][0] + disp[i][0]);
            defmt::assert!(points[i][1] == m.points[i][1]);
        }
    }
}

#[defmt_test::tests]
mod tests {
    use super::*;

    #[test]
    fn elasticity_f64_f32() {
        elasticity::<f64>();
        elasticity::<f32>();
    }
}
