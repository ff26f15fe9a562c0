//! End-to-end runs of the `deform` binary on files the tests generate.

mod common;

use std::process::Output;

use common::{deform, listing, mesh_2d, mesh_3d, su2_bytes, tmp_dir};

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Asserts a failure: exit code, a single stderr line containing `needle`, empty stdout.
fn assert_fails(o: &Output, code: i32, needle: &str) {
    let err = stderr(o);
    assert_eq!(o.status.code(), Some(code), "stderr: {err}");
    assert!(err.contains(needle), "expected {needle:?} in {err:?}");
    assert_eq!(err.trim_end().lines().count(), 1, "one line: {err:?}");
    assert!(err.starts_with("deform: error: "), "{err:?}");
    assert!(
        o.stdout.is_empty(),
        "stdout on failure: {:?}",
        String::from_utf8_lossy(&o.stdout)
    );
}

#[test]
fn help_for_every_command() {
    let d = tmp_dir("help");
    for args in [
        vec!["--help"],
        vec!["demo", "--help"],
        vec!["mesh", "naca", "--help"],
        vec!["move", "--help"],
        vec!["smooth", "--help"],
        vec!["quality", "--help"],
        vec!["convert", "--help"],
    ] {
        let o = deform(&d, &args);
        assert_eq!(o.status.code(), Some(0), "{args:?}");
        assert!(
            String::from_utf8_lossy(&o.stdout).contains("Usage:"),
            "{args:?}"
        );
    }
    let o = deform(&d, &["move", "--json"]);
    assert_eq!(o.status.code(), Some(2), "bad command line");
    let o = deform(&d, &["frobnicate"]);
    assert_eq!(o.status.code(), Some(2));
}

#[test]
fn convert_su2_to_su2_and_vtu() {
    let d = tmp_dir("convert-su2");
    std::fs::write(d.join("m.su2"), su2_bytes(&mesh_2d(6, 4))).expect("write");
    let o = deform(&d, &["convert", "m.su2", "copy.su2"]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert_eq!(
        std::fs::read(d.join("copy.su2")).expect("copy"),
        std::fs::read(d.join("m.su2")).expect("orig")
    );
    let o = deform(&d, &["--json", "convert", "m.su2", "m.vtu"]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).expect("JSON report");
    assert_eq!(v["points"], 35);
    assert_eq!(v["cells"], 30);
    assert_eq!(v["outputs"][0], "m.vtu");
    assert!(v["seconds"].as_f64().is_some());
    let xml = std::fs::read_to_string(d.join("m.vtu")).expect("vtu");
    assert!(xml.contains("<UnstructuredGrid>") && xml.trim_end().ends_with("</VTKFile>"));
    assert_eq!(listing(&d), ["copy.su2", "m.su2", "m.vtu"]);

    std::fs::write(d.join("c.su2"), su2_bytes(&mesh_3d())).expect("write");
    let o = deform(&d, &["convert", "c.su2", "c.vtu"]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
}

#[test]
fn convert_plot3d_layouts_and_vts() {
    let d = tmp_dir("convert-p3d");
    let text = "2\n3 2\n2 2\n0 1 2 0 1 2\n0 0 0 1 1 1\n5 6 5 6\n0 0 1 1\n";
    std::fs::write(d.join("g.xyz"), text).expect("write");
    let o = deform(
        &d,
        &[
            "convert",
            "g.xyz",
            "g.x",
            "--out-encoding",
            "binary",
            "--out-precision",
            "f32",
            "--out-endian",
            "big",
            "--out-records",
            "no",
        ],
    );
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let bin = std::fs::read(d.join("g.x")).expect("binary");
    assert_eq!(bin.len(), 4 + 4 * 4 + 10 * 8);
    // And back to ASCII: identical text values.
    let o = deform(
        &d,
        &[
            "--json",
            "convert",
            "g.x",
            "back.p3d",
            "--out-encoding",
            "ascii",
        ],
    );
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).expect("JSON");
    assert_eq!(v["blocks"], 2);
    assert!(
        v["input_format"]
            .as_str()
            .expect("str")
            .contains("f32 big-endian"),
        "{v}"
    );
    let o = deform(&d, &["convert", "back.p3d", "grid.vts"]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert_eq!(
        listing(&d),
        ["back.p3d", "g.x", "g.xyz", "grid_b1.vts", "grid_b2.vts"]
    );
}

const GOOD: &str = "NDIME= 2\nNELEM= 2\n5 0 1 2\n5 0 2 3\nNPOIN= 4\n0 0\n1 0\n1 1\n0 1\nNMARK= 2\nMARKER_TAG= wall\nMARKER_ELEMS= 1\n3 0 1\nMARKER_TAG= far\nMARKER_ELEMS= 3\n3 1 2\n3 2 3\n3 3 0\n";

/// Runs `args` in a directory holding only `in.su2` = `content`; checks the failure and that
/// nothing else was written.
fn fails_on(name: &str, content: &str, args: &[&str], code: i32, needle: &str) {
    let d = tmp_dir(name);
    std::fs::write(d.join("in.su2"), content).expect("write");
    let o = deform(&d, args);
    assert_fails(&o, code, needle);
    assert_eq!(listing(&d), ["in.su2"], "no output left behind");
}

const CONVERT: &[&str] = &["convert", "in.su2", "out.su2"];
const QUALITY: &[&str] = &["quality", "in.su2", "--vtk", "out.vtu"];
const MOVE: &[&str] = &[
    "move", "in.su2", "--marker", "wall", "--rotate", "5", "--method", "spring", "--out",
    "out.su2", "--vtk", "out.vtu",
];

#[test]
fn malformed_su2_fails_cleanly() {
    let truncated = &GOOD[..GOOD.find("1 1\n").expect("fixture")];
    fails_on(
        "trunc",
        truncated,
        CONVERT,
        1,
        "in.su2: line 8: unexpected end of file, expected point 3 of 4",
    );
    fails_on(
        "trunc-move",
        truncated,
        MOVE,
        1,
        "line 8: unexpected end of file",
    );
    fails_on(
        "trunc-quality",
        truncated,
        QUALITY,
        1,
        "line 8: unexpected end of file",
    );
    fails_on(
        "code-quality",
        &GOOD.replace("5 0 2 3", "12 0 2 3 1 4 5 6 7"),
        QUALITY,
        1,
        "line 4: bad element type code 12, expected 5, 9",
    );
    fails_on(
        "nan-quality",
        &GOOD.replace("0 1\n", "0 -inf\n"),
        QUALITY,
        1,
        "line 9: y of point 3 is not a finite number",
    );
    fails_on(
        "count",
        &GOOD.replace("NELEM= 2", "NELEM= 3"),
        CONVERT,
        1,
        "line 5: expected element 3 of 3",
    );
    fails_on(
        "code",
        &GOOD.replace("5 0 2 3", "8 0 2 3"),
        CONVERT,
        1,
        "line 4: bad element type code 8, expected 5, 9",
    );
    fails_on(
        "nan",
        &GOOD.replace("1 1\n", "nan 1\n"),
        MOVE,
        1,
        "line 8: x of point 2 is not a finite number",
    );
    fails_on(
        "marker-count",
        &GOOD.replace("NMARK= 2", "NMARK= 3"),
        CONVERT,
        1,
        "line 19: unexpected end of file, expected MARKER_TAG= (marker 3 of 3",
    );
    fails_on(
        "garbage",
        "\u{7f}ELF\u{2}\u{1}\u{1}\u{0}",
        CONVERT,
        1,
        "in.su2: line 1: expected a keyword line",
    );
    fails_on(
        "missing-marker",
        GOOD,
        &MOVE
            .iter()
            .map(|s| if *s == "wall" { "airfoil" } else { s })
            .collect::<Vec<_>>(),
        1,
        "marker \"airfoil\" not found (markers: wall, far)",
    );
    fails_on(
        "no-file",
        GOOD,
        &["convert", "nope.su2", "out.su2"],
        1,
        "nope.su2:",
    );
    fails_on(
        "bad-target",
        GOOD,
        &["convert", "in.su2", "out.txt"],
        1,
        "cannot convert in.su2 to out.txt",
    );
}

#[test]
fn malformed_plot3d_fails_cleanly() {
    let d = tmp_dir("p3d-bad");
    std::fs::write(d.join("g.xyz"), "2 3\n0 1 0 1\n0 0 1 1\n").expect("write");
    let o = deform(&d, &["convert", "g.xyz", "out.x"]);
    assert_fails(&o, 1, "g.xyz: line 3: expected");
    std::fs::write(d.join("n.xyz"), "2 2\n0 1 0 NaN\n0 0 1 1\n").expect("write");
    let o = deform(
        &d,
        &[
            "smooth",
            "n.xyz",
            "--direction",
            "i",
            "--iterations",
            "3",
            "--out",
            "s.x",
        ],
    );
    assert_fails(
        &o,
        1,
        "n.xyz: line 2: x of point 3 of block 1 is not a finite number",
    );
    let o = deform(&d, &["convert", "g.xyz", "out.x", "--dim", "4"]);
    assert_eq!(o.status.code(), Some(2));
    assert_eq!(listing(&d), ["g.xyz", "n.xyz"]);
}

#[test]
fn move_validates_its_arguments() {
    let d = tmp_dir("move-args");
    std::fs::write(d.join("in.su2"), GOOD).expect("write");
    let base = [
        "move", "in.su2", "--marker", "wall", "--method", "spring", "--out", "o.su2",
    ];
    let with = |extra: &[&str]| {
        let mut v: Vec<&str> = base.to_vec();
        v.extend_from_slice(extra);
        deform(&d, &v)
    };
    // Motion is required and exclusive.
    assert_eq!(with(&[]).status.code(), Some(2));
    assert_eq!(
        with(&["--rotate", "2", "--translate", "1,0"]).status.code(),
        Some(2)
    );
    assert_fails(
        &with(&["--translate", "1,0,1"]),
        1,
        "a 2D mesh cannot move in z",
    );
    assert_fails(
        &with(&["--rotate", "2", "--axis", "1,0,0"]),
        1,
        "a 2D mesh rotates about z only",
    );
    std::fs::write(d.join("disp.txt"), "0 0.1 0\n2 0.1 0\n").expect("write");
    assert_fails(
        &with(&["--displacements", "disp.txt"]),
        1,
        "disp.txt: node 2 is not on the moved markers",
    );
    std::fs::write(d.join("disp.txt"), "0 0.1\n").expect("write");
    assert_fails(
        &with(&["--displacements", "disp.txt"]),
        1,
        "disp.txt: line 1: expected",
    );
    assert_eq!(listing(&d), ["disp.txt", "in.su2"]);
}
