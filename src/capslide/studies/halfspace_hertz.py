"""The same-law reference of the Hertz sphere: the configuration's repulsive law (``contact.repulsion_only``: the
normal law's compressive part max(Tn, 0)) on a linear elastic half-space with the sphere's profile
(:class:`capslide.studies.halfspace_sphere.SphereOnHalfSpace`, the contact edge where Tn falls to zero).

Hertz assumes a rigid interface; the law is a stiff spring whose compression flattens the pressure: on the
``sphere_hertz`` scene its peak lies 0.47 to 0.67 % below Hertz's p0 and its second-moment radius 0.34 to 0.48 %
above (docs/three_d.md). So the FE is checked against Hertz and, apart from that law's compliance, against this
reference; what is left is the mesh, the finite strains and the body's finite size.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from scipy.interpolate import CubicSpline

from ..laws import analytic, sphere
from ..laws.normal import normal_law
from ..params import Parameters
from .halfspace_sphere import SphereOnHalfSpace, cut_traction

__all__ = ["repulsive", "HertzLawState", "hertz_law_reference"]

RINGS_ON_BAND = 600  # ring width: the contact band's radius / 600 (0.01 L0 on sphere_hertz; 0.02 L0 moves the
#                      peak and the radius by less than 0.05 %)
RADIUS_STEP = 0.1  # the reference path's step in the edge radius (L0)


def repulsive(traction: Callable) -> Callable:
    """The compressive part of ``traction`` (g -> (Tn, dTn/dg)): max(Tn, 0), its slope zero where Tn <= 0."""
    def compressive(g):
        Tn, dTn = traction(g)
        pushes = Tn > 0.0
        return np.where(pushes, Tn, 0.0), np.where(pushes, dTn, 0.0)
    return compressive


@dataclass(frozen=True)
class HertzLawState:
    """The repulsive law's half-space sphere at the load ``P`` (E L0^2, compressive positive): the contact radius
    from the pressure's second moment (a^2 = 5/2 int p r^2 dA / int p dA, as the FE's) and the peak pressure
    (E), both interpolated along the edge path."""

    P: float
    radius_moment: float
    peak_pressure: float


def hertz_law_reference(params: Parameters, loads: list[float]) -> dict[float, HertzLawState]:
    """At each load P (E L0^2, compressive positive) of ``loads``: the scene's repulsive law on a half-space with
    the sphere's profile and its contact band, from an edge path of RADIUS_STEP steps around Hertz's radii."""
    R, ad = params.geometry.R, params.adhesion
    E_star = analytic.effective_modulus(params.material.E, params.material.nu)
    band = params.mesh.band_half_width
    halfspace = SphereOnHalfSpace(repulsive(cut_traction(normal_law(ad), params.contact.far_gap)), R, E_star, band,
                                  band / RINGS_ON_BAND, ad.g_eq)
    a_hertz = [float(sphere.hertz_sphere_radius(P, R, E_star)) for P in loads]
    radii = np.arange(0.8 * min(a_hertz), min(1.2 * max(a_hertz), 0.9 * band) + RADIUS_STEP, RADIUS_STEP)
    path = halfspace.edge_path(radii)
    P = np.array([s.P for s in path])
    if not P[0] <= min(loads) <= max(loads) <= P[-1]:
        raise ValueError(f"loads {loads} outside the reference path's [{P[0]:.4g}, {P[-1]:.4g}]")
    moment = [sphere.hertz_moment_radius(s.Tn * halfspace.ring_area, halfspace.r**2) for s in path]
    radius_at, peak_at = CubicSpline(P, moment), CubicSpline(P, [s.Tn.max() for s in path])
    return {L: HertzLawState(L, float(radius_at(L)), float(peak_at(L))) for L in loads}
