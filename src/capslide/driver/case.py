"""One case end to end: parameters -> model -> the load path observed -> a :class:`CaseResult` with a status.

No file is written here except the checkpoints a caller asks for (see :mod:`capslide.io.results` for the case
file). Observers record the steps, take field snapshots, stop at the onset of full sliding when asked, restate a
shear-induced pull-off, show progress (the caller's) and save checkpoints, in that order.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

from ..fem.mesh import Mesh
from ..io.checkpoint import CheckpointWriter, SavedCase
from ..io.state_check import SavedStateMismatch, shape_problem
from ..loadpath.cap import PathEnd, PathState, after_normal_state, initial_state, load_path
from ..loadpath.continuation import Notice, Returning
from ..loadpath.measures import Snapshot, StepRecord, sliding_onset
from ..model import cost
from ..model.build import build_model, mesh_spec
from ..params import Parameters
from ..states import Status
from .observers import Checkpointing, Clock, Observer, OnsetStop, PeelOff, Recorder, Snap, Snapshots, StepBudget

__all__ = ["CaseResult", "run_case", "snapshot_positions"]


@dataclass
class CaseResult:
    params: Parameters
    mesh: Mesh
    records: list[StepRecord]
    status: Status
    reason: str
    scalars: dict[str, float]
    snapshots: list[Snapshot] = field(default_factory=list)
    cutbacks: int = 0
    min_step: float = float("nan")
    wall_time: float = 0.0
    final_x: np.ndarray | None = None  # last converged [u, h]
    state: PathState | None = None  # where the path stands at the end (load_path(start=state) goes on)


def snapshot_positions(params: Parameters) -> tuple[float, ...]:
    """The ``output.snapshot_ubar`` values the slide reaches (between 0 and ubar_max)."""
    L = params.loading
    return tuple(b for b in params.output.snapshot_ubar
                 if (0.0 <= b <= L.ubar_max) or (L.ubar_max <= b <= 0.0))


def run_case(params: Parameters, mesh: Mesh | None = None, observers: Sequence[Observer] = (),
             checkpoint: CheckpointWriter | None = None, checkpoint_every: int | None = None,
             resume: SavedCase | None = None, stop_before: str = "done", checked: cost.Cost | None = None) -> CaseResult:
    """Run one case; failures end with a status (detached, diverged) and the last converged state.

    ``observers`` see every converged step (progress, for example). With a ``checkpoint`` writer the case is saved
    every ``checkpoint_every`` steps (default ``output.checkpoint_every``); ``resume`` continues a saved case (a
    checkpoint, or a normal state: a saved path that ended there ends the case the same way). The path stops
    before the leg ``stop_before`` (``"dwell"``: a normal state). A configuration beyond ``limits`` is refused
    before anything is computed (ConfigError, see :mod:`capslide.model.cost`), as is a ``resume`` whose arrays do not
    fit the model (SavedStateMismatch naming the file and field), and a case that takes more than
    ``limits.max_steps`` steps ends diverged. ``checked``: the estimate of a caller that ran the check already
    (the command line checks before it writes anything), so that it runs once.
    """
    if mesh is None:
        estimate = checked if checked is not None else cost.check(params, mesh_spec(params))
        for obs in observers:
            obs.notice(Notice(f"building the mesh: {estimate.cells:,} {params.mesh.element} cells, {estimate.dofs:,} DOF"))
    else:
        cost.check_steps(params)
    model = build_model(params, mesh)
    if resume is not None and (problem := shape_problem(resume, model.saved_shapes())) is not None:
        raise SavedStateMismatch(f"{resume.source or 'saved state'}: {problem}")  # before anything is computed
    wanted = snapshot_positions(params)
    records = list(resume.records) if resume is not None else []
    snapshots = list(resume.snapshots) if resume is not None else []
    clock = Clock(resume.elapsed if resume is not None else 0.0)
    snapshot_taker = Snapshots(model, wanted, snapshots)
    held = params.loading.preload if params.loading.preload_area is None else None  # None: the force reached
    watching: list[Observer] = [Recorder(records), snapshot_taker, *observers,
                                PeelOff(records, held), Snap(records, params.friction.weakening),
                                StepBudget(records, params.limits.max_steps)]
    if params.loading.stop_at_onset:
        watching.append(OnsetStop())
    if checkpoint is not None:
        every = params.output.checkpoint_every if checkpoint_every is None else checkpoint_every
        watching.append(Checkpointing(checkpoint, every, model, records, snapshots, clock))
    state = after_normal_state(model, resume.state) if resume is not None else initial_state(model)
    if resume is not None and resume.ended is not None:
        end = PathEnd(*resume.ended, state.x, *state.totals(), state.leg)
    else:
        snapshot_taker.begin(state)
        end = _observe(load_path(model, wanted, start=state, stop_before=stop_before), watching)
    for obs in watching:
        end = obs.end(end)
    return CaseResult(params, model.mesh, records, end.status, end.reason, sliding_onset(records), snapshots,
                      end.cutbacks, end.min_step, clock(), end.x, state)


def _observe(path, observers: Sequence[Observer]) -> PathEnd:
    """Feed every step of ``path`` to the observers until the path ends or one of them stops it."""
    run = Returning(path)
    for step in run:
        if isinstance(step, Notice):
            for obs in observers:
                obs.notice(step)
            continue
        for obs in observers:
            stop = obs.step(step)
            if stop is not None:
                path.close()
                return PathEnd(stop.status, stop.reason, step.x, *step.state.totals(), step.state.leg)
    return run.value
