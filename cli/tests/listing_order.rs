//! Validity independent of the order a cell's nodes are listed in (issue 31 item 1), on two
//! public SU2 meshes that SU2 runs (cli/tests/data/README.md): a piece of the NACA 4412
//! turbulent mesh with 173 convex quads listed clockwise among counter-clockwise ones, and a
//! mixed hexahedron/prism/pyramid structural mesh with 6,304 cells listed left-handed. Neither
//! has a folded cell. The expected numbers come from cli/tests/tools/check_validity.py
//! (numpy + meshio, no code of the tool), and the counts are checked again here with
//! independent signed-measure formulas.

mod common;

use std::path::{Path, PathBuf};

use common::{deform_json, read_su2, tmp_dir};
use deform_cli::formats::su2::Su2Mesh;

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(name)
}

fn copy(dir: &Path, name: &str) {
    std::fs::copy(data(name), dir.join(name)).expect("copy test data");
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn det(a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> f64 {
    a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
        + a[2] * (b[0] * c[1] - b[1] * c[0])
}

/// The sign of a cell as listed, in the SU2/VTK convention, from its own formula per kind: the
/// shoelace area in 2D; in 3D the base's normal against the direction to the top (hexahedra,
/// pyramids; reversed for SU2's prisms) or the tetrahedron's determinant.
fn listed_sign(kind: u8, p: &[[f64; 3]]) -> f64 {
    let mean = |q: &[[f64; 3]]| {
        let n = q.len() as f64;
        q.iter()
            .fold([0.0; 3], |s, x| [s[0] + x[0], s[1] + x[1], s[2] + x[2]])
            .map(|v| v / n)
    };
    // Twice the area vector of a polygon (sum of cross products of consecutive corners).
    let normal = |q: &[[f64; 3]]| {
        (0..q.len()).fold([0.0; 3], |s, i| {
            let (a, b) = (q[i], q[(i + 1) % q.len()]);
            [
                s[0] + a[1] * b[2] - a[2] * b[1],
                s[1] + a[2] * b[0] - a[0] * b[2],
                s[2] + a[0] * b[1] - a[1] * b[0],
            ]
        })
    };
    let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    match kind {
        5 | 9 => normal(p)[2],
        10 => det(sub(p[1], p[0]), sub(p[2], p[0]), sub(p[3], p[0])),
        12 => dot(normal(&p[..4]), sub(mean(&p[4..]), mean(&p[..4]))),
        14 => dot(normal(&p[..4]), sub(p[4], mean(&p[..4]))),
        13 => -dot(normal(&p[..3]), sub(mean(&p[3..]), mean(&p[..3]))),
        _ => panic!("kind {kind}"),
    }
}

fn signs(m: &Su2Mesh) -> Vec<f64> {
    m.elements
        .iter()
        .map(|(kind, nodes)| {
            let p: Vec<[f64; 3]> = nodes.iter().map(|&n| m.points[n as usize]).collect();
            listed_sign(kind, &p)
        })
        .collect()
}

fn negative(m: &Su2Mesh) -> usize {
    signs(m).iter().filter(|&&s| s < 0.0).count()
}

#[test]
fn cells_listed_clockwise_are_not_folded_2d() {
    let d = tmp_dir("listing-2d");
    let name = "naca4412_turb_wake_window.su2";
    copy(&d, name);
    assert_eq!(negative(&read_su2(&d.join(name))), 173);
    let q = deform_json(&d, &["--json", "quality", name]);
    assert_eq!(q["folded_cells"], 0, "{q}");
    assert_eq!(q["nonpositive_cells"], 0);
    assert_eq!(q["orientation"]["cells_listed_reversed"], 173);
    // check_validity.py: min |area| 8.177472160287962e-05.
    let min = q["min_measure"].as_f64().expect("min");
    assert!((min - 8.177472160287962e-05).abs() < 1e-15, "{min}");
}

#[test]
fn cells_listed_mirrored_are_not_folded_3d_and_move_keeps_them_valid() {
    let d = tmp_dir("listing-3d");
    let name = "mixed_elements_knowles.su2";
    copy(&d, name);
    let input = read_su2(&d.join(name));
    assert_eq!(negative(&input), 6304);
    let q = deform_json(&d, &["--json", "quality", name]);
    assert_eq!(q["folded_cells"], 0, "{q}");
    assert_eq!(q["orientation"]["cells_listed_reversed"], 6304);
    let min = q["min_measure"].as_f64().expect("min");
    assert!((min - 3.2552083333333083e-07).abs() < 1e-18, "{min}");
    // A move measures every cell against its own input orientation: nothing folds or
    // inverts, and no cell changes its sign (checked independently).
    let r = deform_json(
        &d,
        &[
            "--json",
            "move",
            name,
            "--marker",
            "load",
            "--rotate",
            "5",
            "--axis",
            "1,0,0",
            "--out",
            "moved.su2",
        ],
    );
    assert_eq!(r["folded_cells"], 0, "{r}");
    assert_eq!(r["inverted_cells"], 0);
    assert_eq!(r["new_invalid_cells"], 0);
    assert_eq!(r["listed_reversed_cells"], 6304);
    let moved = Su2Mesh {
        points: read_su2(&d.join("moved.su2")).points,
        ..input.clone()
    };
    let changed = signs(&input)
        .iter()
        .zip(signs(&moved))
        .filter(|(a, b)| a.signum() != b.signum())
        .count();
    assert_eq!(changed, 0);
}

#[test]
fn convert_reorient_writes_the_su2_convention() {
    let d = tmp_dir("listing-reorient");
    for (name, reversed) in [
        ("naca4412_turb_wake_window.su2", 173),
        ("mixed_elements_knowles.su2", 6304),
    ] {
        copy(&d, name);
        let r = deform_json(&d, &["--json", "convert", name, "r.su2", "--reorient"]);
        assert_eq!(r["reoriented_cells"], reversed);
        let before = read_su2(&d.join(name));
        let after = read_su2(&d.join("r.su2"));
        assert_eq!(negative(&after), 0, "{name}");
        assert_eq!(after.points, before.points);
        // The same cells: node sets equal, kinds equal.
        for ((k0, n0), (k1, n1)) in before.elements.iter().zip(after.elements.iter()) {
            let (mut a, mut b) = (n0.to_vec(), n1.to_vec());
            a.sort_unstable();
            b.sort_unstable();
            assert_eq!((k0, a), (k1, b));
        }
        let q = deform_json(&d, &["--json", "quality", "r.su2"]);
        assert_eq!(q["orientation"]["cells_listed_reversed"], 0);
        assert_eq!(q["folded_cells"], 0);
        // Without --reorient the cells keep their order.
        deform_json(&d, &["--json", "convert", name, "same.su2"]);
        assert_eq!(read_su2(&d.join("same.su2")).elements, before.elements);
    }
}

#[test]
fn a_triangle_flipped_over_its_neighbours_is_folded() {
    // A square fanned into four triangles around node 4, pushed out through the bottom edge:
    // triangle 0-1-4 turns clockwise and overlaps its two neighbours (its corners agree with
    // each other, so only the overlap test sees it).
    let d = tmp_dir("listing-overlap");
    let s = "NDIME= 2\nNELEM= 4\n5 0 1 4\n5 1 2 4\n5 2 3 4\n5 3 0 4\nNPOIN= 5\n0 0\n1 0\n1 1\n0 1\n0.5 -0.2\nNMARK= 0\n";
    std::fs::write(d.join("fan.su2"), s).expect("write");
    let q = deform_json(&d, &["--json", "quality", "fan.su2"]);
    assert_eq!(q["folded_cells"], 1, "{q}");
    assert_eq!(q["orientation"]["cells_listed_reversed"], 0);
    // Listed the other way, the same geometry is no better.
    let s = s.replace("5 0 1 4", "5 1 0 4");
    std::fs::write(d.join("fan2.su2"), s).expect("write");
    let q = deform_json(&d, &["--json", "quality", "fan2.su2"]);
    assert_eq!(q["folded_cells"], 1, "{q}");
}
