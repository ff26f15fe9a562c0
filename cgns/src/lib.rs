//! CGNS meshes through the CGNS library itself (libcgns, mid-level API): the zones of every
//! base with their coordinates, element sections and boundary conditions, read and written.
//! HDF5 and ADF files are read (whatever the library was built for); files are written as HDF5.
//!
//! The model keeps CGNS's own numbering (1-based element and vertex numbers, element type codes
//! of `ElementType_t`); turning it into meshes is the caller's business.

mod sys;

use std::fmt;
use std::path::Path;

pub use sys::CgSize;

/// Element type codes (`ElementType_t`).
pub mod etype {
    /// `BAR_2`.
    pub const BAR_2: i32 = 3;
    /// `TRI_3`.
    pub const TRI_3: i32 = 5;
    /// `QUAD_4`.
    pub const QUAD_4: i32 = 7;
    /// `TETRA_4`.
    pub const TETRA_4: i32 = 10;
    /// `PYRA_5`.
    pub const PYRA_5: i32 = 12;
    /// `PENTA_6`.
    pub const PENTA_6: i32 = 14;
    /// `HEXA_8`.
    pub const HEXA_8: i32 = 17;
    /// `MIXED`: each element's connectivity starts with its type code.
    pub const MIXED: i32 = 20;
}

/// Point set types (`PointSetType_t`) and grid locations (`GridLocation_t`) the tool uses.
pub mod ptset {
    /// `PointList`.
    pub const POINT_LIST: i32 = 2;
    /// `PointRange`.
    pub const POINT_RANGE: i32 = 4;
    /// `ElementRange`.
    pub const ELEMENT_RANGE: i32 = 6;
    /// `ElementList`.
    pub const ELEMENT_LIST: i32 = 7;
    /// `Vertex` (grid location).
    pub const VERTEX: i32 = 2;
    /// `FaceCenter` (grid location).
    pub const FACE_CENTER: i32 = 4;
    /// `EdgeCenter` (grid location).
    pub const EDGE_CENTER: i32 = 8;
}

/// `BCTypeUserDefined`, written for markers (their names carry the meaning).
pub const BC_USER_DEFINED: i32 = 1;

/// A failed library call and the library's message.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Error {
    /// The C function.
    pub call: &'static str,
    /// `cg_get_error()` after it.
    pub message: String,
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "CGNS library: {}: {}", self.call, self.message)
    }
}

impl std::error::Error for Error {}

/// An element section.
#[derive(Clone, Debug, PartialEq)]
pub struct Section {
    /// Section name.
    pub name: String,
    /// `ElementType_t` code.
    pub etype: i32,
    /// First and last element number (1-based, zone-wide).
    pub range: (i64, i64),
    /// Connectivity (1-based vertices; for `MIXED`, each element preceded by its type).
    pub connectivity: Vec<i64>,
}

/// A boundary condition.
#[derive(Clone, Debug, PartialEq)]
pub struct Boco {
    /// BC name.
    pub name: String,
    /// `BCType_t` code.
    pub bctype: i32,
    /// `PointSetType_t` code.
    pub ptset: i32,
    /// `GridLocation_t` code.
    pub location: i32,
    /// The points (index-dimension values each).
    pub points: Vec<i64>,
}

/// A zone.
#[derive(Clone, Debug, PartialEq)]
pub struct Zone {
    /// Zone name.
    pub name: String,
    /// True for `Structured`, false for `Unstructured`.
    pub structured: bool,
    /// Structured: vertices along each index direction (index dimension many); unstructured:
    /// `[vertex count]`.
    pub dims: Vec<usize>,
    /// Vertex coordinates (`z` = 0 when the base is 2D), structured i fastest.
    pub coords: Vec<[f64; 3]>,
    /// Element sections (unstructured).
    pub sections: Vec<Section>,
    /// Boundary conditions.
    pub bocos: Vec<Boco>,
}

/// A base: its dimensions and zones.
#[derive(Clone, Debug, PartialEq)]
pub struct Base {
    /// Base name.
    pub name: String,
    /// Cell dimension (2 or 3).
    pub cell_dim: usize,
    /// Physical dimension (2 or 3).
    pub phys_dim: usize,
    /// Zones in file order.
    pub zones: Vec<Zone>,
}

fn too_large(call: &'static str, what: &str) -> Error {
    Error {
        call,
        message: format!("{what} does not fit this machine's sizes"),
    }
}

fn path_str<'a>(path: &'a Path, call: &'static str) -> Result<&'a str, Error> {
    path.to_str().ok_or_else(|| Error {
        call,
        message: format!("{} is not a UTF-8 path", path.display()),
    })
}

fn read_zone(f: &sys::File, b: i32, z: i32, phys_dim: usize) -> Result<Zone, Error> {
    let (name, t, idim, size) = f.zone(b, z)?;
    let structured = t == sys::STRUCTURED;
    if !structured && t != sys::UNSTRUCTURED {
        return Err(Error {
            call: "cg_zone_type",
            message: format!("zone {name}: zone type {t}"),
        });
    }
    let rmax: Vec<CgSize> = if structured {
        size[..idim].to_vec()
    } else {
        size[..1].to_vec()
    };
    let dims: Vec<usize> = rmax
        .iter()
        .map(|&v| usize::try_from(v).unwrap_or(0))
        .collect();
    let n = dims
        .iter()
        .try_fold(1usize, |a, &d| a.checked_mul(d))
        .ok_or_else(|| too_large("cg_zone_read", "the vertex count"))?;
    let mut coords = vec![[0.0f64; 3]; n];
    for (k, axis) in ["CoordinateX", "CoordinateY", "CoordinateZ"]
        .iter()
        .enumerate()
        .take(phys_dim)
    {
        let v = f.coord(b, z, axis, &rmax, n)?;
        for (p, x) in coords.iter_mut().zip(v) {
            p[k] = x;
        }
    }
    let mut sections = Vec::new();
    if !structured {
        for s in 1..=f.nsections(b, z)? {
            let (name, etype, start, end, conn) = f.section(b, z, s)?;
            sections.push(Section {
                name,
                etype,
                range: (i64::from(start), i64::from(end)),
                connectivity: conn.into_iter().map(i64::from).collect(),
            });
        }
    }
    let mut bocos = Vec::new();
    for bc in 1..=f.nbocos(b, z)? {
        let (name, bctype, ptset, location, pts) =
            f.boco(b, z, bc, if structured { idim } else { 1 })?;
        bocos.push(Boco {
            name,
            bctype,
            ptset,
            location,
            points: pts.into_iter().map(i64::from).collect(),
        });
    }
    Ok(Zone {
        name,
        structured,
        dims,
        coords,
        sections,
        bocos,
    })
}

/// Reads every base of the CGNS file `path`.
pub fn read(path: &Path) -> Result<Vec<Base>, Error> {
    let f = sys::File::open(path_str(path, "cg_open")?, sys::MODE_READ)?;
    let mut bases = Vec::new();
    for b in 1..=f.nbases()? {
        let (name, cd, pd) = f.base(b)?;
        let phys_dim = usize::try_from(pd).unwrap_or(0).min(3);
        let mut zones = Vec::new();
        for z in 1..=f.nzones(b)? {
            zones.push(read_zone(&f, b, z, phys_dim)?);
        }
        bases.push(Base {
            name,
            cell_dim: usize::try_from(cd).unwrap_or(0),
            phys_dim,
            zones,
        });
    }
    f.close()?;
    Ok(bases)
}

fn sizes(v: &[i64], call: &'static str) -> Result<Vec<CgSize>, Error> {
    v.iter()
        .map(|&x| CgSize::try_from(x).map_err(|_| too_large(call, "a number")))
        .collect()
}

fn write_zone(f: &sys::File, b: i32, base: &Base, zone: &Zone) -> Result<(), Error> {
    let idim = zone.dims.len();
    let mut size: Vec<i64> = zone.dims.iter().map(|&d| d as i64).collect();
    if zone.structured {
        size.extend(zone.dims.iter().map(|&d| (d as i64 - 1).max(1)));
        size.extend(std::iter::repeat_n(0, idim));
    } else {
        let cells: i64 = zone
            .sections
            .iter()
            .filter(|s| section_dim(s) == Some(base.cell_dim))
            .map(|s| s.range.1 - s.range.0 + 1)
            .sum();
        size = vec![zone.coords.len() as i64, cells, 0];
    }
    let t = if zone.structured {
        sys::STRUCTURED
    } else {
        sys::UNSTRUCTURED
    };
    let z = f.write_zone(b, &zone.name, &sizes(&size, "cg_zone_write")?, t)?;
    for (k, axis) in ["CoordinateX", "CoordinateY", "CoordinateZ"]
        .iter()
        .enumerate()
        .take(base.phys_dim)
    {
        let v: Vec<f64> = zone.coords.iter().map(|p| p[k]).collect();
        f.write_coord(b, z, axis, &v)?;
    }
    for s in &zone.sections {
        let range = (
            CgSize::try_from(s.range.0)
                .map_err(|_| too_large("cg_section_write", "an element number"))?,
            CgSize::try_from(s.range.1)
                .map_err(|_| too_large("cg_section_write", "an element number"))?,
        );
        f.write_section(
            b,
            z,
            &s.name,
            s.etype,
            range,
            &sizes(&s.connectivity, "cg_section_write")?,
        )?;
    }
    for bc in &zone.bocos {
        let idim = if zone.structured { idim } else { 1 };
        let pts = sizes(&bc.points, "cg_boco_write")?;
        f.write_boco(
            b,
            z,
            &bc.name,
            (bc.bctype, bc.ptset, bc.location),
            &pts,
            idim,
        )?;
    }
    Ok(())
}

/// The dimension of a section's elements (`MIXED`: of its first element); `None` if unknown.
pub fn section_dim(s: &Section) -> Option<usize> {
    let t = if s.etype == etype::MIXED {
        i32::try_from(*s.connectivity.first()?).ok()?
    } else {
        s.etype
    };
    match t {
        etype::BAR_2 => Some(1),
        etype::TRI_3 | etype::QUAD_4 => Some(2),
        etype::TETRA_4 | etype::PYRA_5 | etype::PENTA_6 | etype::HEXA_8 => Some(3),
        _ => None,
    }
}

/// Writes `bases` to a new HDF5 CGNS file at `path` (an existing file is replaced).
pub fn write(path: &Path, bases: &[Base]) -> Result<(), Error> {
    let f = sys::File::open(path_str(path, "cg_open")?, sys::MODE_WRITE)?;
    for base in bases {
        let b = f.write_base(&base.name, base.cell_dim as i32, base.phys_dim as i32)?;
        for zone in &base.zones {
            write_zone(&f, b, base, zone)?;
        }
    }
    f.close()
}

/// Copies the CGNS file `input` to `output` and replaces, in the copy, the coordinates of the
/// zones of the first base that has zones (`coords[k]` for zone k + 1, as many points as the
/// zone has vertices) with doubles. Everything else in the file (families, connectivity,
/// solutions, the HDF5 or ADF format) stays as it was.
pub fn rewrite_coords(input: &Path, output: &Path, coords: &[&[[f64; 3]]]) -> Result<(), Error> {
    let copy_err = |e: std::io::Error| Error {
        call: "copy",
        message: e.to_string(),
    };
    std::fs::copy(input, output).map_err(copy_err)?;
    let f = sys::File::open(path_str(output, "cg_open")?, sys::MODE_MODIFY)?;
    let mut b = 0;
    for k in 1..=f.nbases()? {
        if f.nzones(k)? > 0 {
            b = k;
            break;
        }
    }
    let (_, _, pd) = f.base(b)?;
    let nz = usize::try_from(f.nzones(b)?).unwrap_or(0);
    if nz != coords.len() {
        return Err(Error {
            call: "cg_nzones",
            message: format!("{nz} zones, {} coordinate sets", coords.len()),
        });
    }
    for (z, pts) in (1..).zip(coords) {
        let (name, t, idim, size) = f.zone(b, z)?;
        let n: i64 = if t == sys::STRUCTURED {
            size[..idim].iter().map(|&v| i64::from(v)).product()
        } else {
            size.first().map_or(0, |&v| i64::from(v))
        };
        if n != pts.len() as i64 {
            return Err(Error {
                call: "cg_zone_read",
                message: format!("zone {name}: {n} vertices, {} points", pts.len()),
            });
        }
        let axes = ["CoordinateX", "CoordinateY", "CoordinateZ"];
        for (k, axis) in axes
            .iter()
            .enumerate()
            .take(usize::try_from(pd).unwrap_or(0))
        {
            let v: Vec<f64> = pts.iter().map(|p| p[k]).collect();
            f.write_coord(b, z, axis, &v)?;
        }
    }
    f.close()
}
