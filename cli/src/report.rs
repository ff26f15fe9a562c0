//! What commands report: the [`Outcome`] (JSON and text), small formatting helpers, and
//! pictures written next to the outputs.

use std::io;
use std::path::Path;
use std::time::Instant;

use crate::engine::QualitySummary;
use crate::output::Staged;
use crate::plot::{png, svg, Picture, Window};

use crate::error::CliError;
use crate::files::io_err;

/// What a successful command reports: a JSON value and the same for people.
#[derive(Debug)]
pub struct Outcome {
    /// The `--json` report.
    pub json: serde_json::Value,
    /// The human-readable report.
    pub text: String,
}

pub(crate) fn seconds(t: Instant) -> f64 {
    t.elapsed().as_secs_f64()
}

/// The command-line spelling of an enum value.
pub(crate) fn value_name<E: clap::ValueEnum>(v: &E) -> String {
    v.to_possible_value()
        .map(|p| p.get_name().to_string())
        .unwrap_or_default()
}

pub(crate) fn fmt_opt(v: Option<f64>) -> String {
    v.map_or_else(|| "-".to_string(), |x| format!("{x:.6}"))
}

/// Stages a picture (.svg or .png by extension).
pub(crate) fn write_picture(
    staged: &mut Staged,
    path: &Path,
    pic: &Picture<'_>,
    window: Window,
    width: u32,
) -> Result<(), CliError> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .unwrap_or("")
        .to_ascii_lowercase();
    let bytes = if ext == "png" {
        png(pic, window, width).map_err(|e| CliError::Io {
            path: path.to_path_buf(),
            source: io::Error::other(e),
        })?
    } else {
        svg(pic, window, width).into_bytes()
    };
    staged
        .write(path, |f| io::Write::write_all(f, &bytes))
        .map_err(io_err(path))
}

/// In 3D the measure ratios of a JSON report are volume ratios: renames its top-level
/// `min_area_ratio`/`max_area_ratio` to `min_volume_ratio`/`max_volume_ratio` (the 2D names
/// stay; the 3D report does not keep the old ones).
pub(crate) fn volume_words(mut json: serde_json::Value, dim: usize) -> serde_json::Value {
    if dim == 3 {
        if let Some(map) = json.as_object_mut() {
            for (old, new) in [
                ("min_area_ratio", "min_volume_ratio"),
                ("max_area_ratio", "max_volume_ratio"),
            ] {
                if let Some(v) = map.remove(old) {
                    map.insert(new.to_string(), v);
                }
            }
        }
    }
    json
}

pub(crate) fn add_summary(total: &mut Option<QualitySummary>, s: QualitySummary) {
    let Some(t) = total.as_mut() else {
        *total = Some(s);
        return;
    };
    let add_opt = |a: Option<usize>, b: Option<usize>| match (a, b) {
        (Some(x), Some(y)) => Some(x + y),
        _ => None,
    };
    let min_opt = |a: Option<f64>, b: Option<f64>| match (a, b) {
        (Some(x), Some(y)) => Some(x.min(y)),
        (x, None) => x,
        (None, y) => y,
    };
    let max_opt = |a: Option<f64>, b: Option<f64>| match (a, b) {
        (Some(x), Some(y)) => Some(x.max(y)),
        (x, None) => x,
        (None, y) => y,
    };
    t.cells += s.cells;
    t.inverted_cells = add_opt(t.inverted_cells, s.inverted_cells);
    t.folded_cells += s.folded_cells;
    t.degenerate_cells += s.degenerate_cells;
    t.nonpositive_cells += s.nonpositive_cells;
    t.orientation.regions += s.orientation.regions;
    t.orientation.positive_regions += s.orientation.positive_regions;
    t.orientation.negative_regions += s.orientation.negative_regions;
    t.orientation.cells_against_region += s.orientation.cells_against_region;
    t.orientation.cells_listed_reversed += s.orientation.cells_listed_reversed;
    t.measure.extend(&s.measure);
    t.scaled_jacobian.extend(&s.scaled_jacobian);
    t.ratio.extend(&s.ratio);
    t.inverted.extend(&s.inverted);
    t.folded.extend(&s.folded);
    t.reference_folded.extend(&s.reference_folded);
    t.min_measure = t.min_measure.min(s.min_measure);
    t.min_scaled_jacobian = t.min_scaled_jacobian.min(s.min_scaled_jacobian);
    t.min_area_ratio = min_opt(t.min_area_ratio, s.min_area_ratio);
    t.max_area_ratio = max_opt(t.max_area_ratio, s.max_area_ratio);
    t.max_wall_angle_change_deg = max_opt(t.max_wall_angle_change_deg, s.max_wall_angle_change_deg);
}
