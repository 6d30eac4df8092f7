"""What every linear solver returns besides the solution, its error type and the true residual it checks."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["LinearSolveError", "SolveInfo", "true_residual"]


class LinearSolveError(RuntimeError):
    """A linear solve did not reach its tolerance (message says by how much)."""


@dataclass
class SolveInfo:
    iterations: int = 0  # Krylov iterations over all right-hand sides (0 for direct)
    true_residual: float = 0.0  # max over right-hand sides of ||b - A x|| / ||b||
    rebuilt: bool = False  # hierarchy / factorization built in this call
    setup_time: float = 0.0
    solve_time: float = 0.0


def true_residual(A, X, B) -> float:
    """max over the columns of ||b - A x|| / ||b|| (the plain residual norm for b = 0)."""
    R = B - A @ X
    nb = np.linalg.norm(B, axis=0)
    nr = np.linalg.norm(R, axis=0)
    return float(np.max(np.where(nb > 0, nr / np.where(nb > 0, nb, 1.0), nr)))
