#!/usr/bin/env python3
"""Independent validity check of an SU2 mesh (issue 31 item 1), written without the tool's code.

Reads the mesh with meshio, then per cell: signed measure in the SU2/VTK convention (how many
cells are listed clockwise / mirrored), whether the cell's own corners (2D) or faces (3D) agree in
sign with each other, whether the two cells of every interior face lie on opposite sides of it
(their centroids on opposite sides of the face's plane), and whether the sum of |measures|
equals the area/volume enclosed by the boundary (no overlap). Prints one JSON line.

    python3 check_validity.py mesh.su2
(needs numpy and meshio: python3 -m venv v && v/bin/pip install numpy meshio)
"""
import json
import sys
from collections import defaultdict

import meshio
import numpy as np

# Outward faces of a cell listed in the VTK convention, except the prism (SU2/kernel convention:
# base 0,1,2 turns away from the top). Only the face *sets* matter for the side tests below.
FACES = {
    "tetra": [(0, 2, 1), (0, 1, 3), (1, 2, 3), (0, 3, 2)],
    "hexahedron": [(0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6), (3, 0, 4, 7)],
    "wedge": [(0, 1, 2), (3, 5, 4), (0, 3, 4, 1), (1, 4, 5, 2), (2, 5, 3, 0)],
    "pyramid": [(0, 3, 2, 1), (0, 1, 4), (1, 2, 4), (2, 3, 4), (3, 0, 4)],
}


def newell(p):
    """Area vector of a planar-ish polygon (Newell's method)."""
    n = np.zeros(3)
    for i in range(len(p)):
        a, b = p[i], p[(i + 1) % len(p)]
        n += np.cross(a, b)
    return n / 2


def cross2(u, v):
    return u[0] * v[1] - u[1] * v[0]


def listed_sign_3d(kind, p):
    """+1 when the cell is listed in the SU2/VTK convention, -1 when mirrored."""
    if kind == "tetra":
        return np.sign(np.linalg.det(np.array([p[1] - p[0], p[2] - p[0], p[3] - p[0]])))
    if kind == "hexahedron":
        up = p[4:8].mean(0) - p[0:4].mean(0)
        return np.sign(newell(p[0:4]) @ up)
    if kind == "pyramid":
        return np.sign(newell(p[0:4]) @ (p[4] - p[0:4].mean(0)))
    if kind == "wedge":  # SU2: the base turns away from the top
        return -np.sign(newell(p[0:3]) @ (p[3:6].mean(0) - p[0:3].mean(0)))
    raise ValueError(kind)


def check_2d(pts, cells):
    pts = pts[:, :2]
    signed, folded_corners = [], 0
    sides = defaultdict(list)
    for kind, conn in cells:
        for nodes in conn:
            p = pts[nodes]
            n = len(nodes)
            area = 0.5 * sum(p[i, 0] * p[(i + 1) % n, 1] - p[(i + 1) % n, 0] * p[i, 1] for i in range(n))
            signed.append(area)
            corners = [cross2(p[(i + 1) % n] - p[i], p[i - 1] - p[i]) for i in range(n)]
            if not (all(c > 0 for c in corners) or all(c < 0 for c in corners)):
                folded_corners += 1
            c = p.mean(0)
            for i in range(n):
                a, b = sorted((nodes[i], nodes[(i + 1) % n]))
                side = np.sign(cross2(pts[b] - pts[a], c - pts[a]))
                sides[(a, b)].append((side, area, nodes[i] == a))
    # Enclosed area from the boundary edges, each oriented with its cell's own orientation.
    enclosed = 0.0
    same_side = 0
    for (a, b), s in sides.items():
        if len(s) == 2:
            same_side += s[0][0] == s[1][0]
        elif len(s) == 1:
            _, area, forward = s[0]
            u, v = (a, b) if forward == (area > 0) else (b, a)
            enclosed += 0.5 * (pts[u, 0] * pts[v, 1] - pts[v, 0] * pts[u, 1])
    signed = np.array(signed)
    return signed, folded_corners, same_side, abs(enclosed)


def check_3d(pts, cells):
    signed, folded_faces = [], 0
    faces = defaultdict(list)
    for kind, conn in cells:
        for nodes in conn:
            p = pts[nodes]
            c = p.mean(0)
            outs = []
            vol = 0.0
            for f in FACES[kind]:
                q = p[list(f)]
                outs.append(newell(q) @ (q.mean(0) - c))
                # Volume from the centroid: a fan of triangles over each face.
                for i in range(1, len(f) - 1):
                    vol += np.linalg.det(np.array([q[0] - c, q[i] - c, q[i + 1] - c])) / 6
                faces[tuple(sorted(nodes[list(f)]))].append((q, c))
            if not (all(o > 0 for o in outs) or all(o < 0 for o in outs)):
                folded_faces += 1
            signed.append(listed_sign_3d(kind, p) * abs(vol))
    # Enclosed volume: the divergence theorem over the boundary faces, each turned to point
    # away from its cell's centroid.
    enclosed = 0.0
    for key, owners in faces.items():
        if len(owners) == 1:
            q, c = owners[0]
            if newell(q) @ (q.mean(0) - c) < 0:
                q = q[::-1]
            for i in range(1, len(q) - 1):
                enclosed += np.linalg.det(np.array([q[0], q[i], q[i + 1]])) / 6
    return np.array(signed), folded_faces, abs(enclosed)


def interior_same_side_3d(pts, cells):
    """Interior faces whose two cells' centroids lie on the same side of the face's plane."""
    owners = defaultdict(list)
    for kind, conn in cells:
        for nodes in conn:
            c = pts[nodes].mean(0)
            for f in FACES[kind]:
                key = tuple(sorted(nodes[list(f)]))
                owners[key].append(c)
    count = 0
    for key, cs in owners.items():
        if len(cs) == 2:
            q = pts[list(key)]
            # The plane through the face's nodes (least squares normal).
            centre = q.mean(0)
            normal = np.linalg.svd(q - centre)[2][-1]
            a, b = (cs[0] - centre) @ normal, (cs[1] - centre) @ normal
            count += (a > 0) == (b > 0)
    return count


def main(path):
    m = meshio.read(path, file_format="su2")
    dim = 3 if any(cb.type in FACES for cb in m.cells) else 2
    volume_kinds = set(FACES) if dim == 3 else {"triangle", "quad"}
    cells = [(cb.type, cb.data) for cb in m.cells if cb.type in volume_kinds]
    if dim == 2:
        signed, folded, same_side, enclosed = check_2d(m.points, cells)
    else:
        signed, folded, enclosed = check_3d(m.points, cells)
        same_side = interior_same_side_3d(m.points, cells)
    total = float(np.abs(signed).sum())
    print(json.dumps({
        "file": path,
        "dim": dim,
        "cells": int(len(signed)),
        "listed_reversed": int((signed < 0).sum()),
        "cells_whose_corners_disagree": int(folded),
        "interior_faces_with_both_cells_on_one_side": int(same_side),
        "sum_abs_measure": total,
        "enclosed_measure": float(enclosed),
        "relative_difference": abs(total - enclosed) / enclosed,
        "min_abs_measure": float(np.abs(signed).min()),
    }))


if __name__ == "__main__":
    main(sys.argv[1])
