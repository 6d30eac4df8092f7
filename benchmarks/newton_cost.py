"""Benchmark: where a Newton iteration's time goes, and its cost against one preconditioned solve.

Runs one case (default: DI at zero load) through approach, preload and a short
slide with timers around the model's linearization (assembly), residual
evaluations (line search), admissibility checks and the linear solves of the
bordered system, then prints a Markdown table: per Newton iteration, the
median and total of each part, and the ratio of the mean Newton iteration to
the mean preconditioned solve (its factorization time excluded; reported
apart). Every Newton iteration calls the bordered solve once, so the calls
count the Newton iterations, including those of attempts that failed and
were retried with a shorter step (the step records count only the converged
attempts). Variants in one run, so the ratios compare under the same load:

- ``bordered``: one GMRES run on the bordered system (the default);
- ``two solves``: two GMRES runs on K (right-hand sides R and dR/dh) and the
  scalar Schur complement (the state before issue 7).

    OMP_NUM_THREADS=1 .venv/bin/python benchmarks/newton_cost.py --size 1 --ubar-max 0.2
"""

from __future__ import annotations

import argparse
import statistics
import time
from pathlib import Path

from capslide.config import load_config
from capslide.driver.case import run_case
from capslide.model import system
from capslide.params import Parameters
from capslide.solvers import linsolve

CONFIG = Path(__file__).resolve().parents[1] / "config" / "config.yaml"


class Timers:
    def __init__(self):
        self.t: dict[str, list[float]] = {}

    def wrap(self, owner, name: str, label: str):
        original = getattr(owner, name)

        def timed(*args, **kwargs):
            t0 = time.perf_counter()
            out = original(*args, **kwargs)
            self.t.setdefault(label, []).append(time.perf_counter() - t0)
            return out

        setattr(owner, name, timed)
        return original


def run_variant(overrides: list[str], bordered: bool) -> dict:
    timers = Timers()
    saved = []
    for owner, name, label in ((system.CapModel, "linearize", "assembly (residual + tangent + contact)"),
                               (system.CapModel, "residual", "residual (line search)"),
                               (system.CapModel, "admissible", "admissibility (min det F)"),
                               (system.BorderedSolve, "__call__", "bordered solve (incl. factorizations)"),
                               (linsolve.LUKrylovSolver, "factor", "LU factorizations")):
        saved.append((owner, name, timers.wrap(owner, name, label)))
    stash = linsolve.LUKrylovSolver.solve_bordered
    if not bordered:
        del linsolve.LUKrylovSolver.solve_bordered
    try:
        params = Parameters.from_config(load_config([CONFIG], overrides))
        t0 = time.perf_counter()
        res = run_case(params)
        wall = time.perf_counter() - t0
    finally:
        linsolve.LUKrylovSolver.solve_bordered = stash
        for owner, name, original in saved:
            setattr(owner, name, original)
    its = sum(r.newton_iterations for r in res.records)
    krylov = sum(r.krylov_iterations for r in res.records)
    return {"timers": timers.t, "wall": wall, "newton": its, "krylov": krylov, "status": res.status,
            "dofs": res.mesh.n_dofs + 1, "steps": len(res.records), "peak_Ft": res.scalars["peak_Ft"]}


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--size", type=float, default=1.0)
    ap.add_argument("--ubar-max", type=float, default=0.2)
    ap.add_argument("--set", dest="overrides", action="append", default=[], metavar="KEY=VALUE")
    ap.add_argument("--variant", action="append", choices=("bordered", "two solves"),
                    help="run only these variants (default: both)")
    a = ap.parse_args()
    overrides = [f"mesh.size={a.size}", f"loading.ubar_max={a.ubar_max}", "output.snapshot_ubar=[]",
                 "output.checkpoint_every=0", "solver.linear=lu_krylov", *a.overrides]
    variants = a.variant or ["bordered", "two solves"]
    out = {name: run_variant(overrides, name == "bordered") for name in variants}
    print(f"mesh.size {a.size}, slide to {a.ubar_max} L0; times in ms\n")
    solve_key = "bordered solve (incl. factorizations)"
    print("| variant | DOF | steps | Newton its (converged attempts / all) | Krylov its / Newton | part | calls | median | "
          "total (s) | per Newton it |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for name, r in out.items():
        n = len(r["timers"][solve_key])
        for part, ts in r["timers"].items():
            print(f"| {name} | {r['dofs']:,} | {r['steps']} | {r['newton']} / {n} | {r['krylov'] / r['newton']:.1f} | "
                  f"{part} | {len(ts)} | {1e3 * statistics.median(ts):.1f} | {sum(ts):.2f} | {1e3 * sum(ts) / n:.1f} |")
    print("\n| variant | wall (s) | Newton its (all) | per Newton it: solver parts / wall (ms) | one preconditioned solve "
          "(one Krylov run, factorizations excluded; ms) | ratio (solver parts) | ratio (wall) | peak Ft |")
    print("|---|---|---|---|---|---|---|---|")
    for name, r in out.items():
        t = r["timers"]
        n = len(t[solve_key])
        newton_total = sum(t.get("assembly (residual + tangent + contact)", [])) + sum(t.get("residual (line search)", [])) \
            + sum(t.get("admissibility (min det F)", [])) + sum(t[solve_key])
        runs = 1 if name == "bordered" else 2  # Krylov runs per bordered solve
        solve = (sum(t[solve_key]) - sum(t.get("LU factorizations", []))) / (runs * n)
        parts, wall = newton_total / n, r["wall"] / n
        print(f"| {name} | {r['wall']:.1f} | {n} | {1e3 * parts:.1f} / {1e3 * wall:.1f} | {1e3 * solve:.1f} | "
              f"{parts / solve:.2f} | {wall / solve:.2f} | {r['peak_Ft']:.6f} |")


if __name__ == "__main__":
    main()
