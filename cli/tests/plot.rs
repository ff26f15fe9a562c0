//! Pictures: SVG is well-formed XML, PNG decodes, highlighted cells are red.

mod common;

use common::{mesh_2d, tmp_dir};
use deform_cli::plot::{bounding_window, png, svg, zoom, Picture};

#[test]
fn svg_and_png_of_a_mesh_with_a_highlighted_cell() {
    let m = mesh_2d(8, 5);
    let mut highlight = vec![false; m.elements.len()];
    highlight[20] = true;
    let wall = &m.markers[0].elements;
    let pic = Picture {
        points: &m.points,
        cells: &m.elements,
        boundaries: &[wall],
        highlight: &highlight,
        title: "test <mesh>",
    };
    let w = bounding_window(&m.points);
    let s = svg(&pic, w, 400);
    let mut r = quick_xml::Reader::from_str(&s);
    let mut polygons = 0;
    loop {
        match r.read_event().expect("well-formed SVG") {
            quick_xml::events::Event::Eof => break,
            quick_xml::events::Event::Empty(e) if e.name().as_ref() == b"polygon" => polygons += 1,
            _ => {}
        }
    }
    assert_eq!(polygons, 1);
    let bytes = png(&pic, w, 400).expect("png");
    assert_eq!(&bytes[1..4], b"PNG");
    let pix = tiny_skia::Pixmap::decode_png(&bytes).expect("decode");
    assert_eq!(pix.width(), 400);
    let reds = pix
        .pixels()
        .iter()
        .filter(|p| p.red() > 200 && p.green() < 120 && p.blue() < 120)
        .count();
    assert!(reds > 100, "highlighted cell is red ({reds} red pixels)");
    // A zoom renders too, and a picture of nothing does not fail.
    let z = png(&pic, zoom([0.0, 0.0], 0.5), 200).expect("zoom");
    std::fs::write(tmp_dir("plot").join("mesh.png"), &bytes).expect("write");
    assert!(!z.is_empty());
}
