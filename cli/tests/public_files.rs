//! The `deform` tool on public SU2 files (cli/tests/data/README.md): read under their own
//! names, valid meshes report 0 folded cells whatever their orientation, and the sections the
//! tool does not use (periodic, FFD) pass through `move` and `convert` byte for byte. Counts
//! and orientations are checked with an independent minimal reader written here.

mod common;

use std::path::{Path, PathBuf};
use std::process::Command;

use common::tmp_dir;
use serde_json::Value;

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(name)
}

fn json(dir: &Path, args: &[&str]) -> Value {
    let o = Command::new(env!("CARGO_BIN_EXE_deform"))
        .current_dir(dir)
        .arg("--json")
        .args(args)
        .output()
        .expect("run deform");
    assert_eq!(
        o.status.code(),
        Some(0),
        "{args:?}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    serde_json::from_slice(&o.stdout).unwrap()
}

/// Volume elements as (VTK code, nodes).
type Elements = Vec<(u32, Vec<usize>)>;

/// Independent minimal SU2 reader: (dim, points, volume elements).
fn independent(text: &str) -> (usize, Vec<[f64; 3]>, Elements) {
    let mut lines = text
        .lines()
        .map(|l| l.split('%').next().unwrap().trim())
        .filter(|l| !l.is_empty());
    let mut dim = 0;
    let mut points = Vec::new();
    let mut cells = Vec::new();
    while let Some(l) = lines.next() {
        let value = |l: &str| {
            l.split('=')
                .nth(1)
                .unwrap()
                .trim()
                .parse::<usize>()
                .unwrap()
        };
        if l.starts_with("NDIME=") {
            dim = value(l);
        } else if l.starts_with("NELEM=") {
            for _ in 0..value(l) {
                let t: Vec<usize> = lines
                    .next()
                    .unwrap()
                    .split_whitespace()
                    .map(|x| x.parse().unwrap())
                    .collect();
                let n = match t[0] {
                    5 => 3,
                    9 => 4,
                    10 => 4,
                    12 => 8,
                    13 => 6,
                    14 => 5,
                    c => panic!("code {c}"),
                };
                cells.push((t[0] as u32, t[1..=n].to_vec()));
            }
        } else if l.starts_with("NPOIN=") {
            for _ in 0..value(l) {
                let t: Vec<f64> = lines
                    .next()
                    .unwrap()
                    .split_whitespace()
                    .take(dim)
                    .map(|x| x.parse().unwrap())
                    .collect();
                points.push([t[0], t[1], if dim == 3 { t[2] } else { 0.0 }]);
            }
        } else if l.starts_with("NMARK=") {
            break;
        }
    }
    (dim, points, cells)
}

/// Signed area of a 2D polygon cell (shoelace).
fn area(points: &[[f64; 3]], nodes: &[usize]) -> f64 {
    let k = nodes.len();
    (0..k)
        .map(|i| {
            let (a, b) = (points[nodes[i]], points[nodes[(i + 1) % k]]);
            a[0] * b[1] - a[1] * b[0]
        })
        .sum::<f64>()
        / 2.0
}

#[test]
fn a_public_clockwise_mesh_is_valid() {
    let d = tmp_dir("public-clockwise");
    let file = data("naca64a010_hybrid_clockwise.su2");
    let (dim, points, cells) = independent(&std::fs::read_to_string(&file).unwrap());
    assert_eq!(dim, 2);
    let negative = cells.iter().filter(|(_, n)| area(&points, n) < 0.0).count();
    assert_eq!(
        negative,
        cells.len(),
        "every cell of this public mesh is clockwise"
    );
    let q = json(&d, &["quality", file.to_str().unwrap()]);
    assert_eq!(q["cells"], cells.len());
    assert_eq!(q["folded_cells"], 0, "{q}");
    assert_eq!(q["nonpositive_cells"], 0, "{q}");
    assert_eq!(q["orientation"]["negative_regions"], 1, "{q}");
    // A pitch of the clockwise mesh: the report counts folds relative to clockwise, and equals
    // an independent count on the written file (cells whose area is no longer negative).
    let r = json(
        &d,
        &[
            "move",
            file.to_str().unwrap(),
            "--marker",
            "airfoil",
            "--rotate",
            "3",
            "--center",
            "0.25,0",
            "--method",
            "quaternion",
            "--out",
            "pitched.su2",
        ],
    );
    let (_, moved, _) = independent(&std::fs::read_to_string(d.join("pitched.su2")).unwrap());
    let flipped = cells.iter().filter(|(_, n)| area(&moved, n) >= 0.0).count();
    assert_eq!(r["inverted_cells"], flipped, "{r}");
    assert_eq!(r["orientation"], "clockwise", "{r}");
}

/// The bytes from the `NPERIODIC=` line to the end of a file.
fn tail(bytes: &[u8]) -> &[u8] {
    let at = bytes
        .windows(10)
        .position(|w| w == b"NPERIODIC=")
        .expect("NPERIODIC section");
    &bytes[at..]
}

#[test]
fn periodic_and_ffd_sections_pass_through_move_and_convert() {
    let d = tmp_dir("public-passthrough");
    for (name, marker, dim) in [
        ("wedge_inv_periodic_ffd.su2", "lower", 2),
        ("brick_hex_periodic_ffd.su2", "z_m", 3),
    ] {
        let file = data(name);
        let input = std::fs::read(&file).unwrap();
        let (idim, points, cells) = independent(&String::from_utf8_lossy(&input));
        assert_eq!(idim, dim);
        let q = json(&d, &["quality", file.to_str().unwrap()]);
        assert_eq!(q["cells"], cells.len(), "{name}");
        assert_eq!(q["nodes"], points.len(), "{name}");
        assert_eq!(q["folded_cells"], 0, "{name}: {q}");
        let translate = if dim == 2 { "0,0.001" } else { "0,0,0.001" };
        json(
            &d,
            &[
                "move",
                file.to_str().unwrap(),
                "--marker",
                marker,
                "--translate",
                translate,
                "--method",
                "spring",
                "--out",
                "moved.su2",
            ],
        );
        let moved = std::fs::read(d.join("moved.su2")).unwrap();
        assert_eq!(
            tail(&moved),
            tail(&input),
            "{name}: move keeps the sections byte for byte"
        );
        json(&d, &["convert", file.to_str().unwrap(), "converted.su2"]);
        let converted = std::fs::read(d.join("converted.su2")).unwrap();
        assert_eq!(
            tail(&converted),
            tail(&input),
            "{name}: convert keeps them too"
        );
        // And what was written reads back with the same points.
        let (_, again, _) = independent(&String::from_utf8_lossy(&converted));
        assert_eq!(again, points);
    }
}

#[test]
fn markertag_is_read_like_marker_tag() {
    let d = tmp_dir("public-markertag");
    let text = std::fs::read_to_string(data("wedge_inv_periodic_ffd.su2")).unwrap();
    let variant = text.replace("MARKER_TAG=", "MARKERTAG=");
    assert_ne!(variant, text);
    std::fs::write(d.join("markertag.su2"), &variant).unwrap();
    let a = deform_cli::parse_su2(text.as_bytes()).unwrap();
    let b = deform_cli::parse_su2(variant.as_bytes()).unwrap();
    assert_eq!(a.markers, b.markers);
    let q = json(&d, &["quality", "markertag.su2"]);
    assert_eq!(q["folded_cells"], 0);
}
