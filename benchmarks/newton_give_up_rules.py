"""Could Newton give up sooner on a slide step it will not converge (issue 40, the cost of an experiment case)?

``record``: resume one `experiment` study case from its checkpoint to --ubar um and write every Newton run of the
continuation's steps (converged or not) as a JSON line: the step's ubar, whether it converged, its iterations, its
reason and its residual norms (E L0^2, the first before any iteration); and after each converged run whether the leg
kept the step or rejected it (its rules: an area jump, a fall of Ft, the onset overstepped), with the time.
``rules``: read such files and, for each candidate rule, the converged runs it would have stopped (each then a
failed attempt and a cut-back) and the iterations it would have saved on the runs that failed anyway (each iteration
about 3 to 5 s on the annulus mesh).

    cp -r results/paper/experiment3d/cases/.A0.100.nc.checkpoint /tmp/ck   # a copy: the case may still run
    OMP_NUM_THREADS=1 .venv/bin/python benchmarks/newton_give_up_rules.py record --checkpoint /tmp/ck \\
        --case A0.100 --ubar 40 -o runs.jsonl
    .venv/bin/python benchmarks/newton_give_up_rules.py rules runs.jsonl
"""

from __future__ import annotations

import argparse
import json
import time
from collections.abc import Callable

import numpy as np
import yaml
from slide_newton_diagnosis import study_checkpoint

import capslide.loadpath.continuation as continuation
from capslide.config import load_config, scene_path
from capslide.driver.case import run_case
from capslide.params import Parameters


def record(checkpoint: str, case: str, sets: list[str], ubar: float, out: str, run_sets: list[str]) -> None:
    """Resume ``case`` from ``checkpoint`` to ``ubar`` and append each constrained Newton run to ``out``;
    ``run_sets`` (key=value) change the resumed run only (a lever tried from the same checkpoint)."""
    settings, saved = study_checkpoint(checkpoint, case, sets)
    settings.update({k: yaml.safe_load(v) for k, v in (s.split("=", 1) for s in run_sets)})
    solve = continuation.solve_constrained

    def recorded(model, constraint, history, x0, opts, dt=0.0):
        res, solved = solve(model, constraint, history, x0, opts, dt)
        with open(out, "a") as f:
            f.write(json.dumps({"ubar": float(constraint.ubar), "converged": bool(res.converged),
                                "iterations": int(res.iterations), "reason": res.reason,
                                "norms": [float(n) for n in res.residual_norms]}) + "\n")
        return res, solved

    judge = continuation._judged  # a diagnostic wrap of the continuation's private judge

    def judged(model, loop, leg, res, *args, **kwargs):
        rec, reason, still_steady = judge(model, loop, leg, res, *args, **kwargs)
        if res.converged:
            with open(out, "a") as f:
                f.write(json.dumps({"kept": rec is not None, "reason": reason, "time": time.time()}) + "\n")
        return rec, reason, still_steady

    continuation.solve_constrained, continuation._judged = recorded, judged
    params = Parameters.from_config(load_config([scene_path("experiment")],
                                                settings={**settings, "loading.ubar_max": ubar}))
    start = time.perf_counter()
    res = run_case(params, resume=saved)
    print(f"{res.status.label} at ubar = {res.records[-1].ubar:.4f} ({res.reason or 'to the end'}); "
          f"{time.perf_counter() - start:.0f} s")


def cap(k: int) -> Callable[[list[float]], int | None]:
    """Give up after k iterations."""
    return lambda norms: k if len(norms) - 1 > k else None


def stall(m: int, factor: float, start: int = 0) -> Callable[[list[float]], int | None]:
    """Give up at the first iteration i >= max(m, start) whose residual is above ``factor`` times the one m
    iterations before."""
    def rule(norms: list[float]) -> int | None:
        for i in range(max(m, start), len(norms) - 1):
            if norms[i] > factor * norms[i - m]:
                return i
        return None
    return rule


def level(k: int, r: float) -> Callable[[list[float]], int | None]:
    """Give up at iteration k when the residual there is above r (E L0^2)."""
    return lambda norms: k if len(norms) - 1 > k and norms[k] > r else None


RULES = {"at most 24 iterations": cap(24), "at most 20 iterations": cap(20),
         "no halving over 5 iterations": stall(5, 0.5), "no halving over 8 iterations": stall(8, 0.5),
         "no tenfold fall over 10 iterations": stall(10, 0.1), "no fall over 6 iterations, from the 10th": stall(6, 1.0, 10),
         "residual above 1 at the 15th": level(15, 1.0), "residual above 10 at the 12th": level(12, 10.0)}


def rules(paths: list[str]) -> None:
    lines = [json.loads(line) for p in paths for line in open(p)]
    runs, verdicts = [r for r in lines if "kept" not in r], [r for r in lines if "kept" in r]
    if verdicts:
        rejected = [r["reason"] for r in verdicts if not r["kept"]]
        print(f"converged steps the leg kept: {len(verdicts) - len(rejected)}; rejected: {len(rejected)}"
              + "".join(f"\n  {reason}" for reason in rejected))
    ok = [r for r in runs if r["converged"]]
    bad = [r for r in runs if not r["converged"] and r["reason"].startswith("no convergence")]
    spent = sum(r["iterations"] for r in bad)
    print(f"{len(runs)} Newton runs: {len(ok)} converged ({sum(r['iterations'] for r in ok)} iterations), "
          f"{len(bad)} ran out of iterations ({spent}), {len(runs) - len(ok) - len(bad)} failed otherwise")
    its = np.array([r["iterations"] for r in ok])
    print(f"converged runs' iterations: median {np.median(its):.0f}, 90th percentile {np.percentile(its, 90):.0f}, "
          f"most {its.max()}")
    print("\n| rule | converged runs it stops | iterations saved on the runs that failed | of their iterations |")
    print("|---|---|---|---|")
    for name, rule in RULES.items():
        stopped = sum(rule(r["norms"]) is not None for r in ok)
        saved = sum(r["iterations"] - s for r in bad if (s := rule(r["norms"])) is not None)
        print(f"| {name} | {stopped} of {len(ok)} | {saved} | {100 * saved / max(spent, 1):.0f} % |")


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    sub = ap.add_subparsers(dest="mode", required=True)
    rec = sub.add_parser("record")
    rec.add_argument("--checkpoint", required=True)
    rec.add_argument("--case", default="A0.100")
    rec.add_argument("--ubar", type=float, required=True, help="resume to this ubar (um)")
    rec.add_argument("--set", action="append", default=[], help="key=value besides the study case's")
    rec.add_argument("--run-set", action="append", default=[], help="key=value of the resumed run only")
    rec.add_argument("-o", "--out", required=True, help="JSON lines, appended to")
    rul = sub.add_parser("rules")
    rul.add_argument("files", nargs="+")
    args = ap.parse_args(argv)
    if args.mode == "record":
        record(args.checkpoint, args.case, args.set, args.ubar, args.out, args.run_set)
    else:
        rules(args.files)


if __name__ == "__main__":
    main()
