"""Compare two trees of case files whose slides took different steps (a change of the step control): the approach
and preload records step by step (or, when they took different steps, the last record of each: the approached
and the preloaded state), and the slide records at every ubar both runs reached. Prints, per part, the step
variables with the largest difference relative to the variable's largest magnitude in the first tree, and the file
where it occurs. Wall times and iteration counts are left out.

    .venv/bin/python benchmarks/compare_at_common_ubar.py /tmp/before /tmp/after [--top 12]
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np
import xarray as xr

SKIP = {"newton_iterations", "krylov_iterations", "wall_time"}
SLIDE = 2  # the slide's phase code (capslide.states.Phase)


def record_rows(ds: xr.Dataset) -> tuple[np.ndarray, dict[float, int]]:
    """Indices of the approach and preload records, and the slide records by their ubar."""
    phase, ubar = ds["phase"].values, ds["ubar"].values
    slide = np.flatnonzero(phase == SLIDE)
    return np.flatnonzero(phase != SLIDE), {float(ubar[i]): int(i) for i in slide}


def phase_ends(a: xr.Dataset, b: xr.Dataset, rows_a: np.ndarray, rows_b: np.ndarray) -> tuple[list[int], list[int]]:
    """The last approach and preload records of each tree (the approached and the preloaded state)."""
    pa, pb = a["phase"].values, b["phase"].values
    phases = [p for p in dict.fromkeys(pa[rows_a]) if p in set(pb[rows_b])]
    return ([int(rows_a[pa[rows_a] == p][-1]) for p in phases], [int(rows_b[pb[rows_b] == p][-1]) for p in phases])


def largest_differences(a: xr.Dataset, b: xr.Dataset) -> dict[tuple[str, str], float]:
    """(part, variable) -> largest |a - b| over the compared records / max |a| of the variable."""
    normal_a, slide_a = record_rows(a)
    normal_b, slide_b = record_rows(b)
    if len(normal_a) != len(normal_b):  # a change of their step control: the last state of each phase
        normal_a, normal_b = phase_ends(a, b, normal_a, normal_b)
    common = sorted(set(slide_a) & set(slide_b))
    parts = {"approach + preload": (normal_a, normal_b),
             "slide at common ubar": ([slide_a[u] for u in common], [slide_b[u] for u in common])}
    out = {}
    for name in a.data_vars:
        var = a[name]
        if name in SKIP or name not in b or "step" not in var.dims or var.dtype.kind != "f":
            continue
        x, y = var.transpose("step", ...).values, b[name].transpose("step", ...).values
        scale = np.nanmax(np.abs(x)) if np.isfinite(x).any() else 0.0
        for part, (ia, ib) in parts.items():
            d = x[ia] - y[ib]
            if scale > 0 and len(ia) and np.isfinite(d).any():
                out[(part, name)] = float(np.nanmax(np.abs(d)) / scale)
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("before", type=Path)
    ap.add_argument("after", type=Path)
    ap.add_argument("--top", type=int, default=12, help="variables shown per part")
    args = ap.parse_args()
    worst: dict[tuple[str, str], tuple[float, str]] = {}
    for fa in sorted(args.before.rglob("*.nc")):
        fb = args.after / fa.relative_to(args.before)
        if not fb.is_file():
            continue
        with xr.open_dataset(fa) as a, xr.open_dataset(fb) as b:
            if "phase" not in a or a["phase"].dims != ("step",) or a["ubar"].dims != ("step",):
                continue  # a collected file
            for key, d in largest_differences(a, b).items():
                if d >= worst.get(key, (-1.0, ""))[0]:
                    worst[key] = (d, str(fa.relative_to(args.before)))
    for part in ("approach + preload", "slide at common ubar"):
        rows = sorted(((d, name, f) for (p, name), (d, f) in worst.items() if p == part), reverse=True)
        print(f"\n{part}: variable, largest relative difference, file")
        for d, name, f in rows[:args.top]:
            print(f"  {name:20s} {d:.2e}  {f}")


if __name__ == "__main__":
    main()
