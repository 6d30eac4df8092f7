"""PARDISO's factors in single against double precision (solver.factor_precision) on the `experiment` scene.

1. The bulk tangent at rest (H1/P0, its boundary conditions) at the presets given: a numeric refactorization and
   a solve (medians of --repeats and 5 x --repeats runs), a solve's relative residual, and the GMRES iterations
   to 1e-8 with fresh factors.
2. With --checkpoint: the study's case resumed from a copy of its checkpoint to --ubar um with each precision in
   turn (the same machine load for both, so the ratio is the measurement): wall time, steps, Newton and Krylov
   iterations, factorizations, and Ft and area at the end. The double run repeats the study's own steps.

    OMP_NUM_THREADS=1 .venv/bin/python benchmarks/factor_precision.py --presets coarse annulus
    cp -r results/paper/experiment3d/cases/.A0.270.nc.checkpoint ck
    OMP_NUM_THREADS=1 .venv/bin/python benchmarks/factor_precision.py --presets --checkpoint ck --case A0.270 \\
        --ubar 20
"""

from __future__ import annotations

import argparse
import time

import numpy as np
import scipy.sparse.linalg as spla
from lu_refactor_balance import measure, scene_tangent
from slide_newton_diagnosis import study_checkpoint

from capslide.config import load_config, scene_path
from capslide.driver.case import run_case
from capslide.params import Parameters
from capslide.solvers.linsolve import LUKrylovSolver

PRECISIONS = ("double", "single")


def matrix_row(preset: str, single: bool, repeats: int) -> dict:
    A = scene_tangent(preset)
    A.sort_indices()
    row = measure(A, repeats, single)
    b = np.random.default_rng(0).standard_normal(A.shape[0])
    x, count = row["factors"].solve(b), [0]
    spla.gmres(A, b, M=spla.LinearOperator(A.shape, row["factors"].solve), rtol=1e-8, restart=40, maxiter=3,
               callback=lambda _: count.__setitem__(0, count[0] + 1), callback_type="pr_norm")
    return {**row, "residual": np.linalg.norm(A @ x - b) / np.linalg.norm(b), "gmres": count[0]}


def path_row(checkpoint: str, case: str, ubar: float, precision: str) -> dict:
    """The case resumed from ``checkpoint`` to ``ubar`` with PARDISO's factors in ``precision``."""
    settings, saved = study_checkpoint(checkpoint, case, [])
    params = Parameters.from_config(load_config([scene_path("experiment")], settings={
        **settings, "loading.ubar_max": ubar, "solver.factor_precision": precision}))
    factor, counted = LUKrylovSolver.factor, [0]

    def counted_factor(self, A):
        counted[0] += 1
        return factor(self, A)

    LUKrylovSolver.factor = counted_factor
    cutbacks = saved.state.cutbacks  # before the run, which continues the saved loop in place
    try:
        t = time.perf_counter()
        res = run_case(params, resume=saved)
        wall = time.perf_counter() - t
    finally:
        LUKrylovSolver.factor = factor
    new = res.records[len(saved.records):]
    return {"status": res.status.label, "from": saved.records[-1].ubar, "to": new[-1].ubar, "steps": len(new),
            "cutbacks": res.cutbacks - cutbacks, "wall": wall, "factorizations": counted[0],
            "newton": sum(r.newton_iterations for r in new), "krylov": sum(r.krylov_iterations for r in new),
            "Ft": new[-1].Ft, "area": new[-1].area}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--presets", nargs="*", default=["coarse", "annulus"])
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--checkpoint", help="a copy of a study case's checkpoint directory")
    ap.add_argument("--case", default="A0.270")
    ap.add_argument("--ubar", type=float, help="resume to this ubar (um)")
    ap.add_argument("--precisions", nargs="+", choices=PRECISIONS, default=list(PRECISIONS),
                    help="the precisions of the resumed runs, in this order")
    args = ap.parse_args()
    if args.presets:
        print("| preset | DOF | precision | refactorization (s) | solve (ms) | one solve's residual | GMRES to 1e-8 |")
        print("|---|---|---|---|---|---|---|")
        for preset in args.presets:
            for precision in PRECISIONS:
                r = matrix_row(preset, precision == "single", args.repeats)
                print(f"| {preset} | {r['dofs']:,} | {precision} | {r['refactor']:.3f} | {1e3 * r['solve']:.1f} "
                      f"| {r['residual']:.1e} | {r['gmres']} |", flush=True)
    if args.checkpoint:
        print(f"\n{args.case} from its checkpoint to {args.ubar} um:")
        print("| precision | status | ubar (um) | steps | cut-backs | factorizations | Newton | Krylov | wall (s) "
              "| Ft (E L0^2) | area (um^2) |")
        print("|---|---|---|---|---|---|---|---|---|---|---|")
        for precision in args.precisions:
            r = path_row(args.checkpoint, args.case, args.ubar, precision)
            print(f"| {precision} | {r['status']} | {r['from']:.4f} to {r['to']:.4f} | {r['steps']} | {r['cutbacks']} "
                  f"| {r['factorizations']} | {r['newton']} | {r['krylov']} | {r['wall']:.0f} | {r['Ft']:.5f} "
                  f"| {r['area']:.4f} |", flush=True)


if __name__ == "__main__":
    main()
