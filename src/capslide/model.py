"""The discrete cap-on-substrate system: bulk + contact + clamped base + one scalar constraint.

Unknowns x = [u (n_dofs), h]. Equations: the cap's residual R(u, h) = 0 and
one scalar constraint G(x) = 0 that fixes the load path:

* ``FixedHeight(h*)``:  G = h - h*          (displacement control)
* ``FixedForce(F*)``:   G = Fn(u, h) - F*    (force control)
* ``FixedApexGap(g*)``: G = h - y_apex - g*  (local displacement control that
  follows the jump-in instability through its turning point)
* ``FixedEdgeGap(X, g*)``: G = h - (y(-X) + y(X))/2 - g*, y(X) the current
  height of the top-surface material point at reference abscissa X (linear
  between surface nodes): holds the contact edge at X while the contact
  spreads, a parameter that stays monotone where force, h and the apex gap
  turn (the JKR load is a function of the half-width)
* ``SlideAtForce(ubar, F*)``: G = Fn - F* with the substrate slid by ubar

Each Newton step solves the bordered system [K c; d^T e]: with a solver that
offers ``solve_bordered`` (``lu_krylov``) in one Krylov run preconditioned by
the bordered system of a stored factorization, otherwise with two solves on
the same matrix K (K z1 = R, K z2 = c) and the scalar Schur complement
e - d.z2.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .assembly import BulkForm, Dirichlet
from .interface import SurfaceContact
from .linsolve import make_solver
from .mesh import Mesh
from .params import Parameters

__all__ = ["FixedHeight", "FixedForce", "FixedApexGap", "FixedEdgeGap", "SlideAtForce", "CapModel"]


@dataclass(frozen=True)
class FixedHeight:
    h: float


@dataclass(frozen=True)
class FixedForce:
    Fn: float


@dataclass(frozen=True)
class FixedApexGap:
    gap: float


@dataclass(frozen=True)
class FixedEdgeGap:
    X: float  # reference abscissa of the held surface points +-X (L0)
    gap: float


@dataclass(frozen=True)
class SlideAtForce:
    ubar: float
    Fn: float


class _BorderedSolve:
    """Callable returning J^{-1} r for the bordered Jacobian; counts Krylov iterations."""

    def __init__(self, solver, K, c, d, e):
        self.solver, self.K, self.c, self.d, self.e = solver, K, c, d, e
        self.iterations = 0

    def __call__(self, r: np.ndarray) -> np.ndarray:
        if hasattr(self.solver, "solve_bordered"):  # one Krylov run on the whole bordered system
            x, info = self.solver.solve_bordered(self.K, self.c, self.d, self.e, r)
            self.iterations += info.iterations
            return x
        R, G = r[:-1], r[-1]
        Z, info = self.solver.solve(self.K, np.column_stack([R, self.c]))
        self.iterations += info.iterations
        z1, z2 = Z[:, 0], Z[:, 1]
        schur = self.e - self.d @ z2
        if schur == 0.0 or not np.isfinite(schur):
            raise np.linalg.LinAlgError("singular bordered system (Schur complement zero)")
        dh = (G - self.d @ z1) / schur
        return np.concatenate([z1 - z2 * dh, [dh]])


class CapModel:
    """Residual and linearization of the cap against the rigid flat."""

    def __init__(self, mesh: Mesh, params: Parameters, solver: str | None = None):
        self.mesh, self.params = mesh, params
        m = params.material
        self.bulk = BulkForm(mesh, m.lam, m.mu)
        self.contact = SurfaceContact(
            mesh, params.adhesion, params.mesh.surface_gauss_points,
            far_gap=params.contact.far_gap, repulsion_only=params.contact.repulsion_only,
            friction=params.friction, contact_gap=params.contact.area_gap,
        )
        self.bc = Dirichlet.on_nodes(mesh.base, self.bulk.pattern)
        self.solver = make_solver(solver or params.solver.linear, mesh.nodes, params.solver.krylov_rtol)
        self.n_dofs = mesh.n_dofs
        # contact blocks of a surface segment land in the bulk pattern (the segment's nodes share a cell)
        seg_dofs = self.contact.seg_dofs
        m2 = seg_dofs.shape[1]
        rows = np.repeat(seg_dofs, m2, axis=1).reshape(-1, m2, m2)
        cols = np.tile(seg_dofs, (1, m2)).reshape(-1, m2, m2)
        self._contact_slots = self.bulk.pattern.positions(rows.ravel(), cols.ravel()).reshape(-1, m2 * m2)
        apex = int(np.argmax(mesh.nodes[:, 1]))
        self.apex_node = apex
        self._apex_y = 2 * apex + 1
        self._surface = mesh.surface_nodes
        self._surface_X = mesh.nodes[self._surface, 0]

    # -- helpers --------------------------------------------------------
    def split(self, x: np.ndarray) -> tuple[np.ndarray, float]:
        return x[:-1], float(x[-1])

    def apex_gap(self, x: np.ndarray) -> float:
        u, h = self.split(x)
        return h - (self.mesh.nodes[self.apex_node, 1] + u[self._apex_y])

    def edge_weights(self, X: float) -> tuple[np.ndarray, np.ndarray]:
        """y-DOFs and weights w of the mean height (y(-X) + y(X))/2 = sum w (Y + u_y) of the surface points at +-X."""
        Xs = self._surface_X
        if not abs(X) <= min(-Xs[0], Xs[-1]):
            raise ValueError(f"edge abscissa {X:g} outside the top surface [{Xs[0]:g}, {Xs[-1]:g}]")
        pts = np.array([-abs(X), abs(X)])
        i = np.clip(np.searchsorted(Xs, pts, side="right") - 1, 0, len(Xs) - 2)
        t = (pts - Xs[i]) / (Xs[i + 1] - Xs[i])
        nodes = np.concatenate([self._surface[i], self._surface[i + 1]])
        return 2 * nodes + 1, 0.5 * np.concatenate([1.0 - t, t])

    def edge_gap(self, x: np.ndarray, X: float) -> float:
        """Mean gap (L0) of the top-surface material points at reference abscissa +-X."""
        dofs, w = self.edge_weights(X)
        y = self.mesh.nodes.ravel()[dofs] + x[dofs]
        return float(x[-1] - w @ y)

    def admissible(self, x: np.ndarray) -> bool:
        return self.bulk.min_jacobian(x[:-1]) > 0.0

    def _constraint(self, constraint, x: np.ndarray, Fn: float) -> float:
        u, h = self.split(x)
        if isinstance(constraint, FixedHeight):
            return h - constraint.h
        if isinstance(constraint, (FixedForce, SlideAtForce)):
            return Fn - constraint.Fn
        if isinstance(constraint, FixedApexGap):
            return self.apex_gap(x) - constraint.gap
        if isinstance(constraint, FixedEdgeGap):
            return self.edge_gap(x, constraint.X) - constraint.gap
        raise TypeError(f"unknown constraint {constraint!r}")

    # -- Newton callables -------------------------------------------------
    def residual(self, x: np.ndarray, constraint) -> np.ndarray:
        u, h = self.split(x)
        f_c, Fn, _ = self.contact.force(u, h, getattr(constraint, "ubar", 0.0))
        r = self.bulk.residual(u) - f_c
        r[self.bc.dofs] = 0.0
        return np.concatenate([r, [self._constraint(constraint, x, Fn)]])

    def linearize(self, x: np.ndarray, constraint):
        u, h = self.split(x)
        f_int, data = self.bulk.residual_and_tangent_data(u)
        lin = self.contact.linearize(u, h, getattr(constraint, "ubar", 0.0))
        np.add.at(data, self._contact_slots[lin.active_segments].ravel(), lin.blocks.ravel())
        r = f_int - lin.f
        self.bc.apply(data, r)
        c = lin.dR_dh.copy()
        c[self.bc.dofs] = 0.0
        if isinstance(constraint, FixedHeight):
            d, e = np.zeros(self.n_dofs), 1.0
        elif isinstance(constraint, (FixedForce, SlideAtForce)):
            d, e = lin.dFn_du.copy(), lin.dFn_dh
            d[self.bc.dofs] = 0.0
        elif isinstance(constraint, FixedEdgeGap):
            d, e = np.zeros(self.n_dofs), 1.0
            dofs, w = self.edge_weights(constraint.X)
            np.add.at(d, dofs, -w)
        else:  # FixedApexGap: G = h - Y_apex - u_apex,y - g*
            d, e = np.zeros(self.n_dofs), 1.0
            d[self._apex_y] = -1.0
        K = self.bulk.pattern.matrix(data)
        G = self._constraint(constraint, x, lin.Fn)
        return np.concatenate([r, [G]]), _BorderedSolve(self.solver, K, c, d, e)

    # -- measures of a state ----------------------------------------------
    def base_reaction(self, x: np.ndarray) -> np.ndarray:
        """Sum of the internal forces at the clamped base nodes (x, y), E L0."""
        f = self.bulk.residual(x[:-1]).reshape(-1, 2)
        return f[self.mesh.base].sum(axis=0)
