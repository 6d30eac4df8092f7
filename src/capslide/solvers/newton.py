"""Newton's method with a backtracking line search; failure is returned, never hidden.

The problem is given as two callables: ``residual(x) -> r`` and
``linearize(x) -> (r, solve)`` where ``solve(r)`` returns the Newton
increment dx of the linearization at x (so bordered systems and Dirichlet
conditions stay with the caller). Convergence needs BOTH the residual
(``||r|| <= atol`` or ``||r|| <= rtol * r_ref``, in force units) AND the
increment (``||dx||_inf <= dx_tol``, in length units) to be small: the increment
just taken, or the next one as ``solve.next_increment(r)`` estimates it, when
the linearization offers that (then the iteration that would only confirm a
small increment is saved).

When ``solve.inexact`` is true, ``solve(r, eta)`` solves the linearization to
the relative residual eta only: an inexact Newton method whose forcing term eta
follows Eisenstat and Walker's choice 2 (SIAM J. Sci. Comput. 17, 1996, 16-32):
a loose linear solve while the Newton residual falls slowly (a contact's
stick-slip front advancing a few points per iteration), the solver's own
tolerance once it falls fast. The first iteration of every solve is exact
(eta None): it carries the step's load increment, and a loose first solve
made a stiff-penalty sliding case diverge (docs/performance.md).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

__all__ = ["NewtonOptions", "NewtonResult", "forcing_term", "newton"]


@dataclass(frozen=True)
class NewtonOptions:
    rtol: float = 1e-9
    atol: float = 1e-10
    dx_tol: float = 1e-8
    max_iterations: int = 30
    line_search_steps: int = 8  # halvings before the line search gives up; then the longest admissible step is
    longest_step_max_growth: float = math.inf  # taken (Newton may still converge) if its residual is at most this
    # times the current one, else the solve fails, so that the caller cuts the step back (a law with kinks whose
    # longest step jumps off a plateau into a stiff penalty, docs/three_d.md); 0: fail whenever the search does
    sufficient_decrease: float = 1e-4
    divergence_factor: float = 1e6  # ||r|| above this times the initial one: diverged
    estimate_fraction: float = 0.1  # a residual below tolerance also converges when the estimated next increment
    # (solve.next_increment) is below this fraction of dx_tol (0: never estimate)
    forcing: float = 0.9  # Eisenstat-Walker gamma: eta_k = gamma (|r_k| / |r_k-1|)^2 (0: exact linear solves)
    max_forcing: float = 0.5  # eta never above this


@dataclass
class NewtonResult:
    x: np.ndarray
    converged: bool
    iterations: int
    reason: str
    residual_norms: list[float] = field(default_factory=list)
    linear_iterations: int = 0
    runs: int = 1  # Newton runs whose iterations are summed here (a caller's re-solves)


def _norm(r: np.ndarray) -> float:
    return float(np.linalg.norm(r))


def _next_increment_small(solve, r: np.ndarray, options: NewtonOptions) -> bool:
    """Whether the increment from the residual r, as ``solve.next_increment(r)`` estimates it with the factors at
    hand, is below ``estimate_fraction`` dx_tol; then the iteration that would only confirm it is saved. This is
    Deuflhard's simplified Newton correction (Newton Methods for Nonlinear Problems, Springer 2004) with an earlier
    Jacobian's factors. A failed estimate counts as not small."""
    estimate = getattr(solve, "next_increment", None)
    if estimate is None or options.estimate_fraction <= 0.0:
        return False
    try:
        size = estimate(r)
    except (RuntimeError, ValueError, np.linalg.LinAlgError):
        return False
    return size is not None and math.isfinite(size) and size <= options.estimate_fraction * options.dx_tol


def forcing_term(options: NewtonOptions, r_norm: float, r_prev: float | None, eta_prev: float | None
                 ) -> float | None:
    """Eisenstat-Walker choice 2 (alpha = 2) with their safeguard: the relative tolerance of the linear solve from
    the residual norms of this iteration and the last, at most ``max_forcing``; None (the solver's own tolerance) at
    the first iteration, before any ratio is known."""
    if r_prev is None or r_prev <= 0.0:
        return None
    gamma = options.forcing
    eta = gamma * (r_norm / r_prev) ** 2
    if eta_prev is not None and gamma * eta_prev**2 > 0.1:  # do not tighten abruptly after a loose solve
        eta = max(eta, gamma * eta_prev**2)
    return min(eta, options.max_forcing)


def newton(
    residual: Callable[[np.ndarray], np.ndarray],
    linearize: Callable[[np.ndarray], tuple[np.ndarray, Callable[[np.ndarray], np.ndarray]]],
    x0: np.ndarray,
    options: NewtonOptions = NewtonOptions(),
    r_ref: float | None = None,
    admissible: Callable[[np.ndarray], bool] | None = None,
) -> NewtonResult:
    """Solve residual(x) = 0 from x0.

    ``r_ref`` scales the relative tolerance (default ||r(x0)||).
    ``admissible(x)`` (for example: no inverted element) must hold for
    every accepted iterate; the line search shortens the step until it
    does, and the solve fails when it cannot.
    """
    x = np.array(x0, dtype=float, copy=True)
    norms: list[float] = []
    lin_its = 0
    r, solve = linearize(x)
    r_norm = _norm(r)
    norms.append(r_norm)
    r_ref = r_norm if r_ref is None else r_ref
    tol = max(options.atol, options.rtol * r_ref)
    r0 = max(r_norm, options.atol)
    eta, r_prev = None, None
    for it in range(1, options.max_iterations + 1):
        if not math.isfinite(r_norm):
            return NewtonResult(x, False, it - 1, "residual is not finite", norms, lin_its)
        try:
            if options.forcing > 0.0 and getattr(solve, "inexact", False):
                eta = forcing_term(options, r_norm, r_prev, eta)
                dx = solve(r, eta)
            else:
                dx = solve(r)
        except (RuntimeError, ValueError, np.linalg.LinAlgError) as err:
            return NewtonResult(x, False, it - 1, f"linear solve failed: {err}", norms, lin_its)
        lin_its += getattr(solve, "iterations", 0)
        if not np.all(np.isfinite(dx)):
            return NewtonResult(x, False, it - 1, "Newton increment is not finite", norms, lin_its)
        # backtracking: shorten the step until admissible, then until ||r|| decreases
        alpha, accepted, x_ok = 1.0, False, None
        for _ in range(options.line_search_steps + 1):
            x_try = x - alpha * dx
            if admissible is not None and not admissible(x_try):
                alpha *= 0.5
                continue
            r_try = residual(x_try)
            n_try = _norm(r_try)
            if x_ok is None:
                x_ok, r_ok, n_ok, alpha_ok = x_try, r_try, n_try, alpha  # longest admissible step
            if math.isfinite(n_try) and n_try <= (1.0 - options.sufficient_decrease * alpha) * r_norm:
                accepted = True
                break
            alpha *= 0.5
        if not accepted:  # no decrease found: take the longest admissible step, unless it grows the residual too much
            if x_ok is None:
                return NewtonResult(x, False, it - 1, "no admissible step (inverted elements)", norms, lin_its)
            if n_ok > options.longest_step_max_growth * r_norm:
                return NewtonResult(x, False, it, f"line search found no decrease (longest step: residual {n_ok:.3e})",
                                    norms, lin_its)
            x_try, r_try, n_try, alpha = x_ok, r_ok, n_ok, alpha_ok
        x = x_try
        r_prev, r_norm = r_norm, n_try
        norms.append(r_norm)
        step = alpha * float(np.max(np.abs(dx))) if dx.size else 0.0
        if r_norm <= tol and (step <= options.dx_tol or _next_increment_small(solve, r_try, options)):
            return NewtonResult(x, True, it, "converged", norms, lin_its)  # converged: no tangent needed at x
        if not math.isfinite(r_norm) or r_norm > options.divergence_factor * r0:
            return NewtonResult(x, False, it, f"diverged: residual {r_norm:.3e}", norms, lin_its)
        r, solve = linearize(x)
    return NewtonResult(x, False, options.max_iterations,
                        f"no convergence in {options.max_iterations} iterations (residual {r_norm:.3e})", norms, lin_its)
