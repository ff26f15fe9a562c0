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
            if np.all(np.abs(centre) < hole - 1e-9):
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


HEX_EDGES = [(0, 1), (1, 2), (2, 3), (3, 0), (4, 5), (5, 6), (6, 7), (7, 4),
             (0, 4), (1, 5), (2, 6), (3, 7)]


def hex_box(n=4):
    """Hexahedra filling the unit cube (n x n x n nodes): ``(points (N, 3), hexes (C, 8) in
    VTK order, bottom quads (z = 0), other boundary quads)``."""
    xs = np.linspace(0.0, 1.0, n)
    z, y, x = np.meshgrid(xs, xs, xs, indexing="ij")
    pts = np.column_stack([x.ravel(), y.ravel(), z.ravel()])
    node = lambda i, j, k: (k * n + j) * n + i  # noqa: E731
    hexes = [[node(i, j, k), node(i + 1, j, k), node(i + 1, j + 1, k), node(i, j + 1, k),
              node(i, j, k + 1), node(i + 1, j, k + 1), node(i + 1, j + 1, k + 1),
              node(i, j + 1, k + 1)]
             for k in range(n - 1) for j in range(n - 1) for i in range(n - 1)]
    faces = {}
    for h in hexes:
        for f in ((0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6),
                  (3, 0, 4, 7)):
            quad = [h[v] for v in f]
            faces.setdefault(tuple(sorted(quad)), []).append(quad)
    outer = np.array([q[0] for q in faces.values() if len(q) == 1])
    bottom = np.all(pts[outer][:, :, 2] == 0.0, axis=1)
    return pts, np.array(hexes), outer[bottom], outer[~bottom]


def batina_dense_solve(pts, tris, boundary, disp, local_edges=((0, 1), (1, 2), (2, 0))):
    """The linear spring system solved densely: stiffness 1/L per edge (``local_edges`` of
    each cell), interior rows sum_j k_ij (u_i - u_j) = 0, boundary rows u_i = disp_i."""
    n = len(pts)
    a = np.zeros((n, n))
    edges = {tuple(sorted((t[p], t[q]))) for t in tris for p, q in local_edges}
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


#: SU2 (VTK) codes of volume cells and boundary elements by node count.
SU2_VOLUME = {3: 5, 8: 12}
SU2_BOUNDARY = {2: 3, 4: 9}


def write_su2(path, pts, cells, markers):
    """An SU2 mesh of triangles (2D) or hexahedra (3D), boundary elements of 2 or 4 nodes
    (coordinates in repr, which round-trips exactly)."""
    dim = pts.shape[1]
    lines = [f"NDIME= {dim}", f"NELEM= {len(cells)}"]
    code = SU2_VOLUME[cells.shape[1]]
    lines += [f"{code} {' '.join(map(str, c))} {k}" for k, c in enumerate(cells)]
    lines.append(f"NPOIN= {len(pts)}")
    lines += [" ".join(repr(float(x)) for x in p) + f" {k}" for k, p in enumerate(pts)]
    lines.append(f"NMARK= {len(markers)}")
    for name, elems in markers.items():
        lines += [f"MARKER_TAG= {name}", f"MARKER_ELEMS= {len(elems)}"]
        lines += [f"{SU2_BOUNDARY[len(e)]} {' '.join(map(str, e))}" for e in elems]
    path.write_text("\n".join(lines) + "\n")


def read_su2_points(path, dim=2):
    """The points of an SU2 mesh, parsed exactly (float() of the written decimals)."""
    lines = path.read_text().splitlines()
    start = next(k for k, l in enumerate(lines) if l.startswith("NPOIN="))
    n = int(lines[start].split("=")[1].split()[0])
    out = np.zeros((n, dim))
    for line in lines[start + 1:start + 1 + n]:
        r = line.split()
        out[int(r[dim])] = [float(x) for x in r[:dim]]
    return out
