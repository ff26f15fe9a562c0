//! `deform move --method rbf`: radial-basis-function deformation through the kernel's
//! [`deform_kernel::rbf`].

use deform_kernel::rbf::{rbf_deform, rbf_index_len, rbf_scratch_len, RbfKernel, RbfOptions};
use serde::Serialize;

use crate::error::CliError;

/// The radial function.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum RbfFunction {
    /// Wendland C2 with compact support.
    Wendland,
    /// Thin-plate spline with linear terms.
    Tps,
}

/// The settings of an RBF move (`MoveMethod::Rbf`); distances in mesh units, `None` for the
/// defaults `move_rbf` derives from the mesh.
#[derive(Clone, Copy, Debug)]
pub struct RbfSettings {
    /// The radial function.
    pub function: RbfFunction,
    /// Wendland support radius (default: the mesh's bounding-box diagonal).
    pub radius: Option<f64>,
    /// Greedy tolerance as a fraction of the largest boundary displacement.
    pub tolerance: f64,
    /// Most centres.
    pub max_centres: usize,
    /// Correction radius (default: the moved markers' bounding-box diagonal).
    pub correction: Option<f64>,
}

impl PartialEq for RbfSettings {
    /// Bit equality of the numbers (so that the settings are `Eq`, as `MoveMethod` is).
    fn eq(&self, o: &Self) -> bool {
        let bits = |v: Option<f64>| v.map(f64::to_bits);
        self.function == o.function
            && bits(self.radius) == bits(o.radius)
            && self.tolerance.to_bits() == o.tolerance.to_bits()
            && self.max_centres == o.max_centres
            && bits(self.correction) == bits(o.correction)
    }
}
impl Eq for RbfSettings {}

/// What the RBF fit did, for the report.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct RbfInfo {
    /// `wendland` or `tps`.
    pub kernel: RbfFunction,
    /// Support radius used (Wendland).
    pub radius: Option<f64>,
    /// Centres used, of `boundary_nodes`.
    pub centres: usize,
    /// Boundary nodes (moved and fixed).
    pub boundary_nodes: usize,
    /// Largest boundary error of the interpolant before the correction (mesh units).
    pub max_error: f64,
    /// The correction's radius (mesh units).
    pub correction_radius: f64,
}

/// Diagonal of the bounding box of `pts`.
pub(crate) fn diagonal<const D: usize>(pts: impl Iterator<Item = [f64; D]>) -> f64 {
    let mut lo = [f64::INFINITY; D];
    let mut hi = [f64::NEG_INFINITY; D];
    for p in pts {
        for k in 0..D {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    (0..D).map(|k| (hi[k] - lo[k]).powi(2)).sum::<f64>().sqrt()
}

/// Moves every node of `pts` by the RBF interpolant of the boundary nodes' displacements
/// `disp` (all mesh nodes, 3 components); `moved` are the moved markers' nodes.
pub fn move_rbf<const D: usize>(
    r: &RbfSettings,
    pts: &[[f64; D]],
    boundary: &[u32],
    moved: &[u32],
    disp: &[[f64; 3]],
) -> Result<(Vec<[f64; D]>, RbfInfo), CliError> {
    let at = |i: u32| pts.get(i as usize).copied().unwrap_or([0.0; D]);
    let motion: Vec<[f64; D]> = boundary
        .iter()
        .map(|&b| {
            let d = disp.get(b as usize).copied().unwrap_or([0.0; 3]);
            std::array::from_fn(|k| d[k])
        })
        .collect();
    let largest = motion
        .iter()
        .map(|d| d.iter().map(|x| x * x).sum::<f64>().sqrt())
        .fold(0.0, f64::max);
    let radius = r.radius.unwrap_or_else(|| diagonal(pts.iter().copied()));
    let kernel = match r.function {
        RbfFunction::Wendland => RbfKernel::Wendland { radius },
        RbfFunction::Tps => RbfKernel::ThinPlate,
    };
    let correction = r
        .correction
        .unwrap_or_else(|| diagonal(moved.iter().map(|&m| at(m))));
    let options = RbfOptions {
        kernel,
        tolerance: r.tolerance * largest,
        max_centres: r.max_centres,
        correction_radius: correction,
    };
    let b = boundary.len();
    let mut index = vec![0u32; rbf_index_len::<f64, D>(b, &options)];
    let mut scratch = vec![0.0; rbf_scratch_len::<f64, D>(b, &options)];
    let mut displacement = vec![[0.0; D]; pts.len()];
    let report = rbf_deform(
        pts,
        boundary,
        &motion,
        &options,
        &mut index,
        &mut scratch,
        &mut displacement,
    )
    .map_err(|e| CliError::Kernel {
        context: "RBF".into(),
        source: e,
    })?;
    let out = pts
        .iter()
        .zip(&displacement)
        .map(|(p, d)| std::array::from_fn(|k| p[k] + d[k]))
        .collect();
    let info = RbfInfo {
        kernel: r.function,
        radius: matches!(r.function, RbfFunction::Wendland).then_some(radius),
        centres: report.centres,
        boundary_nodes: b,
        max_error: report.max_error,
        correction_radius: correction,
    };
    Ok((out, info))
}
