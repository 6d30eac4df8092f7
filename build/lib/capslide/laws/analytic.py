"""Closed-form contact solutions used as references (Hertz and JKR).

Conventions of this module: the load P is positive when COMPRESSIVE (the
classical contact-mechanics sign, opposite to capslide's Fn). E_star is the
plane-strain modulus of the elastic body against a rigid counterpart,
E* = E / (1 - nu^2). Line-contact (cylinder) loads are per unit length;
sphere loads are forces. w is the work of adhesion (energy per area).
"""

from __future__ import annotations

import math

import numpy as np
from scipy.optimize import brentq

__all__ = [
    "effective_modulus",
    "hertz_line_half_width",
    "hertz_line_load",
    "hertz_line_pressure",
    "jkr_cylinder_load",
    "jkr_cylinder_critical_half_width",
    "jkr_cylinder_pull_off",
    "jkr_cylinder_half_width",
    "maugis_parameter_cylinder",
    "jkr_sphere_load",
    "jkr_sphere_critical_radius",
    "jkr_sphere_pull_off",
    "jkr_sphere_radius",
]


def effective_modulus(E: float, nu: float) -> float:
    """E* = E / (1 - nu^2) of an elastic body on a rigid one."""
    return E / (1.0 - nu**2)


# --- Hertz line contact --------------------------------------------------
def hertz_line_half_width(P, R: float, E_star: float):
    """Hertz half-width of a cylinder on a flat: a = sqrt(4 P R / (pi E*)).

    Johnson, Contact Mechanics (CUP 1985), section 4.3 (two-dimensional Hertz
    contact) with a rigid counterpart. P per unit length (compressive > 0).
    """
    return np.sqrt(4.0 * np.asarray(P, dtype=float) * R / (math.pi * E_star))


def hertz_line_load(a, R: float, E_star: float):
    """Inverse of :func:`hertz_line_half_width`: P = pi E* a^2 / (4 R)."""
    return math.pi * E_star * np.asarray(a, dtype=float) ** 2 / (4.0 * R)


def hertz_line_pressure(x, P: float, R: float, E_star: float):
    """Hertz line-contact pressure p(x) = (2P / (pi a^2)) sqrt(a^2 - x^2), 0 outside.

    Johnson (1985), section 4.3; peak p0 = 2P / (pi a). Compressive > 0.
    """
    x = np.asarray(x, dtype=float)
    a = float(hertz_line_half_width(P, R, E_star))
    return 2.0 * P / (math.pi * a**2) * np.sqrt(np.clip(a**2 - x**2, 0.0, None))


def _jkr_root(load, P: float, a_c: float, hertz_guess: float, branch: str) -> float:
    """Contact size where load(a) = P on the stable (a >= a_c) or unstable (a < a_c) JKR branch."""
    P_c = load(a_c)
    if P < P_c:
        raise ValueError(f"load {P} is below the JKR pull-off load {P_c}")
    f = lambda a: load(a) - P  # noqa: E731
    if branch == "stable":
        return a_c if P == P_c else _bracketed_root(f, a_c, max(2.0 * a_c, hertz_guess, 1e-300))
    if branch == "unstable":
        if P >= 0.0:
            raise ValueError("the unstable JKR branch exists only for tensile loads (P < 0)")
        return a_c if P == P_c else brentq(f, 0.0, a_c, xtol=1e-16 * a_c, rtol=1e-14, maxiter=500)
    raise ValueError(f"branch must be 'stable' or 'unstable', not {branch!r}")


# --- JKR cylinder (2D, plane strain) --------------------------------------
def jkr_cylinder_load(a, R: float, E_star: float, w: float):
    """JKR load per unit length at half-width a for a cylinder on a flat.

    P = pi E* a^2 / (4 R) - sqrt(2 pi E* w a)
    (Barquins, J. Adhesion 26 (1988) 1; Chaudhury, Weaver, Hui, Kramer,
    J. Appl. Phys. 80 (1996) 30; Baney & Hui, J. Adhesion Sci. Technol. 11
    (1997) 393, JKR limit of their eq. for large lambda).
    """
    a = np.asarray(a, dtype=float)
    return math.pi * E_star * a**2 / (4.0 * R) - np.sqrt(2.0 * math.pi * E_star * w * a)


def jkr_cylinder_critical_half_width(R: float, E_star: float, w: float) -> float:
    """Half-width at the load minimum dP/da = 0: a_c = (2 w R^2 / (pi E*))^(1/3)."""
    return (2.0 * w * R**2 / (math.pi * E_star)) ** (1.0 / 3.0)


def jkr_cylinder_pull_off(R: float, E_star: float, w: float) -> float:
    """Pull-off load under load control, P_c = -(3/4) 4^(1/3) (pi E* w^2 R)^(1/3).

    The minimum of :func:`jkr_cylinder_load` (Chaudhury et al. 1996).
    """
    return float(jkr_cylinder_load(jkr_cylinder_critical_half_width(R, E_star, w), R, E_star, w))


def _bracketed_root(f, lo: float, hi: float) -> float:
    """Root of increasing f on [lo, hi'] with hi' = hi 2^k the first bracket end where f >= 0."""
    if not hi > 0.0:
        raise ValueError("the bracket end must be positive")
    for _ in range(2000):
        if f(hi) >= 0.0:
            return brentq(f, lo, hi, xtol=1e-14 * hi, rtol=1e-14, maxiter=500)
        lo, hi = hi, 2.0 * hi
    raise ValueError("no root found")


def jkr_cylinder_half_width(P: float, R: float, E_star: float, w: float, branch: str = "stable") -> float:
    """Half-width at load P (inverse of :func:`jkr_cylinder_load`).

    ``branch='stable'`` returns the root a >= a_c (stable under load
    control); ``'unstable'`` the root 0 < a < a_c, which exists only for
    pull-off <= P < 0. Raises ValueError below the pull-off load.
    """
    load = lambda a: float(jkr_cylinder_load(a, R, E_star, w))  # noqa: E731
    hertz = float(hertz_line_half_width(abs(P), R, E_star))
    return _jkr_root(load, P, jkr_cylinder_critical_half_width(R, E_star, w), hertz, branch)


def maugis_parameter_cylinder(R: float, E_star: float, w: float, sigma0: float) -> float:
    """Maugis parameter of a cylinder (Baney & Hui 1997; Johnson & Greenwood, J. Phys. D 41 (2008) 155315).

    lambda = 2 sigma0 (4 R / (pi w E*^2))^(1/3): JKR applies for lambda >~ 5,
    with sigma0 the peak adhesive stress (T_max for the CGCM).
    """
    return 2.0 * sigma0 * (4.0 * R / (math.pi * w * E_star**2)) ** (1.0 / 3.0)


# --- JKR sphere (3D) ------------------------------------------------------
def jkr_sphere_load(a, R: float, E_star: float, w: float):
    """JKR load at contact radius a: P = 4 E* a^3 / (3 R) - sqrt(8 pi w E* a^3).

    Johnson, Kendall, Roberts, Proc. R. Soc. Lond. A 324 (1971) 301;
    Johnson (1985), section 5.5, with K = 4 E*/3.
    """
    a = np.asarray(a, dtype=float)
    return 4.0 * E_star * a**3 / (3.0 * R) - np.sqrt(8.0 * math.pi * w * E_star * a**3)


def jkr_sphere_critical_radius(R: float, E_star: float, w: float) -> float:
    """Contact radius at the load minimum: a_c = (9 pi w R^2 / (8 E*))^(1/3)."""
    return (9.0 * math.pi * w * R**2 / (8.0 * E_star)) ** (1.0 / 3.0)


def jkr_sphere_pull_off(R: float, E_star: float, w: float) -> float:
    """Pull-off load under load control: P_c = -(3/2) pi w R (JKR 1971)."""
    return float(jkr_sphere_load(jkr_sphere_critical_radius(R, E_star, w), R, E_star, w))


def jkr_sphere_radius(P: float, R: float, E_star: float, w: float, branch: str = "stable") -> float:
    """Contact radius at load P (inverse of :func:`jkr_sphere_load`), as for the cylinder."""
    load = lambda a: float(jkr_sphere_load(a, R, E_star, w))  # noqa: E731
    hertz = (3.0 * abs(P) * R / (4.0 * E_star)) ** (1.0 / 3.0)
    return _jkr_root(load, P, jkr_sphere_critical_radius(R, E_star, w), hertz, branch)
