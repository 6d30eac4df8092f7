"""A Dugdale normal law for verification: the constant tension sigma0 of Maugis-Dugdale's cohesive zone over the
range h0 = W / sigma0 (Maugis, J. Colloid Interface Sci. 150 (1992) 243), with a stiff repulsive penalty where the
surfaces touch. It lets the FE sphere be checked against the Maugis-Dugdale solution itself, apart from the CGCM
law's shape (docs/three_d.md).

Piecewise linear, so that Newton has a tangent everywhere; the penalty's width delta and the ramp's width rho
are fractions of h0, and the law tends to Dugdale's as both go to zero:

    Tn(g) = sigma0 (g_eq - g) / delta                 g <= g_edge = g_eq + delta
    Tn(g) = -sigma0                                   g_edge <= g <= g_end - rho / 2
    Tn(g) = -sigma0 (g_end + rho / 2 - g) / rho       on the ramp |g - g_end| < rho / 2
    Tn(g) = 0                                         g >= g_end + rho / 2

with g_end = g_edge + h0 - delta / 2, so that the work of separation from g_eq is exactly W = sigma0 h0. The
contact edge, where the Dugdale stress starts, is at g_edge (the law's g_max). Signs as in
:mod:`capslide.laws.contact`: g > 0 apart, Tn > 0 repulsive; any consistent units.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["DugdaleLaw"]


@dataclass(frozen=True)
class DugdaleLaw:
    """The smoothed Dugdale law: stress ``sigma0``, zero-traction gap ``g_eq``, penalty width ``delta``, the
    zone's end ``g_end`` and the ramp's width ``rho`` (lengths)."""

    sigma0: float
    g_eq: float
    delta: float
    g_end: float
    rho: float

    @classmethod
    def from_work(cls, sigma0: float, W: float, g_eq: float, ramp: float, penalty: float) -> DugdaleLaw:
        """The law of Dugdale stress ``sigma0`` and work of adhesion ``W`` (h0 = W / sigma0), zero traction at
        ``g_eq``, its ramp ``ramp`` h0 and its penalty ``penalty`` h0 wide."""
        h0 = W / sigma0
        delta = penalty * h0
        return cls(sigma0, g_eq, delta, g_eq + delta + h0 - 0.5 * delta, ramp * h0)

    @property
    def g_edge(self) -> float:
        """The contact edge: the gap where the Dugdale stress starts (length)."""
        return self.g_eq + self.delta

    def _pieces(self, g: np.ndarray) -> list[np.ndarray]:
        return [g <= self.g_edge, g <= self.g_end - 0.5 * self.rho, g < self.g_end + 0.5 * self.rho]

    def traction(self, g) -> tuple[np.ndarray, np.ndarray]:
        """Tn(g) (stress, repulsive positive) and dTn/dg."""
        g = np.asarray(g, dtype=float)
        s, hi = self.sigma0, self.g_end + 0.5 * self.rho
        pieces = self._pieces(g)
        Tn = np.select(pieces, [s * (self.g_eq - g) / self.delta, -s, -s * (hi - g) / self.rho], 0.0)
        dTn = np.select(pieces, [-s / self.delta, 0.0, s / self.rho], 0.0)
        return Tn, dTn

    def potential(self, g, g_far: float = np.inf) -> np.ndarray:
        """phi(g) = int_g^g_far Tn(s) ds for g < g_far, 0 beyond (energy per area; dphi/dg = -Tn): with the whole
        law, phi(g_eq) = -W."""
        g = np.asarray(g, dtype=float)
        phi = self._potential(g)
        return np.where(g < g_far, phi - self._potential(g_far), 0.0) if np.isfinite(g_far) else phi

    def _potential(self, g) -> np.ndarray:
        g = np.asarray(g, dtype=float)
        s, hi = self.sigma0, self.g_end + 0.5 * self.rho
        at_edge = -s * (self.g_end - self.g_edge)
        return np.select(self._pieces(g), [at_edge + 0.5 * s / self.delta * ((self.g_eq - g) ** 2 - self.delta**2),
                                           -s * (self.g_end - g), -0.5 * s * (hi - g) ** 2 / self.rho], 0.0)
