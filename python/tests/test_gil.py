"""Long work runs with the GIL released: a Python thread keeps running during it."""

import threading
import time

import numpy as np
import pytest

import deform_kernel as dk
from meshes import holed_square


def deform_call():
    pts, tris, hole, outer, _, _ = holed_square(n=41, half=2.0, hole=0.5)
    cells = dk.normalise_cells([("triangle", tris)], len(pts))
    args = (pts, cells, hole, dk.Rotation(5.0), outer, "spring", "jacobi")
    return lambda iterations: dk.deform(*args, tol=1e-300, max_iter=iterations,
                                        allow_unconverged=True)


def plan_call():
    pts, tris, hole, outer, _, _ = holed_square(n=41, half=2.0, hole=0.5)
    boundary = np.concatenate([hole, outer])
    target = pts[boundary] + 0.01
    plans = {}

    def step(iterations):
        if iterations not in plans:  # built outside the timed step
            plans.clear()
            plans[iterations] = dk.Plan(pts, [("triangle", tris)], boundary, solver="jacobi",
                                        tol=1e-300, max_iter=iterations)
        plans[iterations].step(target, start="cold")
    return step


def timed(work, iterations, span):
    span["start"] = time.perf_counter()
    work(iterations)
    span["end"] = time.perf_counter()


@pytest.mark.parametrize("make", [deform_call, plan_call], ids=["deform", "plan-step"])
def test_python_threads_run_during_a_solve(make):
    work, span = make(), {}
    # Enough Jacobi sweeps (which never reach tol = 1e-300) for a solve of 0.3 s or more,
    # whether the extension was built with optimisations or not.
    iterations = 50
    while True:
        work(iterations)  # a plan is built here, so the timed call below only steps
        timed(work, iterations, span)
        if span["end"] - span["start"] > 0.3 or iterations > 10**6:
            break
        iterations *= 4

    worker = threading.Thread(target=timed, args=(work, iterations, span))
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
