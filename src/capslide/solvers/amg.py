"""pyamg smoothed aggregation as the preconditioner of CG or BiCGStab, made robust on the graded cap meshes.

The solver keeps its hierarchy (built with the rigid-body modes as near-null
space) across calls and rebuilds it once the Krylov iterations spent beyond
the fewest a fresh hierarchy has needed add up to what a setup costs (the
setup's time in iterations, measured: :data:`SETUP_COST_ITERATIONS`), when a
solve fails even after one restart from its iterate, or when asked to.
Counted in iterations, not seconds: runs stay deterministic.

On the graded cap meshes pyamg's default smoothed aggregation needed 54 CG
iterations at 12k DOF and 474 at 577k (issue 3). The slow modes live in the
poorly shaped cells (:mod:`capslide.fem.quality`): the near-180-degree cells
at the logical corners of the mesh and the flat cells outside the contact
band. Three measures keep the iteration count nearly mesh-independent (Q2: 29
at 24k DOF, 32 at 1M; Q1: 13 at 12k, 18 at 1M; docs/performance.md, issue 19):
- the options :data:`SETTINGS`: evolution strength of connection, which
  follows the anisotropy, and energy-minimizing prolongation (Olson,
  Schroder and Tuminaro, Numer. Linear Algebra Appl. 17 (2010) 713 and
  SIAM J. Sci. Comput. 33 (2011) 966);
- an exact sparse solve on the DOFs of the poorly shaped cells before and
  after every cycle (a multiplicative Schwarz step with one subdomain);
- a W-cycle (:data:`CYCLE`): it visits the coarse levels twice, which Q1
  needs (V-cycles: 14 iterations at 23k DOF, 26 at 1M) and Q2 does not mind.
"""

from __future__ import annotations

import time
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass, field

import numpy as np
import pyamg
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from .solve_info import LinearSolveError, SolveInfo, true_residual

__all__ = ["AMGSolver", "CYCLE", "SETTINGS", "PYAMG_DEFAULTS", "SETUP_COST_ITERATIONS", "setup_cost_iterations"]

# measured on the graded cap meshes, Q1 and Q2, 12k to 2.1M DOF (benchmarks/amg_scaling.py)
SETTINGS = {"strength": ("evolution", {"k": 4}), "smooth": "energy", "max_coarse": 2000, "coarse_solver": "splu"}
# capslide's options before issue 19: pyamg's defaults with a coarsest level of at most 500 block rows
# (max_coarse counts nodes on the finest level, aggregates below)
PYAMG_DEFAULTS = {"max_coarse": 500}
# the multigrid cycle of the preconditioner: a W-cycle (symmetric, so CG applies), measured against the V-cycle
# capslide ran before (the last two columns of benchmarks/amg_scaling.py)
CYCLE = "W"
# 3D (BSR 3x3, six rigid-body modes) takes the same SETTINGS and W-cycle. pyamg's defaults with a direct coarse
# solve and V-cycles took more CG iterations on the sphere's H1 meshes (benchmarks/amg_sphere.py, nu = 0.4: 22
# against 16 at 82k DOF, 59 against 31 at 842k) and less time for one setup and solve (2.6 s against 5.4 s at 82k,
# 53 s against 101 s at 842k), but more in the load path, where the hierarchy is reused: the sphere scene's coarse
# case took 188 s with them against 165 s (14k DOF; docs/three_d.md)


# A setup's time over the time of one CG iteration per right-hand side: 42, 25, 69 and 86 at 17k, 82k, 369k and
# 842k DOF (the sphere's H1 meshes, capslide's options; benchmarks/amg_sphere.py, the table in docs/three_d.md),
# interpolated in log DOF and held beyond the ends (2D, where AMG runs above 2M DOF, takes the same)
SETUP_COST_ITERATIONS = ((17_352, 42.0), (81_873, 25.0), (369_390, 69.0), (841_860, 86.0))


def setup_cost_iterations(n_dofs: int) -> float:
    """What a hierarchy's setup costs in Krylov iterations per right-hand side at ``n_dofs`` DOF."""
    dofs, cost = zip(*SETUP_COST_ITERATIONS)
    return float(np.interp(np.log(n_dofs), np.log(dofs), cost))


@contextmanager
def _global_rng_seeded(seed: int = 0) -> Iterator[None]:
    """NumPy's global random state seeded inside, the caller's restored after. pyamg 5.4 starts the Arnoldi runs of
    its spectral-radius estimates (tolerance 1e-2; evolution strength, prolongation smoothing) from
    ``np.random.rand``, so without a seed two builds of the same matrix differ and so do the runs that use them."""
    state = np.random.get_state()
    np.random.seed(seed)
    try:
        yield
    finally:
        np.random.set_state(state)


@dataclass
class AMGSolver:
    """pyamg smoothed aggregation as preconditioner of CG (symmetric) or BiCGStab (unsymmetric; GMRES fallback).

    ``near_null_space`` (n, k): the rigid-body modes for elasticity (None:
    pyamg's constant default). ``exact_dofs``: DOFs solved exactly before and
    after each cycle (None or empty: the plain cycle). ``options``: the
    keywords of ``pyamg.smoothed_aggregation_solver``; ``cycle``: "V", "W"
    or "F". ``symmetric=None`` decides per matrix.
    """

    near_null_space: np.ndarray | None = None
    exact_dofs: np.ndarray | None = None
    options: dict = field(default_factory=lambda: dict(SETTINGS))
    cycle: str = CYCLE
    rtol: float = 1e-8
    maxiter: int = 500
    setup_cost: float | None = None  # iterations per right-hand side; None: setup_cost_iterations(DOF)
    symmetric: bool | None = None
    block_size: int = 2
    _ml: object = field(default=None, init=False, repr=False)
    _exact_lu: object = field(default=None, init=False, repr=False)
    _fewest_iterations: float | None = field(default=None, init=False, repr=False)  # a fresh hierarchy's, per RHS
    _excess_iterations: float = field(default=0.0, init=False, repr=False)  # beyond those, since the last setup
    stats: dict = field(default_factory=lambda: {"setups": 0, "solves": 0, "iterations": 0}, init=False)

    def invalidate(self) -> None:
        """Force a rebuild at the next solve (for example after a mesh change), and forget the iterations seen: the
        solver then decides as a new one would (a resumed run repeats the same arithmetic)."""
        self._ml, self._fewest_iterations = None, None

    def setup(self, A) -> float:
        t = time.perf_counter()
        Ab = A.tobsr(blocksize=(self.block_size, self.block_size)) if self.block_size > 1 else A
        kwargs = {"B": self.near_null_space} if self.near_null_space is not None else {}
        with _global_rng_seeded():  # the hierarchy a function of the matrix alone: runs repeat bit for bit
            self._ml = pyamg.smoothed_aggregation_solver(Ab, **self.options, **kwargs)
        d = self.exact_dofs
        self._exact_lu = spla.splu(A[d][:, d].tocsc()) if d is not None and len(d) else None
        self._excess_iterations = 0.0
        self.stats["setups"] += 1
        return time.perf_counter() - t

    def _preconditioner(self, A):
        """The multigrid cycle, or with ``exact_dofs`` the symmetric multiplicative combination: exact block, the
        cycle on the remaining residual, exact block again (symmetric when the cycle and A are, so CG applies)."""
        cycle = self._ml.aspreconditioner(cycle=self.cycle)
        if self._exact_lu is None:
            return cycle
        d, lu, rows = self.exact_dofs, self._exact_lu, A[self.exact_dofs]

        def apply(r):
            r = np.ravel(r)
            x = np.zeros(len(r))
            x[d] = lu.solve(r[d])
            x += cycle @ (r - A @ x)
            x[d] += lu.solve(r[d] - rows @ x)
            return x
        return spla.LinearOperator(A.shape, matvec=apply, dtype=float)

    def _is_symmetric(self, A) -> bool:
        if self.symmetric is not None:
            return self.symmetric
        d = A - A.T
        return d.nnz == 0 or abs(d).max() <= 1e-12 * abs(A).max()

    def _krylov(self, A, b, M, symmetric, x0):
        count = [0]

        def cb(_):
            count[0] += 1

        if symmetric:
            x, info = spla.cg(A, b, x0=x0, rtol=self.rtol, maxiter=self.maxiter, M=M, callback=cb)
            return x, info, count[0]
        # unsymmetric (sliding friction): BiCGStab; restarted GMRES(50) was seen to stagnate here
        x, info = spla.bicgstab(A, b, x0=x0, rtol=self.rtol, maxiter=self.maxiter, M=M, callback=cb)
        if info != 0:
            x, info = spla.gmres(A, b, x0=x, rtol=self.rtol, restart=200, maxiter=max(1, self.maxiter // 200), M=M,
                                 callback=cb, callback_type="pr_norm")
        return x, info, count[0]

    def solve(self, A: sp.csr_matrix, B: np.ndarray, rebuild: bool = False) -> tuple[np.ndarray, SolveInfo]:
        B2 = B.reshape(len(B), -1)
        info = SolveInfo()
        if rebuild or self._ml is None:
            info.setup_time, info.rebuilt = self.setup(A), True
        symmetric = self._is_symmetric(A)
        X = np.zeros_like(B2)
        # attempt 0 starts from zero; attempt 1 restarts the Krylov method from the
        # current iterate (BiCGStab's recursive residual can drift from the true
        # one); attempt 2 also rebuilds the hierarchy, unless it is fresh already
        since_setup = 0  # iterations on this solve's current hierarchy
        for attempt in range(3):
            if attempt == 2 and not info.rebuilt:
                info.setup_time += self.setup(A)
                info.rebuilt, since_setup = True, 0
            M = self._preconditioner(A)
            t = time.perf_counter()
            iters, failed = 0, False
            for j in range(B2.shape[1]):
                X[:, j], code, n = self._krylov(A, B2[:, j], M, symmetric, X[:, j].copy())
                iters += n
                failed |= code != 0
            info.solve_time += time.perf_counter() - t
            info.iterations += iters
            since_setup += iters
            info.true_residual = true_residual(A, X, B2)
            if not failed and info.true_residual <= 10 * self.rtol:
                break
        else:
            raise LinearSolveError(f"AMG-Krylov stopped at relative residual {info.true_residual:.2e} "
                                   f"after {info.iterations} iterations")
        self.stats["solves"] += 1
        self.stats["iterations"] += info.iterations
        self._account(since_setup / B2.shape[1], info.rebuilt, A.shape[0])
        return X.reshape(B.shape), info

    def _account(self, iterations: float, fresh: bool, n_dofs: int) -> None:
        """The rebuild rule, per right-hand side, from a solve's ``iterations`` on its last hierarchy (a solve that
        rebuilt after failed attempts counts only those after the rebuild): a fresh hierarchy's count lowers the
        fewest seen; the iterations beyond the fewest accumulate, and once they reach a setup's cost the hierarchy
        is rebuilt at the next solve. A hierarchy built on a hard matrix (a Newton iterate far from equilibrium)
        that serves the next matrices poorly is so replaced within a few solves."""
        if fresh and (self._fewest_iterations is None or iterations < self._fewest_iterations):
            self._fewest_iterations = max(iterations, 1.0)
        self._excess_iterations += max(iterations - self._fewest_iterations, 0.0)
        cost = self.setup_cost if self.setup_cost is not None else setup_cost_iterations(n_dofs)
        if self._excess_iterations >= cost:
            self._ml = None
