//! Plot3D files are recognised by their content under any name, `--format` forces a reader,
//! and damaged files are refused with the byte offset: a UTF-8 BOM or CRLF line ends are read
//! correctly, integers and reals of different byte order are refused, and a corrupted
//! dimension that fits the iblank layout by size is refused for its implausible iblank values.
//! The public C-grid (cli/tests/data/README.md) is decoded independently here.

mod common;

use std::path::{Path, PathBuf};

use common::{deform, tmp_dir};
use serde_json::Value;

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(name)
}

fn json(dir: &Path, args: &[&str]) -> Value {
    let mut v = vec!["--json"];
    v.extend_from_slice(args);
    let o = deform(dir, &v);
    assert_eq!(
        o.status.code(),
        Some(0),
        "{args:?}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    serde_json::from_slice(&o.stdout).unwrap()
}

fn refused(dir: &Path, args: &[&str], code: i32, needles: &[&str]) {
    let o = deform(dir, args);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(code), "{args:?}: {err}");
    for n in needles {
        assert!(err.contains(n), "{n:?} in {err}");
    }
}

/// Independent decoding of the public C-grid: big-endian Fortran records, `ni nj nk`, then
/// x, y, z as f64.
fn cgrid() -> ([usize; 3], Vec<[f64; 3]>) {
    let b = std::fs::read(data("npot_naca_cgrid.dat")).unwrap();
    let int = |at: usize| i32::from_be_bytes(b[at..at + 4].try_into().unwrap()) as usize;
    let real = |at: usize| f64::from_be_bytes(b[at..at + 8].try_into().unwrap());
    assert_eq!(int(0), 12);
    let dims = [int(4), int(8), int(12)];
    let n = dims[0] * dims[1] * dims[2];
    assert_eq!(int(20), 24 * n);
    let pts = (0..n)
        .map(|p| {
            [
                real(24 + 8 * p),
                real(24 + 8 * (n + p)),
                real(24 + 8 * (2 * n + p)),
            ]
        })
        .collect();
    (dims, pts)
}

#[test]
fn a_public_c_grid_is_read_by_content_under_its_own_name() {
    let d = tmp_dir("p3d-cgrid");
    let (dims, pts) = cgrid();
    let file = data("npot_naca_cgrid.dat");
    let q = json(&d, &["quality", file.to_str().unwrap()]);
    assert_eq!(q["nodes"], pts.len());
    assert_eq!(q["cells"], (dims[0] - 1) * (dims[1] - 1));
    assert_eq!(q["folded_cells"], 0, "{q}");
    assert_eq!(q["dim"], 2, "a constant-z k-plane is measured as 2D: {q}");
    // Written as ASCII under a non-standard name, and read back: same points as decoded here.
    json(
        &d,
        &[
            "convert",
            file.to_str().unwrap(),
            "c.p2dfmt",
            "--out-encoding",
            "ascii",
        ],
    );
    let got = deform_cli::parse_plot3d(
        &std::fs::read(d.join("c.p2dfmt")).unwrap(),
        &Default::default(),
    )
    .unwrap()
    .0;
    assert_eq!(got.blocks[0].dims, dims);
    assert_eq!(got.blocks[0].points, pts);
    // Smoothing along i keeps the wake cut closed and every line end in place.
    let r = json(
        &d,
        &[
            "smooth",
            "c.p2dfmt",
            "--direction",
            "i",
            "--iterations",
            "30",
            "--out",
            "s.fmt",
        ],
    );
    assert!(r["pinned_coincident_points"].as_u64().unwrap() > 0, "{r}");
    assert_eq!(r["flipped_cells"], 0, "{r}");
    let s = deform_cli::parse_plot3d(
        &std::fs::read(d.join("s.fmt")).unwrap(),
        &Default::default(),
    )
    .unwrap()
    .0;
    let ni = dims[0];
    for j in 0..dims[1] {
        for i in [0, ni - 1] {
            assert_eq!(s.blocks[0].points[i + ni * j], pts[i + ni * j]);
        }
    }
}

#[test]
fn bom_and_crlf_variants_read_like_the_original() {
    let d = tmp_dir("p3d-bom");
    let file = data("npot_naca_cgrid.dat");
    json(
        &d,
        &[
            "convert",
            file.to_str().unwrap(),
            "c.fmt",
            "--out-encoding",
            "ascii",
        ],
    );
    let text = std::fs::read(d.join("c.fmt")).unwrap();
    let mut bom = b"\xEF\xBB\xBF".to_vec();
    bom.extend_from_slice(&text);
    std::fs::write(d.join("bom.fmt"), &bom).unwrap();
    let crlf: Vec<u8> = String::from_utf8(text.clone())
        .unwrap()
        .replace('\n', "\r\n")
        .into_bytes();
    std::fs::write(d.join("crlf.dat"), &crlf).unwrap();
    let (_, pts) = cgrid();
    for name in ["bom.fmt", "crlf.dat"] {
        let q = json(&d, &["quality", name]);
        assert_eq!(q["nodes"], pts.len(), "{name}");
        json(&d, &["convert", name, "back.x", "--out-encoding", "binary"]);
        let g = deform_cli::parse_plot3d(
            &std::fs::read(d.join("back.x")).unwrap(),
            &Default::default(),
        )
        .unwrap()
        .0;
        assert_eq!(g.blocks[0].points, pts, "{name}");
    }
}

#[test]
fn format_is_detected_from_content_and_can_be_forced() {
    let d = tmp_dir("p3d-format");
    // An SU2 mesh under a Plot3D-looking name is read as SU2.
    let o = deform(
        &d,
        &[
            "mesh",
            "naca",
            "--code",
            "0012",
            "--kind",
            "inviscid",
            "--out",
            "m.su2",
            "--surface-points",
            "24",
            "--radial-points",
            "8",
        ],
    );
    assert!(o.status.success());
    std::fs::copy(d.join("m.su2"), d.join("mesh.dat")).unwrap();
    let q = json(&d, &["quality", "mesh.dat"]);
    assert!(q["format"].as_str().unwrap().starts_with("SU2"), "{q}");
    // Forcing the wrong reader is the reader's clear error, not a guess.
    refused(
        &d,
        &["--format", "plot3d", "quality", "mesh.dat"],
        1,
        &["mesh.dat"],
    );
    let file = data("npot_naca_cgrid.dat");
    refused(
        &d,
        &["--format", "su2", "quality", file.to_str().unwrap()],
        1,
        &["npot_naca_cgrid.dat"],
    );
    // VTK files are output only: "not supported" (exit 3).
    json(&d, &["convert", "m.su2", "m.vtu"]);
    std::fs::copy(d.join("m.vtu"), d.join("m.bin")).unwrap();
    refused(&d, &["quality", "m.bin"], 3, &["reading VTK files"]);
}

/// A raw (no record markers) single-block 3D f64 Plot3D file.
fn raw_grid(dims: [i32; 3], int_be: bool, real_be: bool, values: &[f64]) -> Vec<u8> {
    let mut out = Vec::new();
    for v in dims {
        out.extend(if int_be {
            v.to_be_bytes()
        } else {
            v.to_le_bytes()
        });
    }
    for v in values {
        out.extend(if real_be {
            v.to_be_bytes()
        } else {
            v.to_le_bytes()
        });
    }
    out
}

#[test]
fn mixed_byte_orders_and_implausible_iblank_are_refused_with_the_byte_offset() {
    let d = tmp_dir("p3d-damaged");
    let (ni, nj, nk): (usize, usize, usize) = (7, 4, 1);
    let n = ni * nj * nk;
    let mut values = Vec::new();
    for c in 0..3 {
        for p in 0..n {
            values.push(match c {
                0 => (p % ni) as f64 * 0.5 + 1.0,
                1 => (p / ni) as f64 * 0.25 + 2.0,
                _ => 3.0,
            });
        }
    }
    let dims = [ni as i32, nj as i32, nk as i32];
    std::fs::write(d.join("good.bin"), raw_grid(dims, false, false, &values)).unwrap();
    let q = json(&d, &["quality", "good.bin"]);
    assert_eq!(q["nodes"], n);
    // Little-endian integers, big-endian reals.
    std::fs::write(d.join("mixed.bin"), raw_grid(dims, false, true, &values)).unwrap();
    refused(&d, &["quality", "mixed.bin"], 1, &["mixed.bin", "byte"]);
    // 7×4 points × 24 bytes = 6×4 points × (24 + 4 iblank bytes): a corrupted first dimension
    // (7 → 6) fits the iblank layout by size; the "iblank" values are then pieces of reals.
    std::fs::write(
        d.join("corrupt.bin"),
        raw_grid([6, 4, 1], false, false, &values),
    )
    .unwrap();
    refused(
        &d,
        &["quality", "corrupt.bin"],
        1,
        &["corrupt.bin", "byte", "iblank"],
    );
}
