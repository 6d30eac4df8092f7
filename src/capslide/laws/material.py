"""Compressible neo-Hooke material, plane strain or 3D (docs/theory.md section 4).

W = Lambda/4 (J^2 - 1 - 2 ln J) + mu/2 (I1 - 3 - 2 ln J), I1 = tr C, with C_zz = 1 in plane strain. All functions
are vectorized over leading axes (typically (element, quadrature point)); F has shape (..., d, d) with d = 2 (plane
strain: the in-plane parts) or d = 3, the dimension read from F. Stresses are in the units of Lambda and mu (E
internally).
"""

from __future__ import annotations

import numpy as np

_IDENTITY4 = {d: np.einsum("ik,jl->ijkl", np.eye(d), np.eye(d)) for d in (2, 3)}  # delta_ik delta_JL

__all__ = ["det2", "inv_transpose2", "det", "inv_transpose", "strain_energy_density",
           "first_piola", "first_piola_and_tangent", "cauchy", "cauchy_zz", "first_invariant"]


def det2(F: np.ndarray) -> np.ndarray:
    """Determinant of (..., 2, 2) arrays."""
    return F[..., 0, 0] * F[..., 1, 1] - F[..., 0, 1] * F[..., 1, 0]


def inv_transpose2(F: np.ndarray, J: np.ndarray | None = None) -> np.ndarray:
    """F^{-T} of (..., 2, 2) arrays."""
    J = det2(F) if J is None else J
    G = np.empty_like(F)
    G[..., 0, 0] = F[..., 1, 1]
    G[..., 0, 1] = -F[..., 1, 0]
    G[..., 1, 0] = -F[..., 0, 1]
    G[..., 1, 1] = F[..., 0, 0]
    return G / J[..., None, None]


def det(F: np.ndarray) -> np.ndarray:
    """Determinant of (..., d, d) arrays, d = 2 or 3 (cofactor expansion)."""
    if F.shape[-1] == 2:
        return det2(F)
    return (F[..., 0, 0] * (F[..., 1, 1] * F[..., 2, 2] - F[..., 1, 2] * F[..., 2, 1])
            - F[..., 0, 1] * (F[..., 1, 0] * F[..., 2, 2] - F[..., 1, 2] * F[..., 2, 0])
            + F[..., 0, 2] * (F[..., 1, 0] * F[..., 2, 1] - F[..., 1, 1] * F[..., 2, 0]))


def inv_transpose(F: np.ndarray, J: np.ndarray | None = None) -> np.ndarray:
    """F^{-T} of (..., d, d) arrays, d = 2 or 3: the cofactor matrix over J."""
    if F.shape[-1] == 2:
        return inv_transpose2(F, J)
    J = det(F) if J is None else J
    cof = np.cross(F[..., [1, 2, 0], :], F[..., [2, 0, 1], :])  # row i: F_(i+1) x F_(i+2), the cofactors of row i
    return cof / J[..., None, None]


def strain_energy_density(F: np.ndarray, lam: float, mu: float) -> np.ndarray:
    """W(F) = Lambda/4 (J^2 - 1 - 2 ln J) + mu/2 (I1 - 3 - 2 ln J), I1 = tr F^T F (+ 1 in plane strain: C_zz)
    (energy per reference area in 2D, per reference volume in 3D)."""
    J = det(F)
    I1 = np.einsum("...ij,...ij->...", F, F) + (1.0 if F.shape[-1] == 2 else 0.0)
    return 0.25 * lam * (J**2 - 1 - 2 * np.log(J)) + 0.5 * mu * (I1 - 3 - 2 * np.log(J))


def first_piola(F: np.ndarray, lam: float, mu: float) -> np.ndarray:
    """First Piola-Kirchhoff stress P = Lambda/2 (J^2 - 1) F^{-T} + mu (F - F^{-T}) (in-plane in 2D)."""
    J = det(F)
    G = inv_transpose(F, J)
    a = 0.5 * lam * (J**2 - 1.0)
    return (a - mu)[..., None, None] * G + mu * F


def first_piola_and_tangent(F: np.ndarray, lam: float, mu: float) -> tuple[np.ndarray, np.ndarray]:
    """P (..., d, d) and the material tangent A_iJkL = dP_iJ / dF_kL (..., d, d, d, d).

    A = Lambda J^2 G_iJ G_kL - (a - mu) G_iL G_kJ + mu delta_ik delta_JL,
    with G = F^{-T} and a = Lambda/2 (J^2 - 1).
    """
    J = det(F)
    G = inv_transpose(F, J)
    a = 0.5 * lam * (J**2 - 1.0)
    P = (a - mu)[..., None, None] * G + mu * F
    GG = G[..., :, :, None, None] * G[..., None, None, :, :]  # G_iJ G_kL
    A = (lam * J**2)[..., None, None, None, None] * GG
    A -= (a - mu)[..., None, None, None, None] * GG.transpose(*range(G.ndim - 2), -4, -1, -2, -3)  # G_iL G_kJ
    A += mu * _IDENTITY4[F.shape[-1]]
    return P, A


def cauchy(F: np.ndarray, lam: float, mu: float) -> np.ndarray:
    """Cauchy stress sigma = Lambda/(2J) (J^2 - 1) I + mu/J (F F^T - I) (in-plane in 2D)."""
    J = det(F)
    b = np.einsum("...ik,...jk->...ij", F, F)
    eye = np.eye(F.shape[-1])
    return (0.5 * lam * (J**2 - 1.0) / J)[..., None, None] * eye + (mu / J)[..., None, None] * (b - eye)


def cauchy_zz(F: np.ndarray, lam: float, mu: float) -> np.ndarray:
    """Out-of-plane Cauchy stress sigma_zz = Lambda/(2J) (J^2 - 1) (plane strain, F_zz = 1)."""
    J = det2(F)
    return 0.5 * lam * (J**2 - 1.0) / J


def first_invariant(F: np.ndarray, lam: float, mu: float) -> np.ndarray:
    """I1(sigma) = sigma_xx + sigma_yy + sigma_zz (plane strain keeps sigma_zz)."""
    s = cauchy(F, lam, mu)
    if F.shape[-1] == 3:
        return s[..., 0, 0] + s[..., 1, 1] + s[..., 2, 2]
    return s[..., 0, 0] + s[..., 1, 1] + cauchy_zz(F, lam, mu)
