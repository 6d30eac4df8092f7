"""The mixed bulk: free of volumetric locking up to nu = 0.5, the incompressible limit included.

Three-field Hu-Washizu form (Simo, Taylor and Pister 1985; Simo and Taylor 1991). In 2D: Q2 displacements, and a
dilatation theta and a pressure p that are linear in each cell and discontinuous between cells (P1 in the
reference coordinates, basis 1, (X - X_c)/h_c, (Y - Y_c)/h_c); Q2/P1 satisfies the inf-sup condition (Boffi,
Brezzi and Fortin 2013, section 8.6.3). In 3D: trilinear H1 displacements with theta and p constant in each cell
(H1/P0, the mean dilatation method of Nagtegaal, Parks and Rice 1974 and Simo, Taylor and Pister 1985: free of
locking, not inf-sup stable, its pressure may checkerboard), or triquadratic H2 displacements with theta and p
linear in each cell (H2/P1, basis 1, (X - X_c)/h_c, (Y - Y_c)/h_c, (Z - Z_c)/h_c; Q2/P1's 3D pair). Both fields
are condensed cell by cell: theta is the L2 projection of J = det F onto the pressure space, p the projection of
U'(theta), so the global system stays displacement-only.

The energy is the neo-Hooke law of :mod:`capslide.laws.material` with J replaced by theta in its volumetric part:
W = mu/2 (I1 - 3 - 2 ln J) + U(theta), U(theta) = Lambda/4 (theta^2 - 1 - 2 ln theta). The first Piola stress is
P = mu (F - F^-T) + p J F^-T. At nu = 0.5 (Lambda infinite) theta = 1 is enforced exactly by an augmented
Lagrangian: U(theta) = lambda (theta - 1) + kappa/2 (theta - 1)^2 with a multiplier field lambda (P1 per cell,
given with each evaluation) that the caller updates, lambda <- p, until max |theta - 1| <= VOLUME_TOLERANCE
(Uzawa's iteration; Simo and Taylor 1991, section 4). Internal units (E = 1, L0 = 1).
"""

from __future__ import annotations

import math

import numpy as np

from ..laws import material
from .assembly import BulkForm
from .element import CELLS
from .mesh import Mesh

__all__ = ["MixedBulkForm", "PENALTY_OVER_MU", "VOLUME_TOLERANCE"]

PENALTY_OVER_MU = 1e2  # kappa / mu of the augmented Lagrangian at nu = 0.5
VOLUME_TOLERANCE = 1e-10  # max |theta - 1| at which Uzawa's iteration stops (nu = 0.5)


PRESSURE_SPACE = {"Q2": "P1", "H1": "P0", "H2": "P1"}  # the mixed pairs: Q2/P1 (2D), H1/P0 and H2/P1 (3D)


class MixedBulkForm(BulkForm):
    """Internal forces and tangent of the Q2/P1 (2D), H1/P0 or H2/P1 (3D) neo-Hooke bulk; ``lam`` may be ``inf``
    (incompressible).

    Every evaluation takes ``multiplier``, the augmented Lagrangian's pressure multiplier (n_cells, m) as the
    pressure space's coefficients (E; m = 1 + dim for P1, 1 for P0), used only when ``lam`` is infinite (None = zero).
    """

    def __init__(self, mesh: Mesh, lam: float, mu: float, quadrature: int | None = None):
        if mesh.element not in PRESSURE_SPACE:
            raise ValueError(f"the mixed formulation needs Q2, H1 or H2 elements, not {mesh.element}")
        super().__init__(mesh, 0.0, mu, quadrature)  # the deviatoric part: neo-Hooke with Lambda = 0
        self.volumetric = float(lam)
        self.incompressible = not math.isfinite(self.volumetric)
        self.penalty = PENALTY_OVER_MU * mu
        ref = CELLS[mesh.element]
        N, _ = ref.shape(ref.gauss(quadrature)[0])
        Xq = np.einsum("qa,eai->eqi", N, mesh.nodes[mesh.cells])  # quadrature points, reference configuration
        if PRESSURE_SPACE[mesh.element] == "P0":
            self.Np = np.ones(Xq.shape[:2] + (1,))  # (e, q, 1)
        else:
            area = self.wdetJ.sum(axis=1)
            centre = np.einsum("eq,eqi->ei", self.wdetJ, Xq) / area[:, None]
            size = np.sqrt(area) if mesh.dim == 2 else np.cbrt(area)  # the cell's size (its volume in 3D)
            scaled = (Xq - centre[:, None, :]) / size[:, None, None]
            self.Np = np.concatenate([np.ones(Xq.shape[:2] + (1,)), scaled], axis=-1)  # (e, q, 1 + dim)
        M = np.einsum("eqm,eq,eqn->emn", self.Np, self.wdetJ, self.Np)
        self.M_inv = np.linalg.inv(M)
        # the projection onto P1 at the quadrature points: f -> Np M^-1 int Np f, (e, q, q)
        self._projection = np.einsum("eqm,emn,ern,er->eqr", self.Np, self.M_inv, self.Np, self.wdetJ)

    # -- the condensed fields --------------------------------------------------
    def dilatation(self, u: np.ndarray) -> np.ndarray:
        """theta, the projection of J onto the pressure space, at the quadrature points (e, q)."""
        return self.project(material.det(self.deformation_gradient(u)))

    def project(self, f: np.ndarray) -> np.ndarray:
        """The L2 projection onto the pressure space per cell of values at the quadrature points (e, q)."""
        return np.einsum("eqr,er->eq", self._projection, f)

    def _multiplier_at_points(self, multiplier: np.ndarray | None) -> np.ndarray:
        if multiplier is None:
            return np.zeros(self.wdetJ.shape)
        return np.einsum("eqm,em->eq", self.Np, multiplier)

    def _volumetric(self, theta: np.ndarray, multiplier) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """U(theta), U'(theta), U''(theta) at the quadrature points."""
        if self.incompressible:
            d, k = theta - 1.0, self.penalty
            lam_q = self._multiplier_at_points(multiplier)
            return lam_q * d + 0.5 * k * d**2, lam_q + k * d, np.full_like(theta, k)
        L = self.volumetric
        with np.errstate(invalid="ignore", divide="ignore"):
            U = 0.25 * L * (theta**2 - 1.0 - 2.0 * np.log(theta))
        return U, 0.5 * L * (theta - 1.0 / theta), 0.5 * L * (1.0 + 1.0 / theta**2)

    def pressure(self, u: np.ndarray, multiplier: np.ndarray | None = None) -> np.ndarray:
        """p, the P1 projection of U'(theta), at the quadrature points (E; positive in tension)."""
        _, dU, _ = self._volumetric(self.dilatation(u), multiplier)
        return self.project(dU)

    def pressure_coefficients(self, u: np.ndarray, multiplier: np.ndarray | None = None) -> np.ndarray:
        """p as the pressure space's coefficients per cell (n_cells, m): Uzawa's update of the multiplier."""
        _, dU, _ = self._volumetric(self.dilatation(u), multiplier)
        return np.einsum("emn,eqn,eq,eq->em", self.M_inv, self.Np, self.wdetJ, dU)

    def volume_error(self, u: np.ndarray) -> float:
        """max |theta - 1| over the quadrature points: how far the incompressibility constraint is from holding."""
        return float(np.max(np.abs(self.dilatation(u) - 1.0)))

    def updated_multiplier(self, u: np.ndarray, multiplier: np.ndarray | None) -> np.ndarray | None:
        """At nu = 0.5, Uzawa's update lambda <- p while max |theta - 1| > VOLUME_TOLERANCE; None once the constraint
        holds (or with a finite Lambda, which has no constraint)."""
        if not self.incompressible or self.volume_error(u) <= VOLUME_TOLERANCE:
            return None
        return self.pressure_coefficients(u, multiplier)

    # -- forces and tangent ----------------------------------------------------
    def _stress(self, u, multiplier):
        F = self.deformation_gradient(u)
        J = material.det(F)
        cof = J[..., None, None] * material.inv_transpose(F, J)  # dJ/dF = J F^-T
        theta = self.project(J)
        _, dU, d2U = self._volumetric(theta, multiplier)
        return F, J, cof, self.project(dU), d2U

    def residual(self, u: np.ndarray, multiplier: np.ndarray | None = None) -> np.ndarray:
        F, _, cof, p, _ = self._stress(u, multiplier)
        return self.internal_force(material.first_piola(F, 0.0, self.mu) + p[..., None, None] * cof)

    def residual_and_tangent_data(self, u: np.ndarray, multiplier: np.ndarray | None = None):
        """(f_int, CSR data of the consistent tangent): the material part plus p d(J F^-T)/dF, plus the
        condensed rank-m block B^T M^-1 H M^-1 B of each cell (B_m = int Np_m dJ/du, H = int Np U'' Np^T)."""
        F, J, cof, p, d2U = self._stress(u, multiplier)
        P, A = material.first_piola_and_tangent(F, 0.0, self.mu)
        P = P + p[..., None, None] * cof
        G = cof / J[..., None, None]
        # d(J G_iJ)/dF_kL = J (G_iJ G_kL - G_iL G_kJ)
        GG = np.einsum("eqiJ,eqkL->eqiJkL", cof, G)
        A = A + p[..., None, None, None, None] * (GG - GG.transpose(0, 1, 2, 5, 4, 3))
        e, q, a, d = self.dN.shape
        B = np.einsum("eqm,eq,eqiJ,eqaJ->emai", self.Np, self.wdetJ, cof, self.dN).reshape(e, self.Np.shape[-1], d * a)
        H = np.einsum("eqm,eq,eqn->emn", self.Np, self.wdetJ * d2U, self.Np)
        D = self.M_inv @ H @ self.M_inv
        K = self.element_tangents(A) + np.swapaxes(B, 1, 2) @ D @ B
        return self.internal_force(P), self.pattern.values(K)

    # -- measures ----------------------------------------------------------------
    def strain_energy(self, u: np.ndarray, multiplier: np.ndarray | None = None) -> float:
        """Total strain energy per unit width (E L0^2); at nu = 0.5 with the augmented Lagrangian's terms (zero
        once theta = 1)."""
        F = self.deformation_gradient(u)
        U, _, _ = self._volumetric(self.project(material.det(F)), multiplier)
        return float(np.sum((material.strain_energy_density(F, 0.0, self.mu) + U) * self.wdetJ))

    def min_jacobian(self, u: np.ndarray) -> float:
        """Smallest det F and theta over the quadrature points (<= 0: inverted)."""
        return min(super().min_jacobian(u), float(self.dilatation(u).min()))

    def cell_first_invariant(self, u: np.ndarray, multiplier: np.ndarray | None = None) -> np.ndarray:
        """I1(sigma) averaged over each cell (E): the deviatoric part's (Lambda = 0) plus 3 p (sigma_zz = p)."""
        I1 = material.first_invariant(self.deformation_gradient(u), 0.0, self.mu) + 3.0 * self.pressure(u, multiplier)
        return self.cell_average(I1)
