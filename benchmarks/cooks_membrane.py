"""Cook's membrane (capslide.studies.membrane): the tip deflection of each bulk element against mesh refinement.

Two settings: the compressible linear one (plane strain, E = 70, nu = 1/3, load 100; very fine quadratic meshes
give 32.27, CoFEA benchmark 002) checks the setup; the nearly incompressible finite-strain one (mu = 80.1938,
bulk modulus 400942, nu = 0.4999, load 100; de Souza Neto et al. 1996) shows locking: OpenGeoSys's F-bar Q1
benchmark gives 6.891 on 30 x 30 cells. The last column extrapolates the mixed element's three finest meshes
(Richardson with the observed order).

    OMP_NUM_THREADS=1 .venv/bin/python benchmarks/cooks_membrane.py --n 4 8 16 32
"""

from __future__ import annotations

import argparse
import math
import time

from capslide.studies.membrane import tip_deflection

ELEMENTS = {"Q1": ("Q1", "displacement"), "Q2": ("Q2", "displacement"), "Q2/P1 mixed": ("Q2", "mixed")}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, nargs="+", default=[4, 8, 16, 32], help="cells per side")
    ap.add_argument("--steps", type=int, default=20, help="load increments of the finite-strain setting")
    a = ap.parse_args()
    E, nu = 70.0, 1.0 / 3.0
    settings = {
        "compressible, linear (reference 32.27)": (E * nu / ((1 + nu) * (1 - 2 * nu)), E / (2 * (1 + nu)), 1e-4, 1),
        "nu = 0.4999, finite strain (F-bar Q1 30 x 30: 6.891)": (400942.0 - 2 * 80.1938 / 3, 80.1938, 100.0, a.steps),
        "nu = 0.5, finite strain": (math.inf, 80.1938, 100.0, a.steps),
    }
    for title, (lam, mu, load, steps) in settings.items():
        print(f"\n{title}\n")
        print("| element | " + " | ".join(f"n = {n}" for n in a.n) + " | wall (s) |")
        print("|---|" + "---|" * len(a.n) + "---|")
        extra = []
        for name, (element, formulation) in ELEMENTS.items():
            if math.isinf(lam) and formulation != "mixed":
                continue
            t0, tips = time.perf_counter(), []
            for n in a.n:
                try:
                    tip = tip_deflection(n, lam, mu, load, element, formulation, steps).tip * 100.0 / load
                except RuntimeError:
                    tip = math.nan
                tips.append(tip)
            print(f"| {name} | " + " | ".join(f"{t:.4f}" for t in tips) + f" | {time.perf_counter() - t0:.1f} |",
                  flush=True)
            if formulation == "mixed" and len(tips) >= 3:
                d1, d2 = tips[-2] - tips[-3], tips[-1] - tips[-2]
                if d1 * d2 > 0 and abs(d2) < abs(d1):
                    extra.append(f"{name}, extrapolated from n = {a.n[-3]}, {a.n[-2]}, {a.n[-1]} (observed order "
                                 f"{math.log2(d1 / d2):.2f}): {tips[-1] + d2 ** 2 / (d1 - d2):.4f}")
        print("\n".join(["", *extra]) if extra else "")


if __name__ == "__main__":
    main()
