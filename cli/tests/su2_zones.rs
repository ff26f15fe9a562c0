//! Multi-zone SU2 files (`NZONE=`, `IZONE=`) on SU2's public sliding-interface mesh
//! (cli/tests/data/README.md): every zone is read, `move` deforms the zone of the named markers
//! and keeps the other zones byte for byte, a marker name is resolved per zone (`K:NAME`, or an
//! error naming the zones when ambiguous), markers of several zones in one run exit 3, and
//! `convert` keeps the zones. Checked with an independent minimal reader written here.

mod common;

use std::path::{Path, PathBuf};

use common::{deform, tmp_dir};
use serde_json::Value;

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(name)
}

const FILE: &str = "su2_uniform_flow_2zones.su2";

/// One zone as an independent reader sees it: its text, points, and marker nodes by name.
struct Zone {
    text: String,
    points: Vec<[f64; 2]>,
    markers: Vec<(String, Vec<usize>)>,
}

/// Splits at `IZONE=` lines and reads each zone's points and marker nodes (2D files only).
fn zones(text: &str) -> (String, Vec<Zone>) {
    let starts: Vec<usize> = text
        .match_indices("IZONE=")
        .map(|(i, _)| i)
        .filter(|&i| i == 0 || text.as_bytes()[i - 1] == b'\n')
        .collect();
    let mut out = Vec::new();
    for (k, &s) in starts.iter().enumerate() {
        let end = starts.get(k + 1).copied().unwrap_or(text.len());
        out.push(zone(&text[s..end]));
    }
    (text[..starts[0]].to_string(), out)
}

fn zone(text: &str) -> Zone {
    let mut lines = text.lines().map(str::trim);
    let (mut points, mut markers) = (Vec::new(), Vec::new());
    let count = |l: &str| {
        l.split('=')
            .nth(1)
            .unwrap()
            .trim()
            .parse::<usize>()
            .unwrap()
    };
    while let Some(l) = lines.next() {
        if l.starts_with("NPOIN=") {
            for _ in 0..count(l) {
                let v: Vec<f64> = lines
                    .next()
                    .unwrap()
                    .split_whitespace()
                    .take(2)
                    .map(|t| t.parse().unwrap())
                    .collect();
                points.push([v[0], v[1]]);
            }
        } else if let Some(name) = l.strip_prefix("MARKER_TAG=") {
            let n = count(lines.next().unwrap());
            let mut nodes: Vec<usize> = (0..n)
                .flat_map(|_| {
                    let e: Vec<usize> = lines
                        .next()
                        .unwrap()
                        .split_whitespace()
                        .skip(1)
                        .map(|t| t.parse().unwrap())
                        .collect();
                    e
                })
                .collect();
            nodes.sort_unstable();
            nodes.dedup();
            markers.push((name.trim().to_string(), nodes));
        }
    }
    Zone {
        text: text.to_string(),
        points,
        markers,
    }
}

fn run(dir: &Path, args: &[&str]) -> (Option<i32>, String, Value) {
    let mut v = vec!["--json"];
    v.extend_from_slice(args);
    let o = deform(dir, &v);
    let json = serde_json::from_slice(&o.stdout).unwrap_or(Value::Null);
    (
        o.status.code(),
        String::from_utf8_lossy(&o.stderr).into_owned(),
        json,
    )
}

/// Moves `marker` by `t` with IDW; checks that zone `moved` is the one deformed (its marker
/// nodes exactly translated), and every other zone is byte for byte the input's.
fn move_and_check(dir: &Path, input: &Path, marker: &str, moved: usize, plain: &str) {
    let (code, err, _) = run(
        dir,
        &[
            "move",
            input.to_str().unwrap(),
            "--marker",
            marker,
            "--translate",
            "0.01,-0.02",
            "--method",
            "idw",
            "--out",
            "out.su2",
        ],
    );
    assert_eq!(code, Some(0), "{marker}: {err}");
    let before = zones(&std::fs::read_to_string(input).unwrap());
    let after = zones(&std::fs::read_to_string(dir.join("out.su2")).unwrap());
    assert_eq!(before.0, after.0, "the header is kept");
    assert_eq!(before.1.len(), after.1.len());
    for (k, (b, a)) in before.1.iter().zip(&after.1).enumerate() {
        if k + 1 != moved {
            assert!(a.text == b.text, "zone {} is not byte for byte", k + 1);
            continue;
        }
        assert_eq!(a.points.len(), b.points.len());
        assert_eq!(
            a.markers,
            b.markers,
            "zone {}: markers as in the file",
            k + 1
        );
        let nodes = &b.markers.iter().find(|m| m.0 == plain).unwrap().1;
        for &n in nodes {
            let (p, q) = (b.points[n], a.points[n]);
            assert_eq!(q, [p[0] + 0.01, p[1] - 0.02], "node {n}");
        }
        assert!(a.points != b.points);
    }
}

#[test]
fn every_zone_is_read_and_the_moved_zone_alone_changes() {
    let d = tmp_dir("su2-zones-move");
    let file = data(FILE);
    let (_, zs) = zones(&std::fs::read_to_string(&file).unwrap());
    assert_eq!(zs.len(), 2);
    let (code, err, q) = run(&d, &["quality", file.to_str().unwrap()]);
    assert_eq!(code, Some(0), "{err}");
    let n: usize = zs.iter().map(|z| z.points.len()).sum();
    assert_eq!(q["nodes"], n, "{q}");
    move_and_check(&d, &file, "internal_interface", 2, "internal_interface");
    move_and_check(&d, &file, "2:internal_interface", 2, "internal_interface");
    move_and_check(&d, &file, "inlet", 1, "inlet");
}

#[test]
fn marker_names_resolve_per_zone() {
    let d = tmp_dir("su2-zones-names");
    // Both zones with an `inlet` (zone 2's interface renamed): the plain name is ambiguous.
    let text = std::fs::read_to_string(data(FILE)).unwrap();
    let amb = d.join("amb.su2");
    std::fs::write(&amb, text.replace("internal_interface", "inlet")).unwrap();
    let mv = |m: &str| {
        let a = amb.to_str().unwrap();
        let args = [
            "move", a, "--marker", m, "--rotate", "3", "--method", "idw", "--out", "o.su2",
        ];
        run(&d, &args)
    };
    let (code, err, _) = mv("inlet");
    assert_eq!(code, Some(1), "{err}");
    assert!(err.contains("1:inlet or 2:inlet"), "{err}");
    assert!(!d.join("o.su2").exists());
    let (code, err, _) = mv("nowhere");
    assert_eq!(code, Some(1), "{err}");
    assert!(err.contains("zone 2: inlet"), "{err}");
    move_and_check(&d, &amb, "2:inlet", 2, "inlet");
    move_and_check(&d, &amb, "1:inlet", 1, "inlet");
    // Markers of two zones in one run: not supported (exit 3), nothing written.
    std::fs::remove_file(d.join("out.su2")).unwrap();
    let file = data(FILE);
    let args = [
        "move",
        file.to_str().unwrap(),
        "--marker",
        "inlet",
        "--marker",
        "internal_interface",
        "--translate",
        "0.01,0",
        "--method",
        "idw",
        "--out",
        "out.su2",
    ];
    let (code, err, _) = run(&d, &args);
    assert_eq!(code, Some(3), "{err}");
    assert!(err.contains("one zone per run"), "{err}");
    assert!(!d.join("out.su2").exists());
}

#[test]
fn convert_keeps_the_zones_and_round_trips() {
    let d = tmp_dir("su2-zones-convert");
    let file = data(FILE);
    let before = zones(&std::fs::read_to_string(&file).unwrap());
    let (code, err, _) = run(&d, &["convert", file.to_str().unwrap(), "a.su2"]);
    assert_eq!(code, Some(0), "{err}");
    let (code, err, _) = run(&d, &["convert", "a.su2", "b.su2"]);
    assert_eq!(code, Some(0), "{err}");
    // As CGNS the zones would not come back (one unstructured zone per file): exit 3.
    let (code, err, _) = run(&d, &["convert", file.to_str().unwrap(), "a.cgns"]);
    assert_eq!(code, Some(3), "{err}");
    assert!(!d.join("a.cgns").exists());
    let a = std::fs::read(d.join("a.su2")).unwrap();
    assert!(a == std::fs::read(d.join("b.su2")).unwrap());
    let after = zones(&String::from_utf8(a).unwrap());
    assert_eq!(before.0, after.0);
    for (b, a) in before.1.iter().zip(&after.1) {
        assert_eq!(b.points, a.points);
        assert_eq!(b.markers, a.markers);
    }
}
