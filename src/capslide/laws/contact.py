"""Contact laws: pure vectorized functions returning value and exact derivative.

Symbols and sign conventions follow Mergel, Sahli, Scheibert, Sauer (2019),
"Continuum contact models for coupled adhesion and friction", J. Adhesion,
section 4 and appendix A. Any consistent units work (capslide uses stress in
E and length in L0). The normal gap g is positive when the surfaces are apart;
the normal traction Tn is positive when repulsive.
"""

from __future__ import annotations

import numpy as np
from scipy.special import expit

__all__ = [
    "normal_traction_unregularized",
    "normal_traction",
    "normal_potential",
    "di_threshold",
    "weakening_return_map",
    "ea_g_cut",
    "ea_threshold",
    "return_map",
    "vector_return_map",
    "tangential_potential",
]


def normal_traction_unregularized(g, T0: float, r0: float):
    """CGCM normal traction and its derivative (paper eq. Tn, theta = J_l = 1).

    Tn(g) = T0 [ (r0/g)^9 / 45 - (r0/g)^3 / 3 ] (stress), g > 0 (length).
    Returns ``(Tn, dTn/dg)``.
    """
    g = np.asarray(g, dtype=float)
    q = r0 / g
    q3 = q**3
    q9 = q3**3
    Tn = T0 * (q9 / 45.0 - q3 / 3.0)
    dTn = T0 * (-q9 / 5.0 + q3) / g
    return Tn, dTn


def normal_traction(g, T0: float, r0: float, g_reg: float):
    """Regularized CGCM normal traction (paper appendix A) and its derivative.

    Tn(g) for g >= g_reg; linear extrapolation Tn(g_reg) + Tn'(g_reg)(g - g_reg)
    below, so penetration (g <= 0) gives a finite repulsion.
    Returns ``(Tn, dTn/dg)``; positive Tn = repulsive.
    """
    g = np.asarray(g, dtype=float)
    T_reg, dT_reg = normal_traction_unregularized(g_reg, T0, r0)
    far = g >= g_reg
    g_safe = np.where(far, g, g_reg)  # no division by g <= 0 in the unused branch
    Tn, dTn = normal_traction_unregularized(g_safe, T0, r0)
    Tn = np.where(far, Tn, T_reg + dT_reg * (g - g_reg))
    dTn = np.where(far, dTn, dT_reg)
    return Tn, dTn


def normal_potential(g, T0: float, r0: float, g_reg: float, g_far: float = np.inf):
    """Interface energy per reference area of the regularized CGCM traction: phi(g) = int_g^g_far Tn(s) ds for
    g < g_far, 0 beyond (the law's tail beyond ``g_far`` dropped, as the contact integral drops it), so that
    dphi/dg = -Tn(g) (energy per area, stress x length).

    Without regularization int_g^inf Tn = T0 [ r0^9 / (360 g^8) - r0^3 / (6 g^2) ]; below g_reg the linear
    extrapolation of Tn adds Tn(g_reg) (g_reg - g) - Tn'(g_reg) (g_reg - g)^2 / 2 to phi(g_reg).
    """
    def tail(x):
        x = np.asarray(x, dtype=float)
        return T0 * (r0**9 / (360.0 * x**8) - r0**3 / (6.0 * x**2))

    g = np.asarray(g, dtype=float)
    T_reg, dT_reg = normal_traction_unregularized(g_reg, T0, r0)
    d = g_reg - g
    phi = np.where(g >= g_reg, tail(np.maximum(g, g_reg)), tail(g_reg) + T_reg * d - 0.5 * dT_reg * d * d)
    if np.isfinite(g_far):
        phi = np.where(g < g_far, phi - tail(g_far), 0.0)
    return phi


def di_threshold(g, tau: float, k: float, g_cut: float):
    """Model DI sliding threshold per current area (paper eq. tslideCA).

    t_slide(g) = tau / (1 + exp(k (g - g_cut))), a logistic step from tau
    (close contact) to 0 (far); t_slide(g_cut) = tau / 2.
    Returns ``(t_slide, dt_slide/dg)``.
    """
    g = np.asarray(g, dtype=float)
    z = k * (g - g_cut)
    s = expit(-z)  # 1 / (1 + exp(z)), overflow-free
    return tau * s, -tau * k * s * expit(z)


def ea_g_cut(s_cut: float, g_eq: float, g_max: float) -> float:
    """Model EA cut-off distance, paper eq. gcutAM: s_cut g_max + (1 - s_cut) g_eq."""
    return s_cut * g_max + (1.0 - s_cut) * g_eq


def ea_threshold(g, mu: float, g_cut: float, T0: float, r0: float, g_reg: float):
    """Model EA sliding threshold per reference area (paper eq. TslideAM, J_cl = 1).

    T_slide(g) = mu [Tn(g) - Tn(g_cut)] for g < g_cut, else 0, with the
    regularized Tn of :func:`normal_traction`. Continuous, with a kink at
    g_cut unless g_cut = g_max (where Tn' = 0). The derivative returned at
    g = g_cut is the one-sided value from g > g_cut (zero).
    Returns ``(T_slide, dT_slide/dg)``.
    """
    g = np.asarray(g, dtype=float)
    Tn, dTn = normal_traction(g, T0, r0, g_reg)
    Tn_cut, _ = normal_traction(g_cut, T0, r0, g_reg)
    active = g < g_cut
    return np.where(active, mu * (Tn - Tn_cut), 0.0), np.where(active, mu * dTn, 0.0)


def return_map(T_trial, threshold):
    """Stick/slip return map of a scalar (2D) tangential trial traction.

    Stick where |T_trial| <= threshold: T = T_trial. Slip elsewhere:
    T = threshold * sign(T_trial). ``threshold`` must be >= 0.
    Returns ``(T, slipping, dT/dT_trial, dT/dthreshold)``; the derivatives
    are those of the active branch.
    """
    T_trial = np.asarray(T_trial, dtype=float)
    threshold = np.asarray(threshold, dtype=float)
    slipping = np.abs(T_trial) > threshold
    sign = np.sign(T_trial)
    T = np.where(slipping, threshold * sign, T_trial)
    dT_dtrial = np.where(slipping, 0.0, 1.0)
    dT_dthreshold = np.where(slipping, sign, 0.0)
    return T, slipping, dT_dtrial, dT_dthreshold


def vector_return_map(T_trial, threshold, magnitude_map=return_map):
    """Isotropic stick/slip return map of a tangential trial traction vector (..., 2) in the contact plane (3D; the
    radial return of Coulomb-type friction, Wriggers 2006, Computational Contact Mechanics, section 5.2).

    Stick where |T_trial| <= threshold: T = T_trial. Slip elsewhere: T = |T| n, n = T_trial / |T_trial|, with the
    magnitude |T| from ``magnitude_map(|T_trial|, threshold)`` (:func:`return_map`: |T| = threshold; or a partial
    :func:`weakening_return_map`). Returns ``(T (..., 2), slipping, dT/dT_trial (..., 2, 2), dT/dthreshold (..., 2))``:
    in slip dT/dT_trial = d|T|/d|T_trial| n n^T + |T| / |T_trial| (I - n n^T), dT/dthreshold = d|T|/dthreshold n.
    """
    T_trial = np.asarray(T_trial, dtype=float)
    m = np.linalg.norm(T_trial, axis=-1)
    T_abs, slipping, dabs_dm, dabs_dthr = magnitude_map(m, threshold)
    n = T_trial / np.where(m > 0.0, m, 1.0)[..., None]
    eye = np.eye(T_trial.shape[-1])
    nn = n[..., :, None] * n[..., None, :]
    ratio = T_abs / np.where(slipping, m, 1.0)
    slip_tangent = dabs_dm[..., None, None] * nn + ratio[..., None, None] * (eye - nn)
    T = np.where(slipping[..., None], T_abs[..., None] * n, T_trial)
    dT_dtrial = np.where(slipping[..., None, None], slip_tangent, eye)
    dT_dthreshold = np.where(slipping[..., None], dabs_dthr[..., None] * n, 0.0)
    return T, slipping, dT_dtrial, dT_dthreshold


def weakening_return_map(T_trial, kinetic, slip, ratio, D_c, eps_t):
    """Stick/slip return map with linear slip weakening of the threshold (a standard regularization of static and
    kinetic friction: Ida 1972, J. Geophys. Res. 77, 3796; Palmer & Rice 1973, Proc. R. Soc. A 332, 527).

    The threshold is m(s) ``kinetic`` with m(s) = ratio - a min(s, D_c), a = (ratio - 1) / D_c: ``ratio`` (>= 1)
    times the kinetic threshold at s = 0 (static), falling linearly to it over the slip distance ``D_c``. ``slip``
    is a point's accumulated slip s before the step; the step's slip ds = (|T_trial| - |T|) / eps_t enters the
    threshold implicitly (backward Euler), with c = a / eps_t:

    * stick where |T_trial| <= m(s) kinetic: T = T_trial;
    * weakening where s + ds < D_c: |T| = kinetic (m(s) - c |T_trial|) / (1 - c kinetic);
    * kinetic elsewhere: |T| = kinetic.

    Where 1 - c kinetic <= 0 the threshold softens faster than the penalty unloads: no local solution, T is NaN.
    ``ratio`` = 1 is :func:`return_map`. Returns ``(T, slipping, dT/dT_trial, dT/dkinetic)`` of the active branch.
    """
    T_trial, kinetic, slip = (np.asarray(v, dtype=float) for v in (T_trial, kinetic, slip))
    a = (ratio - 1.0) / D_c
    c = a / eps_t
    m = ratio - a * np.minimum(slip, D_c)
    mag, sign = np.abs(T_trial), np.sign(T_trial)
    slipping = mag > m * kinetic
    den = 1.0 - c * kinetic
    stable = den > 0.0
    safe = np.where(stable, den, 1.0)
    weak = kinetic * (m - c * mag) / safe  # = kinetic m(s + ds): at least kinetic while s + ds <= D_c
    weakening = slipping & (slip < D_c) & (~stable | (weak > kinetic))
    T_abs = np.where(weakening, np.where(stable, weak, np.nan), kinetic)
    T = np.where(slipping, sign * T_abs, T_trial)
    dT_dtrial = np.where(slipping, np.where(weakening, -c * kinetic / safe, 0.0), 1.0)
    dT_dkinetic = np.where(slipping, sign * np.where(weakening, (m - c * mag) / safe**2, 1.0), 0.0)
    return T, slipping, dT_dtrial, dT_dkinetic


def tangential_potential(slip_gap, threshold, eps_t: float):
    """Energy per reference area (E L0) of the penalty return map over one step with its threshold held fixed: the
    Huber function of the tangential gap's length d = |x - anchor - ubar| (L0) with the stick penalty ``eps_t``
    (E / L0) and the threshold c (E), psi = eps_t d^2 / 2 in stick (eps_t d <= c), c d - c^2 / (2 eps_t) in slip.
    dpsi/dd = min(eps_t d, c) is the magnitude of :func:`return_map`'s and :func:`vector_return_map`'s traction, so
    the step's friction forces are the negative gradient of its integral (loadpath.snap_through's merit function).
    Slip weakening and a threshold that follows the gap have no such potential."""
    d, c = np.abs(np.asarray(slip_gap, dtype=float)), np.asarray(threshold, dtype=float)
    return np.where(eps_t * d <= c, 0.5 * eps_t * d * d, c * d - c * c / (2.0 * eps_t))
