"""Independent reference for the kernel's reverse Cuthill-McKee (host-tests/tests/order/rcm.rs).

  ref_rcm.py edges MESH      print "n" then one undirected edge "a b" a line: every pair of
                             nodes that share a cell of MESH (read by meshio), 0-based
  ref_rcm.py measure GRAPH ORDER
                             GRAPH: the file `edges` prints; ORDER: one old index a line in
                             new order (order[new] = old). Prints the bandwidths (largest
                             |new(i) - new(j)| over the edges) of the original numbering, of
                             ORDER and of scipy.sparse.csgraph.reverse_cuthill_mckee, and the
                             profiles (sum over rows of i - min neighbour) of the same three.
"""
import sys

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import reverse_cuthill_mckee


def edges(path):
    import meshio

    mesh = meshio.read(path)
    pairs = set()
    for block in mesh.cells:
        for cell in block.data:
            cell = [int(v) for v in cell]
            for a in range(len(cell)):
                for b in range(a + 1, len(cell)):
                    x, y = cell[a], cell[b]
                    if x != y:
                        pairs.add((min(x, y), max(x, y)))
    print(len(mesh.points))
    for a, b in sorted(pairs):
        print(a, b)


def read_graph(path):
    with open(path) as f:
        n = int(f.readline())
        e = np.loadtxt(f, dtype=np.int64, ndmin=2).reshape(-1, 2)
    return n, e


def band_profile(e, new):
    a, b = new[e[:, 0]], new[e[:, 1]]
    band = int(np.max(np.abs(a - b))) if len(e) else 0
    lo = np.arange(len(new))
    np.minimum.at(lo, np.concatenate([a, b]), np.concatenate([b, a]))
    return band, int(np.sum(np.arange(len(new)) - lo))


def measure(graph, order_path):
    n, e = read_graph(graph)
    order = np.loadtxt(order_path, dtype=np.int64, ndmin=1)
    assert sorted(order.tolist()) == list(range(n)), "ORDER is not a permutation"
    m = sp.coo_matrix((np.ones(2 * len(e)), (np.r_[e[:, 0], e[:, 1]], np.r_[e[:, 1], e[:, 0]])),
                      shape=(n, n)).tocsr()
    ref = reverse_cuthill_mckee(m, symmetric_mode=True)
    for perm in (np.arange(n), order, ref):
        new = np.empty(n, dtype=np.int64)
        new[perm] = np.arange(n)
        print(*band_profile(e, new))


if __name__ == "__main__":
    if sys.argv[1] == "edges":
        edges(sys.argv[2])
    else:
        measure(sys.argv[2], sys.argv[3])
