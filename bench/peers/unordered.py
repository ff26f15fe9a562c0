"""Meshes as users have them (issue 34), for `cargo xtask bench`:

    python unordered.py DIR DEFORM [--quick] [--box-only]

DIR holds `naca2412.su2` (the generated NACA 2412 mesh, numbered line by line). This script
writes two meshes numbered the way users get them and times, on each, the whole
`deform move` command (spring and quaternion, with `--renumber off` and the default `auto`)
against pyamg's smoothed-aggregation setup + CG solve of the same spring system:

- `naca_shuffled.su2`: the generated 2D triangle mesh with its nodes randomly permuted (fixed
  seed), rotated -10 degrees about the quarter chord as the ordered bench case;
- `box_gmsh_h<size>.su2` (made once, gmsh is deterministic): a 3D tetrahedral mesh written by gmsh (its own numbering) of the cube
  [-2, 2]^3 around a box 1 x 0.5 x 1 refined towards it, the inner box rotated 5 degrees about z.

The spring system is assembled here from the mesh, independently of the kernel (Batina
stiffness 1/L on the cell edges, every marker node fixed, the moved marker's rigid
displacement), and its pyamg solution is compared with the displacement `deform` wrote. Writes
DIR/unordered.txt (`name value` lines) and DIR/unordered.md (the report's table). Speed is
compared, never asserted.
"""

import json
import math
import os
import subprocess
import sys
import time

import numpy as np
import scipy.sparse as sp

# Edges of the VTK cell types that appear in the meshes here (SU2 uses VTK codes).
EDGES = {
    3: [(0, 1)],
    5: [(0, 1), (1, 2), (2, 0)],
    9: [(0, 1), (1, 2), (2, 3), (3, 0)],
    10: [(0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3)],
}


class Su2:
    """The parts of an SU2 file the bench needs (one zone, no periodic sections)."""

    def __init__(self, path):
        with open(path) as f:
            lines = [l.split("%")[0].strip() for l in f]
        lines = [l for l in lines if l]
        it = iter(lines)
        self.dim = int(next(it).split("=")[1])
        self.elements, self.points, self.markers = [], [], []
        for line in it:
            key, _, value = line.partition("=")
            if key == "NELEM":
                self.elements = [[int(v) for v in next(it).split()] for _ in range(int(value))]
            elif key == "NPOIN":
                n = int(value.split()[0])
                self.points = np.array([[float(v) for v in next(it).split()[: self.dim]] for _ in range(n)])
            elif key == "MARKER_TAG":
                name = value.strip()
                count = int(next(it).split("=")[1])
                self.markers.append((name, [[int(v) for v in next(it).split()] for _ in range(count)]))

    def cells(self, code_and_nodes):
        """(code, nodes) of an element line (a trailing index dropped)."""
        code = code_and_nodes[0]
        k = {3: 2, 5: 3, 9: 4, 10: 4, 12: 8, 13: 6, 14: 5}[code]
        return code, code_and_nodes[1 : 1 + k]

    def renumbered(self, inverse):
        """A copy with node `i` renamed `inverse[i]` (points moved to match)."""
        out = Su2.__new__(Su2)
        out.dim = self.dim
        out.points = np.empty_like(self.points)
        out.points[inverse] = self.points
        ren = lambda e: [self.cells(e)[0]] + [int(inverse[v]) for v in self.cells(e)[1]]
        out.elements = [ren(e) for e in self.elements]
        out.markers = [(name, [ren(e) for e in es]) for name, es in self.markers]
        return out

    def write(self, path):
        with open(path, "w") as f:
            f.write(f"NDIME= {self.dim}\nNELEM= {len(self.elements)}\n")
            for k, e in enumerate(self.elements):
                code, nodes = self.cells(e)
                f.write(" ".join(str(v) for v in [code] + list(nodes)) + f" {k}\n")
            f.write(f"NPOIN= {len(self.points)}\n")
            for k, p in enumerate(self.points):
                f.write(" ".join(repr(float(x)) for x in p) + f" {k}\n")
            f.write(f"NMARK= {len(self.markers)}\n")
            for name, es in self.markers:
                f.write(f"MARKER_TAG= {name}\nMARKER_ELEMS= {len(es)}\n")
                for e in es:
                    code, nodes = self.cells(e)
                    f.write(" ".join(str(v) for v in [code] + list(nodes)) + "\n")

    def marker_nodes(self, names=None):
        nodes = set()
        for name, es in self.markers:
            if names is None or name in names:
                for e in es:
                    nodes.update(self.cells(e)[1])
        return np.array(sorted(nodes), dtype=np.int64)


def box_gmsh(path, h):
    """The gmsh tetrahedral mesh of the cube around the box (gmsh's own node numbering)."""
    import gmsh

    gmsh.initialize()
    gmsh.option.setNumber("General.Terminal", 0)
    gmsh.option.setNumber("General.NumThreads", 1)
    gmsh.model.add("box")
    occ = gmsh.model.occ
    outer = occ.addBox(-2, -2, -2, 4, 4, 4)
    inner = occ.addBox(-0.5, -0.25, -0.5, 1, 0.5, 1)
    vol, _ = occ.cut([(3, outer)], [(3, inner)])
    occ.synchronize()
    inner_s, outer_s = [], []
    for d, s in gmsh.model.getBoundary(vol, oriented=False):
        c = occ.getCenterOfMass(d, s)
        (inner_s if max(abs(x) for x in c) < 1 else outer_s).append(s)
    gmsh.model.addPhysicalGroup(2, inner_s, name="inner")
    gmsh.model.addPhysicalGroup(2, outer_s, name="outer")
    gmsh.model.addPhysicalGroup(3, [v[1] for v in vol], name="fluid")
    f = gmsh.model.mesh.field
    d = f.add("Distance")
    f.setNumbers(d, "SurfacesList", inner_s)
    th = f.add("Threshold")
    f.setNumber(th, "InField", d)
    f.setNumber(th, "SizeMin", h)
    f.setNumber(th, "SizeMax", 8 * h)
    f.setNumber(th, "DistMin", 0.1)
    f.setNumber(th, "DistMax", 1.8)
    f.setAsBackgroundMesh(th)
    gmsh.option.setNumber("Mesh.MeshSizeExtendFromBoundary", 0)
    gmsh.option.setNumber("Mesh.Algorithm3D", 1)
    gmsh.model.mesh.generate(3)
    gmsh.write(path)
    gmsh.finalize()


def spring_system(mesh):
    """Batina spring matrix (1/L on every cell edge), as CSR over all nodes."""
    pairs = set()
    for e in mesh.elements:
        code, nodes = mesh.cells(e)
        for a, b in EDGES[code]:
            x, y = nodes[a], nodes[b]
            pairs.add((min(x, y), max(x, y)))
    e = np.array(sorted(pairs), dtype=np.int64)
    k = 1.0 / np.linalg.norm(mesh.points[e[:, 0]] - mesh.points[e[:, 1]], axis=1)
    n = len(mesh.points)
    rows = np.r_[e[:, 0], e[:, 1], np.arange(n)]
    cols = np.r_[e[:, 1], e[:, 0], np.arange(n)]
    diag = np.zeros(n)
    np.add.at(diag, e[:, 0], k)
    np.add.at(diag, e[:, 1], k)
    return sp.csr_matrix((np.r_[-k, -k, diag], (rows, cols)), shape=(n, n)), len(e)


def rotation(points, nodes, degrees, center):
    """Displacement of `nodes` rotated about z through `center`."""
    t = math.radians(degrees)
    c, s = math.cos(t), math.sin(t)
    p = points[nodes, :2] - center[:2]
    d = np.zeros((len(nodes), points.shape[1]))
    d[:, 0] = c * p[:, 0] - s * p[:, 1] - p[:, 0]
    d[:, 1] = s * p[:, 0] + c * p[:, 1] - p[:, 1]
    return d


def pyamg_solve(mesh, moved, degrees, center, fig, tag):
    """Setup + solve of the free-node system by pyamg SA-CG to 1e-8; returns the full field."""
    import pyamg

    a, edges = spring_system(mesh)
    n = len(mesh.points)
    fixed = mesh.marker_nodes()
    free = np.setdiff1d(np.arange(n), fixed)
    u = np.zeros((n, mesh.dim))
    mv = mesh.marker_nodes([moved])
    u[mv] = rotation(mesh.points, mv, degrees, center)
    aff = a[free][:, free].tocsr()
    b = -(a[free][:, fixed] @ u[fixed])
    comps = [c for c in range(mesh.dim) if np.any(b[:, c] != 0)]
    t0 = time.perf_counter()
    ml = pyamg.smoothed_aggregation_solver(aff)
    t1 = time.perf_counter()
    its = []
    for c in comps:
        res = []
        u[free, c] = ml.solve(b[:, c], tol=1e-8, accel="cg", maxiter=1000, residuals=res)
        its.append(len(res) - 1)
    t2 = time.perf_counter()
    fig.put(f"{tag}_nodes", n)
    fig.put(f"{tag}_edges", edges)
    fig.put(f"{tag}_pyamg_setup_s", t1 - t0)
    fig.put(f"{tag}_pyamg_solve_s", t2 - t1)
    fig.put(f"{tag}_pyamg_iterations", ",".join(map(str, its)))
    fig.put(f"{tag}_pyamg_levels", ",".join(str(l.A.shape[0]) for l in ml.levels))
    return u


def run_deform(deform, d, mesh_file, args, renumber, out):
    cmd = [deform, "--json", "move", mesh_file, *args, "--renumber", renumber, "--tol", "1e-8",
           "--allow-folds", "--out", out]
    t = time.perf_counter()
    p = subprocess.run(cmd, cwd=d, capture_output=True, text=True)
    wall = time.perf_counter() - t
    if p.returncode != 0:
        raise SystemExit(f"{' '.join(cmd)} failed: {p.stderr}")
    return wall, json.loads(p.stdout)


def case(deform, d, fig, table, tag, mesh_file, mesh, moved, degrees, center, title):
    u = pyamg_solve(mesh, moved, degrees, center, fig, tag)
    peer = float(fig.get(f"{tag}_pyamg_setup_s")) + float(fig.get(f"{tag}_pyamg_solve_s"))
    args = ["--marker", moved, "--rotate", str(degrees), "--center",
            ",".join(str(c) for c in center[: mesh.dim])]
    for method in ("spring", "quaternion"):
        for renumber in ("off", "auto"):
            out = f"{tag}_{method}_{renumber}.su2"
            wall, rep = run_deform(deform, d, mesh_file, args + ["--method", method], renumber, out)
            r = rep["renumber"]
            key = f"{tag}_{method}_{renumber}"
            fig.put(f"{key}_s", wall)
            fig.put(f"{key}_iterations", rep["iterations"])
            fig.put(f"{key}_renumber", r["method"])
            fig.put(f"{key}_renumber_s", r["seconds"])
            if method == "spring":
                got = Su2(os.path.join(d, out)).points - mesh.points
                scale = np.abs(u).max()
                fig.put(f"{key}_max_relative_difference_to_pyamg", f"{np.abs(got - u).max() / scale:e}")
            what = "input numbering"
            if r["mean_distance_before"] is not None:
                what = (f"{r['method']}: mean index distance {r['mean_distance_before']:.0f} → "
                        f"{r['mean_distance_after']:.0f}, {r['seconds']:.3f} s")
            table.append(
                f"| {title}: `deform move --method {method} --renumber {renumber}` ({what}) "
                f"| {wall:.2f} s, {rep['iterations']} it. | pyamg setup + solve {peer:.2f} s "
                f"({fig.get(tag + '_pyamg_iterations')} it.) | {wall / peer:.2f} | ≤ 0.5 |"
            )


class Figures:
    def __init__(self):
        self.values = {}

    def put(self, name, value):
        print(f"  {name} = {value}", flush=True)
        self.values[name] = str(value)

    def get(self, name):
        return self.values[name]


def main():
    d, deform = sys.argv[1], os.path.abspath(sys.argv[2])
    quick = "--quick" in sys.argv[3:]
    fig, table = Figures(), []
    if "--box-only" not in sys.argv[3:]:
        naca_case(deform, d, fig, table)
    box_case(deform, d, fig, table, quick)
    with open(os.path.join(d, "unordered.txt"), "w") as f:
        f.write("".join(f"{k} {v}\n" for k, v in fig.values.items()))
    with open(os.path.join(d, "unordered.md"), "w") as f:
        f.write("\n".join(table) + "\n")


def naca_case(deform, d, fig, table):
    """The generated NACA mesh, randomly numbered."""
    naca = Su2(os.path.join(d, "naca2412.su2"))
    rng = np.random.default_rng(34)
    shuffled = naca.renumbered(rng.permutation(len(naca.points)))
    shuffled.write(os.path.join(d, "naca_shuffled.su2"))
    case(deform, d, fig, table, "naca_shuffled", "naca_shuffled.su2", shuffled, "airfoil", -10.0,
         np.array([0.25, 0.0, 0.0]), f"NACA 2412, {len(naca.points)} nodes, randomly numbered")


def box_case(deform, d, fig, table, quick):
    """The gmsh tetrahedral mesh in gmsh's numbering (at least 200k nodes unless quick)."""
    h = 0.05 if quick else 0.018
    box_file = f"box_gmsh_h{h}.su2"
    if not os.path.exists(os.path.join(d, box_file)):  # gmsh is deterministic: made once
        t = time.perf_counter()
        box_gmsh(os.path.join(d, box_file), h)
        fig.put("box_gmsh_mesh_s", time.perf_counter() - t)
    box = Su2(os.path.join(d, box_file))
    case(deform, d, fig, table, "box_gmsh", box_file, box, "inner", 5.0,
         np.array([0.0, 0.0, 0.0]), f"box in a cube, gmsh tetrahedra, {len(box.points)} nodes, gmsh's numbering")


if __name__ == "__main__":
    main()
