"""Study: sensitivity of peak Ft and onset ubar to the slide step size and to eps_t.

Runs DI at zero load and EA (s_cut = 0) at Fn* = -0.288 three ways: default
steps, every slide step halved (first, largest and smallest), eps_t doubled.
Prints a Markdown table with the relative changes.

    OMP_NUM_THREADS=1 .venv/bin/python benchmarks/slide_sensitivity.py [--size 8]
"""

from __future__ import annotations

import argparse
from pathlib import Path

from capslide.config import load_config
from capslide.driver.case import run_case
from capslide.params import Parameters

CONFIG = Path(__file__).resolve().parents[1] / "config" / "config.yaml"
CASES = {"DI, Fn* = 0": ["friction.model=DI", "loading.preload=0"],
         "EA s_cut=0, Fn* = -0.288": ["friction.model=EA", "friction.s_cut=0", "loading.preload=-0.288"]}


def variants(cfg):
    L, f = cfg["loading"], cfg["friction"]
    return {
        "default": [],
        "steps halved": [f"loading.slide_step={L['slide_step'] / 2}", f"loading.max_slide_step={L['max_slide_step'] / 2}",
                         f"loading.min_slide_step={L['min_slide_step'] / 2}"],
        "eps_t doubled": [f"friction.eps_t={2 * f['eps_t']}"],
    }


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--size", type=float, default=8.0)
    ap.add_argument("--ubar-max", type=float, default=3.0)
    a = ap.parse_args()
    base = [f"mesh.size={a.size}", f"loading.ubar_max={a.ubar_max}", "output.snapshot_ubar=[]"]
    print("| case | variant | status | steps | peak Ft | onset ubar | change of peak Ft | change of onset ubar | wall (s) |")
    print("|---|---|---|---|---|---|---|---|---|")
    for name, sets in CASES.items():
        cfg = load_config([CONFIG], base + sets)
        ref = None
        for vname, extra in variants(cfg).items():
            r = run_case(Parameters.from_config(load_config([CONFIG], base + sets + extra)))
            s = r.scalars
            ref = ref or s
            d_peak = s["peak_Ft"] / ref["peak_Ft"] - 1
            d_on = s["onset_ubar"] / ref["onset_ubar"] - 1
            print(f"| {name} | {vname} | {r.status} | {len(r.records)} | {s['peak_Ft']:.6f} | {s['onset_ubar']:.5f} "
                  f"| {100 * d_peak:+.3f} % | {100 * d_on:+.3f} % | {r.wall_time:.1f} |", flush=True)


if __name__ == "__main__":
    main()
