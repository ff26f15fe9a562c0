"""Independent FE elasticity with a rigid wall layer, for docs/methods.md (run by hand; no test
calls it): scikit-fem assembly and scipy direct solves (ref_increments.py's), E = (1/V)^power
on each increment's mesh, the nodes within `layer` of a wall node moved by the rotation along
its arc, the rest solved, ten (or `steps`) increments. Prints the minimum area ratio.

python ref_rigid_layer.py mesh.su2 degrees steps layer power nu
"""
import sys, json, time
import numpy as np
sys.path.insert(0, __import__("os").path.dirname(__import__("os").path.abspath(__file__)))
from ref_increments import read_su2, signed_area, assemble, rotate
from scipy.sparse.linalg import spsolve
from scipy.spatial import cKDTree
from skfem import condense

def run(path, degrees, steps, layer, nu=0.3, power=1.0, center=(0.25, 0.0)):
    p0, cells, markers = read_su2(path)
    center = np.array(center)
    tris = np.array([c for c in cells if len(c) == 3], dtype=np.int64).reshape(-1, 3)
    quads = np.array([c for c in cells if len(c) == 4], dtype=np.int64).reshape(-1, 4)
    order = [c for c in cells if len(c) == 3] + [c for c in cells if len(c) == 4]
    a0 = signed_area(p0, order)
    wall = markers["airfoil"]
    dist, _ = cKDTree(p0[wall]).query(p0)
    rigid = np.where(dist <= layer)[0]
    fixed = np.union1d(rigid, markers["farfield"])
    p = p0.copy()
    for s in range(1, steps + 1):
        area = np.abs(signed_area(p, order))
        e = (area.max() / area) ** power
        k, dofs = assemble(p, tris, quads, e[:len(tris)], e[len(tris):], nu)
        n = len(p)
        x = np.zeros(2 * n)
        target = rotate(p0[rigid], center, degrees * s / steps)
        du = target - p[rigid]
        for c in range(2):
            x[dofs[c, rigid]] = du[:, c]
        dfix = dofs[:, fixed].reshape(-1)
        a, b, _, interior = condense(k, np.zeros(2 * n), x=x, D=dfix)
        x[interior] = spsolve(a.tocsc(), b)
        p = p + np.stack([x[dofs[0]], x[dofs[1]]], 1)
        p[rigid] = target
    ratio = signed_area(p, order) / a0
    return dict(layer=layer, steps=steps, power=power, nrigid=len(rigid), min_ratio=float(ratio.min()), inverted=int((ratio <= 0).sum())), p

if __name__ == "__main__":
    t = time.time()
    r, p = run(sys.argv[1], float(sys.argv[2]), int(sys.argv[3]), float(sys.argv[4]), power=float(sys.argv[5]), nu=float(sys.argv[6])); r["nu"]=float(sys.argv[6])
    r["s"] = time.time() - t
    print(json.dumps(r))
