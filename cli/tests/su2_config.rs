//! `deform su2 CONFIG` (issue 29 item 1): SU2_DEF's configuration file drives `deform move`.
//! Checked here: the design variables it applies (ROTATION against SU2's own rotation formula,
//! written out here from CSurfaceMovement::SetRotation, not the tool's code; TRANSLATION;
//! SURFACE_FILE), the same bits as the `deform move` command the options map to, every
//! honoured DEFORM_* option, unknown options reported once, and the errors that name an
//! option or a line.

mod common;

use std::path::Path;

use common::{deform_json, deform_ok, deform_refused, naca_mesh, read_su2, tmp_dir};

/// A deformation config for `m.su2`'s airfoil with the given design-variable lines.
fn config(dir: &Path, name: &str, design: &str, extra: &str) {
    let text = format!(
        "% SU2_DEF configuration\n\
         MESH_FILENAME= m.su2\n\
         MESH_OUT_FILENAME= out.su2\n\
         MACH_NUMBER= 0.8  % a flow option: ignored\n\
         MARKER_EULER= ( airfoil )\n\
         MARKER_FAR= ( farfield )\n\
         DV_MARKER= ( airfoil )\n\
         {design}\n\
         DEFORM_STIFFNESS_TYPE= INVERSE_VOLUME\n\
         DEFORM_LINEAR_SOLVER_ERROR= 1E-11\n\
         {extra}\n"
    );
    std::fs::write(dir.join(name), text).expect("write config");
}

/// SU2's rotation of a point about the line through (a, b, c) with direction (u, v, w) by
/// `theta` (CSurfaceMovement::SetRotation's closed form).
fn su2_rotation(
    p: [f64; 3],
    (a, b, c): (f64, f64, f64),
    (u, v, w): (f64, f64, f64),
    theta: f64,
) -> [f64; 3] {
    let (x, y, z) = (p[0], p[1], p[2]);
    let (u2, v2, w2) = (u * u, v * v, w * w);
    let l2 = u2 + v2 + w2;
    let l = l2.sqrt();
    let (cos_t, sin_t) = (theta.cos(), theta.sin());
    let mx = a * (v2 + w2)
        + u * (-b * v - c * w + u * x + v * y + w * z)
        + (-a * (v2 + w2) + u * (b * v + c * w - v * y - w * z) + (v2 + w2) * x) * cos_t
        + l * (-c * v + b * w - w * y + v * z) * sin_t;
    let my = b * (u2 + w2)
        + v * (-a * u - c * w + u * x + v * y + w * z)
        + (-b * (u2 + w2) + v * (a * u + c * w - u * x - w * z) + (u2 + w2) * y) * cos_t
        + l * (c * u - a * w + w * x - u * z) * sin_t;
    let mz = c * (u2 + v2)
        + w * (-a * u - b * v + u * x + v * y + w * z)
        + (-c * (u2 + v2) + w * (a * u + b * v - u * x - v * y) + (u2 + v2) * z) * cos_t
        + l * (-b * u + a * v - v * x + u * y) * sin_t;
    [mx / l2, my / l2, mz / l2]
}

fn airfoil_nodes(mesh: &deform_cli::formats::su2::Su2Mesh) -> Vec<u32> {
    let mut nodes: Vec<u32> = (mesh.markers.iter())
        .filter(|m| m.name == "airfoil")
        .flat_map(|m| m.elements.nodes.iter().copied())
        .collect();
    nodes.sort_unstable();
    nodes.dedup();
    nodes
}

#[test]
fn rotation_is_su2s_and_the_volume_is_deform_moves() {
    let d = tmp_dir("su2-config-rotation");
    naca_mesh(&d, "inviscid", 64, 16, "m.su2");
    config(
        &d,
        "def.cfg",
        "DV_KIND= ROTATION\nDV_PARAM= ( 0.25, 0.0, 0.0, 0.25, 0.0, 1.0 )\nDV_VALUE= 12.5",
        "DEFORM_NONLINEAR_ITER= 2",
    );
    let r = deform_json(&d, &["--json", "su2", "def.cfg", "--method", "quaternion"]);
    assert_eq!(r["command"], "su2");
    assert_eq!(r["steps"], 2);
    assert_eq!(r["stiffness"], "inverse-volume");
    assert_eq!(r["ignored_options"], serde_json::json!(["MACH_NUMBER"]));
    let before = read_su2(&d.join("m.su2"));
    let after = read_su2(&d.join("out.su2"));
    let theta = 12.5f64.to_radians();
    for n in airfoil_nodes(&before) {
        let want = su2_rotation(
            before.points[n as usize],
            (0.25, 0.0, 0.0),
            (0.0, 0.0, 1.0),
            theta,
        );
        let got = after.points[n as usize];
        for k in 0..2 {
            assert!(
                (got[k] - want[k]).abs() < 1e-13,
                "node {n}: {got:?} vs SU2 {want:?}"
            );
        }
    }
    // The same as the `deform move` command the options map to, bit for bit.
    deform_ok(
        &d,
        &[
            "move",
            "m.su2",
            "--marker",
            "airfoil",
            "--rotate",
            "12.5",
            "--center",
            "0.25,0",
            "--method",
            "quaternion",
            "--stiffness",
            "inverse-volume",
            "--steps",
            "2",
            "--tol",
            "1e-11",
            "--out",
            "direct.su2",
        ],
    );
    let direct = read_su2(&d.join("direct.su2"));
    let bits = |m: &deform_cli::formats::su2::Su2Mesh| -> Vec<[u64; 3]> {
        m.points.iter().map(|p| p.map(f64::to_bits)).collect()
    };
    assert_eq!(bits(&after), bits(&direct));
}

#[test]
fn translation_and_surface_file() {
    let d = tmp_dir("su2-config-translation");
    naca_mesh(&d, "inviscid", 48, 12, "m.su2");
    config(
        &d,
        "t.cfg",
        "DV_KIND= TRANSLATION\nDV_PARAM= ( 1.0, 0.5, 7.0 )\nDV_VALUE= 0.02",
        "",
    );
    deform_json(&d, &["--json", "su2", "t.cfg", "--method", "spring"]);
    let before = read_su2(&d.join("m.su2"));
    let after = read_su2(&d.join("out.su2"));
    for n in airfoil_nodes(&before) {
        let (p, q) = (before.points[n as usize], after.points[n as usize]);
        assert!((q[0] - p[0] - 0.02).abs() < 1e-15 && (q[1] - p[1] - 0.01).abs() < 1e-15);
    }
    // SURFACE_FILE: the positions of DV_FILENAME, placed exactly.
    let lines: String = airfoil_nodes(&before)
        .iter()
        .map(|&n| {
            let p = before.points[n as usize];
            format!("{n} {:e} {:e}\n", p[0] * 1.01, p[1] * 0.99)
        })
        .collect();
    std::fs::write(d.join("surface_positions.dat"), lines).expect("write positions");
    config(
        &d,
        "s.cfg",
        "DV_KIND= SURFACE_FILE",
        "DEFORM_CONSOLE_OUTPUT= NO",
    );
    deform_json(&d, &["--json", "su2", "s.cfg", "--method", "quaternion"]);
    let after = read_su2(&d.join("out.su2"));
    for n in airfoil_nodes(&before) {
        let (p, q) = (before.points[n as usize], after.points[n as usize]);
        assert_eq!([q[0], q[1]], [p[0] * 1.01, p[1] * 0.99]);
    }
}

#[test]
fn unknown_options_are_reported_once() {
    let d = tmp_dir("su2-config-ignored");
    naca_mesh(&d, "inviscid", 32, 10, "m.su2");
    config(
        &d,
        "def.cfg",
        "DV_KIND= TRANSLATION\nDV_PARAM= ( 0.0, 1.0, 0.0 )\nDV_VALUE= 0.01",
        "CFL_NUMBER= 5\nDEFORM_POISSONS_RATIO= 0.3",
    );
    let o = deform_ok(&d, &["su2", "def.cfg", "--method", "spring"]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(err.matches("MACH_NUMBER").count(), 1, "{err}");
    assert_eq!(err.matches("CFL_NUMBER").count(), 1, "{err}");
    // Elasticity's Poisson ratio is not used by the springs: said so too.
    assert_eq!(err.matches("DEFORM_POISSONS_RATIO").count(), 1, "{err}");
    assert!(!err.contains("DEFORM_LINEAR_SOLVER_ERROR"), "{err}");
}

#[test]
fn errors_name_the_option_or_the_line() {
    let d = tmp_dir("su2-config-errors");
    naca_mesh(&d, "inviscid", 32, 10, "m.su2");
    let refuse = |design: &str, extra: &str, needle: &str| {
        config(&d, "bad.cfg", design, extra);
        deform_refused(
            &d,
            &["su2", "bad.cfg", "--method", "spring"],
            1,
            needle,
            "out.su2",
        );
    };
    let rotation = "DV_KIND= ROTATION\nDV_PARAM= ( 0.25, 0.0, 0.0, 0.25, 0.0, 1.0 )\nDV_VALUE= 3";
    refuse(
        "DV_KIND= SURFACE_BUMP\nDV_PARAM= ( 0.1, 0.5, 0.3 )\nDV_VALUE= 0.01",
        "",
        "DV_KIND (line 8)",
    );
    refuse(
        "DV_KIND= HICKS_HENNE\nDV_PARAM= ( 1, 0.5 ); ( 0, 0.2 )\nDV_VALUE= 0.01",
        "",
        "DV_PARAM (line 9)",
    );
    refuse(
        "DV_KIND= FFD_CONTROL_POINT_2D\nDV_PARAM= ( BOX, 1, 1, 0, 1 )\nDV_VALUE= 0.01",
        "",
        "no FFD box",
    );
    refuse(
        "DV_KIND= ROTATION\nDV_PARAM= ( 0, 0, 0, 1, 0, 0 )\nDV_VALUE= 3",
        "",
        "DV_PARAM (line 9)",
    );
    refuse(
        "DV_KIND= ROTATION\nDV_PARAM= ( 0.25, 0 )\nDV_VALUE= 3",
        "",
        "(ROTATION) needs 6 parameters",
    );
    refuse(
        rotation,
        "DEFORM_STIFFNESS_TYPE2= X\nMESH_FORMAT= CGNS",
        "MESH_FORMAT (line 14)",
    );
    refuse(
        rotation,
        "DEFORM_NONLINEAR_ITER= many",
        "DEFORM_NONLINEAR_ITER (line 13)",
    );
    refuse(
        rotation,
        "DEFORM_CONSOLE_OUTPUT= MAYBE",
        "DEFORM_CONSOLE_OUTPUT",
    );
    refuse(rotation, "this line has no equals sign", "line 13");
    refuse(
        rotation,
        "DV_VALUE= 4",
        "line 13: DV_VALUE (first set at line 10) appears twice",
    );
    std::fs::write(
        d.join("nomarker.cfg"),
        "MESH_FILENAME= m.su2\nDV_KIND= ROTATION\n",
    )
    .unwrap();
    deform_refused(
        &d,
        &["su2", "nomarker.cfg", "--method", "spring"],
        1,
        "DV_MARKER",
        "out.su2",
    );
    // DEFORM_COEFF is SU2's Poisson ratio itself: 0.5 (infinite λ) is refused by name.
    config(&d, "half.cfg", rotation, "DEFORM_COEFF= 0.5");
    deform_refused(&d, &["su2", "half.cfg"], 1, "DEFORM_COEFF", "out.su2");
    // Without --method: SU2's elasticity, with SU2's Poisson ratio from DEFORM_COEFF.
    config(&d, "def.cfg", rotation, "DEFORM_COEFF= 0.25");
    let r = deform_json(&d, &["--json", "su2", "def.cfg"]);
    assert_eq!(r["method"], "elasticity");
    assert_eq!(r["stiffness"], "inverse-volume");
    assert_eq!(r["ignored_options"], serde_json::json!(["MACH_NUMBER"]));
}

/// NACA 2412's camber line (the 4-digit formula), to tell upper from lower surface nodes
/// without the tool's normals.
fn camber(x: f64) -> f64 {
    let (m, p) = (0.02, 0.4);
    if x < p {
        m / (p * p) * (2.0 * p * x - x * x)
    } else {
        m / ((1.0 - p) * (1.0 - p)) * ((1.0 - 2.0 * p) + 2.0 * p * x - x * x)
    }
}

#[test]
fn hicks_henne_bumps_are_su2s() {
    let d = tmp_dir("su2-config-hicks-henne");
    naca_mesh(&d, "inviscid", 64, 14, "m.su2");
    config(
        &d,
        "hh.cfg",
        "DV_KIND= HICKS_HENNE, HICKS_HENNE\nDV_PARAM= ( 1, 0.5 ); ( 0, 0.3 )\nDV_VALUE= 0.01, 0.004",
        "OPT_RELAX_FACTOR= 2",
    );
    deform_json(&d, &["--json", "su2", "hh.cfg", "--method", "spring"]);
    let before = read_su2(&d.join("m.su2"));
    let after = read_su2(&d.join("out.su2"));
    // SU2's bump on the raw x: sin(π x^(ln 0.5 / ln x_max))^3, times DV_VALUE × OPT_RELAX_FACTOR.
    let bump = |x: f64, x_max: f64| {
        if x <= 1e-15 {
            return 0.0;
        }
        let e = 0.5f64.log10() / x_max.log10();
        (std::f64::consts::PI * x.powf(e)).sin().powi(3)
    };
    for n in airfoil_nodes(&before) {
        let (p, q) = (before.points[n as usize], after.points[n as usize]);
        let upper = p[1] > camber(p[0]);
        let want = if upper {
            0.02 * bump(p[0], 0.5)
        } else {
            -0.008 * bump(p[0], 0.3)
        };
        assert_eq!(q[0], p[0], "node {n} moved in x");
        assert!(
            (q[1] - p[1] - want).abs() < 1e-12,
            "node {n} at {p:?}: {} vs {want}",
            q[1] - p[1]
        );
    }
}

/// Bernstein polynomial B_i^n(t), written out here.
fn bernstein(n: u32, i: u32, t: f64) -> f64 {
    let binom = (1..=i).fold(1.0, |b, k| b * f64::from(n - k + 1) / f64::from(k));
    binom * t.powi(i as i32) * (1.0 - t).powi((n - i) as i32)
}

#[test]
fn ffd_control_points_move_the_surface_as_bernstein_boxes_do() {
    let d = tmp_dir("su2-config-ffd");
    naca_mesh(&d, "inviscid", 48, 12, "m.su2");
    let mesh = read_su2(&d.join("m.su2"));
    // A degree (4, 1) box around the airfoil, written as SU2 stores it (2D: k = 0, 1 at z = ±0.5).
    let (x0, x1, y0, y1) = (-0.1, 1.1, -0.2, 0.2);
    let mut ffd = String::from(
        "FFD_NBOX= 1\nFFD_NLEVEL= 1\nFFD_TAG= BOX\nFFD_LEVEL= 0\nFFD_DEGREE_I= 4\nFFD_DEGREE_J= 1\n\
         FFD_BLENDING= BEZIER\nFFD_PARENTS= 0\nFFD_CHILDREN= 0\nFFD_CORNER_POINTS= 4\n",
    );
    ffd += &format!("{x0} {y0}\n{x1} {y0}\n{x1} {y1}\n{x0} {y1}\nFFD_CONTROL_POINTS= 20\n");
    for i in 0..=4 {
        for j in 0..=1 {
            for k in 0..=1 {
                let x = x0 + (x1 - x0) * f64::from(i) / 4.0;
                let y = y0 + (y1 - y0) * f64::from(j);
                ffd += &format!("{i} {j} {k} {x:e} {y:e} {}\n", f64::from(k) - 0.5);
            }
        }
    }
    let nodes = airfoil_nodes(&mesh);
    ffd += &format!("FFD_SURFACE_POINTS= {}\n", nodes.len());
    for &n in &nodes {
        let p = mesh.points[n as usize];
        ffd += &format!(
            "airfoil {n} {:e} {:e} 0.5\n",
            (p[0] - x0) / (x1 - x0),
            (p[1] - y0) / (y1 - y0)
        );
    }
    let mut text = std::fs::read_to_string(d.join("m.su2")).unwrap();
    text += &ffd;
    std::fs::write(d.join("m.su2"), text).unwrap();
    config(
        &d,
        "ffd.cfg",
        "DV_KIND= FFD_CONTROL_POINT_2D\nDV_PARAM= ( BOX, 2, 1, 0.0, 1.0 )\nDV_VALUE= 0.01",
        "",
    );
    deform_json(&d, &["--json", "su2", "ffd.cfg", "--method", "quaternion"]);
    let after = read_su2(&d.join("out.su2"));
    for &n in &nodes {
        let (p, q) = (mesh.points[n as usize], after.points[n as usize]);
        let (u, v) = ((p[0] - x0) / (x1 - x0), (p[1] - y0) / (y1 - y0));
        let want = 0.01 * bernstein(4, 2, u) * bernstein(1, 1, v);
        assert!(
            (q[0] - p[0]).abs() < 1e-13,
            "node {n}: x moved by {}",
            q[0] - p[0]
        );
        assert!(
            (q[1] - p[1] - want).abs() < 1e-13,
            "node {n}: {} vs {want}",
            q[1] - p[1]
        );
    }
    // The FFD sections are written back with the mesh.
    let out = std::fs::read_to_string(d.join("out.su2")).unwrap();
    assert!(out.contains("FFD_TAG= BOX"));
}
