"""Rules of the slide leg on the path's last converged steps (its marks): how long the next step may be while the stick
zone closes, which converged steps are cut back (the onset of full sliding overstepped; |Ft| falling too fast
with slip weakening; the contact area jumping), and when sliding is steady. They read the path state's marks and
a step's record (the steady rule also the gaps before the step), nothing else, and the onset check leaves the ubar
of a step it cut back in the path state (its ``onset_ceiling``); the slide leg in :mod:`.cap` applies them.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from ..states import Phase
from .measures import fully_sliding

__all__ = ["Mark", "onset_step_limit", "SNAP_DROP", "snap_check", "AREA_JUMP", "JUMP_REPEAT", "AreaJump", "jump_check",
           "REGROWTH", "regrowth_check", "ONSET_BRACKET", "onset_bracket", "onset_check", "STEADY_TOLERANCE",
           "steady_sliding", "either"]


@dataclass(frozen=True)
class Mark:
    """What the path keeps of a converged step for its own decisions."""

    phase: Phase
    ubar: float
    Fn: float
    area_stick: float
    Ft: float = math.nan
    area: float = math.nan  # contact area (L0)


def onset_step_limit(marks: list[Mark], ubar: float, ceiling: float = math.nan, bracket: float = 0.0,
                     direction: float = 1.0, tolerance: float = 0.005) -> float:
    """Largest next slide step while the stick zone closes: the onset of full sliding is then found to about
    ``tolerance`` |ubar|, whatever the step size elsewhere.

    Before any step overshot the onset, the onset is predicted by extrapolating the stick area of the last two
    slide steps linearly to zero; the step is at most half the predicted remaining distance, and at least
    ``tolerance`` |ubar|. Once a step to ``ceiling`` was cut back for closing the stick zone (:func:`onset_check`),
    the onset lies before it, and the steps bisect what is left: half of it, and a step of ``bracket`` (the longest
    closing step :func:`onset_check` accepts) once at most two brackets are left, which either closes the stick zone
    or leaves at most one bracket to the ceiling. ``direction``: the sign of the slide's steps.
    """
    left = (ceiling - ubar) * direction  # NaN (no ceiling) compares false
    if marks and marks[-1].phase == Phase.SLIDE and marks[-1].area_stick > 0.0 and left > 0.0:
        return min(left, bracket) if left <= 2.0 * bracket else 0.5 * left
    last = [m for m in marks[-2:] if m.phase == Phase.SLIDE]
    if len(last) < 2 or last[-1].area_stick <= 0.0:
        return math.inf
    (u0, a0), (u1, a1) = [(m.ubar, m.area_stick) for m in last]
    if a1 >= a0 or u1 == u0:
        return math.inf
    u_onset = u1 + a1 * (u1 - u0) / (a0 - a1)
    # approach the predicted onset in halving steps: the stick zone shrinks faster than linearly at the end
    return max(0.5 * abs(u_onset - ubar), tolerance * abs(ubar))


SNAP_DROP = 0.01  # largest fall of |Ft| in one slide step, relative to the step's start, with slip weakening


def snap_check(state, drop: float = SNAP_DROP):
    """With slip weakening, a slide step whose |Ft| falls by more than ``drop`` of the last step's is cut back: a
    smooth fall then passes in short steps, and a fall that persists at the minimum step is a snap (no
    quasi-static path; the leg ends diverged there, and the case snapped, :class:`capslide.driver.observers.Snap`).
    Only the forward slide: sliding back unloads |Ft| elastically first. ``state``: the path state, whose marks are
    read at each step."""
    def rejects(rec) -> str | None:
        last = state.marks[-1] if state.marks else None
        if last is None or last.phase != rec.phase or not abs(rec.Ft) < (1.0 - drop) * abs(last.Ft):
            return None
        return f"|Ft| fell from {abs(last.Ft):.6g} to {abs(rec.Ft):.6g} in one step"
    return rejects


AREA_JUMP = 0.2  # largest relative change of the contact area in one slide step (jump_check)
JUMP_REPEAT = 0.25  # two rejected steps jumped to one state: their areas within this share of the jump (AreaJump)


class AreaJump:
    """The area-jump rule of :func:`jump_check`: a callable ``rejects(rec) -> reason or None`` that remembers the
    areas of the last two steps it rejected from the path's last mark."""

    def __init__(self, state, largest: float = AREA_JUMP, repeat: float = JUMP_REPEAT):
        self.state, self.largest, self.repeat = state, largest, repeat
        self.landed: list[tuple[Mark, float]] = []  # (the mark a rejected step started from, the area it found)
        self.skipped_from: Mark | None = None  # the mark whose repeated jump last sent the slide to its smallest step

    def __call__(self, rec) -> str | None:
        last = self.state.marks[-1] if self.state.marks else None
        if last is None or last.phase != rec.phase or not abs(rec.area - last.area) > self.largest * last.area:
            return None
        self.landed = [*(j for j in self.landed[-1:] if j[0] is last), (last, rec.area)]
        return f"the contact area jumped from {last.area:.6g} to {rec.area:.6g} in one step"

    def repeats(self) -> bool:
        """Whether the last two steps rejected from the path's last mark found the same area, within ``repeat`` of
        the jump (a continuous change halves with the step): the jump is there at every step length, so the
        halvings would only repeat it down to the smallest step, and the next step may as well be that one. Not
        from the state right after such a smallest step (the mark it answered for is kept): where that step found no
        jump, the fold lies further on, and the halvings bisect."""
        marks = self.state.marks
        if len(self.landed) < 2 or any(mark is not marks[-1] for mark, _ in self.landed):
            return False
        if len(marks) > 1 and marks[-2] is self.skipped_from:
            return False
        (_, first), (_, second) = self.landed
        if abs(second - first) >= self.repeat * abs(first - marks[-1].area):
            return False
        self.skipped_from = marks[-1]
        return True


def jump_check(state, largest: float = AREA_JUMP) -> AreaJump:
    """A slide step whose contact area changes by more than ``largest`` of the last step's is cut back: a continuous
    change passes in shorter steps, and a change that persists at the minimum step is a jump to another equilibrium
    (at a fold of the path, where no quasi-static path goes on; the leg then ends diverged there). Measured: at most
    5.5 % in a step in the paper's cases, the `fast` cases and the stability suite; 46 % at the jump it was written
    for (the stability suite's tensile_90: 4.59 to 6.72 L0 in a step of 1.3e-4 L0, while the contact peeled off).
    Once two halvings found the same jump (:meth:`AreaJump.repeats`), the slide leg's next step is the smallest."""
    return AreaJump(state, largest)


REGROWTH = "the next equilibrium found re-adheres"  # in the reason of a leg the regrowth rule ended


def regrowth_check(state, largest: float = AREA_JUMP):
    """A snap to a state whose area exceeds the last step's by more than ``largest``: the continuation found the
    contact re-adhered at once, which the quasi-static path is taken not to follow (the plate springs away from a
    contact that comes off, and the snap's own step holds no threshold for points new in contact,
    ``friction.threshold_at``). The leg then ends detached at the last state. Seen on the experiment's A0 = 0.10
    mm^2: the area fell by snaps to 10,000 um^2, then a snap re-adhered it at 118,000 um^2 in full slip. Whether
    the area fell at the last step does not enter: on A0 = 0.19 mm^2 a rise of 0.1 % there let a re-adhering snap of
    34 % pass at slide steps of 0.25 um, which ended the slide at 1 um (docs/experiment3d.md)."""
    def vanishes(rec) -> str | None:
        if not state.marks:
            return None
        last = state.marks[-1]
        if last.phase != rec.phase or not rec.area > (1.0 + largest) * last.area:
            return None
        fell = len(state.marks) > 1 and last.area < state.marks[-2].area
        return (f"the contact came off at ubar = {last.ubar:.6g} (its area {'fell to' if fell else 'was'} "
                f"{last.area:.6g}; {REGROWTH} at {rec.area:.6g})")
    return vanishes


ONSET_BRACKET = 1e-3  # the onset of full sliding is located to this fraction of ubar (onset_check)


def onset_bracket(ubar: float, smallest: float, tolerance: float = ONSET_BRACKET) -> float:
    """The longest slide step to ubar (from below) that may close the stick zone: ``tolerance`` |ubar|, and at least
    2 ``smallest`` so that a cut-back stays above the smallest step."""
    return max(tolerance * abs(ubar), 2.0 * smallest)


def onset_check(state, smallest: float, tolerance: float = ONSET_BRACKET):
    """A slide step that ends the stick zone (its record fully sliding, the last step's stick area > 0) is cut back
    while it is longer than :func:`onset_bracket`: the onset of full sliding, the first fully sliding step, is then
    located to that bracket. The cut-back step's ubar becomes ``state.onset_ceiling``, below which the onset lies
    (:func:`onset_step_limit` bisects up to it)."""
    def rejects(rec) -> str | None:
        last = state.marks[-1] if state.marks else None
        if last is None or last.phase != rec.phase or not last.area_stick > 0.0 or not fully_sliding(rec):
            return None
        length = abs(rec.ubar - last.ubar)
        if length <= onset_bracket(rec.ubar, smallest, tolerance):
            return None
        state.onset_ceiling = rec.ubar
        return f"the stick zone closed within a step of {length:.3g}"
    return rejects


STEADY_TOLERANCE = 1e-8  # steady sliding: relative change of Ft and area per step, gap change per step over r0


def steady_sliding(marks: list[Mark], rec, gap_before: Callable[[], np.ndarray], length: float,
                   tolerance: float = STEADY_TOLERANCE) -> bool:
    """Whether the slide is steady after the converged step ``rec`` (issue 19, item 2): the last two marks and
    ``rec`` slide fully (contact, and no stick length; ubar = 0 too, which :func:`fully_sliding` leaves out for the
    onset), Ft and the contact area changed by at most ``tolerance`` (relative) in each of the two steps, and no
    surface point's gap changed by more than ``tolerance`` ``length`` (L0; the law's range r0) in the last one.
    ``gap_before()`` gives the gaps (L0) before ``rec``'s step; it is called only when the rest holds. A steady
    state only translates with ubar (the same deformation, the anchors moved along), so the path may go on in long
    steps. Measured on the cap: two steps after the onset these changes are round-off (1e-15 to 1e-13), from 1e-5
    in the step before."""
    steps = [*marks[-2:], rec]
    if len(steps) < 3 or any(s.phase != rec.phase or not s.area > 0.0 or s.area_stick > 0.0 for s in steps):
        return False
    for a, b in zip(steps[:-1], steps[1:]):
        if not (abs(b.Ft - a.Ft) <= tolerance * abs(b.Ft) and abs(b.area - a.area) <= tolerance * b.area):
            return False
    return bool(np.max(np.abs(rec.gap - gap_before()), initial=0.0) <= tolerance * length)


def either(*checks):
    """The first reason any of ``checks`` (each None or rejects(record) -> reason or None) gives."""
    active = [c for c in checks if c is not None]
    return lambda rec: next((r for r in (c(rec) for c in active) if r is not None), None)
