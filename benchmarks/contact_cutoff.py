"""Benchmark: cost of the contact integral with and without skipping far surface points.

Paper mesh (mesh.size 1), the flat substrate at the apex (h = H + g_eq), u = 0.
Prints the active segment count and the median time of the contact
linearization and of its scatter into the bulk matrix, for several cut-offs.

    OMP_NUM_THREADS=1 .venv/bin/python benchmarks/contact_cutoff.py
"""

import statistics
import time
from pathlib import Path

import numpy as np

from capslide.config import load_config
from capslide.model.build import build_model
from capslide.model.constraints import FixedForce
from capslide.model.system import History
from capslide.params import Parameters

CONFIG = Path(__file__).resolve().parents[1] / "config" / "config.yaml"


def main():
    print("| far gap (r0) | active segments | of | contact linearize (s) | full linearize incl. bulk (s) |")
    print("|---|---|---|---|---|")
    for far in (5.0, 20.0, 1e6):
        p = Parameters.from_config(load_config([CONFIG], [f"contact.far_gap_over_r0={far}", "solver.linear=direct"]))
        model = build_model(p)
        x = np.zeros(model.n_dofs + 1)
        x[-1] = p.geometry.H + p.adhesion.g_eq
        g, _ = model.contact.gaps(x[:-1], x[-1])
        n_act = len(model.contact.active(g))
        t_c, t_all = [], []
        for _ in range(5):
            t = time.perf_counter()
            model.contact.linearize(x[:-1], x[-1])
            t_c.append(time.perf_counter() - t)
            t = time.perf_counter()
            model.linearize(x, FixedForce(0.0), History())
            t_all.append(time.perf_counter() - t)
        print(f"| {far:g} | {n_act} | {len(g)} | {statistics.median(t_c):.4f} | {statistics.median(t_all):.4f} |")


if __name__ == "__main__":
    main()
