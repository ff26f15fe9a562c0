"""The peers of `cargo xtask bench`, timed on the inputs the kernel side wrote.

    python peers.py DIR

DIR holds what `deform-bench --out DIR` wrote (raw little-endian arrays and kernel.txt). This
script solves the same problems with what a user would otherwise pick, checks that the answers
agree with the kernel's, and writes DIR/peers.txt (`name value` lines):

- graph Taubin (uniform umbrella weights, 20 passes): numpy/scipy CSR, and trimesh's
  filter_taubin when it is installed;
- structured Taubin (Alter's rule: a point averages its neighbours in the directions where it
  has both, so faces drop their normal direction; 20 passes): scipy.ndimage on the interior plus
  the same rule, one dimension lower, on every face;
- the spring system (free-node CSR matrix, both displacement components to relative residual
  1e-8): pyamg smoothed-aggregation CG (setup + solve) and scipy's CG with a Jacobi
  preconditioner.

Times are medians of several runs after a warm-up. Speed is compared, never asserted.
"""

import os
import sys
import time

import numpy as np
import scipy
import scipy.ndimage as ndimage
import scipy.sparse as sp
import scipy.sparse.linalg as spla

LAMBDA, MU = 0.330, -0.334
ITERATIONS = 10  # lambda|mu iterations = 20 passes


def median_time(f, reps):
    f()
    ts = []
    for _ in range(reps):
        t = time.perf_counter()
        f()
        ts.append(time.perf_counter() - t)
    ts.sort()
    return ts[len(ts) // 2]


def load(d, name, dtype):
    return np.fromfile(os.path.join(d, name), dtype=dtype)


def read_kernel(d):
    out = {}
    with open(os.path.join(d, "kernel.txt")) as f:
        for line in f:
            k, v = line.split(maxsplit=1)
            out[k] = v.strip()
    return out


class Figures:
    def __init__(self):
        self.lines = []

    def put(self, name, value):
        print(f"  {name} = {value}", flush=True)
        self.lines.append(f"{name} {value}")


def graph_taubin(d, fig, reps):
    offsets = load(d, "graph_offsets.u32", "<u4").astype(np.int64)
    targets = load(d, "graph_targets.u32", "<u4").astype(np.int64)
    points = load(d, "graph_points.f64", "<f8").reshape(-1, 3)
    expect = load(d, "graph_result.f64", "<f8").reshape(-1, 3)
    n = len(offsets) - 1
    # The umbrella operator D⁻¹A as one CSR matrix (weights 1/degree), built once.
    weights = np.repeat(1.0 / np.diff(offsets).astype(np.float64), np.diff(offsets))
    umbrella = sp.csr_matrix((weights, targets, offsets), shape=(n, n))
    print(f"graph Taubin: {n} vertices (numpy/scipy CSR)", flush=True)

    def run():
        x = points.copy()
        for _ in range(ITERATIONS):
            x += LAMBDA * (umbrella @ x - x)
            x += MU * (umbrella @ x - x)
        return x

    t = median_time(run, reps)
    fig.put("graph_scipy_ns_per_vertex_pass", t * 1e9 / (2 * ITERATIONS * n))
    fig.put("graph_scipy_max_difference", f"{np.abs(run() - expect).max():e}")
    try:
        import trimesh
        import trimesh.smoothing
    except ImportError:
        fig.put("graph_trimesh_ns_per_vertex_pass", "not-installed")
        return
    faces = load(d, "graph_triangles.u32", "<u4").reshape(-1, 3).astype(np.int64)
    mesh = trimesh.Trimesh(vertices=points.copy(), faces=faces, process=False)
    operator = trimesh.smoothing.laplacian_calculation(mesh, equal_weight=True)

    def run_trimesh():
        m = trimesh.Trimesh(vertices=points.copy(), faces=faces, process=False)
        trimesh.smoothing.filter_taubin(
            m, lamb=LAMBDA, nu=-MU, iterations=2 * ITERATIONS, laplacian_operator=operator
        )
        return np.asarray(m.vertices)

    t = median_time(run_trimesh, reps)
    fig.put("graph_trimesh_ns_per_vertex_pass", t * 1e9 / (2 * ITERATIONS * n))
    fig.put("graph_trimesh_max_difference", f"{np.abs(run_trimesh() - expect).max():e}")


def alter_step(x, weight):
    """One pass of Alter's rule on an n-dimensional array: interior points average their 2·ndim
    neighbours (scipy.ndimage), each face applies the same rule one dimension lower (its normal
    direction is dropped), points of a 1D line's ends keep their values."""
    if x.shape[0] < 1:
        return x.copy()
    if x.ndim == 1:
        y = x.copy()
        if len(x) > 2:
            y[1:-1] = x[1:-1] + weight * ((x[:-2] + x[2:]) / 2.0 - x[1:-1])
        return y
    kernel = np.zeros((3,) * x.ndim)
    centre = (1,) * x.ndim
    for a in range(x.ndim):
        for s in (0, 2):
            idx = list(centre)
            idx[a] = s
            kernel[tuple(idx)] = 1.0 / (2 * x.ndim)
    avg = ndimage.correlate(x, kernel, mode="nearest")
    y = x + weight * (avg - x)
    for a in range(x.ndim):
        for end in (0, -1):
            sl = [slice(None)] * x.ndim
            sl[a] = end
            y[tuple(sl)] = alter_step(x[tuple(sl)], weight)
    return y


def structured_taubin(d, fig, reps):
    dims = [int(v) for v in open(os.path.join(d, "structured.dims")).read().split()]
    ni, nj, nk = dims
    field = load(d, "structured_field.f64", "<f8").reshape(nk, nj, ni)
    expect = load(d, "structured_result.f64", "<f8").reshape(nk, nj, ni)
    print(f"structured Taubin: {ni}x{nj}x{nk} (scipy.ndimage)", flush=True)

    def run():
        x = field
        for _ in range(ITERATIONS):
            x = alter_step(x, LAMBDA)
            x = alter_step(x, MU)
        return x

    t = median_time(run, reps)
    fig.put("structured_ndimage_ns_per_point_pass", t * 1e9 / (2 * ITERATIONS * field.size))
    fig.put("structured_ndimage_max_difference", f"{np.abs(run() - expect).max():e}")


def spring(d, fig, reps):
    import pyamg

    indptr = load(d, "spring_indptr.u32", "<u4").astype(np.int64)
    indices = load(d, "spring_indices.u32", "<u4").astype(np.int64)
    data = load(d, "spring_data.f64", "<f8")
    rhs = load(d, "spring_rhs.f64", "<f8").reshape(-1, 2)
    kernel_x = load(d, "spring_solution.f64", "<f8").reshape(-1, 2)
    m = len(indptr) - 1
    a = sp.csr_matrix((data, indices, indptr), shape=(m, m))
    print(f"spring solve: {m} free unknowns per component (pyamg {pyamg.__version__})", flush=True)
    setup = median_time(lambda: pyamg.smoothed_aggregation_solver(a), min(reps, 3))
    ml = pyamg.smoothed_aggregation_solver(a)
    its = []

    def solve():
        its.clear()
        xs = []
        for c in range(2):
            residuals = []
            x = ml.solve(rhs[:, c], tol=1e-8, accel="cg", maxiter=1000, residuals=residuals)
            its.append(len(residuals) - 1)
            xs.append(x)
        return np.stack(xs, axis=1)

    t = median_time(solve, min(reps, 3))
    x = solve()
    fig.put("spring_pyamg_setup_s", setup)
    fig.put("spring_pyamg_solve_s", t)
    fig.put("spring_pyamg_iterations", f"{its[0]},{its[1]}")
    fig.put("spring_pyamg_levels", ",".join(str(l.A.shape[0]) for l in ml.levels))
    scale = np.abs(x).max()
    fig.put("spring_pyamg_max_relative_difference", f"{np.abs(x - kernel_x).max() / scale:e}")

    diag = a.diagonal()
    jacobi = spla.LinearOperator(a.shape, matvec=lambda v: v / diag)

    def cg():
        out = []
        for c in range(2):
            count = [0]

            def cb(_):
                count[0] += 1

            x, info = spla.cg(a, rhs[:, c], rtol=1e-8, maxiter=100000, M=jacobi, callback=cb)
            out.append(count[0])
        return out

    t0 = time.perf_counter()
    n_its = cg()
    fig.put("spring_scipy_cg_jacobi_s", time.perf_counter() - t0)
    fig.put("spring_scipy_cg_jacobi_iterations", f"{n_its[0]},{n_its[1]}")


def main():
    d = sys.argv[1]
    kernel = read_kernel(d)
    reps = 3 if kernel.get("quick") == "true" else 5
    fig = Figures()
    fig.put("numpy_version", np.__version__)
    fig.put("scipy_version", scipy.__version__)
    if "graph_vertices" in kernel:
        graph_taubin(d, fig, reps)
    if "structured_points" in kernel:
        structured_taubin(d, fig, reps)
    if "spring_nodes" in kernel:
        spring(d, fig, reps)
    with open(os.path.join(d, "peers.txt"), "w") as f:
        f.write("\n".join(fig.lines) + "\n")


if __name__ == "__main__":
    main()
