"""The same-law reference of the adhesive sphere: a rigid flat against a linear elastic half-space whose surface
has the sphere's profile, under the configuration's normal law, CGCM or Dugdale (frictionless, axisymmetric).

It answers what the Maugis-Dugdale comparison cannot: how far the 3D FE sphere is from the exact solution of its
own law, apart from the law's shape (the Lennard-Jones type traction against Dugdale's constant stress).

The surface's normal displacement is the Boussinesq integral of the interface traction. The traction is piecewise
constant on N rings of width dr, collocated at the ring centers. A uniform pressure p on a disk of radius b moves
the surface by (Johnson 1985, Contact Mechanics, section 3.4; E(k), K(k) complete elliptic integrals of modulus k)

    w(r) = 4 p b / (pi E*) E(r / b)                                   r <= b,
    w(r) = 4 p r / (pi E*) [E(b / r) - (1 - b^2 / r^2) K(b / r)]       r >= b,

and a ring is the difference of two disks, so the influence matrix is exact for the piecewise constant traction.
Greenwood (Proc. R. Soc. A 453 (1997) 1277) solved the Lennard-Jones sphere on a half-space numerically and set it
against Maugis-Dugdale.

Signs: the gap g(r) = s(r) - delta + w(r) with s the profile (s(0) = 0), delta the approach, w = C Tn(g); Tn > 0
(repulsive) pushes the surface away. The load P = sum Tn x ring area is compressive positive. The contact edge a
is where g = g_max (the gap of the largest tension: the FE's contact area), as in the FE. Edge control: delta is
an unknown and g(a) = g_max the extra equation, so the path runs through the pull-off and the unstable branch.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from functools import cached_property

import numpy as np
from scipy.interpolate import CubicSpline
from scipy.special import ellipe, ellipk

from ..laws import analytic, sphere
from ..laws.normal import NormalLaw, normal_law
from ..params import Parameters

__all__ = ["disk_displacement", "ring_influence", "cut_traction", "SphereOnHalfSpace", "EdgeSolution", "pull_off",
           "SameLawReference", "same_law_reference", "halfspace_of", "reference_radii"]

RINGS_PER_ZONE = 16  # ring width: the length E* W / T_max^2 (the cohesive zone's scale, ~ 1 / lambda^2) / 16
RADII_PER_RADIUS_SCALE = 100  # the reference path's step in the contact radius
MAX_RINGS = 3000  # a dense system: beyond this (lambda above about 8 on a band of 17 L0), no reference


def disk_displacement(r, b, E_star: float):
    """Normal surface displacement (length) at radii ``r`` from a unit pressure on a disk of radius ``b`` on an
    elastic half-space of plane-strain modulus E* (against a rigid flat), positive into the body."""
    r, b = np.broadcast_arrays(np.asarray(r, dtype=float), np.asarray(b, dtype=float))
    out = np.zeros(r.shape)
    inside = (r <= b) & (b > 0.0)
    k2 = np.where(inside, (r / np.where(b > 0.0, b, 1.0)) ** 2, 0.0)
    out[inside] = 4.0 * b[inside] * ellipe(k2[inside]) / (math.pi * E_star)
    outside = (r > b) & (b > 0.0)
    q2 = (b[outside] / r[outside]) ** 2
    out[outside] = 4.0 * r[outside] * (ellipe(q2) - (1.0 - q2) * ellipk(q2)) / (math.pi * E_star)
    return out


def ring_influence(centers, edges, E_star: float) -> np.ndarray:
    """C[i, j]: displacement at ``centers[i]`` from a unit pressure on the ring [edges[j], edges[j + 1]]."""
    disks = disk_displacement(np.asarray(centers)[:, None], np.asarray(edges)[None, :], E_star)
    return disks[:, 1:] - disks[:, :-1]


def cut_traction(law: NormalLaw, far_gap: float) -> Callable:
    """The FE's normal law as ``g -> (Tn, dTn/dg)``: ``law``'s traction (CGCM or Dugdale), zero from ``far_gap`` on
    (the contact integral drops the tail there)."""
    def traction(g):
        near = g < far_gap
        Tn, dTn = law.traction(np.where(near, g, far_gap))
        return np.where(near, Tn, 0.0), np.where(near, dTn, 0.0)
    return traction


@dataclass(frozen=True)
class EdgeSolution:
    """One equilibrium at the contact radius ``a`` (length): approach ``delta`` (length), load ``P`` (force,
    compressive positive), ring gaps ``g`` (length) and tractions ``Tn`` (stress, repulsive positive)."""

    a: float
    delta: float
    P: float
    g: np.ndarray
    Tn: np.ndarray
    iterations: int


class SphereOnHalfSpace:
    """The axisymmetric half-space under a traction law ``traction(g) -> (Tn, dTn/dg)``, on rings of width ``dr``
    out to ``r_band`` (no traction beyond, as the FE's contact band); the contact edge is where g = ``edge_gap``.
    ``profile``: ``"sphere"`` (R - sqrt(R^2 - r^2)) or ``"paraboloid"`` (r^2 / 2R). ``max_step``: the largest change
    of a ring's gap in one Newton iteration (length; a quarter of the edge gap unless given)."""

    def __init__(self, traction: Callable, R: float, E_star: float, r_band: float, dr: float, edge_gap: float,
                 profile: str = "sphere", max_step: float | None = None):
        n = int(round(r_band / dr))
        self.edges = np.linspace(0.0, r_band, n + 1)
        self.r = 0.5 * (self.edges[1:] + self.edges[:-1])
        self.ring_area = math.pi * np.diff(self.edges**2)
        self.C = ring_influence(self.r, self.edges, E_star)
        if profile == "sphere":
            self.s = R - np.sqrt(R * R - self.r**2)
        elif profile == "paraboloid":
            self.s = self.r**2 / (2.0 * R)
        else:
            raise ValueError(f"profile = {profile!r}: 'sphere' or 'paraboloid'")
        self.traction, self.edge_gap = traction, edge_gap
        self.max_step = 0.25 * edge_gap if max_step is None else max_step

    def _edge_row(self, a: float) -> np.ndarray:
        """Weights that interpolate the ring gaps linearly at radius a."""
        i = int(np.clip(np.searchsorted(self.r, a) - 1, 0, self.r.size - 2))
        t = (a - self.r[i]) / (self.r[i + 1] - self.r[i])
        row = np.zeros(self.r.size)
        row[i], row[i + 1] = 1.0 - t, t
        return row

    def solve_at_edge(self, a: float, start: tuple[np.ndarray, float] | None = None, tol: float = 1e-11,
                      max_iter: int = 60) -> EdgeSolution:
        """Equilibrium with the contact edge at ``a``: Newton on (g, delta) from ``start``. Without a start, from
        the rigid sphere with g(a) = edge_gap, through the law's amplitude raised in ten steps (the band's
        attraction can pull the surface by many interaction ranges). Raises RuntimeError when Newton does not
        converge."""
        if start is not None:
            return self._newton(a, start[0].copy(), start[1], 1.0, tol, max_iter)
        row = self._edge_row(a)
        delta = float(row @ self.s) - self.edge_gap
        g = self.s - delta
        for amplitude in np.linspace(0.1, 1.0, 10):
            sol = self._newton(a, g, delta, float(amplitude), tol, max_iter)
            g, delta = sol.g.copy(), sol.delta
        return sol

    def _newton(self, a: float, g: np.ndarray, delta: float, amplitude: float, tol: float,
                max_iter: int) -> EdgeSolution:
        """Newton on F(g, delta) = [g - s + delta - amplitude C Tn(g), g(a) - edge_gap] = 0."""
        row = self._edge_row(a)
        n = g.size
        J = np.empty((n + 1, n + 1))
        for it in range(max_iter + 1):
            Tn, dTn = self.traction(g)
            Tn, dTn = amplitude * Tn, amplitude * dTn
            F = np.concatenate([g - self.s + delta - self.C @ Tn, [row @ g - self.edge_gap]])
            if np.max(np.abs(F)) < tol * self.edge_gap:
                return EdgeSolution(a, delta, float(Tn @ self.ring_area), g, Tn, it)
            J[:n, :n] = -self.C * dTn[None, :]
            J[np.arange(n), np.arange(n)] += 1.0
            J[:n, n] = 1.0
            J[n, :n], J[n, n] = row, 0.0
            step = np.linalg.solve(J, -F)
            # keep a ring's Newton step within max_step, so that no ring jumps across the law's well
            step *= min(1.0, self.max_step / max(np.max(np.abs(step[:n])), 1e-300))
            g = g + step[:n]
            delta += step[n]
        raise RuntimeError(f"no equilibrium at a = {a:g} after {max_iter} Newton iterations")

    def edge_path(self, radii) -> list[EdgeSolution]:
        """Equilibria at the increasing contact radii ``radii``, each started from the one before."""
        out, start = [], None
        for a in np.sort(np.asarray(radii, dtype=float)):
            sol = self.solve_at_edge(float(a), start)
            out.append(sol)
            start = (sol.g, sol.delta)
        return out


def pull_off(path: list[EdgeSolution]) -> tuple[float, float]:
    """(P_c, a_c): the smallest load of an edge path and its radius, from the parabola through the smallest
    sampled load and its two neighbours (a path sampled at equal radius steps)."""
    P = np.array([sol.P for sol in path])
    i = int(np.clip(np.argmin(P), 1, P.size - 2))
    a = np.array([path[i - 1].a, path[i].a, path[i + 1].a])
    c2, c1, c0 = np.polyfit(a, P[i - 1:i + 2], 2)
    if c2 <= 0.0:
        raise ValueError("the edge path has no interior load minimum")
    a_c = -c1 / (2.0 * c2)
    return float(c0 - c1 * c1 / (4.0 * c2)), float(a_c)


@dataclass(frozen=True)
class SameLawReference:
    """P(a) of the configuration's law on a half-space (load compressive positive, E L0^2; radius L0), and its
    pull-off ``P_c`` at ``a_c``."""

    radii: np.ndarray
    loads: np.ndarray
    P_c: float
    a_c: float

    @cached_property
    def _spline(self) -> CubicSpline:
        return CubicSpline(self.radii, self.loads)

    def load_at(self, a: float) -> float:
        """The load at contact radius ``a`` (cubic spline through the path, built once)."""
        if not self.radii[0] <= a <= self.radii[-1]:
            raise ValueError(f"radius {a:g} is outside the reference path [{self.radii[0]:g}, {self.radii[-1]:g}]")
        return float(self._spline(a))


def halfspace_of(params: Parameters, profile: str = "sphere", edge_gap: float | None = None) -> SphereOnHalfSpace | None:
    """The adhesive sphere of ``params`` (its normal law, far gap and contact band; E* of its small strains) on a
    half-space, on rings of E* W_adh / T_max^2 / RINGS_PER_ZONE; None when that needs more than MAX_RINGS rings (a
    cohesive zone too narrow against the band). ``edge_gap``: the gap (L0) whose radius the edge control holds
    (the contact edge g_max unless given; a larger one is a radius inside the cohesive zone)."""
    ad, R = params.adhesion, params.geometry.R
    E_star = analytic.effective_modulus(params.material.E, params.material.nu)
    dr = E_star * ad.W_adh / ad.T_max**2 / RINGS_PER_ZONE
    band = params.mesh.band_half_width
    if band / dr > MAX_RINGS:
        return None
    law = normal_law(ad)
    max_step = 0.1 * law.rho if ad.law == "dugdale" else None  # a ring's step within a tenth of the Dugdale ramp
    return SphereOnHalfSpace(cut_traction(law, params.contact.far_gap), R, E_star, band, dr,
                             ad.g_max if edge_gap is None else edge_gap, profile, max_step)


def reference_radii(params: Parameters, a_max: float) -> np.ndarray:
    """The radii (L0) of a reference path up to ``a_max``: steps of Maugis-Dugdale's radius scale / 100."""
    E_star = analytic.effective_modulus(params.material.E, params.material.nu)
    step = sphere.md_scales(params.geometry.R, E_star, params.adhesion.W_adh)["radius"] / RADII_PER_RADIUS_SCALE
    return np.arange(2.0 * step, a_max + 2.0 * step, step)


def same_law_reference(params: Parameters, a_max: float, profile: str = "sphere",
                       edge_gap: float | None = None) -> SameLawReference | None:
    """P(a) of the adhesive sphere of ``params`` on a half-space (:func:`halfspace_of`), along the edge path up to
    the radius ``a_max`` of the gap ``edge_gap``; None when it needs more than MAX_RINGS rings."""
    halfspace = halfspace_of(params, profile, edge_gap)
    if halfspace is None:
        return None
    path = halfspace.edge_path(reference_radii(params, a_max))
    P_c, a_c = pull_off(path)
    return SameLawReference(np.array([s.a for s in path]), np.array([s.P for s in path]), P_c, a_c)
