"""Observers of a running case: each sees every converged step in order, and may end the case there.

The driver (:mod:`capslide.driver.case`) calls ``step(step)`` on each observer in turn; an observer that returns a
:class:`Stop` ends the case at that step (the observers after it do not see the step). ``end(end)`` may restate
how the case ended once the load path has stopped.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

from ..io.checkpoint import CheckpointWriter, SavedCase
from ..loadpath.cap import PathEnd, PathState, PathStep
from ..loadpath.continuation import Notice
from ..loadpath.legs import LegName
from ..loadpath.measures import Snapshot, StepRecord, field_snapshot, fully_sliding, peeling_off
from ..model.system import CapModel
from ..states import Phase, Status

__all__ = ["Stop", "Observer", "Recorder", "Snapshots", "OnsetStop", "PeelOff", "Snap", "StepBudget", "Checkpointing",
           "Clock", "AfterSteps"]


@dataclass(frozen=True)
class Stop:
    status: Status
    reason: str


class Observer:
    """Base class: sees every converged step and notice; ends nothing, restates nothing."""

    def step(self, step: PathStep) -> Stop | None:
        return None

    def notice(self, notice: Notice) -> None:
        """What the case is doing between steps (building the mesh, a cut-back)."""

    def end(self, end: PathEnd) -> PathEnd:
        return end


class Recorder(Observer):
    """Keeps every step record in ``records``."""

    def __init__(self, records: list[StepRecord]):
        self.records = records

    def step(self, step):
        self.records.append(step.record)


class Snapshots(Observer):
    """Field snapshots at the slide positions ``wanted`` (L0): the slide's steps land on them; ubar = 0 is the
    preloaded state the slide starts from."""

    def __init__(self, model: CapModel, wanted, snapshots: list[Snapshot]):
        self.model, self.snapshots = model, snapshots
        self.at_start = any(b == 0.0 for b in wanted)
        self._last: tuple | None = None  # the last converged state and its history

    def begin(self, state: PathState) -> None:
        """Take the snapshot at ubar = 0 now when the path starts where the slide starts (a normal state), unless
        it was taken before (a checkpoint saved there)."""
        self._last = (state.x, state.history)
        if self._starts_slide(state) and not any(sn.ubar == 0.0 for sn in self.snapshots):
            self.snapshots.append(field_snapshot(self.model, state.x, 0.0, state.history))

    def end(self, end):
        """A path without a slide (loading.ubar_max = 0, the 3D normal contact) that completed: its last state is
        the preloaded one that ubar = 0 stands for."""
        if (self.at_start and end.status == Status.COMPLETED and self.model.params.loading.ubar_max == 0.0
                and self._last is not None and not any(sn.ubar == 0.0 for sn in self.snapshots)):
            self.snapshots.append(field_snapshot(self.model, self._last[0], 0.0, self._last[1]))
        return end

    def _starts_slide(self, state: PathState) -> bool:
        return self.at_start and state.leg == LegName.SLIDE and state.loop is None

    def step(self, step):
        self._last = (step.x, step.state.history)
        if self._starts_slide(step.state):  # this state starts the slide
            self.snapshots.append(field_snapshot(self.model, step.x, 0.0, step.state.history))
        if step.breakpoint is not None:
            self.snapshots.append(field_snapshot(self.model, step.x, step.breakpoint, step.state.history,
                                                 step.record.slip_state))


class OnsetStop(Observer):
    """Ends the case at the onset of full sliding (``loading.stop_at_onset``)."""

    def step(self, step):
        if fully_sliding(step.record):
            return Stop(Status.COMPLETED, f"slide: stopped at the onset of full sliding, ubar = {step.record.ubar:.6g}")


class PeelOff(Observer):
    """A slide that found no equilibrium under a tensile load while the contact peeled ends detached, not diverged
    (shear-induced pull-off, :func:`capslide.loadpath.measures.peeling_off`)."""

    def __init__(self, records: list[StepRecord], Fn: float | None):
        self.records, self.Fn = records, Fn  # Fn None: the force the preload reached (a preload to an area)

    def _held(self) -> float:
        if self.Fn is not None:
            return self.Fn
        preloaded = [r.Fn for r in self.records if r.phase == Phase.PRELOAD]
        return preloaded[-1] if preloaded else math.nan

    def end(self, end):
        Fn = self._held()
        if end.status != Status.DIVERGED or end.leg != LegName.SLIDE or not peeling_off(self.records, Fn):
            return end
        last = self.records[-1]
        reason = (f"slide: no equilibrium at Fn = {Fn:.6g} beyond ubar = {last.ubar:.6g}; the contact was peeling "
                  f"off (area {last.area:.4g}, shrinking, h rising)")
        return PathEnd(Status.DETACHED, reason, end.x, end.cutbacks, end.min_step, end.leg)


class AfterSteps(Observer):
    """Calls ``action()`` once, after ``n`` converged steps (a deterministic interruption for tests)."""

    def __init__(self, n: int, action):
        self.n, self.action, self.seen = n, action, 0

    def step(self, step):
        self.seen += 1
        if self.seen == self.n:
            self.action()


class Snap(Observer):
    """With slip weakening (``weakening`` = (static/kinetic, D_c), None without), a slide that finds no equilibrium
    has snapped: the friction force falls faster than the cap unloads, and no quasi-static path goes on (a
    dynamic slip event). The case ends snapped at the last converged ubar; it never hangs (the step control's
    minimum step and cut-back budget end the search)."""

    def __init__(self, records: list[StepRecord], weakening: tuple[float, float] | None):
        self.records, self.weakening = records, weakening

    def end(self, end):
        if self.weakening is None or end.status != Status.DIVERGED or end.leg != LegName.SLIDE:
            return end
        last = self.records[-1]
        peak = max((abs(r.Ft) for r in self.records if r.phase == last.phase), default=abs(last.Ft))
        reason = (f"{end.leg}: snapped at ubar = {last.ubar:.6g}, no quasi-static equilibrium beyond it (slip weakening, "
                  f"static/kinetic = {self.weakening[0]:g}; |Ft| = {abs(last.Ft):.6g}, peak {peak:.6g}): {end.reason}")
        return PathEnd(Status.SNAPPED, reason, end.x, end.cutbacks, end.min_step, end.leg)


class StepBudget(Observer):
    """Ends the case as diverged once it has more than ``limit`` converged steps (``limits.max_steps``): the cost of a
    case is bounded even where no estimate foresaw it (a preload's range is known only once the approach ends)."""

    def __init__(self, records: list[StepRecord], limit: int):
        self.records, self.limit = records, limit

    def step(self, step):
        if len(self.records) > self.limit:
            return Stop(Status.DIVERGED, f"{step.state.leg}: more than limits.max_steps = {self.limit} steps, stopped at "
                                         f"ubar = {step.record.ubar:.6g}, Fn = {step.record.Fn:.6g} (raise the limit or "
                                         f"the step sizes)")
        return None


class Clock:
    """Wall time of a case over interruptions: ``elapsed`` seconds before this process, plus this process's."""

    def __init__(self, elapsed: float = 0.0):
        self.elapsed, self._t0 = elapsed, time.perf_counter()

    def __call__(self) -> float:
        return self.elapsed + time.perf_counter() - self._t0


class Checkpointing(Observer):
    """Saves the case with ``writer`` every ``every`` converged steps.

    The model's linear solver renews its factorization at every save, in the uninterrupted run as well, so that a
    resumed run repeats the same arithmetic and gives the same history.
    """

    def __init__(self, writer: CheckpointWriter, every: int, model: CapModel, records: list[StepRecord],
                 snapshots: list[Snapshot], clock: Clock):
        self.writer, self.every, self.model = writer, every, model
        self.records, self.snapshots, self.clock = records, snapshots, clock

    def step(self, step):
        if not self.every or step.last or len(self.records) % self.every:
            return None  # saves at every multiple of ``every`` converged steps of the case, however it started
        self.model.solver.invalidate()
        self.writer.save(SavedCase(step.state, self.records, self.snapshots, self.clock()))
        return None
