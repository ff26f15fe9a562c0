//! Tangent and adjoint of [`tfi_block`](super::tfi_block), the TFI of `deform move` on a
//! Plot3D block, with respect to the positions of the wall face's nodes (the opposite face
//! stays, as in the move).
//!
//! The displacement TFI is linear in the wall's displacement: its tangent is the same
//! blend of the perturbation (`displacement_tfi`), its adjoint the kernel's transposed blend
//! (`deform_tfi_adjoint` with identity rotations held, which is `R = r + Σ w (d − u)`).
//! The quaternion TFI is differentiated with the rotations of both faces taken from their
//! shape (the kernel's `RotationSource::Shape`: segments in 2D, quadrilaterals in 3D): for
//! the rigid motions `deform move` makes, the shape gives back the motion's own rotation, so
//! this is `deform move`'s map along every rigid motion of the wall, and a function of the
//! wall's positions alone for any other perturbation. The origin is the move's: `--center`,
//! else the wall face's centroid.

use deform_kernel::quaternion::{
    deform_tfi_adjoint, deform_tfi_sensitivity_scratch_len, deform_tfi_tangent, displacement_tfi,
    tfi_scratch_len, BoundaryMotion, RotationSource,
};
use deform_kernel::{Block, Directions, Quat};

use super::{cells_view, kernel, points_d, Face, Motion, TfiFaces, WallMotion};
use crate::error::CliError;
use crate::formats::CellList;

/// The tangent `δR` of `tfi_block(dim, dims, points, wall, motion, quaternion)` at every
/// block point for the change `direction` of the wall face's nodes (one per block point; only
/// the wall's entries are read). Components past `dim` are zero.
pub fn tfi_block_tangent(
    dim: usize,
    dims: [usize; 3],
    points: &[[f64; 3]],
    wall: Face,
    motion: &Motion,
    quaternion: bool,
    direction: &[[f64; 3]],
) -> Result<Vec<[f64; 3]>, CliError> {
    match dim {
        2 => Point::<2>::new(dims, points, wall, motion, quaternion)?.tangent(direction),
        3 => Point::<3>::new(dims, points, wall, motion, quaternion)?.tangent(direction),
        d => Err(CliError::Invalid(format!("dimension {d} is not 2 or 3"))),
    }
}

/// The adjoint `(∂R/∂d)ᵀ w` of the same map for the weights `w = dJ/dR` (one per block
/// point): `dJ/dd` at the wall face's nodes, zero at every other point.
pub fn tfi_block_adjoint(
    dim: usize,
    dims: [usize; 3],
    points: &[[f64; 3]],
    wall: Face,
    motion: &Motion,
    quaternion: bool,
    weights: &[[f64; 3]],
) -> Result<Vec<[f64; 3]>, CliError> {
    match dim {
        2 => Point::<2>::new(dims, points, wall, motion, quaternion)?.adjoint(weights),
        3 => Point::<3>::new(dims, points, wall, motion, quaternion)?.adjoint(weights),
        d => Err(CliError::Invalid(format!("dimension {d} is not 2 or 3"))),
    }
}

/// The linearisation point of one block: the undeformed points, the listed nodes (wall, then
/// the opposite face) at their moved positions, the faces' cells in that numbering.
struct Point<const D: usize> {
    block: Block,
    directions: Directions,
    pts: Vec<[f64; D]>,
    nodes: Vec<u32>,
    wall_len: usize,
    deformed: Vec<[f64; D]>,
    elements: CellList,
    origin: [f64; D],
    quaternion: bool,
}

impl<const D: usize> Point<D> {
    fn new(
        dims: [usize; 3],
        points: &[[f64; 3]],
        wall: Face,
        motion: &Motion,
        quaternion: bool,
    ) -> Result<Self, CliError> {
        let block = Block::new(dims).map_err(kernel("block"))?;
        let pts = points_d::<D>(points);
        let faces = TfiFaces::new(&block, wall);
        let rigid = WallMotion::new(motion, points, &faces.wall)?;
        let nodes: Vec<u32> = faces.wall.iter().chain(&faces.far).copied().collect();
        let wall_len = faces.wall.len();
        let deformed = (nodes.iter().enumerate())
            .map(|(k, &p)| match k < wall_len {
                true => rigid.apply(points[p as usize]),
                false => pts[p as usize],
            })
            .collect();
        let elements = face_cells(&block, wall, &nodes, D)?;
        Ok(Point {
            block,
            directions: Directions::only(wall.direction),
            pts,
            nodes,
            wall_len,
            deformed,
            elements,
            origin: core::array::from_fn(|k| rigid.center[k]),
            quaternion,
        })
    }

    /// The kernel's motion: shape rotations (quaternion TFI) or identity rotations held.
    fn run<R>(
        &self,
        f: impl FnOnce(&BoundaryMotion<'_, f64, D>) -> Result<R, CliError>,
    ) -> Result<R, CliError> {
        let identity = vec![Quat::identity(); self.nodes.len()];
        let m = BoundaryMotion {
            nodes: &self.nodes,
            deformed: &self.deformed,
            elements: Some(cells_view(&self.elements, self.nodes.len())?),
            rotations: match self.quaternion {
                true => RotationSource::Shape,
                false => RotationSource::PerNode(&identity),
            },
            origin: Some(self.origin),
        };
        f(&m)
    }

    fn tangent(&self, direction: &[[f64; 3]]) -> Result<Vec<[f64; 3]>, CliError> {
        let n = self.pts.len();
        let at = |p: usize| -> [f64; D] {
            let v = direction.get(p).copied().unwrap_or([0.0; 3]);
            core::array::from_fn(|c| v[c])
        };
        let mut out = vec![[0.0; D]; n];
        if self.quaternion {
            let dir: Vec<[f64; D]> = (self.nodes.iter().enumerate())
                .map(|(k, &p)| {
                    if k < self.wall_len {
                        at(p as usize)
                    } else {
                        [0.0; D]
                    }
                })
                .collect();
            let len = deform_tfi_sensitivity_scratch_len::<D>(&self.block, self.nodes.len());
            let mut scratch = vec![0.0; len];
            self.run(|m| {
                deform_tfi_tangent(
                    &self.block,
                    self.directions,
                    &self.pts,
                    m,
                    &dir,
                    &mut scratch,
                    &mut out,
                )
                .map_err(kernel("quaternion TFI tangent"))
            })?;
        } else {
            // `deform move`'s own blend of the displacements, here of the perturbation.
            for &p in &self.nodes[..self.wall_len] {
                out[p as usize] = at(p as usize);
            }
            let mut scratch = vec![0.0; tfi_scratch_len::<D>(&self.block)];
            displacement_tfi(
                &self.block,
                self.directions,
                &self.pts,
                &mut out,
                &mut scratch,
            )
            .map_err(kernel("displacement TFI tangent"))?;
        }
        Ok(widen(&out))
    }

    fn adjoint(&self, weights: &[[f64; 3]]) -> Result<Vec<[f64; 3]>, CliError> {
        let n = self.pts.len();
        let w = points_d::<D>(weights);
        let mut back = vec![[0.0; D]; self.nodes.len()];
        let len = deform_tfi_sensitivity_scratch_len::<D>(&self.block, self.nodes.len());
        let mut scratch = vec![0.0; len];
        self.run(|m| {
            deform_tfi_adjoint(
                &self.block,
                self.directions,
                &self.pts,
                m,
                &w,
                &mut scratch,
                &mut back,
            )
            .map_err(kernel("TFI adjoint"))
        })?;
        let mut g = vec![[0.0; D]; n];
        for (&p, b) in self.nodes.iter().zip(&back).take(self.wall_len) {
            g[p as usize] = *b;
        }
        Ok(widen(&g))
    }
}

/// `[f64; D]` rows as `[f64; 3]` (zero past `D`).
fn widen<const D: usize>(v: &[[f64; D]]) -> Vec<[f64; 3]> {
    v.iter()
        .map(|x| core::array::from_fn(|c| x.get(c).copied().unwrap_or(0.0)))
        .collect()
}

/// The cells of the listed faces (`nodes`: the wall's nodes, then the opposite face's) in the
/// numbering of `nodes`: segments along the face in 2D, quadrilaterals in 3D (the shape
/// rotations' elements). Both faces list their cells the same way round, so their normals
/// turn with the grid.
fn face_cells(block: &Block, wall: Face, nodes: &[u32], dim: usize) -> Result<CellList, CliError> {
    let dims = block.dims();
    let mut local = vec![u32::MAX; block.point_count()];
    for (k, &p) in nodes.iter().enumerate() {
        local[p as usize] = k as u32;
    }
    let normal = wall.direction.index();
    let along: Vec<usize> = (0..dim).filter(|&d| d != normal).collect();
    let stride = |d: usize| dims[..d].iter().product::<usize>();
    let mut cells = CellList::new();
    for &p in nodes {
        let c = block.ijk(p as usize);
        if along.iter().any(|&d| c[d] + 1 >= dims[d]) {
            continue;
        }
        let p = p as usize;
        let corners: Vec<usize> = match along[..] {
            [a] => vec![p, p + stride(a)],
            [a, b] => {
                let (sa, sb) = (stride(a), stride(b));
                vec![p, p + sa, p + sa + sb, p + sb]
            }
            _ => return Err(CliError::Invalid(format!("dimension {dim} is not 2 or 3"))),
        };
        let ids: Vec<u32> = corners.iter().map(|&q| local[q]).collect();
        // VTK line (3) in 2D, quadrilateral (9) in 3D.
        let code = if ids.len() == 2 { 3 } else { 9 };
        if !cells.push_code(code, &ids) {
            return Err(CliError::Invalid("too many face cells".into()));
        }
    }
    Ok(cells)
}

/// The points (ascending) of a `dims` block on its `wall` face: the nodes
/// [`tfi_block_tangent`] perturbs and [`tfi_block_adjoint`] writes.
pub fn tfi_wall_nodes(dims: [usize; 3], wall: Face) -> Result<Vec<u32>, CliError> {
    let block = Block::new(dims).map_err(kernel("block"))?;
    Ok(TfiFaces::new(&block, wall).wall)
}
