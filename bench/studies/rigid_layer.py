"""Elasticity with a rigid wall layer against issue 28's done-when (docs/methods.md).

    python bench/studies/rigid_layer.py [--deform target/release/deform] [--out DIR] [--quick]

Generates the demo's viscous NACA 2412 mesh (`deform mesh naca --kind viscous`: first layer
1e-5 chord, boundary-layer aspect ratios near 2,000), pitches it nose down about the quarter
chord with `deform move --method elasticity --steps 10` in the variants listed in VARIANTS,
and measures every result with this script's own metrics (numpy, from the SU2 files, none of
the tool's code): inverted cells (signed area changed sign), folded quads (a corner's cross
product changed sign), the minimum deformed/undeformed area ratio and the largest change of
the first grid line's angle to the wall (at each wall node the non-wall neighbour along a
cell edge that is most normal to the wall in the undeformed mesh; the angle between the
wall normal and that edge, before and after). Then, for the winning variant, the first pitch
with an inverted or folded cell by bisection to 1°. Prints one JSON line per run.
"""

import argparse
import json
import pathlib
import subprocess
import tempfile

import numpy as np

ROOT = pathlib.Path(__file__).resolve().parents[2]

# (name, extra arguments of `deform move`)
VARIANTS = [
    ("elasticity nu 0.3 (SU2)", ["--poisson", "0.3"]),
    ("elasticity nu 0.45", ["--poisson", "0.45"]),
    ("rigid layer 1e-4, nu 0.3", ["--poisson", "0.3", "--rigid-layer", "1e-4"]),
    ("rigid layer 1e-4, nu 0.45", ["--poisson", "0.45", "--rigid-layer", "1e-4"]),
    ("rigid layer 2e-5, nu 0.45", ["--poisson", "0.45", "--rigid-layer", "2e-5"]),
    ("rigid layer 1e-3, nu 0.45", ["--poisson", "0.45", "--rigid-layer", "1e-3"]),
    ("rigid layer 1e-4, nu 0.49", ["--poisson", "0.49", "--rigid-layer", "1e-4"]),
]
WINNER = ["--poisson", "0.45", "--rigid-layer", "1e-4"]


def read_su2(path):
    """Points (n, 2), cells (lists of node ids) and marker nodes of a 2D SU2 file."""
    lines = [l.split("%")[0].strip() for l in open(path)]
    lines = [l for l in lines if l]
    i, cells, pts, markers = 0, [], None, {}
    while i < len(lines):
        l = lines[i]
        if l.startswith("NELEM="):
            ne = int(l.split("=")[1])
            for k in range(ne):
                f = lines[i + 1 + k].split()
                cells.append([int(x) for x in f[1:1 + {5: 3, 9: 4}[int(f[0])]]])
            i += ne + 1
        elif l.startswith("NPOIN="):
            npn = int(l.split("=")[1].split()[0])
            pts = np.array([[float(x) for x in lines[i + 1 + k].split()[:2]] for k in range(npn)])
            i += npn + 1
        elif l.startswith("MARKER_TAG="):
            tag = l.split("=")[1].strip()
            ne = int(lines[i + 1].split("=")[1])
            markers[tag] = [[int(x) for x in lines[i + 2 + k].split()[1:]] for k in range(ne)]
            i += ne + 2
        else:
            i += 1
    return pts, cells, markers


def shoelace(q):
    return 0.5 * np.sum(q[:, 0] * np.roll(q[:, 1], -1) - np.roll(q[:, 0], -1) * q[:, 1])


def corner_crosses(p, c):
    q = p[c]
    a, b = np.roll(q, 1, 0) - q, np.roll(q, -1, 0) - q
    return b[:, 0] * a[:, 1] - b[:, 1] * a[:, 0]


def wall_angles(p, lines, first):
    """Angle from the wall normal to the first grid line at each wall node."""
    normal = {}
    for a, b in lines:
        d = p[b] - p[a]
        for v in (a, b):
            normal[v] = normal.get(v, 0) + np.array([d[1], -d[0]])
    out = {}
    for w, j in first.items():
        n, e = normal[w], p[j] - p[w]
        out[w] = np.arctan2(n[0] * e[1] - n[1] * e[0], n @ e)
    return out


def metrics(p0, p1, cells, lines):
    ratio = np.array([shoelace(p1[c]) / shoelace(p0[c]) for c in cells])
    a0 = np.array([shoelace(p0[c]) for c in cells])
    folded = sum(1 for c, s in zip(cells, np.sign(a0))
                 if np.min(corner_crosses(p1, c) * s) <= 0)
    wall = {v for l in lines for v in l}
    nbrs = {}
    for c in cells:
        for k in range(len(c)):
            a, b = c[k], c[(k + 1) % len(c)]
            nbrs.setdefault(a, set()).add(b)
            nbrs.setdefault(b, set()).add(a)
    first = {}
    normals = {}
    for a, b in lines:
        d = p0[b] - p0[a]
        for v in (a, b):
            normals[v] = normals.get(v, 0) + np.array([d[1], -d[0]])
    for w in wall:
        n = normals[w] / np.linalg.norm(normals[w])
        cand = sorted(nbrs[w] - wall)
        score = [abs(n @ (p0[j] - p0[w])) / np.linalg.norm(p0[j] - p0[w]) for j in cand]
        first[w] = cand[int(np.argmax(score))]
    t0, t1 = wall_angles(p0, lines, first), wall_angles(p1, lines, first)
    turn = max(abs((t1[w] - t0[w] + np.pi) % (2 * np.pi) - np.pi) for w in first)
    return {"inverted": int((ratio <= 0).sum()), "folded": folded,
            "min_area_ratio": float(ratio.min()), "wall_angle_change_deg": float(np.degrees(turn))}


def move(deform, mesh, angle, extra, out):
    cmd = [deform, "--json", "move", str(mesh), "--marker", "airfoil", "--center", "0.25,0",
           "--rotate", f"-{angle}", "--method", "elasticity", "--steps", "10", "--out", str(out),
           "--allow-folds", "--allow-unconverged"]
    r = subprocess.run(cmd + extra, capture_output=True, text=True)
    if r.returncode != 0:
        return {"error": r.stderr.strip()}
    rep = json.loads(r.stdout)
    return {"seconds": rep["seconds"], "iterations": rep["iterations"]}


def measure(deform, mesh, ref, angle, extra, out):
    r = move(deform, mesh, angle, extra, out)
    if "error" not in r:
        p1, _, _ = read_su2(out)
        r.update(metrics(ref[0], p1, ref[1], ref[2]))
    return r


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--deform", default=str(ROOT / "target/release/deform"))
    ap.add_argument("--out", default=None)
    ap.add_argument("--quick", action="store_true", help="the winner at 50° only")
    args = ap.parse_args()
    work = pathlib.Path(args.out or tempfile.mkdtemp())
    work.mkdir(parents=True, exist_ok=True)
    mesh, out = work / "viscous.su2", work / "moved.su2"
    subprocess.run([args.deform, "mesh", "naca", "--kind", "viscous", "--out", str(mesh)],
                   check=True, capture_output=True)
    p0, cells, markers = read_su2(mesh)
    ref = (p0, cells, markers["airfoil"])
    runs = [("winner", WINNER, 50)] if args.quick else (
        [(name, extra, 50) for name, extra in VARIANTS]
        + [("winner", WINNER, a) for a in (10, 25)])
    for name, extra, angle in runs:
        r = measure(args.deform, mesh, ref, angle, extra, out)
        print(json.dumps({"variant": name, "pitch": angle, **r}), flush=True)
    if args.quick:
        return
    lo, hi = 50.0, 180.0
    r = measure(args.deform, mesh, ref, hi, WINNER, out)
    print(json.dumps({"variant": "winner", "pitch": hi, **r}), flush=True)
    if r.get("inverted", 1) + r.get("folded", 1) == 0:
        return
    while hi - lo > 1.0:
        mid = 0.5 * (lo + hi)
        r = measure(args.deform, mesh, ref, mid, WINNER, out)
        print(json.dumps({"variant": "winner (bisection)", "pitch": mid, **r}), flush=True)
        ok = r.get("inverted", 1) + r.get("folded", 1) == 0
        lo, hi = (mid, hi) if ok else (lo, mid)
    print(json.dumps({"variant": "winner", "last_valid_pitch": lo, "first_bad_pitch": hi}))


if __name__ == "__main__":
    main()
