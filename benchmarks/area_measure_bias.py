"""How far the FE's two contact radii read from a mesh's nodes lie from the exact edge, on the same law's exact
gap profile (capslide.studies.halfspace_sphere: the scene's law on a half-space with the sphere's profile).

The profile at each radius of the law's edge-controlled path is sampled at nodes a ring width apart (40 offsets
of the nodes across one ring), and read as the FE reads its nodal gaps, interpolated linearly between nodes:
- the contact edge, where the gap rises through g_max (the contact area's radius, sqrt(A / pi)): the gap touches
  g_max with zero slope (the opening grows as the distance to the power 3/2), so the crossing falls near the last
  node inside;
- the level radius, where it rises through g_eq + 0.3 W_adh / T_max (capslide.studies.verification_3d), inside the
  cohesive zone where the opening's slope is finite.
Each reading's error, and the load error it makes, P_law(r) - P_law(r_exact) with the sign of P - P_law(r_read)
(so "+" is the FE lying less tensile than its law), relative to the law's |P_c|: mean and range over the offsets.

    OMP_NUM_THREADS=1 .venv/bin/python benchmarks/area_measure_bias.py [--scene sphere_dugdale3] [--widths 0.2 0.1]
"""

from __future__ import annotations

import argparse

import numpy as np
from scipy.interpolate import CubicSpline

from capslide.config import load_config, scene_path
from capslide.params import Parameters
from capslide.studies.halfspace_sphere import halfspace_of, pull_off, reference_radii
from capslide.studies.verification_3d import LEVEL_OVER_RANGE, level_radius

RADII = (5.0, 7.0, 9.0, 10.0, 11.0, 11.5, 12.0, 12.5)  # L0, exact radii of the gap read
OFFSETS = 40


def read_crossing(r: np.ndarray, gap: np.ndarray, level: float, width: float, offset: float) -> float:
    """Where the gap (on the fine radii r) first rises through ``level``, read as the FE reads it
    (:func:`level_radius` on one radial line of nodes ``width`` apart, starting at ``offset``)."""
    nodes = np.arange(offset, r[-1], width)
    return level_radius(nodes, np.zeros_like(nodes), np.interp(nodes, r, gap), level)


def table(params: Parameters, widths: list[float]) -> None:
    ad = params.adhesion
    levels = {"contact edge (area)": ad.g_max, "level radius": ad.g_eq + LEVEL_OVER_RANGE * ad.W_adh / ad.T_max}
    print("| reading | ring width (L0) | exact r (L0) | P (E L0^2) | radius error (L0), mean [range] | "
          "P - P_law(r read), of |P_c|, mean [range] |\n|---|---|---|---|---|---|")
    for name, level in levels.items():
        halfspace = halfspace_of(params, edge_gap=level)
        path = halfspace.edge_path(np.union1d(reference_radii(params, max(RADII) + 0.5), RADII))
        P_c, _ = pull_off(path)
        load_at = CubicSpline([s.a for s in path], [s.P for s in path])
        for width in widths:
            for sol in (s for s in path if np.any(np.isclose(s.a, RADII, rtol=0.0, atol=1e-12))):
                read = np.array([read_crossing(halfspace.r, sol.g, level, width, o)
                                 for o in np.linspace(0.0, width, OFFSETS, endpoint=False)])
                dP = -(load_at(read) - sol.P) / abs(P_c)
                err = read - sol.a
                print(f"| {name} | {width:g} | {sol.a:g} | {sol.P:+.3f} | {err.mean():+.4f} [{err.min():+.4f}, "
                      f"{err.max():+.4f}] | {dP.mean():+.2%} [{dP.min():+.2%}, {dP.max():+.2%}] |")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scene", default="sphere_dugdale3")
    ap.add_argument("--widths", type=float, nargs="+", default=[0.2, 0.1, 0.05], help="ring widths (L0)")
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE")
    args = ap.parse_args()
    table(Parameters.from_config(load_config([scene_path(args.scene)], args.set)), args.widths)


if __name__ == "__main__":
    main()
