"""Plane-strain compressible neo-Hooke material (docs/theory.md section 4).

W = Lambda/4 (J^2 - 1 - 2 ln J) + mu/2 (I1 - 3 - 2 ln J), I1 = tr C with
C_zz = 1 (plane strain). All functions are vectorized over leading axes
(typically (element, quadrature point)); F has shape (..., 2, 2). Stresses
are in the units of Lambda and mu (E internally).
"""

from __future__ import annotations

import numpy as np

_IDENTITY4 = np.einsum("ik,jl->ijkl", np.eye(2), np.eye(2))  # delta_ik delta_JL

__all__ = ["det2", "inv_transpose2", "strain_energy_density",
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


def strain_energy_density(F: np.ndarray, lam: float, mu: float) -> np.ndarray:
    """W(F) = Lambda/4 (J^2 - 1 - 2 ln J) + mu/2 (I1 - 3 - 2 ln J), I1 = tr F^T F + 1 (energy per reference area)."""
    J = det2(F)
    I1 = np.einsum("...ij,...ij->...", F, F) + 1.0
    return 0.25 * lam * (J**2 - 1 - 2 * np.log(J)) + 0.5 * mu * (I1 - 3 - 2 * np.log(J))


def first_piola(F: np.ndarray, lam: float, mu: float) -> np.ndarray:
    """In-plane first Piola-Kirchhoff stress P = Lambda/2 (J^2 - 1) F^{-T} + mu (F - F^{-T})."""
    J = det2(F)
    G = inv_transpose2(F, J)
    a = 0.5 * lam * (J**2 - 1.0)
    return (a - mu)[..., None, None] * G + mu * F


def first_piola_and_tangent(F: np.ndarray, lam: float, mu: float) -> tuple[np.ndarray, np.ndarray]:
    """P (..., 2, 2) and the material tangent A_iJkL = dP_iJ / dF_kL (..., 2, 2, 2, 2).

    A = Lambda J^2 G_iJ G_kL - (a - mu) G_iL G_kJ + mu delta_ik delta_JL,
    with G = F^{-T} and a = Lambda/2 (J^2 - 1).
    """
    J = det2(F)
    G = inv_transpose2(F, J)
    a = 0.5 * lam * (J**2 - 1.0)
    P = (a - mu)[..., None, None] * G + mu * F
    GG = G[..., :, :, None, None] * G[..., None, None, :, :]  # G_iJ G_kL
    A = (lam * J**2)[..., None, None, None, None] * GG
    A -= (a - mu)[..., None, None, None, None] * GG.transpose(*range(G.ndim - 2), -4, -1, -2, -3)  # G_iL G_kJ
    A += mu * _IDENTITY4
    return P, A


def cauchy(F: np.ndarray, lam: float, mu: float) -> np.ndarray:
    """In-plane Cauchy stress sigma = Lambda/(2J) (J^2 - 1) I + mu/J (F F^T - I)."""
    J = det2(F)
    b = np.einsum("...ik,...jk->...ij", F, F)
    eye = np.eye(2)
    return (0.5 * lam * (J**2 - 1.0) / J)[..., None, None] * eye + (mu / J)[..., None, None] * (b - eye)


def cauchy_zz(F: np.ndarray, lam: float, mu: float) -> np.ndarray:
    """Out-of-plane Cauchy stress sigma_zz = Lambda/(2J) (J^2 - 1) (plane strain, F_zz = 1)."""
    J = det2(F)
    return 0.5 * lam * (J**2 - 1.0) / J


def first_invariant(F: np.ndarray, lam: float, mu: float) -> np.ndarray:
    """I1(sigma) = sigma_xx + sigma_yy + sigma_zz (plane strain keeps sigma_zz)."""
    s = cauchy(F, lam, mu)
    return s[..., 0, 0] + s[..., 1, 1] + cauchy_zz(F, lam, mu)
