"""The 3D cap model against the Hertz sphere (issue 39, a first measurement before the 3D load path).

The `hertz` scene's law (repulsion only, frictionless, E = 2 MPa, nu = 0.4) on the H1 half model of a large
spherical cap (R = 100 L0, H = 50 L0, band radius 6 L0), pressed by the rigid flat under height control in equal
steps, each solved by Newton with pyamg's smoothed aggregation (BSR 3x3, six rigid-body modes) as the linear solver.
At each step: the load P = -Fn (the whole sphere, E L0^2), the contact radius from the pressure's second moment
(a^2 = 5/2 int p r^2 dA / int p dA, exact for the Hertz pressure), the radius of the area where Tn >= 0
(g_n <= g_eq, from the nodal gaps: loadpath/contact_patch.py), and the largest Gauss-point pressure, against Hertz
(a^3 = 3 P R / (4 E*), p0 = 3 P / (2 pi a^2)), and the moment radius and the peak against the same repulsive law on
a half-space at the same load (capslide.studies.halfspace_hertz: Hertz but for the law's compliance). --R 400 with
the depths scaled by 100 / R keeps the contact radii and quarters a / R (the finite strains).

    OMP_NUM_THREADS=1 .venv/bin/python benchmarks/hertz_sphere.py --h0 0.8 0.5 0.35 --depths 0.2 --R 100 400

Locking: Hertz depends on E* = E / (1 - nu^2) alone, so the error at nu = 0.49 or 0.499 measures the element's
volumetric locking (H1 displacement, or --formulation mixed: H1/P0, the mean dilatation):

    OMP_NUM_THREADS=1 .venv/bin/python benchmarks/hertz_sphere.py --h0 0.8 --depths 0.2 --nu 0.4 0.49 0.499 \
        --formulation displacement mixed
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np

from capslide.config import load_config
from capslide.fem.assembly import rigid_body_modes
from capslide.fem.hex_mesh import SphereCapSpec, sphere_cap_mesh
from capslide.laws import sphere
from capslide.loadpath.contact_patch import contact_patch
from capslide.loadpath.continuation import solve_constrained
from capslide.model.constraints import FixedHeight
from capslide.model.system import CapModel, History
from capslide.params import Parameters
from capslide.solvers.linsolve import make_solver
from capslide.solvers.newton import NewtonOptions
from capslide.studies.halfspace_hertz import hertz_law_reference


def run(h0: float, depths: list[float], nu: float = 0.4, formulation: str = "displacement", element: str = "H1",
        gauss: int = 2, R: float = 100.0) -> None:
    p = Parameters.from_config(load_config(["hertz"], overrides=[
        f"mesh.surface_gauss_points={gauss}", f"material.nu={nu}", f"mesh.formulation={formulation}",
        f"mesh.element={element}", "limits.refuse_locking=false", f"geometry.R={R}", "geometry.H=50",
        "mesh.band_half_width=6"]))
    mesh = sphere_cap_mesh(SphereCapSpec(R=R, H=50.0, h0=h0, band_radius=6.0, order=2 if element == "H2" else 1))
    model = CapModel(mesh, p, make_solver("amg", near_null_space=rigid_body_modes(mesh.nodes)))
    E_star = 1.0 / (1.0 - p.material.nu**2)
    x = np.zeros(mesh.n_dofs + 1)
    touch = 50.0 + p.adhesion.g_eq
    for depth in depths:
        x[-1] = touch - depth
        t = time.perf_counter()
        res, _ = solve_constrained(model, FixedHeight(touch - depth), History(), x, NewtonOptions())
        elapsed = time.perf_counter() - t
        if not res.converged:
            print(f"| {element} | {h0:g} | {nu:g} | {formulation} | {mesh.n_dofs} | {depth:g} | no equilibrium: "
                  f"{res.reason} |")
            return
        x = res.x
        u, h = x[:-1], x[-1]
        _, Fn, _ = model.contact.force(u, h)
        g, xs = model.contact.gaps(u, h)
        Tn, _ = model.contact.traction(g)
        Tn = np.maximum(Tn, 0.0)
        w = model.contact.quad.weight
        r2 = xs[..., 0] ** 2 + xs[..., 1] ** 2
        a_moment = sphere.hertz_moment_radius(Tn * w, r2)
        positions = mesh.nodes + u.reshape(-1, 3)
        patch = contact_patch(positions, h - positions[:, 2] - p.adhesion.g_eq, mesh.surface_quads,
                              model.contact.multiplicity)
        a_area = math.sqrt(patch.area / math.pi)
        P = -Fn  # the whole sphere's (the half model reports it)
        a_h = (3 * P * R / (4 * E_star)) ** (1 / 3)
        p0 = 3 * P / (2 * math.pi * a_h**2)
        law = hertz_law_reference(p, [P])[P]
        print(f"| {element} | {h0:g} | {R:g} | {nu:g} | {formulation} | {mesh.n_dofs} | {depth:g} | {P:.4g} "
              f"| {a_moment:.4f} | {a_area:.4f} | {a_h:.4f} "
              f"| {a_moment / a_h - 1:+.2%} | {a_area / a_h - 1:+.2%} | {Tn.max() / p0 - 1:+.2%} "
              f"| {a_moment / law.radius_moment - 1:+.2%} | {Tn.max() / law.peak_pressure - 1:+.2%} | {res.iterations} "
              f"| {res.linear_iterations} "
              f"| {elapsed:.1f} |", flush=True)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--h0", type=float, nargs="+", default=[0.5, 0.35])
    ap.add_argument("--depths", type=float, nargs="+", default=[0.05, 0.1, 0.2])
    ap.add_argument("--nu", type=float, nargs="+", default=[0.4])
    ap.add_argument("--formulation", nargs="+", default=["displacement"], choices=["displacement", "mixed"])
    ap.add_argument("--element", nargs="+", default=["H1"], choices=["H1", "H2"],
                    help="trilinear or triquadratic hexahedra (H2 with mixed: H2/P1)")
    ap.add_argument("--gauss", type=int, default=2, help="Gauss points per face edge of the contact integral")
    ap.add_argument("--R", type=float, nargs="+", default=[100.0],
                    help="sphere radii (L0); the depths scale as 100 / R, so that the contact radii stay")
    args = ap.parse_args()
    print("| element | h0 (L0) | R (L0) | nu | formulation | DOF | depth (L0) | P (E L0^2) | a, moment | a, Tn >= 0 "
          "| a, Hertz | a error | a error, Tn >= 0 | peak p error | a error, same law | peak p error, same law "
          "| Newton | CG | time (s) |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for R in args.R:
        for element in args.element:
            for h0 in args.h0:
                for nu in args.nu:
                    for formulation in args.formulation:
                        run(h0, [d * 100.0 / R for d in args.depths], nu, formulation, element, args.gauss, R)


if __name__ == "__main__":
    main()
