//! Warnings that save a user's day (issue 31 item 6): boundary faces in no marker, `--wall`
//! naming a block of a multi-block grid, a default `--method`, volume wording in 3D reports and
//! a clear refusal for lines with zero-length segments.

mod common;

use std::path::{Path, PathBuf};

use common::{deform, deform_json, deform_refused, tmp_dir};

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(name)
}

/// SU2's half cylinder: 20 edges of the cylinder's surface (radius 1) are in no marker (counted
/// independently: 180 boundary edges, 160 of them in the markers).
#[test]
fn boundary_faces_in_no_marker_are_reported_and_their_motion_warned() {
    let d = tmp_dir("warn-unmarked");
    let name = "cylinder_half_unmarked_wall.su2";
    std::fs::copy(data(name), d.join(name)).expect("copy");
    let q = deform_json(&d, &["--json", "quality", name]);
    assert_eq!(q["unmarked_boundary_faces"], 20, "{q}");
    let s: Vec<f64> = q["unmarked_boundary_sample"]
        .as_array()
        .expect("sample")
        .iter()
        .map(|v| v.as_f64().expect("number"))
        .collect();
    let r = s[0].hypot(s[1]);
    assert!(
        (0.99..=1.0).contains(&r),
        "sample {s:?} not on the cylinder"
    );
    let text = String::from_utf8_lossy(&deform(&d, &["quality", name]).stdout).into_owned();
    assert!(text.contains("boundary faces in no marker"), "{text}");
    // Moving the marked wall drags the unmarked part of the surface like the field: warned.
    let o = deform(
        &d,
        &[
            "--json",
            "move",
            name,
            "--marker",
            "wall",
            "--translate",
            "0.05,0",
            "--out",
            "m.su2",
        ],
    );
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("belong to no marker"), "{err}");
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).expect("JSON");
    assert_eq!(v["unmarked_boundary_faces"], 20);
    assert!(v["unmarked_boundary_max_displacement"].as_f64().expect("d") > 0.0);
    // A mesh whose boundary is all in markers says nothing.
    common::naca_mesh(&d, "inviscid", 32, 12, "n.su2");
    let o = deform(
        &d,
        &[
            "move", "n.su2", "--marker", "airfoil", "--rotate", "2", "--out", "nm.su2",
        ],
    );
    assert_eq!(o.status.code(), Some(0));
    assert!(!String::from_utf8_lossy(&o.stderr).contains("no marker"));
}

/// Two 2D blocks side by side in one ASCII Plot3D file (block count, then dimensions).
fn two_blocks(dir: &Path) -> Vec<Vec<[f64; 3]>> {
    let (ni, nj) = (5, 4);
    let mut s = format!("2\n{ni} {nj}\n{ni} {nj}\n");
    let mut blocks = Vec::new();
    for b in 0..2 {
        let pts: Vec<[f64; 3]> = (0..nj)
            .flat_map(|j| (0..ni).map(move |i| [(b * 10 + i) as f64 * 0.5, j as f64 * 0.5, 0.0]))
            .collect();
        for c in 0..2 {
            let v: Vec<String> = pts.iter().map(|p| format!("{:?}", p[c])).collect();
            s.push_str(&v.join(" "));
            s.push('\n');
        }
        blocks.push(pts);
    }
    std::fs::write(dir.join("two.xy"), s).expect("write");
    blocks
}

fn read_blocks(path: &Path) -> Vec<Vec<[f64; 3]>> {
    let bytes = std::fs::read(path).expect("read");
    let g = deform_cli::parse_plot3d(&bytes, &Default::default())
        .expect("grid")
        .0;
    g.blocks.into_iter().map(|b| b.points).collect()
}

#[test]
fn wall_on_a_multi_block_grid_names_its_block() {
    let d = tmp_dir("warn-wall-block");
    let input = two_blocks(&d);
    let args = |wall: &str| {
        vec![
            "--json".to_string(),
            "move".into(),
            "two.xy".into(),
            "--wall".into(),
            wall.into(),
            "--translate".into(),
            "0,0.1".into(),
            "--out".into(),
            "o.xy".into(),
        ]
    };
    let refuse = |wall: &str, needle: &str| {
        let a = args(wall);
        let a: Vec<&str> = a.iter().map(String::as_str).collect();
        deform_refused(&d, &a, 1, needle, "o.xy");
    };
    refuse("jmin", "the grid has 2 blocks: say whose jmin face moves");
    refuse("3:jmin", "the grid has 2 block(s)");
    let a = args("2:jmin");
    let a: Vec<&str> = a.iter().map(String::as_str).collect();
    let r = deform_json(&d, &a);
    // Without --method a Plot3D grid gets the quaternion TFI.
    assert_eq!(r["method"], "tfi");
    assert_eq!(r["wall"], "2:jmin");
    assert_eq!(r["moved_blocks"], serde_json::json!([2]));
    let out = read_blocks(&d.join("o.xy"));
    assert_eq!(out[0], input[0], "block 1 must not move");
    for i in 0..5 {
        let (p, q) = (input[1][i], out[1][i]);
        assert_eq!([q[0], q[1]], [p[0], p[1] + 0.1], "block 2 jmin point {i}");
    }
    let a = args("all:jmin");
    let a: Vec<&str> = a.iter().map(String::as_str).collect();
    let r = deform_json(&d, &a);
    assert_eq!(r["moved_blocks"], serde_json::json!([1, 2]));
    let out = read_blocks(&d.join("o.xy"));
    assert_eq!(out[0][0][1], input[0][0][1] + 0.1);
    // A bad block spelling is a command-line error.
    let o = deform(
        &d,
        &[
            "move",
            "two.xy",
            "--wall",
            "x:jmin",
            "--translate",
            "0,1",
            "--out",
            "p.xy",
        ],
    );
    assert_eq!(o.status.code(), Some(2));
}

#[test]
fn three_d_reports_say_volume() {
    let d = tmp_dir("warn-volume");
    std::fs::copy(data("mixed_elements_knowles.su2"), d.join("m3.su2")).expect("copy");
    let r = deform_json(
        &d,
        &[
            "--json",
            "move",
            "m3.su2",
            "--marker",
            "load",
            "--translate",
            "0,0.001,0",
            "--out",
            "o.su2",
        ],
    );
    assert!(r.get("min_volume_ratio").is_some(), "{r}");
    assert!(r.get("min_area_ratio").is_none(), "{r}");
    let q = deform_json(&d, &["--json", "quality", "o.su2", "--reference", "m3.su2"]);
    assert!(q.get("max_volume_ratio").is_some(), "{q}");
    assert!(q.get("max_area_ratio").is_none(), "{q}");
    // 2D keeps the area words.
    common::naca_mesh(&d, "inviscid", 32, 12, "n.su2");
    let q = deform_json(&d, &["--json", "quality", "n.su2", "--reference", "n.su2"]);
    assert!(q.get("min_area_ratio").is_some(), "{q}");
}

#[test]
fn a_line_with_a_zero_length_segment_is_named_before_smoothing() {
    let d = tmp_dir("warn-zero-segment");
    // 6 × 4 grid; on row j = 2 the points i = 3 and i = 4 coincide.
    let (ni, nj) = (6, 4);
    let mut xs = Vec::new();
    let mut ys = Vec::new();
    for j in 0..nj {
        for i in 0..ni {
            let x = if j == 1 && i == 3 { 2.0 } else { i as f64 };
            xs.push(format!("{x:?}"));
            ys.push(format!("{:?}", j as f64));
        }
    }
    let s = format!("1\n{ni} {nj}\n{}\n{}\n", xs.join(" "), ys.join(" "));
    std::fs::write(d.join("z.xy"), s).expect("write");
    fn smooth(dir: &str) -> Vec<&str> {
        vec![
            "smooth",
            "z.xy",
            "--direction",
            dir,
            "--iterations",
            "5",
            "--out",
            "o.xy",
        ]
    }
    deform_refused(
        &d,
        &smooth("i"),
        1,
        "block 1: the grid line through i=3, j=2 has a segment of zero length",
        "o.xy",
    );
    // Across that line (along j) nothing is of zero length: smoothed.
    assert_eq!(deform(&d, &smooth("j")).status.code(), Some(0));
}
