"""Friction laws as objects chosen once from the parameters (docs/theory.md section 3; Mergel et al. 2019, section 4.2).

A law gives the sliding threshold per REFERENCE area at a surface point from the normal gap g_n and the current
surface stretch J_s = |dx/dX|, with both derivatives. Model DI has its threshold per current area, so per
reference area it is J_s t_slide(g_n); model EA is per reference area already (T_slide(g_n), J_cl = 1).
``friction.DI_area = reference`` takes DI's threshold per reference area instead, t_slide(g_n): the variant that
section 4.2.1 of the paper says would "miss the change in the contact area" (Ft = tau x reference contact length).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Protocol

import numpy as np

from ..params import Adhesion, Friction
from . import contact

__all__ = ["FrictionLaw", "DistanceIndependent", "ExtendedAmontons", "Sticking", "friction_law", "ReturnMapSettings"]


class FrictionLaw(Protocol):
    def threshold(self, g: np.ndarray, J: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Threshold per reference area and its derivatives with respect to g_n and J_s (stress, E)."""


@dataclass(frozen=True)
class DistanceIndependent:
    """Model DI: tau / (1 + exp(k (g_n - g_cut))) per current area (paper eq. tslideCA), or per reference area
    when ``per_current_area`` is False."""

    tau: float
    k: float  # 1 / L0
    g_cut: float  # L0
    per_current_area: bool = True

    def threshold(self, g, J):
        t, dt = contact.di_threshold(g, self.tau, self.k, self.g_cut)
        if not self.per_current_area:
            return t, dt, np.zeros_like(t)
        return J * t, J * dt, t


@dataclass(frozen=True)
class ExtendedAmontons:
    """Model EA: mu [Tn(g_n) - Tn(g_cut)] for g_n < g_cut, else 0, per reference area (paper eq. TslideAM)."""

    mu: float
    g_cut: float  # L0
    T0: float
    r0: float
    g_reg: float

    def threshold(self, g, J):
        T, dT = contact.ea_threshold(g, self.mu, self.g_cut, self.T0, self.r0, self.g_reg)
        return T, dT, np.zeros_like(T)


@dataclass(frozen=True)
class Sticking:
    """Every point sticks: a threshold no trial traction reaches (the largest float, not inf, so that the return
    map's unused slip branch stays finite). The slide's stick predictor solves with it (loadpath.continuation)."""

    def threshold(self, g, J):
        g = np.asarray(g, dtype=float)
        return np.full_like(g, np.finfo(float).max), np.zeros_like(g), np.zeros_like(g)


@dataclass(frozen=True)
class ReturnMapSettings:
    """How a law's threshold is enforced: the tangential penalty ``eps_t`` (E/L0), the slip weakening
    (static/kinetic ratio, slip-weakening distance D_c in L0), None for one threshold, and whether the threshold is
    fixed over a step at its value at the step's start state (``friction.threshold_at = step_start``; with
    ``step_predicted`` at the state extrapolated to the step's end, :meth:`capslide.model.system.CapModel.step_history`)."""

    eps_t: float
    weakening: tuple[float, float] | None = None
    threshold_at_step_start: bool = False


def friction_law(friction: Friction, adhesion: Adhesion) -> FrictionLaw | None:
    """The law of ``friction.model``: DI, EA, or None (frictionless)."""
    if friction.model == "DI":
        return DistanceIndependent(friction.tau_DI, friction.k_DI, friction.g_cut_DI, friction.DI_area == "current")
    if friction.model == "EA":
        return ExtendedAmontons(friction.mu_EA, friction.g_cut_EA, adhesion.T0, adhesion.r0, adhesion.g_reg)
    return None
