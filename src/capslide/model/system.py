"""The discrete cap-on-substrate system: bulk + contact + clamped base + one scalar load constraint.

Unknowns x = [u (n_dofs), h]. Equations: the cap's residual R(u, h) = f_int - f_contact = 0 and the constraint
G(x) = 0 of :mod:`capslide.model.constraints`. The history (:class:`History`) is an explicit input of every
evaluation and is renewed only by :meth:`CapModel.commit` at converged states; so is the step's time increment
``dt`` (s), which only a viscoelastic bulk uses (0: instantaneous).

Each Newton step solves the bordered system [K c; d^T e]: with a solver that offers ``solve_bordered``
(``lu_krylov``) in one Krylov run preconditioned by the bordered system of a stored factorization, otherwise with
two solves on the same matrix K (K z1 = R, K z2 = c) and the scalar Schur complement e - d.z2.
"""

from __future__ import annotations

import copy
from dataclasses import dataclass, replace

import numpy as np

from ..fem.assembly import BulkForm, Dirichlet, node_dofs
from ..fem.interface import SurfaceContact
from ..fem.mesh import Mesh
from ..fem.mixed import MixedBulkForm
from ..fem.viscous import Networks, ViscousBranches
from ..laws.friction import ReturnMapSettings, Sticking, friction_law
from ..params import Parameters
from ..solvers.interfaces import KeepsFactors, LinearSolver, SolvesBordered
from .constraints import FixedForce

__all__ = ["History", "BorderedSolve", "CapModel"]


@dataclass(frozen=True)
class History:
    """State variables that change only at converged steps: the friction anchors (s, g; 3D: (s, g, 2), x and y),
    None before friction;
    with slip weakening each point's accumulated slip (s, g), None without; at nu = 0.5 the augmented Lagrangian's
    pressure multiplier (n_cells, 3; P1 coefficients, E), None = zero (fem.mixed); with a viscoelastic bulk the
    branches' networks (fem.viscous), None = undeformed; the time of the state (s; 0 when quasi-static); with
    ``friction.threshold_at = step_start`` the sliding thresholds of the state (s, g; E), which the next step holds
    fixed, None otherwise."""

    anchors: np.ndarray | None = None
    slip: np.ndarray | None = None
    pressure: np.ndarray | None = None
    networks: Networks | None = None
    time: float = 0.0
    thresholds: np.ndarray | None = None

    @property
    def friction(self) -> tuple[np.ndarray | None, np.ndarray | None, np.ndarray | None]:
        """The friction history as the contact's methods take it: (anchors, slip, thresholds)."""
        return self.anchors, self.slip, self.thresholds


class BorderedSolve:
    """Callable returning J^{-1} r for the bordered Jacobian [K c; d^T e]; counts Krylov iterations. ``inexact``:
    the solver runs one Krylov solve on the bordered system, and ``self(r, eta)`` stops it at the relative residual
    eta (never below the solver's own tolerance); other solvers ignore eta."""

    def __init__(self, solver: LinearSolver, K, c, d, e):
        self.solver, self.K, self.c, self.d, self.e = solver, K, c, d, e
        self.iterations = 0
        self.inexact = isinstance(solver, SolvesBordered)

    def next_increment(self, r: np.ndarray) -> float | None:
        """||J0^{-1} r||_inf with the solver's stored factors J0 (an earlier Jacobian, or this one with the direct
        solver): the size of the increment a Newton iteration would take from the residual r, estimated without a
        new tangent or Krylov run; None when the solver keeps no factors."""
        dx = self.solver.approximate_bordered(self.c, self.d, self.e, r) if isinstance(self.solver, KeepsFactors) else None
        return None if dx is None else float(np.max(np.abs(dx)))

    def __call__(self, r: np.ndarray, eta: float | None = None) -> np.ndarray:
        if self.inexact:  # one Krylov run on the whole bordered system
            x, info = self.solver.solve_bordered(self.K, self.c, self.d, self.e, r, rtol=eta)
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
    """Residual and linearization of the cap against the rigid flat; ``solver`` is the linear solver to use."""

    def __init__(self, mesh: Mesh, params: Parameters, solver: LinearSolver):
        self.mesh, self.params, self.solver = mesh, params, solver
        m = params.material
        mixed = params.mesh.formulation == "mixed"
        self.bulk = MixedBulkForm(mesh, m.lam, m.mu) if mixed else BulkForm(mesh, m.lam, m.mu)
        self.branches = ViscousBranches(self.bulk, m.mu, m.prony_g, m.prony_tau) if m.prony_g else None
        self.contact = SurfaceContact(
            mesh, params.adhesion, params.mesh.surface_gauss_points,
            far_gap=params.contact.far_gap, repulsion_only=params.contact.repulsion_only,
            law=friction_law(params.friction, params.adhesion),
            return_map=ReturnMapSettings(params.friction.eps_t, params.friction.weakening,
                                         params.friction.threshold_at in ("step_start", "step_predicted")),
            contact_gap=params.contact.area_gap,
            normal_per_current_area=params.contact.normal_traction_area == "current",
        )
        self.predicts_thresholds = params.friction.threshold_at == "step_predicted"
        self.dim = d = mesh.dim
        # the clamped base; in a 3D half model also the normal (y) DOFs of the plane of symmetry
        fixed = node_dofs(mesh.base, d)
        self.bc = Dirichlet.on_dofs(np.union1d(fixed, d * mesh.symmetry + 1) if len(mesh.symmetry) else fixed,
                                    self.bulk.pattern)
        self.n_dofs = mesh.n_dofs
        # contact blocks of a surface segment land in the bulk pattern (the segment's nodes share a cell)
        seg_dofs = self.contact.seg_dofs
        m2 = seg_dofs.shape[1]
        rows = np.repeat(seg_dofs, m2, axis=1).reshape(-1, m2, m2)
        cols = np.tile(seg_dofs, (1, m2)).reshape(-1, m2, m2)
        self._contact_slots = self.bulk.pattern.positions(rows.ravel(), cols.ravel()).reshape(-1, m2 * m2)
        self.apex_node = int(np.argmax(mesh.nodes[:, -1]))
        self.apex_y_dof = d * self.apex_node + d - 1  # the apex's vertical DOF
        # the edge gap's material points, by reference x: the top line (2D), the top's line on the plane of symmetry (3D)
        if d == 2:
            self._surface = mesh.surface_nodes
        else:
            top = np.unique(mesh.surface_segments)
            line = top[mesh.nodes[top, 1] == 0.0]
            self._surface = line[np.argsort(mesh.nodes[line, 0])]
        self._surface_X = mesh.nodes[self._surface, 0]

    def sticking(self) -> CapModel:
        """This model with every surface point held in stick (:class:`capslide.laws.friction.Sticking`, no slip
        weakening) and a fresh linear solver of the same settings, so that its solves leave this model's factors
        alone: the model of the slide's stick predictor (loadpath.continuation)."""
        stuck = copy.copy(self)
        stuck.contact = copy.copy(self.contact)
        stuck.contact.law, stuck.contact.weakening, stuck.contact.threshold_at_step_start = Sticking(), None, False
        stuck.solver = replace(self.solver)
        return stuck

    # -- geometry of a state ------------------------------------------------
    def split(self, x: np.ndarray) -> tuple[np.ndarray, float]:
        return x[:-1], float(x[-1])

    def apex_gap(self, x: np.ndarray) -> float:
        u, h = self.split(x)
        return h - (self.mesh.nodes[self.apex_node, -1] + u[self.apex_y_dof])

    def edge_weights(self, X: float) -> tuple[np.ndarray, np.ndarray]:
        """Vertical DOFs and weights w of the mean height (y(-X) + y(X))/2 = sum w (Y + u_y) of the surface points at
        +-X (3D: on the plane of symmetry, z for y)."""
        Xs = self._surface_X
        if not abs(X) <= min(-Xs[0], Xs[-1]):
            raise ValueError(f"edge abscissa {X:g} outside the top surface [{Xs[0]:g}, {Xs[-1]:g}]")
        pts = np.array([-abs(X), abs(X)])
        i = np.clip(np.searchsorted(Xs, pts, side="right") - 1, 0, len(Xs) - 2)
        t = (pts - Xs[i]) / (Xs[i + 1] - Xs[i])
        nodes = np.concatenate([self._surface[i], self._surface[i + 1]])
        return self.dim * nodes + self.dim - 1, 0.5 * np.concatenate([1.0 - t, t])

    def edge_limit(self) -> float:
        """The largest edge abscissa X (L0) of :meth:`edge_weights`: the nearer end of the surface line."""
        return float(np.min(np.abs(self._surface_X[[0, -1]])))

    def edge_gap(self, x: np.ndarray, X: float) -> float:
        """Mean gap (L0) of the top-surface material points at reference abscissa +-X."""
        dofs, w = self.edge_weights(X)
        y = self.mesh.nodes.ravel()[dofs] + x[dofs]
        return float(x[-1] - w @ y)

    def admissible(self, x: np.ndarray) -> bool:
        return self.bulk.min_jacobian(x[:-1]) > 0.0

    # -- Newton callables -------------------------------------------------
    def internal_force(self, u: np.ndarray, history: History, dt: float = 0.0) -> np.ndarray:
        """The bulk's internal forces (E L0) at the end of a step of dt seconds from ``history``."""
        f = self.bulk.residual(u, history.pressure)
        return f if self.branches is None else f + self.branches.residual(u, history.networks, dt)

    def residual(self, x: np.ndarray, constraint, history: History, dt: float = 0.0) -> np.ndarray:
        u, h = self.split(x)
        f_c, Fn, _ = self.contact.force(u, h, constraint.ubar, *history.friction)
        r = self.internal_force(u, history, dt) - f_c
        r[self.bc.dofs] = 0.0
        return np.concatenate([r, [constraint.residual(self, x, Fn)]])

    def linearize(self, x: np.ndarray, constraint, history: History, dt: float = 0.0
                  ) -> tuple[np.ndarray, BorderedSolve]:
        u, h = self.split(x)
        f_int, data = self.bulk.residual_and_tangent_data(u, history.pressure)
        if self.branches is not None:
            f_v, data_v = self.branches.residual_and_tangent_data(u, history.networks, dt)
            f_int, data = f_int + f_v, data + data_v
        lin = self.contact.linearize(u, h, constraint.ubar, *history.friction)
        np.add.at(data, self._contact_slots[lin.active_segments].ravel(), lin.blocks.ravel())
        r = f_int - lin.f
        self.bc.apply(data, r)
        c = lin.dR_dh.copy()
        c[self.bc.dofs] = 0.0
        d, e = constraint.border(self, x, lin)
        K = self.bulk.pattern.matrix(data)
        G = constraint.residual(self, x, lin.Fn)
        return np.concatenate([r, [G]]), BorderedSolve(self.solver, K, c, d, e)

    def normal_stiffness(self, x: np.ndarray, history: History) -> float:
        """dFn/dh along equilibria (E: force per width per length), bulk and contact together, at the converged
        state x: the Schur complement e - d.K^{-1}c of the force-controlled bordered system. Positive: lowering
        the substrate makes Fn more compressive."""
        _, solve = self.linearize(x, FixedForce(0.0), history)
        z, _ = self.solver.solve(solve.K, solve.c)
        return float(solve.e - solve.d @ z)

    def saved_shapes(self) -> dict[str, tuple[int, ...]]:
        """The shapes of the arrays a saved state of this model holds (capslide.io.state_check): the state [u, h],
        the friction history per surface point, the pressure multiplier, the viscous branches' networks, a step
        record's surface profile (its y parts of the tangential vectors: empty in 2D) and base reaction, a
        snapshot's nodal displacements and cell invariant."""
        points, n_dofs = self.contact.quad.X.shape[:-1], self.n_dofs + 1
        anchors = points if self.dim == 2 else (*points, 2)
        shapes = {"x": (n_dofs,), "loop_x": (n_dofs,), "loop_x_prev": (n_dofs,), "anchors": anchors,
                  "accumulated_slip": points, "frozen_thresholds": points,
                  "profile": (int(np.prod(points)),), "reaction": (self.dim,),
                  "profile_3d": (int(np.prod(points)) if self.dim == 3 else 0,),
                  "snapshot_u": (self.mesh.n_nodes, self.dim), "snapshot_I1_sigma": (self.mesh.n_cells,)}
        if self.params.mesh.formulation == "mixed":
            shapes["pressure_multiplier"] = (self.mesh.n_cells, self.bulk.Np.shape[-1])
        if self.branches is not None:
            qp = self.bulk.wdetJ.shape
            shapes.update(viscous_networks=(*qp, len(self.branches.g), 2, 2), viscous_c_inv=(*qp, 2, 2))
        return shapes

    # -- friction history ---------------------------------------------------
    def start_friction(self, x: np.ndarray, ubar: float = 0.0, history: History | None = None) -> History:
        """``history`` (default: none) with every surface point anchored where it is (friction acts from here on)."""
        anchors = self.contact.anchors_at(x[:-1], ubar)
        slip = None if self.contact.weakening is None else np.zeros(self.contact.quad.weight.shape)
        return replace(history or History(), anchors=anchors, slip=slip,
                       thresholds=self.contact.point_thresholds(x[:-1], x[-1]))

    def commit(self, x: np.ndarray, ubar: float, history: History, dt: float = 0.0) -> History:
        """The history after the converged state x, a step of dt seconds on (slipping points' anchors follow the
        return map, and their accumulated slip grows by the anchors' move; the viscous networks relax; the thresholds
        that the next step holds fixed are x's)."""
        anchors = self.contact.committed_anchors(x[:-1], x[-1], ubar, *history.friction)
        history = self.committed_bulk(x, history, dt)
        if anchors is not None:
            history = replace(history, thresholds=self.contact.point_thresholds(x[:-1], x[-1]))
        if history.slip is None:
            return replace(history, anchors=anchors)
        moved = anchors - history.anchors
        slip = np.abs(moved) if self.dim == 2 else np.linalg.norm(moved, axis=-1)  # 3D: the anchors' move in the plane
        return replace(history, anchors=anchors, slip=history.slip + slip)

    def step_history(self, history: History, x: np.ndarray, x_before: np.ndarray | None, ratio: float) -> History:
        """The history a step from the converged state x holds, the step ``ratio`` times as long as the one from
        ``x_before`` to x: with ``friction.threshold_at = step_predicted`` the thresholds at the gaps and stretches
        extrapolated to the step's end (held at x's when there is no step before); else ``history`` itself."""
        if not self.predicts_thresholds or history.thresholds is None or x_before is None or not ratio > 0.0:
            return history
        before = (x_before[:-1], x_before[-1])
        return replace(history, thresholds=self.contact.point_thresholds(x[:-1], x[-1], before, ratio))

    def committed_bulk(self, x: np.ndarray, history: History, dt: float) -> History:
        """``history`` with the bulk's part (the viscous networks and the time) moved to the converged state x."""
        if self.branches is None:
            return history if dt == 0.0 else replace(history, time=history.time + dt)
        return replace(history, networks=self.branches.committed(x[:-1], history.networks, dt), time=history.time + dt)

    def updated_pressure(self, x: np.ndarray, history: History) -> History | None:
        """At nu = 0.5, Uzawa's update of the pressure multiplier (lambda <- p) while max |theta - 1| exceeds
        fem.mixed.VOLUME_TOLERANCE at the converged state x; None when the constraint holds (or nothing is
        incompressible)."""
        multiplier = self.bulk.updated_multiplier(x[:-1], history.pressure)
        return None if multiplier is None else replace(history, pressure=multiplier)

    # -- measures of a state ----------------------------------------------
    def base_reaction(self, x: np.ndarray, history: History | None = None, dt: float = 0.0) -> np.ndarray:
        """Sum of the internal forces at the clamped base nodes (x, y (, z)), E L0 (E L0^2 in 3D), at the end of a
        step of dt seconds from ``history`` (its pressure multiplier and viscous networks)."""
        f = self.internal_force(x[:-1], history or History(), dt).reshape(-1, self.dim)
        reaction = f[self.mesh.base].sum(axis=0)
        if self.contact.multiplicity != 1.0:  # a half model: the whole body's (the y part cancels by symmetry)
            reaction = self.contact.multiplicity * reaction * (np.arange(self.dim) != 1)
        return reaction

    def cell_first_invariant(self, x: np.ndarray, history: History) -> np.ndarray:
        """I1(sigma) averaged over each cell (E) of the converged state x, ``history`` the one after it."""
        I1 = self.bulk.cell_first_invariant(x[:-1], history.pressure)
        return I1 if self.branches is None else I1 + self.branches.cell_first_invariant(x[:-1], history.networks, 0.0)

    def step_energy(self, x: np.ndarray, constraint, history: History) -> float | None:
        """The potential of a step's equations from ``history`` (E L0^2 per unit width; 3D E L0^3, the whole
        body's): the bulk's energy, the adhesion's, the friction's with its thresholds held at the step's start, and
        the load's (``constraint.potential``). Its gradient is the residual with the u rows times the half model's
        multiplicity (:meth:`energy_gradient`); at a fixed height, in u at h = h*. None where the step has none: a
        constraint without a potential, a viscoelastic bulk, theta_k = J_s, or friction whose threshold follows the
        state or weakens."""
        potential = getattr(constraint, "potential", None)
        if potential is None or self.branches is not None or self.contact.normal_per_current_area:
            return None
        u, h = self.split(x)
        friction = self.contact.friction_energy(u, h, constraint.ubar, history.anchors, history.thresholds)
        if not np.isfinite(friction):
            return None
        return self.strain_energy(x, history) + self.contact.adhesion_energy(u, h) + friction + potential(h)

    def energy_gradient(self, r: np.ndarray) -> np.ndarray:
        """The gradient of :meth:`step_energy` from the residual r = [R(u), G] at the same state: R is the modelled
        part's (a half model's: times 2), G the whole body's."""
        return np.concatenate([self.contact.multiplicity * r[:-1], r[-1:]])

    def strain_energy(self, x: np.ndarray, history: History, dt: float = 0.0) -> float:
        """The bulk's stored energy per unit width (E L0^2; in 3D E L0^3, the whole body's) at the end of a step of
        dt seconds from ``history``: the elastic part and the viscous branches'."""
        W = self.contact.whole(self.bulk.strain_energy(x[:-1], history.pressure))
        return W if self.branches is None else W + self.branches.energy(x[:-1], history.networks, dt)
