"""Closed forms of a sphere against a rigid flat: Hertz, and the Maugis-Dugdale adhesive sphere, references of
the 3D verification (issue 39).

Conventions as in :mod:`capslide.laws.analytic`: the load P is positive when COMPRESSIVE; E* = E / (1 - nu^2);
K = 4 E* / 3; w is the work of adhesion (energy per area), sigma0 the Dugdale stress (T_max for the CGCM law).

The Maugis-Dugdale solution (Maugis, J. Colloid Interface Sci. 150 (1992) 243) is written in the dimensionless
variables of Johnson and Greenwood (J. Colloid Interface Sci. 192 (1997) 326):
A = a (K / (pi w R^2))^(1/3), P_bar = P / (pi w R), D = delta (K^2 / (pi^2 w^2 R))^(1/3),
lambda = 2 sigma0 (R / (pi w K^2))^(1/3), m = c / a (c: the outer edge of the cohesive zone). With s = sqrt(m^2 - 1)
and arcsec m = arccos(1 / m), m solves

    lambda A^2 / 2 [s + (m^2 - 2) arcsec m] + 4 lambda^2 A / 3 [s arcsec m - m + 1] = 1,

then P_bar = A^3 - lambda A^2 [s + m^2 arcsec m] and D = A^2 - 4 lambda A s / 3. Its limits are JKR (lambda -> inf:
P_bar = A^3 - sqrt(6 A^3), pull-off -3/2) and DMT (lambda -> 0: pull-off -2).
"""

from __future__ import annotations

import math

import numpy as np
from scipy.optimize import brentq, minimize_scalar

__all__ = ["hertz_sphere_radius", "hertz_moment_radius", "hertz_sphere_peak_pressure", "hertz_sphere_approach",
           "maugis_parameter_sphere", "dugdale_stress_for_lambda",
           "md_cohesive_ratio", "md_load", "md_approach", "md_pull_off", "md_zero_load_radius", "md_scales",
           "jkr_radius", "md_radius"]


def hertz_sphere_radius(P, R: float, E_star: float):
    """Hertz contact radius a = (3 P R / (4 E*))^(1/3) under the compressive load P (Johnson 1985, eq. 4.22)."""
    return np.cbrt(3.0 * np.asarray(P, dtype=float) * R / (4.0 * E_star))


def hertz_sphere_peak_pressure(P, R: float, E_star: float):
    """Hertz peak pressure p0 = 3 P / (2 pi a^2) (Johnson 1985, eq. 4.23)."""
    a = hertz_sphere_radius(P, R, E_star)
    return 3.0 * np.asarray(P, dtype=float) / (2.0 * math.pi * a**2)


def hertz_moment_radius(force, r_squared) -> float:
    """The contact radius from a pressure's second moment, a^2 = 5/2 sum(f r^2) / sum(f), exact for the Hertz
    pressure p0 sqrt(1 - r^2 / a^2); ``force``: the pressure times the area at each point (any units), ``r_squared``:
    the points' squared distance from the axis (length^2)."""
    return math.sqrt(2.5 * np.sum(force * r_squared) / np.sum(force))


def hertz_sphere_approach(P, R: float, E_star: float):
    """Hertz approach delta = a^2 / R."""
    return hertz_sphere_radius(P, R, E_star) ** 2 / R


def maugis_parameter_sphere(R: float, E_star: float, w: float, sigma0: float) -> float:
    """lambda = 2 sigma0 (R / (pi w K^2))^(1/3), K = 4 E*/3: JKR is approached for large lambda (Maugis 1992)."""
    K = 4.0 * E_star / 3.0
    return 2.0 * sigma0 * (R / (math.pi * w * K**2)) ** (1.0 / 3.0)


def dugdale_stress_for_lambda(lam: float, R: float, E_star: float, w: float) -> float:
    """The Dugdale stress sigma0 that gives a sphere the Maugis parameter ``lam`` at fixed work of adhesion w: the
    inverse of :func:`maugis_parameter_sphere` (lambda is linear in sigma0). With the CGCM, sigma0 = T_max, and
    r0 follows from (T_max, w) (:func:`capslide.params.cgcm_constants`): how a scene sets the interaction range
    through lambda when the real range cannot be meshed."""
    return lam / maugis_parameter_sphere(R, E_star, w, 1.0)


def md_scales(R: float, E_star: float, w: float) -> dict[str, float]:
    """The scales of the dimensionless Maugis-Dugdale variables: a = A x radius, P = P_bar x load, delta = D x
    approach."""
    K = 4.0 * E_star / 3.0
    return {"radius": (math.pi * w * R**2 / K) ** (1.0 / 3.0), "load": math.pi * w * R,
            "approach": (math.pi**2 * w**2 * R / K**2) ** (1.0 / 3.0)}


def _terms(m: float) -> tuple[float, float]:
    s = math.sqrt(max(m * m - 1.0, 0.0))
    return s, math.acos(1.0 / m)


def md_cohesive_ratio(A: float, lam: float) -> float:
    """m = c / a of the Maugis-Dugdale sphere at the dimensionless contact radius A > 0 and Maugis parameter lam."""
    if not (A > 0.0 and lam > 0.0):
        raise ValueError(f"A = {A!r} and lambda = {lam!r} must be positive")

    def residual(m: float) -> float:
        s, sec = _terms(m)
        return 0.5 * lam * A * A * (s + (m * m - 2.0) * sec) + 4.0 * lam * lam * A / 3.0 * (s * sec - m + 1.0) - 1.0

    hi = 2.0
    while residual(hi) < 0.0:  # residual(1) = -1, and it grows without bound in m
        hi *= 2.0
        if hi > 1e12:
            raise ValueError(f"no cohesive zone found at A = {A!r}, lambda = {lam!r}")
    return brentq(residual, 1.0, hi, xtol=1e-15, rtol=1e-14, maxiter=500)


def md_load(A, lam: float):
    """Dimensionless load P_bar = P / (pi w R), compressive positive, at the dimensionless radii A."""
    def one(a: float) -> float:
        m = md_cohesive_ratio(a, lam)
        s, sec = _terms(m)
        return a**3 - lam * a * a * (s + m * m * sec)
    return np.vectorize(one, otypes=[float])(np.asarray(A, dtype=float))


def md_approach(A, lam: float):
    """Dimensionless approach D at the dimensionless radii A."""
    def one(a: float) -> float:
        s, _ = _terms(md_cohesive_ratio(a, lam))
        return a * a - 4.0 * lam * a * s / 3.0
    return np.vectorize(one, otypes=[float])(np.asarray(A, dtype=float))


def md_pull_off(lam: float) -> tuple[float, float]:
    """(P_bar, A) at the minimum of the load, the pull-off under load control."""
    res = minimize_scalar(lambda a: float(md_load(a, lam)), bounds=(1e-3, 3.0), method="bounded",
                          options={"xatol": 1e-10})
    return float(res.fun), float(res.x)


def md_zero_load_radius(lam: float) -> float:
    """The dimensionless contact radius A at zero load on the stable branch (beyond the pull-off radius)."""
    _, a_min = md_pull_off(lam)
    return brentq(lambda a: float(md_load(a, lam)), a_min, 10.0, xtol=1e-13, rtol=1e-13)


def jkr_radius(P):
    """The dimensionless JKR contact radius A on the stable branch at the load P_bar >= -3/2 (compressive
    positive): P_bar = A^3 - sqrt(6 A^3), so A^(3/2) = (sqrt 6 + sqrt(6 + 4 P_bar)) / 2 (Johnson, Kendall and
    Roberts 1971, in Johnson and Greenwood's variables)."""
    t = 0.5 * (math.sqrt(6.0) + np.sqrt(6.0 + 4.0 * np.asarray(P, dtype=float)))
    return t ** (2.0 / 3.0)


def md_radius(P, lam: float) -> float:
    """The dimensionless Maugis-Dugdale contact radius A on the stable branch (beyond the pull-off radius) at the
    load P_bar (compressive positive, at least the pull-off load)."""
    P_c, a_c = md_pull_off(lam)
    if P < P_c:
        raise ValueError(f"P_bar = {P:g} is beyond the pull-off load {P_c:.6g}: no contact")
    hi = 2.0
    while float(md_load(hi, lam)) < P:
        hi *= 2.0
    return brentq(lambda a: float(md_load(a, lam)) - P, a_c, hi, xtol=1e-13, rtol=1e-13)
