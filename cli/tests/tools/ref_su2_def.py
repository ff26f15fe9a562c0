"""Independent reference for `deform su2` on SU2's own FFD test cases (cli/tests/su2_def.rs).

Reads the SU2 mesh before and after `deform su2`, and
1. the surface: evaluates the FFD box stored in the mesh (Bernstein polynomials, numpy) with
   the design variables' control-point moves, at the stored parametric coordinates of the
   DV_MARKER points, minus the mesh point (SU2's SetCartesianCoord), and SU2's fixed planes
   (a box face the DV_MARKER surface crosses fixes it and, for 2ND_DERIVATIVE, the next two
   planes; here found by sign changes across the axis-aligned face, a simpler test than
   SU2's and the tool's);
2. the volume: assembles SU2's linear elasticity with scikit-fem (P1 triangles, Q1 quads /
   hexahedra, 2x2(x2) Gauss points), per cell nu = DEFORM_COEFF (SU2's convention),
   mu = E / (2 (1 + nu)), lambda = nu E / ((1 + nu) (1 - 2 nu)) with
   E = 1 / |cell measure| (INVERSE_VOLUME), the DV_MARKER nodes displaced by (1), every
   other marker fixed, and solves it by a sparse direct solve.

Usage: ref_su2_def.py BEFORE AFTER DV_MARKER CONTINUITY DEFORM_COEFF MOVE...
  MOVE: "cp2d:TAG:i:j:dx:dy" (dx, dy already times DV_VALUE) or "cp:TAG:i:j:k:dx:dy:dz".
Prints: max |surface error|, max |volume error| (nodes not on a marker), max |displacement|.
"""
import sys
from math import comb

import numpy as np
from scipy.sparse.linalg import spsolve
from skfem import Basis, BilinearForm, ElementVector, MeshHex, MeshQuad, MeshTri, asm, condense
from skfem.element import ElementHex1, ElementQuad1, ElementTriP1
from skfem.helpers import ddot, sym_grad, trace


def read_su2(path):
    """NDIME, points, cells (VTK code, nodes), markers {name: [nodes per element]}, FFD lines."""
    lines = [l.split("%")[0].strip() for l in open(path)]
    lines = [l for l in lines if l]
    it = iter(lines)
    mesh = {"markers": {}, "ffd": []}
    for line in it:
        key, _, value = line.partition("=")
        key, value = key.strip().upper(), value.strip()
        if key == "NDIME":
            mesh["dim"] = int(value)
        elif key == "NELEM":
            rows = [next(it).split() for _ in range(int(value))]
            mesh["cells"] = [(int(r[0]), [int(x) for x in r[1:-1]]) for r in rows]
        elif key == "NPOIN":
            n = int(value.split()[0])
            rows = [next(it).split() for _ in range(n)]
            mesh["points"] = np.array([[float(x) for x in r[: mesh["dim"]]] for r in rows])
        elif key == "MARKER_TAG":
            elems = int(next(it).partition("=")[2])
            rows = [next(it).split() for _ in range(elems)]
            mesh["markers"][value] = [[int(x) for x in r[1:]] for r in rows]
        elif key.startswith("FFD_"):
            mesh["ffd"].append(line)
            mesh["ffd"].extend(rest for rest in it)
    return mesh


def read_box(ffd_lines):
    """The first box: degrees, control points [l+1, m+1, n+1, 3], surface points."""
    kv = {}
    i = 0
    while i < len(ffd_lines):
        key, _, value = ffd_lines[i].partition("=")
        key = key.strip()
        kv[key] = value.strip()
        i += 1
        if key == "FFD_CORNER_POINTS":
            i += int(value)
        elif key == "FFD_CONTROL_POINTS":
            n = int(value)
            cps = [ffd_lines[i + r].split() for r in range(n)]
            i += n
        elif key == "FFD_SURFACE_POINTS":
            n = int(value)
            surface = [ffd_lines[i + r].split() for r in range(n)]
            break
    deg = [int(kv["FFD_DEGREE_I"]), int(kv["FFD_DEGREE_J"]), int(kv.get("FFD_DEGREE_K", 1))]
    p = np.zeros((deg[0] + 1, deg[1] + 1, deg[2] + 1, 3))
    for r in cps:
        xyz = [float(x) for x in r[3:]] + [0.0] * (6 - len(r))
        p[int(r[0]), int(r[1]), int(r[2])] = xyz
    surf = [(r[0], int(r[1]), np.array([float(x) for x in r[2:5]])) for r in surface]
    return kv["FFD_TAG"], deg, p, surf


def bernstein(n, i, t):
    return comb(n, i) * t**i * (1.0 - t) ** (n - i)


def evaluate(deg, p, uvw):
    out = np.zeros(3)
    for i in range(deg[0] + 1):
        for j in range(deg[1] + 1):
            for k in range(deg[2] + 1):
                w = bernstein(deg[0], i, uvw[0]) * bernstein(deg[1], j, uvw[1])
                out += p[i, j, k] * w * bernstein(deg[2], k, uvw[2])
    return out


def fixed_planes(mesh, marker, deg, p, depth):
    """Planes fixed where the DV_MARKER edges cross an axis-aligned face of the box."""
    fixed = [set(), set(), set()]
    pts = mesh["points"]
    for axis in range(mesh["dim"]):
        for side, plane in ((0, 0), (1, deg[axis])):
            index = [0, 0, 0]
            index[axis] = plane
            level = p[tuple(index)][axis]
            crossed = any(
                (pts[a, axis] - level) * (pts[b, axis] - level) <= 0.0
                for e in mesh["markers"][marker]
                for a in e
                for b in e
                if b > a
            )
            if crossed and not (depth == 2 and deg[axis] <= 1):
                planes = range(min(depth, deg[axis]) + 1)
                fixed[axis] |= {s if side == 0 else deg[axis] - s for s in planes}
    return fixed


def apply_moves(deg, p, moves, fixed):
    p = p.copy()
    for move in moves:
        f = move.split(":")
        if f[0] == "cp2d":
            i, j, dx, dy = int(f[2]), int(f[3]), float(f[4]), float(f[5])
            if i in fixed[0] or j in fixed[1] or 0 in fixed[2]:
                continue
            p[i, j, :, 0] += dx
            p[i, j, :, 1] += dy
        else:
            ijk = [int(x) for x in f[2:5]]
            if any(ijk[a] in fixed[a] for a in range(3)):
                continue
            p[tuple(ijk)] += [float(x) for x in f[5:8]]
    return p


@BilinearForm
def elasticity(u, v, w):
    eu, ev = sym_grad(u), sym_grad(v)
    return w.lam * trace(eu) * trace(ev) + 2.0 * w.mu * ddot(eu, ev)


def measure(x):
    """|area| of a polygon (2D, nodes in order) or |volume| of a hexahedron (VTK order)."""
    if x.shape[1] == 2:
        return 0.5 * abs(np.dot(x[:, 0], np.roll(x[:, 1], -1)) - np.dot(np.roll(x[:, 0], -1), x[:, 1]))
    c = x.mean(axis=0)
    faces = [(0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6), (3, 0, 4, 7)]
    vol = 0.0
    for f in faces:
        fc = x[list(f)].mean(axis=0)
        for a, b in zip(f, f[1:] + f[:1]):
            vol += np.dot(np.cross(x[a] - c, x[b] - c), fc - c) / 6.0
    return abs(vol)


def skfem_mesh(mesh):
    code = {c for c, _ in mesh["cells"]}
    assert len(code) == 1, "one element kind"
    code = code.pop()
    pts = mesh["points"]
    cells = np.array([c for _, c in mesh["cells"]])
    if code in (5, 9):
        # scikit-fem wants counter-clockwise cells: reverse the clockwise ones.
        for c in cells:
            x = pts[c]
            if np.dot(x[:, 0], np.roll(x[:, 1], -1)) - np.dot(np.roll(x[:, 0], -1), x[:, 1]) < 0:
                c[:] = c[::-1]
        kind, elem = (MeshTri, ElementTriP1) if code == 5 else (MeshQuad, ElementQuad1)
        return kind(pts.T, cells.T), elem, cells
    # skfem's hexahedron node order from VTK's.
    return MeshHex(pts.T, cells[:, [0, 3, 4, 1, 2, 7, 5, 6]].T), ElementHex1, cells


def volume(mesh, surface, coeff, marker):
    m, elem, cells = skfem_mesh(mesh)
    dim = mesh["dim"]
    e = np.array([1.0 / measure(mesh["points"][c]) for c in cells])
    # skfem keeps the cell order given: e[c] belongs to m.t[:, c].
    basis = Basis(m, ElementVector(elem()), intorder=3)
    nqp = basis.X.shape[1]
    # SU2's CMeshSolver / CVolumetricMovement: nu = DEFORM_COEFF, E = 1/V.
    nu = coeff
    lam = nu * e / ((1.0 + nu) * (1.0 - 2.0 * nu))
    mu = e / (2.0 * (1.0 + nu))
    k = asm(elasticity, basis, lam=np.repeat(lam[:, None], nqp, 1),
            mu=np.repeat(mu[:, None], nqp, 1))
    n = len(mesh["points"])
    x = np.zeros(k.shape[0])
    dofs = basis.nodal_dofs
    boundary = sorted({a for es in mesh["markers"].values() for el in es for a in el})
    for node, d in surface.items():
        for c in range(dim):
            x[dofs[c, node]] = d[c]
    dfix = dofs[:, boundary].reshape(-1)
    a, b, _, interior = condense(k, np.zeros(k.shape[0]), x=x, D=dfix)
    x[interior] = spsolve(a.tocsc(), b)
    return np.array([[x[dofs[c, i]] for c in range(dim)] for i in range(n)]), set(boundary)


def main():
    before, after = read_su2(sys.argv[1]), read_su2(sys.argv[2])
    marker, continuity, coeff = sys.argv[3], sys.argv[4], float(sys.argv[5])
    depth = {"NO_DERIVATIVE": 0, "1ST_DERIVATIVE": 1, "2ND_DERIVATIVE": 2}[continuity]
    _, deg, p, surf = read_box(before["ffd"])
    dim = before["dim"]
    moved = apply_moves(deg, p, sys.argv[6:], fixed_planes(before, marker, deg, p, depth))
    surface = {}
    for name, node, uvw in surf:
        if name == marker:
            surface[node] = (evaluate(deg, moved, uvw) - np.append(before["points"][node], 0.0)[:3])[:dim]
    got = after["points"] - before["points"]
    surface_err = max(np.abs(got[n] - d).max() for n, d in surface.items())
    u, boundary = volume(before, surface, coeff, marker)
    inner = [i for i in range(len(u)) if i not in boundary]
    volume_err = np.abs(got[inner] - u[inner]).max()
    print(surface_err, volume_err, np.abs(got).max())


if __name__ == "__main__":
    main()
