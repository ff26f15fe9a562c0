//! The output without a gather: every process formats its element lines (those it read) and
//! its owned point lines with the serial writer's functions, learns where they go from
//! prefix sums of the lengths, and writes them into their place of one staged file
//! (`pwrite`); the first process writes the header, the `NPOIN=` line and the markers, and
//! renames the file into place once every process has written its part.

use std::fs::{File, OpenOptions};
use std::os::unix::fs::FileExt;
use std::path::{Path, PathBuf};

use super::comm::{Failed, World};
use crate::error::CliError;
use crate::formats::su2::{
    su2_newline, write_su2_element, write_su2_head, write_su2_point, write_su2_points_head,
    write_su2_tail, Su2Mesh,
};
use crate::formats::CellList;

/// What this process writes.
pub(super) struct Rows<'a> {
    /// The mesh without elements and points (header, markers, comments).
    pub skeleton: &'a Su2Mesh,
    pub nelem: u64,
    pub npoin: u64,
    /// The elements this process read, from global index `first_element`.
    pub elements: &'a CellList,
    pub first_element: u64,
    /// The deformed points this process owns, from global id `first_point`.
    pub points: &'a [[f64; 3]],
    pub first_point: u64,
}

/// The staging file next to `out` (one name for every process).
fn staged(out: &Path) -> PathBuf {
    let name = out
        .file_name()
        .map_or_else(|| "out".into(), |n| n.to_string_lossy().into_owned());
    out.with_file_name(format!(".{name}.deform-distributed-tmp"))
}

/// The four pieces this process formats: header (first process), elements, `NPOIN=`
/// line, points, tail (first process).
fn pieces(rows: &Rows<'_>) -> std::io::Result<[Vec<u8>; 5]> {
    let mesh = rows.skeleton;
    let nl = su2_newline(mesh);
    let (mut head, mut mid, mut tail) = (Vec::new(), Vec::new(), Vec::new());
    write_su2_head(mesh, rows.nelem as usize, &mut head)?;
    write_su2_points_head(mesh, rows.npoin as usize, &mut mid)?;
    write_su2_tail(mesh, &mut tail)?;
    let mut elements = Vec::new();
    for (c, (code, nodes)) in rows.elements.iter().enumerate() {
        let index = (rows.first_element as usize) + c;
        write_su2_element(&mut elements, code, nodes, index, nl)?;
    }
    let mut points = Vec::new();
    for (i, p) in rows.points.iter().enumerate() {
        write_su2_point(&mut points, p, mesh.dim, rows.first_point as usize + i, nl)?;
    }
    Ok([head, elements, mid, points, tail])
}

/// Writes the output (see the module's documentation); nothing is left at `out` or beside
/// it unless every process wrote its part.
pub(super) fn write(world: &World<'_>, out: &Path, rows: &Rows<'_>) -> Result<(), Failed> {
    let io = |source| CliError::Io {
        path: out.to_path_buf(),
        source,
    };
    let [head, elements, mid, points, tail] = world.agree(pieces(rows).map_err(io))?;
    let lens = [elements.len() as u64, points.len() as u64];
    let totals = world.sum(&lens);
    let before = [world.before(lens[0]), world.before(lens[1])];
    let h = head.len() as u64;
    let at_points = h + totals[0] + mid.len() as u64;
    let tmp = staged(out);
    let root = world.rank == 0;
    let created = if root {
        crate::guard::register_temp(&tmp);
        File::create(&tmp)
            .and_then(|f| f.set_len(at_points + totals[1] + tail.len() as u64))
            .map_err(io)
    } else {
        Ok(())
    };
    if root && created.is_err() {
        let _ = std::fs::remove_file(&tmp);
        crate::guard::forget_temp(&tmp);
    }
    world.agree(created)?;
    let mut writes: Vec<(u64, &[u8])> = vec![(h + before[0], &elements)];
    writes.push((at_points + before[1], &points));
    if root {
        writes.extend([(0, &head[..]), (h + totals[0], &mid[..])]);
        writes.push((at_points + totals[1], &tail));
    }
    let wrote = OpenOptions::new().write(true).open(&tmp).and_then(|f| {
        for (at, bytes) in writes {
            f.write_all_at(bytes, at)?;
        }
        f.sync_data()
    });
    let done = world.agree(wrote.map_err(io));
    if root && done.is_err() {
        let _ = std::fs::remove_file(&tmp);
        crate::guard::forget_temp(&tmp);
    }
    done?;
    let renamed = if root {
        let r = std::fs::rename(&tmp, out).map_err(io);
        if r.is_err() {
            let _ = std::fs::remove_file(&tmp);
        }
        crate::guard::forget_temp(&tmp);
        r
    } else {
        Ok(())
    };
    world.agree(renamed)
}
