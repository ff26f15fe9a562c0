"""Independent FE elasticity for docs/methods.md (run by hand; no test calls it):
scikit-fem assembly, scipy direct solves, SU2's INVERSE_VOLUME stiffness on each
increment's mesh and load increments, on a 2D SU2 mesh (triangles + quads).

python ref_increments.py mesh.su2 degrees steps split modulus nu [out.npy]
  split: chord (SU2: VarCoord/N per increment) | arc (rotation by s*theta/N)
  modulus: current (1/V of the mesh of each increment, SU2) | original (1/V of the undeformed)
           | constant
"""
import json
import sys
import time

import numpy as np
from scipy.sparse.linalg import spsolve
from skfem import Basis, BilinearForm, ElementVector, MeshQuad, MeshTri, asm, condense
from skfem.element import ElementQuad1, ElementTriP1
from skfem.helpers import ddot, sym_grad, trace


def read_su2(path):
    lines = [l.split("%")[0].strip() for l in open(path)]
    lines = [l for l in lines if l]
    i, cells, pts, markers = 0, [], None, {}
    while i < len(lines):
        l = lines[i]
        if l.startswith("NELEM="):
            ne = int(l.split("=")[1])
            for k in range(ne):
                f = lines[i + 1 + k].split()
                code = int(f[0])
                nn = {5: 3, 9: 4}[code]
                cells.append([int(x) for x in f[1:1 + nn]])
            i += ne + 1
        elif l.startswith("NPOIN="):
            npn = int(l.split("=")[1].split()[0])
            pts = np.array([[float(x) for x in lines[i + 1 + k].split()[:2]] for k in range(npn)])
            i += npn + 1
        elif l.startswith("MARKER_TAG="):
            tag = l.split("=")[1].strip()
            ne = int(lines[i + 1].split("=")[1])
            nodes = set()
            for k in range(ne):
                nodes.update(int(x) for x in lines[i + 2 + k].split()[1:])
            markers[tag] = np.array(sorted(nodes))
            i += ne + 2
        else:
            i += 1
    return pts, cells, markers


def signed_area(p, cells):
    out = np.empty(len(cells))
    for c, nodes in enumerate(cells):
        q = p[nodes]
        out[c] = 0.5 * np.sum(q[:, 0] * np.roll(q[:, 1], -1) - np.roll(q[:, 0], -1) * q[:, 1])
    return out


@BilinearForm
def elasticity(u, v, w):
    eu, ev = sym_grad(u), sym_grad(v)
    return w.lam * trace(eu) * trace(ev) + 2.0 * w.mu * ddot(eu, ev)


def assemble(p, tris, quads, e_tri, e_quad, nu):
    k = None
    for kind, t, e in (("tri", tris, e_tri), ("quad", quads, e_quad)):
        if len(t) == 0:
            continue
        if kind == "tri":
            mesh = MeshTri(p.T.copy(), t.T.copy(), validate=False, sort_t=False)
            basis = Basis(mesh, ElementVector(ElementTriP1()), intorder=1)
        else:
            mesh = MeshQuad(p.T.copy(), t.T.copy(), validate=False, sort_t=False)
            basis = Basis(mesh, ElementVector(ElementQuad1()), intorder=3)
        lam = e * nu / ((1 + nu) * (1 - 2 * nu))
        mu = e / (2 * (1 + nu))
        nq = basis.X.shape[1]
        kk = asm(elasticity, basis, lam=np.repeat(lam[:, None], nq, 1),
                 mu=np.repeat(mu[:, None], nq, 1))
        kk = kk.tocsr()
        kk.resize((2 * len(p), 2 * len(p)))
        k = kk if k is None else k + kk
    return k, np.arange(2 * len(p)).reshape(-1, 2).T


def rotate(p, center, deg):
    th = np.radians(deg)
    c, s = np.cos(th), np.sin(th)
    r = p - center
    return center + np.stack([c * r[:, 0] - s * r[:, 1], s * r[:, 0] + c * r[:, 1]], 1)


def run(path, degrees, steps, split, modulus, nu, center=(0.25, 0.0)):
    p0, cells, markers = read_su2(path)
    center = np.array(center)
    tris = np.array([c for c in cells if len(c) == 3], dtype=np.int64).reshape(-1, 3)
    quads = np.array([c for c in cells if len(c) == 4], dtype=np.int64).reshape(-1, 4)
    order = [c for c in cells if len(c) == 3] + [c for c in cells if len(c) == 4]
    a0 = signed_area(p0, order)
    wall = markers["airfoil"]
    fixed = np.union1d(wall, markers["farfield"])
    final = rotate(p0[wall], center, degrees)
    p = p0.copy()
    iters = 0
    for s in range(1, steps + 1):
        area = np.abs(signed_area(p if modulus == "current" else p0, order))
        e = 1.0 / (area / area.max()) if modulus != "constant" else np.ones_like(area)
        k, dofs = assemble(p, tris, quads, e[:len(tris)], e[len(tris):], nu)
        n = len(p)
        x = np.zeros(2 * n)
        if split == "chord":
            target = p0[wall] + (final - p0[wall]) * s / steps
        else:
            target = rotate(p0[wall], center, degrees * s / steps)
        du = target - p[wall]
        for c in range(2):
            x[dofs[c, wall]] = du[:, c]
        dfix = dofs[:, fixed].reshape(-1)
        a, b, _, interior = condense(k, np.zeros(2 * n), x=x, D=dfix)
        x[interior] = spsolve(a.tocsc(), b)
        u = np.stack([x[dofs[0]], x[dofs[1]]], 1)
        p = p + u
        p[wall] = target
    a1 = signed_area(p, order)
    ratio = a1 / a0
    cent0 = np.array([p0[c].mean(0) for c in order])
    worst = int(np.argmin(ratio))
    return {
        "degrees": degrees, "steps": steps, "split": split, "modulus": modulus, "nu": nu,
        "min_area_ratio": float(ratio.min()), "inverted": int((ratio <= 0).sum()),
        "worst_cell_centroid": cent0[worst].tolist(),
        "worst_dist_from_center": float(np.linalg.norm(cent0[worst] - center)),
    }, p


if __name__ == "__main__":
    t = time.time()
    r, p = run(sys.argv[1], float(sys.argv[2]), int(sys.argv[3]), sys.argv[4], sys.argv[5],
               float(sys.argv[6]))
    r["seconds"] = time.time() - t
    if len(sys.argv) > 7:
        np.save(sys.argv[7], p)
    print(json.dumps(r))
