//! Compressed sparse row (CSR) adjacency: the [`Graph`] view every solver works on.
//!
//! Node `i`'s neighbours are `targets[offsets[i]..offsets[i + 1]]`. Entry positions in
//! `targets` double as *directed-edge* indices, so per-edge data (spring stiffness, weights)
//! lives in a caller slice of the same length as `targets`.

use core::ops::Range;

use crate::error::{Error, Result};

/// A validated CSR adjacency view over caller-owned `offsets` (n + 1 entries) and `targets`.
///
/// Guarantees after construction: `offsets[0] == 0`, offsets never decrease,
/// `offsets[n] == targets.len()`, every target is `< n`, no node lists itself, and
/// `targets.len()` fits in `u32`. Symmetry is checked on demand by [`Graph::check_symmetric`].
#[derive(Clone, Copy, Debug)]
pub struct Graph<'a> {
    offsets: &'a [u32],
    targets: &'a [u32],
}

impl<'a> Graph<'a> {
    /// Validates `offsets` and `targets` and wraps them. Never copies.
    ///
    /// # Errors
    /// Offsets that do not start at 0, decrease or do not end at `targets.len()`
    /// ([`Error::BadOffsets`]); more than `u32::MAX` nodes or edges ([`Error::TooLarge`]); a
    /// target `>= node_count` ([`Error::IndexOutOfRange`]); an edge from a node to itself
    /// ([`Error::SelfLoop`]).
    pub fn new(offsets: &'a [u32], targets: &'a [u32]) -> Result<Self> {
        let Some((&first, _)) = offsets.split_first() else {
            return Err(Error::BadOffsets {
                arg: "offsets",
                position: 0,
            });
        };
        if first != 0 {
            return Err(Error::BadOffsets {
                arg: "offsets",
                position: 0,
            });
        }
        if u32::try_from(targets.len()).is_err() {
            return Err(Error::TooLarge {
                arg: "targets",
                value: targets.len(),
            });
        }
        let n = offsets.len() - 1;
        if u32::try_from(n).is_err() {
            return Err(Error::TooLarge {
                arg: "offsets",
                value: offsets.len(),
            });
        }
        for (i, w) in offsets.windows(2).enumerate() {
            if let [a, b] = *w {
                if b < a || b as usize > targets.len() {
                    return Err(Error::BadOffsets {
                        arg: "offsets",
                        position: i + 1,
                    });
                }
            }
        }
        if offsets.last().map(|&l| l as usize) != Some(targets.len()) {
            return Err(Error::BadOffsets {
                arg: "offsets",
                position: n,
            });
        }
        for (i, w) in offsets.windows(2).enumerate() {
            if let [a, b] = *w {
                let row = targets.get(a as usize..b as usize).unwrap_or(&[]);
                for (k, &t) in row.iter().enumerate() {
                    if t as usize >= n {
                        return Err(Error::IndexOutOfRange {
                            arg: "targets",
                            position: a as usize + k,
                            index: t as usize,
                            bound: n,
                        });
                    }
                    if t as usize == i {
                        return Err(Error::SelfLoop { node: i });
                    }
                }
            }
        }
        Ok(Graph { offsets, targets })
    }

    /// Wraps arrays that [`Graph::new`] accepted before (a prepared plan's copies): no check.
    #[inline]
    pub(crate) fn trusted(offsets: &'a [u32], targets: &'a [u32]) -> Self {
        Graph { offsets, targets }
    }

    /// Number of nodes `n`.
    #[inline]
    pub fn node_count(&self) -> usize {
        self.offsets.len().saturating_sub(1)
    }

    /// Number of directed edges (entries in `targets`); twice the undirected count when
    /// symmetric.
    #[inline]
    pub fn edge_count(&self) -> usize {
        self.targets.len()
    }

    /// The offsets array (n + 1 entries).
    #[inline]
    pub fn offsets(&self) -> &'a [u32] {
        self.offsets
    }

    /// The targets array (one entry per directed edge).
    #[inline]
    pub fn targets(&self) -> &'a [u32] {
        self.targets
    }

    /// Directed-edge indices of node `i`'s row (empty when `i` is out of range).
    #[inline]
    pub fn edge_range(&self, i: usize) -> Range<usize> {
        match (self.offsets.get(i), self.offsets.get(i + 1)) {
            (Some(&a), Some(&b)) => a as usize..b as usize,
            _ => 0..0,
        }
    }

    /// Neighbours of node `i` (empty when `i` is out of range).
    #[inline]
    pub fn neighbors(&self, i: usize) -> &'a [u32] {
        self.targets.get(self.edge_range(i)).unwrap_or(&[])
    }

    /// Iterates over the rows: `(node, first directed-edge index, neighbours)`.
    #[inline]
    pub fn rows(&self) -> impl Iterator<Item = (usize, usize, &'a [u32])> + 'a {
        let targets = self.targets;
        self.offsets
            .windows(2)
            .enumerate()
            .map(move |(i, w)| match *w {
                [a, b] => (
                    i,
                    a as usize,
                    targets.get(a as usize..b as usize).unwrap_or(&[]),
                ),
                _ => (i, 0, &[][..]),
            })
    }

    /// Directed-edge index of `from → to`, if that edge exists.
    #[inline]
    pub fn find_edge(&self, from: usize, to: usize) -> Option<usize> {
        let r = self.edge_range(from);
        let start = r.start;
        self.targets
            .get(r)
            .and_then(|row| row.iter().position(|&t| t as usize == to))
            .map(|k| start + k)
    }

    /// Checks that every edge `i → j` has its reverse `j → i`.
    ///
    /// # Errors
    /// The first edge `i → j` without its reverse ([`Error::NotSymmetric`]).
    pub fn check_symmetric(&self) -> Result<()> {
        for (i, _, row) in self.rows() {
            for &j in row {
                if self.find_edge(j as usize, i).is_none() {
                    return Err(Error::NotSymmetric {
                        from: i,
                        to: j as usize,
                    });
                }
            }
        }
        Ok(())
    }
}
