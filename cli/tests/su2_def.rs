//! `deform su2` (issue 29) on SU2's own deformation case and on the design variables SU2 applies
//! to FFD boxes and surfaces, each checked against what this project did not write:
//!
//! - SU2's `TestCases/cont_adj_euler/wedge/inv_wedge_ROE.cfg`, unchanged, on its mesh
//!   (`cli/tests/data/wedge_inv_periodic_ffd.su2`, SU2's `mesh_wedge_inv_FFD.su2`): the surface
//!   against a numpy Bernstein evaluation of the stored box, the volume against a scikit-fem
//!   elasticity solve (`cli/tests/tools/ref_su2_def.py`).
//! - FFD_CAMBER, FFD_THICKNESS, FFD_TWIST on a generated box mesh, SCALE with TRANSLATION on a
//!   NACA mesh: against the formulas of SU2's SetFFDCamber / SetFFDThickness / SetFFDTwist /
//!   SetScale written out here.
//! - The planes SU2 fixes where the surface crosses a box face, and FFD_FIX_I.

mod common;

use std::path::{Path, PathBuf};

use common::{deform_json, deform_ok, deform_refused, naca_mesh, read_su2, tmp_dir};

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(name)
}

fn tool(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/tools")
        .join(name)
}

/// The wedge case in `dir`: SU2's config as `cfg` (with `edit` applied) and its mesh.
fn wedge_case(dir: &Path, cfg: &str, edit: &dyn Fn(String) -> String) {
    let text = std::fs::read_to_string(data("su2_def/inv_wedge_ROE.cfg")).unwrap();
    std::fs::write(dir.join(cfg), edit(text)).unwrap();
    std::fs::copy(
        data("wedge_inv_periodic_ffd.su2"),
        dir.join("mesh_wedge_inv_FFD.su2"),
    )
    .unwrap();
}

/// ref_su2_def.py's (surface error, volume error, largest displacement).
fn reference(dir: &Path, out: &str, moves: &[&str]) -> [f64; 3] {
    let (before, after) = (dir.join("mesh_wedge_inv_FFD.su2"), dir.join(out));
    let mut args = vec![
        before.to_str().unwrap(),
        after.to_str().unwrap(),
        "lower",
        "2ND_DERIVATIVE",
        "1e6",
    ];
    args.extend(moves);
    let out = common::python::run_script(&tool("ref_su2_def.py"), &args);
    let v: Vec<f64> = (out.split_whitespace())
        .map(|t| t.parse().unwrap())
        .collect();
    [v[0], v[1], v[2]]
}

#[test]
fn su2s_wedge_case_runs_unchanged_and_matches_independent_ffd_and_elasticity() {
    let d = tmp_dir("su2-def-wedge");
    wedge_case(&d, "inv_wedge_ROE.cfg", &|t| t);
    // Unchanged: SU2's material (nu = DEFORM_COEFF = 1e6 by default) converges within SU2's
    // 500 iterations to DEFORM_LINEAR_SOLVER_ERROR= 1E-14.
    let r = deform_json(&d, &["--json", "su2", "inv_wedge_ROE.cfg"]);
    assert_eq!(r["converged"], true, "{r}");
    assert_eq!(r["method"], "elasticity");
    assert_eq!(r["stiffness"], "inverse-volume");
    // The report names the motion the config gave, not a rotation by 0°.
    let motions = r.to_string();
    assert!(
        motions.contains("design variables") && !motions.contains("rotate 0"),
        "{r}"
    );
    let ignored: Vec<&str> = (r["ignored_options"].as_array().unwrap().iter())
        .map(|v| v.as_str().unwrap())
        .collect();
    // Read by the FFD variables: not ignored; only for FFD_SETTING or FFD_TWIST: ignored.
    for used in ["FFD_CONTINUITY", "DV_PARAM", "DEFORM_LINEAR_SOLVER_ITER"] {
        assert!(!ignored.contains(&used), "{used} in {ignored:?}");
    }
    for unused in [
        "FFD_TOLERANCE",
        "FFD_DEFINITION",
        "REF_LENGTH",
        "MACH_NUMBER",
    ] {
        assert!(ignored.contains(&unused), "{unused} not in {ignored:?}");
    }
    let residual = r["residual"].as_f64().unwrap();
    assert!(residual < 1e-5, "{r}");
    // DV_PARAM= (MAIN_BOX, 3,0, 0,1.0,0,0 ), DV_VALUE= 0.5: control points (3, 0, k) up by 0.5.
    let [surface, volume, largest] = reference(&d, "mesh_out.su2", &["cp2d:MAIN_BOX:3:0:0:0.5"]);
    assert!(largest > 0.05, "the surface moved by {largest}");
    assert!(surface < 1e-14, "surface vs numpy Bernstein: {surface}");
    // The iterative solve agrees with scikit-fem's direct solve of SU2's material.
    assert!(
        volume < 1e-9 * largest.max(1.0),
        "volume vs scikit-fem: {volume}"
    );

    // The same case solved to 1e-12 (only the two solver options changed): to 1e-9.
    wedge_case(&d, "converged.cfg", &|t| {
        t.replace(
            "DEFORM_LINEAR_SOLVER_ITER= 500",
            "DEFORM_LINEAR_SOLVER_ITER= 20000",
        )
        .replace(
            "DEFORM_LINEAR_SOLVER_ERROR= 1E-14",
            "DEFORM_LINEAR_SOLVER_ERROR= 1E-12",
        )
        .replace("MESH_OUT_FILENAME= mesh_out.su2", "MESH_OUT_FILENAME= conv")
    });
    let r = deform_json(&d, &["--json", "su2", "converged.cfg"]);
    assert_eq!(r["converged"], true);
    // MESH_OUT_FILENAME without an extension: SU2's writer adds .su2.
    assert_eq!(r["outputs"], serde_json::json!(["conv.su2"]));
    let [surface, volume, largest] = reference(&d, "conv.su2", &["cp2d:MAIN_BOX:3:0:0:0.5"]);
    assert!(
        surface < 1e-14 && volume < 1e-9 * largest.max(1.0),
        "{surface} {volume}"
    );
}

#[test]
fn planes_where_the_surface_crosses_the_box_stay_fixed() {
    let d = tmp_dir("su2-def-fixed-planes");
    // The lower wall crosses the box faces i = 0 and i = 10: with 2ND_DERIVATIVE, SU2 keeps
    // i = 0, 1, 2 and 8, 9, 10; a variable on i = 1 moves nothing, on i = 7 it moves.
    let cfg = |i: usize, extra: &'static str| {
        move |t: String| {
            t.replace(
                "DV_PARAM= (MAIN_BOX, 3,0, 0,1.0,0,0 )",
                &format!("DV_PARAM= (MAIN_BOX, {i},0, 0,1.0 )\n{extra}"),
            )
        }
    };
    let run = |name: &str, i: usize, extra: &'static str| {
        wedge_case(&d, name, &cfg(i, extra));
        deform_ok(&d, &["su2", name, "--method", "spring"]);
        let out = read_su2(&d.join("mesh_out.su2"));
        let before = read_su2(&d.join("mesh_wedge_inv_FFD.su2"));
        let moved = (out.points.iter().zip(&before.points))
            .map(|(a, b)| (a[1] - b[1]).abs())
            .fold(0.0, f64::max);
        std::fs::remove_file(d.join("mesh_out.su2")).unwrap();
        moved
    };
    assert_eq!(run("i1.cfg", 1, ""), 0.0);
    assert!(run("i7.cfg", 7, "") > 0.01);
    // FFD_CONTINUITY= USER_INPUT: only FFD_FIX_I's planes; i = 1 moves, i = 7 does not.
    let user = "FFD_CONTINUITY= USER_INPUT\nFFD_FIX_I= ( 7 )";
    let t = std::fs::read_to_string(data("su2_def/inv_wedge_ROE.cfg")).unwrap();
    let strip = |t: String| t.replace("FFD_CONTINUITY= 2ND_DERIVATIVE", "");
    assert!(t.contains("FFD_CONTINUITY= 2ND_DERIVATIVE"));
    let run_user = |name: &str, i: usize| {
        wedge_case(&d, name, &|t| strip(cfg(i, user)(t)));
        deform_ok(&d, &["su2", name, "--method", "spring"]);
        let out = read_su2(&d.join("mesh_out.su2"));
        let before = read_su2(&d.join("mesh_wedge_inv_FFD.su2"));
        std::fs::remove_file(d.join("mesh_out.su2")).unwrap();
        (out.points.iter().zip(&before.points))
            .map(|(a, b)| (a[1] - b[1]).abs())
            .fold(0.0, f64::max)
    };
    assert!(run_user("u1.cfg", 1) > 0.01);
    assert_eq!(run_user("u7.cfg", 7), 0.0);
}

/// Bernstein polynomial B_i^n(t), written out here.
fn bernstein(n: u32, i: u32, t: f64) -> f64 {
    let binom = (1..=i).fold(1.0, |b, k| b * f64::from(n - k + 1) / f64::from(k));
    binom * t.powi(i as i32) * (1.0 - t).powi((n - i) as i32)
}

/// The box around the generated wing: corners, degrees (3, 2, 1).
const BOX: ([f64; 3], [f64; 3]) = ([-0.5, -0.5, -0.1], [2.5, 1.5, 0.3]);
const DEG: [usize; 3] = [3, 2, 1];

/// A surface point of the box: node, point, parametric coordinates.
type SurfacePoint = (u32, [f64; 3], [f64; 3]);

/// A 6 × 4 × 3 hexahedral block [0, 2] × [0, 1] × [0, 0.5] whose z = 0 face is marker `wing`
/// (the rest `far`), with an FFD box `B` around the wing as SU2 stores it.
fn wing_mesh(dir: &Path) -> Vec<SurfacePoint> {
    let (nx, ny, nz) = (6usize, 4usize, 3usize);
    let id = |i: usize, j: usize, k: usize| (k * (ny + 1) + j) * (nx + 1) + i;
    let mut pts = Vec::new();
    for k in 0..=nz {
        for j in 0..=ny {
            for i in 0..=nx {
                pts.push([
                    2.0 * i as f64 / nx as f64,
                    j as f64 / ny as f64,
                    0.5 * k as f64 / nz as f64,
                ]);
            }
        }
    }
    let mut s = format!("NDIME= 3\nNELEM= {}\n", nx * ny * nz);
    let mut e = 0;
    for k in 0..nz {
        for j in 0..ny {
            for i in 0..nx {
                let c = [
                    id(i, j, k),
                    id(i + 1, j, k),
                    id(i + 1, j + 1, k),
                    id(i, j + 1, k),
                ];
                let t = c.map(|n| n + (nx + 1) * (ny + 1));
                s += &format!(
                    "12 {} {} {} {} {} {} {} {} {e}\n",
                    c[0], c[1], c[2], c[3], t[0], t[1], t[2], t[3]
                );
                e += 1;
            }
        }
    }
    s += &format!("NPOIN= {}\n", pts.len());
    for (n, p) in pts.iter().enumerate() {
        s += &format!("{:e} {:e} {:e} {n}\n", p[0], p[1], p[2]);
    }
    let (wing, far) = block_faces(nx, ny, nz);
    s += &format!(
        "NMARK= 2\nMARKER_TAG= wing\nMARKER_ELEMS= {}\n{}",
        wing.len(),
        wing.concat()
    );
    s += &format!(
        "MARKER_TAG= far\nMARKER_ELEMS= {}\n{}",
        far.len(),
        far.concat()
    );
    let (ffd, surface) = ffd_section(&pts, (nx + 1) * (ny + 1));
    s += &ffd;
    std::fs::write(dir.join("wing.su2"), s).unwrap();
    surface
}

/// The boundary quads of the `nx × ny × nz` block: the z = 0 face (`wing`) and the rest.
fn block_faces(nx: usize, ny: usize, nz: usize) -> (Vec<String>, Vec<String>) {
    let id = |i: usize, j: usize, k: usize| (k * (ny + 1) + j) * (nx + 1) + i;
    let quad = |a: usize, b: usize, c: usize, d: usize| format!("9 {a} {b} {c} {d}\n");
    let (mut wing, mut far) = (Vec::new(), Vec::new());
    for j in 0..ny {
        for i in 0..nx {
            wing.push(quad(
                id(i, j, 0),
                id(i, j + 1, 0),
                id(i + 1, j + 1, 0),
                id(i + 1, j, 0),
            ));
            far.push(quad(
                id(i, j, nz),
                id(i + 1, j, nz),
                id(i + 1, j + 1, nz),
                id(i, j + 1, nz),
            ));
        }
    }
    for k in 0..nz {
        for j in 0..ny {
            far.push(quad(
                id(0, j, k),
                id(0, j + 1, k),
                id(0, j + 1, k + 1),
                id(0, j, k + 1),
            ));
            far.push(quad(
                id(nx, j, k),
                id(nx, j, k + 1),
                id(nx, j + 1, k + 1),
                id(nx, j + 1, k),
            ));
        }
        for i in 0..nx {
            far.push(quad(
                id(i, 0, k),
                id(i, 0, k + 1),
                id(i + 1, 0, k + 1),
                id(i + 1, 0, k),
            ));
            far.push(quad(
                id(i, ny, k),
                id(i + 1, ny, k),
                id(i + 1, ny, k + 1),
                id(i, ny, k + 1),
            ));
        }
    }
    (wing, far)
}

/// The FFD section of box `B` (as SU2 stores it) with the first `wing` points as its surface
/// points; the text and the surface points (node, point, parametric coordinates).
fn ffd_section(pts: &[[f64; 3]], wing: usize) -> (String, Vec<SurfacePoint>) {
    let (lo, hi) = BOX;
    let mut s = String::from("FFD_NBOX= 1\nFFD_NLEVEL= 1\nFFD_TAG= B\nFFD_LEVEL= 0\nFFD_DEGREE_I= 3\nFFD_DEGREE_J= 2\nFFD_DEGREE_K= 1\nFFD_BLENDING= BEZIER\nFFD_PARENTS= 0\nFFD_CHILDREN= 0\nFFD_CORNER_POINTS= 8\n");
    for k in 0..2 {
        for (x, y) in [
            (lo[0], lo[1]),
            (hi[0], lo[1]),
            (hi[0], hi[1]),
            (lo[0], hi[1]),
        ] {
            s += &format!("{x} {y} {}\n", [lo[2], hi[2]][k]);
        }
    }
    s += "FFD_CONTROL_POINTS= 24\n";
    for (i, j, k) in control_indices() {
        let p = control_point(i, j, k);
        s += &format!("{i} {j} {k} {:e} {:e} {:e}\n", p[0], p[1], p[2]);
    }
    // The wing (z = 0) nodes are the first `wing` nodes.
    let mut surface = Vec::new();
    for (n, &p) in pts.iter().enumerate().take(wing) {
        let uvw: [f64; 3] = std::array::from_fn(|a| (p[a] - lo[a]) / (hi[a] - lo[a]));
        surface.push((n as u32, p, uvw));
    }
    s += &format!("FFD_SURFACE_POINTS= {}\n", surface.len());
    for (n, _, u) in &surface {
        s += &format!("wing {n} {:e} {:e} {:e}\n", u[0], u[1], u[2]);
    }
    (s, surface)
}

fn control_indices() -> Vec<(usize, usize, usize)> {
    let mut v = Vec::new();
    for i in 0..=DEG[0] {
        for j in 0..=DEG[1] {
            for k in 0..=DEG[2] {
                v.push((i, j, k));
            }
        }
    }
    v
}

fn control_point(i: usize, j: usize, k: usize) -> [f64; 3] {
    let (lo, hi) = BOX;
    let f = [
        i as f64 / DEG[0] as f64,
        j as f64 / DEG[1] as f64,
        k as f64 / DEG[2] as f64,
    ];
    std::array::from_fn(|a| lo[a] + (hi[a] - lo[a]) * f[a])
}

/// Runs `deform su2` on the wing with the design-variable lines; the surface displacements.
fn wing_run(dir: &Path, name: &str, design: &str) -> Vec<[f64; 3]> {
    let surface = wing_mesh(dir);
    let cfg = format!(
        "MESH_FILENAME= wing.su2\nMESH_OUT_FILENAME= {name}.su2\nMARKER_EULER= ( wing )\n\
         MARKER_FAR= ( far )\nDV_MARKER= ( wing )\n{design}\n"
    );
    std::fs::write(dir.join(format!("{name}.cfg")), cfg).unwrap();
    deform_ok(dir, &["su2", &format!("{name}.cfg"), "--method", "idw"]);
    let out = read_su2(&dir.join(format!("{name}.su2")));
    (surface.iter())
        .map(|(n, p, _)| std::array::from_fn(|a| out.points[*n as usize][a] - p[a]))
        .collect()
}

fn close(got: &[[f64; 3]], want: &[[f64; 3]]) {
    for (g, w) in got.iter().zip(want) {
        for a in 0..3 {
            assert!((g[a] - w[a]).abs() < 1e-13, "{g:?} vs {w:?}");
        }
    }
}

#[test]
fn ffd_camber_and_thickness_move_the_k_layers_as_su2() {
    let d = tmp_dir("su2-def-camber");
    let surface = wing_mesh(&d);
    // FFD_CAMBER (B, 1, 1) by a: (1, 1, 0) and (1, 1, 1) up by a; FFD_THICKNESS (B, 2, 1) by
    // b: (2, 1, 0) down by b and (2, 1, 1) up by b. OPT_RELAX_FACTOR scales both.
    let got = wing_run(
        &d,
        "ct",
        "DV_KIND= FFD_CAMBER, FFD_THICKNESS\nDV_PARAM= ( B, 1, 1 ); ( B, 2, 1 )\n\
         DV_VALUE= 0.02, 0.03\nOPT_RELAX_FACTOR= 2",
    );
    let (a, b) = (0.04, 0.06);
    let want: Vec<[f64; 3]> = (surface.iter())
        .map(|(_, _, [u, v, w])| {
            let camber = a * bernstein(3, 1, *u) * bernstein(2, 1, *v);
            let k = bernstein(1, 1, *w) - bernstein(1, 0, *w);
            let thickness = b * bernstein(3, 2, *u) * bernstein(2, 1, *v) * k;
            [0.0, 0.0, camber + thickness]
        })
        .collect();
    assert!(want.iter().any(|w| w[2].abs() > 1e-3));
    close(&got, &want);
}

#[test]
fn ffd_twist_turns_layer_j_about_the_y_axis_through_the_segment() {
    let d = tmp_dir("su2-def-twist");
    let surface = wing_mesh(&d);
    // FFD_TWIST (B, j = 1, segment (1, -1, 0.05)–(1, 2, 0.05)): layer j = 1 (y = 0.5) turns by
    // atan(DV_VALUE / REF_LENGTH) about the y-parallel axis through x = 1, z = 0.05.
    let got = wing_run(
        &d,
        "tw",
        "DV_KIND= FFD_TWIST\nDV_PARAM= ( B, 1, 1.0, -1.0, 0.05, 1.0, 2.0, 0.05 )\n\
         DV_VALUE= 0.3\nREF_LENGTH= 2.0",
    );
    let theta = (0.3f64 / 2.0).atan();
    let (c, s) = (theta.cos(), theta.sin());
    let (ax, az) = (1.0, 0.05);
    let want: Vec<[f64; 3]> = (surface.iter())
        .map(|(_, _, [u, v, w])| {
            let mut dx = [0.0; 3];
            for i in 0..=3 {
                for k in 0..=1 {
                    let p = control_point(i, 1, k);
                    let x = ax + (p[0] - ax) * c + (p[2] - az) * s;
                    let z = az + (p[2] - az) * c - (p[0] - ax) * s;
                    let b = bernstein(3, i as u32, *u)
                        * bernstein(2, 1, *v)
                        * bernstein(1, k as u32, *w);
                    dx[0] += (x - p[0]) * b;
                    dx[2] += (z - p[2]) * b;
                }
            }
            dx
        })
        .collect();
    assert!(want.iter().any(|w| w[0].abs() > 1e-3));
    close(&got, &want);
    // A segment that misses the layer's plane: SU2 silently moves nothing; refused here.
    std::fs::write(
        d.join("miss.cfg"),
        "MESH_FILENAME= wing.su2\nMESH_OUT_FILENAME= miss.su2\nDV_MARKER= ( wing )\n\
         DV_KIND= FFD_TWIST\nDV_PARAM= ( B, 1, 1, 0.7, 0, 1, 2, 0 )\nDV_VALUE= 0.3\n",
    )
    .unwrap();
    deform_refused(
        &d,
        &["su2", "miss.cfg", "--method", "idw"],
        1,
        "segment",
        "miss.su2",
    );
}

#[test]
fn scale_and_translation_add_up_as_su2s_surface_variables() {
    let d = tmp_dir("su2-def-scale");
    naca_mesh(&d, "inviscid", 48, 12, "m.su2");
    let cfg = "MESH_FILENAME= m.su2\nMESH_OUT_FILENAME= out.su2\nMARKER_EULER= ( airfoil )\n\
               MARKER_FAR= ( farfield )\nDV_MARKER= ( airfoil )\n\
               DV_KIND= SCALE, TRANSLATION\nDV_PARAM= ( 1.0 ); ( 1.0, 0.5, 0.0 )\n\
               DV_VALUE= 1.02, 0.01\nOPT_RELAX_FACTOR= 1.5\n";
    std::fs::write(d.join("s.cfg"), cfg).unwrap();
    deform_ok(&d, &["su2", "s.cfg", "--method", "spring"]);
    let (before, after) = (read_su2(&d.join("m.su2")), read_su2(&d.join("out.su2")));
    let nodes: std::collections::BTreeSet<u32> = (before.markers.iter())
        .filter(|m| m.name == "airfoil")
        .flat_map(|m| m.elements.nodes.iter().copied())
        .collect();
    // SetScale: (A − 1) x with A = 1.02 × 1.5; SetTranslation: 0.01 × 1.5 × (1, 0.5).
    let a = 1.02 * 1.5;
    for n in nodes {
        let (p, q) = (before.points[n as usize], after.points[n as usize]);
        let want = [(a - 1.0) * p[0] + 0.015, (a - 1.0) * p[1] + 0.0075];
        for k in 0..2 {
            assert!((q[k] - p[k] - want[k]).abs() < 1e-14, "node {n}");
        }
    }
}

#[test]
fn ffd_options_su2_would_compute_otherwise_are_refused_by_name() {
    let d = tmp_dir("su2-def-refused");
    let refuse = |extra: &str, needle: &str| {
        let extra = extra.to_string();
        wedge_case(&d, "r.cfg", &move |t| format!("{t}{extra}\n"));
        deform_refused(
            &d,
            &["su2", "r.cfg", "--method", "spring"],
            1,
            needle,
            "mesh_out.su2",
        );
    };
    // The wedge's variable moves the surface by 0.053: beyond a bound of 0.01 SU2 rescales.
    refuse("OPT_LINE_SEARCH_BOUND= 0.01", "OPT_LINE_SEARCH_BOUND");
    refuse("FFD_INTPREV= YES", "FFD_INTPREV");
    refuse(
        "FFD_COORDINATE_SYSTEM= CYLINDRICAL",
        "FFD_COORDINATE_SYSTEM",
    );
    refuse("FFD_BLENDING= BSPLINE", "FFD_BLENDING");
    refuse("FFD_SYMMETRY_PLANE= MAYBE", "FFD_SYMMETRY_PLANE");
    let bad_continuity = |t: String| t.replace("= 2ND_DERIVATIVE", "= 3RD_DERIVATIVE");
    wedge_case(&d, "c.cfg", &bad_continuity);
    deform_refused(
        &d,
        &["su2", "c.cfg", "--method", "spring"],
        1,
        "FFD_CONTINUITY (line",
        "mesh_out.su2",
    );
    // FFD and surface kinds mixed: SU2 would apply only the first family.
    let mixed = |t: String| {
        t.replace(
            "DV_KIND= FFD_CONTROL_POINT_2D",
            "DV_KIND= FFD_CONTROL_POINT_2D, HICKS_HENNE",
        )
        .replace(
            "DV_PARAM= (MAIN_BOX, 3,0, 0,1.0,0,0 )",
            "DV_PARAM= (MAIN_BOX, 3,0, 0,1.0 ); ( 1, 0.5 )",
        )
        .replace("DV_VALUE= 0.5", "DV_VALUE= 0.5, 0.01")
    };
    wedge_case(&d, "m.cfg", &mixed);
    deform_refused(
        &d,
        &["su2", "m.cfg", "--method", "spring"],
        1,
        "DV_KIND",
        "mesh_out.su2",
    );
    // A bound the surface stays within: runs.
    wedge_case(&d, "ok.cfg", &|t| {
        format!("{t}OPT_LINE_SEARCH_BOUND= 0.06\nFFD_SYMMETRY_PLANE= NO\n")
    });
    deform_ok(&d, &["su2", "ok.cfg", "--method", "spring"]);
}
