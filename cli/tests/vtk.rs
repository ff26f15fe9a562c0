//! VTK XML output: parse our own .vtu/.vts back with an XML parser and compare the arrays.

mod common;

use common::{mesh_2d, mesh_3d};
use deform_cli::formats::base64;
use deform_cli::formats::vtk::{write_vts, write_vtu, VtkEncoding, VtkField};
use quick_xml::events::Event;
use quick_xml::Reader;

#[derive(Debug, Default)]
struct Array {
    ty: String,
    name: String,
    comps: usize,
    format: String,
    text: String,
}

#[derive(Debug, Default)]
struct Parsed {
    root_type: String,
    attrs: Vec<(String, String)>,
    arrays: Vec<Array>,
}

fn attrs(e: &quick_xml::events::BytesStart<'_>) -> Vec<(String, String)> {
    e.attributes()
        .map(|a| {
            let a = a.expect("well-formed attribute");
            (
                String::from_utf8(a.key.as_ref().to_vec()).expect("utf8"),
                String::from_utf8(a.value.to_vec())
                    .expect("utf8")
                    .replace("&lt;", "<")
                    .replace("&gt;", ">")
                    .replace("&quot;", "\"")
                    .replace("&apos;", "'")
                    .replace("&amp;", "&"),
            )
        })
        .collect()
}

fn parse(xml: &str) -> Parsed {
    let mut r = Reader::from_str(xml);
    let mut out = Parsed::default();
    let mut current: Option<Array> = None;
    let mut depth = 0i32;
    loop {
        match r.read_event().expect("well-formed XML") {
            Event::Start(e) => {
                depth += 1;
                let a = attrs(&e);
                let get = |k: &str| a.iter().find(|(n, _)| n == k).map(|(_, v)| v.clone());
                match e.name().as_ref() {
                    b"VTKFile" => out.root_type = get("type").expect("type"),
                    b"Piece" => out.attrs.extend(a.clone()),
                    b"DataArray" => {
                        current = Some(Array {
                            ty: get("type").expect("type"),
                            name: get("Name").expect("Name"),
                            comps: get("NumberOfComponents")
                                .expect("comps")
                                .parse()
                                .expect("n"),
                            format: get("format").expect("format"),
                            text: String::new(),
                        })
                    }
                    _ => {}
                }
            }
            Event::Text(t) => {
                if let Some(c) = current.as_mut() {
                    c.text
                        .push_str(std::str::from_utf8(t.as_ref()).expect("utf8"));
                }
            }
            Event::End(e) => {
                depth -= 1;
                if e.name().as_ref() == b"DataArray" {
                    out.arrays.push(current.take().expect("open array"));
                }
            }
            Event::Eof => break,
            _ => {}
        }
    }
    assert_eq!(depth, 0, "unbalanced XML");
    out
}

fn decode_b64(s: &str) -> Vec<u8> {
    let val = |c: u8| -> u32 {
        match c {
            b'A'..=b'Z' => (c - b'A') as u32,
            b'a'..=b'z' => (c - b'a' + 26) as u32,
            b'0'..=b'9' => (c - b'0' + 52) as u32,
            b'+' => 62,
            b'/' => 63,
            _ => panic!("bad base64 {c}"),
        }
    };
    let clean: Vec<u8> = s.bytes().filter(|b| !b.is_ascii_whitespace()).collect();
    assert_eq!(clean.len() % 4, 0);
    let mut out = Vec::new();
    for ch in clean.chunks(4) {
        let pad = ch.iter().filter(|&&c| c == b'=').count();
        let n = ch
            .iter()
            .map(|&c| if c == b'=' { 0 } else { val(c) })
            .fold(0u32, |a, v| (a << 6) | v);
        let bytes = [(n >> 16) as u8, (n >> 8) as u8, n as u8];
        out.extend_from_slice(&bytes[..3 - pad]);
    }
    out
}

/// Array values as f64 bit patterns (integers converted exactly).
fn values(a: &Array) -> Vec<u64> {
    if a.format == "ascii" {
        return a
            .text
            .split_whitespace()
            .map(|t| {
                if a.ty == "Float64" {
                    t.parse::<f64>().expect("float").to_bits()
                } else {
                    (t.parse::<i64>().expect("int") as f64).to_bits()
                }
            })
            .collect();
    }
    assert_eq!(a.format, "binary");
    let raw = decode_b64(&a.text);
    let (head, body) = raw.split_at(8);
    let n = u64::from_le_bytes(head.try_into().expect("8 bytes")) as usize;
    assert_eq!(n, body.len(), "{}: header byte count", a.name);
    match a.ty.as_str() {
        "Float64" => body
            .chunks(8)
            .map(|c| u64::from_le_bytes(c.try_into().expect("8")))
            .collect(),
        "Int64" => body
            .chunks(8)
            .map(|c| (i64::from_le_bytes(c.try_into().expect("8")) as f64).to_bits())
            .collect(),
        "UInt8" => body.iter().map(|&b| (b as f64).to_bits()).collect(),
        t => panic!("unexpected type {t}"),
    }
}

fn find<'a>(p: &'a Parsed, name: &str) -> &'a Array {
    p.arrays.iter().find(|a| a.name == name).expect(name)
}

fn bits(v: impl IntoIterator<Item = f64>) -> Vec<u64> {
    v.into_iter().map(f64::to_bits).collect()
}

#[test]
fn base64_known_vectors() {
    assert_eq!(base64::encode(b""), "");
    assert_eq!(base64::encode(b"M"), "TQ==");
    assert_eq!(base64::encode(b"Ma"), "TWE=");
    assert_eq!(base64::encode(b"Man"), "TWFu");
    assert_eq!(base64::encode(&[0xfb, 0xff, 0xbf]), "+/+/");
    let all: Vec<u8> = (0..=255).collect();
    assert_eq!(decode_b64(&base64::encode(&all)), all);
}

/// The connectivity VTK expects: prisms (13) as `0,2,1,3,5,4`, everything else unchanged.
fn vtk_order(cells: &deform_cli::formats::CellList) -> Vec<u32> {
    let mut out = Vec::new();
    for (c, &kind) in cells.kinds.iter().enumerate() {
        let nodes = &cells.nodes[cells.offsets[c] as usize..cells.offsets[c + 1] as usize];
        if kind == 13 {
            out.extend([0, 2, 1, 3, 5, 4].map(|k| nodes[k]));
        } else {
            out.extend_from_slice(nodes);
        }
    }
    out
}

/// A prism that the kernel calls positive must reach VTK with its base `0,1,2` turning toward
/// the top `3,4,5`: that is the wedge VTK's own code (vtkMeshQuality's wedge volume,
/// vtkCellSizeFilter, checked with VTK 9 from PyPI: +0.5 for this order, −0.5 for SU2's)
/// calls positive, whatever vtkWedge's documentation says.
#[test]
fn prisms_reach_vtk_with_vtk_orientation() {
    use deform_kernel::quality::cell_measures;
    let points = [
        [0.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 0.0, 1.0],
        [0.0, 1.0, 1.0],
        [1.0, 0.0, 1.0],
    ];
    let mut cells = deform_cli::formats::CellList::new();
    cells.push(deform_kernel::CellKind::Prism, &[0, 1, 2, 3, 4, 5]);
    let view = deform_kernel::Cells::new(6, &cells.offsets, &cells.nodes, &cells.kinds).unwrap();
    let mut m = [0.0];
    cell_measures(&view, &points, &mut m).unwrap();
    assert!(m[0] > 0.0, "the kernel calls this prism positive: {}", m[0]);
    let mut out = Vec::new();
    write_vtu(&mut out, &points, &cells, &[], &[], VtkEncoding::Ascii).unwrap();
    let p = parse(&String::from_utf8(out).unwrap());
    let conn: Vec<usize> = values(find(&p, "connectivity"))
        .into_iter()
        .map(|b| f64::from_bits(b) as usize)
        .collect();
    let sub =
        |a: usize, b: usize| -> [f64; 3] { core::array::from_fn(|k| points[b][k] - points[a][k]) };
    let (e1, e2, up) = (
        sub(conn[0], conn[1]),
        sub(conn[0], conn[2]),
        sub(conn[0], conn[3]),
    );
    let normal = [
        e1[1] * e2[2] - e1[2] * e2[1],
        e1[2] * e2[0] - e1[0] * e2[2],
        e1[0] * e2[1] - e1[1] * e2[0],
    ];
    let toward_top = normal[0] * up[0] + normal[1] * up[1] + normal[2] * up[2];
    assert!(
        toward_top > 0.0,
        "VTK's base must turn toward the top: {conn:?}"
    );
}

#[test]
fn vtu_round_trips_in_both_encodings() {
    for mesh in [mesh_2d(4, 3), mesh_3d()] {
        let n = mesh.points.len();
        let disp: Vec<f64> = (0..3 * n).map(|i| (i as f64 * 0.37).sin() * 1e-3).collect();
        let q: Vec<f64> = (0..mesh.elements.len())
            .map(|c| 1.0 / (c as f64 + 3.0))
            .collect();
        for enc in [VtkEncoding::Ascii, VtkEncoding::Base64] {
            let mut out = Vec::new();
            write_vtu(
                &mut out,
                &mesh.points,
                &mesh.elements,
                &[VtkField {
                    name: "displacement",
                    components: 3,
                    values: &disp,
                }],
                &[VtkField {
                    name: "quality <ratio>",
                    components: 1,
                    values: &q,
                }],
                enc,
            )
            .expect("write");
            let xml = String::from_utf8(out).expect("utf8");
            let p = parse(&xml);
            assert_eq!(p.root_type, "UnstructuredGrid");
            let piece = |k: &str| p.attrs.iter().find(|(n, _)| n == k).map(|(_, v)| v.clone());
            assert_eq!(piece("NumberOfPoints"), Some(n.to_string()));
            assert_eq!(
                piece("NumberOfCells"),
                Some(mesh.elements.len().to_string())
            );
            assert_eq!(values(find(&p, "displacement")), bits(disp.iter().copied()));
            assert_eq!(find(&p, "displacement").comps, 3);
            assert_eq!(values(find(&p, "quality <ratio>")), bits(q.iter().copied()));
            assert_eq!(
                values(find(&p, "Points")),
                bits(mesh.points.iter().flatten().copied())
            );
            assert_eq!(
                values(find(&p, "connectivity")),
                bits(vtk_order(&mesh.elements).into_iter().map(|v| v as f64))
            );
            assert_eq!(
                values(find(&p, "offsets")),
                bits(mesh.elements.offsets[1..].iter().map(|&v| v as f64))
            );
            assert_eq!(
                values(find(&p, "types")),
                bits(mesh.elements.kinds.iter().map(|&v| v as f64))
            );
        }
    }
}

#[test]
fn vts_round_trips() {
    let dims = [4, 3, 2];
    let pts: Vec<[f64; 3]> = (0..24)
        .map(|i| [i as f64, (i * i) as f64 * 0.1, -(i as f64)])
        .collect();
    let cq: Vec<f64> = (0..6).map(|c| c as f64 + 0.5).collect();
    for enc in [VtkEncoding::Ascii, VtkEncoding::Base64] {
        let mut out = Vec::new();
        write_vts(
            &mut out,
            dims,
            &pts,
            &[],
            &[VtkField {
                name: "quality",
                components: 1,
                values: &cq,
            }],
            enc,
        )
        .expect("write");
        let xml = String::from_utf8(out).expect("utf8");
        assert!(xml.contains("<StructuredGrid WholeExtent=\"0 3 0 2 0 1\">"));
        let p = parse(&xml);
        assert_eq!(p.root_type, "StructuredGrid");
        assert_eq!(
            values(find(&p, "Points")),
            bits(pts.iter().flatten().copied())
        );
        assert_eq!(values(find(&p, "quality")), bits(cq.iter().copied()));
    }
    // Wrong field length is an error, not a broken file.
    let mut out = Vec::new();
    let e = write_vts(
        &mut out,
        dims,
        &pts,
        &[VtkField {
            name: "d",
            components: 3,
            values: &[0.0; 5],
        }],
        &[],
        VtkEncoding::Ascii,
    );
    assert!(e.is_err());
}
