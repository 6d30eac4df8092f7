"""Where the FE sphere's load departs from its law's: the FE's normal traction against the same law's half-space
solution (capslide.studies.halfspace_sphere, the path stepped by the level gap) at the same level radius a, summed
over bands of r - a, for each spread and load state of a verification sweep's checkpoint.

`capslide verify` deletes its sweep checkpoint when the table is written; copy it while the sweep runs (docs/
three_d.md). The checkpoint's arrays are read without the code-version check that a resume makes: only the records
are used. Loads relative to the law's |P_c| (its path runs past the pull-off whether or not the sweep did), "+" the FE
less tensile.

    OMP_NUM_THREADS=1 .venv/bin/python benchmarks/sphere_load_by_band.py CHECKPOINT.npz [--scene sphere_dugdale3]
        [--set KEY=VALUE ...] [--from-radius 7] [--band-scale 4.6416]

--band-scale multiplies the bands' edges, so that a sphere whose mesh is scaled with Maugis-Dugdale's lengths (R =
1000 L0: (R / 100 L0)^(2/3) = 4.6416) is read in the same bands as R = 100 L0.
"""

from __future__ import annotations

import argparse
import math
from pathlib import Path

import numpy as np

from capslide.config import load_config, scene_path
from capslide.fem.surface import SurfaceQuadrature
from capslide.io.checkpoint import read_arrays, records_in
from capslide.laws import analytic, sphere
from capslide.model.build import mesh_of
from capslide.params import Parameters
from capslide.states import Phase
from capslide.studies.halfspace_sphere import halfspace_of, pull_off, reference_radii
from capslide.studies.verification_3d import LEVEL_OVER_RANGE, level_radius

BANDS = (-math.inf, -3.0, -1.0, -0.4, 0.0, 0.4, math.inf)  # r - a (L0)


def band_table(params: Parameters, checkpoint: Path, from_radius: float, band_scale: float = 1.0) -> None:
    ad = params.adhesion
    level = ad.g_eq + LEVEL_OVER_RANGE * ad.W_adh / ad.T_max
    data = read_arrays(checkpoint)
    records = records_in(data)
    mesh = mesh_of(params)
    weight = SurfaceQuadrature.on(mesh, params.mesh.surface_gauss_points).weight.ravel() * (2.0 if len(mesh.symmetry) else 1.0)
    states = [(i, rec, level_radius(rec.x_surface, rec.y_surface, rec.gap, level)) for i, rec in enumerate(records)
              if rec.phase in (Phase.SPREAD, Phase.PRELOAD)]
    states = [(i, rec, a) for i, rec, a in states if math.isfinite(a) and a >= from_radius]
    halfspace = halfspace_of(params, edge_gap=level)
    E_star = analytic.effective_modulus(params.material.E, params.material.nu)
    past_pull_off = 1.5 * sphere.md_scales(params.geometry.R, E_star, ad.W_adh)["radius"]  # JKR's: 1.04 of the scale
    P_c, _ = pull_off(halfspace.edge_path(reference_radii(params, max(1.02 * max(a for _, _, a in states),
                                                                      past_pull_off))))
    bands = tuple(band_scale * b for b in BANDS)
    names = [f"{lo:.4g} to {hi:.4g}" for lo, hi in zip(bands[:-1], bands[1:])]
    print(f"| record | phase | a, level (L0) | P, FE | P, law | P - P_law | {' | '.join(names)} |")
    print("|" + "---|" * (6 + len(names)))
    start = None
    for i, rec, a in states:
        sol = halfspace.solve_at_edge(a, start)
        start = (sol.g, sol.delta)
        r = np.hypot(rec.x_surface, rec.y_surface)
        P_fe = float(np.sum(rec.traction_n * weight))
        parts = []
        for lo, hi in zip(bands[:-1], bands[1:]):
            fe = (r - a >= lo) & (r - a < hi)
            law = (halfspace.r - a >= lo) & (halfspace.r - a < hi)
            diff = np.sum(rec.traction_n[fe] * weight[fe]) - np.sum(sol.Tn[law] * halfspace.ring_area[law])
            parts.append(f"{diff / abs(P_c):+.2%}")
        print(f"| {i} | {rec.phase.name.lower()} | {a:.3f} | {P_fe:+.3f} | {sol.P:+.3f} | {(P_fe - sol.P) / abs(P_c):+.2%} "
              f"| {' | '.join(parts)} |", flush=True)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("checkpoint", type=Path)
    ap.add_argument("--scene", default="sphere_dugdale3")
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE", help="the sweep's --set options")
    ap.add_argument("--from-radius", type=float, default=7.0, help="the smallest level radius shown (L0)")
    ap.add_argument("--band-scale", type=float, default=1.0,
                    help="multiplies the bands' edges: (R / 100 L0)^(2/3) on a sphere scaled from R = 100 L0")
    args = ap.parse_args()
    band_table(Parameters.from_config(load_config([scene_path(args.scene)], args.set)), args.checkpoint,
               args.from_radius, args.band_scale)


if __name__ == "__main__":
    main()
