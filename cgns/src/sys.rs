//! The CGNS mid-level C API (cgnslib.h, CGNS 3.4 and later), declared by hand, and thin safe
//! wrappers: every buffer handed to the library is sized here from what the library said
//! before (counts, sizes), and every call's status is turned into an [`Error`].
#![allow(unsafe_code)] // the C API boundary: only this module calls into libcgns

use std::ffi::{c_char, c_int, c_void, CStr, CString};

use crate::Error;

/// `cgsize_t`: `int` or a 64-bit integer, as the installed library was built (build.rs).
#[cfg(not(cgsize64))]
pub type CgSize = i32;
/// `cgsize_t`: `int` or a 64-bit integer, as the installed library was built (build.rs).
#[cfg(cgsize64)]
pub type CgSize = i64;

/// `CG_MODE_READ`.
pub const MODE_READ: c_int = 0;
/// `CG_MODE_WRITE`.
pub const MODE_WRITE: c_int = 1;
/// `CG_MODE_MODIFY`.
pub const MODE_MODIFY: c_int = 2;
/// `CG_FILE_HDF5`.
pub const FILE_HDF5: c_int = 2;
/// `RealDouble` (DataType_t).
pub const REAL_DOUBLE: c_int = 4;
/// `Vertex` (GridLocation_t).
pub const VERTEX: c_int = 2;
/// `ElementRange` (PointSetType_t).
pub const ELEMENT_RANGE: c_int = 6;
/// `ElementList` (PointSetType_t).
pub const ELEMENT_LIST: c_int = 7;
/// `MIXED` (ElementType_t).
pub const MIXED: c_int = 20;
/// `Structured` (ZoneType_t).
pub const STRUCTURED: c_int = 2;
/// `Unstructured` (ZoneType_t).
pub const UNSTRUCTURED: c_int = 3;

#[link(name = "cgns")]
extern "C" {
    fn cg_open(filename: *const c_char, mode: c_int, fn_: *mut c_int) -> c_int;
    fn cg_close(fn_: c_int) -> c_int;
    fn cg_set_file_type(file_type: c_int) -> c_int;
    fn cg_get_error() -> *const c_char;
    fn cg_nbases(fn_: c_int, n: *mut c_int) -> c_int;
    fn cg_base_read(
        fn_: c_int,
        b: c_int,
        name: *mut c_char,
        cd: *mut c_int,
        pd: *mut c_int,
    ) -> c_int;
    fn cg_base_write(fn_: c_int, name: *const c_char, cd: c_int, pd: c_int, b: *mut c_int)
        -> c_int;
    fn cg_nzones(fn_: c_int, b: c_int, n: *mut c_int) -> c_int;
    fn cg_zone_read(fn_: c_int, b: c_int, z: c_int, name: *mut c_char, size: *mut CgSize) -> c_int;
    fn cg_zone_type(fn_: c_int, b: c_int, z: c_int, t: *mut c_int) -> c_int;
    fn cg_index_dim(fn_: c_int, b: c_int, z: c_int, d: *mut c_int) -> c_int;
    fn cg_zone_write(
        fn_: c_int,
        b: c_int,
        name: *const c_char,
        size: *const CgSize,
        t: c_int,
        z: *mut c_int,
    ) -> c_int;
    fn cg_coord_read(
        fn_: c_int,
        b: c_int,
        z: c_int,
        name: *const c_char,
        t: c_int,
        rmin: *const CgSize,
        rmax: *const CgSize,
        data: *mut c_void,
    ) -> c_int;
    fn cg_coord_write(
        fn_: c_int,
        b: c_int,
        z: c_int,
        t: c_int,
        name: *const c_char,
        data: *const c_void,
        c: *mut c_int,
    ) -> c_int;
    fn cg_nsections(fn_: c_int, b: c_int, z: c_int, n: *mut c_int) -> c_int;
    fn cg_section_read(
        fn_: c_int,
        b: c_int,
        z: c_int,
        s: c_int,
        name: *mut c_char,
        t: *mut c_int,
        start: *mut CgSize,
        end: *mut CgSize,
        nbndry: *mut c_int,
        parent_flag: *mut c_int,
    ) -> c_int;
    fn cg_ElementDataSize(fn_: c_int, b: c_int, z: c_int, s: c_int, n: *mut CgSize) -> c_int;
    fn cg_elements_read(
        fn_: c_int,
        b: c_int,
        z: c_int,
        s: c_int,
        elements: *mut CgSize,
        parent: *mut CgSize,
    ) -> c_int;
    fn cg_poly_elements_read(
        fn_: c_int,
        b: c_int,
        z: c_int,
        s: c_int,
        elements: *mut CgSize,
        offsets: *mut CgSize,
        parent: *mut CgSize,
    ) -> c_int;
    fn cg_npe(t: c_int, npe: *mut c_int) -> c_int;
    fn cg_poly_section_write(
        fn_: c_int,
        b: c_int,
        z: c_int,
        name: *const c_char,
        t: c_int,
        start: CgSize,
        end: CgSize,
        nbndry: c_int,
        elements: *const CgSize,
        offsets: *const CgSize,
        s: *mut c_int,
    ) -> c_int;
    fn cg_section_write(
        fn_: c_int,
        b: c_int,
        z: c_int,
        name: *const c_char,
        t: c_int,
        start: CgSize,
        end: CgSize,
        nbndry: c_int,
        elements: *const CgSize,
        s: *mut c_int,
    ) -> c_int;
    fn cg_nbocos(fn_: c_int, b: c_int, z: c_int, n: *mut c_int) -> c_int;
    fn cg_boco_info(
        fn_: c_int,
        b: c_int,
        z: c_int,
        bc: c_int,
        name: *mut c_char,
        bctype: *mut c_int,
        ptset: *mut c_int,
        npnts: *mut CgSize,
        normal_index: *mut c_int,
        normal_list_size: *mut CgSize,
        normal_type: *mut c_int,
        ndataset: *mut c_int,
    ) -> c_int;
    fn cg_boco_read(
        fn_: c_int,
        b: c_int,
        z: c_int,
        bc: c_int,
        pnts: *mut CgSize,
        normals: *mut c_void,
    ) -> c_int;
    fn cg_boco_gridlocation_read(
        fn_: c_int,
        b: c_int,
        z: c_int,
        bc: c_int,
        loc: *mut c_int,
    ) -> c_int;
    fn cg_boco_write(
        fn_: c_int,
        b: c_int,
        z: c_int,
        name: *const c_char,
        bctype: c_int,
        ptset: c_int,
        npnts: CgSize,
        pnts: *const CgSize,
        bc: *mut c_int,
    ) -> c_int;
    fn cg_boco_gridlocation_write(fn_: c_int, b: c_int, z: c_int, bc: c_int, loc: c_int) -> c_int;
}

/// The offsets of a `MIXED` connectivity (type code, then that type's nodes, per element):
/// one per element of `range`, plus the end, which must be the connectivity's length.
fn mixed_offsets(conn: &[CgSize], range: (CgSize, CgSize)) -> Result<Vec<CgSize>, Error> {
    let bad = |m: &str| Error {
        call: "cg_poly_section_write",
        message: m.to_string(),
    };
    let n = usize::try_from(range.1 - range.0 + 1).map_err(|_| bad("empty range"))?;
    let mut offsets: Vec<CgSize> = Vec::with_capacity(n + 1);
    let mut at = 0usize;
    for _ in 0..n {
        offsets.push(CgSize::try_from(at).map_err(|_| bad("too long"))?);
        let t = *conn.get(at).ok_or_else(|| bad("connectivity ends early"))?;
        let mut npe: c_int = 0;
        // SAFETY: plain integer argument and a valid out pointer.
        check(unsafe { cg_npe(t as c_int, &mut npe) }, "cg_npe")?;
        at += 1 + usize::try_from(npe).map_err(|_| bad("element type without fixed size"))?;
    }
    if at != conn.len() {
        return Err(bad("connectivity length does not match its elements"));
    }
    offsets.push(CgSize::try_from(at).map_err(|_| bad("too long"))?);
    Ok(offsets)
}

/// The library's message for the last failed call.
fn last_error(call: &'static str) -> Error {
    // SAFETY: cg_get_error returns a pointer to a static, NUL-terminated buffer (or NULL).
    let msg = unsafe {
        let p = cg_get_error();
        if p.is_null() {
            String::new()
        } else {
            CStr::from_ptr(p).to_string_lossy().into_owned()
        }
    };
    Error { call, message: msg }
}

fn check(status: c_int, call: &'static str) -> Result<(), Error> {
    if status == 0 {
        Ok(())
    } else {
        Err(last_error(call))
    }
}

/// A name buffer: CGNS names are at most 32 characters plus the NUL.
type NameBuf = [c_char; 64];

fn name_of(buf: &NameBuf) -> String {
    let bytes: Vec<u8> = buf
        .iter()
        .take_while(|&&c| c != 0)
        .map(|&c| c as u8)
        .collect();
    String::from_utf8_lossy(&bytes).into_owned()
}

fn c_string(s: &str, call: &'static str) -> Result<CString, Error> {
    CString::new(s).map_err(|_| Error {
        call,
        message: format!("name {s:?} contains a NUL byte"),
    })
}

/// An open CGNS file; closed on drop.
pub struct File(c_int);

impl File {
    /// Opens `path` for reading (`MODE_READ`), changing (`MODE_MODIFY`), or creates it as HDF5
    /// (`MODE_WRITE`).
    pub fn open(path: &str, mode: c_int) -> Result<File, Error> {
        let c = c_string(path, "cg_open")?;
        let mut f: c_int = 0;
        if mode == MODE_WRITE {
            // SAFETY: plain integer argument.
            check(unsafe { cg_set_file_type(FILE_HDF5) }, "cg_set_file_type")?;
        }
        // SAFETY: `c` is NUL-terminated and outlives the call; `f` is a valid out pointer.
        check(unsafe { cg_open(c.as_ptr(), mode, &mut f) }, "cg_open")?;
        Ok(File(f))
    }

    /// Closes the file, reporting the library's error (a write that fails at close).
    pub fn close(self) -> Result<(), Error> {
        let f = self.0;
        std::mem::forget(self);
        // SAFETY: `f` is an open file number from cg_open, closed once.
        check(unsafe { cg_close(f) }, "cg_close")
    }

    /// Number of bases.
    pub fn nbases(&self) -> Result<c_int, Error> {
        let mut n = 0;
        // SAFETY: valid out pointer.
        check(unsafe { cg_nbases(self.0, &mut n) }, "cg_nbases")?;
        Ok(n)
    }

    /// Base `b`: (name, cell dimension, physical dimension).
    pub fn base(&self, b: c_int) -> Result<(String, c_int, c_int), Error> {
        let mut name: NameBuf = [0; 64];
        let (mut cd, mut pd) = (0, 0);
        check(
            // SAFETY: the name buffer holds 64 > 33 bytes; out pointers are valid.
            unsafe { cg_base_read(self.0, b, name.as_mut_ptr(), &mut cd, &mut pd) },
            "cg_base_read",
        )?;
        Ok((name_of(&name), cd, pd))
    }

    /// Number of zones of base `b`.
    pub fn nzones(&self, b: c_int) -> Result<c_int, Error> {
        let mut n = 0;
        // SAFETY: valid out pointer.
        check(unsafe { cg_nzones(self.0, b, &mut n) }, "cg_nzones")?;
        Ok(n)
    }

    /// Zone `z`: (name, type, index dimension, size array of 3 × index dimension).
    pub fn zone(&self, b: c_int, z: c_int) -> Result<(String, c_int, usize, Vec<CgSize>), Error> {
        let (mut t, mut idim) = (0, 0);
        check(
            // SAFETY: valid out pointers.
            unsafe { cg_zone_type(self.0, b, z, &mut t) },
            "cg_zone_type",
        )?;
        check(
            // SAFETY: valid out pointer.
            unsafe { cg_index_dim(self.0, b, z, &mut idim) },
            "cg_index_dim",
        )?;
        let idim = usize::try_from(idim).unwrap_or(0).min(3);
        let mut size: [CgSize; 9] = [0; 9];
        let mut name: NameBuf = [0; 64];
        check(
            // SAFETY: `size` holds 9 = 3 × the largest index dimension; the name buffer 64 bytes.
            unsafe { cg_zone_read(self.0, b, z, name.as_mut_ptr(), size.as_mut_ptr()) },
            "cg_zone_read",
        )?;
        Ok((name_of(&name), t, idim, size[..3 * idim].to_vec()))
    }

    /// Coordinate array `name` of zone `z` as f64, `n` values over the index range `rmax`.
    pub fn coord(
        &self,
        b: c_int,
        z: c_int,
        name: &str,
        rmax: &[CgSize],
        n: usize,
    ) -> Result<Vec<f64>, Error> {
        let c = c_string(name, "cg_coord_read")?;
        let rmin: Vec<CgSize> = vec![1; rmax.len()];
        let mut out = vec![0.0f64; n];
        check(
            // SAFETY: `out` holds the n = product of `rmax` values the range asks for; the range
            // arrays have the zone's index dimension; `c` is NUL-terminated.
            unsafe {
                cg_coord_read(
                    self.0,
                    b,
                    z,
                    c.as_ptr(),
                    REAL_DOUBLE,
                    rmin.as_ptr(),
                    rmax.as_ptr(),
                    out.as_mut_ptr().cast(),
                )
            },
            "cg_coord_read",
        )?;
        Ok(out)
    }

    /// Number of element sections of zone `z`.
    pub fn nsections(&self, b: c_int, z: c_int) -> Result<c_int, Error> {
        let mut n = 0;
        check(
            // SAFETY: valid out pointer.
            unsafe { cg_nsections(self.0, b, z, &mut n) },
            "cg_nsections",
        )?;
        Ok(n)
    }

    /// Section `s`: (name, element type, start, end, connectivity as stored).
    pub fn section(
        &self,
        b: c_int,
        z: c_int,
        s: c_int,
    ) -> Result<(String, c_int, CgSize, CgSize, Vec<CgSize>), Error> {
        let mut name: NameBuf = [0; 64];
        let (mut t, mut start, mut end, mut nb, mut pf) = (0, 0, 0, 0, 0);
        check(
            // SAFETY: name buffer of 64 bytes; valid out pointers.
            unsafe {
                cg_section_read(
                    self.0,
                    b,
                    z,
                    s,
                    name.as_mut_ptr(),
                    &mut t,
                    &mut start,
                    &mut end,
                    &mut nb,
                    &mut pf,
                )
            },
            "cg_section_read",
        )?;
        let mut len: CgSize = 0;
        check(
            // SAFETY: valid out pointer.
            unsafe { cg_ElementDataSize(self.0, b, z, s, &mut len) },
            "cg_ElementDataSize",
        )?;
        let len = usize::try_from(len).map_err(|_| Error {
            call: "cg_ElementDataSize",
            message: format!("negative size {len}"),
        })?;
        let mut conn: Vec<CgSize> = vec![0; len];
        if t == MIXED {
            // Variable-size elements: the library wants room for the offsets too.
            let n = usize::try_from(end - start + 1).unwrap_or(0);
            let mut offsets: Vec<CgSize> = vec![0; n + 1];
            check(
                // SAFETY: `conn` holds ElementDataSize values and `offsets` one more than the
                // section's element count, as the library requires; no parent data (NULL).
                unsafe {
                    cg_poly_elements_read(
                        self.0,
                        b,
                        z,
                        s,
                        conn.as_mut_ptr(),
                        offsets.as_mut_ptr(),
                        std::ptr::null_mut(),
                    )
                },
                "cg_poly_elements_read",
            )?;
            return Ok((name_of(&name), t, start, end, conn));
        }
        check(
            // SAFETY: `conn` holds ElementDataSize values, as the library requires; parent data
            // is not requested (NULL is allowed).
            unsafe { cg_elements_read(self.0, b, z, s, conn.as_mut_ptr(), std::ptr::null_mut()) },
            "cg_elements_read",
        )?;
        Ok((name_of(&name), t, start, end, conn))
    }

    /// Number of boundary conditions of zone `z`.
    pub fn nbocos(&self, b: c_int, z: c_int) -> Result<c_int, Error> {
        let mut n = 0;
        // SAFETY: valid out pointer.
        check(unsafe { cg_nbocos(self.0, b, z, &mut n) }, "cg_nbocos")?;
        Ok(n)
    }

    /// Boundary condition `bc`: (name, BC type, point set type, grid location, points).
    /// `idim` is the zone's index dimension (each point has `idim` values).
    pub fn boco(
        &self,
        b: c_int,
        z: c_int,
        bc: c_int,
        idim: usize,
    ) -> Result<(String, c_int, c_int, c_int, Vec<CgSize>), Error> {
        let mut name: NameBuf = [0; 64];
        let (mut bctype, mut ptset, mut ni, mut nt, mut nds) = (0, 0, 0, 0, 0);
        let (mut npnts, mut nls): (CgSize, CgSize) = (0, 0);
        check(
            // SAFETY: name buffer of 64 bytes; valid out pointers.
            unsafe {
                cg_boco_info(
                    self.0,
                    b,
                    z,
                    bc,
                    name.as_mut_ptr(),
                    &mut bctype,
                    &mut ptset,
                    &mut npnts,
                    &mut ni,
                    &mut nls,
                    &mut nt,
                    &mut nds,
                )
            },
            "cg_boco_info",
        )?;
        let n = usize::try_from(npnts)
            .unwrap_or(0)
            .saturating_mul(idim.max(1));
        let mut pts: Vec<CgSize> = vec![0; n];
        check(
            // SAFETY: `pts` holds npnts × index dimension values; normals are not requested.
            unsafe { cg_boco_read(self.0, b, z, bc, pts.as_mut_ptr(), std::ptr::null_mut()) },
            "cg_boco_read",
        )?;
        let mut loc = 0;
        check(
            // SAFETY: valid out pointer.
            unsafe { cg_boco_gridlocation_read(self.0, b, z, bc, &mut loc) },
            "cg_boco_gridlocation_read",
        )?;
        Ok((name_of(&name), bctype, ptset, loc, pts))
    }

    /// Writes a base; its index.
    pub fn write_base(&self, name: &str, cell_dim: c_int, phys_dim: c_int) -> Result<c_int, Error> {
        let c = c_string(name, "cg_base_write")?;
        let mut b = 0;
        check(
            // SAFETY: `c` is NUL-terminated; valid out pointer.
            unsafe { cg_base_write(self.0, c.as_ptr(), cell_dim, phys_dim, &mut b) },
            "cg_base_write",
        )?;
        Ok(b)
    }

    /// Writes a zone with its size array (3 × index dimension values); its index.
    pub fn write_zone(
        &self,
        b: c_int,
        name: &str,
        size: &[CgSize],
        t: c_int,
    ) -> Result<c_int, Error> {
        let c = c_string(name, "cg_zone_write")?;
        let mut z = 0;
        check(
            // SAFETY: `size` has 3 × the index dimension the base's cell dimension implies
            // (the caller builds it so); `c` is NUL-terminated.
            unsafe { cg_zone_write(self.0, b, c.as_ptr(), size.as_ptr(), t, &mut z) },
            "cg_zone_write",
        )?;
        Ok(z)
    }

    /// Writes one coordinate array (as many values as the zone has vertices).
    pub fn write_coord(&self, b: c_int, z: c_int, name: &str, data: &[f64]) -> Result<(), Error> {
        let c = c_string(name, "cg_coord_write")?;
        let mut i = 0;
        check(
            // SAFETY: `data` holds the zone's vertex count of f64 values (the caller's zone size).
            unsafe {
                cg_coord_write(
                    self.0,
                    b,
                    z,
                    REAL_DOUBLE,
                    c.as_ptr(),
                    data.as_ptr().cast(),
                    &mut i,
                )
            },
            "cg_coord_write",
        )
    }

    /// Writes an element section (elements `start..=end`, connectivity as CGNS stores it).
    pub fn write_section(
        &self,
        b: c_int,
        z: c_int,
        name: &str,
        t: c_int,
        range: (CgSize, CgSize),
        conn: &[CgSize],
    ) -> Result<(), Error> {
        let c = c_string(name, "cg_section_write")?;
        let mut s = 0;
        if t == MIXED {
            let offsets = mixed_offsets(conn, range)?;
            return check(
                // SAFETY: `offsets` has one entry per element plus one, each within `conn` (checked
                // by mixed_offsets); `c` is NUL-terminated.
                unsafe {
                    cg_poly_section_write(
                        self.0,
                        b,
                        z,
                        c.as_ptr(),
                        t,
                        range.0,
                        range.1,
                        0,
                        conn.as_ptr(),
                        offsets.as_ptr(),
                        &mut s,
                    )
                },
                "cg_poly_section_write",
            );
        }
        check(
            // SAFETY: `conn` holds the connectivity of the `range` elements of type `t` (built by
            // the caller from the same counts); `c` is NUL-terminated.
            unsafe {
                cg_section_write(
                    self.0,
                    b,
                    z,
                    c.as_ptr(),
                    t,
                    range.0,
                    range.1,
                    0,
                    conn.as_ptr(),
                    &mut s,
                )
            },
            "cg_section_write",
        )
    }

    /// Writes a boundary condition over the points (`idim` values each) at grid location `loc`.
    pub fn write_boco(
        &self,
        b: c_int,
        z: c_int,
        name: &str,
        kind: (c_int, c_int, c_int),
        pts: &[CgSize],
        idim: usize,
    ) -> Result<(), Error> {
        let c = c_string(name, "cg_boco_write")?;
        let n = CgSize::try_from(pts.len() / idim.max(1)).map_err(|_| Error {
            call: "cg_boco_write",
            message: "too many points".into(),
        })?;
        let mut bc = 0;
        check(
            // SAFETY: `pts` holds n × idim values; `c` is NUL-terminated.
            unsafe {
                cg_boco_write(
                    self.0,
                    b,
                    z,
                    c.as_ptr(),
                    kind.0,
                    kind.1,
                    n,
                    pts.as_ptr(),
                    &mut bc,
                )
            },
            "cg_boco_write",
        )?;
        // The library writes the location of element ranges and lists itself; Vertex is the
        // default.
        if kind.2 == VERTEX || kind.1 == ELEMENT_RANGE || kind.1 == ELEMENT_LIST {
            return Ok(());
        }
        check(
            // SAFETY: plain integer arguments.
            unsafe { cg_boco_gridlocation_write(self.0, b, z, bc, kind.2) },
            "cg_boco_gridlocation_write",
        )
    }
}

impl Drop for File {
    fn drop(&mut self) {
        // SAFETY: `self.0` is an open file number; close() forgets self, so this runs once.
        unsafe {
            cg_close(self.0);
        }
    }
}
