"""Study: the paper's cap under the three preloads, at several mesh levels and surface quadratures.

Prints a Markdown table: preload Fn*, mesh size, Gauss points, DOF, status,
contact area A (g_n <= g_max), half-width A/2 next to the 2D JKR estimate of
a rigid-flat / elastic-half-space line contact, compressive area, steps and
wall time. Only the approach and preload run (no sliding).

    OMP_NUM_THREADS=1 .venv/bin/python benchmarks/normal_contact_study.py [--sizes 2 1] [--gauss 4] [--preloads -0.288 0 0.288]
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

from capslide.config import load_config
from capslide.laws import analytic
from capslide.loadpath.cap import load_path
from capslide.loadpath.continuation import drain
from capslide.model.build import build_model
from capslide.params import Parameters

CONFIG = Path(__file__).resolve().parents[1] / "config" / "config.yaml"


def run(size: float, gauss: int, preload: float):
    p = Parameters.from_config(load_config([CONFIG], [f"mesh.size={size}", f"mesh.surface_gauss_points={gauss}",
                                                      f"loading.preload={preload}"]))
    model = build_model(p)
    mesh = model.mesh
    t = time.perf_counter()
    records = []
    end = drain(load_path(model, stop_before="slide"), lambda step: records.append(step.record))
    rec = records[-1]
    E_star = analytic.effective_modulus(p.material.E, p.material.nu)
    try:
        a_jkr = analytic.jkr_cylinder_half_width(-preload, p.geometry.R, E_star, p.adhesion.W_adh)
    except ValueError:
        a_jkr = float("nan")
    return (preload, size, gauss, mesh.n_dofs, end.status.label, rec.Fn, rec.area, rec.area / 2, a_jkr, rec.area_compressive,
            len(records), time.perf_counter() - t)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", type=float, nargs="+", default=[2.0, 1.0])
    ap.add_argument("--gauss", type=int, nargs="+", default=[4])
    ap.add_argument("--preloads", type=float, nargs="+", default=[-0.288, 0.0, 0.288])
    a = ap.parse_args()
    rows = [run(s, g, f) for f in a.preloads for s in a.sizes for g in a.gauss]
    print("| Fn* | mesh.size | Gauss pts | DOF | status | Fn reached | area A | A/2 | 2D JKR half-width | compressive area "
          "| steps | wall (s) |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        print(f"| {r[0]:+.3f} | {r[1]:g} | {r[2]} | {r[3]:,} | {r[4]} | {r[5]:+.6f} | {r[6]:.5f} | {r[7]:.4f} | {r[8]:.4f} "
              f"| {r[9]:.5f} | {r[10]} | {r[11]:.1f} |")


if __name__ == "__main__":
    main()
