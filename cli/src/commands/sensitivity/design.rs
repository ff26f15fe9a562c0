//! `deform adjoint --config`: dJ/dα of an SU2 config's design variables from the surface
//! sensitivity, written as SU2_DOT writes `of_grad.dat` (`CDiscAdjDeformationDriver::Run` and
//! `OutputGradient`, SU2 v8: a first line `<OBJECTIVE_FUNCTION> gradient `, then one value per
//! design variable at `OUTPUT_PRECISION` digits, 6 by default, as `ostream <<` writes them).

use std::fmt::Write as _;

use crate::args::AdjointArgs;
use crate::error::CliError;
use crate::files::read_bytes;
use crate::formats::su2::Su2Mesh;
use crate::formats::su2_config::parse_su2_config;

use super::super::su2::gradient::{cpp_general, design_gradient};

/// The `of_grad.dat` text and the gradient values, when `--config` is given.
pub(super) fn gradient(
    a: &AdjointArgs,
    mesh: &Su2Mesh,
    g: &[[f64; 3]],
) -> Result<Option<(String, Vec<f64>)>, CliError> {
    let Some(path) = &a.config else {
        return Ok(None);
    };
    let config = parse_su2_config(&read_bytes(path)?).map_err(|source| CliError::Read {
        path: path.clone(),
        source,
    })?;
    let grad = design_gradient(&config, mesh, g)?;
    let mut text = format!("{} gradient \n", grad.objective);
    for v in &grad.values {
        let _ = writeln!(text, "{}", cpp_general(*v, grad.precision));
    }
    Ok(Some((text, grad.values)))
}
