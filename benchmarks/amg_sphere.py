"""pyamg on the graded spherical-cap meshes (issue 39): CG iterations, setup and solve time against DOF.

The tangent of the neo-Hooke bulk at rest (nu = 0.4, and 0.49 with --nu), on the H1 half model of the `sphere`
scene's cap (R = 47.1 L0, H = 10 L0, band radius 9 L0) at several surface cell sizes h0: the base clamped, the
symmetry plane's y-DOFs fixed, a downward load on the top nodes within 3 L0 of the axis. Smoothed aggregation on
the BSR 3x3 matrix with the six rigid-body modes as near-null space, as the preconditioner of CG to 1e-8, with
capslide's options (solvers.amg.SETTINGS, W-cycle) and with pyamg's defaults (V-cycle) with a direct coarse solve.
Prints one row per mesh and option set; times are single runs (setup and one solve), one BLAS thread.

    OMP_NUM_THREADS=1 .venv/bin/python benchmarks/amg_sphere.py --h0 0.6 0.3 0.15 0.1
"""

from __future__ import annotations

import argparse
import resource
import time

import numpy as np

from capslide.fem.assembly import BulkForm, Dirichlet, rigid_body_modes
from capslide.fem.hex_mesh import SphereCapSpec, sphere_cap_mesh
from capslide.solvers.amg import SETTINGS, AMGSolver

OPTION_SETS = {"capslide (evolution, energy, W)": (dict(SETTINGS), "W"),
               "pyamg defaults + splu coarse (V)": ({"max_coarse": 2000, "coarse_solver": "splu"}, "V")}


def system(h0: float, nu: float, max_aspect: float | None = None):
    mesh = sphere_cap_mesh(SphereCapSpec(R=47.1, H=10.0, h0=h0, band_radius=9.0, max_layer_aspect=max_aspect))
    lam, mu = nu / ((1 + nu) * (1 - 2 * nu)), 1.0 / (2 * (1 + nu))
    form = BulkForm(mesh, lam, mu)
    _, data = form.residual_and_tangent_data(np.zeros(mesh.n_dofs))
    fixed = np.union1d(np.concatenate([3 * mesh.base + i for i in range(3)]), 3 * mesh.symmetry + 1)
    bc = Dirichlet.on_dofs(fixed, form.pattern)
    b = np.zeros(mesh.n_dofs)
    top = np.unique(mesh.surface_segments)
    near = top[np.linalg.norm(mesh.nodes[top, :2], axis=1) < 3.0]
    b[3 * near + 2] = -1.0
    bc.apply(data, b)
    return mesh, form.pattern.matrix(data), b


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--h0", type=float, nargs="+", default=[0.6, 0.3, 0.15, 0.1])
    ap.add_argument("--nu", type=float, default=0.4)
    ap.add_argument("--max-aspect", type=float, default=None, help="cap the layers under the band at this many h0")
    ap.add_argument("--options", nargs="+", default=list(OPTION_SETS), choices=list(OPTION_SETS))
    args = ap.parse_args()
    print(f"nu = {args.nu}, layers under the band at most {args.max_aspect} h0 thick")
    print("| h0 (L0) | cells | DOF | options | CG iterations | setup (s) | solve (s) | peak RSS (GB) |")
    print("|---|---|---|---|---|---|---|---|")
    for h0 in args.h0:
        mesh, A, b = system(h0, args.nu, args.max_aspect)
        for name in args.options:
            options, cycle = OPTION_SETS[name]
            solver = AMGSolver(near_null_space=rigid_body_modes(mesh.nodes), options=dict(options), cycle=cycle,
                               block_size=3, rtol=1e-8, maxiter=1000, symmetric=True)
            t = time.perf_counter()
            _, info = solver.solve(A, b)
            rss = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 2**20
            print(f"| {h0:g} | {mesh.n_cells} | {mesh.n_dofs} | {name} | {info.iterations} | {info.setup_time:.1f} "
                  f"| {info.solve_time:.1f} | {rss:.1f} |", flush=True)
            del solver, t


if __name__ == "__main__":
    main()
