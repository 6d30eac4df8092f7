"""Study: Hertz half-width by element type, in current and reference coordinates.

Runs the Hertz scene (repulsion only) at the JKR scene's geometry (R = 1600 L0,
H = 1500 L0, band 95 L0; contact half-widths 30-80 L0, a/R = 0.02-0.05) for
each mesh variant and prints a Markdown table: contact half-width against
a = sqrt(4 P R / (pi E*)), measured in the current configuration (what the
verification reports) and on the reference surface (the material points in
contact; small-strain theory does not tell the two apart, they differ by the
tangential surface displacement at the edge, -(1 - 2 nu)(1 + nu) P / (2 E) on
a half-space, Johnson 1985, section 2.2), the L2 pressure error, DOF and time.

    OMP_NUM_THREADS=1 .venv/bin/python benchmarks/hertz_element.py --variant Q1:10 --variant Q2:20 --loads 1.5

A variant is ELEMENT:SIZE[:MAX_SIZE_OVER_H]. One case per variant and load
set; about 10-20 min per variant on one core.
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

from capslide.config import load_config
from capslide.laws import analytic, contact
from capslide.model.build import build_model
from capslide.params import Parameters
from capslide.studies.verification import force_controlled_sweep, pressure_error, reference_half_width

ROOT = Path(__file__).resolve().parents[1]
GEOMETRY = ["geometry.R=1600", "geometry.H=1500", "mesh.band_half_width=95"]


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--variant", action="append", default=[], metavar="EL:SIZE[:MAX]")
    ap.add_argument("--loads", type=float, nargs="+", default=[0.6, 1.5, 2.5, 3.7], metavar="P")
    args = ap.parse_args()
    loads = sorted(args.loads, reverse=True)
    print("| variant | DOF | P | a/R | half-width error, current | reference | pressure L2 / p0 | time (s) |")
    print("|---|---|---|---|---|---|---|---|")
    for variant in args.variant or ["Q1:10", "Q2:20"]:
        element, size, *rest = variant.split(":")
        overrides = [*GEOMETRY, f"mesh.element={element}", f"mesh.size={size}", f"verification.loads={loads}"]
        if rest:
            overrides.append(f"mesh.max_size_over_H={rest[0]}")
        params = Parameters.from_config(load_config([ROOT / "config" / "scenes" / "hertz.yaml"], overrides))
        t0 = time.perf_counter()
        model = build_model(params)
        states, _, _ = force_controlled_sweep(model, loads, [], None, adhesive=False)
        wall = time.perf_counter() - t0
        R = params.geometry.R
        E_star = analytic.effective_modulus(params.material.E, params.material.nu)
        for P in reversed(loads):
            rec = states[P]
            a_h = float(analytic.hertz_line_half_width(P, R, E_star))
            a = params.adhesion
            Tn, _ = contact.normal_traction(rec.gap, a.T0, a.r0, a.g_reg)
            cur, ref = 0.5 * rec.area_compressive, reference_half_width(model, rec, -Tn)
            print(f"| {variant} | {model.contact.n_dofs:,} | {P:g} | {a_h / R:.3f} | {100 * (cur / a_h - 1):+.2f} % "
                  f"| {100 * (ref / a_h - 1):+.2f} % | {100 * pressure_error(rec, P, R, E_star):.2f} % "
                  f"| {wall:.0f} |", flush=True)


if __name__ == "__main__":
    main()
