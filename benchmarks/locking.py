"""Volumetric locking of the displacement elements as nu -> 0.5: the zero-load contact area of the paper's cap.

The cap is approached and preloaded to Fn* = 0 (no slide) with the presets' elements, ``fast`` (Q1, mesh.size 32)
and ``paper`` (Q2, mesh.size 16), and with a reference whose bulk is refined too (Q2, mesh.size 8,
mesh.max_size_over_H 1/16); a second, finer reference (mesh.size 4, 1/32) shows whether the reference itself has
converged. mesh.size refines only the contact band, so a locking bulk shows as an error against the reference that
grows as nu -> 0.5. The table gives the areas and the errors; the refusal thresholds of capslide.config come from it.
The mixed Q2/P1 bulk (mesh.formulation = mixed) computes up to nu = 0.5; as the reference it shows the other elements
against a locking-free one (docs/options.md):

    OMP_NUM_THREADS=1 .venv/bin/python benchmarks/locking.py --nu 0.4 0.45 0.48 0.49 0.495 0.499
    OMP_NUM_THREADS=1 .venv/bin/python benchmarks/locking.py --nu 0.4 0.45 0.49 0.499 0.4999 0.5 \
        --reference "mixed (Q2/P1, 32)" --variants "fast (Q1, 32)" "Q2 (32)"
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

from capslide.config import ConfigError, load_config
from capslide.loadpath.cap import load_path
from capslide.loadpath.continuation import drain
from capslide.model.build import build_model
from capslide.params import Parameters
from capslide.states import Status

CONFIG = Path(__file__).resolve().parents[1] / "config" / "config.yaml"
VARIANTS = {"fast (Q1, 32)": ("Q1", 32, 0.25), "paper (Q2, 16)": ("Q2", 16, 0.25), "reference (Q2, 8, 1/16)": ("Q2", 8, 0.0625),
            "finer (Q2, 4, 1/32)": ("Q2", 4, 0.03125), "Q2 (32)": ("Q2", 32, 0.25),
            "mixed (Q2/P1, 32)": ("Q2", 32, 0.25, "mixed"), "mixed (Q2/P1, 16)": ("Q2", 16, 0.25, "mixed")}


def zero_load_area(element: str, size: float, bulk: float, nu: float,
                   formulation: str = "displacement") -> tuple[float, float]:
    """Contact area at Fn* = 0 (L0) and wall time (s); NaN where the configuration is refused (nu = 0.5 with the
    displacement formulation)."""
    sets = [f"mesh.element={element}", f"mesh.size={size}", f"mesh.max_size_over_H={bulk}", f"material.nu={nu}",
            f"mesh.formulation={formulation}", "limits.max_steps=100000", "limits.max_dofs=1e7",
            "limits.refuse_locking=false"]
    try:
        config = load_config([CONFIG], sets)
    except ConfigError:
        return float("nan"), 0.0
    model = build_model(Parameters.from_config(config))
    records = []
    t0 = time.perf_counter()
    end = drain(load_path(model, stop_before="slide"), lambda step: records.append(step.record))
    return (records[-1].area if end.status == Status.COMPLETED else float("nan")), time.perf_counter() - t0


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--nu", type=float, nargs="+", default=[0.4, 0.45, 0.48, 0.49, 0.495, 0.499])
    ap.add_argument("--variants", nargs="+", default=list(VARIANTS)[:4], choices=list(VARIANTS))
    ap.add_argument("--reference", default="reference (Q2, 8, 1/16)", choices=list(VARIANTS))
    a = ap.parse_args()
    ref = a.reference
    names = [v for v in a.variants if v != ref]
    print("| nu | reference area | " + " | ".join(f"{v}: area, error" for v in names) + " | wall (s) |")
    print("|---|---|" + "---|" * len(names) + "---|")
    for nu in a.nu:
        A_ref, wall = zero_load_area(*VARIANTS[ref][:3], nu, *VARIANTS[ref][3:])
        cells = []
        for v in names:
            A, t = zero_load_area(*VARIANTS[v][:3], nu, *VARIANTS[v][3:])
            wall += t
            cells.append(f"{A:.4f}, {100 * (A / A_ref - 1):+.2f} %")
        print(f"| {nu:g} | {A_ref:.4f} | " + " | ".join(cells) + f" | {wall:.0f} |", flush=True)


if __name__ == "__main__":
    main()
