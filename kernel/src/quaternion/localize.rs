//! Renumbering boundary elements from mesh numbering to boundary-local numbering.

use crate::check;
use crate::error::{Error, Result};

/// Length of the `u32` scratch [`localize_nodes`] needs: one entry per mesh node.
#[inline]
pub fn localize_nodes_scratch_len(node_count: usize) -> usize {
    node_count
}

/// Rewrites mesh node numbers as positions in `boundary`: `local[e] = k` where
/// `boundary[k] == global[e]`. Boundary elements usually come in mesh numbering (a marker's
/// faces); the boundary-level routines ([`boundary_rotations`](super::boundary_rotations),
/// [`BoundaryMotion::elements`](super::BoundaryMotion)) want them numbered `0..B`. Pass the
/// element node array of a marker as `global` and build the [`Cells`](crate::Cells) view over
/// `local` with the same offsets and kinds.
///
/// `scratch` needs [`localize_nodes_scratch_len`] entries (contents unspecified afterwards).
///
/// # Errors
/// `boundary` or `global` entries `>= node_count`, a node listed twice in `boundary`
/// ([`Error::DuplicateNode`]), an element node not in `boundary`
/// ([`Error::IndexOutOfRange`] on `"global"`, `bound` = the boundary length), `local` of the
/// wrong length. On error `local` is unchanged.
pub fn localize_nodes(
    node_count: usize,
    boundary: &[u32],
    global: &[u32],
    scratch: &mut [u32],
    local: &mut [u32],
) -> Result<()> {
    check::len("local", local.len(), global.len())?;
    check::buffer(
        "scratch",
        scratch.len(),
        localize_nodes_scratch_len(node_count),
    )?;
    if u32::try_from(boundary.len()).is_err() {
        return Err(Error::TooLarge {
            arg: "boundary",
            value: boundary.len(),
        });
    }
    check::indices("boundary", boundary, node_count)?;
    check::indices("global", global, node_count)?;
    let map = scratch.get_mut(..node_count).unwrap_or(&mut []);
    for m in map.iter_mut() {
        *m = u32::MAX;
    }
    for (k, &node) in boundary.iter().enumerate() {
        if let Some(m) = map.get_mut(node as usize) {
            if *m != u32::MAX {
                return Err(Error::DuplicateNode {
                    arg: "boundary",
                    position: k,
                    node: node as usize,
                });
            }
            *m = k as u32;
        }
    }
    for (position, &node) in global.iter().enumerate() {
        if map.get(node as usize).is_none_or(|&m| m == u32::MAX) {
            return Err(Error::IndexOutOfRange {
                arg: "global",
                position,
                index: node as usize,
                bound: boundary.len(),
            });
        }
    }
    for (l, &node) in local.iter_mut().zip(global) {
        *l = map.get(node as usize).copied().unwrap_or(0);
    }
    Ok(())
}
