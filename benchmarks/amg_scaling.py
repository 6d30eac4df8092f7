"""Benchmark: AMG iterations against mesh size on the graded cap meshes, next to SuperLU (issue 19, item 5).

For each element and mesh.size, one symmetric bulk solve (plane-strain
neo-Hooke tangent at rest, base clamped, vertical surface loads; the system of
benchmarks/bulk_solvers.py) with CG to 1e-8 preconditioned by:
- pyamg's defaults (smoothed aggregation, coarsest level at most 500 block rows,
  V-cycle: capslide before issue 19);
- capslide's SETTINGS (evolution strength, energy-minimizing prolongation,
  coarsest level up to 2000 block rows solved by SuperLU), V-cycle;
- SETTINGS plus the exact solve on the DOFs of the poorly shaped cells
  around each V-cycle;
- the same around each W-cycle (what ``solver.linear: amg`` runs).
Printed: CG iterations, setup and solve seconds (median of repeats), the
memory of the hierarchy (matrix, prolongation and restriction entries of all
levels, plus the exact block's LU factors), and SuperLU's factor + solve time and memory (entries of L + U) for
comparison. Entries count 12 bytes (value and column index).

    OMP_NUM_THREADS=1 .venv/bin/python benchmarks/amg_scaling.py [--q1-sizes 8 4 1 0.25] [--q2-sizes 16 8 4 2]
        [--configs 0 1 2 3] [--repeats 1]
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np
import scipy.sparse.linalg as spla

from capslide.fem.assembly import BulkForm, Dirichlet, rigid_body_modes
from capslide.fem.mesh import H0_AT_SIZE_1, CapMeshSpec, cap_mesh
from capslide.fem.quality import poorly_shaped_dofs
from capslide.params import lame_plane_strain
from capslide.solvers.amg import CYCLE, PYAMG_DEFAULTS, SETTINGS, AMGSolver

# (column, pyamg options, exact block, cycle)
CONFIGS = (("pyamg defaults", PYAMG_DEFAULTS, False, "V"), ("SETTINGS", SETTINGS, False, "V"),
           ("SETTINGS + exact", SETTINGS, True, "V"), (f"SETTINGS + exact, {CYCLE}-cycle", SETTINGS, True, CYCLE))


def cap_system(element: str, size: float):
    mesh = cap_mesh(CapMeshSpec(R=47.1, H=10.0, h0=H0_AT_SIZE_1 * size, band_half_width=11.35, element=element))
    form = BulkForm(mesh, *lame_plane_strain(1.0, 0.4))
    _, data = form.residual_and_tangent_data(np.zeros(mesh.n_dofs))
    bc = Dirichlet.on_nodes(mesh.base, form.pattern)
    bc.apply(data)
    b = np.zeros(mesh.n_dofs)
    b[2 * mesh.surface_nodes + 1] = -1e-3
    b[bc.dofs] = 0.0
    return mesh, form.pattern.matrix(data), b


def hierarchy_mib(ml) -> float:
    entries = sum(lv.A.nnz + (lv.P.nnz + lv.R.nnz if hasattr(lv, "P") else 0) for lv in ml.levels)
    return 12 * entries / 2**20


def amg_row(mesh, A, b, options, exact, cycle, repeats):
    dofs = poorly_shaped_dofs(mesh.nodes, mesh.cells) if exact else None
    setups, solves, its = [], [], 0
    for _ in range(repeats):
        solver = AMGSolver(near_null_space=rigid_body_modes(mesh.nodes), exact_dofs=dofs, options=options,
                           cycle=cycle, symmetric=True)
        _, info = solver.solve(A, b)
        setups.append(info.setup_time)
        solves.append(info.solve_time)
        its = info.iterations
    mib = hierarchy_mib(solver._ml) + (12 * (solver._exact_lu.L.nnz + solver._exact_lu.U.nnz) / 2**20 if exact else 0)
    return its, statistics.median(setups), statistics.median(solves), mib, 0 if dofs is None else len(dofs)


def superlu_row(A, b, repeats):
    times = []
    for _ in range(repeats):
        t = time.perf_counter()
        lu = spla.splu(A.tocsc(), permc_spec="MMD_AT_PLUS_A")
        lu.solve(b)
        times.append(time.perf_counter() - t)
    return statistics.median(times), 12 * (lu.L.nnz + lu.U.nnz) / 2**20


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--q1-sizes", type=float, nargs="*", default=[8, 4, 1, 0.25])
    p.add_argument("--q2-sizes", type=float, nargs="*", default=[16, 8, 4, 2])
    p.add_argument("--repeats", type=int, default=1)
    p.add_argument("--configs", type=int, nargs="*", default=[0, 1, 2, 3],
                   help="which AMG columns to run (0 pyamg defaults, 1 SETTINGS, 2 SETTINGS + exact, 3 the same with "
                        f"a {CYCLE}-cycle); '-' for the rest")
    a = p.parse_args()
    print("| element | mesh.size | DOF | exact DOFs | " + " | ".join(f"{n}: its, setup, solve (s), MiB" for n, *_ in CONFIGS)
          + " | SuperLU factor+solve (s), MiB |")
    print("|" + "---|" * (5 + len(CONFIGS)))
    for element, sizes in (("Q1", a.q1_sizes), ("Q2", a.q2_sizes)):
        for size in sizes:
            mesh, A, b = cap_system(element, size)
            cells, n_exact = [], 0
            for k, (_, options, exact, cycle) in enumerate(CONFIGS):
                if k not in a.configs:
                    cells.append("-")
                    continue
                its, t_setup, t_solve, mib, n = amg_row(mesh, A, b, options, exact, cycle, a.repeats)
                n_exact = max(n_exact, n)
                cells.append(f"{its}, {t_setup:.2f}, {t_solve:.2f}, {mib:.0f}")
            t_lu, mib_lu = superlu_row(A, b, a.repeats)
            print(f"| {element} | {size:g} | {mesh.n_dofs:,} | {n_exact:,} | " + " | ".join(cells)
                  + f" | {t_lu:.2f}, {mib_lu:.0f} |", flush=True)


if __name__ == "__main__":
    main()
