"""The sliding sphere on its half model against the whole cap (issue 40): does the plane of symmetry change the
slide? The `sphere` scene with model DI on a coarse mesh, slid at zero load, once as the half model (y >= 0, the
plane y = 0 of symmetry; the default) and once as the whole cap (mesh.symmetry_plane = false: the half and its
mirror image, twice the cells). Prints, at common ubar, Ft, the contact area, the extents along x and y and the
stick area of both, and their largest relative differences; and the cost of each.

    OMP_NUM_THREADS=1 .venv/bin/python benchmarks/sphere_symmetry.py --size 220 --ubar-max 2.7
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from capslide.config import load_config
from capslide.driver.case import run_case
from capslide.params import Parameters
from capslide.states import Phase

QUANTITIES = ("Fn", "Ft", "area", "x_left", "x_right", "width_y", "area_stick")


def slide(size: float, ubar_max: float, symmetry_plane: bool):
    config = load_config(["sphere"], [f"mesh.size={size}", "loading.approach_edge_step=1.0",
                                      f"loading.ubar_max={ubar_max}", "loading.max_slide_step=0.1",
                                      "output.snapshot_ubar=[]", f"mesh.symmetry_plane={str(symmetry_plane).lower()}"])
    t0 = time.perf_counter()
    result = run_case(Parameters.from_config(config))
    records = [r for r in result.records if r.phase == Phase.SLIDE]
    return result, records, time.perf_counter() - t0


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--size", type=float, default=220.0)
    parser.add_argument("--ubar-max", type=float, default=2.7)
    args = parser.parse_args()
    runs = {name: slide(args.size, args.ubar_max, plane) for name, plane in (("half", True), ("whole", False))}
    for name, (result, recs, wall) in runs.items():
        print(f"{name}: {result.mesh.n_dofs:,} DOF, {len(recs)} slide steps, {wall:.0f} s, {result.status.label}, "
              f"onset ubar {result.scalars['onset_ubar']:.4f}, peak Ft {result.scalars['peak_Ft']:.5f}")
    half, whole = runs["half"][1], runs["whole"][1]
    u_half, u_whole = np.array([r.ubar for r in half]), np.array([r.ubar for r in whole])
    common = [u for u in (0.25, 0.5, 1.0, 1.5, 2.0, 2.5, args.ubar_max) if u <= min(u_half[-1], u_whole[-1])]
    print("\n| ubar | " + " | ".join(f"{q} half | {q} whole" for q in QUANTITIES) + " |")
    print("|---" * (1 + 2 * len(QUANTITIES)) + "|")
    worst = dict.fromkeys(QUANTITIES, 0.0)
    for u in common:
        row = [f"{u:g}"]
        for q in QUANTITIES:
            a = np.interp(u, u_half, [getattr(r, q) for r in half])
            b = np.interp(u, u_whole, [getattr(r, q) for r in whole])
            row += [f"{a:.5f}", f"{b:.5f}"]
            scale = max(abs(a), abs(b), 1e-9) if q not in ("x_left", "x_right", "Fn") else max(
                abs(half[-1].x_right - half[-1].x_left), 1.0)
            worst[q] = max(worst[q], abs(a - b) / scale)
        print("| " + " | ".join(row) + " |")
    print("\nlargest relative difference (x_left, x_right, Fn: relative to the contact's length):")
    for q, w in worst.items():
        print(f"  {q}: {w:.2e}")


if __name__ == "__main__":
    main()
