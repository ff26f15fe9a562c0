//! The options of `deform move --method rbf` and their checks.

use clap::{Args, ValueEnum};

use crate::error::CliError;

/// The radial function of `--method rbf`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum RbfKernelArg {
    /// Wendland C2, compact support --rbf-radius (SU2's WENDLAND_C2).
    Wendland,
    /// Thin-plate spline r² ln r with linear terms (reproduces rigid motions exactly).
    Tps,
}
/// The options of `--method rbf` (flattened into `deform move`).
#[derive(Clone, Debug, Args)]
pub struct RbfArgs {
    /// --method rbf: the radial function.
    #[arg(long, value_enum, default_value = "wendland")]
    pub rbf_kernel: RbfKernelArg,
    /// --method rbf --rbf-kernel wendland: support radius in mesh units (default: the
    /// diagonal of the mesh's bounding box, so every node feels every centre).
    #[arg(long, value_name = "R")]
    pub rbf_radius: Option<f64>,
    /// --method rbf: greedy centre selection (SU2's data reduction) stops when the largest
    /// boundary error is at most this fraction of the largest boundary displacement (SU2's
    /// default is 1e-3); 0 takes every boundary node while there are at most
    /// --rbf-max-centres.
    #[arg(long, value_name = "TOL", default_value_t = 0.0)]
    pub rbf_tolerance: f64,
    /// --method rbf: most centres (the dense solve grows as their cube).
    #[arg(long, value_name = "N", default_value_t = 1000)]
    pub rbf_max_centres: usize,
    /// --method rbf: the boundary error a reduced fit leaves is faded into the volume over
    /// this distance (mesh units), so the wall moves exactly as prescribed (default: the
    /// diagonal of the moved markers' bounding box).
    #[arg(long, value_name = "DISTANCE")]
    pub rbf_correction: Option<f64>,
}

/// Checks the `--rbf-*` options (meaningful only with `--method rbf`).
pub fn check_rbf_args(r: &RbfArgs, rbf: bool) -> Result<(), CliError> {
    let given = r.rbf_radius.is_some()
        || r.rbf_correction.is_some()
        || r.rbf_tolerance != 0.0
        || r.rbf_max_centres != 1000
        || r.rbf_kernel != RbfKernelArg::Wendland;
    if given && !rbf {
        return Err(CliError::Invalid(
            "--rbf-* options apply to --method rbf".into(),
        ));
    }
    let positive = |v: Option<f64>| v.is_none_or(|x| x.is_finite() && x > 0.0);
    if !positive(r.rbf_radius) || !positive(r.rbf_correction) {
        return Err(CliError::Invalid(
            "--rbf-radius and --rbf-correction must be positive distances".into(),
        ));
    }
    if r.rbf_radius.is_some() && r.rbf_kernel == RbfKernelArg::Tps {
        return Err(CliError::Invalid(
            "--rbf-radius is the Wendland support; thin-plate splines have none".into(),
        ));
    }
    if !(r.rbf_tolerance.is_finite() && r.rbf_tolerance >= 0.0) {
        return Err(CliError::Invalid(
            "--rbf-tolerance must be a non-negative fraction".into(),
        ));
    }
    if r.rbf_max_centres < 4 {
        return Err(CliError::Invalid(
            "--rbf-max-centres must be at least 4".into(),
        ));
    }
    Ok(())
}
