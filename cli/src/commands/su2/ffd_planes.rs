//! The FFD control-point planes SU2 holds fixed (`CSurfaceMovement::CheckFFDIntersections`):
//! where a DV_MARKER surface cuts a face of the box, design variables must not move the
//! control points of that face (and, for FFD_CONTINUITY= 1ST_DERIVATIVE / 2ND_DERIVATIVE, the
//! next one or two planes), so the surface stays continuous across the face. With
//! FFD_CONTINUITY= USER_INPUT the planes are FFD_FIX_I/J/K instead.
//!
//! The tests are SU2's own: in 2D each boundary edge against the (infinite) line through a
//! face's two corner control points (`SegmentIntersectsLine`), in 3D each pair of nodes of a
//! boundary face against the face's two triangles (`SegmentIntersectsTriangle`, with
//! `RayIntersectsTriangle`'s 1e-6 determinant cut); FFD_SYMMETRY_PLANE= YES skips the j faces
//! in 3D.

use crate::error::CliError;
use crate::formats::su2::Su2Mesh;
use crate::formats::su2_config::{list_items, Su2Config};

use super::design::FfdSetup;
use super::{number, option_error};

/// FFD_CONTINUITY.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Continuity {
    /// USER_INPUT: FFD_FIX_I/J/K.
    User,
    /// NO_DERIVATIVE, 1ST_DERIVATIVE, 2ND_DERIVATIVE: that many planes behind a cut face.
    Derivative(usize),
}

/// How the fixed planes of every box are found.
pub(super) struct PlaneRules {
    pub continuity: Continuity,
    /// FFD_FIX_I, FFD_FIX_J, FFD_FIX_K (USER_INPUT only).
    pub fix: [Vec<i64>; 3],
    /// FFD_SYMMETRY_PLANE.
    pub symmetry_plane: bool,
}

type P3 = [f64; 3];

fn sub(a: P3, b: P3) -> P3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
fn dot(a: P3, b: P3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
fn cross(a: P3, b: P3) -> P3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// SU2's `SegmentIntersectsLine`: the segment p0–p1 crosses the infinite line through v0, v1.
fn segment_crosses_line(p0: P3, p1: P3, v0: P3, v1: P3) -> bool {
    let (d0a, d1a) = (p0[0] - p1[0], p0[1] - p1[1]);
    let (d0b, d1b) = (v0[0] - v1[0], v0[1] - v1[1]);
    let det = d0a * d1b - d1a * d0b;
    if det == 0.0 {
        return false;
    }
    let (cp, cv) = (p0[0] * p1[1] - p0[1] * p1[0], v0[0] * v1[1] - v0[1] * v1[0]);
    let x = [(cp * d0b - cv * d0a) / det, (cp * d1b - cv * d1a) / det];
    let d2 = |p: P3| (x[0] - p[0]) * (x[0] - p[0]) + (x[1] - p[1]) * (x[1] - p[1]);
    let length = d0a * d0a + d1a * d1a;
    d2(p0) <= length && d2(p1) <= length
}

/// SU2's `SegmentIntersectsTriangle` (through `RayIntersectsTriangle`).
fn segment_crosses_triangle(p0: P3, p1: P3, [v0, v1, v2]: [P3; 3]) -> bool {
    let dir = sub(p1, p0);
    let (e1, e2) = (sub(v1, v0), sub(v2, v0));
    let pvec = cross(dir, e2);
    let det = dot(e1, pvec);
    if det.abs() < 0.000001 {
        return false;
    }
    let inv = 1.0 / det;
    let tvec = sub(p0, v0);
    let u = inv * dot(tvec, pvec);
    if !(0.0..=1.0).contains(&u) {
        return false;
    }
    let qvec = cross(tvec, e1);
    let v = inv * dot(dir, qvec);
    if v < 0.0 || u + v > 1.0 {
        return false;
    }
    let t = inv * dot(e2, qvec);
    let x = [p0[0] + t * dir[0], p0[1] + t * dir[1], p0[2] + t * dir[2]];
    let normal = cross(e1, e2);
    dot(normal, sub(p1, x)) * dot(normal, sub(p0, x)) <= 0.0
}

/// The faces of a box as SU2 tests them: per face (IA, IB, JA, JB, KA, KB) its two triangles
/// (3D; corner indices) or its line (2D: the first two corners of the first triangle and the
/// third, as SU2 pairs them).
fn faces(l: usize, m: usize, n: usize) -> [[[usize; 3]; 6]; 6] {
    [
        [
            [0, 0, 0],
            [0, 0, n],
            [0, m, 0],
            [0, m, n],
            [0, m, 0],
            [0, 0, n],
        ],
        [
            [l, 0, 0],
            [l, 0, n],
            [l, m, 0],
            [l, m, n],
            [l, m, 0],
            [l, 0, n],
        ],
        [
            [0, 0, 0],
            [0, 0, n],
            [l, 0, 0],
            [l, 0, n],
            [l, 0, 0],
            [0, 0, n],
        ],
        [
            [0, m, 0],
            [0, m, n],
            [l, m, 0],
            [l, m, n],
            [l, m, 0],
            [0, m, n],
        ],
        [
            [0, 0, 0],
            [0, m, 0],
            [l, 0, 0],
            [l, m, 0],
            [l, 0, 0],
            [0, m, 0],
        ],
        [
            [0, 0, n],
            [0, m, n],
            [l, 0, n],
            [l, m, n],
            [l, 0, n],
            [0, m, n],
        ],
    ]
}

/// Which faces (IA, IB, JA, JB, KA, KB) the DV_MARKER surface cuts. `cp(i, j, k)` gives a
/// control point.
fn cut_faces(
    mesh: &Su2Mesh,
    markers: &[String],
    degree: [usize; 3],
    cp: &dyn Fn([usize; 3]) -> P3,
    symmetry_plane: bool,
) -> [bool; 6] {
    let [l, m, n] = degree;
    let faces = faces(l, m, n);
    let mut cut = [false; 6];
    let point = |v: u32| mesh.points.get(v as usize).copied().unwrap_or([0.0; 3]);
    let three_d = mesh.dim == 3;
    for marker in mesh.markers.iter().filter(|m| markers.contains(&m.name)) {
        for (_, e) in marker.elements.iter() {
            for &a in e {
                for &b in e.iter().filter(|&&b| b > a) {
                    let (p0, p1) = (point(a), point(b));
                    for (f, face) in faces.iter().enumerate() {
                        if cut[f] || (three_d && symmetry_plane && (f == 2 || f == 3)) {
                            continue;
                        }
                        let c = face.map(cp);
                        cut[f] = if three_d {
                            segment_crosses_triangle(p0, p1, [c[0], c[1], c[2]])
                                || segment_crosses_triangle(p0, p1, [c[3], c[4], c[5]])
                        } else {
                            f < 4 && segment_crosses_line(p0, p1, c[0], c[2])
                        };
                    }
                }
            }
        }
    }
    cut
}

/// The fixed i, j and k planes of one box (its control points as `cp`).
pub(super) fn fixed_planes(
    mesh: &Su2Mesh,
    markers: &[String],
    degree: [usize; 3],
    cp: &dyn Fn([usize; 3]) -> P3,
    rules: &PlaneRules,
) -> [Vec<u32>; 3] {
    let mut fixed: [Vec<u32>; 3] = Default::default();
    let depth = match rules.continuity {
        Continuity::User => {
            for ((f, list), &d) in fixed.iter_mut().zip(&rules.fix).zip(&degree) {
                f.extend(
                    list.iter()
                        .filter(|&&x| x >= 0 && x as usize <= d)
                        .map(|&x| x as u32),
                );
            }
            return fixed;
        }
        Continuity::Derivative(depth) => depth,
    };
    let cut = cut_faces(mesh, markers, degree, cp, rules.symmetry_plane);
    for (axis, (f, &d)) in fixed.iter_mut().zip(&degree).enumerate() {
        // SU2 fixes nothing for 2ND_DERIVATIVE on a direction of degree 1.
        if depth == 2 && d <= 1 {
            continue;
        }
        for (side, &hit) in cut[2 * axis..2 * axis + 2].iter().enumerate() {
            if hit {
                let planes = (0..=depth.min(d)).map(|s| if side == 0 { s } else { d - s });
                f.extend(planes.map(|p| p as u32));
            }
        }
    }
    fixed
}

/// The config options the FFD design variables read besides DV_*.
pub(super) const FFD_OPTIONS: &[&str] = &[
    "FFD_CONTINUITY",
    "FFD_FIX_I",
    "FFD_FIX_J",
    "FFD_FIX_K",
    "FFD_SYMMETRY_PLANE",
    "FFD_COORDINATE_SYSTEM",
    "FFD_BLENDING",
    "FFD_INTPREV",
    "OPT_LINE_SEARCH_BOUND",
    "REF_LENGTH",
];

/// An upper-case option value, or `default`.
fn word(config: &Su2Config, key: &str, default: &str) -> String {
    config
        .get(key)
        .map_or(default.into(), |e| e.value.trim().to_ascii_uppercase())
}

/// FFD_CONTINUITY, FFD_FIX_*, FFD_SYMMETRY_PLANE and OPT_LINE_SEARCH_BOUND, with SU2's
/// defaults (2ND_DERIVATIVE, none, NO, 1e6); FFD_COORDINATE_SYSTEM other than CARTESIAN,
/// FFD_BLENDING other than BEZIER and FFD_INTPREV= YES are refused.
pub(super) fn setup<'a>(
    config: &Su2Config,
    markers: &'a [String],
) -> Result<FfdSetup<'a>, CliError> {
    let refuse = |key: &str, ok: &str| -> Result<(), CliError> {
        let v = word(config, key, ok);
        if v == ok {
            return Ok(());
        }
        Err(option_error(
            config,
            key,
            format!("{v}: only {ok} (SU2's other settings are not supported)"),
        ))
    };
    refuse("FFD_COORDINATE_SYSTEM", "CARTESIAN")?;
    refuse("FFD_BLENDING", "BEZIER")?;
    refuse("FFD_INTPREV", "NO")?;
    let continuity = match word(config, "FFD_CONTINUITY", "2ND_DERIVATIVE").as_str() {
        "USER_INPUT" => Continuity::User,
        "NO_DERIVATIVE" => Continuity::Derivative(0),
        "1ST_DERIVATIVE" => Continuity::Derivative(1),
        "2ND_DERIVATIVE" => Continuity::Derivative(2),
        v => {
            let why = format!("{v}: USER_INPUT, NO_DERIVATIVE, 1ST_DERIVATIVE or 2ND_DERIVATIVE");
            return Err(option_error(config, "FFD_CONTINUITY", why));
        }
    };
    let fix = |key: &str| -> Result<Vec<i64>, CliError> {
        let items = config
            .get(key)
            .map(|e| list_items(&e.value))
            .unwrap_or_default();
        (items.iter())
            .map(|t| {
                t.parse::<i64>()
                    .map_err(|_| option_error(config, key, format!("{t:?} is not a plane index")))
            })
            .collect()
    };
    let symmetry_plane = match word(config, "FFD_SYMMETRY_PLANE", "NO").as_str() {
        "YES" => true,
        "NO" => false,
        v => {
            return Err(option_error(
                config,
                "FFD_SYMMETRY_PLANE",
                format!("{v}: YES or NO"),
            ))
        }
    };
    Ok(FfdSetup {
        markers,
        rules: PlaneRules {
            continuity,
            fix: [fix("FFD_FIX_I")?, fix("FFD_FIX_J")?, fix("FFD_FIX_K")?],
            symmetry_plane,
        },
        bound: number(config, "OPT_LINE_SEARCH_BOUND", 1e6)?,
    })
}
