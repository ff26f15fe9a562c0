"""Independent reference for the rigid-mode multigrid of the elasticity solve: pyamg's
smoothed aggregation with the rigid-body modes as near-null space, on the same matrix.

Input (argv[1]): a text file
    D n_free nnz
    n_free lines of coordinates (the free nodes, in order)
    nnz lines: row col value (dofs node-major over the free nodes: node*D + component)
    n_free*D lines: right-hand side
Output (stdout): the CG iterations pyamg needs to reduce the residual by 1e-10 (from x = 0),
then the solution, one value per line.
"""
import sys

import numpy as np
import pyamg
import scipy.sparse as sp


def rigid_modes(x):
    n, d = x.shape
    x = x - 0.5 * (x.min(axis=0) + x.max(axis=0))
    if d == 2:
        b = np.zeros((2 * n, 3))
        b[0::2, 0] = 1
        b[1::2, 1] = 1
        b[0::2, 2] = -x[:, 1]
        b[1::2, 2] = x[:, 0]
        return b
    b = np.zeros((3 * n, 6))
    for c in range(3):
        b[c::3, c] = 1
    b[1::3, 3], b[2::3, 3] = -x[:, 2], x[:, 1]
    b[0::3, 4], b[2::3, 4] = x[:, 2], -x[:, 0]
    b[0::3, 5], b[1::3, 5] = -x[:, 1], x[:, 0]
    return b


def main():
    lines = open(sys.argv[1]).read().split("\n")
    d, n, nnz = (int(v) for v in lines[0].split())
    x = np.array([[float(v) for v in lines[1 + i].split()] for i in range(n)])
    trip = np.array([[float(v) for v in lines[1 + n + k].split()] for k in range(nnz)])
    a = sp.csr_matrix((trip[:, 2], (trip[:, 0].astype(int), trip[:, 1].astype(int))),
                      shape=(n * d, n * d))
    b = np.array([float(lines[1 + n + nnz + k]) for k in range(n * d)])
    ml = pyamg.smoothed_aggregation_solver(sp.bsr_matrix(a, blocksize=(d, d)),
                                           B=rigid_modes(x))
    res = []
    u = ml.solve(b, x0=np.zeros_like(b), tol=1e-10, accel="cg", maxiter=2000, residuals=res)
    print(len(res) - 1)
    print("\n".join(repr(float(v)) for v in u))


if __name__ == "__main__":
    main()
