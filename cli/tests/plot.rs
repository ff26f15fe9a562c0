//! Pictures: SVG is well-formed XML, PNG decodes, highlighted cells are red.

mod common;

use common::{mesh_2d, tmp_dir};
use deform_cli::formats::CellList;
use deform_cli::plot::{
    bounding_window, colour_scale, has_volume_cells, png, slice_z, svg, zoom, Picture, Shading,
    VTK_POLYGON,
};
use deform_kernel::CellKind;

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
        shading: None,
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

/// A structured `n × n × n` box of hexahedra on [0, 1]³, with its `z = 0` face as a marker.
fn hex_box(n: usize) -> (Vec<[f64; 3]>, CellList, CellList) {
    let id = |i: usize, j: usize, k: usize| (i + (n + 1) * (j + (n + 1) * k)) as u32;
    let h = 1.0 / n as f64;
    let mut points = Vec::new();
    for k in 0..=n {
        for j in 0..=n {
            for i in 0..=n {
                points.push([i as f64 * h, j as f64 * h, k as f64 * h]);
            }
        }
    }
    let mut cells = CellList::new();
    let mut bottom = CellList::new();
    for k in 0..n {
        for j in 0..n {
            for i in 0..n {
                cells.push(
                    CellKind::Hexahedron,
                    &[
                        id(i, j, k),
                        id(i + 1, j, k),
                        id(i + 1, j + 1, k),
                        id(i, j + 1, k),
                        id(i, j, k + 1),
                        id(i + 1, j, k + 1),
                        id(i + 1, j + 1, k + 1),
                        id(i, j + 1, k + 1),
                    ],
                );
            }
        }
    }
    for j in 0..n {
        for i in 0..n {
            bottom.push(
                CellKind::Quad,
                &[
                    id(i, j, 0),
                    id(i + 1, j, 0),
                    id(i + 1, j + 1, 0),
                    id(i, j + 1, 0),
                ],
            );
        }
    }
    (points, cells, bottom)
}

#[test]
fn a_3d_mesh_is_drawn_as_its_section_not_as_every_projected_edge() {
    let n = 4;
    let (points, cells, bottom) = hex_box(n);
    assert!(has_volume_cells(&cells));
    // Through the middle of a layer of cells: one square polygon per cell of the layer.
    let s = slice_z(&points, &cells, &[&bottom], 0.3);
    assert_eq!(s.cells.len(), n * n);
    assert!(s
        .cells
        .iter()
        .all(|(code, nodes)| code == VTK_POLYGON && nodes.len() == 4));
    // One intersection point per vertical edge of the layer, shared by its cells.
    assert_eq!(s.points.len(), (n + 1) * (n + 1));
    assert!(s.points.iter().all(|p| p[2] == 0.3));
    let mut xs: Vec<f64> = s.points.iter().map(|p| p[0]).collect();
    xs.sort_by(f64::total_cmp);
    xs.dedup();
    assert_eq!(xs.len(), n + 1);
    // Each section polygon is a convex ring: consecutive corners are one cell width apart.
    for (_, nodes) in s.cells.iter() {
        for k in 0..4 {
            let (a, b) = (
                s.points[nodes[k] as usize],
                s.points[nodes[(k + 1) % 4] as usize],
            );
            let d = ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2)).sqrt();
            assert!((d - 0.25).abs() < 1e-12, "ring edge {d}");
        }
    }
    // The marker lies below the plane: it is not cut.
    assert_eq!(s.boundaries.len(), 1);
    assert!(s.boundaries[0].is_empty());
    // The SVG of the section draws the section's 2·n·(n+1) distinct edges; the projection of
    // the whole box would draw 3·n·(n+1)² edges on top of each other.
    let none = vec![false; s.cells.len()];
    let pic = Picture {
        points: &s.points,
        cells: &s.cells,
        boundaries: &[],
        highlight: &none,
        title: "section",
        shading: None,
    };
    let text = svg(&pic, bounding_window(&s.points), 300);
    let grey = text
        .lines()
        .find(|l| l.contains("stroke=\"#505050\""))
        .expect("the cell edges");
    assert_eq!(grey.matches('M').count(), 2 * n * (n + 1));
}

#[test]
fn a_tilted_plane_section_of_a_tetrahedron_is_a_triangle_and_its_faces_give_segments() {
    let points = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
    ];
    let mut cells = CellList::new();
    cells.push(CellKind::Tetra, &[0, 1, 2, 3]);
    let mut faces = CellList::new();
    faces.push(CellKind::Triangle, &[0, 1, 3]);
    faces.push(CellKind::Triangle, &[0, 1, 2]); // in the plane z = 0: below, not cut
    let s = slice_z(&points, &cells, &[&faces], 0.5);
    assert_eq!(s.cells.len(), 1);
    assert_eq!(s.cells.cell(0).1.len(), 3);
    let mut got: Vec<[f64; 2]> = s.points.iter().map(|p| [p[0], p[1]]).collect();
    got.sort_by(|a, b| a[0].total_cmp(&b[0]).then(a[1].total_cmp(&b[1])));
    assert_eq!(got, [[0.0, 0.0], [0.0, 0.5], [0.5, 0.0]]);
    assert_eq!(s.boundaries[0].len(), 1);
    assert_eq!(s.boundaries[0].cell(0).0, CellKind::Line.vtk_code());
}

#[test]
fn shaded_cells_take_the_colour_of_their_value_on_a_shared_range() {
    let m = mesh_2d(4, 1);
    let values: Vec<f64> = (0..m.elements.len()).map(|c| c as f64).collect();
    let top = (m.elements.len() - 1) as f64;
    let none = vec![false; m.elements.len()];
    let pic = Picture {
        points: &m.points,
        cells: &m.elements,
        boundaries: &[],
        highlight: &none,
        title: "shaded",
        shading: Some(Shading {
            values: &values,
            range: [0.0, top],
            label: "cell index",
        }),
    };
    let w = bounding_window(&m.points);
    let text = svg(&pic, w, 400);
    assert_eq!(text.matches("class=\"shade\"").count(), m.elements.len());
    let first = colour_scale(0.0);
    let last = colour_scale(1.0);
    assert_ne!(first, last);
    assert!(text.contains(&format!("rgb({},{},{})", first[0], first[1], first[2])));
    assert!(text.contains(&format!("rgb({},{},{})", last[0], last[1], last[2])));
    // In the PNG the centre of the first and of the last cell have those colours.
    let pix = tiny_skia::Pixmap::decode_png(&png(&pic, w, 400).expect("png")).expect("decode");
    let at = |c: usize| {
        let (_, nodes) = m.elements.cell(c);
        let n = nodes.len() as f64;
        let (x, y) = nodes.iter().fold((0.0, 0.0), |(x, y), &k| {
            (
                x + m.points[k as usize][0] / n,
                y + m.points[k as usize][1] / n,
            )
        });
        let px = ((x - w[0]) / (w[2] - w[0]) * f64::from(pix.width())) as u32;
        let py = ((w[3] - y) / (w[3] - w[1]) * f64::from(pix.height())) as u32;
        let p = pix.pixel(px, py).expect("inside");
        [p.red(), p.green(), p.blue()]
    };
    assert_eq!(at(0), first);
    assert_eq!(at(m.elements.len() - 1), last);
}
