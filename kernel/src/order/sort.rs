//! In-place heapsort for the orderings: no recursion, no allocation, no panic, `O(n log n)`
//! whatever the input (a star graph's hub row sorts as fast as a mesh row).

/// A sequence that can compare and swap two of its positions.
pub(crate) trait Sortable {
    /// Number of items.
    fn len(&self) -> usize;
    /// Whether item `a` sorts before item `b`.
    fn less(&self, a: usize, b: usize) -> bool;
    /// Swaps items `a` and `b`.
    fn swap(&mut self, a: usize, b: usize);
}

/// Sorts `s` ascending (heapsort: the same comparisons on every platform).
pub(crate) fn heap_sort<S: Sortable>(s: &mut S) {
    let n = s.len();
    for start in (0..n / 2).rev() {
        sift_down(s, start, n);
    }
    for end in (1..n).rev() {
        s.swap(0, end);
        sift_down(s, 0, end);
    }
}

/// Restores the max-heap below `root` within `0..end`.
fn sift_down<S: Sortable>(s: &mut S, mut root: usize, end: usize) {
    loop {
        let mut child = 2 * root + 1;
        if child >= end {
            return;
        }
        if child + 1 < end && s.less(child, child + 1) {
            child += 1;
        }
        if s.less(root, child) {
            s.swap(root, child);
            root = child;
        } else {
            return;
        }
    }
}

/// Swaps two entries of a slice (nothing when either is out of range).
#[inline]
pub(crate) fn swap_at<X: Copy>(v: &mut [X], a: usize, b: usize) {
    if let (Some(&x), Some(&y)) = (v.get(a), v.get(b)) {
        if let Some(p) = v.get_mut(a) {
            *p = y;
        }
        if let Some(p) = v.get_mut(b) {
            *p = x;
        }
    }
}

/// Node indices sorted by a key of each node (ties must be broken inside the key).
pub(crate) struct ByKey<'s, K: Ord, F: Fn(u32) -> K> {
    /// The node indices.
    pub(crate) items: &'s mut [u32],
    /// The key of a node.
    pub(crate) key: F,
}

impl<K: Ord, F: Fn(u32) -> K> Sortable for ByKey<'_, K, F> {
    fn len(&self) -> usize {
        self.items.len()
    }
    fn less(&self, a: usize, b: usize) -> bool {
        match (self.items.get(a), self.items.get(b)) {
            (Some(&x), Some(&y)) => (self.key)(x) < (self.key)(y),
            _ => false,
        }
    }
    fn swap(&mut self, a: usize, b: usize) {
        swap_at(self.items, a, b);
    }
}

/// A graph row's targets sorted ascending, each carrying its directed-edge index along.
pub(crate) struct RowWithEdges<'s> {
    /// The row's targets (the sort key; distinct within a row).
    pub(crate) targets: &'s mut [u32],
    /// The directed-edge index of each target (moved with it).
    pub(crate) edges: &'s mut [u32],
}

impl Sortable for RowWithEdges<'_> {
    fn len(&self) -> usize {
        self.targets.len()
    }
    fn less(&self, a: usize, b: usize) -> bool {
        match (self.targets.get(a), self.targets.get(b)) {
            (Some(x), Some(y)) => (x, self.edges.get(a)) < (y, self.edges.get(b)),
            _ => false,
        }
    }
    fn swap(&mut self, a: usize, b: usize) {
        swap_at(self.targets, a, b);
        swap_at(self.edges, a, b);
    }
}
