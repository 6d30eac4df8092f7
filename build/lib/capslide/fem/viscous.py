"""The viscous branches of a viscoelastic bulk on a mesh: forces, tangent and committed networks at every
quadrature point (laws in :mod:`capslide.laws.viscoelastic`).

The branches add to any elastic :class:`capslide.fem.assembly.BulkForm` (displacement or mixed Q2/P1, whose
volumetric part they leave alone) and share its geometry and sparse pattern. Their state, :class:`Networks`, is
history: it changes only at converged steps (``committed``), like the friction anchors. Every evaluation takes the
committed state and the step's time increment ``dt`` (s); ``dt = 0`` is an instantaneous (elastic) response.
Internal units (E = 1, L0 = 1).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..laws import material
from ..laws import viscoelastic as ve
from .assembly import BulkForm

__all__ = ["Networks", "ViscousBranches"]


@dataclass(frozen=True)
class Networks:
    """The branches' committed state at every quadrature point: the remembered inverse right Cauchy-Green
    tensors A_i (n_cells, n_points, n_branches, 2, 2) and C^-1 of the committed deformation (n_cells, n_points, 2,
    2). None of either stands for the undeformed start (identity)."""

    networks: np.ndarray
    c_inv: np.ndarray


class ViscousBranches:
    """Generalized Maxwell branches with moduli ``g`` (relative to mu) and relaxation times ``tau`` (s) on the
    geometry of ``bulk``."""

    def __init__(self, bulk: BulkForm, mu: float, g, tau):
        self.bulk = bulk
        self.g = np.asarray(g, dtype=float)
        self.tau = np.asarray(tau, dtype=float)
        self.moduli = self.g * mu

    def start(self) -> Networks:
        """The undeformed state: every A_i = I, C^-1 = I."""
        shape = self.bulk.wdetJ.shape
        eye = np.broadcast_to(np.eye(2), shape + (2, 2))
        return Networks(np.ascontiguousarray(np.broadcast_to(eye[..., None, :, :], shape + (len(self.g), 2, 2))),
                        np.ascontiguousarray(eye))

    def _history(self, state: Networks | None, dt: float) -> tuple[np.ndarray, float]:
        """(H, kappa) of a step of dt seconds from ``state``: S = H - kappa C^-1 at its end."""
        state = self.start() if state is None else state
        a, b, c = ve.step_weights(dt, self.tau)
        return ve.history_stress(state.networks, state.c_inv, self.moduli, a, b), float(np.sum(self.moduli * (1.0 - c)))

    def residual(self, u: np.ndarray, state: Networks | None, dt: float) -> np.ndarray:
        """The branches' internal forces (E L0) at the end of a step of dt seconds from ``state``."""
        return self.bulk.internal_force(ve.viscous_piola(self.bulk.deformation_gradient(u), *self._history(state, dt)))

    def residual_and_tangent_data(self, u: np.ndarray, state: Networks | None, dt: float):
        """(internal forces, CSR data of their exact algorithmic tangent) in the bulk's pattern."""
        P, A = ve.viscous_piola_and_tangent(self.bulk.deformation_gradient(u), *self._history(state, dt))
        return self.bulk.internal_force(P), self.bulk.tangent_data(A)

    def committed(self, u: np.ndarray, state: Networks | None, dt: float) -> Networks:
        """The state after the converged step that ends at u."""
        state = self.start() if state is None else state
        c_inv = ve.inverse_right_cauchy_green(self.bulk.deformation_gradient(u))
        return Networks(ve.updated_networks(state.networks, state.c_inv, c_inv, *ve.step_weights(dt, self.tau)), c_inv)

    def energy(self, u: np.ndarray, state: Networks | None, dt: float) -> float:
        """The branches' stored energy per unit width (E L0^2) at the end of the step."""
        F = self.bulk.deformation_gradient(u)
        Y = ve.branch_energy(np.swapaxes(F, -1, -2) @ F, self.committed(u, state, dt).networks, self.moduli)
        return float(np.sum(Y * self.bulk.wdetJ))

    def cell_first_invariant(self, u: np.ndarray, state: Networks | None, dt: float) -> np.ndarray:
        """The branches' part of I1(sigma), cell averages (E): tr(F S F^T) / J; their sigma_zz is zero (A_zz =
        C^-1_zz = 1)."""
        F = self.bulk.deformation_gradient(u)
        P = ve.viscous_piola(F, *self._history(state, dt))
        return self.bulk.cell_average(np.einsum("...ij,...ij->...", P, F) / material.det2(F))
