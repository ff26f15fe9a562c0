//! `deform adjoint --config`: dJ/dα of an SU2 config's design variables from the surface
//! sensitivity, written as SU2_DOT writes `of_grad.dat` (`CDiscAdjDeformationDriver::Run` and
//! `OutputGradient`, SU2 v8: a first line `<OBJECTIVE_FUNCTION> gradient `, then one value per
//! design variable at `OUTPUT_PRECISION` digits, 6 by default, as `ostream <<` writes them).

use std::fmt::Write as _;

use crate::args::{AdjointArgs, SensitivitySetup};
use crate::error::CliError;
use crate::files::read_bytes;
use crate::formats::su2::Su2Mesh;
use crate::formats::su2_config::{list_items, parse_su2_config, Su2Config};

use super::super::su2::gradient::{cpp_general, design_gradient};

/// The config of `--config`, when given.
fn config(a: &AdjointArgs) -> Result<Option<Su2Config>, CliError> {
    let Some(path) = &a.config else {
        return Ok(None);
    };
    let config = parse_su2_config(&read_bytes(path)?).map_err(|source| CliError::Read {
        path: path.clone(),
        source,
    })?;
    Ok(Some(config))
}

/// The setup of the adjoint with `--config`'s MARKER_DEFORM_MESH_SYM_PLANE markers added to
/// `--slide`: they slide in `deform su2`, so they slide in its derivative.
pub(super) fn with_symmetry_planes(a: &AdjointArgs) -> Result<SensitivitySetup, CliError> {
    let mut setup = a.setup.clone();
    let planes = config(a)?.and_then(|c| {
        (c.get("MARKER_DEFORM_MESH_SYM_PLANE"))
            .map(|e| list_items(&e.value).into_iter().map(String::from).collect())
    });
    for m in planes.unwrap_or_else(Vec::new) {
        if !setup.slide.contains(&m) {
            setup.slide.push(m);
        }
    }
    Ok(setup)
}

/// The `of_grad.dat` text and the gradient values, when `--config` is given.
pub(super) fn gradient(
    a: &AdjointArgs,
    mesh: &Su2Mesh,
    g: &[[f64; 3]],
) -> Result<Option<(String, Vec<f64>)>, CliError> {
    let Some(config) = config(a)? else {
        return Ok(None);
    };
    let grad = design_gradient(&config, mesh, g)?;
    let mut text = format!("{} gradient \n", grad.objective);
    for v in &grad.values {
        let _ = writeln!(text, "{}", cpp_general(*v, grad.precision));
    }
    Ok(Some((text, grad.values)))
}
