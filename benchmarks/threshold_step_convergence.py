"""Study: does the slide with its thresholds held over each step (``friction.threshold_at: step_start``, or at the
state extrapolated to the step's end: ``step_predicted``) converge with the step to the slide with the current
state's threshold (``current``, the paper's model)?

The 2D test cap at zero load (model DI, ``mesh.size`` 32 at the ``fast`` preset, to ubar = 2 L0, before the area's
first jump at 2.07): ``current`` at the finest largest slide step is the reference, and each run's Ft, contact area
and stick area at a few ubar are given against it (each interpolated linearly between the run's slide steps).
``solver.snap_through`` is on for every run, as in the experiment scene. Prints a Markdown table; about two minutes
(228 s beside four other jobs).

    OMP_NUM_THREADS=1 .venv/bin/python benchmarks/threshold_step_convergence.py
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

from capslide.config import load_config
from capslide.driver.case import run_case
from capslide.params import Parameters
from capslide.states import Phase

CONFIG = Path(__file__).resolve().parents[1] / "config" / "config.yaml"
BASE = ["preset=fast", "mesh.size=32", "loading.preload=0", "loading.ubar_max=2.0", "solver.snap_through=true",
        "output.snapshot_ubar=[]"]
RUNS = [("current", 0.025), ("current", 0.2), ("step_start", 0.2), ("step_start", 0.1), ("step_start", 0.05),
        ("step_start", 0.025), ("step_start", 0.0125), ("step_predicted", 0.2), ("step_predicted", 0.1),
        ("step_predicted", 0.05), ("step_predicted", 0.025)]  # the first is the reference
QUANTITIES = ("Ft", "area", "area_stick")


def slide_curves(threshold_at: str, max_step: float):
    """The run's status, slide steps, wall time (s) and its slide's ubar and QUANTITIES per step."""
    sets = BASE + [f"friction.threshold_at={threshold_at}", f"loading.max_slide_step={max_step}"]
    r = run_case(Parameters.from_config(load_config([CONFIG], sets)))
    slide = [rec for rec in r.records if rec.phase == Phase.SLIDE]
    curves = {q: np.array([getattr(rec, q) for rec in slide]) for q in ("ubar",) + QUANTITIES}
    return r.status, len(slide), r.wall_time, curves


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--ubar", type=float, nargs="+", default=[0.5, 1.0, 1.5, 1.8, 2.0], help="ubar (L0)")
    a = ap.parse_args()
    runs = [(t, s, *slide_curves(t, s)) for t, s in RUNS]
    ref = runs[0][-1]
    at = lambda c, q: np.interp(a.ubar, c["ubar"], c[q])  # noqa: E731
    head = " | ".join(f"{q} at {u:g}" for q in QUANTITIES for u in a.ubar)
    print(f"| threshold_at | largest slide step (L0) | status | slide steps | wall (s) | {head} |")
    print("|" + "---|" * (5 + len(QUANTITIES) * len(a.ubar)))
    for t, s, status, n, wall, c in runs:
        if c is ref:
            cells = [f"{v:.5f}" for q in QUANTITIES for v in at(c, q)]
        else:
            cells = [f"{100 * (v / r - 1):+.3f} %" for q in QUANTITIES for v, r in zip(at(c, q), at(ref, q))]
        print(f"| {t} | {s:g} | {status} | {n} | {wall:.1f} | " + " | ".join(cells) + " |", flush=True)


if __name__ == "__main__":
    main()
