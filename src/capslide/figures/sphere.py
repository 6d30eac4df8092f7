"""Figures of a 3D sphere case (mesh.element = H1): the normal traction over the contact plane, and the load
against the contact radius with the JKR and Maugis-Dugdale spheres."""

from __future__ import annotations

import math

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.colors import TwoSlopeNorm
from matplotlib.tri import Triangulation

from ..laws import analytic, sphere
from ..params import Parameters
from .style import BLUE, ORANGE, SINGLE_COLUMN

__all__ = ["fig_sphere_Tn", "fig_sphere_Pa"]


def fig_sphere_Tn(case, params: Parameters, step: int = -1):
    """The normal traction Tn / E over the current contact plane at ``step`` (default: the last), the half model's
    surface points mirrored to the whole contact (positive = compressive; the tensile ring is the cohesive zone)."""
    s = case.isel(step=step)
    x, y, Tn = (np.asarray(s[k].values, dtype=float) for k in ("x_current", "y_current", "traction_n"))
    reach = 1.3 * max(float(s.x_right - s.x_left) / 2, 1e-9) if np.isfinite(float(s.x_right)) else np.abs(x).max()
    near = np.hypot(x, y) <= reach
    X, Y, T = np.concatenate([x[near], x[near]]), np.concatenate([y[near], -y[near]]), np.concatenate([Tn[near]] * 2)
    keep = np.unique(np.column_stack([X, Y]).round(12), axis=0, return_index=True)[1]  # points on y = 0 once
    tri = Triangulation(X[keep], Y[keep])
    fig, ax = plt.subplots(figsize=(SINGLE_COLUMN, 0.85 * SINGLE_COLUMN))
    lo, hi = float(min(T.min(), -1e-12)), float(max(T.max(), 1e-12))
    m = ax.tricontourf(tri, T[keep], levels=24, cmap="RdBu_r", norm=TwoSlopeNorm(0.0, lo, hi))
    fig.colorbar(m, ax=ax, label=r"$T_n/E$ (compressive $> 0$)")
    ax.set_aspect("equal")
    ax.set_xlabel(r"$x/L_0$ (current)")
    ax.set_ylabel(r"$y/L_0$ (current)")
    ax.set_title(f"$F_n = {float(s.Fn):.3f}\\,E L_0^2$, step {int(s.step)}")
    fig.tight_layout()
    return fig


def fig_sphere_Pa(case, params: Parameters):
    """The load P = -Fn against the contact radius a = sqrt(A / pi) along the path (Johnson and Greenwood's
    dimensionless P / (pi W R) and a (K / (pi W R^2))^(1/3)), with JKR and the Maugis-Dugdale sphere at the case's
    lambda (Maugis 1992)."""
    R, a = params.geometry.R, params.adhesion
    E_star = analytic.effective_modulus(params.material.E, params.material.nu)
    scales = sphere.md_scales(R, E_star, a.W_adh)
    lam = sphere.maugis_parameter_sphere(R, E_star, a.W_adh, a.T_max)
    contact = case.area.values > 0
    A_fe = np.sqrt(case.area.values[contact] / math.pi) / scales["radius"]
    P_fe = -case.Fn.values[contact] / scales["load"]
    A = np.linspace(0.02, max(2.6, 1.05 * float(A_fe.max()) if len(A_fe) else 2.6), 300)
    fig, ax = plt.subplots(figsize=(SINGLE_COLUMN, 0.75 * SINGLE_COLUMN))
    ax.plot(A, A**3 - np.sqrt(6 * A**3), color="0.4", lw=0.9, ls="--", label="JKR")
    ax.plot(A, sphere.md_load(A, lam), color=BLUE, lw=1.1, label=f"Maugis-Dugdale, $\\lambda = {lam:.2g}$")
    ax.plot(A_fe, P_fe, "o", ms=3, mfc="none", color=ORANGE, label="FE (contact: $g_n \\leq g_{max}$)")
    ax.axhline(0.0, color="0.7", lw=0.5)
    ax.set_xlabel(r"$a\,(K/\pi W R^2)^{1/3}$")
    ax.set_ylabel(r"$P/\pi W R$ (compressive $> 0$)")
    ax.set_ylim(-2.2, max(3.0, float(P_fe.max()) * 1.1 if len(P_fe) else 3.0))
    ax.legend(frameon=False, loc="upper left")
    fig.tight_layout()
    return fig
