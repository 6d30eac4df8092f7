"""Adaptive continuation in one scalar load parameter, as a generator of converged states.

``continuation`` steps the parameter from the loop's value to ``end`` under :class:`StepControl`: the step grows by
``growth`` after a Newton solve of at most ``easy_iterations`` iterations and is halved after a failure; a step
shortened to land on the end, a breakpoint or the leg's step limit leaves the step as it was; below the minimum
step, or past ``max_cutbacks`` halvings, the continuation ends as diverged with a reason instead of looping. A
secant predictor extrapolates the last two converged states, unless the leg asks for none (under force control it
started the preload's Newton solves farther off than the last state did). A leg may ask for a stick predictor of its
first step instead (``stick_first``): a Newton solve with every friction point held in stick
(:meth:`CapModel.sticking`), from which the real solve starts; its iterations count in the step's. Once the
leg's ``steady`` rule holds after a step, the step control no longer caps the next steps: each goes to the next
breakpoint or the end in one, and its record says so; a long step that fails, or after which the rule no longer
holds, is cut back as any other (halved, to at most the step control's maximum). Each converged
step is measured, the history committed, and a :class:`Converged` yielded; the generator's return value is the
:class:`LegEnd`. The loop variables live in a :class:`Loop` that the caller owns, so a continuation can start again
from a saved one. Nothing here knows of files, terminals or checkpoints.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Generator
from dataclasses import dataclass, field

import numpy as np

from ..model.system import CapModel, History
from ..solvers.newton import NewtonOptions, NewtonResult, newton
from ..states import Phase, Status
from .measures import StepRecord, measure
from .snap_through import PseudoTransient, pseudo_transient

__all__ = ["StepControl", "Leg", "Loop", "LegEnd", "Converged", "Notice", "newton_options", "solve_constrained", "continuation",
           "Returning", "drain"]


@dataclass(frozen=True)
class StepControl:
    """Step sizes of a continuation (units of its load parameter) and when to grow or give up."""

    first: float
    minimum: float
    maximum: float
    growth: float = 1.5
    easy_iterations: int = 4  # a solve with at most this many Newton iterations lets the step grow
    max_cutbacks: int = 200


@dataclass(frozen=True)
class Leg:
    """What a continuation runs: ``constraint_of(value)`` is the model constraint at load value ``value``, ``end``
    the value to reach under ``control``; records get ``phase``; reasons start with ``name``. ``ends(record)`` may
    end the leg after a step with a status; ``step_limit(value)`` may cap the next step; a converged step for whose
    record ``rejects(record)`` gives a reason counts as a failed one (the step is cut back); a step that snapped
    through (``solver.snap_through``) for whose record ``vanishes(record)`` gives a reason ends the leg detached at
    the last state instead."""

    constraint_of: Callable[[float], object]
    end: float
    control: StepControl
    phase: Phase
    name: str
    ends: Callable[[StepRecord], Status | None] | None = None
    step_limit: Callable[[float], float] | None = None
    rejects: Callable[[StepRecord], str | None] | None = None
    seconds_per_unit: float = 0.0  # time (s) a unit change of the load value takes (0: no time passes)
    secant: bool = True  # predict from the last two converged states (False: start from the last one)
    stick_first: bool = False  # predict the leg's first step by a solve with every point in stick
    steady: Callable[[StepRecord, np.ndarray], bool] | None = None  # steady(record, state before the step)
    vanishes: Callable[[StepRecord], str | None] | None = None


@dataclass
class Loop:
    """The loop variables of a continuation between two steps: all it needs to go on."""

    value: float  # load parameter of the last converged state x
    step: float  # next step size (inf: steady, the next step goes to the next breakpoint or the end)
    x: np.ndarray
    x_prev: np.ndarray | None = None  # the converged state one step before x (secant predictor)
    value_prev: float = math.nan
    smallest: float = math.inf  # smallest step taken
    cutbacks: int = 0
    pending: list[float] = field(default_factory=list)  # breakpoints still ahead: steps end exactly on them
    snapped: bool = False  # the step to x snapped through: its change predicts no threshold (held_history)

    @classmethod
    def start(cls, x: np.ndarray, start: float, end: float, control: StepControl, breakpoints=()) -> Loop:
        direction = 1.0 if end >= start else -1.0
        tol = _tolerance(end)
        pending = sorted((b for b in breakpoints if direction * (b - start) > tol and direction * (end - b) >= -tol),
                         key=lambda b: direction * b)
        return cls(start, min(abs(control.first), control.maximum), x, pending=list(pending))


@dataclass(frozen=True)
class LegEnd:
    status: Status
    reason: str = ""


@dataclass
class Converged:
    """One converged step: its record, state, history after it, load parameter, and whether it ends the run."""

    record: StepRecord
    x: np.ndarray
    history: History
    value: float
    loop: Loop
    breakpoint: float | None = None  # the breakpoint this step landed on
    end: LegEnd | None = None  # set on the last step of the continuation


@dataclass(frozen=True)
class Notice:
    """What the path is doing between converged steps (a cut-back), for a progress display."""

    text: str


def _tolerance(end: float) -> float:
    return 1e-12 * max(1.0, abs(end))


def newton_options(model: CapModel) -> NewtonOptions:
    """Newton tolerances of the configuration."""
    s = model.params.solver
    return NewtonOptions(rtol=s.newton_rtol, atol=s.newton_atol, max_iterations=s.newton_max_iterations,
                         longest_step_max_growth=math.inf if s.longest_step_max_growth is None else s.longest_step_max_growth)


SNAP_HANDOVER = 1e-6  # the fall of the residual at which a snap's continuation first hands over to Newton
MAX_UZAWA = 30  # Uzawa updates of the pressure multiplier per step (nu = 0.5) before the step counts as failed


def solve_constrained(model: CapModel, constraint, history: History, x0: np.ndarray,
                      opts: NewtonOptions, dt: float = 0.0) -> tuple[NewtonResult, History]:
    """Newton from x0 on the cap's equations plus ``constraint`` (forces in E L0, r_ref = 1) at the end of a step
    of dt seconds from ``history``, and the history with the pressure multiplier it converged with: at nu = 0.5
    Newton runs again after each of Uzawa's updates of the multiplier until the volume constraint holds
    (fem.mixed). Iterations are summed over the runs."""
    def solve(hist: History, x: np.ndarray) -> NewtonResult:
        return newton(lambda z: model.residual(z, constraint, hist, dt), lambda z: model.linearize(z, constraint, hist, dt),
                      x, opts, r_ref=1.0, admissible=model.admissible)

    res = solve(history, x0)
    for _ in range(MAX_UZAWA):
        updated = model.updated_pressure(res.x, history) if res.converged else None
        if updated is None:
            return res, history
        history = updated
        res = _after(res, solve(history, res.x))
    if res.converged and model.updated_pressure(res.x, history) is not None:
        res.converged = False
        res.reason = f"volume constraint not met after {MAX_UZAWA} Uzawa updates"
    return res, history


def _after(first: NewtonResult, then: NewtonResult) -> NewtonResult:
    """``then`` with the iterations, linear iterations, residual norms and runs of ``first``, which ran before it
    in the same step, added."""
    then.iterations += first.iterations
    then.linear_iterations += first.linear_iterations
    then.residual_norms = first.residual_norms + then.residual_norms
    then.runs += first.runs
    return then


@dataclass(frozen=True)
class _Aim:
    """Where the next step goes: its length, its target value, whether it was shortened (to land on the end, a
    breakpoint or the step limit: ``loop.step`` is then kept) and whether it is a steady long step."""

    step: float
    target: float
    shortened: bool
    long_step: bool


def _aim(loop: Loop, leg: Leg, direction: float, tol: float) -> _Aim:
    """The next step from ``loop`` towards the leg's end, within its step limit and the next breakpoint."""
    step = min(loop.step, abs(leg.end - loop.value))
    if leg.step_limit is not None:
        step = max(min(step, leg.step_limit(loop.value)), leg.control.minimum)
    if loop.pending:
        step = min(step, abs(loop.pending[0] - loop.value))
    target = loop.value + direction * step
    if loop.pending and abs(target - loop.pending[0]) <= tol:
        target = loop.pending[0]
    return _Aim(step, target, step < loop.step, math.isinf(loop.step))


def _predicted(model: CapModel, loop: Loop, leg: Leg, target: float) -> np.ndarray:
    """The Newton start of a step to ``target``: the secant through the last two converged states (when the leg
    asks for it and the prediction is admissible), else the last state."""
    if leg.secant and loop.x_prev is not None and loop.value_prev != loop.value:
        x0 = loop.x + (loop.x - loop.x_prev) * ((target - loop.value) / (loop.value - loop.value_prev))
        if model.admissible(x0):
            return x0
    return loop.x


def _step_ratio(loop: Loop, target: float) -> float:
    """The step to ``target`` over the last converged step (0 when there is none)."""
    last = loop.value - loop.value_prev
    return (target - loop.value) / last if loop.x_prev is not None and last != 0.0 else 0.0


def held_history(model: CapModel, loop: Loop, history: History, target: float) -> History:
    """The friction history a step from ``loop.x`` to ``target`` holds (:meth:`CapModel.step_history`): with
    ``friction.threshold_at = step_predicted`` the thresholds extrapolated along the last converged step, except
    after a snap, whose jump is no rate of change: then the thresholds at x."""
    before = None if loop.snapped else loop.x_prev
    return model.step_history(history, loop.x, before, _step_ratio(loop, target))


def _solved_step(model: CapModel, loop: Loop, leg: Leg, history: History, target: float, opts: NewtonOptions,
                 dt: float, constraint) -> tuple[NewtonResult, History]:
    """Newton on the step to ``target``; a leg's first step with ``stick_first`` starts from its stick solution
    (whose iterations count in the step's)."""
    x0 = _predicted(model, loop, leg, target)
    stick = None
    if leg.stick_first and loop.x_prev is None:
        stick, _ = solve_constrained(model.sticking(), constraint, history, x0, opts, dt)
        x0 = stick.x if stick.converged else x0
    res, solved = solve_constrained(model, constraint, history, x0, opts, dt)
    return (res if stick is None else _after(stick, res)), solved


def _snapped_through(model: CapModel, loop: Loop, leg: Leg, history: History, target: float, opts: NewtonOptions,
                     dt: float, constraint) -> tuple[NewtonResult, History]:
    """The step to ``target`` by pseudo-transient continuation from the last state, then Newton from where it
    hands over (``solver.snap_through``, :mod:`capslide.loadpath.snap_through`): once the residual has fallen by
    SNAP_HANDOVER; where Newton fails from there, the continuation goes on to Newton's tolerance first."""
    tol = max(opts.atol, opts.rtol)
    early = PseudoTransient(handover=tol, relative_handover=SNAP_HANDOVER)
    transient = pseudo_transient(model, constraint, history, loop.x, dt, early)
    if not transient.converged:
        return transient, history
    res, solved = solve_constrained(model, constraint, history, transient.x, opts, dt)
    if res.converged or transient.residual_norms[-1] <= tol:
        return _after(transient, res), solved
    spent = _after(transient, res)
    rest = _after(spent, pseudo_transient(model, constraint, history, transient.x, dt, PseudoTransient(handover=tol)))
    if not rest.converged:
        return rest, history
    res, solved = solve_constrained(model, constraint, history, rest.x, opts, dt)
    return _after(rest, res), solved


def _snap_outcome(leg: Leg, aim: _Aim, rec: StepRecord | None, res: NewtonResult, failed: LegEnd,
                  reason: str) -> Notice | LegEnd:
    """After a snap-through: a notice when it found a state the leg goes on from; the leg's end detached when the
    leg says its contact vanished there (``leg.vanishes``); else the failed step's end, with the snap's reason."""
    if rec is None:
        return LegEnd(failed.status, f"{failed.reason}; snap-through: {reason}")
    gone = leg.vanishes(rec) if leg.vanishes is not None else None
    if gone is not None:
        return LegEnd(Status.DETACHED, f"{leg.name}: {gone}")
    return Notice(f"{leg.name}: snapped through at {aim.target:.4g} ({res.iterations} iterations)")


def _judged(model: CapModel, loop: Loop, leg: Leg, res: NewtonResult, solved: History, aim: _Aim, constraint,
            wall: float, dt: float, snapped: bool = False) -> tuple[StepRecord | None, str, bool]:
    """The record of a converged step, or None with the reason it counts as failed (no convergence, the leg's
    rejection, a long step that ended unsteady); and whether the steady rule still holds after it. A step that
    ``snapped`` through is not judged by the leg's rejections: a jump is what it is."""
    if not res.converged:
        return None, res.reason, False
    rec = measure(model, res.x, solved, leg.phase, constraint.ubar, res.iterations, res.linear_iterations, wall, dt)
    rec.steady_step, rec.snapped = aim.long_step, snapped
    still_steady = leg.steady is not None and leg.steady(rec, loop.x)
    rejected = leg.rejects(rec) if leg.rejects is not None and not snapped else None
    if rejected is None and aim.long_step and not still_steady:
        rejected = "not steady over the long step"
    return (None, rejected, still_steady) if rejected is not None else (rec, res.reason, still_steady)


def _cut_back(loop: Loop, leg: Leg, step: float, reason: str) -> LegEnd | Notice:
    """Halve the step after a failed one; the leg's end (diverged) past the cut-back budget or below the minimum
    step, else a notice."""
    control, name = leg.control, leg.name
    loop.cutbacks += 1
    loop.step = min(0.5 * step, control.maximum)
    if loop.cutbacks > control.max_cutbacks:
        return LegEnd(Status.DIVERGED, f"{name}: more than {control.max_cutbacks} cut-backs, stopped at "
                      f"{loop.value:.6g} ({reason})")
    if loop.step < control.minimum:
        return LegEnd(Status.DIVERGED, f"{name}: step below minimum {control.minimum:g} at {loop.value:.6g} "
                      f"({reason})")
    return Notice(f"{name}: cut-back {loop.cutbacks} at {loop.value:.4g}, step {loop.step:.3g} ({reason})")


def _advanced(loop: Loop, aim: _Aim, x: np.ndarray, snapped: bool = False) -> float | None:
    """Move ``loop`` to the converged state ``x`` at the aim's target (``snapped``: reached by a snap-through); the
    breakpoint it landed on, if any."""
    loop.x_prev, loop.value_prev = loop.x, loop.value
    loop.x, loop.value, loop.snapped = x, aim.target, snapped
    loop.smallest = min(loop.smallest, aim.step)
    if loop.pending and aim.target == loop.pending[0]:
        return loop.pending.pop(0)
    return None


def _next_step_size(loop: Loop, control: StepControl, aim: _Aim, res: NewtonResult, still_steady: bool) -> None:
    """After a converged step that does not end the leg: a steady slide goes on in long steps; an easy solve (at
    most ``easy_iterations`` per Newton run: Uzawa's runs each count) grows the step unless it was shortened."""
    if still_steady:
        loop.step = math.inf
    elif not aim.shortened and res.iterations <= control.easy_iterations * res.runs:
        loop.step = min(loop.step * control.growth, control.maximum)


def continuation(model: CapModel, loop: Loop, history: History,
                 leg: Leg) -> Generator[Converged | Notice, None, LegEnd]:
    """Continue ``loop`` to the end of ``leg`` from the friction ``history``; the steps as they converge, and a
    :class:`Notice` at every cut-back."""
    direction = 1.0 if leg.end >= loop.value else -1.0
    tol = _tolerance(leg.end)
    opts = newton_options(model)
    while direction * (leg.end - loop.value) > tol:
        aim = _aim(loop, leg, direction, tol)
        t0 = time.perf_counter()
        constraint = leg.constraint_of(aim.target)
        dt = leg.seconds_per_unit * abs(aim.target - loop.value)
        held = held_history(model, loop, history, aim.target)
        res, solved = _solved_step(model, loop, leg, held, aim.target, opts, dt, constraint)
        rec, reason, still_steady = _judged(model, loop, leg, res, solved, aim, constraint, time.perf_counter() - t0, dt)
        if rec is None:
            outcome = _cut_back(loop, leg, aim.step, reason)
            if isinstance(outcome, LegEnd) and loop.step < leg.control.minimum and model.params.solver.snap_through:
                if not res.converged:  # no equilibrium near the last: pseudo-transient continuation
                    res, solved = _snapped_through(model, loop, leg, held, aim.target, opts, dt, constraint)
                # a converged step the leg rejected (a jump that persists at the minimum step) stands as it is
                rec, reason, still_steady = _judged(model, loop, leg, res, solved, aim, constraint,
                                                    time.perf_counter() - t0, dt, snapped=True)
                outcome = _snap_outcome(leg, aim, rec, res, outcome, reason)
                loop.step = max(loop.step, leg.control.minimum)
            if isinstance(outcome, LegEnd):
                return outcome
            yield outcome
            if rec is None:
                continue
        landed = _advanced(loop, aim, res.x, rec.snapped)
        history = model.commit(loop.x, constraint.ubar, solved, dt)  # the history only at converged steps
        status = leg.ends(rec) if leg.ends is not None else None
        leg_end = LegEnd(status, f"{leg.name}: {status.label} at {loop.value:.6g}") if status is not None else None
        if leg_end is None:
            _next_step_size(loop, leg.control, aim, res, still_steady)
            if not direction * (leg.end - loop.value) > tol:
                leg_end = LegEnd(Status.COMPLETED)
        yield Converged(rec, loop.x, history, loop.value, loop, landed, leg_end)
        if leg_end is not None:
            return leg_end
    return LegEnd(Status.COMPLETED)


class Returning:
    """A generator of steps to loop over with ``for``; once the loop has run out, ``value`` is what the generator
    returned (its end)."""

    def __init__(self, steps: Generator):
        self.steps, self.value = steps, None

    def __iter__(self):
        self.value = yield from self.steps


def drain(steps: Generator, observe: Callable[[object], None] | None = None,
          notify: Callable[[Notice], None] | None = None):
    """Run a generator of steps to its end, calling ``observe(step)`` on each converged step and ``notify(notice)``
    on each notice; its return value."""
    run = Returning(steps)
    for step in run:
        callback = notify if isinstance(step, Notice) else observe
        if callback is not None:
            callback(step)
    return run.value
