//! Mesh pictures: SVG (own writer) and PNG (rasterised with tiny-skia). The mesh is drawn in
//! the x–y plane: every cell edge in grey, marker edges in blue, highlighted cells (inverted or
//! folded) filled red, and optionally every cell filled by a value on a colour scale (with a
//! colour bar). A window zooms in (trailing edge, wall). A 3D mesh is drawn as its section by a
//! plane `z = const` ([`slice_z`]): drawing every edge of a volume mesh projected on x–y is an
//! unreadable tangle.

use std::collections::{BTreeMap, BTreeSet};
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
    /// Per cell: a value to colour the cell by (`None`: no fill).
    pub shading: Option<Shading<'a>>,
}

/// Cells filled by a value on a colour scale, with a colour bar in the lower right corner.
#[derive(Clone, Copy, Debug)]
pub struct Shading<'a> {
    /// One value per cell (NaN: not filled).
    pub values: &'a [f64],
    /// The values mapped to the two ends of the scale (values outside are clamped), so that
    /// two pictures with the same range can be compared.
    pub range: [f64; 2],
    /// What the colours mean (drawn in SVG only, with the range).
    pub label: &'a str,
}

/// The colour of `t` in [0, 1] on a blue → green → yellow → red scale.
pub fn colour_scale(t: f64) -> [u8; 3] {
    const STOPS: [[f64; 3]; 5] = [
        [48.0, 18.0, 59.0],
        [40.0, 140.0, 230.0],
        [60.0, 200.0, 110.0],
        [240.0, 200.0, 40.0],
        [200.0, 30.0, 20.0],
    ];
    let t = if t.is_nan() { 0.0 } else { t.clamp(0.0, 1.0) } * 4.0;
    let k = (t.floor() as usize).min(3);
    let f = t - k as f64;
    let (a, b) = (STOPS[k], STOPS[k + 1]);
    let mix = |i: usize| (a[i] + (b[i] - a[i]) * f).round().clamp(0.0, 255.0) as u8;
    [mix(0), mix(1), mix(2)]
}

impl Shading<'_> {
    fn colour(&self, c: usize) -> Option<[u8; 3]> {
        let v = *self.values.get(c)?;
        if !v.is_finite() {
            return None;
        }
        let span = self.range[1] - self.range[0];
        let t = if span > 0.0 {
            (v - self.range[0]) / span
        } else {
            0.0
        };
        Some(colour_scale(t))
    }
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

/// VTK's polygon code: the sections drawn by [`slice_z`] (not a kernel cell kind).
pub const VTK_POLYGON: u8 = 7;

fn unique_edges(cells: &CellList) -> Vec<(u32, u32)> {
    let mut set = BTreeSet::new();
    for (code, nodes) in cells.iter() {
        if code == VTK_POLYGON {
            for (k, &a) in nodes.iter().enumerate() {
                let b = nodes[(k + 1) % nodes.len()];
                set.insert((a.min(b), a.max(b)));
            }
            continue;
        }
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

/// A polygon in picture coordinates.
type Polygon = Vec<(f64, f64)>;

/// Polygons (in picture coordinates) of the cells `keep` selects.
fn cell_polygons(
    pic: &Picture<'_>,
    f: &Frame,
    mut keep: impl FnMut(usize) -> bool,
) -> Vec<(usize, Vec<(f64, f64)>)> {
    let mut out = Vec::new();
    for (c, (code, nodes)) in pic.cells.iter().enumerate() {
        if !keep(c) {
            continue;
        }
        let poly: Vec<(f64, f64)> = match CellKind::from_vtk(code) {
            _ if code == VTK_POLYGON => nodes
                .iter()
                .filter_map(|&n| point(pic.points, n).map(|p| f.map(p)))
                .collect(),
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
            out.push((c, poly));
        }
    }
    out
}

/// Polygons of the highlighted cells.
fn highlighted(pic: &Picture<'_>, f: &Frame) -> Vec<Vec<(f64, f64)>> {
    cell_polygons(pic, f, |c| pic.highlight.get(c).copied().unwrap_or(false))
        .into_iter()
        .map(|(_, p)| p)
        .collect()
}

/// Polygons of the shaded cells with their colours.
fn shaded(pic: &Picture<'_>, f: &Frame) -> Vec<([u8; 3], Polygon)> {
    let Some(sh) = pic.shading else {
        return Vec::new();
    };
    cell_polygons(pic, f, |c| sh.colour(c).is_some())
        .into_iter()
        .filter_map(|(c, p)| sh.colour(c).map(|col| (col, p)))
        .collect()
}

/// The colour bar's rectangle (x, y, width, height) in picture coordinates.
fn colour_bar(f: &Frame) -> (f64, f64, f64, f64) {
    let w = (0.3 * f.width).clamp(60.0, 300.0);
    let h = 14.0;
    (f.width - w - 10.0, f.height - h - 10.0, w, h)
}

/// Steps the colour bar is drawn in.
const BAR_STEPS: usize = 32;

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
    for (col, poly) in shaded(pic, f) {
        let pts: Vec<String> = poly.iter().map(|(x, y)| format!("{x:.2},{y:.2}")).collect();
        let _ = writeln!(
            s,
            "<polygon class=\"shade\" points=\"{}\" fill=\"rgb({},{},{})\" stroke=\"none\"/>",
            pts.join(" "),
            col[0],
            col[1],
            col[2]
        );
    }
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
    let clean = |t: &str| -> String {
        t.chars()
            .map(|c| match c {
                '<' | '>' | '&' => ' ',
                c => c,
            })
            .collect()
    };
    let _ = writeln!(
        s,
        "<text x=\"8\" y=\"20\" font-family=\"sans-serif\" font-size=\"14\" fill=\"black\">{}</text>",
        clean(pic.title)
    );
    if let Some(sh) = pic.shading {
        let (x, y, w, h) = colour_bar(f);
        for k in 0..BAR_STEPS {
            let c = colour_scale((k as f64 + 0.5) / BAR_STEPS as f64);
            let step = w / BAR_STEPS as f64;
            let _ = writeln!(
                s,
                "<rect x=\"{:.2}\" y=\"{y:.2}\" width=\"{:.2}\" height=\"{h}\" fill=\"rgb({},{},{})\"/>",
                x + k as f64 * step,
                step + 0.3,
                c[0],
                c[1],
                c[2]
            );
        }
        let _ = writeln!(
            s,
            "<text x=\"{x:.2}\" y=\"{:.2}\" font-family=\"sans-serif\" font-size=\"12\" fill=\"black\">{}: {:.3} … {:.3}</text>",
            y - 4.0,
            clean(sh.label),
            sh.range[0],
            sh.range[1]
        );
    }
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
    for (col, poly) in shaded(pic, &f) {
        fill_poly(&mut pixmap, &poly, [col[0], col[1], col[2], 255]);
    }
    let mut red = Paint::default();
    red.set_color_rgba8(224, 32, 32, 200);
    red.anti_alias = true;
    for poly in highlighted(pic, &f) {
        if let Some(path) = polygon_path(&poly) {
            pixmap.fill_path(&path, &red, FillRule::EvenOdd, Transform::identity(), None);
            let stroke = Stroke {
                width: 1.5,
                ..Stroke::default()
            };
            pixmap.stroke_path(&path, &red, &stroke, Transform::identity(), None);
        }
    }
    draw_edges(&mut pixmap, pic, &f, pic.cells, [64, 64, 64, 255], 0.0);
    for b in pic.boundaries {
        draw_edges(&mut pixmap, pic, &f, b, [31, 79, 208, 255], 2.0);
    }
    if pic.shading.is_some() {
        let (x, y, w, h) = colour_bar(&f);
        let step = w / BAR_STEPS as f64;
        for k in 0..BAR_STEPS {
            let c = colour_scale((k as f64 + 0.5) / BAR_STEPS as f64);
            let x0 = x + k as f64 * step;
            let rect = [
                (x0, y),
                (x0 + step + 0.5, y),
                (x0 + step + 0.5, y + h),
                (x0, y + h),
            ];
            fill_poly(&mut pixmap, &rect, [c[0], c[1], c[2], 255]);
        }
    }
    Ok(pixmap)
}

/// A closed polygon in pixel coordinates (`None` when it has no area to draw).
fn polygon_path(poly: &[(f64, f64)]) -> Option<tiny_skia::Path> {
    let mut pb = PathBuilder::new();
    for (k, (x, y)) in poly.iter().enumerate() {
        if k == 0 {
            pb.move_to(*x as f32, *y as f32);
        } else {
            pb.line_to(*x as f32, *y as f32);
        }
    }
    pb.close();
    pb.finish()
}

/// Fills a polygon in one colour, without anti-aliasing (shaded cells tile without seams).
fn fill_poly(pixmap: &mut Pixmap, poly: &[(f64, f64)], rgba: [u8; 4]) {
    if let Some(path) = polygon_path(poly) {
        let mut paint = Paint::default();
        paint.set_color_rgba8(rgba[0], rgba[1], rgba[2], rgba[3]);
        paint.anti_alias = false;
        pixmap.fill_path(
            &path,
            &paint,
            FillRule::EvenOdd,
            Transform::identity(),
            None,
        );
    }
}

/// Strokes every edge of `cells` once that is visible in the frame.
fn draw_edges(
    pixmap: &mut Pixmap,
    pic: &Picture<'_>,
    f: &Frame,
    cells: &CellList,
    rgba: [u8; 4],
    width: f32,
) {
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
}

/// A 3D mesh cut by the plane `z = z0`: each cell the plane crosses becomes the polygon of
/// its section (a [`VTK_POLYGON`] cell), each boundary face a segment; highlighted flags and
/// shading values follow their cells. Points are the edge–plane intersections (one per cut
/// edge, shared by the cells around it, so shared section edges are drawn once). 2D cells
/// are dropped.
#[derive(Clone, Debug, Default)]
pub struct Section {
    /// Intersection points (z = z0).
    pub points: Vec<[f64; 3]>,
    /// Section polygons.
    pub cells: CellList,
    /// For each section polygon, the index of the cell it cuts.
    pub source: Vec<usize>,
    /// The boundary lists' sections (line segments).
    pub boundaries: Vec<CellList>,
}

/// The section of `cells` (and of the boundary face lists) by the plane `z = z0`.
pub fn slice_z(
    points: &[[f64; 3]],
    cells: &CellList,
    boundaries: &[&CellList],
    z0: f64,
) -> Section {
    let mut cutter = Cutter {
        points,
        z0,
        index: BTreeMap::new(),
    };
    let mut out = Section::default();
    for (c, (code, nodes)) in cells.iter().enumerate() {
        let Some(kind) = CellKind::from_vtk(code) else {
            continue;
        };
        if kind.dimension() < 3 {
            continue;
        }
        let mut ids = cutter.cut_cell(kind, nodes, &mut out);
        ring(&mut ids, &out.points);
        if ids.len() >= 3 {
            out.cells.push_code(VTK_POLYGON, &ids);
            out.source.push(c);
        }
    }
    for list in boundaries {
        let mut segs = CellList::new();
        for (code, nodes) in list.iter() {
            let Some(kind) = CellKind::from_vtk(code) else {
                continue;
            };
            let mut ids = cutter.cut_cell(kind, nodes, &mut out);
            ids.sort_unstable();
            ids.dedup();
            if let [a, b] = ids[..] {
                segs.push(CellKind::Line, &[a, b]);
            }
        }
        out.boundaries.push(segs);
    }
    out
}

/// The edge–plane intersections of [`slice_z`], one point per cut edge.
struct Cutter<'p> {
    points: &'p [[f64; 3]],
    z0: f64,
    index: BTreeMap<(u32, u32), u32>,
}

impl Cutter<'_> {
    /// The section point of edge `a`–`b` (added to `out` the first time), if the plane cuts it.
    fn cut(&mut self, a: u32, b: u32, out: &mut Section) -> Option<u32> {
        let (pa, pb) = (point(self.points, a)?, point(self.points, b)?);
        let (da, db) = (pa[2] - self.z0, pb[2] - self.z0);
        // Half-open rule: a node exactly on the plane counts as above, so each crossing
        // edge is found once and a face lying in the plane produces nothing degenerate.
        if (da >= 0.0) == (db >= 0.0) {
            return None;
        }
        let key = (a.min(b), a.max(b));
        if let Some(&k) = self.index.get(&key) {
            return Some(k);
        }
        let t = da / (da - db);
        let p = [
            pa[0] + t * (pb[0] - pa[0]),
            pa[1] + t * (pb[1] - pa[1]),
            self.z0,
        ];
        let k = u32::try_from(out.points.len()).ok()?;
        out.points.push(p);
        self.index.insert(key, k);
        Some(k)
    }

    /// The section points of every cut edge of one cell (or face).
    fn cut_cell(&mut self, kind: CellKind, nodes: &[u32], out: &mut Section) -> Vec<u32> {
        let mut ids = Vec::new();
        for e in kind.edges() {
            let (Some(&a), Some(&b)) = (nodes.get(e[0] as usize), nodes.get(e[1] as usize)) else {
                continue;
            };
            if let Some(k) = self.cut(a, b, out) {
                ids.push(k);
            }
        }
        ids
    }
}

/// Orders a cell's section points (once each) around their centroid, into a polygon.
fn ring(ids: &mut Vec<u32>, pts: &[[f64; 3]]) {
    ids.sort_unstable();
    ids.dedup();
    let n = ids.len() as f64;
    let (cx, cy) = ids.iter().fold((0.0, 0.0), |(x, y), &k| {
        let p = pts[k as usize];
        (x + p[0] / n, y + p[1] / n)
    });
    ids.sort_by(|&a, &b| {
        let (pa, pb) = (pts[a as usize], pts[b as usize]);
        let ta = (pa[1] - cy).atan2(pa[0] - cx);
        let tb = (pb[1] - cy).atan2(pb[0] - cx);
        ta.total_cmp(&tb)
    });
}

/// True when any cell of `cells` is a volume cell, so pictures show a section.
pub fn has_volume_cells(cells: &CellList) -> bool {
    cells
        .iter()
        .any(|(code, _)| CellKind::from_vtk(code).is_some_and(|k| k.dimension() == 3))
}
