"""The experiment's figure f:exp:FnJKR: initial normal force from contact area by JKR for the PDMS sphere."""

from __future__ import annotations

from dataclasses import dataclass

import matplotlib.pyplot as plt
import numpy as np

from ..laws import analytic
from ..params import Parameters
from .style import BLUE, DOUBLE_COLUMN, ORANGE

__all__ = ["JKRSphereExperiment", "PDMS_SPHERE", "fig_exp_FnJKR"]


@dataclass(frozen=True)
class JKRSphereExperiment:
    """The PDMS sphere on glass of the paper's section 3 (SI units).

    Mergel et al. (2019), figure f:exp:setup: R = 9.42 mm, E = 1.6 +- 0.1 MPa,
    nu = 0.5, dgamma = 27 +- 1 mJ/m^2; measured initial areas up to 0.5 mm^2.
    """

    R: float = 9.42e-3  # m
    E: float = 1.6e6  # Pa
    dE: float = 0.1e6  # Pa
    nu: float = 0.5
    w: float = 27e-3  # J/m^2
    dw: float = 1e-3  # J/m^2
    area_max_mm2: float = 0.5


PDMS_SPHERE = JKRSphereExperiment()


def _jkr_force_mN(area_mm2, e: JKRSphereExperiment, E: float, w: float):
    """Normal force (mN, tensile > 0, the paper's sign) from contact area by JKR for a sphere."""
    a = np.sqrt(np.asarray(area_mm2) * 1e-6 / np.pi)
    return -1e3 * analytic.jkr_sphere_load(a, e.R, analytic.effective_modulus(E, e.nu), w)


def fig_exp_FnJKR(p: Parameters | None = None, e: JKRSphereExperiment = PDMS_SPHERE):
    """f:exp:FnJKR: initial normal force from contact area (a) and radius (b), JKR sphere.

    The band is the range of the JKR force over E +- dE and dgamma +- d(dgamma): the uncertainty of the prediction.
    No measured points are drawn (the paper's per-experiment bars come from data capslide does not have).
    """
    area = np.linspace(0.0, e.area_max_mm2, 400)
    E_grid = np.linspace(e.E - e.dE, e.E + e.dE, 21)[:, None, None]
    w_grid = np.array([e.w - e.dw, e.w + e.dw])[None, :, None]
    F_nom = _jkr_force_mN(area, e, e.E, e.w)
    F_band = _jkr_force_mN(area[None, None, :], e, E_grid, w_grid)
    P_c = -1e3 * analytic.jkr_sphere_pull_off(e.R, analytic.effective_modulus(e.E, e.nu), e.w)
    a_c = analytic.jkr_sphere_critical_radius(e.R, analytic.effective_modulus(e.E, e.nu), e.w)
    fig, axes = plt.subplots(1, 2, figsize=(DOUBLE_COLUMN, 2.6))
    for ax, scale, ylabel, letter in (
        (axes[0], lambda A: A, r"initial contact area $A^0_\mathrm{real}$ (mm$^2$)", "a"),
        (axes[1], lambda A: np.sqrt(A / np.pi), r"contact radius $r^0_\mathrm{real} = \sqrt{A^0_\mathrm{real}/\pi}$ (mm)", "b"),
    ):
        ax.fill_betweenx(scale(area), F_band.min(axis=(0, 1)), F_band.max(axis=(0, 1)), color=BLUE, alpha=0.2, lw=0,
                         label=fr"JKR over $E = {e.E/1e6:g} \pm {e.dE/1e6:g}$ MPa, "
                               fr"$\Delta\gamma = {e.w*1e3:g} \pm {e.dw*1e3:g}$ mJ/m$^2$")
        ax.plot(F_nom, scale(area), color=BLUE, label="JKR, nominal parameters")
        ax.plot(P_c, scale(np.pi * (a_c * 1e3) ** 2), "s", color=ORANGE, ms=4, label="pull-off (load control)")
        ax.axvline(0.0, color="k", lw=0.4)
        ax.set(xlabel=r"initial normal force $F^0_\mathrm{n}$ (mN), tensile $> 0$", ylabel=ylabel,
               title=f"({letter})", ylim=(0, scale(e.area_max_mm2) * 1.02))
    axes[0].legend(loc="lower left", title="predictions, no measured points", title_fontsize=7)
    fig.tight_layout()
    return fig
