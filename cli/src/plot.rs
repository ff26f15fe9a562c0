//! Mesh pictures: SVG (own writer) and PNG (rasterised with tiny-skia). The mesh is drawn in
//! the x–y plane: every cell edge in grey, marker edges in blue, highlighted cells (inverted or
//! folded) filled red. A window zooms in (trailing edge, wall).

use std::collections::BTreeSet;
use std::fmt::Write as _;

use deform_kernel::CellKind;
use tiny_skia::{Color, FillRule, Paint, PathBuilder, Pixmap, Stroke, Transform};

use crate::formats::CellList;

/// What to draw.
#[derive(Clone, Copy, Debug)]
pub struct Picture<'a> {
    /// Point coordinates (x and y are drawn).
    pub points: &'a [[f64; 3]],
    /// The cells.
    pub cells: &'a CellList,
    /// Boundary elements to draw in blue (markers).
    pub boundaries: &'a [&'a CellList],
    /// Per cell: fill red (empty slice: none).
    pub highlight: &'a [bool],
    /// Caption (drawn in SVG only).
    pub title: &'a str,
}

/// A rectangular window `[xmin, ymin, xmax, ymax]` of the x–y plane.
pub type Window = [f64; 4];

/// The bounding box of the points (with a 2% margin), or a unit box when there are none.
pub fn bounding_window(points: &[[f64; 3]]) -> Window {
    let mut w = [
        f64::INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::NEG_INFINITY,
    ];
    for p in points {
        w[0] = w[0].min(p[0]);
        w[1] = w[1].min(p[1]);
        w[2] = w[2].max(p[0]);
        w[3] = w[3].max(p[1]);
    }
    if !w.iter().all(|v| v.is_finite()) {
        return [0.0, 0.0, 1.0, 1.0];
    }
    let m = 0.02 * (w[2] - w[0]).max(w[3] - w[1]).max(1e-300);
    [w[0] - m, w[1] - m, w[2] + m, w[3] + m]
}

/// A square window of half-width `half` around `centre`.
pub fn zoom(centre: [f64; 2], half: f64) -> Window {
    [
        centre[0] - half,
        centre[1] - half,
        centre[0] + half,
        centre[1] + half,
    ]
}

fn unique_edges(cells: &CellList) -> Vec<(u32, u32)> {
    let mut set = BTreeSet::new();
    for (code, nodes) in cells.iter() {
        let Some(kind) = CellKind::from_vtk(code) else {
            continue;
        };
        for e in kind.edges() {
            let a = nodes.get(e[0] as usize).copied();
            let b = nodes.get(e[1] as usize).copied();
            if let (Some(a), Some(b)) = (a, b) {
                set.insert((a.min(b), a.max(b)));
            }
        }
    }
    set.into_iter().collect()
}

struct Frame {
    w: Window,
    width: f64,
    height: f64,
}

impl Frame {
    fn new(w: Window, width: u32) -> Frame {
        let dx = (w[2] - w[0]).max(1e-300);
        let dy = (w[3] - w[1]).max(1e-300);
        let width = f64::from(width.clamp(16, 8192));
        let height = (width * dy / dx).clamp(16.0, 8192.0).round();
        Frame { w, width, height }
    }
    fn map(&self, p: &[f64; 3]) -> (f64, f64) {
        let x = (p[0] - self.w[0]) / (self.w[2] - self.w[0]) * self.width;
        let y = self.height - (p[1] - self.w[1]) / (self.w[3] - self.w[1]) * self.height;
        (x, y)
    }
    /// False when the segment is surely outside the picture.
    fn visible(&self, a: (f64, f64), b: (f64, f64)) -> bool {
        let (lo_x, hi_x) = (a.0.min(b.0), a.0.max(b.0));
        let (lo_y, hi_y) = (a.1.min(b.1), a.1.max(b.1));
        hi_x >= -1.0 && lo_x <= self.width + 1.0 && hi_y >= -1.0 && lo_y <= self.height + 1.0
    }
}

fn point(points: &[[f64; 3]], n: u32) -> Option<&[f64; 3]> {
    points.get(n as usize)
}

/// Polygons (in picture coordinates) of the highlighted 2D cells.
fn highlighted(pic: &Picture<'_>, f: &Frame) -> Vec<Vec<(f64, f64)>> {
    let mut out = Vec::new();
    for (c, (code, nodes)) in pic.cells.iter().enumerate() {
        if !pic.highlight.get(c).copied().unwrap_or(false) {
            continue;
        }
        let poly: Vec<(f64, f64)> = match CellKind::from_vtk(code) {
            Some(CellKind::Triangle | CellKind::Quad) => nodes
                .iter()
                .filter_map(|&n| point(pic.points, n).map(|p| f.map(p)))
                .collect(),
            // 3D cells: their edges, as degenerate polygons, so they show up.
            Some(kind) => kind
                .edges()
                .iter()
                .flat_map(|e| [e[0], e[1]])
                .filter_map(|l| nodes.get(l as usize))
                .filter_map(|&n| point(pic.points, n).map(|p| f.map(p)))
                .collect(),
            None => Vec::new(),
        };
        if poly.len() >= 2 {
            out.push(poly);
        }
    }
    out
}

/// The picture as an SVG document, `width` pixels wide (height from the window's aspect).
pub fn svg(pic: &Picture<'_>, window: Window, width: u32) -> String {
    svg_panels(&[(*pic, window)], width)
}

/// Several pictures side by side in one SVG document, each `width` pixels wide.
pub fn svg_panels(panels: &[(Picture<'_>, Window)], width: u32) -> String {
    let frames: Vec<Frame> = panels.iter().map(|(_, w)| Frame::new(*w, width)).collect();
    let total_w: f64 = frames.iter().map(|f| f.width + GAP).sum::<f64>() - GAP;
    let total_h = frames.iter().map(|f| f.height).fold(0.0, f64::max);
    let mut s = String::new();
    let _ = writeln!(
        s,
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{w}\" height=\"{h}\" viewBox=\"0 0 {w} {h}\">",
        w = total_w.max(1.0),
        h = total_h.max(1.0)
    );
    let _ = writeln!(s, "<rect width=\"100%\" height=\"100%\" fill=\"#d0d0d0\"/>");
    let mut x = 0.0;
    for ((pic, _), f) in panels.iter().zip(&frames) {
        let _ = writeln!(
            s,
            "<svg x=\"{x}\" y=\"0\" width=\"{w}\" height=\"{h}\" viewBox=\"0 0 {w} {h}\">",
            w = f.width,
            h = f.height
        );
        svg_body(pic, f, &mut s);
        s.push_str("</svg>\n");
        x += f.width + GAP;
    }
    s.push_str("</svg>\n");
    s
}

/// Space between panels, pixels.
const GAP: f64 = 6.0;

fn svg_body(pic: &Picture<'_>, f: &Frame, s: &mut String) {
    let _ = writeln!(s, "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>");
    for poly in highlighted(pic, f) {
        let pts: Vec<String> = poly.iter().map(|(x, y)| format!("{x:.2},{y:.2}")).collect();
        let _ = writeln!(
            s,
            "<polygon points=\"{}\" fill=\"#e02020\" fill-opacity=\"0.75\" stroke=\"#e02020\" stroke-width=\"1\"/>",
            pts.join(" ")
        );
    }
    let path = |cells: &CellList, colour: &str, width: f64, s: &mut String| {
        let mut d = String::new();
        for (a, b) in unique_edges(cells) {
            let (Some(pa), Some(pb)) = (point(pic.points, a), point(pic.points, b)) else {
                continue;
            };
            let (pa, pb) = (f.map(pa), f.map(pb));
            if f.visible(pa, pb) {
                let _ = write!(d, "M{:.2} {:.2}L{:.2} {:.2}", pa.0, pa.1, pb.0, pb.1);
            }
        }
        let _ = writeln!(
            s,
            "<path d=\"{d}\" fill=\"none\" stroke=\"{colour}\" stroke-width=\"{width}\"/>"
        );
    };
    path(pic.cells, "#505050", 0.5, s);
    for b in pic.boundaries {
        path(b, "#1f4fd0", 1.5, s);
    }
    let title: String = pic
        .title
        .chars()
        .map(|c| match c {
            '<' | '>' | '&' => ' ',
            c => c,
        })
        .collect();
    let _ = writeln!(
        s,
        "<text x=\"8\" y=\"20\" font-family=\"sans-serif\" font-size=\"14\" fill=\"black\">{title}</text>"
    );
}

/// The picture as PNG bytes, `width` pixels wide.
pub fn png(pic: &Picture<'_>, window: Window, width: u32) -> Result<Vec<u8>, String> {
    render(pic, window, width)?
        .encode_png()
        .map_err(|e| e.to_string())
}

/// Several pictures side by side in one PNG, each `width` pixels wide.
pub fn png_panels(panels: &[(Picture<'_>, Window)], width: u32) -> Result<Vec<u8>, String> {
    let maps = panels
        .iter()
        .map(|(p, w)| render(p, *w, width))
        .collect::<Result<Vec<_>, _>>()?;
    let gap = GAP as u32;
    let total_w = maps
        .iter()
        .map(|m| m.width() + gap)
        .sum::<u32>()
        .saturating_sub(gap);
    let total_h = maps.iter().map(Pixmap::height).max().unwrap_or(1);
    let mut out = Pixmap::new(total_w.max(1), total_h.max(1))
        .ok_or_else(|| "cannot allocate the picture".to_string())?;
    out.fill(Color::from_rgba8(208, 208, 208, 255));
    let mut x = 0i32;
    for m in &maps {
        out.draw_pixmap(
            x,
            0,
            m.as_ref(),
            &tiny_skia::PixmapPaint::default(),
            Transform::identity(),
            None,
        );
        x = x.saturating_add(i32::try_from(m.width() + gap).unwrap_or(i32::MAX));
    }
    out.encode_png().map_err(|e| e.to_string())
}

fn render(pic: &Picture<'_>, window: Window, width: u32) -> Result<Pixmap, String> {
    let f = Frame::new(window, width);
    let mut pixmap = Pixmap::new(f.width as u32, f.height as u32)
        .ok_or_else(|| "cannot allocate the picture".to_string())?;
    pixmap.fill(Color::WHITE);
    let mut red = Paint::default();
    red.set_color_rgba8(224, 32, 32, 200);
    red.anti_alias = true;
    for poly in highlighted(pic, &f) {
        let mut pb = PathBuilder::new();
        for (k, (x, y)) in poly.iter().enumerate() {
            if k == 0 {
                pb.move_to(*x as f32, *y as f32);
            } else {
                pb.line_to(*x as f32, *y as f32);
            }
        }
        pb.close();
        if let Some(path) = pb.finish() {
            pixmap.fill_path(&path, &red, FillRule::EvenOdd, Transform::identity(), None);
            let stroke = Stroke {
                width: 1.5,
                ..Stroke::default()
            };
            pixmap.stroke_path(&path, &red, &stroke, Transform::identity(), None);
        }
    }
    let mut draw = |cells: &CellList, rgba: [u8; 4], width: f32| {
        let mut pb = PathBuilder::new();
        for (a, b) in unique_edges(cells) {
            let (Some(pa), Some(pb_)) = (point(pic.points, a), point(pic.points, b)) else {
                continue;
            };
            let (pa, pb2) = (f.map(pa), f.map(pb_));
            if f.visible(pa, pb2) {
                pb.move_to(pa.0 as f32, pa.1 as f32);
                pb.line_to(pb2.0 as f32, pb2.1 as f32);
            }
        }
        if let Some(path) = pb.finish() {
            let mut paint = Paint::default();
            paint.set_color_rgba8(rgba[0], rgba[1], rgba[2], rgba[3]);
            paint.anti_alias = true;
            let stroke = Stroke {
                width,
                ..Stroke::default()
            };
            pixmap.stroke_path(&path, &paint, &stroke, Transform::identity(), None);
        }
    };
    draw(pic.cells, [64, 64, 64, 255], 0.0);
    for b in pic.boundaries {
        draw(b, [31, 79, 208, 255], 2.0);
    }
    Ok(pixmap)
}
