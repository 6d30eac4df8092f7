"""Linear solvers behind one interface: pyamg-preconditioned Krylov and sparse LU.

``solver.solve(A, B)`` solves A X = B for one or several right-hand sides
(columns of B) with the same matrix, returning X and a :class:`SolveInfo`.
Three kinds: ``amg`` (pyamg smoothed aggregation preconditioning CG or
BiCGStab, :mod:`capslide.solvers.amg`), ``lu_krylov`` (a stored SuperLU
factorization of an earlier matrix preconditioning GMRES, refactorized when
iterations grow; or MKL PARDISO's, :mod:`capslide.solvers.pardiso`) and
``direct`` (a fresh SuperLU factorization per matrix, the reference and
fallback); :func:`choose_linear_solver` resolves ``auto``.
The true relative residual ||b - A x|| / ||b|| is computed after every solve;
a solve whose Krylov method reports convergence but whose true residual is
above 10 rtol counts as failed.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from .amg import AMGSolver
from .pardiso import PardisoFactors
from .solve_info import LinearSolveError, SolveInfo
from .solve_info import true_residual as _true_residual

__all__ = ["SolveInfo", "LinearSolveError", "AMGSolver", "DirectSolver", "LUKrylovSolver", "make_solver",
           "choose_linear_solver", "SOLVERS", "factorization_cost_in_solves"]

# A numeric factorization runs its counted flops about this many times faster than a triangular solve runs its two
# per entry of L + U (dense fronts against memory-bound sweeps); PARDISO, one thread, on the experiment scene's
# tangents and on 2D and 3D model grids (benchmarks/lu_refactor_balance.py).
FACTOR_FLOP_SPEEDUP = 6.0


def factorization_cost_in_solves(factors: PardisoFactors) -> float:
    """A numeric refactorization's cost in triangular solves with the same factors, estimated from PARDISO's counts
    of the factorization's flops and the fill: about 10 on 2D tangents, 50 to 130 on 3D ones of 20k to 66k DOF.
    The counts come from the analysis of the pattern, so the estimate is the same in every run."""
    return factors.factorization_flops / (FACTOR_FLOP_SPEEDUP * 2.0 * factors.fill)


def _factor(A: sp.csr_matrix, permc_spec: str, diagonal_pivoting: bool):
    """SuperLU factors of A; ``diagonal_pivoting`` keeps the pivots on the diagonal (SuperLU's symmetric mode), so
    the fill-reducing order holds. Partial pivoting leaves it on the mixed bulk at nu = 0.5, whose penalty entries
    dwarf the rest: with kappa = 1000 mu, 14 times the fill of L + U and 45 times the time on the paper's cap (Q2,
    mesh.size 32)."""
    if diagonal_pivoting:
        return spla.splu(A.tocsc(), permc_spec=permc_spec, diag_pivot_thresh=0.0, options={"SymmetricMode": True})
    return spla.splu(A.tocsc(), permc_spec=permc_spec)


def _bordered_inverse(lu, c: np.ndarray, d: np.ndarray, e: float, border_solve=None):
    """The exact inverse of [A0 c; d^T e] as a callable (n + 1 vectors), A0 the matrix of the LU factors ``lu``:
    one LU solve per application, and one for A0^{-1} c (``border_solve()``, default ``lu.solve(c)``) when
    first needed. With d = 0 (a fixed height) that is only for a vector whose last entry is not zero, which GMRES
    on a residual with G = 0 never makes; the result is the same bit for bit, as z - w 0 = z."""
    n = len(c)
    w = None

    def border() -> np.ndarray:
        nonlocal w
        if w is None:
            w = lu.solve(c) if border_solve is None else border_solve()
        return w

    schur = e - d @ border() if d.any() else e
    if schur == 0.0 or not np.isfinite(schur):
        raise np.linalg.LinAlgError("singular bordered preconditioner (Schur complement zero)")

    def apply(r: np.ndarray) -> np.ndarray:
        z = lu.solve(r[:n])
        dh = (r[n] - d @ z) / schur
        return np.concatenate([z if dh == 0.0 else z - border() * dh, [dh]])
    return apply


def _repeat_kept(apply):
    """``apply`` that answers a call with the same vector as the call before from memory. SciPy's GMRES applies the
    preconditioner twice to the right-hand side when it starts from zero (once for its norm, once for the first
    Krylov vector), and each application is an LU solve: one of the 4-10 per Newton iteration."""
    last = None

    def kept(r: np.ndarray) -> np.ndarray:
        nonlocal last
        if last is None or not np.array_equal(last[0], r):
            last = (np.array(r, copy=True), apply(r))
        return last[1].copy()
    return kept


@dataclass
class DirectSolver:
    """SciPy SuperLU (MMD on A^T + A ordering); a new factorization per matrix."""

    permc_spec: str = "MMD_AT_PLUS_A"
    diagonal_pivoting: bool = False
    _lu: object = field(default=None, init=False, repr=False)
    stats: dict = field(default_factory=lambda: {"setups": 0, "solves": 0, "iterations": 0}, init=False)

    def invalidate(self) -> None:
        self._lu = None

    def approximate_bordered(self, c: np.ndarray, d: np.ndarray, e: float, b: np.ndarray) -> np.ndarray | None:
        """[A c; d^T e]^{-1} b with the factors of the last matrix A solved with (None before any)."""
        return None if self._lu is None else _bordered_inverse(self._lu, c, d, e)(b)

    def solve(self, A: sp.csr_matrix, B: np.ndarray, rebuild: bool = True) -> tuple[np.ndarray, SolveInfo]:
        info = SolveInfo(rebuilt=True)
        t = time.perf_counter()
        lu = self._lu = _factor(A, self.permc_spec, self.diagonal_pivoting)
        info.setup_time = time.perf_counter() - t
        t = time.perf_counter()
        X = lu.solve(B)
        info.solve_time = time.perf_counter() - t
        info.true_residual = _true_residual(A, X.reshape(len(B), -1), B.reshape(len(B), -1))
        self.stats["setups"] += 1
        self.stats["solves"] += 1
        return X, info


@dataclass
class LUKrylovSolver:
    """GMRES preconditioned by the LU factors of an earlier matrix: SuperLU's, or with ``factorization='pardiso'``
    MKL PARDISO's, whose analysis is kept while the pattern stays (``diagonal_pivoting`` is SuperLU's only).

    The factorization is reused across Newton iterations and load steps and
    renewed when GMRES fails, and in :meth:`solve` when it needs more than
    ``max_iterations_before_refactor`` iterations per right-hand side. In
    :meth:`solve_bordered` the rule is a cost balance instead: refactorize once
    the Krylov iterations beyond those of the first solve after the last
    factorization add up to what a factorization costs: ``refactor_excess_iterations``
    (10-20 preconditioned iterations on the 2D cap meshes from 4k to 90k DOF,
    docs/performance.md), or with PARDISO's factors their estimated cost in
    solves if larger (:func:`factorization_cost_in_solves`: 3D factors fill in);
    or past ``hard_iteration_limit`` iterations. Counted in iterations and
    flops, not seconds: runs stay deterministic.
    A solve to a looser tolerance (an inexact Newton step) counts the
    iterations it would have taken to ``rtol`` at the rate it converged.
    """

    rtol: float = 1e-8
    max_iterations_before_refactor: int = 12
    refactor_excess_iterations: int = 15
    hard_iteration_limit: int = 40
    permc_spec: str = "MMD_AT_PLUS_A"
    diagonal_pivoting: bool = False
    factorization: str = "superlu"  # or 'pardiso': MKL PARDISO, its analysis kept while the pattern stays
    single: bool = False  # PARDISO's factors in single precision (GMRES runs in double)
    _lu: object = field(default=None, init=False, repr=False)
    _pardiso: PardisoFactors | None = field(default=None, init=False, repr=False)
    _generation: int = field(default=0, init=False, repr=False)  # counts factorizations
    _border: tuple | None = field(default=None, init=False, repr=False)  # (generation, c, A0^{-1} c)
    _base_iterations: float | None = field(default=None, init=False, repr=False)
    _excess_iterations: float = field(default=0, init=False, repr=False)
    _stale: bool = field(default=False, init=False, repr=False)  # factors kept, but renewed at the next solve
    stats: dict = field(default_factory=lambda: {"setups": 0, "solves": 0, "iterations": 0}, init=False)

    def invalidate(self) -> None:
        self._lu = None

    def approximate_bordered(self, c: np.ndarray, d: np.ndarray, e: float, b: np.ndarray) -> np.ndarray | None:
        """[A0 c; d^T e]^{-1} b with the stored factors A0 (the preconditioner of :meth:`solve_bordered`); None
        without factors."""
        return None if self._lu is None else self._bordered(c, d, e)(b)

    def _bordered(self, c: np.ndarray, d: np.ndarray, e: float):
        """The bordered inverse of the stored factors; A0^{-1} c is kept for the next call with the same factors
        and the same array c (a Newton iteration's GMRES run, then its next-increment estimate)."""
        lu, generation = self._lu, self._generation

        def border_solve() -> np.ndarray:
            kept = self._border
            if kept is None or kept[0] != generation or kept[1] is not c:
                kept = self._border = (generation, c, lu.solve(c))
            return kept[2]
        return _bordered_inverse(lu, c, d, e, border_solve)

    def factor(self, A) -> float:
        t = time.perf_counter()
        if self.factorization == "pardiso":
            if self._pardiso is not None and self._pardiso.same_pattern(A):
                self._pardiso.refactor(A)  # numeric only
            else:
                self._pardiso = PardisoFactors(A, single=self.single)
            self._lu = self._pardiso
        else:
            self._lu = _factor(A, self.permc_spec, self.diagonal_pivoting)
        self._generation += 1
        self._stale = False
        self.stats["setups"] += 1
        self._base_iterations, self._excess_iterations = None, 0
        return time.perf_counter() - t

    def _refactor_balance(self) -> float:
        """The excess Krylov iterations a factorization is worth (see the class docstring)."""
        if self.factorization != "pardiso" or self._pardiso is None:
            return self.refactor_excess_iterations
        return max(self.refactor_excess_iterations, factorization_cost_in_solves(self._pardiso))

    def solve(self, A: sp.csr_matrix, B: np.ndarray, rebuild: bool = False) -> tuple[np.ndarray, SolveInfo]:
        B2 = B.reshape(len(B), -1)
        info = SolveInfo()
        if rebuild or self._lu is None or self._stale:
            info.setup_time, info.rebuilt = self.factor(A), True
        for _attempt in range(2):
            lu = self._lu
            M = spla.LinearOperator(A.shape, matvec=_repeat_kept(lu.solve), dtype=float)
            t = time.perf_counter()
            X = np.empty_like(B2)
            iters, failed = 0, False
            for j in range(B2.shape[1]):
                count = [0]
                X[:, j], code = spla.gmres(A, B2[:, j], rtol=self.rtol, restart=40, maxiter=3, M=M,
                                           callback=lambda _: count.__setitem__(0, count[0] + 1), callback_type="pr_norm")
                iters += count[0]
                failed |= code != 0
            info.solve_time += time.perf_counter() - t
            info.iterations += iters
            info.true_residual = _true_residual(A, X, B2)
            if not failed and info.true_residual <= 10 * self.rtol:
                break
            if info.rebuilt:
                raise LinearSolveError(f"LU-preconditioned GMRES stopped at relative residual {info.true_residual:.2e}")
            info.setup_time += self.factor(A)
            info.rebuilt = True
        if info.iterations > self.max_iterations_before_refactor * B2.shape[1]:
            self._stale = True  # refactor at the next solve
        self.stats["solves"] += 1
        self.stats["iterations"] += info.iterations
        return X.reshape(B.shape), info

    def solve_bordered(self, A: sp.csr_matrix, c: np.ndarray, d: np.ndarray, e: float,
                       b: np.ndarray, rtol: float | None = None) -> tuple[np.ndarray, SolveInfo]:
        """Solve the bordered system [A c; d^T e] x = b (n + 1 unknowns) with one GMRES run, to the relative
        residual ``rtol`` when given (an inexact Newton method's forcing term; never tighter than ``self.rtol``).

        The preconditioner is the exact inverse of [A0 c; d^T e], A0 the stored
        factorization: one LU solve for A0^{-1} c per call, then one LU solve
        per GMRES iteration (a two-solve Schur approach needs two Krylov runs).
        """
        n = A.shape[0]
        rtol = self.rtol if rtol is None else max(rtol, self.rtol)
        info = SolveInfo()
        if self._lu is None or self._stale:
            info.setup_time, info.rebuilt = self.factor(A), True
        matvec = lambda x: np.concatenate([A @ x[:n] + c * x[n], [d @ x[:n] + e * x[n]]])  # noqa: E731
        op = spla.LinearOperator((n + 1, n + 1), matvec=matvec, dtype=float)
        nb = float(np.linalg.norm(b))
        for _attempt in range(2):
            M = spla.LinearOperator((n + 1, n + 1), matvec=_repeat_kept(self._bordered(c, d, e)), dtype=float)
            count = [0]
            t = time.perf_counter()
            x, code = spla.gmres(op, b, rtol=rtol, restart=40, maxiter=3, M=M,
                                 callback=lambda _: count.__setitem__(0, count[0] + 1), callback_type="pr_norm")
            info.solve_time += time.perf_counter() - t
            info.iterations += count[0]
            res = float(np.linalg.norm(b - op @ x))
            info.true_residual = res / nb if nb > 0 else res
            if code == 0 and info.true_residual <= min(10 * rtol, 0.9):
                break
            if info.rebuilt:
                raise LinearSolveError(f"LU-preconditioned GMRES (bordered) stopped at relative residual "
                                       f"{info.true_residual:.2e}")
            info.setup_time += self.factor(A)
            info.rebuilt = True
        its = info.iterations
        if rtol > self.rtol:  # a loose solve: its iterations at the rate it reached, as if run to self.rtol
            its = its * math.log(self.rtol) / math.log(min(max(info.true_residual, 1e-16), 0.9))
        if self._base_iterations is None:
            self._base_iterations = its
        else:  # iterations that a fresh factorization would have saved
            self._excess_iterations += max(its - self._base_iterations, 0)
        if self._excess_iterations > self._refactor_balance() or info.iterations > self.hard_iteration_limit:
            self._stale = True  # refactor at the next solve (the factors still serve approximate_bordered)
        self.stats["solves"] += 1
        self.stats["iterations"] += info.iterations
        return x, info


SOLVERS = ("amg", "lu_krylov", "direct")


def choose_linear_solver(kind: str, n_dofs: int, mixed: bool, amg_above_dofs: int, dim: int = 2) -> str:
    """The solver ``kind`` names; 'auto' is 'amg' in 3D (where factors fill in: 5.2 GB and 84 s for one SuperLU
    factorization at 86k DOF, ../shared/reference/sphere-facts.md), and in 2D 'lu_krylov' up to ``amg_above_dofs``
    DOF and for the mixed formulation (whose penalty bulk AMG was not made robust for), 'amg' above.

    On the graded cap meshes, 12k to 2.1M DOF, a SuperLU factorization plus
    solve takes 6 to 11 times less time than one AMG setup plus W-cycle solve,
    and the factors are reused over many Newton iterations; AMG's memory is
    0.77-0.81x of the factors' (docs/performance.md, issue 19). The default
    limit is the largest size measured; it is counted in DOF so that every
    machine chooses the same.
    """
    if kind != "auto":
        return kind
    if dim == 3:
        return "amg"
    return "amg" if n_dofs > amg_above_dofs and not mixed else "lu_krylov"


def make_solver(kind: str, rtol: float = 1e-8, near_null_space: np.ndarray | None = None,
                diagonal_pivoting: bool = False, exact_dofs: np.ndarray | None = None, factorization: str = "superlu",
                single: bool = False):
    """A solver by name: 'amg' (with ``near_null_space``, e.g. the rigid-body modes, and ``exact_dofs``, e.g. those
    of the poorly shaped cells), 'lu_krylov' (its factors from ``factorization``: 'superlu' or 'pardiso', the
    latter in single precision with ``single``) or 'direct' (``diagonal_pivoting``: see :func:`_factor`)."""
    if kind == "amg":  # BSR blocks of the node's DOFs: 3 in 3D (six rigid-body modes), 2 in 2D (three)
        block = 3 if near_null_space is not None and near_null_space.shape[1] == 6 else 2
        return AMGSolver(near_null_space=near_null_space, exact_dofs=exact_dofs, rtol=rtol, block_size=block)
    if kind == "lu_krylov":
        return LUKrylovSolver(rtol=rtol, diagonal_pivoting=diagonal_pivoting, factorization=factorization,
                              single=single)
    if kind == "direct":
        return DirectSolver(diagonal_pivoting=diagonal_pivoting)
    raise ValueError(f"unknown linear solver {kind!r} (allowed: {', '.join(SOLVERS)}; 'auto' goes through "
                     "choose_linear_solver)")
