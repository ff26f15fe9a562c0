//! SU2 reader/writer: round trips, accepted variants, and malformed input.

mod common;

use common::{deform_ok, mesh_2d, mesh_3d, su2_bytes, tmp_dir, Rng};
use deform_cli::formats::su2::parse_su2;
use deform_cli::formats::{FormatErrorKind, Location};

#[test]
fn round_trip_2d_bitwise() {
    let m = mesh_2d(5, 4);
    let bytes = su2_bytes(&m);
    let back = parse_su2(&bytes).expect("parse own output");
    assert_eq!(back, m);
    for (a, b) in back.points.iter().zip(&m.points) {
        for k in 0..3 {
            assert_eq!(a[k].to_bits(), b[k].to_bits());
        }
    }
    assert_eq!(su2_bytes(&back), bytes);
}

#[test]
fn round_trip_3d_all_kinds() {
    let m = mesh_3d();
    let bytes = su2_bytes(&m);
    let back = parse_su2(&bytes).expect("parse own output");
    assert_eq!(back, m);
    let mut kinds: Vec<u8> = back.elements.kinds.clone();
    kinds.extend(back.markers.iter().flat_map(|mk| mk.elements.kinds.clone()));
    kinds.sort();
    kinds.dedup();
    assert_eq!(kinds, vec![5, 9, 10, 12, 13, 14]);
    assert_eq!(back.marker("side wall").map(|m| m.elements.len()), Some(1));
}

#[test]
fn extreme_values_round_trip() {
    let mut m = mesh_2d(1, 1);
    m.points[0] = [f64::MAX, -f64::MIN_POSITIVE, 0.0];
    m.points[1] = [-0.0, 5e-324, 0.0];
    m.points[2] = [0.1 + 0.2, 1.0 / 3.0, 0.0];
    let back = parse_su2(&su2_bytes(&m)).expect("parse");
    for (a, b) in back.points.iter().zip(&m.points) {
        assert_eq!(a[0].to_bits(), b[0].to_bits());
        assert_eq!(a[1].to_bits(), b[1].to_bits());
    }
}

#[test]
fn accepts_points_first_comments_trailing_columns_and_crlf() {
    let text = "% a comment line\r\n\
                NDIME= 2\r\n\
                NPOIN= 4  4\r\n\
                0.0 0.0 0 extra\r\n\
                1.0 0.0 1\r\n\
                \r\n\
                1.0 1.0 2 % trailing comment\r\n\
                0.0 1.0 3\r\n\
                NELEM=2\r\n\
                5 0 1 2 0\r\n\
                5 0 2 3 1\r\n\
                NMARK= 1\r\n\
                MARKER_TAG= lower\r\n\
                MARKER_ELEMS= 1\r\n\
                3 0 1\r\n\
                FFD_NBOX= 0\r\n\
                FFD_NLEVEL= 0\r\n";
    let m = parse_su2(text.as_bytes()).expect("valid file");
    assert_eq!(m.points.len(), 4);
    assert_eq!(m.elements.len(), 2);
    assert_eq!(m.elements.cell(1), (5, &[0u32, 2, 3][..]));
    assert_eq!(
        m.marker("lower").map(|k| k.elements.nodes.clone()),
        Some(vec![0, 1])
    );
}

fn err(text: &str) -> deform_cli::FormatError {
    match parse_su2(text.as_bytes()) {
        Ok(_) => panic!("expected an error for:\n{text}"),
        Err(e) => e,
    }
}

const GOOD: &str = "NDIME= 2\nNELEM= 2\n5 0 1 2\n9 0 1 2 3\nNPOIN= 4\n0 0\n1 0\n1 1\n0 1\nNMARK= 1\nMARKER_TAG= wall\nMARKER_ELEMS= 1\n3 0 1\n";

#[test]
fn good_fixture_parses() {
    let m = parse_su2(GOOD.as_bytes()).expect("good");
    assert_eq!((m.dim, m.points.len(), m.elements.len()), (2, 4, 2));
}

#[test]
fn truncated_file_names_the_line() {
    let cut = &GOOD[..GOOD.find("1 1\n").expect("fixture")];
    let e = err(cut);
    assert_eq!(e.location, Location::Line(8));
    assert_eq!(
        e.to_string(),
        "line 8: unexpected end of file, expected point 3 of 4 (NPOIN= 4)"
    );
}

#[test]
fn wrong_counts() {
    // NELEM says 3 but only 2 elements follow: the NPOIN line is not an element.
    let e = err(&GOOD.replace("NELEM= 2", "NELEM= 3"));
    assert_eq!(e.location, Location::Line(5));
    assert!(e.to_string().contains("expected element 3 of 3"), "{e}");
    // NPOIN says 3 but 4 points follow: the 4th point line is not a keyword.
    let e = err(&GOOD.replace("NPOIN= 4", "NPOIN= 3"));
    assert_eq!(e.location, Location::Line(9));
    assert!(e.to_string().contains("expected a keyword line"), "{e}");
    // Too few nodes on an element line.
    let e = err(&GOOD.replace("9 0 1 2 3", "9 0 1 2"));
    assert_eq!(e.location, Location::Line(4));
    assert!(
        e.to_string()
            .contains("4 node indices for element type 9, found only 3"),
        "{e}"
    );
    // Node index out of range is reported at the element line.
    let e = err(&GOOD.replace("5 0 1 2", "5 0 1 7"));
    assert_eq!(e.location, Location::Line(3));
    assert_eq!(
        e.kind,
        FormatErrorKind::IndexOutOfRange { index: 7, bound: 4 }
    );
}

#[test]
fn bad_element_codes() {
    let e = err(&GOOD.replace("5 0 1 2", "7 0 1 2"));
    assert_eq!(
        e.to_string(),
        "line 3: bad element type code 7, expected 5, 9"
    );
    // A 3D element in a 2D mesh.
    let e = err(&GOOD.replace("5 0 1 2", "10 0 1 2 3"));
    assert_eq!(e.location, Location::Line(3));
    // A triangle as a 2D boundary element.
    let e = err(&GOOD.replace("3 0 1\n", "5 0 1 2\n"));
    assert_eq!(
        e.to_string(),
        "line 13: bad element type code 5, expected 3"
    );
    let e = err(&GOOD.replace("5 0 1 2", "-5 0 1 2"));
    assert_eq!(e.location, Location::Line(3));
    let e = err(&GOOD.replace("5 0 1 2", "5 0 1 1"));
    assert_eq!(e.kind, FormatErrorKind::RepeatedNode { node: 1 });
}

#[test]
fn nan_and_infinite_coordinates() {
    let e = err(&GOOD.replace("1 1\n", "1 NaN\n"));
    assert_eq!(
        e.to_string(),
        "line 8: y of point 2 is not a finite number: \"NaN\""
    );
    let e = err(&GOOD.replace("1 1\n", "inf 1\n"));
    assert_eq!(e.location, Location::Line(8));
    let e = err(&GOOD.replace("1 1\n", "1e999 1\n"));
    assert_eq!(e.location, Location::Line(8));
    let e = err(&GOOD.replace("1 1\n", "1,5 1\n"));
    assert!(
        e.to_string()
            .starts_with("line 8: expected x of point 2 (a number)"),
        "{e}"
    );
}

#[test]
fn missing_marker_and_sections() {
    let e = err(&GOOD.replace("NMARK= 1", "NMARK= 2"));
    assert_eq!(e.location, Location::Line(14));
    assert!(
        e.to_string()
            .contains("expected MARKER_TAG= (marker 2 of 2"),
        "{e}"
    );
    let e = err(&GOOD.replace("MARKER_TAG= wall\n", ""));
    assert!(e.to_string().contains("expected MARKER_TAG="), "{e}");
    let e = err(&GOOD.replace("MARKER_ELEMS= 1", "MARKER_ELEMS= 2"));
    assert!(
        e.to_string().contains("element 2 of 2 of marker wall"),
        "{e}"
    );
    let e = err("NDIME= 2\nNELEM= 0\n");
    assert_eq!(
        e.to_string(),
        "line 3: missing NPOIN= section (end of file reached)"
    );
    let e = err("NELEM= 0\n");
    assert!(e.to_string().contains("NDIME= before NELEM="), "{e}");
    let e = err("NDIME= 2\nNDIME= 2\n");
    assert_eq!(
        e.to_string(),
        "line 2: NDIME appears twice, expected it once"
    );
    let e = err("NDIME= 2\nNMARK= 0\n");
    assert!(
        e.to_string()
            .contains("NELEM= and NPOIN= sections before NMARK="),
        "{e}"
    );
}

#[test]
fn garbage_bytes_are_errors_not_panics() {
    let e = err("\u{0}\u{1}binary\u{ff}");
    assert_eq!(e.location, Location::Line(1));
    let e = parse_su2(&[0xff, 0xfe, b'=', 0x80, b'\n']).expect_err("garbage");
    assert_eq!(e.location, Location::Line(1));
    let e = err("NDIME= 2\nNELEM= 99999999999999999999999\n");
    assert_eq!(e.location, Location::Line(2));
    let e = err("NDIME= 2\nNELEM= 4294967296\n");
    assert!(matches!(e.kind, FormatErrorKind::TooLarge { .. }), "{e}");
    // A huge count with no data is an end-of-file error, not an allocation.
    let e = err("NDIME= 2\nNPOIN= 4000000000\n");
    assert!(
        matches!(e.kind, FormatErrorKind::UnexpectedEof { .. }),
        "{e}"
    );
}

#[test]
fn random_mutations_never_panic() {
    let base = su2_bytes(&mesh_3d());
    let base2 = GOOD.as_bytes().to_vec();
    let mut rng = Rng(0xdead_beef);
    for round in 0..3000 {
        let mut b = if round % 2 == 0 {
            base.clone()
        } else {
            base2.clone()
        };
        for _ in 0..1 + rng.below(4) {
            let i = rng.below(b.len());
            match rng.below(4) {
                0 => b[i] = rng.next() as u8,
                1 => {
                    b.truncate(i);
                }
                2 => b.insert(i, b"0123456789 -.eE%=\n"[rng.below(18)]),
                _ => {
                    b.remove(i);
                }
            }
            if b.is_empty() {
                break;
            }
        }
        let _ = parse_su2(&b);
    }
    for _ in 0..500 {
        let n = rng.below(200);
        let b: Vec<u8> = (0..n).map(|_| rng.next() as u8).collect();
        let _ = parse_su2(&b);
    }
}

/// The input's comment lines and line ends survive `convert` and `move` (issue 31: outputs
/// dropped them): every comment-only line of the input is in the output, in order, and every
/// output line ends in `\r\n` as the input's did. Checked on the bytes, not by our reader.
#[test]
fn comments_and_crlf_are_kept_by_convert_and_move() {
    let d = tmp_dir("su2-comments");
    let body = String::from_utf8(su2_bytes(&mesh_2d(4, 3))).unwrap();
    let mut text = String::new();
    for line in body.lines().filter(|l| !l.starts_with('%')) {
        for key in ["NDIME=", "NELEM=", "NPOIN=", "NMARK=", "MARKER_TAG= wall"] {
            if line.starts_with(key) {
                text.push_str(&format!("%\r\n% before {key}\r\n%\r\n"));
            }
        }
        text.push_str(line);
        text.push_str("\r\n");
    }
    text.push_str("% the end\r\n");
    std::fs::write(d.join("in.su2"), &text).unwrap();
    let comments = |t: &str| -> Vec<String> {
        t.split("\r\n")
            .filter(|l| l.trim_start().starts_with('%'))
            .map(str::to_string)
            .collect()
    };
    let want = comments(&text);
    assert_eq!(want.len(), 16);
    deform_ok(&d, &["convert", "in.su2", "out.su2"]);
    deform_ok(
        &d,
        &[
            "move",
            "in.su2",
            "--marker",
            "wall",
            "--translate",
            "0,0.01",
            "--out",
            "moved.su2",
        ],
    );
    for out in ["out.su2", "moved.su2"] {
        let got = std::fs::read_to_string(d.join(out)).unwrap();
        assert_eq!(comments(&got), want, "{out}");
        assert!(got.ends_with("\r\n"), "{out}");
        assert_eq!(
            got.matches('\n').count(),
            got.matches("\r\n").count(),
            "{out}"
        );
    }
    assert_eq!(std::fs::read_to_string(d.join("out.su2")).unwrap(), text);
}
