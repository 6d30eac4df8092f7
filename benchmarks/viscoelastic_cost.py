"""What the viscous branches cost: the DI case at zero load, elastic against viscoelastic, on the same mesh.

Both run the whole load path (approach, preload, slide to ubar_max) with the same stage velocity; the viscoelastic
one adds ``--branches`` Prony branches (g = 0.5 each, tau spread over a decade around ``--tau``). The table gives
the median wall time of ``--repeats`` runs, the steps and Newton iterations, and the time per Newton iteration; the
ratios are measured in this one run. The paths differ (a viscous slide is another problem), so the time per Newton
iteration is the cost of the history variables themselves, and the wall-time ratio what a user waits for:

    OMP_NUM_THREADS=1 .venv/bin/python benchmarks/viscoelastic_cost.py --preset paper --repeats 3
"""

from __future__ import annotations

import argparse
import statistics
import time
from pathlib import Path

import numpy as np

from capslide.config import load_config
from capslide.driver.case import run_case
from capslide.params import Parameters
from capslide.states import Status

CONFIG = Path(__file__).resolve().parents[1] / "config" / "config.yaml"


def run(sets: list[str]) -> tuple[float, int, int, float]:
    """(wall time s, steps, Newton iterations, peak Ft) of one case."""
    params = Parameters.from_config(load_config([CONFIG], sets))
    t0 = time.perf_counter()
    result = run_case(params)
    wall = time.perf_counter() - t0
    if result.status != Status.COMPLETED:
        raise SystemExit(f"case ended {result.status.label}: {result.reason}")
    return (wall, len(result.records), sum(r.newton_iterations for r in result.records),
            float(result.scalars["peak_Ft"]))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--preset", default="paper")
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--branches", type=int, default=3)
    ap.add_argument("--tau", type=float, default=1.0, help="central relaxation time (s); v = 1 L0/s")
    a = ap.parse_args()
    taus = a.tau * np.logspace(-1, 1, a.branches) if a.branches > 1 else [a.tau]
    prony = "[" + ", ".join(f"{{g: 0.5, tau: {t:.6g}}}" for t in taus) + "]"
    base = [f"preset={a.preset}", "loading.preload=0.0", "loading.velocity=1e-6", "output.snapshot_ubar=[]"]
    variants = {"elastic": base,
                f"viscoelastic ({a.branches} branches)": [*base, "material.model=viscoelastic", f"material.prony={prony}"]}
    rows = {}
    for name, sets in variants.items():
        runs = [run(sets) for _ in range(a.repeats)]
        wall = statistics.median(r[0] for r in runs)
        _, steps, newton, peak = runs[0]
        rows[name] = (wall, steps, newton, wall / newton, peak)
    ref = rows["elastic"]
    print(f"preset {a.preset}, DI at Fn* = 0, v = 1 L0/s, median of {a.repeats}")
    print(f"{'case':28s} {'wall s':>8s} {'steps':>6s} {'Newton':>7s} {'ms/Newton':>10s} {'peak Ft':>9s} "
          f"{'wall ratio':>10s} {'per-Newton ratio':>16s}")
    for name, (wall, steps, newton, per, peak) in rows.items():
        print(f"{name:28s} {wall:8.2f} {steps:6d} {newton:7d} {1e3 * per:10.1f} {peak:9.5f} {wall / ref[0]:10.2f} "
              f"{per / ref[3]:16.2f}")


if __name__ == "__main__":
    main()
