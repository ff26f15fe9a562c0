//! CGNS meshes (`--features cgns`, through the CGNS library: crate deform-cgns) as the tool's
//! meshes: the unstructured zone of the first base as an SU2 mesh (element sections as cells,
//! boundary conditions as markers), or the structured zones as the blocks of a Plot3D grid.
//! Writing copies the file the mesh came from with new coordinates (everything else kept), or
//! builds a new file from an SU2 mesh or a Plot3D grid.

use std::collections::HashMap;
use std::path::Path;

use deform_cgns::{etype, ptset, Base, Boco, Section, Zone};
use deform_kernel::CellKind;

use super::plot3d::{Plot3dBlock, Plot3dGrid};
use super::su2::{Su2Marker, Su2Mesh};
use super::CellList;

/// The start of the messages about valid CGNS that the tool does not support (exit 3).
pub const UNSUPPORTED: &str = "not supported: ";

/// Reads every base of a CGNS file.
pub fn read(path: &Path) -> Result<Vec<Base>, String> {
    deform_cgns::read(path).map_err(|e| e.to_string())
}

/// The first base that has zones.
fn first_base(bases: &[Base]) -> Result<&Base, String> {
    bases
        .iter()
        .find(|b| !b.zones.is_empty())
        .ok_or_else(|| "the file has no zone".to_string())
}

/// True when the first base's zones are structured.
pub fn is_structured(bases: &[Base]) -> Result<bool, String> {
    let b = first_base(bases)?;
    let s = b.zones.iter().filter(|z| z.structured).count();
    match s {
        0 => Ok(false),
        n if n == b.zones.len() => Ok(true),
        _ => Err(format!(
            "{UNSUPPORTED}a base with structured and unstructured zones"
        )),
    }
}

/// CGNS element type → the kernel's kind.
fn kind_of(t: i64) -> Option<CellKind> {
    Some(match i32::try_from(t).ok()? {
        etype::BAR_2 => CellKind::Line,
        etype::TRI_3 => CellKind::Triangle,
        etype::QUAD_4 => CellKind::Quad,
        etype::TETRA_4 => CellKind::Tetra,
        etype::PYRA_5 => CellKind::Pyramid,
        etype::PENTA_6 => CellKind::Prism,
        etype::HEXA_8 => CellKind::Hexahedron,
        _ => return None,
    })
}

/// The kernel's kind → CGNS element type.
fn cgns_of(kind: CellKind) -> i32 {
    match kind {
        CellKind::Line => etype::BAR_2,
        CellKind::Triangle => etype::TRI_3,
        CellKind::Quad => etype::QUAD_4,
        CellKind::Tetra => etype::TETRA_4,
        CellKind::Pyramid => etype::PYRA_5,
        CellKind::Prism => etype::PENTA_6,
        _ => etype::HEXA_8,
    }
}

/// CGNS lists a `PENTA_6` with its base `1,2,3` turning towards the top `4,5,6` (the face
/// `1,3,2` points out of the cell); SU2 and the kernel call a prism positive when its base
/// turns away from the top. Swapping nodes 1 ↔ 2 and 4 ↔ 5 (0-based) converts either way.
fn swap_prism<T>(nodes: &mut [T]) {
    if nodes.len() == 6 {
        nodes.swap(1, 2);
        nodes.swap(4, 5);
    }
}

/// The elements of a section: (element number, kind, 0-based nodes).
fn elements(s: &Section, nvert: usize) -> Result<Vec<(i64, CellKind, Vec<u32>)>, String> {
    let mut out = Vec::new();
    let mut it = s.connectivity.iter().copied();
    for number in s.range.0..=s.range.1 {
        let t = if s.etype == etype::MIXED {
            it.next().unwrap_or(-1)
        } else {
            i64::from(s.etype)
        };
        let kind = kind_of(t).ok_or_else(|| {
            format!("{UNSUPPORTED}section {}: element type {t} (linear elements only: BAR_2, TRI_3, QUAD_4, TETRA_4, PYRA_5, PENTA_6, HEXA_8)", s.name)
        })?;
        let mut nodes = Vec::with_capacity(kind.node_count());
        for _ in 0..kind.node_count() {
            let v = it
                .next()
                .ok_or_else(|| format!("section {}: connectivity ends early", s.name))?;
            if v < 1 || v as u64 > nvert as u64 {
                return Err(format!(
                    "section {}: element {number}: vertex {v} is not in 1..={nvert}",
                    s.name
                ));
            }
            nodes.push((v - 1) as u32);
        }
        if kind == CellKind::Prism {
            swap_prism(&mut nodes);
        }
        out.push((number, kind, nodes));
    }
    Ok(out)
}

/// The unstructured zone of the first base as an SU2 mesh.
pub fn to_su2(bases: &[Base]) -> Result<Su2Mesh, String> {
    let base = first_base(bases)?;
    let [zone] = base.zones.as_slice() else {
        return Err(format!(
            "{UNSUPPORTED}{} unstructured zones in one base (one is supported)",
            base.zones.len()
        ));
    };
    let dim = base.cell_dim;
    if dim != 2 && dim != 3 {
        return Err(format!("{UNSUPPORTED}cell dimension {dim}"));
    }
    let nvert = zone.coords.len();
    let mut cells = CellList::new();
    let mut boundary: HashMap<i64, (CellKind, Vec<u32>)> = HashMap::new();
    let mut unused: Vec<(String, Vec<i64>)> = Vec::new();
    for s in &zone.sections {
        let mut numbers = Vec::new();
        for (number, kind, nodes) in elements(s, nvert)? {
            if kind.dimension() == dim {
                cells.push(kind, &nodes);
            } else if kind.dimension() + 1 == dim {
                boundary.insert(number, (kind, nodes));
                numbers.push(number);
            }
        }
        if !numbers.is_empty() {
            unused.push((s.name.clone(), numbers));
        }
    }
    let mut markers = Vec::new();
    // Boundary conditions over elements subdivide the sections; those over vertices (ICEM,
    // ANSA) are left to the sections, as SU2 does: a vertex set does not say which faces.
    for bc in zone.bocos.iter().filter(|bc| !by_vertex(bc)) {
        let numbers = boco_elements(bc, &boundary)?;
        unused
            .iter_mut()
            .for_each(|(_, n)| n.retain(|x| !numbers.contains(x)));
        markers.push(marker(&bc.name, &numbers, &boundary));
    }
    for (name, numbers) in unused.iter().filter(|(_, n)| !n.is_empty()) {
        markers.push(marker(name, numbers, &boundary));
    }
    Ok(Su2Mesh {
        dim,
        points: zone.coords.clone(),
        elements: cells,
        markers,
        passthrough: Vec::new(),
    })
}

fn marker(name: &str, numbers: &[i64], boundary: &HashMap<i64, (CellKind, Vec<u32>)>) -> Su2Marker {
    let mut elements = CellList::new();
    for n in numbers {
        if let Some((kind, nodes)) = boundary.get(n) {
            elements.push(*kind, nodes);
        }
    }
    Su2Marker {
        name: name.to_string(),
        elements,
    }
}

/// A boundary condition given as a set of vertices.
fn by_vertex(bc: &Boco) -> bool {
    bc.location == ptset::VERTEX
        && bc.ptset != ptset::ELEMENT_RANGE
        && bc.ptset != ptset::ELEMENT_LIST
}

/// The boundary elements a BC names by element number (ranges or lists, at faces or edges).
fn boco_elements(
    bc: &Boco,
    boundary: &HashMap<i64, (CellKind, Vec<u32>)>,
) -> Result<Vec<i64>, String> {
    let range = bc.ptset == ptset::POINT_RANGE || bc.ptset == ptset::ELEMENT_RANGE;
    let listed: Vec<i64> = match (range, bc.points.as_slice()) {
        (true, [a, b]) => (*a..=*b).collect(),
        (true, _) => {
            return Err(format!(
                "boundary condition {}: a range of {} values",
                bc.name,
                bc.points.len()
            ))
        }
        (false, p) => p.to_vec(),
    };
    if let Some(bad) = listed.iter().find(|n| !boundary.contains_key(n)) {
        return Err(format!(
            "boundary condition {}: element {bad} is not a boundary element of the zone's sections",
            bc.name
        ));
    }
    Ok(listed)
}

/// The structured zones of the first base as Plot3D blocks (2D zones with `nk = 1`).
pub fn to_plot3d(bases: &[Base]) -> Result<Plot3dGrid, String> {
    let base = first_base(bases)?;
    let dim = base.cell_dim;
    if dim != 2 && dim != 3 {
        return Err(format!("{UNSUPPORTED}cell dimension {dim}"));
    }
    let mut blocks = Vec::new();
    for z in &base.zones {
        let mut dims = [1usize; 3];
        for (d, &v) in dims.iter_mut().zip(&z.dims) {
            *d = v;
        }
        blocks.push(Plot3dBlock {
            dims,
            points: z.coords.clone(),
            iblank: None,
        });
    }
    Ok(Plot3dGrid { dim, blocks })
}

/// Copies the CGNS file `input` to `output` with new coordinates for the zones of its first
/// base, everything else kept.
pub fn rewrite_coords(input: &Path, output: &Path, coords: &[&[[f64; 3]]]) -> Result<(), String> {
    deform_cgns::rewrite_coords(input, output, coords).map_err(|e| e.to_string())
}

/// A new CGNS file for an SU2 mesh: one zone, the cells in one section (`MIXED` when of
/// several kinds), each marker a section of boundary elements and a boundary condition over
/// that element range.
pub fn from_su2(m: &Su2Mesh) -> Result<Vec<Base>, String> {
    let mut sections = Vec::new();
    let mut next = 1i64;
    let mut add = |name: &str, list: &CellList| -> Result<(i64, i64), String> {
        if list.is_empty() {
            return Ok((0, -1));
        }
        let kinds: Vec<CellKind> = list
            .kinds
            .iter()
            .filter_map(|&k| CellKind::from_vtk(k))
            .collect();
        let mixed = kinds.iter().any(|k| Some(k) != kinds.first());
        let mut conn = Vec::new();
        for ((_, nodes), kind) in list.iter().zip(&kinds) {
            if mixed {
                conn.push(i64::from(cgns_of(*kind)));
            }
            let mut one: Vec<i64> = nodes.iter().map(|&n| i64::from(n) + 1).collect();
            if *kind == CellKind::Prism {
                swap_prism(&mut one);
            }
            conn.extend(one);
        }
        let t = if mixed {
            etype::MIXED
        } else {
            kinds.first().map_or(etype::MIXED, |k| cgns_of(*k))
        };
        let range = (next, next + list.len() as i64 - 1);
        next = range.1 + 1;
        sections.push(Section {
            name: name.to_string(),
            etype: t,
            range,
            connectivity: conn,
        });
        Ok(range)
    };
    add("Elements", &m.elements)?;
    let mut bocos = Vec::new();
    for mk in &m.markers {
        if mk.name.len() > 32 {
            return Err(format!(
                "marker {:?} is longer than CGNS's 32 characters",
                mk.name
            ));
        }
        let (a, b) = add(&mk.name, &mk.elements)?;
        let location = if m.dim == 2 {
            ptset::EDGE_CENTER
        } else {
            ptset::FACE_CENTER
        };
        bocos.push(Boco {
            name: mk.name.clone(),
            bctype: deform_cgns::BC_USER_DEFINED,
            ptset: ptset::POINT_RANGE,
            location,
            points: vec![a, b],
        });
    }
    let zone = Zone {
        name: "Zone".into(),
        structured: false,
        dims: vec![m.points.len()],
        coords: m.points.clone(),
        sections,
        bocos,
    };
    Ok(vec![Base {
        name: "Base".into(),
        cell_dim: m.dim,
        phys_dim: m.dim,
        zones: vec![zone],
    }])
}

/// A new CGNS file for a Plot3D grid: one structured zone per block.
pub fn from_plot3d(g: &Plot3dGrid) -> Vec<Base> {
    let zones = g
        .blocks
        .iter()
        .enumerate()
        .map(|(b, blk)| Zone {
            name: format!("Block {}", b + 1),
            structured: true,
            dims: blk.dims[..g.dim].to_vec(),
            coords: blk.points.clone(),
            sections: Vec::new(),
            bocos: Vec::new(),
        })
        .collect();
    vec![Base {
        name: "Base".into(),
        cell_dim: g.dim,
        phys_dim: g.dim,
        zones,
    }]
}

/// Writes `bases` to `path` through the library.
pub fn write(path: &Path, bases: &[Base]) -> Result<(), String> {
    deform_cgns::write(path, bases).map_err(|e| e.to_string())
}
