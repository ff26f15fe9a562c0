//! CGNS files (`--features cgns`) on public files (cli/tests/data/README.md), checked with the
//! CGNS library's own tools and HDF5's, never with the tool's reader: `cgns_to_plot3d` for
//! structured zones, `h5dump` (after `adf2hdf` for ADF files) for coordinates and element
//! connectivity, `cgnscheck` for files the tool writes. Needs `cgns_to_plot3d`, `adf2hdf`,
//! `cgnscheck` (Debian's cgns-convert) and `h5dump` (hdf5-tools); `cargo xtask ci` installs
//! them and runs this file with the feature. Without the feature, a CGNS file is refused with
//! exit 3 and the way to enable it.

mod common;

use std::path::{Path, PathBuf};
#[cfg(feature = "cgns")]
use std::process::Command;

use common::tmp_dir;

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(name)
}

/// Runs `deform`, asserting success.
#[cfg(feature = "cgns")]
fn ok(dir: &Path, args: &[&str]) {
    common::deform_ok(dir, args);
}

#[cfg(not(feature = "cgns"))]
#[test]
fn without_the_feature_cgns_is_refused_with_the_way_to_enable_it() {
    let d = tmp_dir("cgns-off");
    for f in ["su2_wedge_inv.cgns", "cfl3d_n4412_structured.cgns"] {
        // Under a name that says nothing: recognised by the signature (HDF5, ADF).
        std::fs::copy(data(f), d.join("mesh.dat")).unwrap();
        let o = common::deform(&d, &["quality", "mesh.dat"]);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(3), "{f}: {err}");
        assert!(
            err.contains("--features cgns") && err.contains("libcgns-dev"),
            "{err}"
        );
    }
}

/// Runs a tool of the CGNS or HDF5 distribution.
#[cfg(feature = "cgns")]
fn tool(dir: &Path, name: &str, args: &[&str]) {
    let o = Command::new(name)
        .current_dir(dir)
        .args(args)
        .output()
        .unwrap_or_else(|e| panic!("{name} on PATH (cargo xtask ci installs it): {e}"));
    assert!(
        o.status.success(),
        "{name} {args:?}: {}{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    );
}

/// The raw little-endian values of an HDF5 dataset, by h5dump.
#[cfg(feature = "cgns")]
fn h5(dir: &Path, file: &str, dataset: &str) -> Vec<u8> {
    tool(
        dir,
        "h5dump",
        &["-d", dataset, "-b", "LE", "-o", "h5.bin", file],
    );
    std::fs::read(dir.join("h5.bin")).unwrap()
}

#[cfg(feature = "cgns")]
fn f64s(b: &[u8]) -> Vec<f64> {
    b.chunks_exact(8)
        .map(|c| f64::from_le_bytes(c.try_into().unwrap()))
        .collect()
}

#[cfg(feature = "cgns")]
fn i32s(b: &[u8]) -> Vec<i64> {
    b.chunks_exact(4)
        .map(|c| i64::from(i32::from_le_bytes(c.try_into().unwrap())))
        .collect()
}

/// Points, volume cells and markers of an SU2 file, read here: (points, cells, markers).
#[cfg(feature = "cgns")]
type Su2 = (Vec<[f64; 3]>, Vec<Vec<i64>>, Vec<(String, Vec<Vec<i64>>)>);

#[cfg(feature = "cgns")]
fn su2(path: &Path) -> Su2 {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines().map(str::trim).filter(|l| !l.starts_with('%'));
    let count = |l: &str| {
        l.split('=')
            .nth(1)
            .unwrap()
            .trim()
            .parse::<usize>()
            .unwrap()
    };
    let (mut dim, mut pts, mut cells, mut markers) = (0, Vec::new(), Vec::new(), Vec::new());
    let row = |l: &str| -> Vec<i64> { l.split_whitespace().map(|t| t.parse().unwrap()).collect() };
    while let Some(l) = lines.next() {
        if l.starts_with("NDIME=") {
            dim = count(l);
        } else if l.starts_with("NELEM=") {
            for _ in 0..count(l) {
                let r = row(lines.next().unwrap());
                cells.push(r[1..r.len() - 1].to_vec());
            }
        } else if l.starts_with("NPOIN=") {
            for _ in 0..count(l) {
                let v: Vec<f64> = lines
                    .next()
                    .unwrap()
                    .split_whitespace()
                    .map(|t| t.parse().unwrap())
                    .collect();
                pts.push([v[0], v[1], if dim == 3 { v[2] } else { 0.0 }]);
            }
        } else if let Some(name) = l.strip_prefix("MARKER_TAG=") {
            let n = count(lines.next().unwrap());
            let elems = (0..n)
                .map(|_| row(lines.next().unwrap())[1..].to_vec())
                .collect();
            markers.push((name.trim().to_string(), elems));
        }
    }
    (pts, cells, markers)
}

/// Structured (ADF, NASA's CFL3D example): read, written, smoothed and moved; each result
/// decoded by the CGNS library's `cgns_to_plot3d` equals the tool's Plot3D of the same work.
#[cfg(feature = "cgns")]
#[test]
fn structured_zones_are_plot3d_blocks_both_ways() {
    let d = tmp_dir("cgns-structured");
    std::fs::copy(data("cfl3d_n4412_structured.cgns"), d.join("n.cgns")).unwrap();
    let p3d = |cgns: &str, out: &str| {
        tool(&d, "cgns_to_plot3d", &["-d", "-n", cgns, out]);
        std::fs::read(d.join(out)).unwrap()
    };
    ok(&d, &["convert", "n.cgns", "a.x"]);
    let a = std::fs::read(d.join("a.x")).unwrap();
    assert!(
        p3d("n.cgns", "ref.xyz") == a,
        "read: cgns_to_plot3d and deform differ"
    );
    ok(&d, &["convert", "a.x", "b.cgns"]);
    tool(&d, "cgnscheck", &["b.cgns"]);
    assert!(
        p3d("b.cgns", "b.xyz") == a,
        "write: the library reads other values back"
    );
    let smooth = ["--direction", "j", "--iterations", "5"];
    ok(
        &d,
        &[&["smooth", "n.cgns", "--out", "s.cgns"][..], &smooth].concat(),
    );
    ok(
        &d,
        &[&["smooth", "a.x", "--out", "s.x"][..], &smooth].concat(),
    );
    tool(&d, "cgnscheck", &["s.cgns"]);
    assert!(
        p3d("s.cgns", "s.xyz") == std::fs::read(d.join("s.x")).unwrap(),
        "smooth"
    );
    let tfi = ["--method", "tfi", "--wall", "jmin", "--rotate", "1"];
    ok(
        &d,
        &[&["move", "n.cgns", "--out", "t.cgns"][..], &tfi].concat(),
    );
    ok(&d, &[&["move", "a.x", "--out", "t.x"][..], &tfi].concat());
    assert!(
        p3d("t.cgns", "t.xyz") == std::fs::read(d.join("t.x")).unwrap(),
        "move"
    );
}

/// Unstructured 2D (HDF5, written by Pointwise for SU2's wedge case): coordinates, quads and
/// each boundary section equal what h5dump decodes; a move keeps sections and boundary
/// conditions (and the families the tool does not read) and moves the marker's nodes exactly; SU2 → CGNS → SU2 is exact.
#[cfg(feature = "cgns")]
#[test]
fn unstructured_2d_reads_moves_and_round_trips() {
    let d = tmp_dir("cgns-wedge");
    std::fs::copy(data("su2_wedge_inv.cgns"), d.join("w.cgns")).unwrap();
    let coord = |f: &str, zone: &str, c: &str| {
        f64s(&h5(
            &d,
            f,
            &format!("/Base/{zone}/GridCoordinates/Coordinate{c}/ data"),
        ))
    };
    let (x, y) = (coord("w.cgns", "dom-1", "X"), coord("w.cgns", "dom-1", "Y"));
    ok(&d, &["convert", "w.cgns", "w.su2"]);
    let (pts, cells, markers) = su2(&d.join("w.su2"));
    assert_eq!(pts.len(), x.len());
    assert!(pts
        .iter()
        .zip(x.iter().zip(&y))
        .all(|(p, (a, b))| p[0] == *a && p[1] == *b));
    let quads = i32s(&h5(
        &d,
        "w.cgns",
        "/Base/dom-1/QuadElements/ElementConnectivity/ data",
    ));
    let ours: Vec<i64> = cells.iter().flatten().map(|n| n + 1).collect();
    assert_eq!(ours, quads);
    let names: Vec<&str> = markers.iter().map(|m| m.0.as_str()).collect();
    assert_eq!(names, ["inlet", "lower", "outlet", "upper"]);
    for (name, elems) in &markers {
        let conn = i32s(&h5(
            &d,
            "w.cgns",
            &format!("/Base/dom-1/{name}/ElementConnectivity/ data"),
        ));
        let ours: Vec<i64> = elems.iter().flatten().map(|n| n + 1).collect();
        assert_eq!(ours, conn, "marker {name}");
    }
    // Move the lower wall; the library's file keeps everything but the coordinates.
    let mv = [
        "move",
        "w.cgns",
        "--marker",
        "lower",
        "--translate",
        "0.001,0.002",
        "--method",
        "idw",
        "--out",
        "m.cgns",
    ];
    ok(&d, &mv);
    tool(&d, "cgnscheck", &["m.cgns"]);
    let (mx, my) = (coord("m.cgns", "dom-1", "X"), coord("m.cgns", "dom-1", "Y"));
    let lower = &markers[1].1;
    for &n in lower.iter().flatten() {
        let n = n as usize;
        assert_eq!((mx[n], my[n]), (x[n] + 0.001, y[n] + 0.002), "node {n}");
    }
    // What the tool does not model (families) is kept too.
    for kept in [
        "/Base/dom-1/lower/ElementConnectivity/ data",
        "/Base/dom-1/FamilyName/ data",
        "/Base/inlet/FamBC/ data",
    ] {
        assert!(h5(&d, "m.cgns", kept) == h5(&d, "w.cgns", kept), "{kept}");
    }
    // SU2 → a new CGNS file → SU2: the same file.
    ok(&d, &["convert", "w.su2", "n.cgns"]);
    tool(&d, "cgnscheck", &["n.cgns"]);
    assert!(coord("n.cgns", "Zone", "X") == x);
    ok(&d, &["convert", "n.cgns", "n.su2"]);
    assert!(std::fs::read(d.join("n.su2")).unwrap() == std::fs::read(d.join("w.su2")).unwrap());
}

/// Unstructured 3D (ADF, SU2's tetrahedral cylinder with six boundary sections and vertex
/// boundary conditions): counts and coordinates as h5dump decodes them after `adf2hdf`, the
/// sections as markers, and an exact SU2 → CGNS → SU2 round trip.
#[cfg(feature = "cgns")]
#[test]
fn unstructured_3d_adf_reads_and_round_trips() {
    let d = tmp_dir("cgns-cyl");
    std::fs::copy(data("su2_cylinder3d.cgns"), d.join("c.cgns")).unwrap();
    tool(&d, "adf2hdf", &["c.cgns", "h.cgns"]);
    let zone = "/BASE#1/project";
    let z = f64s(&h5(
        &d,
        "h.cgns",
        &format!("{zone}/GridCoordinates/CoordinateZ/ data"),
    ));
    let tets = i32s(&h5(
        &d,
        "h.cgns",
        &format!("{zone}/TETS/ElementConnectivity/ data"),
    ));
    ok(&d, &["convert", "c.cgns", "c.su2"]);
    let (pts, cells, markers) = su2(&d.join("c.su2"));
    assert!(pts.iter().map(|p| p[2]).eq(z.iter().copied()));
    assert_eq!(
        cells.iter().flatten().map(|n| n + 1).collect::<Vec<_>>(),
        tets
    );
    for (name, elems) in &markers {
        let conn = i32s(&h5(
            &d,
            "h.cgns",
            &format!("{zone}/{name}/ElementConnectivity/ data"),
        ));
        assert_eq!(
            elems.iter().flatten().map(|n| n + 1).collect::<Vec<_>>(),
            conn,
            "{name}"
        );
    }
    assert_eq!(markers.len(), 6);
    ok(&d, &["convert", "c.su2", "r.cgns"]);
    tool(&d, "cgnscheck", &["r.cgns"]);
    ok(&d, &["convert", "r.cgns", "r.su2"]);
    assert!(std::fs::read(d.join("r.su2")).unwrap() == std::fs::read(d.join("c.su2")).unwrap());
}

/// Mixed hexahedra, prisms, pyramids and tetrahedra in one `MIXED` section (ADF, SU2's bend
/// case): each cell has the nodes h5dump decodes, and every prism turns the way the hexahedra
/// do in SU2's convention (CGNS lists a `PENTA_6` base towards its top; SU2 away from it),
/// checked with the geometry here; SU2 → CGNS (`MIXED`, written with offsets) → SU2 is exact.
#[cfg(feature = "cgns")]
#[test]
fn mixed_sections_and_prism_orientation() {
    let d = tmp_dir("cgns-bend");
    std::fs::copy(data("su2_bend_mixed.cgns"), d.join("b.cgns")).unwrap();
    tool(&d, "adf2hdf", &["b.cgns", "h.cgns"]);
    let mixed = i32s(&h5(
        &d,
        "h.cgns",
        "/BASE#1/box/SOLID_1_1_SOLID/ElementConnectivity/ data",
    ));
    ok(&d, &["convert", "b.cgns", "b.su2"]);
    let (pts, cells, _) = su2(&d.join("b.su2"));
    // CGNS MIXED: type code, then its nodes (npe by type: TETRA_4 10, PYRA_5 12, PENTA_6 14,
    // HEXA_8 17).
    let (mut at, mut theirs) = (0, Vec::new());
    while at < mixed.len() {
        let n = match mixed[at] {
            10 => 4,
            12 => 5,
            14 => 6,
            17 => 8,
            t => panic!("type {t}"),
        };
        let mut set: Vec<i64> = mixed[at + 1..at + 1 + n].iter().map(|v| v - 1).collect();
        set.sort_unstable();
        theirs.push(set);
        at += 1 + n;
    }
    let ours: Vec<Vec<i64>> = cells
        .iter()
        .map(|c| {
            let mut s = c.clone();
            s.sort_unstable();
            s
        })
        .collect();
    assert_eq!(ours, theirs);
    // Sign of (base normal) · (top centroid − base centroid), base = the first 4 (hexahedron)
    // or 3 (prism) nodes: SU2 wants hexahedra positive and prisms negative.
    let sign = |c: &[i64], k: usize| {
        let p = |i: usize| pts[c[i] as usize];
        let sub = |a: [f64; 3], b: [f64; 3]| [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
        let (u, v) = (sub(p(1), p(0)), sub(p(2), p(0)));
        let n = [
            u[1] * v[2] - u[2] * v[1],
            u[2] * v[0] - u[0] * v[2],
            u[0] * v[1] - u[1] * v[0],
        ];
        let centroid = |r: std::ops::Range<usize>| {
            let m = r.len() as f64;
            r.fold([0.0; 3], |s, i| {
                [s[0] + p(i)[0] / m, s[1] + p(i)[1] / m, s[2] + p(i)[2] / m]
            })
        };
        let h = sub(centroid(k..2 * k), centroid(0..k));
        (n[0] * h[0] + n[1] * h[1] + n[2] * h[2]).signum()
    };
    let hexes: Vec<f64> = cells
        .iter()
        .filter(|c| c.len() == 8)
        .map(|c| sign(c, 4))
        .collect();
    let prisms: Vec<f64> = cells
        .iter()
        .filter(|c| c.len() == 6)
        .map(|c| sign(c, 3))
        .collect();
    assert!(
        !hexes.is_empty() && hexes.iter().all(|&s| s == 1.0),
        "{hexes:?}"
    );
    assert!(
        !prisms.is_empty() && prisms.iter().all(|&s| s == -1.0),
        "{prisms:?}"
    );
    ok(&d, &["convert", "b.su2", "r.cgns"]);
    tool(&d, "cgnscheck", &["r.cgns"]);
    ok(&d, &["convert", "r.cgns", "r.su2"]);
    assert!(std::fs::read(d.join("r.su2")).unwrap() == std::fs::read(d.join("b.su2")).unwrap());
}
