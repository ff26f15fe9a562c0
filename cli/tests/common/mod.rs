//! Shared test helpers: small generated meshes, a deterministic random generator, and running
//! the `deform` binary (exit codes, JSON reports, NACA meshes, SU2 files read back).
#![allow(dead_code)]

/// The interpreter of the independent Python references (shared with host-tests).
#[path = "../../../host-tests/tests/support/python.rs"]
pub mod python;

use std::path::Path;
use std::process::{Command, Output};

use deform_cli::formats::su2::{Su2Marker, Su2Mesh};
use deform_cli::formats::CellList;
use deform_kernel::CellKind;

/// A tiny xorshift generator (deterministic, no dependencies).
pub struct Rng(pub u64);

impl Rng {
    pub fn next(&mut self) -> u64 {
        let mut x = self.0;
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        self.0 = x;
        x
    }
    pub fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }
    /// A value in [-1, 1) with awkward bits.
    pub fn real(&mut self) -> f64 {
        (self.next() >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    }
}

/// A 2D mesh: an nx × ny grid of quads with the first row split into triangles,
/// with markers "wall" (bottom), "farfield" (top, left, right).
pub fn mesh_2d(nx: usize, ny: usize) -> Su2Mesh {
    let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
    let id = |i: usize, j: usize| (i + (nx + 1) * j) as u32;
    let mut points = Vec::new();
    for j in 0..=ny {
        for i in 0..=nx {
            points.push([
                i as f64 + 0.1 * rng.real(),
                j as f64 * 0.7 + 0.1 * rng.real(),
                0.0,
            ]);
        }
    }
    let mut elements = CellList::new();
    for j in 0..ny {
        for i in 0..nx {
            let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
            if j == 0 {
                elements.push(CellKind::Triangle, &[a, b, c]);
                elements.push(CellKind::Triangle, &[a, c, d]);
            } else {
                elements.push(CellKind::Quad, &[a, b, c, d]);
            }
        }
    }
    let mut wall = CellList::new();
    for i in 0..nx {
        wall.push(CellKind::Line, &[id(i, 0), id(i + 1, 0)]);
    }
    let mut far = CellList::new();
    for i in 0..nx {
        far.push(CellKind::Line, &[id(i + 1, ny), id(i, ny)]);
    }
    for j in 0..ny {
        far.push(CellKind::Line, &[id(0, j + 1), id(0, j)]);
        far.push(CellKind::Line, &[id(nx, j), id(nx, j + 1)]);
    }
    Su2Mesh {
        dim: 2,
        points,
        elements,
        markers: vec![
            Su2Marker {
                name: "wall".into(),
                elements: wall,
            },
            Su2Marker {
                name: "farfield".into(),
                elements: far,
            },
        ],
        passthrough: Vec::new(),
        text: Default::default(),
    }
}

/// A 3D mesh with one of each volume kind (hex, prism, tet, pyramid) sharing nodes, and
/// triangle and quad boundary markers.
pub fn mesh_3d() -> Su2Mesh {
    let mut rng = Rng(12345);
    let mut points = Vec::new();
    for k in 0..3 {
        for j in 0..2 {
            for i in 0..2 {
                points.push([
                    i as f64 + 0.01 * rng.real(),
                    j as f64 + 0.01 * rng.real(),
                    k as f64 * 1e-3 + 1e-9 * rng.real(),
                ]);
            }
        }
    }
    points.push([0.5, 0.5, -1.0]); // 12: pyramid apex below
    points.push([2.0, 0.5, 0.5]); // 13: tet apex
    let mut elements = CellList::new();
    elements.push(CellKind::Hexahedron, &[0, 1, 3, 2, 4, 5, 7, 6]);
    elements.push(CellKind::Prism, &[4, 5, 6, 8, 9, 10]);
    elements.push(CellKind::Pyramid, &[0, 2, 3, 1, 12]);
    elements.push(CellKind::Tetra, &[1, 3, 5, 13]);
    let mut tri = CellList::new();
    tri.push(CellKind::Triangle, &[8, 9, 10]);
    tri.push(CellKind::Triangle, &[1, 3, 13]);
    let mut quad = CellList::new();
    quad.push(CellKind::Quad, &[0, 2, 6, 4]);
    Su2Mesh {
        dim: 3,
        points,
        elements,
        markers: vec![
            Su2Marker {
                name: "top".into(),
                elements: tri,
            },
            Su2Marker {
                name: "side wall".into(),
                elements: quad,
            },
        ],
        passthrough: Vec::new(),
        text: Default::default(),
    }
}

pub fn su2_bytes(mesh: &Su2Mesh) -> Vec<u8> {
    let mut v = Vec::new();
    deform_cli::formats::su2::write_su2(mesh, &mut v).expect("write to a Vec");
    v
}

/// A fresh, empty directory under the target tmp dir, unique per test name.
pub fn tmp_dir(name: &str) -> std::path::PathBuf {
    let d = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("cli-{name}"));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).expect("create test dir");
    d
}

/// File names in `dir`, sorted.
pub fn listing(dir: &std::path::Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .expect("read dir")
        .filter_map(|e| e.ok())
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

/// Runs the `deform` binary in `dir`.
pub fn deform(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_deform"))
        .current_dir(dir)
        .args(args)
        .output()
        .expect("run deform")
}

/// Runs `deform` and asserts that it succeeded (its stderr in the message).
pub fn deform_ok(dir: &Path, args: &[&str]) -> Output {
    let o = deform(dir, args);
    assert_eq!(
        o.status.code(),
        Some(0),
        "{args:?}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    o
}

/// Runs `deform` (with `--json` among `args`), asserts success and parses its report.
pub fn deform_json(dir: &Path, args: &[&str]) -> serde_json::Value {
    serde_json::from_slice(&deform_ok(dir, args).stdout).expect("JSON report")
}

/// Runs `deform` and asserts that it failed with `code`, said `needle` on stderr, and did
/// not write `out`.
pub fn deform_refused(dir: &Path, args: &[&str], code: i32, needle: &str, out: &str) {
    let o = deform(dir, args);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(code), "{args:?}: {err}");
    assert!(err.contains(needle), "expected {needle:?} in {err:?}");
    assert!(!dir.join(out).exists(), "{out} written");
}

/// `deform mesh naca --kind KIND` with `surface` × `radial` points into `dir/out`.
pub fn naca_mesh(dir: &Path, kind: &str, surface: usize, radial: usize, out: &str) {
    let (surface, radial) = (surface.to_string(), radial.to_string());
    deform_ok(
        dir,
        &[
            "mesh",
            "naca",
            "--kind",
            kind,
            "--surface-points",
            &surface,
            "--radial-points",
            &radial,
            "--out",
            out,
        ],
    );
}

/// An SU2 file read back.
pub fn read_su2(path: &Path) -> Su2Mesh {
    deform_cli::parse_su2(&std::fs::read(path).expect("read")).expect("parse SU2")
}

/// Rows `node, values...` of an output CSV (header skipped).
pub fn read_csv(path: &Path) -> Vec<(usize, Vec<f64>)> {
    std::fs::read_to_string(path)
        .expect("output")
        .lines()
        .skip(1)
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            (
                f[0].parse().unwrap(),
                f[1..].iter().map(|x| x.parse().unwrap()).collect(),
            )
        })
        .collect()
}
