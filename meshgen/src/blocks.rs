//! Structured blocks: plain (optionally stretched) rectangles and boxes, noisy grids for the
//! smoothing demo, and cavity-like grids with abrupt stretching jumps (after Alter's RCC
//! cavity, where neighbouring cells differed by a factor of 3.25).
//!
//! Points are numbered `i + ni (j + nj k)`; cells are quads (2D) or hexes (3D); markers
//! `imin imax jmin jmax` (and `kmin kmax` in 3D) with outward-pointing element normals.

use deform_kernel::CellKind;

use crate::rng::XorShift64;
use crate::{invalid, stretched_fractions, Marker, Mesh2, Mesh3, Result};

/// Size and spacing of a structured block.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BlockSpec {
    /// Points per direction `[ni, nj, nk]` (each ≥ 2; `nk` ignored in 2D).
    pub dims: [usize; 3],
    /// Extent per direction; the block spans `[0, lengths[d]]`.
    pub lengths: [f64; 3],
    /// Ratio of consecutive cell sizes per direction (1 = uniform, 1.1 = 10% growth).
    pub ratios: [f64; 3],
}

impl BlockSpec {
    /// A uniform unit square/cube grid with `n` points per direction.
    pub fn uniform(n: usize) -> Self {
        BlockSpec {
            dims: [n, n, n],
            lengths: [1.0; 3],
            ratios: [1.0; 3],
        }
    }

    fn validate(&self, rank: usize) -> Result<()> {
        for d in 0..rank {
            if self.dims[d] < 2 {
                return invalid(format!("dims[{d}] must be >= 2"));
            }
            if !(self.lengths[d] > 0.0) || !self.lengths[d].is_finite() {
                return invalid(format!("lengths[{d}] must be positive and finite"));
            }
            if !(self.ratios[d] > 0.0) || !self.ratios[d].is_finite() {
                return invalid(format!("ratios[{d}] must be positive and finite"));
            }
        }
        let n = self.dims[..rank]
            .iter()
            .try_fold(1usize, |a, &b| a.checked_mul(b));
        if n.and_then(|n| u32::try_from(n).ok()).is_none() {
            return invalid("too many nodes for u32 indices");
        }
        Ok(())
    }

    fn coordinates(&self, d: usize) -> Vec<f64> {
        stretched_fractions(self.dims[d] - 1, self.ratios[d])
            .into_iter()
            .map(|f| f * self.lengths[d])
            .collect()
    }
}

/// Builds a 2D block from per-direction coordinate lists (tensor product).
fn tensor2(x: &[f64], y: &[f64]) -> Mesh2 {
    let (ni, nj) = (x.len(), y.len());
    let mut mesh = Mesh2::new();
    for &yj in y {
        for &xi in x {
            mesh.points.push([xi, yj]);
        }
    }
    let id = |i: usize, j: usize| (i + ni * j) as u32;
    for j in 0..nj - 1 {
        for i in 0..ni - 1 {
            mesh.push_cell(
                CellKind::Quad,
                &[id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)],
            );
        }
    }
    let mut m = [
        Marker::new("imin"),
        Marker::new("imax"),
        Marker::new("jmin"),
        Marker::new("jmax"),
    ];
    for j in 0..nj - 1 {
        m[0].push(CellKind::Line, &[id(0, j + 1), id(0, j)]);
        m[1].push(CellKind::Line, &[id(ni - 1, j), id(ni - 1, j + 1)]);
    }
    for i in 0..ni - 1 {
        m[2].push(CellKind::Line, &[id(i, 0), id(i + 1, 0)]);
        m[3].push(CellKind::Line, &[id(i + 1, nj - 1), id(i, nj - 1)]);
    }
    for mk in &mut m {
        mk.finish();
    }
    mesh.markers = m.into();
    mesh.dims = Some([ni, nj, 1]);
    mesh
}

/// Builds a 3D block from per-direction coordinate lists (tensor product).
fn tensor3(x: &[f64], y: &[f64], z: &[f64]) -> Mesh3 {
    let (ni, nj, nk) = (x.len(), y.len(), z.len());
    let mut mesh = Mesh3::new();
    for &zk in z {
        for &yj in y {
            for &xi in x {
                mesh.points.push([xi, yj, zk]);
            }
        }
    }
    let id = |i: usize, j: usize, k: usize| (i + ni * (j + nj * k)) as u32;
    for k in 0..nk - 1 {
        for j in 0..nj - 1 {
            for i in 0..ni - 1 {
                mesh.push_cell(
                    CellKind::Hexahedron,
                    &[
                        id(i, j, k),
                        id(i + 1, j, k),
                        id(i + 1, j + 1, k),
                        id(i, j + 1, k),
                        id(i, j, k + 1),
                        id(i + 1, j, k + 1),
                        id(i + 1, j + 1, k + 1),
                        id(i, j + 1, k + 1),
                    ],
                );
            }
        }
    }
    let mut m = [
        Marker::new("imin"),
        Marker::new("imax"),
        Marker::new("jmin"),
        Marker::new("jmax"),
        Marker::new("kmin"),
        Marker::new("kmax"),
    ];
    for k in 0..nk - 1 {
        for j in 0..nj - 1 {
            // Outward normal -x: (i,j,k) -> (i,j,k+1) -> (i,j+1,k+1) -> (i,j+1,k).
            m[0].push(
                CellKind::Quad,
                &[
                    id(0, j, k),
                    id(0, j, k + 1),
                    id(0, j + 1, k + 1),
                    id(0, j + 1, k),
                ],
            );
            let e = ni - 1;
            m[1].push(
                CellKind::Quad,
                &[
                    id(e, j, k),
                    id(e, j + 1, k),
                    id(e, j + 1, k + 1),
                    id(e, j, k + 1),
                ],
            );
        }
        for i in 0..ni - 1 {
            m[2].push(
                CellKind::Quad,
                &[
                    id(i, 0, k),
                    id(i + 1, 0, k),
                    id(i + 1, 0, k + 1),
                    id(i, 0, k + 1),
                ],
            );
            let e = nj - 1;
            m[3].push(
                CellKind::Quad,
                &[
                    id(i, e, k),
                    id(i, e, k + 1),
                    id(i + 1, e, k + 1),
                    id(i + 1, e, k),
                ],
            );
        }
    }
    for j in 0..nj - 1 {
        for i in 0..ni - 1 {
            m[4].push(
                CellKind::Quad,
                &[
                    id(i, j, 0),
                    id(i, j + 1, 0),
                    id(i + 1, j + 1, 0),
                    id(i + 1, j, 0),
                ],
            );
            let e = nk - 1;
            m[5].push(
                CellKind::Quad,
                &[
                    id(i, j, e),
                    id(i + 1, j, e),
                    id(i + 1, j + 1, e),
                    id(i, j + 1, e),
                ],
            );
        }
    }
    for mk in &mut m {
        mk.finish();
    }
    mesh.markers = m.into();
    mesh.dims = Some([ni, nj, nk]);
    mesh
}

/// A rectangle `[0, lx] × [0, ly]` of quads with geometric stretching per direction.
pub fn block2(spec: &BlockSpec) -> Result<Mesh2> {
    spec.validate(2)?;
    Ok(tensor2(&spec.coordinates(0), &spec.coordinates(1)))
}

/// A box `[0, lx] × [0, ly] × [0, lz]` of hexes with geometric stretching per direction.
pub fn block3(spec: &BlockSpec) -> Result<Mesh3> {
    spec.validate(3)?;
    Ok(tensor3(
        &spec.coordinates(0),
        &spec.coordinates(1),
        &spec.coordinates(2),
    ))
}

fn check_amplitude(amplitude: f64) -> Result<()> {
    if !(0.0..0.4).contains(&amplitude) {
        return invalid("amplitude must be in [0, 0.4) (fraction of the local spacing)");
    }
    Ok(())
}

/// Smallest spacing to a neighbour along each grid direction of point `(i, j[, k])`.
fn local_spacing(c: &[Vec<f64>], idx: &[usize]) -> f64 {
    let mut h = f64::INFINITY;
    for (coords, &i) in c.iter().zip(idx) {
        if i > 0 {
            h = h.min(coords[i] - coords[i - 1]);
        }
        if i + 1 < coords.len() {
            h = h.min(coords[i + 1] - coords[i]);
        }
    }
    h
}

/// [`block2`] with every interior point moved by a uniform random offset of at most
/// `amplitude` times its smallest neighbour spacing in each coordinate (boundary points stay
/// put). `amplitude < 0.4` keeps every cell positively oriented. Deterministic for a `seed`.
pub fn noisy_block2(spec: &BlockSpec, amplitude: f64, seed: u64) -> Result<Mesh2> {
    spec.validate(2)?;
    check_amplitude(amplitude)?;
    let c = [spec.coordinates(0), spec.coordinates(1)];
    let mut mesh = tensor2(&c[0], &c[1]);
    let (ni, nj) = (spec.dims[0], spec.dims[1]);
    let mut rng = XorShift64::new(seed);
    for j in 1..nj - 1 {
        for i in 1..ni - 1 {
            let h = local_spacing(&c, &[i, j]);
            let p = &mut mesh.points[i + ni * j];
            for x in p.iter_mut() {
                *x += amplitude * h * rng.symmetric();
            }
        }
    }
    Ok(mesh)
}

/// [`block3`] with interior points jittered as in [`noisy_block2`].
pub fn noisy_block3(spec: &BlockSpec, amplitude: f64, seed: u64) -> Result<Mesh3> {
    spec.validate(3)?;
    check_amplitude(amplitude)?;
    let c = [
        spec.coordinates(0),
        spec.coordinates(1),
        spec.coordinates(2),
    ];
    let mut mesh = tensor3(&c[0], &c[1], &c[2]);
    let [ni, nj, nk] = spec.dims;
    let mut rng = XorShift64::new(seed);
    for k in 1..nk - 1 {
        for j in 1..nj - 1 {
            for i in 1..ni - 1 {
                let h = local_spacing(&c, &[i, j, k]);
                let p = &mut mesh.points[i + ni * (j + nj * k)];
                for x in p.iter_mut() {
                    *x += amplitude * h * rng.symmetric();
                }
            }
        }
    }
    Ok(mesh)
}

/// Streamwise coordinates with two abrupt spacing jumps: cells in the first and last sixth are
/// `jump` times smaller than in the middle, so the stretching ratio jumps to `jump` twice.
fn jumpy(n_points: usize, length: f64, jump: f64) -> Vec<f64> {
    let cells = n_points - 1;
    let edge = (cells / 6).max(1);
    let mut x = vec![0.0];
    let mut s = 0.0;
    for c in 0..cells {
        let h = if c < edge || c >= cells - edge {
            1.0
        } else {
            jump
        };
        s += h;
        x.push(s);
    }
    x.into_iter().map(|v| v / s * length).collect()
}

fn check_cavity(ni: usize, nj: usize, jump: f64) -> Result<()> {
    if ni < 8 || nj < 2 {
        return invalid("a cavity grid needs ni >= 8 and nj >= 2");
    }
    if !(jump >= 1.0) || !jump.is_finite() {
        return invalid("jump must be finite and >= 1");
    }
    Ok(())
}

/// A cavity-like 2D grid on `[0, 4] × [0, 1]`: the `i` lines have abrupt spacing jumps of
/// factor `jump` (e.g. 3.25) near both ends; `j` grows geometrically (ratio 1.1) from the
/// floor. For stretching-reduction tests with normalised-arclength smoothing.
pub fn cavity2(ni: usize, nj: usize, jump: f64) -> Result<Mesh2> {
    check_cavity(ni, nj, jump)?;
    let spec = BlockSpec {
        dims: [ni, nj, 1],
        lengths: [4.0, 1.0, 1.0],
        ratios: [1.0, 1.1, 1.0],
    };
    spec.validate(2)?;
    Ok(tensor2(&jumpy(ni, 4.0, jump), &spec.coordinates(1)))
}

/// The 3D cavity: [`cavity2`]'s `i` and `j` distributions times a uniform `k` over `[0, 1]`.
pub fn cavity3(ni: usize, nj: usize, nk: usize, jump: f64) -> Result<Mesh3> {
    check_cavity(ni, nj, jump)?;
    let spec = BlockSpec {
        dims: [ni, nj, nk],
        lengths: [4.0, 1.0, 1.0],
        ratios: [1.0, 1.1, 1.0],
    };
    spec.validate(3)?;
    Ok(tensor3(
        &jumpy(ni, 4.0, jump),
        &spec.coordinates(1),
        &spec.coordinates(2),
    ))
}
