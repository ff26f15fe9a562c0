//! Reverse Cuthill–McKee on a [`Graph`]: breadth-first levels from a pseudo-peripheral node
//! (George and Liu's search), neighbours in increasing degree, ties by index, one connected
//! component after another, the whole order reversed at the end.
//!
//! The breadth-first queue is `order` itself and the visited marks live in `inverse`, so the
//! routine needs no buffer besides the two it returns.

use super::sort::{heap_sort, ByKey};
use crate::graph::Graph;

/// `inverse` entry of a node not yet placed.
pub(super) const UNSEEN: u32 = u32::MAX;
/// `inverse` entry of a node reached by a trial search (reset to [`UNSEEN`] after it).
const TRIAL: u32 = u32::MAX - 1;

/// Writes the reverse Cuthill–McKee order (`order[new] = old`, `inverse[old] = new`); the
/// caller has checked both have `g.node_count()` entries and that the count is below
/// [`TRIAL`].
pub(super) fn rcm(g: &Graph<'_>, order: &mut [u32], inverse: &mut [u32]) {
    let n = g.node_count();
    inverse.fill(UNSEEN);
    let mut placed = 0usize;
    for s in 0..n {
        if inverse.get(s) != Some(&UNSEEN) {
            continue;
        }
        let Some(free) = order.get_mut(placed..) else {
            break;
        };
        let root = pseudo_peripheral(g, s as u32, free, inverse);
        placed = cuthill_mckee(g, root, placed, order, inverse);
    }
    order.reverse();
    for (k, &v) in order.iter().enumerate() {
        if let Some(slot) = inverse.get_mut(v as usize) {
            *slot = k as u32;
        }
    }
}

/// Degree of a node (its row length).
#[inline]
fn degree(g: &Graph<'_>, v: u32) -> usize {
    g.neighbors(v as usize).len()
}

/// Breadth-first search from `root` over the nodes still [`UNSEEN`], into `queue`, marking
/// them [`TRIAL`]. Returns (depth of the last level, start of the last level, nodes reached).
fn levels(g: &Graph<'_>, root: u32, queue: &mut [u32], marks: &mut [u32]) -> (usize, usize, usize) {
    let (Some(q0), Some(m0)) = (queue.first_mut(), marks.get_mut(root as usize)) else {
        return (0, 0, 0);
    };
    *q0 = root;
    *m0 = TRIAL;
    let (mut head, mut tail, mut level_end) = (0usize, 1usize, 1usize);
    let (mut depth, mut last) = (0usize, 0usize);
    while head < tail {
        if head == level_end {
            depth += 1;
            last = head;
            level_end = tail;
        }
        let Some(&u) = queue.get(head) else { break };
        head += 1;
        for &v in g.neighbors(u as usize) {
            if let Some(m) = marks.get_mut(v as usize) {
                if *m == UNSEEN {
                    if let Some(slot) = queue.get_mut(tail) {
                        *m = TRIAL;
                        *slot = v;
                        tail += 1;
                    }
                }
            }
        }
    }
    (depth, last, tail)
}

/// Resets the marks of the nodes a trial search reached.
fn clear(queue: &[u32], marks: &mut [u32]) {
    for &v in queue {
        if let Some(m) = marks.get_mut(v as usize) {
            *m = UNSEEN;
        }
    }
}

/// George and Liu's pseudo-peripheral node of `start`'s component: from the last level of a
/// search, the node of least degree (ties: lowest index) starts the next search, as long as
/// the depth grows. Leaves `marks` as it found them.
fn pseudo_peripheral(g: &Graph<'_>, start: u32, queue: &mut [u32], marks: &mut [u32]) -> u32 {
    let mut root = start;
    let (mut depth, mut last, mut count) = levels(g, root, queue, marks);
    loop {
        let candidate = queue
            .get(last..count)
            .unwrap_or(&[])
            .iter()
            .copied()
            .min_by_key(|&v| (degree(g, v), v));
        clear(queue.get(..count).unwrap_or(&[]), marks);
        let Some(c) = candidate.filter(|&c| c != root) else {
            return root;
        };
        let (d, l, k) = levels(g, c, queue, marks);
        if d <= depth {
            clear(queue.get(..k).unwrap_or(&[]), marks);
            return root;
        }
        (root, depth, last, count) = (c, d, l, k);
    }
}

/// Cuthill–McKee from `root`, appending its component to `order` from position `placed`
/// (each node's new neighbours in increasing degree, ties by index). Returns the new count.
fn cuthill_mckee(
    g: &Graph<'_>,
    root: u32,
    placed: usize,
    order: &mut [u32],
    inverse: &mut [u32],
) -> usize {
    let (Some(o), Some(m)) = (order.get_mut(placed), inverse.get_mut(root as usize)) else {
        return placed;
    };
    *o = root;
    *m = placed as u32;
    let (mut head, mut tail) = (placed, placed + 1);
    while head < tail {
        let Some(&u) = order.get(head) else { break };
        head += 1;
        let first = tail;
        for &v in g.neighbors(u as usize) {
            if let Some(m) = inverse.get_mut(v as usize) {
                if *m == UNSEEN {
                    if let Some(slot) = order.get_mut(tail) {
                        *m = tail as u32;
                        *slot = v;
                        tail += 1;
                    }
                }
            }
        }
        if let Some(new) = order.get_mut(first..tail) {
            heap_sort(&mut ByKey {
                items: new,
                key: |v| (degree(g, v), v),
            });
        }
    }
    tail
}
