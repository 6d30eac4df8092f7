"""Passing a snap: pseudo-transient continuation to an equilibrium the step's Newton runs cannot reach.

Where the quasi-static path has no equilibrium near the last one (a contact edge that peels or re-adheres by a
jump, docs/experiment3d.md), Newton fails at any step length. ``solver.snap_through`` then tries the failed step
once more by pseudo-transient continuation (Kelley and Keyes, SIAM J. Numer. Anal. 35, 1998, 508-523): each
iteration solves (J + sigma D) dx = r, with D the tangent's diagonal at the start (a mass-like damping), so that
the first iterations crawl down a damped path and the last ones are Newton's. How sigma moves:

* **on the step's energy** where the step has one (:meth:`capslide.model.system.CapModel.step_energy`: a force
  or spring load, or a fixed height, where h is held at h*; an elastic bulk, and friction with its threshold held
  at the step's start): an iterate is
  taken only if it lowers that energy by Armijo's rule (x - alpha dx, alpha = 1, 1/4, 1/16, 1/64), else sigma grows
  fourfold; a full step lets sigma fall threefold. The constraint's row is shifted too (sigma |e|), so that the
  shifted system is the Hessian of a convex-ish model of the energy and dx a descent direction. This is
  Levenberg-Marquardt on the potential (Nocedal and Wright 2006, Numerical Optimization, section 10.3); it cannot
  cycle, and ends in the snapped state's basin.
* **by the residual** otherwise (switched evolution relaxation: sigma_k = sigma_{k-1} |r_k| / |r_{k-1}|); the
  constraint's row is not shifted. On the experiment it cycled at a fold (docs/experiment3d.md).

It hands over to Newton once the residual has fallen a millionfold (loadpath.continuation), and where Newton fails
from there it runs on from that state down to Newton's own tolerance: handed over at 1e-3 E L0^2, Newton had cycled
near the old state where no equilibrium is, while the damped path went on to the snapped one (A0 = 0.16 mm^2 of the
experiment, docs/experiment3d.md); on the energy, run to Newton's tolerance alone, the continuation crawled at a
residual of 4e-6 E L0^2, where the energy's changes are round-off (A0 = 0.19 mm^2). The step's regular Newton run
confirms the state, so a state it leads to is an equilibrium to the same tolerances as every other step; the
friction history is the step's, as in any step.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from ..model.system import BorderedSolve, CapModel, History
from ..solvers.newton import NewtonResult

__all__ = ["PseudoTransient", "pseudo_transient"]


@dataclass(frozen=True)
class PseudoTransient:
    """The continuation's settings: the first relative shift, its bounds, the iterations allowed and the residual
    (E L0) below which Newton takes over: ``handover``, or ``relative_handover`` times the first residual if that is
    larger."""

    first_shift: float = 1.0
    largest_shift: float = 1e6
    smallest_shift: float = 1e-12
    max_iterations: int = 400
    handover: float = 1e-8
    relative_handover: float = 0.0


def pseudo_transient(model: CapModel, constraint, history: History, x0: np.ndarray, dt: float = 0.0,
                     settings: PseudoTransient = PseudoTransient()) -> NewtonResult:
    """Pseudo-transient continuation of the step's equations from x0 until the residual is below ``handover``
    (converged: Newton is to take over from the result's x): on the step's energy where it has one, else by the
    residual. Not converged when the shift passes ``largest_shift`` (no admissible or descending iterate) or the
    iterations run out."""
    if model.step_energy(x0, constraint, history) is not None:
        return _on_the_energy(model, constraint, history, x0, settings)
    return _by_the_residual(model, constraint, history, x0, dt, settings)


def _shifted_solve(model: CapModel, bordered: BorderedSolve, damping, sigma: float, e_damping: float, r: np.ndarray):
    """dx of (J + sigma D) dx = r, the constraint's diagonal term shifted by sigma e_damping; and the Krylov
    iterations (an exception of the linear solver passes through)."""
    shifted = BorderedSolve(model.solver, (bordered.K + sigma * damping).tocsr(), bordered.c, bordered.d,
                            bordered.e + sigma * e_damping)
    dx = shifted(r)
    return dx, shifted.iterations


_LINEAR_FAILURES = (RuntimeError, ValueError, np.linalg.LinAlgError)
ARMIJO = 1e-4  # the fraction of the linear decrease an iterate must realize
STEP_FRACTIONS = (1.0, 0.25, 0.0625, 0.015625)


def _on_the_energy(model: CapModel, constraint, history: History, x0: np.ndarray,
                   settings: PseudoTransient) -> NewtonResult:
    """Levenberg-Marquardt on the step's energy (the module's docstring)."""
    energy = lambda x: model.step_energy(x, constraint, history)  # noqa: E731
    project = getattr(constraint, "project", _as_is)  # a fixed height: h held at h*, where the energy is taken
    x0 = project(x0)
    r, bordered = model.linearize(x0, constraint, history)
    damping = sp.diags(np.abs(bordered.K.diagonal()))
    e_damping = abs(float(bordered.e)) or 1.0
    x, E, sigma = x0.copy(), energy(x0), settings.first_shift
    r_norm = float(np.linalg.norm(r))
    krylov, norms = 0, [r_norm]
    handover = max(settings.handover, settings.relative_handover * r_norm)
    for it in range(1, settings.max_iterations + 1):
        try:
            dx, iterations = _shifted_solve(model, bordered, damping, sigma, e_damping, r)
        except _LINEAR_FAILURES as err:
            return NewtonResult(x, False, it, f"linear solve failed: {err}", norms, krylov)
        krylov += iterations
        slope = -float(model.energy_gradient(r) @ dx)  # dE/dalpha along -dx
        taken = _armijo(model, constraint, history, energy, x, E, dx, slope, r_norm, project) if slope < 0.0 else None
        if taken is None:
            sigma *= 4.0
            if sigma > settings.largest_shift:
                return NewtonResult(x, False, it, "no iterate lowers the energy", norms, krylov)
            continue
        alpha, x, E = taken
        r, bordered = model.linearize(x, constraint, history)
        r_norm = float(np.linalg.norm(r))
        norms.append(r_norm)
        if r_norm <= handover:
            return NewtonResult(x, True, it, "handed over to Newton", norms, krylov)
        if alpha == 1.0:
            sigma = max(sigma / 3.0, settings.smallest_shift)
    return NewtonResult(x, False, settings.max_iterations,
                        f"residual {r_norm:.3e} after {settings.max_iterations} iterations", norms, krylov)


def _as_is(x: np.ndarray) -> np.ndarray:
    return x


def _armijo(model: CapModel, constraint, history: History, energy, x: np.ndarray, E: float, dx: np.ndarray,
            slope: float, r_norm: float, project=_as_is) -> tuple[float, np.ndarray, float] | None:
    """The first of x - alpha dx (alpha in STEP_FRACTIONS, then ``project``ed) that is admissible and lowers the
    energy by ARMIJO times the linear decrease, or, where the energies differ by round-off only, lowers the residual;
    (alpha, x, E) or None."""
    for alpha in STEP_FRACTIONS:
        x_try = project(x - alpha * dx)
        if not (np.all(np.isfinite(x_try)) and model.admissible(x_try)):
            continue
        E_try = energy(x_try)
        if not np.isfinite(E_try):
            continue
        if E_try <= E + ARMIJO * alpha * slope:
            return alpha, x_try, E_try
        if abs(E_try - E) <= 64.0 * np.finfo(float).eps * max(abs(E), abs(E_try)):
            if float(np.linalg.norm(model.residual(x_try, constraint, history))) < r_norm:
                return alpha, x_try, E_try
    return None


def _by_the_residual(model: CapModel, constraint, history: History, x0: np.ndarray, dt: float,
                     settings: PseudoTransient) -> NewtonResult:
    """Switched evolution relaxation on the residual (the module's docstring)."""
    r, bordered = model.linearize(x0, constraint, history, dt)
    damping = sp.diags(np.abs(bordered.K.diagonal()))
    x, sigma, r_norm = x0.copy(), settings.first_shift, float(np.linalg.norm(r))
    krylov, norms = 0, [r_norm]
    handover = max(settings.handover, settings.relative_handover * r_norm)
    for it in range(1, settings.max_iterations + 1):
        try:
            dx, iterations = _shifted_solve(model, bordered, damping, sigma, 0.0, r)
        except _LINEAR_FAILURES as err:
            return NewtonResult(x, False, it, f"linear solve failed: {err}", norms, krylov)
        krylov += iterations
        x_try = x - dx
        if not (np.all(np.isfinite(dx)) and model.admissible(x_try)):
            sigma *= 10.0
            if sigma > settings.largest_shift:
                return NewtonResult(x, False, it, "no admissible iterate", norms, krylov)
            continue
        x = x_try
        r_prev, (r, bordered) = r_norm, model.linearize(x, constraint, history, dt)
        r_norm = float(np.linalg.norm(r))
        norms.append(r_norm)
        if not math.isfinite(r_norm):
            return NewtonResult(x, False, it, "residual is not finite", norms, krylov)
        if r_norm <= handover:
            return NewtonResult(x, True, it, "handed over to Newton", norms, krylov)
        sigma = min(max(sigma * r_norm / r_prev, settings.smallest_shift), settings.largest_shift)
    return NewtonResult(x, False, settings.max_iterations,
                        f"residual {r_norm:.3e} after {settings.max_iterations} iterations", norms, krylov)
