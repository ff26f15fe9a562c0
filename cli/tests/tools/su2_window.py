#!/usr/bin/env python3
"""Cut the cells of a 2D SU2 mesh whose centroid lies in a box into a smaller SU2 file (to commit
a small piece of a large public mesh as test data). Node order, cell node order and coordinates
(as text) are kept; nodes are renumbered in their original order; marker lines are kept when
they are an edge of a kept cell.

    python3 su2_window.py IN.su2 OUT.su2 XMIN XMAX YMIN YMAX
"""
import sys


def main(src, dst, x0, x1, y0, y1):
    lines = open(src).read().splitlines()
    it = iter(lines)
    cells, points, markers = [], [], []
    for line in it:
        key = line.split("=")[0].strip()
        if key == "NELEM":
            for _ in range(int(line.split("=")[1])):
                cells.append(next(it).split())
        elif key == "NPOIN":
            for _ in range(int(line.split("=")[1].split()[0])):
                points.append(next(it).split())
        elif key in ("MARKER_TAG", "MARKERTAG"):
            name = line.split("=")[1].strip()
            n = int(next(it).split("=")[1])
            markers.append((name, [next(it).split() for _ in range(n)]))
    xy = [(float(p[0]), float(p[1])) for p in points]
    keep = []
    for c in cells:
        nodes = [int(v) for v in c[1:1 + {"5": 3, "9": 4}[c[0]]]]
        cx = sum(xy[n][0] for n in nodes) / len(nodes)
        cy = sum(xy[n][1] for n in nodes) / len(nodes)
        if x0 < cx < x1 and y0 < cy < y1:
            keep.append((c[0], nodes))
    used = sorted({n for _, nodes in keep for n in nodes})
    new = {n: i for i, n in enumerate(used)}
    edges = set()
    for _, nodes in keep:
        for i in range(len(nodes)):
            edges.add(frozenset((nodes[i], nodes[(i + 1) % len(nodes)])))
    out = [
        f"% {len(keep)} cells of {src.split('/')[-1]} with centroid in "
        f"({x0}, {x1}) x ({y0}, {y1}), cut by cli/tests/tools/su2_window.py",
        "NDIME= 2",
        f"NELEM= {len(keep)}",
    ]
    out += [f"{k} " + " ".join(str(new[n]) for n in nodes) + f" {i}" for i, (k, nodes) in enumerate(keep)]
    out.append(f"NPOIN= {len(used)}")
    out += [f"{points[n][0]} {points[n][1]} {i}" for i, n in enumerate(used)]
    kept_markers = []
    for name, elems in markers:
        e = [[int(v) for v in el[1:3]] for el in elems]
        e = [pair for pair in e if frozenset(pair) in edges]
        if e:
            kept_markers.append((name, e))
    out.append(f"NMARK= {len(kept_markers)}")
    for name, e in kept_markers:
        out += [f"MARKER_TAG= {name}", f"MARKER_ELEMS= {len(e)}"]
        out += [f"3 {new[a]} {new[b]}" for a, b in e]
    open(dst, "w").write("\n".join(out) + "\n")


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2], *map(float, sys.argv[3:7]))
