"""Where the preload's path lands (docs/theory.md section 5): the targets of the preload leg, from the loading parameters
alone (``loading.preload``, ``retract_from``, ``preload_via``) and the force at which the approach ended.

Compressive and zero preloads are reached by loading from the approach's end; tensile ones by retraction from
``retract_from``, as in the experiment. On the way the path lands on the forces of ``preload_via`` it passes, each
reached the way the path to it alone would reach it, so the path to one preload passes through the states at the
others and a study's normal states can be computed one after the other (:func:`previous_target`). A preload to a
target contact area (``loading.preload_area``) corrects the force after it by secant steps (:func:`area_correction`).
"""

from __future__ import annotations

import math
from collections.abc import Iterable

__all__ = ["preload_targets", "previous_target", "area_correction", "area_targets", "area_unreachable",
           "AreaUnreachable"]


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


def area_correction(Fn: tuple[float, float], area: tuple[float, float], target: float, rtol: float,
                    min_step: float) -> float | None:
    """The next force target toward the contact area ``target`` by a secant through the last two converged states
    (``Fn`` in E L0^2 or E L0, positive = tensile; ``area`` in L0^2 or L0, the later state last); None when the later
    area is within ``rtol`` of the target, or when the secant's step is below ``min_step`` (the force is resolved as
    finely as the preload's steps go). On the stable branch the area grows as Fn falls (compression)."""
    (F0, F1), (A0, A1) = Fn, area
    if abs(A1 - target) <= rtol * target:
        return None
    slope = (A1 - A0) / (F1 - F0) if F1 != F0 else 0.0
    if not slope < 0.0:
        raise AreaUnreachable(f"the contact area {A1:.6g} does not grow under compression there (dA/dFn = {slope:.3g}); "
                              f"target {target:.6g}")
    step = (target - A1) / slope
    return None if abs(step) < min_step else F1 + step


def area_targets(loading, marks) -> list[float]:
    """The next force target of a preload to ``loading.preload_area`` from the last two converged states of
    ``marks`` (anything with ``Fn`` and ``area``): [] when the area is reached; AreaUnreachable when no force step
    reaches it from there."""
    if len(marks) < 2:
        raise AreaUnreachable("a secant needs two converged states, the path has one")
    m0, m1 = marks[-2:]
    L = loading
    target = area_correction((m0.Fn, m1.Fn), (m0.area, m1.area), L.preload_area, L.preload_area_rtol, L.min_force_step)
    return [] if target is None else [target]


def area_unreachable(loading, marks) -> str:
    """Why :func:`area_targets` finds no force target from ``marks`` (one line, naming the key and its value)."""
    try:
        area_targets(loading, marks)
    except AreaUnreachable as err:
        return f"preload to loading.preload_area = {loading.preload_area:.6g}: {err}"
    return f"preload to loading.preload_area = {loading.preload_area:.6g}: no force target"
