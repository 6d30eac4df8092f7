"""A Dugdale sphere sweep's loads against Maugis-Dugdale: at each force-controlled load of a verification sweep's
checkpoint, the FE's level radius, the FE against its law's half-space path at that radius (FE - law), the law's
load against Maugis-Dugdale's at the law's contact radius (law - MD), their sum (FE - MD), and FE - MD read at the
area's radius; then the pull-off, and FE - law at each edge-controlled state past the pull-off (a / a_c: a_c the
law's pull-off radius).

The law's path is stepped by the level gap and interpolated (cubic spline) in the level radius; its contact radius,
where the gap meets g_max with a small slope, is uncertain by some tenths of a percent of |P_c| in "law - MD"
(docs/three_d.md). Loads in % of Maugis-Dugdale's |P_c|, "+" the FE less tensile. `capslide verify` deletes its
checkpoint when the table is written: copy it while the sweep runs.

    OMP_NUM_THREADS=1 .venv/bin/python benchmarks/sphere_loads_against_md.py CHECKPOINT.npz [--set KEY=VALUE ...]
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np
from scipy.interpolate import CubicSpline

from capslide.config import load_config, scene_path
from capslide.io.checkpoint import read_arrays, records_in
from capslide.laws import analytic, sphere
from capslide.params import Parameters
from capslide.states import Phase
from capslide.studies.halfspace_sphere import SameLawReference, halfspace_of, pull_off, reference_radii
from capslide.studies.verification import pull_off_reference
from capslide.studies.verification_3d import LEVEL_OVER_RANGE, level_radius


def loads_table(params: Parameters, checkpoint: Path) -> None:
    ad = params.adhesion
    level = ad.g_eq + LEVEL_OVER_RANGE * ad.W_adh / ad.T_max
    E_star = analytic.effective_modulus(params.material.E, params.material.nu)
    lam = sphere.maugis_parameter_sphere(params.geometry.R, E_star, ad.W_adh, ad.T_max)
    scales = sphere.md_scales(params.geometry.R, E_star, ad.W_adh)
    P_c = pull_off_reference(params)
    data = read_arrays(checkpoint)
    records = records_in(data)

    def md_load(a: float) -> float:
        return float(sphere.md_load(a / scales["radius"], lam)) * scales["load"]

    loads = sorted((-r.Fn, level_radius(r.x_surface, r.y_surface, r.gap, level), np.sqrt(r.area / np.pi))
                   for r in records if r.phase == Phase.PRELOAD)
    halfspace = halfspace_of(params, edge_gap=level)
    path = halfspace.edge_path(reference_radii(params, 1.02 * max(a for _, a, _ in loads)))
    law = SameLawReference(np.array([s.a for s in path]), np.array([s.P for s in path]), *pull_off(path))

    def contact_radius(sol) -> float:  # where the law's gap meets g_max, linear between its rings
        i = int(np.argmax(sol.g > ad.g_max))
        r, g = halfspace.r, sol.g
        return float(r[i - 1] + (r[i] - r[i - 1]) * (ad.g_max - g[i - 1]) / (g[i] - g[i - 1]))

    contact_at = CubicSpline(law.radii, [contact_radius(s) for s in path])
    print("| P (E L0^2) | a, level | a, area | law's contact radius | FE - law | law - MD | FE - MD "
          "| FE - MD, the area's radius |")
    print("|---|---|---|---|---|---|---|---|")
    for P, a_level, a_area in loads:
        P_law, a_law = law.load_at(a_level), float(contact_at(a_level))
        print(f"| {P:+.1f} | {a_level:.3f} | {a_area:.3f} | {a_law:.3f} | {(P - P_law) / abs(P_c):+.2%} "
              f"| {(P_law - md_load(a_law)) / abs(P_c):+.2%} | {(P - md_load(a_law)) / abs(P_c):+.2%} "
              f"| {(P - md_load(a_area)) / abs(P_c):+.2%} |")
    F_max = max(r.Fn for r in records if r.phase == Phase.SPREAD)
    print(f"\npull-off: FE {-F_max:.4f}, Maugis-Dugdale {P_c:.4f} ({(-F_max - P_c) / abs(P_c):+.2%}), its law "
          f"{law.P_c:.4f} ({(-F_max - law.P_c) / abs(law.P_c):+.2%}) E L0^2")
    past = []
    for r in records:
        a_level = level_radius(r.x_surface, r.y_surface, r.gap, level) if r.phase == Phase.SPREAD else np.nan
        if np.isfinite(a_level) and law.a_c <= a_level <= law.radii[-1]:
            past.append(f"{a_level / law.a_c:.2f}: {(-r.Fn - law.load_at(a_level)) / abs(P_c):+.2%}")
    print("edge-controlled states past the pull-off (a / a_c: FE - law): " + ", ".join(past))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("checkpoint", type=Path)
    ap.add_argument("--scene", default="sphere_dugdale3")
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE", help="the sweep's --set options")
    args = ap.parse_args()
    loads_table(Parameters.from_config(load_config([scene_path(args.scene)], args.set)), args.checkpoint)


if __name__ == "__main__":
    main()
