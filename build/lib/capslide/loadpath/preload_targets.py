"""Where the preload's path lands (docs/theory.md section 5): the targets of the preload leg, from the loading parameters
alone (``loading.preload``, ``retract_from``, ``preload_via``) and the force at which the approach ended.

Compressive and zero preloads are reached by loading from the approach's end; tensile ones by retraction from
``retract_from``, as in the experiment. On the way the path lands on the forces of ``preload_via`` it passes, each
reached the way the path to it alone would reach it, so the path to one preload passes through the states at the
others and a study's normal states can be computed one after the other (:func:`previous_target`).
"""

from __future__ import annotations

import math
from collections.abc import Iterable

__all__ = ["preload_targets", "previous_target"]


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
