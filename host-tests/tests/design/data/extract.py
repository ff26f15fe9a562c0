"""Extracts one FFD box and the coordinates of its surface points from a public SU2 mesh.

Usage: python3 extract.py MESH.su2 EVERY > OUT.txt   (keeps every EVERY-th surface point)

Output (whitespace separated): "dim l m n", then one line per control point "i j k x y z"
(FFD_CONTROL_POINTS as stored), then "surface count", then per kept surface point
"node u v w x y [z]" (FFD_SURFACE_POINTS' parametric coordinates followed by the mesh
coordinates of that node, copied as text, unrounded).
"""
import sys


def main():
    path, every = sys.argv[1], int(sys.argv[2])
    lines = open(path).read().splitlines()
    dim = int(lines[0].split("=")[1])
    npoin_at = next(i for i, l in enumerate(lines) if l.startswith("NPOIN="))
    npoin = int(lines[npoin_at].split("=")[1].split()[0])
    coords = [l.split()[:dim] for l in lines[npoin_at + 1 : npoin_at + 1 + npoin]]
    get = lambda key: next(i for i, l in enumerate(lines) if l.startswith(key))
    deg = [int(lines[get(k)].split("=")[1]) for k in ("FFD_DEGREE_I", "FFD_DEGREE_J")]
    deg.append(int(lines[get("FFD_DEGREE_K")].split("=")[1]) if dim == 3 else 1)
    cp_at = get("FFD_CONTROL_POINTS=")
    ncp = int(lines[cp_at].split("=")[1])
    sp_at = get("FFD_SURFACE_POINTS=")
    nsp = int(lines[sp_at].split("=")[1])
    out = ["%d %d %d %d" % (dim, *deg)]
    out += [lines[cp_at + 1 + c].strip() for c in range(ncp)]
    kept = [lines[sp_at + 1 + s].split() for s in range(0, nsp, every)]
    out.append("surface %d" % len(kept))
    for f in kept:
        node = int(f[1])
        out.append(" ".join([f[1]] + f[2:5] + coords[node]))
    print("\n".join(out))


if __name__ == "__main__":
    main()
