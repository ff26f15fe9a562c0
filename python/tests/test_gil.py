"""The solve runs with the GIL released: a Python thread keeps running during it."""

import threading
import time

import numpy as np

import deform_kernel as dk
from meshes import holed_square


def test_python_threads_run_during_a_solve():
    pts, tris, hole, outer, _, _ = holed_square(n=41, half=2.0, hole=0.5)
    cells = dk.normalise_cells([("triangle", tris)], len(pts))
    args = (pts, cells, hole, dk.Rotation(5.0), outer, "spring", "jacobi")
    span = {}

    def solve(iterations):
        span["start"] = time.perf_counter()
        dk.deform(*args, tol=1e-300, max_iter=iterations, allow_unconverged=True)
        span["end"] = time.perf_counter()

    # Enough Jacobi sweeps (which never reach tol = 1e-300) for a solve of 0.3 s or more,
    # whether the extension was built with optimisations or not.
    iterations = 50
    while True:
        solve(iterations)
        if span["end"] - span["start"] > 0.3 or iterations > 10**6:
            break
        iterations *= 4

    worker = threading.Thread(target=solve, args=(iterations,))
    ticks = []
    worker.start()
    while worker.is_alive():
        ticks.append(time.perf_counter())
        time.sleep(0.001)
    worker.join()
    duration = span["end"] - span["start"]
    inside = np.array([t for t in ticks if span["start"] < t < span["end"]])
    assert duration > 0.2, f"the solve took only {duration:.3f} s: make the mesh larger"
    # With the GIL held the main thread would stop for the whole native call.
    gaps = np.diff(np.concatenate([[span["start"]], inside, [span["end"]]]))
    assert gaps.max() < 0.5 * duration, (gaps.max(), duration)
