"""Why a slide step of the `experiment` scene fails (issue 40, docs/experiment3d.md): from one case's checkpoint,

1. the tangent against the residual along the Newton increment of a step of --step um (central differences at
   several difference steps: a consistent tangent agrees to second order), and the line search's residuals;
2. the case resumed to --ubar um, printing for every Newton run that fails its residual norms and the nodes where
   the last residual is largest (a diagnostic: it wraps the continuation's Newton call);
3. with --iterations, for every Newton run of the resumed steps (converged or not), per iteration: the line search's
   residual evaluations (1: the full step taken; each halving adds one) and the points whose stick/slip state
   changed since the last iteration, with the residual norms (where a slide step's iterations go);
4. with --active-set, after each failed Newton run, Newton runs with every point's stick/slip state frozen (the
   return map's classification held, so each run is smooth), the states updated from the result, up to 12 times,
   printing the points that flip, their gap against DI's cut g_cut and their threshold and traction (a probe of
   whether the step has a consistent state; it patches the contact's return map, capslide has no such option).

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

import capslide.fem.interface as interface
import capslide.loadpath.continuation as continuation
from capslide.config import load_config, scene_path
from capslide.driver.case import run_case
from capslide.io.checkpoint import config_text, load_checkpoint
from capslide.laws import contact as contact_laws
from capslide.loadpath.cap import slide_constraint
from capslide.model.build import build_model
from capslide.model.system import CapModel
from capslide.params import Parameters
from capslide.studies.experiment_3d import study_cases


def study_checkpoint(checkpoint: str, case: str, sets: list[str]) -> tuple[dict, object]:
    """The config settings of the `experiment` study's ``case`` with the ``key=value`` ``sets``, and the case's
    checkpoint read for them."""
    settings = {**study_cases(load_config([scene_path("experiment")]))[case],
                **{k: yaml.safe_load(v) for k, v in (s.split("=", 1) for s in sets)}}
    return settings, load_checkpoint(checkpoint, config_text(load_config([scene_path("experiment")], settings=settings)))


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


_FROZEN: dict = {"slipping": None}  # the classification the patched return map holds (None: the law's own)


def _patch_return_map() -> None:
    """Let the contact's return map hold the stick/slip states of ``_FROZEN`` (points in the band's active set)."""
    cls = interface.SurfaceContact
    active, return_map = cls.active, cls._return_map

    def recorded_active(self, g):
        self._probe_active = active(self, g)
        return self._probe_active

    def held_return_map(self, trial, threshold, slip):
        held = _FROZEN["slipping"]
        if held is None:
            return return_map(self, trial, threshold, slip)
        s = held[self._probe_active]
        return contact_laws.vector_return_map(trial, threshold, lambda m, t: (
            np.where(s, t, m), s.copy(), np.where(s, 0.0, 1.0), np.where(s, 1.0, 0.0)))

    cls.active, cls._return_map = recorded_active, held_return_map


def _states(model, x, constraint, history):
    """Slipping per surface point (the law's own return map), the points' gaps and traction magnitudes."""
    c = model.contact
    u, h = model.split(x)
    pts = c._points(u, h, constraint.ubar, history.anchors, history.slip)
    shape = c.quad.X.shape[:-1]
    slipping, gap, traction = np.zeros(shape, dtype=bool), np.full(shape, np.nan), np.full(shape, np.nan)
    slipping[c._probe_active], gap[c._probe_active] = pts.slipping, pts.g
    traction[c._probe_active] = np.linalg.norm(pts.Tt, axis=-1)
    return slipping, gap, traction


def probe_active_set() -> None:
    """After a failed Newton run: frozen-state Newton runs, the states updated from each result."""
    _patch_return_map()
    solve = continuation.solve_constrained

    def probed(model, constraint, history, x0, opts, dt=0.0):
        res, solved = solve(model, constraint, history, x0, opts, dt)
        if res.converged or history.anchors is None or not hasattr(model.contact.law, "g_cut"):
            return res, solved
        x, (held, _, _) = x0, _states(model, x0, constraint, history)
        for k in range(12):
            _FROZEN["slipping"] = held
            frozen, _ = solve(model, constraint, history, x, opts, dt)
            _FROZEN["slipping"] = None
            if not frozen.converged:
                print(f"  frozen run {k}: {frozen.reason}")
                break
            x = frozen.x
            now, gap, traction = _states(model, x, constraint, history)
            law, flipped = model.contact.law, np.argwhere(now != held)
            print(f"  frozen run {k}: {frozen.iterations} Newton iterations, {len(flipped)} points flip")
            for i in map(tuple, flipped[:3]):
                thr = law.threshold(np.array([gap[i]]), np.ones(1))[0][0]
                print(f"    at {model.contact.quad.current(model.split(x)[0])[0][i].round(2)}: slips now {now[i]}, "
                      f"g = {gap[i]:.5f} (g_cut {law.g_cut:.5f}), threshold(g) / tau {thr / law.tau:.4f} per reference area, "
                      f"|T| / tau {traction[i] / law.tau:.4f}")
            if not len(flipped):
                break
            held = now
        return res, solved

    continuation.solve_constrained = probed


def report_iterations() -> None:
    """Wrap the model's linearization and residual and the continuation's Newton call: print, for every Newton run,
    each iteration's line-search evaluations and stick/slip flips, and the residual norms."""
    seen = {"states": None, "evaluations": 0, "rows": []}
    linearize, residual = CapModel.linearize, CapModel.residual

    def counted_linearize(model, z, constraint, history, dt=0.0):
        if history.anchors is not None:
            u, h = model.split(z)
            _, states = model.contact.tangential_state(u, h, constraint.ubar, *history.friction)
            if seen["states"] is not None:
                seen["rows"].append((seen["evaluations"], int(np.sum(states != seen["states"]))))
            seen["states"] = states
        seen["evaluations"] = 0
        return linearize(model, z, constraint, history, dt)

    def counted_residual(model, z, constraint, history, dt=0.0):
        seen["evaluations"] += 1
        return residual(model, z, constraint, history, dt)

    CapModel.linearize, CapModel.residual = counted_linearize, counted_residual
    solve = continuation.solve_constrained

    def wrapped(model, constraint, history, x0, opts, dt=0.0):
        seen.update(states=None, evaluations=0, rows=[])
        res, solved = solve(model, constraint, history, x0, opts, dt)
        print(f"ubar = {constraint.ubar:.4f}: converged {res.converged} in {res.iterations}; evaluations/flips "
              + " ".join(f"{e}/{f}" for e, f in seen["rows"]))
        print("  residual norms:", " ".join(f"{n:.1e}" for n in res.residual_norms))
        return res, solved

    continuation.solve_constrained = wrapped


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--checkpoint", required=True)
    ap.add_argument("--case", default="A0.270")
    ap.add_argument("--step", type=float, default=0.3, help="the step of the tangent check (um; 0: no check)")
    ap.add_argument("--ubar", type=float, help="resume to this ubar (um), printing failed Newton runs")
    ap.add_argument("--iterations", action="store_true",
                    help="print every Newton run's line-search evaluations and stick/slip flips per iteration")
    ap.add_argument("--active-set", action="store_true", help="probe each failed step with frozen stick/slip states")
    ap.add_argument("--set", action="append", default=[],
                    help="key=value of the checkpoint's case besides the study's (e.g. friction.eps_t=10)")
    args = ap.parse_args()
    settings, saved = study_checkpoint(args.checkpoint, args.case, args.set)
    if args.step > 0.0:
        tangent_check(Parameters.from_config(load_config([scene_path("experiment")], settings=settings)), saved, args.step)
    if args.ubar is not None:
        if args.iterations:
            report_iterations()
        else:
            report_failures()
        if args.active_set:
            probe_active_set()
        params = Parameters.from_config(load_config([scene_path("experiment")],
                                                    settings={**settings, "loading.ubar_max": args.ubar}))
        res = run_case(params, resume=saved)
        print(f"{res.status.label} at ubar = {res.records[-1].ubar:.4f} ({res.reason or 'to the end'})")


if __name__ == "__main__":
    main()
