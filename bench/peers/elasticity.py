"""The peer of the kernel's elasticity rows in `cargo xtask bench` (issue 28 item 4).

Reads the meshes, boundary data and kernel solutions that `bench/src/elasticity.rs` wrote to
DIR (elastic2d_*: P1 triangles, elastic3d_*: Q1 hexahedra), assembles the same linear
elasticity with scikit-fem (plane strain in 2D; E = mean cell measure / cell measure, SU2's
inverse-volume stiffness, nu = 0.3; hexahedra with 2x2x2 Gauss points as the kernel), and
solves K_ff u_f = -K_fb u_b with pyamg's smoothed_aggregation_solver(A, B=rigid_modes) (A as
BSR with dim x dim blocks, so the aggregates are nodes) and CG to a relative residual of 1e-8.

Writes DIR/peers_elasticity.txt (`name value` lines): assembly, setup and solve seconds,
iterations, levels, and the largest difference to the kernel's solution relative to the
largest displacement.

    python elasticity.py DIR
"""

import sys
import time
from pathlib import Path

import numpy as np
import pyamg
import scipy.sparse as sp
from skfem import (Basis, BilinearForm, ElementHex0, ElementHex1, ElementTriP0, ElementTriP1,
                   ElementVector, MeshHex, MeshTri)
from skfem.helpers import ddot, sym_grad, trace
from skfem.quadrature import get_quadrature

NU = 0.3
TOL = 1e-8


def read(d, tag):
    n, dim, per = (int(x) for x in (d / f"{tag}_dims").read_text().split())
    pts = np.fromfile(d / f"{tag}_points.f64", dtype="<f8").reshape(n, dim)
    cells = np.fromfile(d / f"{tag}_cells.u32", dtype="<u4").reshape(-1, per)
    fixed = np.fromfile(d / f"{tag}_fixed.u32", dtype="<u4").astype(bool)
    disp = np.fromfile(d / f"{tag}_disp.f64", dtype="<f8").reshape(n, dim)
    sol = np.fromfile(d / f"{tag}_solution.f64", dtype="<f8").reshape(n, dim)
    return pts, cells, fixed, disp, sol


# VTK hexahedron order (the kernel's) -> scikit-fem's MeshHex order. scikit-fem numbers a
# unit cube's corners (0,0,0),(0,0,1),(0,1,0),(1,0,0),(0,1,1),(1,0,1),(1,1,0),(1,1,1); VTK's
# are (0,0,0),(1,0,0),(1,1,0),(0,1,0),(0,0,1),(1,0,1),(1,1,1),(0,1,1).
VTK_TO_SKFEM_HEX = [0, 4, 3, 1, 7, 5, 2, 6]


@BilinearForm
def elasticity(u, v, w):
    lam = w.E * NU / ((1.0 + NU) * (1.0 - 2.0 * NU))
    mu = w.E / (2.0 * (1.0 + NU))
    eu, ev = sym_grad(u), sym_grad(v)
    return 2.0 * mu * ddot(eu, ev) + lam * trace(eu) * trace(ev)


def rigid_modes(pts):
    n, dim = pts.shape
    if dim == 2:
        b = np.zeros((n, 2, 3))
        b[:, 0, 0] = 1.0
        b[:, 1, 1] = 1.0
        b[:, 0, 2] = -pts[:, 1]
        b[:, 1, 2] = pts[:, 0]
    else:
        b = np.zeros((n, 3, 6))
        for k in range(3):
            b[:, k, k] = 1.0
        x, y, z = pts.T
        b[:, 1, 3], b[:, 2, 3] = -z, y
        b[:, 0, 4], b[:, 2, 4] = z, -x
        b[:, 0, 5], b[:, 1, 5] = -y, x
    return b.reshape(n * dim, -1)


# Elements per assembly chunk: scikit-fem holds every basis function's gradient at every
# quadrature point of the elements it assembles (24 dofs x 9 x 8 points per hexahedron), ~3 GB
# for the whole 205k-node cube at once; chunks keep the peer's memory near the matrix's.
CHUNK = 40000


def assemble(pts, cells, dim):
    """The stiffness in node-major (x0, y0[, z0], x1, ...) order, as CSR."""
    if dim == 2:
        mesh = MeshTri(pts.T.copy(), cells.T.copy(), sort_t=False, validate=False)
        elem, scalar0, quad = ElementVector(ElementTriP1()), ElementTriP0(), {"intorder": 2}
    else:
        t = cells[:, VTK_TO_SKFEM_HEX]
        mesh = MeshHex(pts.T.copy(), t.T.copy(), sort_t=False, validate=False)
        q = get_quadrature(mesh.elem.refdom, 3)
        elem, scalar0, quad = ElementVector(ElementHex1()), ElementHex0(), {"quadrature": q}
    measure = Basis(mesh, scalar0, **quad).dx.sum(axis=1)
    e = measure.mean() / measure
    k = None
    for idx in np.array_split(np.arange(mesh.nelements), max(1, mesh.nelements // CHUNK)):
        basis = Basis(mesh, elem, elements=idx, **quad)
        part = elasticity.assemble(basis, E=np.repeat(e[idx, None], basis.dx.shape[1], axis=1))
        k = part if k is None else k + part
    # scikit-fem's vector dofs: nodal_dofs[c, i] is component c of node i.
    order = basis.nodal_dofs.T.reshape(-1)
    return k[order][:, order].tocsr()


def run(d, tag, out):
    pts, cells, fixed, disp, sol = read(d, tag)
    n, dim = pts.shape
    t = time.perf_counter()
    k = assemble(pts, cells, dim)
    t_asm = time.perf_counter() - t
    free_nodes = ~fixed
    free = np.repeat(free_nodes, dim)
    u = disp.reshape(-1).copy()
    u[free] = 0.0
    a = k[free][:, free].tocsr()
    b = -(k[free][:, ~free] @ u[~free])
    t = time.perf_counter()
    ml = pyamg.smoothed_aggregation_solver(a.tobsr(blocksize=(dim, dim)), B=rigid_modes(pts[free_nodes]))
    t_setup = time.perf_counter() - t
    res = []
    t = time.perf_counter()
    x = ml.solve(b, tol=TOL, accel="cg", maxiter=10000, residuals=res)
    t_solve = time.perf_counter() - t
    u[free] = x
    scale = np.abs(sol).max()
    diff = np.abs(u - sol.reshape(-1)).max() / scale
    rel = np.linalg.norm(b - a @ x) / np.linalg.norm(b)
    print(f"{tag}: {n} nodes, assembly {t_asm:.3f} s, setup {t_setup:.3f} s, solve {t_solve:.3f} s, "
          f"{len(res) - 1} it., {len(ml.levels)} levels, residual {rel:.2e}, max rel. difference {diff:.2e}")
    out[f"{tag}_skfem_assembly_s"] = t_asm
    out[f"{tag}_pyamg_setup_s"] = t_setup
    out[f"{tag}_pyamg_solve_s"] = t_solve
    out[f"{tag}_pyamg_iterations"] = len(res) - 1
    out[f"{tag}_pyamg_levels"] = len(ml.levels)
    out[f"{tag}_pyamg_residual"] = rel
    out[f"{tag}_max_relative_difference"] = f"{diff:.1e}"


def main():
    d = Path(sys.argv[1])
    out = {}
    for tag in ("elastic2d", "elastic3d"):
        run(d, tag, out)
    (d / "peers_elasticity.txt").write_text("".join(f"{k} {v}\n" for k, v in out.items()))


if __name__ == "__main__":
    main()
