//! Deterministic mesh generators (std) shared by the tests, the benchmarks and `deform demo`.
//!
//! Every generator is a pure function of its options: no clock, no hashing with random state,
//! noise from a fixed-seed xorshift ([`rng::XorShift64`]) and transcendental functions from
//! `libm`, so the same call gives the same bits on every platform.
//!
//! Conventions (shared with the kernel):
//! - Points are `[f64; D]`; cells are CSR `offsets`/`nodes`/`kinds` with VTK type codes and
//!   VTK node order, ready for [`deform_kernel::Cells::new`] (see [`Mesh::cells`]).
//! - 2D cells are counter-clockwise (positive signed area). 3D cells have positive volume in
//!   the VTK convention (hex and pyramid base `0,1,2,3` turning towards the top/apex; the
//!   prism/wedge base `0,1,2` turning *away* from `3,4,5`, as `vtkWedge` documents).
//! - Boundary markers ([`Marker`]) hold boundary elements: lines in 2D, triangles or quads in
//!   3D. Every element is oriented so that its right-hand normal points **out of the domain**
//!   (into the body for an airfoil wall): in 2D a line `a → b` has the domain on its left and
//!   the outward normal `(dy, −dx)`.
//! - Structured meshes record their block dimensions `[ni, nj, nk]` with point index
//!   `i + ni (j + nj k)`; the airfoil O-grids are periodic in `i` (no duplicated seam), flagged
//!   by [`Mesh::periodic_i`].

// Option checks are written `!(x > 0.0)` on purpose: the negation also rejects NaN.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use std::fmt;

pub mod adapted;
pub mod airfoil;
pub mod blocks;
pub mod extrude;
pub mod motion;
pub mod naca;
pub mod partition;
pub mod rng;
pub mod shapes;

pub use adapted::{adapted_block, AdaptedSpec};
pub use airfoil::{naca_hybrid, naca_ogrid, naca_triangulated, AirfoilGrid};
pub use blocks::{block2, block3, cavity2, cavity3, noisy_block2, noisy_block3, BlockSpec};
pub use extrude::{extrude, twist_bend, TwistBend};
pub use motion::{rotate_markers2, rotate_markers3, Prescribed};
pub use naca::Naca4;
pub use shapes::{annulus, box_with_inner_box2, box_with_inner_box3};

use deform_kernel::{CellKind, Cells};

/// A 2D mesh.
pub type Mesh2 = Mesh<2>;
/// A 3D mesh.
pub type Mesh3 = Mesh<3>;

/// What went wrong building a mesh.
#[derive(Clone, Debug, PartialEq)]
pub enum MeshError {
    /// An option is out of range; the string says which and why.
    InvalidOption(String),
    /// A NACA code that is not four digits.
    BadNacaCode(String),
    /// No marker of that name.
    UnknownMarker(String),
}

impl fmt::Display for MeshError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            MeshError::InvalidOption(s) => write!(f, "invalid mesh option: {s}"),
            MeshError::BadNacaCode(s) => write!(f, "`{s}` is not a NACA 4-digit code"),
            MeshError::UnknownMarker(s) => write!(f, "the mesh has no marker `{s}`"),
        }
    }
}

impl std::error::Error for MeshError {}

/// Shorthand for results of this crate.
pub type Result<T> = std::result::Result<T, MeshError>;

pub(crate) fn invalid<T>(msg: impl Into<String>) -> Result<T> {
    Err(MeshError::InvalidOption(msg.into()))
}

/// A named set of boundary elements (lines in 2D, triangles/quads in 3D), oriented with the
/// right-hand normal pointing out of the domain, plus the sorted list of their nodes.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct Marker {
    /// The marker name, e.g. `"airfoil"`, `"farfield"`, `"imin"`.
    pub name: String,
    /// CSR offsets of the boundary elements (`kinds.len() + 1` entries).
    pub offsets: Vec<u32>,
    /// Concatenated element nodes.
    pub nodes: Vec<u32>,
    /// VTK kind codes of the elements (3 line, 5 triangle, 9 quad).
    pub kinds: Vec<u8>,
    /// Every node of the marker once, ascending.
    pub node_list: Vec<u32>,
}

impl Marker {
    /// An empty marker called `name`.
    pub fn new(name: &str) -> Self {
        Marker {
            name: name.to_string(),
            offsets: vec![0],
            nodes: Vec::new(),
            kinds: Vec::new(),
            node_list: Vec::new(),
        }
    }

    /// Appends one boundary element.
    pub fn push(&mut self, kind: CellKind, nodes: &[u32]) {
        self.nodes.extend_from_slice(nodes);
        self.kinds.push(kind.vtk_code());
        self.offsets.push(self.nodes.len() as u32);
    }

    /// Recomputes [`Marker::node_list`] from the elements.
    pub fn finish(&mut self) {
        let mut list = self.nodes.clone();
        list.sort_unstable();
        list.dedup();
        self.node_list = list;
    }

    /// Number of boundary elements.
    pub fn len(&self) -> usize {
        self.kinds.len()
    }

    /// `true` when the marker has no elements.
    pub fn is_empty(&self) -> bool {
        self.kinds.is_empty()
    }

    /// The elements as a validated kernel [`Cells`] view over `node_count` mesh points.
    pub fn cells(&self, node_count: usize) -> deform_kernel::Result<Cells<'_>> {
        Cells::new(node_count, &self.offsets, &self.nodes, &self.kinds)
    }
}

/// A mesh: points, mixed cells, boundary markers and (for structured meshes) block dims.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct Mesh<const D: usize> {
    /// Point coordinates.
    pub points: Vec<[f64; D]>,
    /// CSR offsets of the cells (`kinds.len() + 1` entries).
    pub offsets: Vec<u32>,
    /// Concatenated cell nodes, VTK order.
    pub nodes: Vec<u32>,
    /// VTK kind codes.
    pub kinds: Vec<u8>,
    /// Named boundary markers.
    pub markers: Vec<Marker>,
    /// Structured block dimensions `[ni, nj, nk]` when the points are a structured block.
    pub dims: Option<[usize; 3]>,
    /// `true` when the block is periodic in `i` (O-grids: point `i = ni` is point `i = 0`).
    pub periodic_i: bool,
}

impl<const D: usize> Mesh<D> {
    /// An empty mesh.
    pub fn new() -> Self {
        Mesh {
            points: Vec::new(),
            offsets: vec![0],
            nodes: Vec::new(),
            kinds: Vec::new(),
            markers: Vec::new(),
            dims: None,
            periodic_i: false,
        }
    }

    /// Number of points.
    pub fn node_count(&self) -> usize {
        self.points.len()
    }

    /// Number of cells.
    pub fn cell_count(&self) -> usize {
        self.kinds.len()
    }

    /// Appends a cell.
    pub fn push_cell(&mut self, kind: CellKind, nodes: &[u32]) {
        self.nodes.extend_from_slice(nodes);
        self.kinds.push(kind.vtk_code());
        self.offsets.push(self.nodes.len() as u32);
    }

    /// The cells as a validated kernel [`Cells`] view.
    pub fn cells(&self) -> deform_kernel::Result<Cells<'_>> {
        Cells::new(self.points.len(), &self.offsets, &self.nodes, &self.kinds)
    }

    /// Cell `c`'s kind and nodes.
    pub fn cell(&self, c: usize) -> Option<(CellKind, &[u32])> {
        let kind = CellKind::from_vtk(*self.kinds.get(c)?)?;
        let a = *self.offsets.get(c)? as usize;
        let b = *self.offsets.get(c + 1)? as usize;
        Some((kind, self.nodes.get(a..b)?))
    }

    /// The marker called `name`.
    pub fn marker(&self, name: &str) -> Option<&Marker> {
        self.markers.iter().find(|m| m.name == name)
    }

    /// The marker called `name`, or [`MeshError::UnknownMarker`].
    pub fn require_marker(&self, name: &str) -> Result<&Marker> {
        self.marker(name)
            .ok_or_else(|| MeshError::UnknownMarker(name.to_string()))
    }

    /// Per-node fixed mask in the kernel's convention (`1` = fixed): every node of every
    /// marker (the usual Dirichlet set).
    pub fn boundary_mask(&self) -> Vec<u8> {
        self.fixed_mask(&[])
    }

    /// Per-node fixed mask (`1` = fixed): the nodes of the named markers, or of every marker
    /// when `markers` is empty. Unknown names are ignored (see [`Mesh::require_marker`]).
    pub fn fixed_mask(&self, markers: &[&str]) -> Vec<u8> {
        let mut mask = vec![0u8; self.points.len()];
        for m in &self.markers {
            if markers.is_empty() || markers.contains(&m.name.as_str()) {
                for &n in &m.node_list {
                    mask[n as usize] = 1;
                }
            }
        }
        mask
    }

    /// The points converted to `f32` (rounded to nearest).
    pub fn points_f32(&self) -> Vec<[f32; D]> {
        self.points.iter().map(|p| p.map(|x| x as f32)).collect()
    }
}

/// Finds the boundary edges of a 2D mesh (edges used by exactly one cell), oriented as in
/// their cell (so the domain is on the left), and sorts them into markers by `classify`
/// applied to the edge midpoint. Markers are created in the order of `names`.
pub(crate) fn boundary_markers2(
    mesh: &Mesh2,
    names: &[&str],
    classify: impl Fn([f64; 2]) -> usize,
) -> Vec<Marker> {
    use std::collections::BTreeMap;
    let mut edges: BTreeMap<(u32, u32), (u32, u32, usize)> = BTreeMap::new();
    for c in 0..mesh.cell_count() {
        let Some((kind, nodes)) = mesh.cell(c) else {
            continue;
        };
        for e in kind.edges() {
            let a = nodes[e[0] as usize];
            let b = nodes[e[1] as usize];
            let key = (a.min(b), a.max(b));
            edges.entry(key).or_insert((a, b, 0)).2 += 1;
        }
    }
    let mut markers: Vec<Marker> = names.iter().map(|n| Marker::new(n)).collect();
    for &(a, b, count) in edges.values() {
        if count != 1 {
            continue;
        }
        let pa = mesh.points[a as usize];
        let pb = mesh.points[b as usize];
        let mid = [0.5 * (pa[0] + pb[0]), 0.5 * (pa[1] + pb[1])];
        let k = classify(mid).min(markers.len() - 1);
        markers[k].push(CellKind::Line, &[a, b]);
    }
    for m in &mut markers {
        m.finish();
    }
    markers
}

/// Outward-oriented faces of each 3D cell kind (local node numbers, VTK order): the
/// right-hand normal of each face points out of the cell.
pub(crate) fn outward_faces(kind: CellKind) -> &'static [&'static [usize]] {
    match kind {
        CellKind::Hexahedron => &[
            &[0, 3, 2, 1],
            &[4, 5, 6, 7],
            &[0, 1, 5, 4],
            &[1, 2, 6, 5],
            &[2, 3, 7, 6],
            &[3, 0, 4, 7],
        ],
        // VTK wedge: base 0,1,2 turns away from 3,4,5, so it is already outward.
        CellKind::Prism => &[
            &[0, 1, 2],
            &[3, 5, 4],
            &[0, 3, 4, 1],
            &[1, 4, 5, 2],
            &[2, 5, 3, 0],
        ],
        CellKind::Tetra => &[&[0, 2, 1], &[0, 1, 3], &[1, 2, 3], &[2, 0, 3]],
        CellKind::Pyramid => &[
            &[0, 3, 2, 1],
            &[0, 1, 4],
            &[1, 2, 4],
            &[2, 3, 4],
            &[3, 0, 4],
        ],
        _ => &[],
    }
}

/// Finds the boundary faces of a 3D mesh (faces used by exactly one cell), oriented outward,
/// and sorts them into markers by `classify` applied to the face centroid.
pub(crate) fn boundary_markers3(
    mesh: &Mesh3,
    names: &[&str],
    classify: impl Fn([f64; 3]) -> usize,
) -> Vec<Marker> {
    use std::collections::BTreeMap;
    let mut faces: BTreeMap<Vec<u32>, (Vec<u32>, usize)> = BTreeMap::new();
    for c in 0..mesh.cell_count() {
        let Some((kind, nodes)) = mesh.cell(c) else {
            continue;
        };
        for f in outward_faces(kind) {
            let face: Vec<u32> = f.iter().map(|&l| nodes[l]).collect();
            let mut key = face.clone();
            key.sort_unstable();
            faces.entry(key).or_insert((face, 0)).1 += 1;
        }
    }
    let mut markers: Vec<Marker> = names.iter().map(|n| Marker::new(n)).collect();
    for (face, count) in faces.values() {
        if *count != 1 {
            continue;
        }
        let mut c = [0.0; 3];
        for &n in face {
            let p = mesh.points[n as usize];
            for d in 0..3 {
                c[d] += p[d];
            }
        }
        let inv = 1.0 / face.len() as f64;
        let c = c.map(|x| x * inv);
        let k = classify(c).min(markers.len() - 1);
        let kind = if face.len() == 3 {
            CellKind::Triangle
        } else {
            CellKind::Quad
        };
        markers[k].push(kind, face);
    }
    for m in &mut markers {
        m.finish();
    }
    markers
}

/// Removes points no cell uses and renumbers cells and markers (keeps the order of the rest).
pub(crate) fn compact<const D: usize>(mesh: &mut Mesh<D>) {
    let mut used = vec![false; mesh.points.len()];
    for &n in &mesh.nodes {
        used[n as usize] = true;
    }
    let mut map = vec![u32::MAX; mesh.points.len()];
    let mut points = Vec::new();
    for (i, p) in mesh.points.iter().enumerate() {
        if used[i] {
            map[i] = points.len() as u32;
            points.push(*p);
        }
    }
    mesh.points = points;
    for n in &mut mesh.nodes {
        *n = map[*n as usize];
    }
    for m in &mut mesh.markers {
        for n in &mut m.nodes {
            *n = map[*n as usize];
        }
        m.finish();
    }
    mesh.dims = None;
}

/// A geometric distribution of `n` intervals on `[0, 1]` whose first interval is `first`
/// (fraction of the length): returns `n + 1` increasing values from 0 to 1. Uniform when
/// `first ≥ 1/n`. The growth ratio is found by bisection (deterministic, 200 steps).
pub fn geometric_fractions(n: usize, first: f64) -> Vec<f64> {
    let n = n.max(1);
    let uniform = || (0..=n).map(|k| k as f64 / n as f64).collect::<Vec<_>>();
    if !(first > 0.0) || first * n as f64 >= 1.0 {
        return uniform();
    }
    // Sum of first * q^k for k < n equals 1.
    let total = |q: f64| {
        let mut s = 0.0;
        let mut h = first;
        for _ in 0..n {
            s += h;
            h *= q;
        }
        s
    };
    let (mut lo, mut hi) = (1.0, 2.0);
    while total(hi) < 1.0 && hi < 1e6 {
        hi *= 2.0;
    }
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if total(mid) < 1.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let q = 0.5 * (lo + hi);
    let mut out = Vec::with_capacity(n + 1);
    let mut s = 0.0;
    let mut h = first;
    out.push(0.0);
    for _ in 0..n {
        s += h;
        h *= q;
        out.push(s);
    }
    // Normalise so the last value is exactly 1.
    let last = s;
    for v in &mut out {
        *v /= last;
    }
    out
}

/// Fractions on `[0, 1]` for `n` intervals whose consecutive ratio is `ratio` (1 = uniform).
pub fn stretched_fractions(n: usize, ratio: f64) -> Vec<f64> {
    let n = n.max(1);
    let mut out = Vec::with_capacity(n + 1);
    let mut s = 0.0;
    let mut h = 1.0;
    out.push(0.0);
    for _ in 0..n {
        s += h;
        h *= ratio;
        out.push(s);
    }
    for v in &mut out {
        *v /= s;
    }
    out
}
