//! `--method rbf` of `deform adjoint` and `deform tangent`: the RBF deformation (`deform move
//! --method rbf` with the --rbf-* options; every marker's nodes are the boundary) through the
//! kernel's `rbf_tangent` / `rbf_adjoint`. With every boundary node a centre the map is
//! linear; with greedy centres (`--rbf-tolerance > 0` or fewer `--rbf-max-centres` than
//! boundary nodes) the centres depend on the motion, so the derivative is taken about the
//! boundary motion of `--deformed`, with the centres its fit chooses.

use deform_kernel::rbf::{rbf_index_len, rbf_scratch_len, RbfKernel, RbfOptions};
use deform_kernel::sensitivity::{rbf_adjoint, rbf_tangent};

use super::{kernel, Solved};
use crate::args::{RbfKernelArg, SensitivitySetup};
use crate::engine::points_d;
use crate::engine::rbf::diagonal;
use crate::error::CliError;
use crate::files::read_su2;
use crate::formats::su2::Su2Mesh;

/// The linearisation point and the kernel's options and buffers.
struct Setup<const D: usize> {
    points: Vec<[f64; D]>,
    motion: Vec<[f64; D]>,
    options: RbfOptions<f64>,
    index: Vec<u32>,
    scratch: Vec<f64>,
}

impl<const D: usize> Setup<D> {
    fn new(setup: &SensitivitySetup, mesh: &Su2Mesh, boundary: &[u32]) -> Result<Self, CliError> {
        let points = points_d::<D>(&mesh.points);
        let at = |i: u32| points[i as usize];
        let motion: Vec<[f64; D]> = match &setup.deformed {
            None => vec![[0.0; D]; boundary.len()],
            Some(path) => {
                let def = read_su2(path)?;
                if def.points.len() != points.len() || def.dim != mesh.dim {
                    return Err(CliError::Invalid(format!(
                        "{}: not the mesh's nodes ({} points in {}D)",
                        path.display(),
                        def.points.len(),
                        def.dim
                    )));
                }
                let moved = points_d::<D>(&def.points);
                let d = |b: u32| std::array::from_fn(|k| moved[b as usize][k] - at(b)[k]);
                boundary.iter().map(|&b| d(b)).collect()
            }
        };
        let r = &setup.rbf;
        let b = boundary.len();
        let greedy = r.rbf_tolerance > 0.0 || r.rbf_max_centres < b;
        if greedy && setup.deformed.is_none() {
            return Err(CliError::Invalid(
                "--method rbf with greedy centres (--rbf-tolerance > 0 or --rbf-max-centres below \
                 the boundary node count) chooses its centres from the motion: give the \
                 linearisation point with --deformed"
                    .into(),
            ));
        }
        let largest = motion
            .iter()
            .map(|d| d.iter().map(|x| x * x).sum::<f64>().sqrt());
        let largest = largest.fold(0.0, f64::max);
        let kernel = match r.rbf_kernel {
            RbfKernelArg::Wendland => RbfKernel::Wendland {
                radius: r
                    .rbf_radius
                    .unwrap_or_else(|| diagonal(points.iter().copied())),
            },
            RbfKernelArg::Tps => RbfKernel::ThinPlate,
        };
        let options = RbfOptions {
            kernel,
            tolerance: r.rbf_tolerance * largest,
            max_centres: r.rbf_max_centres,
            correction_radius: r
                .rbf_correction
                .unwrap_or_else(|| diagonal(boundary.iter().map(|&m| at(m)))),
        };
        Ok(Setup {
            index: vec![0; rbf_index_len::<f64, D>(b, &options)],
            scratch: vec![0.0; rbf_scratch_len::<f64, D>(b, &options)],
            points,
            motion,
            options,
        })
    }
}

/// `Jᵀ w` at every node (zero off the boundary).
pub(super) fn adjoint<const D: usize>(
    setup: &SensitivitySetup,
    mesh: &Su2Mesh,
    boundary: &[u32],
    w: &[[f64; D]],
) -> Result<Solved<D>, CliError> {
    let mut s = Setup::<D>::new(setup, mesh, boundary)?;
    let mut back = vec![[0.0; D]; boundary.len()];
    let (p, m, o) = (&s.points, &s.motion, &s.options);
    rbf_adjoint(
        p,
        boundary,
        m,
        o,
        &mut s.index,
        &mut s.scratch,
        w,
        &mut back,
    )
    .map_err(kernel("RBF adjoint"))?;
    let mut g = vec![[0.0; D]; w.len()];
    for (&b, x) in boundary.iter().zip(back) {
        g[b as usize] = x;
    }
    Ok((g, None))
}

/// `J v` for `dx` holding `v` at the boundary nodes.
pub(super) fn tangent<const D: usize>(
    setup: &SensitivitySetup,
    mesh: &Su2Mesh,
    boundary: &[u32],
    dx: &[[f64; D]],
) -> Result<Solved<D>, CliError> {
    let mut s = Setup::<D>::new(setup, mesh, boundary)?;
    let v: Vec<[f64; D]> = boundary.iter().map(|&b| dx[b as usize]).collect();
    let mut out = vec![[0.0; D]; dx.len()];
    let (p, m, o) = (&s.points, &s.motion, &s.options);
    rbf_tangent(
        p,
        boundary,
        m,
        o,
        &mut s.index,
        &mut s.scratch,
        &v,
        &mut out,
    )
    .map_err(kernel("RBF tangent"))?;
    Ok((out, None))
}
