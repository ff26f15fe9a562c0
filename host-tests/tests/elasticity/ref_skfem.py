"""Independent reference for the elasticity tests: scikit-fem assembles the stiffness of
isotropic linear elasticity (plane strain in 2D) with element-wise Young's modulus and
Poisson ratio, and solves the Dirichlet problem by a sparse direct solve.

Input (argv[1]): a text file
    D n cells nu
    n lines of coordinates
    `cells` lines: VTK code, Young's modulus, node indices (VTK order)
    n lines: fixed flag, prescribed displacement (D values)
Output (stdout): the dense stiffness, `n*D` lines of `n*D` values (dof = node*D + component),
then `n` lines of the solution.
"""
import sys

import meshio
import numpy as np
from scipy.sparse.linalg import spsolve
from skfem import Basis, BilinearForm, ElementVector, asm, condense
from skfem.element import ElementHex1, ElementQuad1, ElementTetP1, ElementTriP1
from skfem.helpers import ddot, sym_grad, trace
from skfem.io.meshio import from_meshio

ELEMENTS = {5: ("triangle", ElementTriP1), 9: ("quad", ElementQuad1),
            10: ("tetra", ElementTetP1), 12: ("hexahedron", ElementHex1)}


@BilinearForm
def elasticity(u, v, w):
    eu, ev = sym_grad(u), sym_grad(v)
    return w.lam * trace(eu) * trace(ev) + 2.0 * w.mu * ddot(eu, ev)


def main():
    lines = open(sys.argv[1]).read().split("\n")
    d, n, ncells, nu = lines[0].split()
    d, n, ncells, nu = int(d), int(n), int(ncells), float(nu)
    pts = np.array([[float(x) for x in lines[1 + i].split()] for i in range(n)])
    rows = [lines[1 + n + c].split() for c in range(ncells)]
    codes = {int(r[0]) for r in rows}
    assert len(codes) == 1, "one element kind per mesh"
    name, element = ELEMENTS[codes.pop()]
    young = np.array([float(r[1]) for r in rows])
    cells = np.array([[int(x) for x in r[2:]] for r in rows])
    bc = np.array([[float(x) for x in lines[1 + n + ncells + i].split()] for i in range(n)])
    mesh = from_meshio(meshio.Mesh(pts, [(name, cells)]))
    assert np.array_equal(mesh.p.T, pts), "scikit-fem kept the node order"
    # 2x2 (2x2x2) Gauss points for the Q1 elements, as the kernel (and SU2) integrate.
    basis = Basis(mesh, ElementVector(element()), intorder=3)
    # scikit-fem may reorder its elements: map moduli through the element centroids.
    ours = {tuple(np.round(pts[c].mean(axis=0), 12)): e for c, e in zip(cells, young)}
    e_sk = np.array([ours[tuple(np.round(mesh.p[:, t].mean(axis=1), 12))] for t in mesh.t.T])
    lam = e_sk * nu / ((1 + nu) * (1 - 2 * nu))
    mu = e_sk / (2 * (1 + nu))
    nqp = basis.X.shape[1]
    k = asm(elasticity, basis, lam=np.repeat(lam[:, None], nqp, 1),
            mu=np.repeat(mu[:, None], nqp, 1))
    dofs = basis.nodal_dofs  # dofs[c, i]: component c of node i
    order = dofs.T.reshape(-1)  # node-major
    dense = k.toarray()[np.ix_(order, order)]
    x = np.zeros(n * d)
    fixed = np.nonzero(bc[:, 0] != 0)[0]
    for c in range(d):
        x[dofs[c, fixed]] = bc[fixed, 1 + c]
    dfix = dofs[:, fixed].reshape(-1)
    u = solve_dirichlet(k, x, dfix)
    out = [" ".join(repr(float(v)) for v in row) for row in dense]
    out += [" ".join(repr(float(u[dofs[c, i]])) for c in range(d)) for i in range(n)]
    print("\n".join(out))


def solve_dirichlet(k, x, dfix):
    a, b, xi, interior = condense(k, np.zeros(k.shape[0]), x=x, D=dfix)
    x = x.copy()
    x[interior] = spsolve(a.tocsc(), b)
    return x


if __name__ == "__main__":
    main()
