"""The levers on the cost of the `experiment` scene's linear solves (issue 40, item 6): CG iterations and time of one
AMG solve of the bulk tangent at rest, against Poisson's ratio, the modelled height and the mesh size.

The tangent of the mixed bulk (H1/P0) at rest with the scene's boundary conditions (base clamped, plane of symmetry)
and a downward load on the top nodes within 100 um of the axis, solved by AMG (solver.linear: amg, 3D's default;
the scene itself solves with PARDISO, benchmarks/experiment_solvers.py: pyamg smoothed aggregation on BSR 3x3
blocks with the rigid-body modes, CG to its tolerance). One BLAS thread;
setup + solve times are the median of --repeats runs, each with a fresh hierarchy.

    OMP_NUM_THREADS=1 .venv/bin/python benchmarks/experiment_levers.py
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np

from capslide.config import load_config, scene_path
from capslide.model.build import build_model
from capslide.params import Parameters

VARIANTS = [
    ("scene (nu 0.49, H 1000 um, h0 40 um)", []),
    ("nu = 0.499", ["material.nu=0.499"]),
    ("nu = 0.45", ["material.nu=0.45"]),
    ("H = 2000 um (the real cap's height)", ["geometry.H=2000"]),
    ("h0 = 28 um (fast preset)", ["preset=fast"]),
]


def one_solve(sets: list[str], repeats: int) -> tuple[int, int, float]:
    """(DOF, CG iterations, median seconds of setup + solve)."""
    settings = ["preset=coarse", *sets, "solver.linear=amg"]  # the coarse bulk, as docs/experiment3d.md's table
    model = build_model(Parameters.from_config(load_config([scene_path("experiment")], settings)))
    _, data = model.bulk.residual_and_tangent_data(np.zeros(model.n_dofs), None)
    b = np.zeros(model.n_dofs)
    top = np.unique(model.mesh.surface_segments)
    b[3 * top[np.linalg.norm(model.mesh.nodes[top, :2], axis=1) < 100.0] + 2] = -1.0
    model.bc.apply(data, b)
    K = model.bulk.pattern.matrix(data)
    times, its = [], 0
    for _ in range(repeats):
        model.solver.invalidate()
        t = time.perf_counter()
        _, info = model.solver.solve(K, b)
        times.append(time.perf_counter() - t)
        its = info.iterations
    return model.n_dofs, its, statistics.median(times)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=3)
    args = ap.parse_args()
    print("| variant | DOF | CG iterations | setup + solve (s) |")
    print("|---|---|---|---|")
    for name, sets in VARIANTS:
        dofs, its, seconds = one_solve(sets, args.repeats)
        print(f"| {name} | {dofs:,} | {its} | {seconds:.2f} |", flush=True)


if __name__ == "__main__":
    main()
