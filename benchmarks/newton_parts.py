"""Benchmark: cost of each part of a Newton iteration on the cap, per call.

Builds the cap model at one mesh level, puts the substrate at the apex
(substrate height H + 0.9 g_eq, small random displacement), and prints a
Markdown table of median times (ms) over repeats of: the deformation
gradient, first Piola stress, internal forces, stress and tangent, element
tangents, the CSR refill, the contact force and linearization, and the
model's residual, admissibility check and linearization as Newton calls them.

    OMP_NUM_THREADS=1 .venv/bin/python benchmarks/newton_parts.py --size 4 --set mesh.element=Q2
"""

from __future__ import annotations

import argparse
import statistics
import time
from pathlib import Path

import numpy as np

from capslide.config import load_config
from capslide.laws import material
from capslide.model.build import build_model
from capslide.model.constraints import FixedHeight
from capslide.model.system import History
from capslide.params import Parameters

CONFIG = Path(__file__).resolve().parents[1] / "config" / "config.yaml"


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--size", type=float, default=1.0)
    ap.add_argument("--repeats", type=int, default=9)
    ap.add_argument("--set", dest="overrides", action="append", default=[], metavar="KEY=VALUE")
    a = ap.parse_args()
    params = Parameters.from_config(load_config([CONFIG], [f"mesh.size={a.size}", "mesh.band_half_width=11.3516",
                                                           *a.overrides]))
    model = build_model(params)
    bulk = model.bulk
    x = np.zeros(model.n_dofs + 1)
    x[:-1] = 1e-4 * np.random.default_rng(0).standard_normal(model.n_dofs)
    x[-1] = params.geometry.H + 0.9 * params.adhesion.g_eq
    u, h, c = x[:-1], x[-1], FixedHeight(x[-1])
    F = bulk.deformation_gradient(u)
    P, A = material.first_piola_and_tangent(F, bulk.lam, bulk.mu)
    K_e = bulk.element_tangents(A)
    lin = model.contact.linearize(u, h, 0.0)

    def fresh(fn):  # a new state each call: no cached deformation gradient
        def call():
            x[0] += 1e-12
            return fn()
        return call

    parts = {
        "deformation gradient F": fresh(lambda: bulk.deformation_gradient(x[:-1])),
        "first Piola stress P(F)": lambda: material.first_piola(F, bulk.lam, bulk.mu),
        "internal forces from P": lambda: bulk.internal_force(P),
        "P and tangent A(F)": lambda: material.first_piola_and_tangent(F, bulk.lam, bulk.mu),
        "element tangents from A": lambda: bulk.element_tangents(A),
        "CSR refill": lambda: bulk.pattern.values(K_e),
        "contact force": lambda: model.contact.force(u, h, 0.0),
        "contact linearization": lambda: model.contact.linearize(u, h, 0.0),
        "model.residual (line search)": fresh(lambda: model.residual(x, c, History())),
        "model.admissible (min det F)": fresh(lambda: model.admissible(x)),
        "model.linearize": fresh(lambda: model.linearize(x, c, History())),
    }
    print(f"{params.mesh.element}, mesh.size {a.size}: {model.n_dofs + 1:,} DOF, {model.mesh.n_cells:,} cells, "
          f"{len(lin.active_segments)} of {len(model.contact.seg_dofs)} surface segments active; "
          f"median of {a.repeats} (ms)\n")
    print("| part | ms |\n|---|---|")
    for name, fn in parts.items():
        times = []
        for _ in range(a.repeats):
            t = time.perf_counter()
            fn()
            times.append(time.perf_counter() - t)
        print(f"| {name} | {1e3 * statistics.median(times):.2f} |")


if __name__ == "__main__":
    main()
