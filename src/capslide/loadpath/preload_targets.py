"""Where the preload's path lands (docs/theory.md section 5): the targets of the preload leg, from the loading parameters
alone (``loading.preload``, ``retract_from``, ``preload_via``) and the force at which the approach ended.

Compressive and zero preloads are reached by loading from the approach's end; tensile ones by retraction from
``retract_from``, as in the experiment. On the way the path lands on the forces of ``preload_via`` it passes, each
reached the way the path to it alone would reach it, so the path to one preload passes through the states at the
others and a study's normal states can be computed one after the other (:func:`previous_target`). A preload to a
target contact area (``loading.preload_area``) corrects the force after it by secant steps (:func:`area_correction`),
inside the bracket of states on either side of the area once there is one (:func:`bracketed_force`).
"""

from __future__ import annotations

import math
from collections.abc import Iterable

from ..states import Phase

__all__ = ["SECANT_STEP_GROWTH", "preload_targets", "previous_target", "area_correction", "area_bracket",
           "bracketed_force", "area_targets", "area_unreachable", "AreaUnreachable"]


def _retracted_to(loading, Fn: float, Fn_approached: float) -> bool:
    """Whether the path reaches the preload ``Fn`` by retraction from ``loading.retract_from``."""
    return Fn > 0.0 and loading.retract_from < min(Fn_approached, Fn)


def _landings(loading, start: float, end: float, retracting: bool, Fn_approached: float) -> list[float]:
    """The forces of ``loading.preload_via`` strictly between ``start`` and ``end``, in the order a path from
    ``start`` meets them, that the path to each of them itself reaches by retraction (or not: ``retracting``)."""
    lo, hi = sorted((start, end))
    passed = {v for v in loading.preload_via
              if lo < v < hi and _retracted_to(loading, v, Fn_approached) == retracting}
    return sorted(passed, reverse=end < start)


def preload_targets(loading, Fn_approached: float) -> list[float]:
    """The preload targets after an approach that ended at ``Fn_approached``: the preload, reached through
    ``retract_from`` when it is tensile beyond the approach's end force, and landing on the forces of
    ``loading.preload_via`` that the loading (or the retraction) passes. Each target starts a new continuation, so
    the path to a preload continues the path to any target before it, step for step."""
    L = loading
    if _retracted_to(L, L.preload, Fn_approached):
        return [*_landings(L, Fn_approached, L.retract_from, False, Fn_approached), L.retract_from,
                *_landings(L, L.retract_from, L.preload, True, Fn_approached), L.preload]
    return [*_landings(L, Fn_approached, L.preload, False, Fn_approached), L.preload]


def previous_target(loading, computed: Iterable[float]) -> float | None:
    """The last target before ``loading.preload`` on its path that is among ``computed`` (the preloads whose
    states a study computes), for an approach that ended above every target (a tensile force, as on the adhesive
    cap); None when there is none and the path starts from the approach."""
    computed = set(computed)
    before = [t for t in preload_targets(loading, math.inf)[:-1] if t in computed]
    return before[-1] if before else None


class AreaUnreachable(ValueError):
    """The contact area does not grow with the compressive force where the preload stands (an unstable branch, or a
    contact that does not change): no force step reaches the target area from there."""


SECANT_STEP_GROWTH = 2.0  # a secant's force step is at most this many times the last one


def area_correction(Fn: tuple[float, float], area: tuple[float, float], target: float, rtol: float,
                    min_step: float) -> float | None:
    """The next force target toward the contact area ``target`` by a secant through the last two converged states
    (``Fn`` in E L0^2 or E L0, positive = tensile; ``area`` in L0^2 or L0, the later state last); None when the later
    area is within ``rtol`` of the target, or when the secant's step is below ``min_step`` (the force is resolved as
    finely as the preload's steps go). On the stable branch the area grows as Fn falls (compression).

    The step is at most ``SECANT_STEP_GROWTH`` times the last one: where the contact's edge is pinned between two
    jumps (a stair of the area on a mesh that does not resolve the cohesive zone), the secant is nearly flat and
    would leap several jumps past the target (docs/experiment3d.md, lambda = 3 on the annulus)."""
    (F0, F1), (A0, A1) = Fn, area
    if abs(A1 - target) <= rtol * target:
        return None
    slope = (A1 - A0) / (F1 - F0) if F1 != F0 else 0.0
    if not slope < 0.0:
        raise AreaUnreachable(f"the contact area {A1:.6g} does not grow under compression there (dA/dFn = {slope:.3g}); "
                              f"target {target:.6g}")
    step = (target - A1) / slope
    step = math.copysign(min(abs(step), SECANT_STEP_GROWTH * abs(F1 - F0)), step)
    return None if abs(step) < min_step else F1 + step


def area_bracket(bracket: list, marks, target: float) -> list:
    """The converged preload states nearest the target area on either side (anything with ``Fn`` and ``area``; at
    most one with ``area >= target`` and one below): ``bracket`` updated with the last two of ``marks`` in order,
    each replacing the state on its side."""
    out = list(bracket)
    for m in [m for m in marks[-2:] if m.phase == Phase.PRELOAD]:
        out = [b for b in out if (b.area >= target) != (m.area >= target)] + [m]
    return out


def bracketed_force(bracket: list, last_two: tuple, target: float, rtol: float, min_step: float) -> float | None:
    """The next force target inside a ``bracket`` of two states on either side of the contact area ``target``: the
    secant's force through the ``last_two`` states when it falls well inside (1 % of the width from either end), the
    bracket's middle otherwise (an area that jumps, or does not grow under compression, between them); None when the
    bracket is resolved (width at most ``rtol`` times its force, or below ``min_step``): the area jumps over the
    target there, as a contact edge snapping in or out by a face does."""
    a, b = bracket
    width, (lo, hi) = abs(a.Fn - b.Fn), sorted((a.Fn, b.Fn))
    if width <= max(min_step, rtol * max(abs(a.Fn), abs(b.Fn))):
        return None
    m0, m1 = last_two
    slope = (m1.area - m0.area) / (m1.Fn - m0.Fn) if m1.Fn != m0.Fn else 0.0
    F = m1.Fn + (target - m1.area) / slope if slope < 0.0 else math.nan
    return F if lo + 0.01 * width <= F <= hi - 0.01 * width else 0.5 * (lo + hi)


def area_targets(loading, marks, bracket: list) -> tuple[list[float], list]:
    """The next force target of a preload to ``loading.preload_area`` from the last two converged states of
    ``marks`` (anything with ``phase``, ``Fn`` and ``area``) and the bracket so far (:func:`area_bracket`), and the
    bracket updated: [] when the area is reached, or when the states on either side of it are as close in force as
    the area's tolerance asks (the last state stays); by a secant through the last two states, kept inside the bracket
    once there is one; AreaUnreachable when no force step reaches the area from there."""
    if len(marks) < 2:
        raise AreaUnreachable("a secant needs two converged states, the path has one")
    L, (m0, m1) = loading, marks[-2:]
    bracket = area_bracket(bracket, marks, L.preload_area)
    if len(bracket) == 2 and abs(m1.area - L.preload_area) > L.preload_area_rtol * L.preload_area:
        target = bracketed_force(bracket, (m0, m1), L.preload_area, L.preload_area_rtol, L.min_force_step)
    else:
        target = area_correction((m0.Fn, m1.Fn), (m0.area, m1.area), L.preload_area, L.preload_area_rtol,
                                 L.min_force_step)
    return ([] if target is None else [target]), bracket


def area_unreachable(loading, marks, bracket: list) -> str:
    """Why :func:`area_targets` finds no force target from ``marks`` (one line, naming the key and its value)."""
    try:
        area_targets(loading, marks, bracket)
    except AreaUnreachable as err:
        return f"preload to loading.preload_area = {loading.preload_area:.6g}: {err}"
    return f"preload to loading.preload_area = {loading.preload_area:.6g}: no force target"
