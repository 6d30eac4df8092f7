"""The cap's load path (docs/theory.md section 5) as one generator of converged states: approach, preload, slide.

The path is a sequence of legs, each an adaptive continuation (:mod:`capslide.loadpath.continuation`) in one
scalar load parameter:

* ``approach``: the apex gap from ``approach_start_gap`` down to ``approach_end_gap`` (local displacement control
  follows the jump-in instability through its turning point, so every state is an exact equilibrium with no
  artificial term);
* ``spread`` (with ``approach_edge_step`` > 0): the contact edge, its surface points held at the end gap, spreads
  until Fn <= 0 (stiff, short-range laws, whose apex gap turns too at the snap-in);
* ``preload``: the normal force to each target; tensile targets are reached by retracting from
  ``loading.retract_from``, as in the experiment, and the path lands on the forces of ``loading.preload_via`` it
  passes; a retraction that loses the contact ends the path detached;
* ``dwell`` (with ``loading.dwell`` > 0): time passes at the preload under the slide's normal control, from a
  stage set at the preloaded state (a viscoelastic bulk relaxes);
* ``slide``: friction starts (anchors at the preloaded state; from the start of the approach with
  ``friction.active_from = contact``) and ubar goes to ``ubar_max`` under the normal
  control ``loading.normal_control``: at fixed Fn, at the preloaded height, or on a spring from a stage fixed at
  the preloaded state (:func:`slide_constraint`);
* ``slide back`` (with ``loading.slide_back``): ubar returns to 0.

With ``loading.velocity`` v every leg takes time: the stage moves at v while sliding and approaching (an apex-gap
or edge step of d L0 takes d L0 / v), and a preload step of dFn* takes as long as the stage needs for dFn* L0.

:class:`PathState` says where the path stands between two steps and holds everything it needs to go on, so
``load_path(model, start=state)`` continues a saved path. The driver observes the yielded :class:`PathStep` s;
the path knows nothing of files, terminals or checkpoints.
"""

from __future__ import annotations

import math
from collections.abc import Generator
from dataclasses import dataclass, field, replace

import numpy as np

from ..fem.mesh import H0_AT_SIZE_1
from ..model.constraints import FixedApexGap, FixedEdgeGap, FixedForce, FixedHeight, SlideAtForce, SlideOnSpring
from ..model.system import CapModel, History
from ..states import Phase, Status
from . import slide_rules
from .continuation import Converged, Leg, LegEnd, Loop, Notice, Returning, StepControl, continuation
from .legs import LEGS, LegName, plan
from .measures import StepRecord, fully_sliding
from .preload_targets import AreaUnreachable, area_targets, area_unreachable, preload_targets
from .slide_rules import Mark, either, jump_check, onset_bracket, onset_check, onset_step_limit, snap_check, steady_sliding

__all__ = ["LEGS", "LegName", "plan", "Mark", "PathState", "PathStep", "PathEnd", "initial_state", "load_path",
           "after_normal_state", "approach_control", "approach_step_limit", "spread_control", "spread_constraint",
           "onset_step_limit", "fully_sliding", "preload_targets", "continued_from", "slide_constraint", "snap_check"]


@dataclass
class PathState:
    """Where the path stands between two steps; ``load_path(model, start=state)`` goes on from here."""

    leg: LegName  # the running leg, or the next one when ``loop`` is None (a str of LEGS when read from a file)
    x: np.ndarray  # the current converged state [u, h]
    history: History = field(default_factory=History)
    loop: Loop | None = None  # loop variables of the running leg
    targets: list[float] = field(default_factory=list)  # preload targets not yet reached, the running one first
    marks: list[Mark] = field(default_factory=list)  # the last two steps
    cutbacks: int = 0  # over the finished legs
    smallest: float = math.inf  # smallest step over the finished legs
    stage_h: float | None = None  # substrate height at the start of the slide (L0): the stage of normal control
    onset_ceiling: float = math.nan  # ubar of the last slide step cut back for closing the stick zone (onset_check)
    preload_Fn: float | None = None  # the force the slide holds, when a preload to an area set it (else loading.preload)
    area_bracket: list[Mark] = field(default_factory=list)  # a preload to an area: the states either side of it

    def totals(self) -> tuple[int, float]:
        """Cut-backs and smallest step so far, the running leg included."""
        if self.loop is None:
            return self.cutbacks, self.smallest
        return self.cutbacks + self.loop.cutbacks, min(self.smallest, self.loop.smallest)


@dataclass
class PathStep:
    """A converged step as the driver sees it. ``state`` is the path after this step (the live object: save it
    before the path goes on); ``last`` says that the path ends after this step."""

    record: StepRecord
    x: np.ndarray
    breakpoint: float | None
    state: PathState
    last: bool = False


@dataclass(frozen=True)
class PathEnd:
    """How the path ended, with its last converged state, cut-backs, smallest step and the leg it ended in."""

    status: Status
    reason: str
    x: np.ndarray
    cutbacks: int
    min_step: float
    leg: str


def initial_state(model: CapModel) -> PathState:
    """The undeformed cap with the substrate ``approach_start_gap`` above the apex; with ``friction.active_from =
    contact`` every surface point is anchored where it starts (points out of contact meet no threshold and slip
    freely, so each is anchored in effect where it first touches)."""
    x = np.zeros(model.n_dofs + 1)
    x[-1] = model.params.geometry.H + model.params.loading.approach_start_gap
    if model.params.friction.active_from == "contact":
        return PathState(LegName.APPROACH, x, model.start_friction(x, 0.0))
    return PathState(LegName.APPROACH, x)


def seconds_per_unit(model: CapModel) -> float:
    """The time (s) a unit change of a leg's load value takes: L0 / v (no time when quasi-static)."""
    return 0.0 if model.params.loading.velocity is None else 1.0 / model.params.loading.velocity


def approach_control(model: CapModel) -> StepControl:
    L = model.params.loading
    return StepControl(L.approach_step, 1e-4 * model.params.adhesion.r0, L.approach_step, max_cutbacks=L.max_cutbacks)


APPROACH_MIN_CAP = 0.02  # r0: the approach's smallest step cap


def approach_step_limit(model: CapModel):
    """The approach's step cap at apex gap g (L0): half the distance left to the end gap, at least 0.02 r0. The
    last steps before the end gap pull the surface around the apex in, and longer ones ran to the Newton limit and
    were cut back (docs/performance.md)."""
    end, floor = model.params.loading.approach_end_gap, APPROACH_MIN_CAP * model.params.adhesion.r0
    return lambda gap: max(0.5 * abs(gap - end), floor)


def spread_control(model: CapModel) -> StepControl:
    # easy_iterations 6: each step moves a steep cohesive zone, Newton takes 5-7 iterations even for short steps
    step = model.params.loading.approach_edge_step
    return StepControl(0.25 * step, 1e-4 * step, step, easy_iterations=6, max_cutbacks=model.params.loading.max_cutbacks)


def spread_constraint(model: CapModel):
    """Edge control at the approach's end gap, and the largest edge abscissa the top surface allows."""
    gap = model.params.loading.approach_end_gap
    return (lambda X: FixedEdgeGap(X, gap)), model.edge_limit()


def _force_control(model: CapModel) -> StepControl:
    L = model.params.loading
    return StepControl(L.force_step, L.min_force_step, L.force_step, max_cutbacks=L.max_cutbacks)


def _slide_control(model: CapModel) -> StepControl:
    L = model.params.loading
    return StepControl(L.slide_step, L.min_slide_step, L.max_slide_step, easy_iterations=L.slide_growth_iterations,
                       max_cutbacks=L.max_cutbacks)


def _min_area(model: CapModel) -> float:  # a contact shorter than two surface elements has come off
    return 2.0 * H0_AT_SIZE_1 * model.params.mesh.size


# -- legs: each sets up its loop (unless resumed), runs it, and says what comes next ----------------------------
def _run(model: CapModel, state: PathState, steps: Generator[Converged | Notice, None, LegEnd],
         after: str) -> Generator[PathStep | Notice, None, LegEnd]:
    """Relay the continuation's steps as path steps (notices as they are); on completion the state moves on to the
    leg ``after``."""
    run = Returning(steps)
    for conv in run:
        if isinstance(conv, Notice):
            yield conv
            continue
        state.x, state.history = conv.x, conv.history
        rec = conv.record
        state.marks = [*state.marks[-1:], Mark(rec.phase, rec.ubar, rec.Fn, rec.area_stick, rec.Ft, rec.area)]
        if conv.end is not None and conv.end.status == Status.COMPLETED:
            _finish_leg(model, state, after)
        yield PathStep(conv.record, conv.x, conv.breakpoint, state,
                       last=conv.end is not None and conv.end.status != Status.COMPLETED)
    if run.value.status == Status.COMPLETED and state.loop is not None:  # a leg of zero length: no step, skipped
        _finish_leg(model, state, after)
    return run.value


def _finish_leg(model: CapModel, state: PathState, after: str) -> None:
    cut, smallest = state.totals()
    state.cutbacks, state.smallest, state.loop = cut, smallest, None
    if state.leg == LegName.PRELOAD:
        state.targets = state.targets[1:]
        if not state.targets and model.params.loading.preload_area is not None:
            try:
                state.targets, state.area_bracket = area_targets(model.params.loading, state.marks, state.area_bracket)
            except AreaUnreachable:
                return  # the preload leg stays, without a target: it ends the path with the reason
        if state.targets:
            return
    if after == LegName.PRELOAD:
        state.targets = _preload_targets(model, state)
    state.leg = after


def _after_preload(model: CapModel) -> LegName:
    if model.params.loading.dwell > 0.0:
        return LegName.DWELL
    return _after_dwell(model)


def _after_dwell(model: CapModel) -> LegName:
    return LegName.SLIDE if model.params.loading.ubar_max != 0.0 else LegName.DONE


def _current_Fn(model: CapModel, state: PathState) -> float:
    return state.marks[-1].Fn if state.marks else model.contact.force(state.x[:-1], state.x[-1], 0.0, *state.history.friction)[1]


def _preload_targets(model: CapModel, state: PathState) -> list[float]:
    return preload_targets(model.params.loading, _current_Fn(model, state))


def continued_from(loading, preloaded: PathState, reached: float, Fn_approached: float) -> PathState | None:
    """The path to ``loading.preload`` continued from ``preloaded``, a path of the same configuration preloaded to
    ``reached`` whose approach ended at ``Fn_approached``, when the path passes through it (its targets begin with
    those of ``reached``: a preload beyond it on the loading, or a tensile one reached by retraction; a preload to an
    area from any), None otherwise. The continued path is the uninterrupted one: same targets, marks and totals."""
    ours = preload_targets(loading, Fn_approached)
    theirs = preload_targets(replace(loading, preload=reached), Fn_approached)
    if loading.preload_area is not None:  # its force is a guess: the path goes on from any preloaded state
        ours, theirs = [reached, loading.preload], [reached]
    if (len(ours) <= len(theirs) or ours[:len(theirs)] != theirs or preloaded.loop is not None or preloaded.targets
            or preloaded.leg not in (LegName.DWELL, LegName.SLIDE, LegName.DONE)):
        return None
    if not preloaded.marks or preloaded.marks[-1].phase != Phase.PRELOAD:
        return None
    return PathState(LegName.PRELOAD, preloaded.x, preloaded.history, None, ours[len(theirs):], list(preloaded.marks),
                     preloaded.cutbacks, preloaded.smallest)


def _approach(model: CapModel, state: PathState, snapshot_ubar) -> Generator[PathStep, None, LegEnd]:
    L = model.params.loading
    control = approach_control(model)
    if state.loop is None:
        state.loop = Loop.start(state.x, L.approach_start_gap, L.approach_end_gap, control)
    after = LegName.SPREAD if L.approach_edge_step > 0.0 else LegName.PRELOAD
    steps = continuation(model, state.loop, state.history,
                         Leg(FixedApexGap, L.approach_end_gap, control, Phase.APPROACH, "approach",
                             step_limit=approach_step_limit(model), seconds_per_unit=seconds_per_unit(model)))
    return (yield from _run(model, state, steps, after))


def _spread(model: CapModel, state: PathState, snapshot_ubar) -> Generator[PathStep, None, LegEnd]:
    constraint_of, X_end = spread_constraint(model)
    control = spread_control(model)
    if state.loop is None:
        state.loop = Loop.start(state.x, 0.0, X_end, control)
    until = lambda rec: Status.COMPLETED if rec.Fn <= 0.0 else None  # noqa: E731
    steps = continuation(model, state.loop, state.history,
                         Leg(constraint_of, X_end, control, Phase.SPREAD, "approach", ends=until,
                             seconds_per_unit=seconds_per_unit(model)))
    return (yield from _run(model, state, steps, LegName.PRELOAD))


def _preload(model: CapModel, state: PathState, snapshot_ubar) -> Generator[PathStep, None, LegEnd]:
    control = _force_control(model)
    if not state.targets:  # a preload to an area that no force step reaches (_finish_leg)
        return LegEnd(Status.DIVERGED, area_unreachable(model.params.loading, state.marks, state.area_bracket))
    target = state.targets[0]
    if state.loop is None:
        state.loop = Loop.start(state.x, _current_Fn(model, state), target, control)
    retracting = target > state.loop.value  # only a retraction can pull the contact off
    min_area, area = _min_area(model), model.params.loading.preload_area

    def ends(rec: StepRecord) -> Status | None:  # a preload to an area stops where it passes the area (a bracket)
        passed = area is not None and (rec.area <= area if retracting else rec.area >= area)
        return Status.DETACHED if retracting and rec.area < min_area else Status.COMPLETED if passed else None

    steps = continuation(model, state.loop, state.history,
                         Leg(FixedForce, target, control, Phase.PRELOAD, "preload", ends=ends,
                             seconds_per_unit=seconds_per_unit(model), secant=False))
    end = yield from _run(model, state, steps, _after_preload(model))
    Fn = _current_Fn(model, state)
    if end.status == Status.DIVERGED and target > Fn and target > 0:  # no equilibrium at the tensile force: pull-off
        return LegEnd(Status.DETACHED, f"pull-off: no equilibrium beyond Fn = {Fn:.6g}")
    return end


def slide_constraint(loading, stage_h: float, Fn: float | None = None):
    """The constraint at ubar of ``loading.normal_control``, with the stage set where the substrate stood at the start
    of the slide (``stage_h``, L0) holding the preload ``Fn`` (default ``loading.preload``)."""
    Fn = loading.preload if Fn is None else Fn
    if loading.normal_control == "height":
        return lambda ubar: FixedHeight(stage_h, ubar)
    if loading.normal_control == "spring":
        return lambda ubar: SlideOnSpring(ubar, Fn, stage_h, loading.spring_stiffness)
    return lambda ubar: SlideAtForce(ubar, Fn)


def _set_stage(model: CapModel, state: PathState) -> None:  # and the force reached by a preload to an area
    state.stage_h = float(state.x[-1])
    if model.params.loading.preload_area is not None:
        state.preload_Fn = _current_Fn(model, state)


def _slide_leg(model: CapModel, state: PathState, start: float, end: float, breakpoints, name: str,
               after: str) -> Generator[PathStep, None, LegEnd]:
    control = _slide_control(model)
    if state.loop is None:
        state.loop = Loop.start(state.x, start, end, control, breakpoints)
        state.onset_ceiling = math.nan
    detached = lambda rec: Status.DETACHED if rec.area < _min_area(model) else None  # noqa: E731
    forward = name == LegName.SLIDE
    regrowth = slide_rules.regrowth_check(state) if model.params.loading.readhesion_snap == "end" else None
    rejects = either(onset_check(state, control.minimum) if forward else None,
                      snap_check(state) if model.params.friction.weakening and forward else None, jumps := jump_check(state))
    direction = 1.0 if end >= start else -1.0

    def step_limit(ubar: float) -> float:  # the closing step a hair inside the bracket: ubar + step rounds
        bracket = (1.0 - 1e-9) * onset_bracket(ubar, control.minimum)
        closing = onset_step_limit(state.marks, ubar, state.onset_ceiling if forward else math.nan, bracket, direction)
        return 0.0 if jumps.repeats() else closing  # once a jump repeats, the smallest step (where a jump stands)

    def steady(rec: StepRecord, x_before: np.ndarray) -> bool:
        gap_before = lambda: model.contact.gaps(*model.split(x_before))[0].ravel()  # noqa: E731
        return steady_sliding(state.marks, rec, gap_before, model.params.adhesion.r0)

    constraint = slide_constraint(model.params.loading, state.stage_h, state.preload_Fn)
    steps = continuation(model, state.loop, state.history,
                         Leg(constraint, end, control, Phase.SLIDE, name,
                             ends=detached, step_limit=step_limit, rejects=rejects, steady=steady,
                             seconds_per_unit=seconds_per_unit(model), stick_first=True, vanishes=regrowth))
    return (yield from _run(model, state, steps, after))


def _slide(model: CapModel, state: PathState, snapshot_ubar) -> Generator[PathStep, None, LegEnd]:
    L = model.params.loading
    if state.loop is None:  # the stage is set (unless a dwell set it); friction acts from here on (default)
        if model.params.friction.active_from == "slide":
            state.history = model.start_friction(state.x, 0.0, state.history)
        if state.stage_h is None:
            _set_stage(model, state)
    after = LegName.SLIDE_BACK if L.slide_back else LegName.DONE
    return (yield from _slide_leg(model, state, 0.0, L.ubar_max, tuple(snapshot_ubar), LegName.SLIDE, after))


def _slide_back(model: CapModel, state: PathState, snapshot_ubar) -> Generator[PathStep, None, LegEnd]:
    return (yield from _slide_leg(model, state, model.params.loading.ubar_max, 0.0, (), LegName.SLIDE_BACK, LegName.DONE))


def _dwell(model: CapModel, state: PathState, snapshot_ubar) -> Generator[PathStep, None, LegEnd]:
    """Time from 0 to ``loading.dwell`` at the preload, under the slide's normal control at ubar = 0."""
    L = model.params.loading
    control = StepControl(L.dwell / 64.0, L.dwell * 1e-6, L.dwell / 4.0, max_cutbacks=L.max_cutbacks)
    if state.loop is None:
        _set_stage(model, state)
        state.loop = Loop.start(state.x, 0.0, L.dwell, control)
    at_rest = slide_constraint(L, state.stage_h, state.preload_Fn)
    steps = continuation(model, state.loop, state.history,
                         Leg(lambda t: at_rest(0.0), L.dwell, control, Phase.DWELL, "dwell", seconds_per_unit=1.0))
    return (yield from _run(model, state, steps, _after_dwell(model)))


_LEG_RUNNERS = {LegName.APPROACH: _approach, LegName.SPREAD: _spread, LegName.PRELOAD: _preload,
                LegName.DWELL: _dwell, LegName.SLIDE: _slide, LegName.SLIDE_BACK: _slide_back}


def after_normal_state(model: CapModel, state: PathState) -> PathState:
    """``state`` with its next leg set by ``model``'s own loading when the path stands just after its last preload
    step (a normal state, computed with another dwell or ubar_max): a dwell when this case asks for one, then the
    slide; unchanged elsewhere."""
    preloaded = (state.loop is None and not state.targets and state.leg in (LegName.DWELL, LegName.SLIDE, LegName.DONE)
                 and bool(state.marks) and state.marks[-1].phase == Phase.PRELOAD)
    if preloaded:
        state.leg = _after_preload(model)
    return state


def _counted(steps: Generator, seen: list[int]) -> Generator:  # steps relayed, the converged ones counted in seen[0]
    run = Returning(steps)
    for step in run:
        if isinstance(step, PathStep):
            seen[0] += 1
        yield step
    return run.value


def load_path(model: CapModel, snapshot_ubar=(), start: PathState | None = None,
              stop_before: str = LegName.DONE) -> Generator[PathStep, None, PathEnd]:
    """Converged steps of the load path from ``start`` (default: :func:`initial_state`) until the leg ``stop_before``
    would start, slide steps ending on every ``snapshot_ubar``; returns how it ended (diverged when a leg ends
    without a step and leaves the path where it was: no loop repeats without progress)."""
    state = start if start is not None else initial_state(model)
    while LEGS.index(state.leg) < LEGS.index(stop_before):
        if state.loop is None:  # every leg starts with a fresh factorization: a leg repeats the same arithmetic
            model.solver.invalidate()  # whether the path ran up to it or starts there from a saved state
        where, seen = (state.leg, len(state.targets), state.loop is None), [0]
        end = yield from _counted(_LEG_RUNNERS[state.leg](model, state, snapshot_ubar), seen)
        if end.status != Status.COMPLETED:
            return PathEnd(end.status, end.reason, state.x, *state.totals(), state.leg)
        if not seen[0] and (state.leg, len(state.targets), state.loop is None) == where:
            return PathEnd(Status.DIVERGED, f"{state.leg}: the leg ended without a step and the path did not move on",
                           state.x, *state.totals(), state.leg)
    return PathEnd(Status.COMPLETED, "", state.x, *state.totals(), state.leg)
