"""Load constraints: the one scalar equation G(x) = 0 that closes the bordered system (unknowns x = [u, h]).

Each constraint gives its residual row G and the border terms of the Jacobian, d = dG/du and e = dG/dh, from the
model and the contact linearization. ``ubar`` is the substrate's tangential displacement under which the contact
is evaluated (L0; zero except while sliding). Adding a way to load the cap means adding one class here.

* ``FixedHeight(h)``:      G = h - h*                        (displacement control)
* ``FixedForce(Fn)``:      G = Fn(u, h) - F*                  (force control)
* ``FixedApexGap(gap)``:   G = h - y_apex - g*                (follows the jump-in through its turning point)
* ``FixedEdgeGap(X, gap)``: G = h - (y(-X) + y(X))/2 - g*     (holds the contact edge while the contact spreads)
* ``SlideAtForce(ubar, Fn)``: G = Fn - F* with the substrate slid by ubar
* ``SlideOnSpring(ubar, Fn, h, k)``: G = Fn - F* + k (h - h*)  (the substrate hangs from a fixed stage through a
  vertical spring of stiffness k (E = force per width per length), which holds F* at h*; k -> 0 is force
  control, k -> infinity fixes h = h*)

A slide at a fixed height is ``FixedHeight(h, ubar)``.

The force-controlled constraints also give ``potential(h)``, the load's part of the step's energy (E L0^2; 3D
E L0^3), whose derivative in h is G - Fn: with the contact's energy, whose derivative in h is Fn, the row G is that
energy's gradient in h (loadpath.snap_through's merit function). ``FixedHeight`` gives a potential of 0 and
``project(x)``, the state at h = h*: its step's energy is the displacements' at that height. The gap controls have
none.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Protocol

import numpy as np

__all__ = ["Constraint", "FixedHeight", "FixedForce", "FixedApexGap", "FixedEdgeGap", "SlideAtForce", "SlideOnSpring"]


class Constraint(Protocol):
    ubar: float

    def residual(self, model, x: np.ndarray, Fn: float) -> float:
        """G(x); ``Fn`` is the normal contact force at x (E L0)."""

    def border(self, model, x: np.ndarray, lin) -> tuple[np.ndarray, float]:
        """(dG/du with the clamped DOFs zeroed, dG/dh) at x; ``lin`` is the contact linearization at x."""


def _unit_border(model, dofs=(), weights=()) -> tuple[np.ndarray, float]:
    """d = -sum of weights at y-DOFs (a height of surface material points subtracted from h), e = 1."""
    d = np.zeros(model.n_dofs)
    np.add.at(d, np.asarray(dofs, dtype=int), -np.asarray(weights, dtype=float))
    return d, 1.0


@dataclass(frozen=True)
class FixedHeight:
    h: float  # L0
    ubar: float = 0.0

    def residual(self, model, x, Fn):
        return float(x[-1]) - self.h

    def border(self, model, x, lin):
        return _unit_border(model)

    def potential(self, h: float) -> float:
        """The load does no work at a fixed height: the step's energy is the displacements' at h = h*, over the
        states :meth:`project` gives."""
        return 0.0

    def project(self, x: np.ndarray) -> np.ndarray:
        """x with the substrate at h*, where the step's energy is taken."""
        y = np.array(x, dtype=float)
        y[-1] = self.h
        return y


class _ForceControl:
    """G = Fn - F*: the border is the contact force's own linearization; the load's potential is -F* h."""

    def potential(self, h: float) -> float:
        return -self.Fn * h

    def residual(self, model, x, Fn):
        return Fn - self.Fn

    def border(self, model, x, lin):
        d = lin.dFn_du.copy()
        d[model.bc.dofs] = 0.0
        return d, lin.dFn_dh


@dataclass(frozen=True)
class FixedForce(_ForceControl):
    Fn: float  # E L0, positive = tensile
    ubar: float = 0.0


@dataclass(frozen=True)
class SlideAtForce(_ForceControl):
    ubar: float  # L0
    Fn: float  # E L0, positive = tensile


@dataclass(frozen=True)
class FixedApexGap:
    gap: float  # L0
    ubar: float = 0.0

    def residual(self, model, x, Fn):
        return model.apex_gap(x) - self.gap

    def border(self, model, x, lin):
        return _unit_border(model, [model.apex_y_dof], [1.0])


@dataclass(frozen=True)
class FixedEdgeGap:
    X: float  # reference abscissa of the held surface points +-X (L0)
    gap: float  # L0
    ubar: float = 0.0

    def residual(self, model, x, Fn):
        return model.edge_gap(x, self.X) - self.gap

    def border(self, model, x, lin):
        return _unit_border(model, *model.edge_weights(self.X))


@dataclass(frozen=True)
class SlideOnSpring(_ForceControl):
    """The substrate on a spring from a fixed stage: the spring force F* - k (h - h*) balances Fn (positive
    tensile); the substrate rising by dh lowers the spring's pull by k dh."""

    ubar: float  # L0
    Fn: float  # E L0: the spring force at h*
    h: float  # L0: the substrate height where the spring pulls F*
    k: float  # E (force per width E L0 per length L0)

    def residual(self, model, x, Fn):
        return Fn - self.Fn + self.k * (float(x[-1]) - self.h)

    def potential(self, h: float) -> float:
        return -self.Fn * h + 0.5 * self.k * (h - self.h) ** 2

    def border(self, model, x, lin):
        d, e = super().border(model, x, lin)
        return d, e + self.k
