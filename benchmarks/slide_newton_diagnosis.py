"""Why a slide step of the `experiment` scene fails (issue 40, docs/experiment3d.md): from one case's checkpoint,

1. the tangent against the residual along the Newton increment of a step of --step um (central differences at
   several difference steps: a consistent tangent agrees to second order), and the line search's residuals;
2. the case resumed to --ubar um, printing for every Newton run that fails its residual norms and the nodes where
   the last residual is largest (a diagnostic: it wraps the continuation's Newton call).

    OMP_NUM_THREADS=1 .venv/bin/python benchmarks/slide_newton_diagnosis.py \\
        --checkpoint results/paper/experiment3d/cases/.A0.270.nc.checkpoint --case A0.270 --step 0.3 --ubar 28
(copy the checkpoint directory first if its case is still running: the resumed run writes no checkpoint.)
"""

from __future__ import annotations

import argparse

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla
import yaml

import capslide.loadpath.continuation as continuation
from capslide.config import load_config, scene_path
from capslide.driver.case import run_case
from capslide.io.checkpoint import config_text, load_checkpoint
from capslide.loadpath.cap import slide_constraint
from capslide.model.build import build_model
from capslide.params import Parameters
from capslide.studies.experiment_3d import study_cases


def tangent_check(params: Parameters, saved, step: float) -> None:
    model = build_model(params)
    state = saved.state
    constraint = slide_constraint(params.loading, state.stage_h, state.preload_Fn)(saved.records[-1].ubar + step)
    x, history = state.x, state.history
    r, bordered = model.linearize(x, constraint, history)
    J = sp.bmat([[bordered.K, sp.csc_matrix(bordered.c.reshape(-1, 1))],
                 [sp.csr_matrix(bordered.d.reshape(1, -1)), np.array([[bordered.e]])]]).tocsc()
    dx = spla.spsolve(J, r)
    print(f"step {step:g} um from ubar = {saved.records[-1].ubar:.4f}: |r| = {np.linalg.norm(r):.4g}, "
          f"largest |dx| = {np.abs(dx).max():.4g} um")
    Jdx = J @ dx
    for eps in (1e-3, 1e-4, 1e-5):
        fd = (model.residual(x + eps * dx, constraint, history) - model.residual(x - eps * dx, constraint, history))
        error = np.linalg.norm(fd / (2 * eps) - Jdx) / np.linalg.norm(Jdx)
        print(f"  difference step {eps:g}: |fd - J dx| / |J dx| = {error:.2e}")
    for alpha in (1.0, 0.1, 0.01, 0.001):
        print(f"  line search alpha {alpha:g}: |r| = {np.linalg.norm(model.residual(x - alpha * dx, constraint, history)):.4g}")


def report_failures() -> None:
    """Wrap the continuation's constrained Newton solve: print each failed run's residuals and where they sit."""
    solve = continuation.solve_constrained

    def wrapped(model, constraint, history, x0, opts, dt=0.0):
        res, solved = solve(model, constraint, history, x0, opts, dt)
        if not res.converged:
            print(f"failed at ubar = {constraint.ubar:.4f}: {res.reason}")
            print("  residual norms:", " ".join(f"{n:.2e}" for n in res.residual_norms))
            r = model.residual(res.x, constraint, history, dt)[:-1].reshape(-1, model.dim)
            for i in np.argsort(-np.abs(r).max(axis=1))[:4]:
                print(f"  node {i} at {model.mesh.nodes[i].round(1)}: residual {r[i].round(4)}")
        return res, solved

    continuation.solve_constrained = wrapped


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--checkpoint", required=True)
    ap.add_argument("--case", default="A0.270")
    ap.add_argument("--step", type=float, default=0.3, help="the step of the tangent check (um)")
    ap.add_argument("--ubar", type=float, help="resume to this ubar (um), printing failed Newton runs")
    ap.add_argument("--set", action="append", default=[],
                    help="key=value of the checkpoint's case besides the study's (e.g. friction.eps_t=10)")
    args = ap.parse_args()
    case = study_cases(load_config([scene_path("experiment")]))[args.case]
    changed = {k: yaml.safe_load(v) for k, v in (s.split("=", 1) for s in args.set)}
    saved = load_checkpoint(args.checkpoint, config_text(load_config([scene_path("experiment")],
                                                                     settings={**case, **changed})))
    tangent_check(Parameters.from_config(load_config([scene_path("experiment")], settings={**case, **changed})), saved,
                  args.step)
    if args.ubar is not None:
        report_failures()
        params = Parameters.from_config(load_config([scene_path("experiment")],
                                                    settings={**case, **changed, "loading.ubar_max": args.ubar}))
        res = run_case(params, resume=saved)
        print(f"{res.status.label} at ubar = {res.records[-1].ubar:.4f} ({res.reason or 'to the end'})")


if __name__ == "__main__":
    main()
