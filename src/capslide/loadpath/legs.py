"""The legs of the cap's load path (docs/theory.md section 5), in their order, and the plan of a path: which legs
it runs and the share of the path each covers (what a progress display shows)."""

from __future__ import annotations

from enum import StrEnum

__all__ = ["LegName", "LEGS", "plan"]


class LegName(StrEnum):
    """The legs of the path, in their order. A member is equal to its text, so saved states keep the text."""

    APPROACH = "approach"
    SPREAD = "spread"
    PRELOAD = "preload"
    DWELL = "dwell"
    SLIDE = "slide"
    SLIDE_BACK = "slide back"
    DONE = "done"


LEGS = tuple(LegName)
# Each leg's usual share of a case's steps: the weights of :func:`plan`, which a progress display reads
_SHARE = {LegName.APPROACH: 0.10, LegName.SPREAD: 0.05, LegName.PRELOAD: 0.15, LegName.DWELL: 0.05,
          LegName.SLIDE: 0.70, LegName.SLIDE_BACK: 0.70}


def plan(loading) -> dict[LegName, tuple[float, float]]:
    """The legs a path with ``loading`` runs, each with the span (start, end; 0 to 1) of the whole path it
    covers, weighted by its usual share of the steps (a slide back halves the slide's share with it)."""
    legs = [LegName.APPROACH, *([LegName.SPREAD] if loading.approach_edge_step > 0.0 else []), LegName.PRELOAD,
            *([LegName.DWELL] if loading.dwell > 0.0 else []),
            *([LegName.SLIDE] if loading.ubar_max != 0.0 else []),
            *([LegName.SLIDE_BACK] if loading.ubar_max != 0.0 and loading.slide_back else [])]
    share = {leg: _SHARE[leg] * (0.5 if loading.slide_back and leg in (LegName.SLIDE, LegName.SLIDE_BACK) else 1.0)
             for leg in legs}
    total, start, spans = sum(share.values()), 0.0, {}
    for leg in legs:
        spans[leg] = (start / total, (start + share[leg]) / total)
        start += share[leg]
    spans[LegName.DONE] = (1.0, 1.0)
    return spans
