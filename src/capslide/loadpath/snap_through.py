"""Passing a snap: pseudo-transient continuation to an equilibrium the step's Newton runs cannot reach.

Where the quasi-static path has no equilibrium near the last one (a contact edge that peels or re-adheres by a
jump, docs/experiment3d.md), Newton fails at any step length. ``solver.snap_through`` then tries the failed step
once more by pseudo-transient continuation (Kelley and Keyes, SIAM J. Numer. Anal. 35, 1998, 508-523): each
iteration solves (J + sigma D) dx = r, with D the tangent's diagonal at the start (a mass-like damping) and the
relative shift sigma following the residual (switched evolution relaxation: sigma_k = sigma_{k-1} |r_k| / |r_{k-1}|),
so that the first iterations crawl down a damped path and the last ones are Newton's. The constraint's row is not
shifted. It runs down to Newton's residual tolerance: handed over earlier (1e-3 E L0^2), Newton cycled at the
residual's floor near the old state where no equilibrium is, while the damped path went on to the snapped one
(A0 = 0.16 mm^2 of the experiment, docs/experiment3d.md). Then the step's regular Newton run confirms it
(loadpath.continuation), so a state it leads to is an equilibrium to the same tolerances as every other step; the
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
    (E L0) below which Newton takes over."""

    first_shift: float = 1.0
    largest_shift: float = 1e6
    smallest_shift: float = 1e-12
    max_iterations: int = 400
    handover: float = 1e-8


def pseudo_transient(model: CapModel, constraint, history: History, x0: np.ndarray, dt: float = 0.0,
                     settings: PseudoTransient = PseudoTransient()) -> NewtonResult:
    """Pseudo-transient continuation of the step's equations from x0 until the residual is below ``handover``
    (converged: Newton is to take over from the result's x). Not converged when the shift reaches
    ``largest_shift`` (no admissible iterate) or the iterations run out."""
    r, bordered = model.linearize(x0, constraint, history, dt)
    damping = sp.diags(np.abs(bordered.K.diagonal()))
    x, sigma, r_norm = x0.copy(), settings.first_shift, float(np.linalg.norm(r))
    krylov, norms = 0, [r_norm]
    for it in range(1, settings.max_iterations + 1):
        shifted = BorderedSolve(model.solver, (bordered.K + sigma * damping).tocsr(), bordered.c, bordered.d, bordered.e)
        try:
            dx = shifted(r)
        except (RuntimeError, ValueError, np.linalg.LinAlgError) as err:
            return NewtonResult(x, False, it, f"linear solve failed: {err}", norms, krylov)
        krylov += shifted.iterations
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
        if r_norm <= settings.handover:
            return NewtonResult(x, True, it, "handed over to Newton", norms, krylov)
        sigma = min(max(sigma * r_norm / r_prev, settings.smallest_shift), settings.largest_shift)
    return NewtonResult(x, False, settings.max_iterations,
                        f"residual {r_norm:.3e} after {settings.max_iterations} iterations", norms, krylov)
