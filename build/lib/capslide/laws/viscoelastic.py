"""Finite-strain generalized Maxwell branches on the neo-Hooke bulk: Green and Tobolsky's transient network.

Each branch i is a network of chains that re-form stress-free at rate 1/tau_i (Green and Tobolsky 1946, J. Chem.
Phys. 14, 80; in the finite linear viscoelasticity of Liu et al. 2025, arXiv:2501.11947, it is the Seth-Hill
strain with m = -2). Its internal variable A_i is the inverse right Cauchy-Green tensor the network remembers:

    branch energy   Y_i = g_i mu / 2 (tr(C A_i) - 3 - ln det C - ln det A_i)     (plane strain: zz parts are 1)
    evolution       dA_i/dt = (C^-1 - A_i) / tau_i,   A_i = I before any load
    stress          S_i = 2 dY_i/dC = g_i mu (A_i - C^-1)
    dissipation     D_i = g_i mu / (2 tau_i) (tr Z + tr Z^-1 - 4) >= 0,   Z = A_i^1/2 C A_i^1/2

so the total is the neo-Hooke law of :mod:`capslide.laws.material` (mu, Lambda) plus sum_i S_i. ``g_i`` are the
branches' moduli relative to the long-time shear modulus mu, ``tau_i`` their relaxation times (s). Limits: tau -> 0
gives A_i = C^-1, S_i = 0, the neo-Hooke law with mu (long-time); tau -> infinity keeps A_i = I, S_i = g_i mu (I -
C^-1), the neo-Hooke law with mu (1 + sum g_i) and the same Lambda (instantaneous). At small strain the shear
relaxation modulus is mu (1 + sum g_i exp(-t / tau_i)), a Prony series.

Time integration: A_i is integrated exactly over a step with C^-1 linear in time (an exponential integrator,
second order): A_i^(n+1) = a A_i^n + b C^-1_n + c C^-1_(n+1), h = dt / tau_i, a = exp(-h), b = (1 - a) / h - a,
c = 1 - (1 - a) / h. The stress at the step's end is then S = H - kappa C^-1 with H = sum g_i mu (a A_i^n + b
C^-1_n) fixed in the step and kappa = sum g_i mu (1 - c); its exact algorithmic tangent is kappa times that of the
neo-Hooke shear term. F is (..., 2, 2) in-plane; stresses in the units of mu.
"""

from __future__ import annotations

import numpy as np

from .material import det2, inv_transpose2

__all__ = ["step_weights", "inverse_right_cauchy_green", "history_stress", "viscous_piola", "viscous_piola_and_tangent",
           "updated_networks", "branch_energy", "dissipation_rate", "step_dissipation", "prony_shear_modulus"]

_EYE = np.eye(2)


def step_weights(dt: float, tau: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(a, b, c) per branch of A^(n+1) = a A^n + b C^-1_n + c C^-1_(n+1) for a step of dt seconds (dt >= 0;
    tau in s, may be inf)."""
    h = dt / np.asarray(tau, dtype=float)
    a = np.exp(-h)
    with np.errstate(invalid="ignore", divide="ignore"):
        w = np.where(h > 0.0, -np.expm1(-h) / h, 1.0)  # (1 - exp(-h)) / h, 1 at h = 0, 0 at h = inf
    w = np.where(np.isinf(h), 0.0, w)
    return a, w - a, 1.0 - w


def inverse_right_cauchy_green(F: np.ndarray) -> np.ndarray:
    """C^-1 = F^-1 F^-T, (..., 2, 2)."""
    G = inv_transpose2(F, det2(F))
    return np.swapaxes(G, -1, -2) @ G


def history_stress(networks: np.ndarray, c_inv_start: np.ndarray, moduli: np.ndarray, a: np.ndarray,
                   b: np.ndarray) -> np.ndarray:
    """H = sum_i g_i mu (a_i A_i + b_i C^-1_n), (..., 2, 2): the part of the step's viscous stress fixed by the
    committed state (``networks`` A_i (..., n_branches, 2, 2), ``moduli`` g_i mu)."""
    weight = moduli * a
    return (np.einsum("...bij,b->...ij", networks, weight) + float(np.sum(moduli * b)) * c_inv_start)


def viscous_piola(F: np.ndarray, H: np.ndarray, kappa: float) -> np.ndarray:
    """The branches' first Piola stress P = F S, S = H - kappa C^-1."""
    return F @ (H - kappa * inverse_right_cauchy_green(F))


def viscous_piola_and_tangent(F: np.ndarray, H: np.ndarray, kappa: float) -> tuple[np.ndarray, np.ndarray]:
    """The branches' first Piola stress P = F S, S = H - kappa C^-1, and its tangent dP_iJ/dF_kL =
    delta_ik S_JL + kappa (G_iL G_kJ + delta_ik C^-1_JL), G = F^-T."""
    G = inv_transpose2(F, det2(F))
    c_inv = np.swapaxes(G, -1, -2) @ G
    S = H - kappa * c_inv
    P = F @ S
    A = np.einsum("ik,...JL->...iJkL", _EYE, S + kappa * c_inv)
    A += kappa * np.einsum("...iL,...kJ->...iJkL", G, G)
    return P, A


def updated_networks(networks: np.ndarray, c_inv_start: np.ndarray, c_inv_end: np.ndarray, a, b, c) -> np.ndarray:
    """A_i at the end of a step, (..., n_branches, 2, 2)."""
    return (a[:, None, None] * networks + b[:, None, None] * c_inv_start[..., None, :, :]
            + c[:, None, None] * c_inv_end[..., None, :, :])


def branch_energy(C: np.ndarray, networks: np.ndarray, moduli: np.ndarray) -> np.ndarray:
    """sum_i Y_i(C, A_i), (...): the energy the branches store (units of mu)."""
    tr = np.einsum("...ij,...bji->...b", C, networks)
    Y = 0.5 * moduli * (tr - 2.0 - np.log(det2(C))[..., None] - np.log(det2(networks)))
    return Y.sum(axis=-1)


def dissipation_rate(C: np.ndarray, networks: np.ndarray, moduli: np.ndarray, tau: np.ndarray) -> np.ndarray:
    """sum_i g_i mu / (2 tau_i) (tr(C A_i) + tr((C A_i)^-1) - 4) (units of mu per s), >= 0."""
    CA = C[..., None, :, :] @ networks
    tr = np.trace(CA, axis1=-2, axis2=-1)
    tr_inv = tr / det2(CA)  # 2x2: tr(M^-1) = tr M / det M
    return np.sum(moduli / (2.0 * tau) * (tr + tr_inv - 4.0), axis=-1)


def step_dissipation(F0: np.ndarray, F1: np.ndarray, networks: np.ndarray, moduli: np.ndarray, tau: np.ndarray,
                     dt: float, points: int = 8) -> tuple[np.ndarray, np.ndarray]:
    """Energy dissipated in one step along the integrator's own path (C^-1 linear in time, A_i exact on it), two
    ways: (work of the branch stress - change of the branch energy, time integral of the dissipation rate), both
    by Gauss-Legendre quadrature in time; they agree when the update is consistent with the energy."""
    ci0, ci1 = inverse_right_cauchy_green(F0), inverse_right_cauchy_green(F1)
    s, w = np.polynomial.legendre.leggauss(points)
    s, w = 0.5 * (s + 1.0), 0.5 * w
    work = np.zeros(F0.shape[:-2])
    rate = np.zeros(F0.shape[:-2])
    for sk, wk in zip(s, w):
        ci = (1.0 - sk) * ci0 + sk * ci1
        C = np.linalg.inv(ci)
        Ak = updated_networks(networks, ci0, ci, *step_weights(sk * dt, tau))
        S = np.einsum("b,...bij->...ij", moduli, Ak) - float(np.sum(moduli)) * ci
        dC = -C @ (ci1 - ci0) @ C  # dC/ds along the path
        work += wk * 0.5 * np.einsum("...ij,...ij->...", S, dC)
        rate += wk * dt * dissipation_rate(C, Ak, moduli, tau)
    A1 = updated_networks(networks, ci0, ci1, *step_weights(dt, tau))
    change = branch_energy(np.linalg.inv(ci1), A1, moduli) - branch_energy(np.linalg.inv(ci0), networks, moduli)
    return work - change, rate


def prony_shear_modulus(t: np.ndarray, mu: float, g: np.ndarray, tau: np.ndarray) -> np.ndarray:
    """The small-strain shear relaxation modulus mu (1 + sum g_i exp(-t / tau_i))."""
    t = np.asarray(t, dtype=float)
    return mu * (1.0 + np.sum(np.asarray(g) * np.exp(-t[..., None] / np.asarray(tau)), axis=-1))
