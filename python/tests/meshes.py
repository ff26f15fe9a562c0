"""Small test meshes built with numpy (no kernel code)."""

import numpy as np


def holed_square(n=9, half=2.0, hole=0.5):
    """A triangulated square ``[-half, half]^2`` (n x n nodes) with a square hole
    ``[-hole, hole]^2``: ``(points (N, 2), triangles (C, 3), hole_nodes, outer_nodes,
    hole_edges, outer_edges)``, unused nodes removed, triangles counter-clockwise."""
    xs = np.linspace(-half, half, n)
    x, y = np.meshgrid(xs, xs, indexing="xy")
    pts = np.column_stack([x.ravel(), y.ravel()])
    tris = []
    for j in range(n - 1):
        for i in range(n - 1):
            a, b, c, d = j * n + i, j * n + i + 1, (j + 1) * n + i + 1, (j + 1) * n + i
            centre = pts[[a, b, c, d]].mean(axis=0)
            if np.all(np.abs(centre) < hole):
                continue
            tris += [[a, b, c], [a, c, d]]
    tris = np.array(tris)
    used = np.unique(tris)
    renum = np.full(len(pts), -1)
    renum[used] = np.arange(used.size)
    pts, tris = pts[used], renum[tris]
    on_hole = np.all(np.abs(pts) <= hole + 1e-12, axis=1)
    on_outer = np.any(np.abs(pts) >= half - 1e-12, axis=1)
    return pts, tris, np.flatnonzero(on_hole), np.flatnonzero(on_outer), _edges(
        pts, tris, on_hole), _edges(pts, tris, on_outer)


def _edges(pts, tris, mask):
    """Boundary edges (in one triangle only) with both nodes in ``mask``."""
    count = {}
    for t in tris:
        for a, b in ((t[0], t[1]), (t[1], t[2]), (t[2], t[0])):
            count.setdefault(tuple(sorted((a, b))), []).append((a, b))
    return np.array([e[0] for e in count.values() if len(e) == 1 and mask[e[0][0]] and mask[e[0][1]]])


def batina_dense_solve(pts, tris, boundary, disp):
    """The linear spring system solved densely: stiffness 1/L per edge, interior rows
    sum_j k_ij (u_i - u_j) = 0, boundary rows u_i = disp_i."""
    n = len(pts)
    a = np.zeros((n, n))
    edges = {tuple(sorted(e)) for t in tris for e in ((t[0], t[1]), (t[1], t[2]), (t[2], t[0]))}
    for i, j in edges:
        k = 1.0 / np.linalg.norm(pts[i] - pts[j])
        a[i, i] += k
        a[j, j] += k
        a[i, j] -= k
        a[j, i] -= k
    rhs = np.zeros_like(pts)
    for b in boundary:
        a[b, :] = 0.0
        a[b, b] = 1.0
        rhs[b] = disp[b]
    return np.linalg.solve(a, rhs)


def write_su2(path, pts, tris, markers):
    """A 2D SU2 mesh (coordinates in repr, which round-trips exactly)."""
    lines = ["NDIME= 2", f"NELEM= {len(tris)}"]
    lines += [f"5 {a} {b} {c} {k}" for k, (a, b, c) in enumerate(tris)]
    lines.append(f"NPOIN= {len(pts)}")
    lines += [f"{float(x)!r} {float(y)!r} {k}" for k, (x, y) in enumerate(pts)]
    lines.append(f"NMARK= {len(markers)}")
    for name, edges in markers.items():
        lines += [f"MARKER_TAG= {name}", f"MARKER_ELEMS= {len(edges)}"]
        lines += [f"3 {a} {b}" for a, b in edges]
    path.write_text("\n".join(lines) + "\n")


def read_su2_points(path):
    """The points of an SU2 mesh, parsed exactly (float() of the written decimals)."""
    lines = path.read_text().splitlines()
    start = next(k for k, l in enumerate(lines) if l.startswith("NPOIN="))
    n = int(lines[start].split("=")[1].split()[0])
    rows = [l.split() for l in lines[start + 1:start + 1 + n]]
    out = np.zeros((n, 2))
    for r in rows:
        out[int(r[2])] = [float(r[0]), float(r[1])]
    return out
