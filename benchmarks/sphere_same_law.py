"""The adhesive sphere's law against Maugis-Dugdale, and the FE path against both.

The scene's normal law (CGCM, or Dugdale's with --scenes sphere_dugdale3) on an elastic half-space
(capslide.studies.halfspace_sphere: same law, band and far gap, the sphere's profile) against the Maugis-Dugdale
sphere at the scene's lambda: the law's shape, apart from any mesh.
Variants: the paraboloid r^2 / 2R (Maugis-Dugdale's profile) and a band of 40 L0, times (R / 100 L0)^(2/3) (the
law's tail kept; at lambda = 5 that is 2,600 rings, about 20 minutes). With ``--log``, the edge-controlled path
of a `capslide verify` log (its `spread` and `preload` lines) against both.
Loads P = -Fn (E L0^2, compressive positive), errors relative to Maugis-Dugdale's |P_c|.

    OMP_NUM_THREADS=1 .venv/bin/python benchmarks/sphere_same_law.py [--scenes sphere_md3 sphere_md5] [--log LOG]
        [--set adhesion.maugis_lambda=2]
"""

from __future__ import annotations

import argparse
import math
import re

import numpy as np
from scipy.optimize import brentq

from capslide.config import load_config, scene_path
from capslide.laws import analytic, sphere
from capslide.params import Parameters
from capslide.studies.halfspace_sphere import same_law_reference

RADII = (1.0, 2.0, 4.0, 6.0, 7.0, 8.0, 9.0, 10.0, 11.0, 12.0)  # L0 at R = 100 L0; x (R / 100 L0)^(2/3) otherwise
LINE = re.compile(r"(spread|preload)\s+ubar=.*Fn=([+-][\d.]+).*area=\s*([\d.]+)")


def length_scale(params: Parameters) -> float:
    """(R / 100 L0)^(2/3): Maugis-Dugdale's lengths at fixed lambda grow as R^(2/3), so RADII and the wide band
    scale with it (1 on the scenes' R = 100 L0)."""
    return (params.geometry.R / 100.0) ** (2.0 / 3.0)


def md(params: Parameters):
    """(lambda, the Maugis-Dugdale load at radius a, P_c, the scales of sphere.md_scales) of a configuration."""
    a, R = params.adhesion, params.geometry.R
    E_star = analytic.effective_modulus(params.material.E, params.material.nu)
    lam = sphere.maugis_parameter_sphere(R, E_star, a.W_adh, a.T_max)
    scales = sphere.md_scales(R, E_star, a.W_adh)
    P_c = sphere.md_pull_off(lam)[0] * scales["load"]
    return lam, lambda r: float(sphere.md_load(r / scales["radius"], lam)) * scales["load"], P_c, scales


def zero_load_radius(ref) -> float:
    """The contact radius at P = 0 on the stable branch (past the pull-off) of a reference path."""
    beyond = ref.radii > ref.a_c
    return brentq(ref.load_at, ref.a_c, float(ref.radii[beyond][np.argmax(ref.loads[beyond] > 0.0)]), xtol=1e-10)


def law_table(scene: str, overrides: list[str]) -> None:
    params = Parameters.from_config(load_config([scene_path(scene)], overrides))
    lam, md_load, P_c, md_scale = md(params)
    scale = md_scale["radius"]
    a0_md, a0_jkr = sphere.md_zero_load_radius(lam) * scale, 6.0 ** (1.0 / 3.0) * scale
    k = length_scale(params)
    radii, reach = [k * r for r in RADII], k * (max(RADII) + 0.5)
    wide = Parameters.from_config(load_config([scene_path(scene)], [*overrides, f"mesh.band_half_width={40 * k:g}"]))
    refs = {"sphere, band": same_law_reference(params, reach),
            "paraboloid, band": same_law_reference(params, reach, profile="paraboloid"),
            f"paraboloid, {40 * k:.4g} L0": same_law_reference(wide, reach, profile="paraboloid")}
    print(f"\n{scene}: lambda = {lam:.3f}, Maugis-Dugdale P_c = {P_c:.4f} E L0^2, band {params.mesh.band_half_width:g} L0")
    print(f"zero-load radius: Maugis-Dugdale {a0_md:.4f} L0, JKR {a0_jkr:.4f} L0")
    print("| same law on | pull-off P_c | against MD | radius a_c | zero-load area against MD | against JKR | "
          + " | ".join(f"a = {r:.4g}" for r in radii) + " |")
    print("|---" * (6 + len(radii)) + "|")
    for name, ref in refs.items():
        diffs = " | ".join(f"{(ref.load_at(r) - md_load(r)) / abs(P_c):+.2%}" for r in radii)
        a0 = zero_load_radius(ref)
        print(f"| {name} | {ref.P_c:.4f} | {(ref.P_c - P_c) / abs(P_c):+.2%} | {ref.a_c:.3f} | {(a0 / a0_md) ** 2 - 1:+.2%} "
              f"| {(a0 / a0_jkr) ** 2 - 1:+.2%} | {diffs} |")
    print("(the columns a = ...: P_same_law(a) - P_MD(a), relative to |P_c|)")


def log_table(scene: str, log: str, overrides: list[str]) -> None:
    params = Parameters.from_config(load_config([scene_path(scene)], overrides))
    lam, md_load, P_c, md_scale = md(params)
    points = []
    for line in open(log):
        m = LINE.match(line)
        if m and float(m.group(3)) > 0.0:
            points.append((m.group(1), math.sqrt(float(m.group(3)) / math.pi), -float(m.group(2))))
    # the reference reaches past the pull-off, so that a log that ends before it reads too
    a_c_md = sphere.md_pull_off(lam)[1] * md_scale["radius"]
    ref = same_law_reference(params, max(1.02 * max(a for _, a, _ in points), 1.2 * a_c_md))
    print(f"\n{log}: {len(points)} states of {scene}")
    print("| step | a (L0) | P (E L0^2) | FE - same law | same law - MD | FE - MD |")
    print("|---|---|---|---|---|---|")
    for kind, a, P in points:
        if a < ref.radii[0]:
            continue  # below the reference's first radius
        same, ref_md = ref.load_at(a), md_load(a)
        print(f"| {kind} | {a:.3f} | {P:+.4f} | {(P - same) / abs(P_c):+.2%} | {(same - ref_md) / abs(P_c):+.2%} "
              f"| {(P - ref_md) / abs(P_c):+.2%} |")
    print("\nthe sweep's loads (force-controlled equilibria):")
    print("| P (E L0^2) | a, FE (L0) | a, the law | a against the law's | a, MD | a against MD | P - P_law(a), of the "
          "law's \\|P_c\\| | P - P_MD(a), of MD's \\|P_c\\| |")
    print("|---" * 8 + "|")
    for kind, a, P in points:
        if kind != "preload":
            continue
        a_law = brentq(lambda r, P=P: ref.load_at(r) - P, ref.a_c, ref.radii[-1])
        a_md = sphere.md_radius(P / md_scale["load"], lam) * md_scale["radius"]
        print(f"| {P:+.1f} | {a:.3f} | {a_law:.3f} | {100 * (a / a_law - 1):+.2f} % | {a_md:.3f} "
              f"| {100 * (a / a_md - 1):+.2f} % | {100 * (P - ref.load_at(a)) / abs(ref.P_c):+.2f} % "
              f"| {100 * (P - md_load(a)) / abs(P_c):+.2f} % |")
    P_fe = min(P for kind, _, P in points if kind == "spread")
    print(f"pull-off along the path: FE {P_fe:.4f}, same law {ref.P_c:.4f} ({(P_fe - ref.P_c) / abs(ref.P_c):+.2%}), "
          f"Maugis-Dugdale {P_c:.4f} ({(P_fe - P_c) / abs(P_c):+.2%})")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scenes", nargs="+", default=["sphere_md3", "sphere_md5"])
    ap.add_argument("--log", help="a `capslide verify` or `capslide run` log of the first scene, run with the same --set")
    ap.add_argument("--set", dest="overrides", action="append", default=[], metavar="KEY=VALUE")
    args = ap.parse_args()
    for scene in args.scenes:
        law_table(scene, args.overrides)
    if args.log:
        log_table(args.scenes[0], args.log, args.overrides)


if __name__ == "__main__":
    main()
