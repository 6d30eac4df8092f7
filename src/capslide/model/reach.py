"""What a preload to a contact area (``loading.preload_area``) can reach, known before anything is computed.

The contact lies on the cap's top surface: its area is below the top's (2 pi R H in 3D, L0^2, the whole body's; the
arc's length in 2D, L0). A preload under force control cannot hold an adhesive sphere's contact below its pull-off
radius: the Maugis-Dugdale sphere's (Maugis 1992) at the configuration's Maugis parameter bounds it, and areas below
half of that are refused for sure (the FE's law and mesh move the pull-off area by a few per cent, the 3D
verification in docs/three_d.md). Areas between are reached, or reported at run time
(:func:`capslide.loadpath.preload_targets.area_unreachable`).
"""

from __future__ import annotations

import math

from ..config import SPHERE_ELEMENTS, ConfigError
from ..config_rules import top_surface
from ..laws import analytic, sphere
from ..params import Parameters

__all__ = ["SURE_BELOW_PULL_OFF", "md_pull_off_area", "preload_area_bounds", "check_preload_area"]

SURE_BELOW_PULL_OFF = 0.5  # areas below this share of the Maugis-Dugdale pull-off area are refused


def md_pull_off_area(params: Parameters) -> float:
    """The Maugis-Dugdale sphere's contact area at pull-off under load control (L0^2), at the configuration's
    Maugis parameter (sigma0 = T_max, internal units E = L0 = 1)."""
    mat, adh, R = params.material, params.adhesion, params.geometry.R
    E_star = analytic.effective_modulus(mat.E, mat.nu)
    lam = sphere.maugis_parameter_sphere(R, E_star, adh.W_adh, adh.T_max)
    _, A = sphere.md_pull_off(lam)
    return math.pi * (A * sphere.md_scales(R, E_star, adh.W_adh)["radius"]) ** 2


def preload_area_bounds(params: Parameters) -> tuple[float, float]:
    """(smallest, largest) area a preload to an area can hold, in the units of ``loading.preload_area``; the
    smallest is 0 without adhesion, and in 2D."""
    three_d = params.mesh.element in SPHERE_ELEMENTS
    smallest = SURE_BELOW_PULL_OFF * md_pull_off_area(params) if three_d and not params.contact.repulsion_only else 0.0
    return smallest, top_surface(params.config)


def check_preload_area(params: Parameters) -> None:
    """ConfigError (one line naming ``loading.preload_area`` and its value) when no preload can reach the area."""
    area = params.loading.preload_area
    if area is None:
        return
    smallest, largest = preload_area_bounds(params)
    three_d = params.mesh.element in SPHERE_ELEMENTS
    unit, where = ("L0^2", "the cap's top surface 2 pi R H") if three_d else ("L0", "the cap's top arc")
    if area >= largest:
        raise ConfigError(f"loading.preload_area = {area!r} is not allowed here: beyond {where} = {largest:.6g} {unit} "
                          "(the area is the whole body's, in L0 units)")
    if area < smallest:
        raise ConfigError(f"loading.preload_area = {area!r} is not allowed here: below half of the Maugis-Dugdale "
                          f"sphere's pull-off area ({smallest / SURE_BELOW_PULL_OFF:.6g} {unit}): no preload holds so "
                          "small a contact (the area is the whole body's, in L0 units)")
