//! The derivative of the assembled elasticity stiffness with respect to the node
//! coordinates, applied to a fixed displacement `u`: forward `r = (∂K/∂x · δx) u` and
//! reverse `∇ₓ (λᵀ K(x) u)`, element by element from the Gauss points of the assembly.
//!
//! At a Gauss point with gradients `G_a = ∇N_a` and weight `w = ω |det J|`, write
//! `A = Σ_a λ_a ⊗ G_a`, `B = Σ_a u_a ⊗ G_a`, `L = Σ_a δx_a ⊗ G_a` and the stress
//! `S(B) = λ_L tr(B) I + μ (B + Bᵀ)`. Then `λᵀ K_e u = Σ_g w A : S(B)` and, with
//! `δG_a = −Lᵀ G_a` (that is `δA = −A L`) and `δw = w tr L`,
//!
//! ```text
//! r_a    = Σ_g w [tr(L) S(B) − S(B) Lᵀ − S(B L)] G_a + ε_c (K_e u)_a
//! ∇_b    = Σ_g w [φ I − Aᵀ S(B) − Bᵀ S(A)] G_b + κ_c Σ_g w G_b,     φ = A : S(B)
//! ```
//!
//! where `ε_c = δE_c / E_c` and `κ_c` carry the modulus's dependence on the cell volumes
//! ([`Modulus::InverseVolume`]: `E_c = V̄ / V_c`, so `ε_c = δV/V − δV_c/V_c` over the total
//! volume `V`, and `κ_c = Φ/V − φ_c/V_c` with `Φ = Σ_c φ_c`). The other moduli do not depend
//! on the moved mesh (the wall distances are those of the reference mesh).

use crate::cells::{CellKind, Cells};
use crate::elasticity::element::{gauss_point, lame, point_count, GaussPoint, MAX_NODES};
use crate::elasticity::Modulus;
use crate::real::Real;

/// A `D×D` matrix, row-major.
type Mat<T, const D: usize> = [[T; D]; D];

/// What one cell gives the forward pass: `Σ_g w [...] G_a` (geometry), `K_e u` and
/// `(V_c, δV_c)`.
struct Forward<T, const D: usize> {
    geometry: [[T; D]; MAX_NODES],
    force: [[T; D]; MAX_NODES],
    volume: [T; 2],
}

/// What one cell gives the reverse pass: `Σ_g w P G_b`, `Σ_g w G_b`, `φ_c` and `V_c`.
struct Reverse<T, const D: usize> {
    geometry: [[T; D]; MAX_NODES],
    volume_gradient: [[T; D]; MAX_NODES],
    phi: T,
    volume: T,
}

#[inline]
fn get<T: Real, const D: usize>(m: &Mat<T, D>, i: usize, j: usize) -> T {
    m.get(i).and_then(|r| r.get(j)).copied().unwrap_or(T::ZERO)
}

/// `Σ_a f_a ⊗ G_a` over the cell's nodes.
fn gradient<T: Real, const D: usize>(f: &[[T; D]], p: &GaussPoint<T, D>) -> Mat<T, D> {
    let mut m = [[T::ZERO; D]; D];
    for (fa, ga) in f.iter().zip(&p.grads) {
        for (row, &fi) in m.iter_mut().zip(fa) {
            for (e, &gj) in row.iter_mut().zip(ga) {
                *e += fi * gj;
            }
        }
    }
    m
}

fn trace<T: Real, const D: usize>(m: &Mat<T, D>) -> T {
    (0..D).fold(T::ZERO, |s, i| s + get(m, i, i))
}

/// `λ_L tr(B) I + μ (B + Bᵀ)`.
fn stress<T: Real, const D: usize>(b: &Mat<T, D>, lambda: T, mu: T) -> Mat<T, D> {
    let t = lambda * trace(b);
    let mut s = [[T::ZERO; D]; D];
    for (i, row) in s.iter_mut().enumerate() {
        for (j, e) in row.iter_mut().enumerate() {
            *e = mu * (get(b, i, j) + get(b, j, i));
            if i == j {
                *e += t;
            }
        }
    }
    s
}

/// `a b` (`ta`: `aᵀ b`; `tb`: `a bᵀ`).
fn mul<T: Real, const D: usize>(a: &Mat<T, D>, b: &Mat<T, D>, ta: bool, tb: bool) -> Mat<T, D> {
    let mut m = [[T::ZERO; D]; D];
    for (i, row) in m.iter_mut().enumerate() {
        for (j, e) in row.iter_mut().enumerate() {
            for k in 0..D {
                let x = if ta { get(a, k, i) } else { get(a, i, k) };
                let y = if tb { get(b, j, k) } else { get(b, k, j) };
                *e += x * y;
            }
        }
    }
    m
}

fn frobenius<T: Real, const D: usize>(a: &Mat<T, D>, b: &Mat<T, D>) -> T {
    a.iter()
        .flatten()
        .zip(b.iter().flatten())
        .fold(T::ZERO, |s, (&x, &y)| s + x * y)
}

/// `out_a += w m G_a` for the cell's `n` nodes.
fn add_mat_grads<T: Real, const D: usize>(
    out: &mut [[T; D]; MAX_NODES],
    m: &Mat<T, D>,
    p: &GaussPoint<T, D>,
    n: usize,
) {
    for (o, ga) in out.iter_mut().zip(&p.grads).take(n) {
        for (oi, row) in o.iter_mut().zip(m) {
            *oi += p.weight * crate::vector::dot(*row, *ga);
        }
    }
}

/// The forward pieces of one cell with nodes `x`, perturbation `dx`, displacement `u`.
fn cell_forward<T: Real, const D: usize>(
    kind: CellKind,
    [x, dx, u]: [&[[T; D]]; 3],
    lambda: T,
    mu: T,
) -> Option<Forward<T, D>> {
    let n = x.len().min(MAX_NODES);
    let mut f = Forward {
        geometry: [[T::ZERO; D]; MAX_NODES],
        force: [[T::ZERO; D]; MAX_NODES],
        volume: [T::ZERO; 2],
    };
    for g in 0..point_count(kind) {
        let p = gauss_point(kind, x, g)?;
        let (l, b) = (gradient(dx, &p), gradient(u, &p));
        let s = stress(&b, lambda, mu);
        let tl = trace(&l);
        let sl = mul(&s, &l, false, true);
        let sbl = stress(&mul(&b, &l, false, false), lambda, mu);
        let mut m = s;
        for (i, row) in m.iter_mut().enumerate() {
            for (j, e) in row.iter_mut().enumerate() {
                *e = tl * *e - get(&sl, i, j) - get(&sbl, i, j);
            }
        }
        add_mat_grads(&mut f.geometry, &m, &p, n);
        add_mat_grads(&mut f.force, &s, &p, n);
        f.volume[0] += p.weight;
        f.volume[1] += p.weight * tl;
    }
    Some(f)
}

/// The reverse pieces of one cell with nodes `x`, adjoint `lam`, displacement `u`.
fn cell_reverse<T: Real, const D: usize>(
    kind: CellKind,
    [x, lam, u]: [&[[T; D]]; 3],
    lambda: T,
    mu: T,
) -> Option<Reverse<T, D>> {
    let n = x.len().min(MAX_NODES);
    let mut r = Reverse {
        geometry: [[T::ZERO; D]; MAX_NODES],
        volume_gradient: [[T::ZERO; D]; MAX_NODES],
        phi: T::ZERO,
        volume: T::ZERO,
    };
    let mut identity = [[T::ZERO; D]; D];
    for (i, row) in identity.iter_mut().enumerate() {
        if let Some(e) = row.get_mut(i) {
            *e = T::ONE;
        }
    }
    for g in 0..point_count(kind) {
        let p = gauss_point(kind, x, g)?;
        let (a, b) = (gradient(lam, &p), gradient(u, &p));
        let (sa, sb) = (stress(&a, lambda, mu), stress(&b, lambda, mu));
        let phi = frobenius(&a, &sb);
        let (asb, bsa) = (mul(&a, &sb, true, false), mul(&b, &sa, true, false));
        let mut m = [[T::ZERO; D]; D];
        for (i, row) in m.iter_mut().enumerate() {
            for (j, e) in row.iter_mut().enumerate() {
                *e = phi * get(&identity, i, j) - get(&asb, i, j) - get(&bsa, i, j);
            }
        }
        add_mat_grads(&mut r.geometry, &m, &p, n);
        add_mat_grads(&mut r.volume_gradient, &identity, &p, n);
        r.phi += p.weight * phi;
        r.volume += p.weight;
    }
    Some(r)
}

/// The cell's node values of a field.
fn gather<T: Real, const D: usize>(nodes: &[u32], f: &[[T; D]]) -> [[T; D]; MAX_NODES] {
    let mut x = [[T::ZERO; D]; MAX_NODES];
    for (x, &n) in x.iter_mut().zip(nodes) {
        *x = f.get(n as usize).copied().unwrap_or([T::ZERO; D]);
    }
    x
}

/// `out[nodes[a]] += scale · v[a]`.
fn scatter<T: Real, const D: usize>(
    nodes: &[u32],
    v: &[[T; D]; MAX_NODES],
    scale: T,
    out: &mut [[T; D]],
) {
    for (&n, va) in nodes.iter().zip(v) {
        if let Some(o) = out.get_mut(n as usize) {
            *o = crate::vector::add(*o, crate::vector::scale(*va, scale));
        }
    }
}

/// The mesh the stiffness was assembled on, with its moduli and Poisson ratio.
pub(super) struct Stiffness<'a, T, const D: usize> {
    pub cells: &'a Cells<'a>,
    pub points: &'a [[T; D]],
    pub moduli: &'a [T],
    pub poisson: T,
    pub modulus: Modulus,
}

/// One cell's pieces from its kind, its node values of `[x, a, u]` and its Lamé parameters.
type CellFn<T, const D: usize, R> = fn(CellKind, [&[[T; D]]; 3], T, T) -> Option<R>;

impl<T: Real, const D: usize> Stiffness<'_, T, D> {
    /// Calls `f(nodes, cell(kind, [x, a, u], λ, μ))` for every cell in order; `false` when a
    /// cell is degenerate (the assembly on the same mesh has already rejected that).
    fn sweep<R>(
        &self,
        [a, u]: [&[[T; D]]; 2],
        cell: CellFn<T, D, R>,
        mut f: impl FnMut(&[u32], R),
    ) -> bool {
        for ((kind, nodes), &e) in self.cells.iter().zip(self.moduli) {
            let (lambda, mu) = lame(e, self.poisson);
            let k = nodes.len();
            let (x, av, uv) = (
                gather(nodes, self.points),
                gather(nodes, a),
                gather(nodes, u),
            );
            let (Some(x), Some(av), Some(uv)) = (x.get(..k), av.get(..k), uv.get(..k)) else {
                return false;
            };
            match cell(kind, [x, av, uv], lambda, mu) {
                Some(r) => f(nodes, r),
                None => return false,
            }
        }
        true
    }

    /// `out += (∂K/∂x · dx) u` at every node; `false` (after a partial update) when a cell is
    /// degenerate.
    pub fn forward(&self, dx: &[[T; D]], u: &[[T; D]], out: &mut [[T; D]]) -> bool {
        let volumes = matches!(self.modulus, Modulus::InverseVolume);
        let mut total = [T::ZERO; 2];
        if volumes
            && !self.sweep([dx, u], cell_forward, |_, f| {
                total = [total[0] + f.volume[0], total[1] + f.volume[1]];
            })
        {
            return false;
        }
        self.sweep([dx, u], cell_forward, |nodes, f| {
            scatter(nodes, &f.geometry, T::ONE, out);
            if volumes {
                let eps = total[1] / total[0] - f.volume[1] / f.volume[0];
                scatter(nodes, &f.force, eps, out);
            }
        })
    }

    /// `out += ∇ₓ (λᵀ K(x) u)` at every node; `false` (after a partial update) when a cell is
    /// degenerate.
    pub fn reverse(&self, lam: &[[T; D]], u: &[[T; D]], out: &mut [[T; D]]) -> bool {
        let volumes = matches!(self.modulus, Modulus::InverseVolume);
        let (mut phi, mut total) = (T::ZERO, T::ZERO);
        if volumes
            && !self.sweep([lam, u], cell_reverse, |_, r| {
                phi += r.phi;
                total += r.volume;
            })
        {
            return false;
        }
        self.sweep([lam, u], cell_reverse, |nodes, r| {
            scatter(nodes, &r.geometry, T::ONE, out);
            if volumes {
                let kappa = phi / total - r.phi / r.volume;
                scatter(nodes, &r.volume_gradient, kappa, out);
            }
        })
    }
}
