"""Figures of a 3D sphere case (mesh.element = H1, H2): the normal traction over the contact plane, the load against
the contact radius with the JKR and Maugis-Dugdale spheres, and the contact and stick-zone outlines seen from above
during the slide."""

from __future__ import annotations

import math

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.colors import TwoSlopeNorm
from matplotlib.tri import Triangulation

from ..laws import analytic, sphere
from ..params import Parameters
from ..states import Phase
from .style import BLUE, DOUBLE_COLUMN, ORANGE, SINGLE_COLUMN

__all__ = ["fig_sphere_Tn", "fig_sphere_Pa", "fig_sphere_Aczoom", "outline_loops"]


def _normal_steps(case) -> np.ndarray:
    """The steps before the slide (approach, spread, preload)."""
    return np.flatnonzero(case.phase.values != Phase.SLIDE)


def fig_sphere_Tn(case, params: Parameters, step: int | None = None):
    """The normal traction Tn / E over the current contact plane at ``step`` (default: the preloaded state, the
    last step before the slide), the half model's surface points mirrored to the whole contact (positive =
    compressive; the tensile ring is the cohesive zone)."""
    s = case.isel(step=int(_normal_steps(case)[-1]) if step is None else step)
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
    """The load P = -Fn against the contact radius a = sqrt(A / pi) along the normal path (Johnson and Greenwood's
    dimensionless P / (pi W R) and a (K / (pi W R^2))^(1/3)), with JKR and the Maugis-Dugdale sphere at the case's
    lambda (Maugis 1992)."""
    R, a = params.geometry.R, params.adhesion
    E_star = analytic.effective_modulus(params.material.E, params.material.nu)
    scales = sphere.md_scales(R, E_star, a.W_adh)
    lam = sphere.maugis_parameter_sphere(R, E_star, a.W_adh, a.T_max)
    contact = (case.area.values > 0) & (case.phase.values != Phase.SLIDE)
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


def outline_loops(curve: np.ndarray) -> list[np.ndarray]:
    """The polylines of a NaN-separated, NaN-padded outline."""
    rows = np.isnan(curve[:, 0])
    cut = np.flatnonzero(rows)
    return [c[~np.isnan(c[:, 0])] for c in np.split(curve, cut) if np.count_nonzero(~np.isnan(c[:, 0])) > 2]


def fig_sphere_Aczoom(case, params: Parameters, panels: int = 8):
    """The contact seen from above at the slide's snapshots (the 3D f:cap:Aczoom): the contact outline (line) and
    the stick zone (shaded), in the current x, y plane; the substrate slides along +x."""
    ubar = case.snapshot_ubar.values[:panels]
    cols = min(4, len(ubar))
    rows = -(-len(ubar) // cols)
    fig, axes = plt.subplots(rows, cols, figsize=(DOUBLE_COLUMN, 1.9 * rows + 0.3), squeeze=False, sharex=True,
                             sharey=True)
    for k, ax in enumerate(axes.ravel()):
        if k >= len(ubar):
            ax.set_visible(False)
            continue
        outline = np.column_stack([case.outline_x[k].values, case.outline_y[k].values])
        stick = np.column_stack([case.stick_outline_x[k].values, case.stick_outline_y[k].values])
        for loop in outline_loops(stick):
            ax.fill(loop[:, 0], loop[:, 1], color=BLUE, alpha=0.35, lw=0)
        for loop in outline_loops(outline):
            ax.plot(loop[:, 0], loop[:, 1], color="k", lw=0.8)
        ax.set_aspect("equal")
        ax.text(0.03, 0.04, fr"$\bar{{u}} = {float(ubar[k]):.2g}\,L_0$", transform=ax.transAxes, fontsize=7)
    for ax in axes[-1]:
        ax.set_xlabel(r"$x\,/\,L_0$ (current)")
    for ax in axes[:, 0]:
        ax.set_ylabel(r"$y\,/\,L_0$")
    fig.suptitle("contact (line) and stick zone (shaded) seen from above; the substrate slides along $+x$", fontsize=8)
    fig.tight_layout()
    return fig
