"""The interfaces of the linear solvers, as protocols: what every solver does, and what some can do besides.

- :class:`LinearSolver`: every solver (``amg``, ``lu_krylov``, ``direct``): ``solve(A, B)`` for one or several
  right-hand sides, and ``invalidate()``, which drops whatever it keeps from earlier matrices.
- :class:`KeepsFactors`: a solver that keeps the factors of an earlier matrix (``lu_krylov``, ``direct``) can
  estimate the next Newton increment with them (``approximate_bordered``).
- :class:`SolvesBordered`: a solver that runs one Krylov solve on the whole bordered system [A c; d^T e]
  (``lu_krylov``), to a relative residual the caller sets (inexact Newton).

The model asks with ``isinstance`` (the protocols are runtime-checkable), not by attribute names.
"""

from __future__ import annotations

from typing import Protocol, runtime_checkable

import numpy as np
import scipy.sparse as sp

from .solve_info import SolveInfo

__all__ = ["LinearSolver", "KeepsFactors", "SolvesBordered"]


@runtime_checkable
class LinearSolver(Protocol):
    def solve(self, A: sp.csr_matrix, B: np.ndarray, rebuild: bool = False) -> tuple[np.ndarray, SolveInfo]:
        """X with A X = B (B: one or several columns) and how the solve went."""

    def invalidate(self) -> None:
        """Forget the factors or hierarchy of earlier matrices: the next solve starts afresh."""


@runtime_checkable
class KeepsFactors(Protocol):
    def approximate_bordered(self, c: np.ndarray, d: np.ndarray, e: float, b: np.ndarray) -> np.ndarray | None:
        """[A0 c; d^T e]^{-1} b with the stored factors of an earlier A0; None when none are stored."""


@runtime_checkable
class SolvesBordered(Protocol):
    def solve_bordered(self, A: sp.csr_matrix, c: np.ndarray, d: np.ndarray, e: float, b: np.ndarray,
                       rtol: float | None = None) -> tuple[np.ndarray, SolveInfo]:
        """[A c; d^T e]^{-1} b by one Krylov solve, to the relative residual ``rtol`` (default: the solver's)."""
