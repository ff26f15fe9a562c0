"""Yang & Özgen's angle-spring claim, measured (issue 28 item 5; docs/methods.md).

    python bench/studies/angle_springs.py [--deform target/release/deform] [--out DIR]

The paper (../shared/papers/yang-ozgen-spring-analogy-comparison.txt, section 3) reports that
angle inclusion keeps a NACA 2412 mesh valid pitched 50° (inviscid) and 25° (viscous), judged
from pictures. This script generates NACA 2412 meshes with `deform mesh naca` (the inviscid
one at three resolutions, the viscous one with first layers of 1e-3, 1e-4 and 1e-5 chord),
pitches them about the quarter chord with `deform move` (angle springs, converged, the
paper's stiffness 1/L; also with 10 increments and with the tool's other stiffnesses) and
prints, for each: inverted/folded cells at 10°, 25°, 50°, the first angle (bisection to
0.5°) with an inverted cell and with a folded one, and where the first inverted cells lie
(distance to the trailing edge). Cells are counted by the tool's move report; their places by
numpy from the SU2 files (signed areas before and after). Needs numpy and meshio.
"""

import argparse
import json
import logging
import pathlib
import subprocess
import tempfile

import meshio
import numpy as np

ROOT = pathlib.Path(__file__).resolve().parents[2]
logging.disable(logging.WARNING)  # meshio: "tags of string type will be replaced"


def move(deform, mesh, angle, extra, out):
    cmd = [deform, "--json", "move", str(mesh), "--marker", "airfoil", "--center", "0.25,0",
           "--rotate", f"-{angle}", "--out", str(out), "--allow-folds", "--allow-unconverged"]
    r = subprocess.run(cmd + extra, capture_output=True, text=True)
    return json.loads(r.stdout) if r.returncode == 0 else None


def first_bad(deform, mesh, extra, key, out, hi=90.0):
    """The largest pitch (0.5° steps of a bisection) with no cell counted under `key`."""
    lo = 0.0
    while hi - lo > 0.5:
        mid = 0.5 * (lo + hi)
        d = move(deform, mesh, mid, extra, out)
        lo, hi = (mid, hi) if d is not None and d[key] == 0 else (lo, mid)
    return lo


def signed_areas(points, cells):
    x = points[cells][:, :, :2]
    n = cells.shape[1]
    return 0.5 * sum(x[:, i, 0] * x[:, (i + 1) % n, 1] - x[:, (i + 1) % n, 0] * x[:, i, 1]
                     for i in range(n))


def where_inverted(mesh, moved):
    """Distances of the inverted cells' centres to the trailing edge (1, 0)."""
    a, b = meshio.read(mesh), meshio.read(moved)
    d = []
    for ca in a.cells:
        bad = np.sign(signed_areas(a.points, ca.data)) != np.sign(signed_areas(b.points, ca.data))
        c = a.points[ca.data[bad]][:, :, :2].mean(axis=1)
        d.extend(np.hypot(c[:, 0] - 1.0, c[:, 1]))
    return np.array(d)


def max_aspect(mesh):
    m = meshio.read(mesh)
    quads = [c.data for c in m.cells if c.type == "quad"]
    if not quads:
        return None
    x = m.points[np.concatenate(quads)][:, :, :2]
    e1 = np.linalg.norm(x[:, 1] - x[:, 0], axis=1)
    e2 = np.linalg.norm(x[:, 2] - x[:, 1], axis=1)
    return float((np.maximum(e1, e2) / np.minimum(e1, e2)).max())


MESHES = [
    ("inviscid, 64 surface points", ["--kind", "inviscid", "--surface-points", "64",
                                     "--radial-points", "40"]),
    ("inviscid, 128 surface points", ["--kind", "inviscid", "--surface-points", "128",
                                      "--radial-points", "40"]),
    ("inviscid (the demo's)", ["--kind", "inviscid"]),
    ("viscous, first layer 1e-3", ["--kind", "viscous", "--first-layer", "1e-3"]),
    ("viscous, first layer 1e-4", ["--kind", "viscous", "--first-layer", "1e-4"]),
    ("viscous, first layer 1e-5 (the demo's)", ["--kind", "viscous"]),
]
VARIANTS = [
    ("angle-cg, stiffness 1/L (the paper's)", ["--method", "angle-cg"]),
    ("same, 10 increments", ["--method", "angle-cg", "--steps", "10"]),
    ("angle-direct (Gauss-Seidel) stopped after 500 sweeps", ["--method", "angle-direct",
                                                              "--solver", "gs", "--max-iter",
                                                              "500"]),
    ("angle-cg, wall-distance stiffness", ["--method", "angle-cg", "--stiffness",
                                           "wall-distance"]),
    ("angle-cg, inverse-volume stiffness", ["--method", "angle-cg", "--stiffness",
                                            "inverse-volume"]),
]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--deform", default=str(ROOT / "target" / "release" / "deform"))
    args = ap.parse_args()
    print("| mesh | max quad aspect ratio | method | inverted/folded at 10°, 25°, 50° "
          "| first inverted | first folded | first inverted cells: distance to the TE |")
    print("|---|---:|---|---|---:|---:|---|")
    with tempfile.TemporaryDirectory() as tmp:
        out = pathlib.Path(tmp) / "moved.su2"
        for name, gen in MESHES:
            mesh = pathlib.Path(tmp) / "mesh.su2"
            subprocess.run([args.deform, "mesh", "naca", *gen, "--out", str(mesh)], check=True,
                           capture_output=True)
            ar = max_aspect(mesh)
            for label, extra in VARIANTS:
                counts = []
                for angle in (10, 25, 50):
                    d = move(args.deform, mesh, angle, extra, out)
                    counts.append("—" if d is None else
                                  f"{d['inverted_cells']}/{d['folded_cells']}")
                inv = first_bad(args.deform, mesh, extra, "inverted_cells", out)
                fold = first_bad(args.deform, mesh, extra, "folded_cells", out)
                move(args.deform, mesh, inv + 0.5, extra, out)
                dist = where_inverted(mesh, out)
                place = (f"{dist.size} cells, {dist.min():.2g}–{dist.max():.2g} chord"
                         if dist.size else "—")
                print(f"| {name} | {'—' if ar is None else f'{ar:.0f}'} | {label} | "
                      f"{', '.join(counts)} | {inv:.1f}° | {fold:.1f}° | {place} |", flush=True)


if __name__ == "__main__":
    main()
