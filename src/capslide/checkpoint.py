"""Checkpoints of a running case, so that ``capslide run --resume`` continues where a killed run stopped.

The load path is a fixed sequence of continuation stages (approach, preload
targets, slide, slide back), numbered in the order they run. Every
``every`` converged steps the running stage's loop state is saved together
with everything the case has produced so far (step records, field
snapshots, friction anchors, the results of finished stages). A resumed run
replays the stage sequence: finished stages return their saved results, the
interrupted stage continues from its saved state, later stages run as usual.

The linear solver's reused factorization is renewed at every checkpoint in
the uninterrupted run as well, so a resumed run repeats the same arithmetic
and gives the same history (to round-off).

A checkpoint is a private file (pickle, written atomically next to the case
file) that is only read back by the same capslide version and configuration;
it is removed when the case file has been written.
"""

from __future__ import annotations

import pickle
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from . import __version__
from .atomic import replacing

__all__ = ["ContinuationState", "Checkpointer", "checkpoint_path", "CheckpointError"]


class CheckpointError(ValueError):
    """A checkpoint that cannot be used for this run (message says why)."""


@dataclass
class ContinuationState:
    """The loop variables of an adaptive continuation between two steps."""

    value: float
    step: float
    x: np.ndarray
    x_prev: np.ndarray | None
    value_prev: float | None
    smallest: float
    cutbacks: int
    pending: list[float]


def checkpoint_path(output: str | Path) -> Path:
    """Where the checkpoint of the case file ``output`` lives: ``.<name>.checkpoint`` beside it."""
    output = Path(output)
    return output.with_name(f".{output.name}.checkpoint")


@dataclass
class Checkpointer:
    """Saves the state of a running case every ``every`` converged steps; replays a loaded one."""

    path: Path | None
    config_yaml: str
    every: int = 0  # 0: never save
    records: list = field(default_factory=list)
    snapshots: list = field(default_factory=list)
    stage: int = -1  # index of the running stage
    finished: dict[int, tuple[str, str, int, float, np.ndarray]] = field(default_factory=dict)
    resume_stage: int = -1  # stage to continue (-1: a fresh run)
    resume_state: ContinuationState | None = None
    anchors: np.ndarray | None = None
    elapsed: float = 0.0  # wall time before this process (s)
    _t0: float = field(default_factory=time.perf_counter)
    _since: int = 0

    @classmethod
    def load(cls, path: Path, config_yaml: str, every: int) -> "Checkpointer":
        """Read a checkpoint written for the same configuration and capslide version."""
        try:
            with open(path, "rb") as f:
                data: dict[str, Any] = pickle.load(f)
        except (OSError, pickle.UnpicklingError, EOFError, AttributeError) as err:
            raise CheckpointError(f"cannot read checkpoint '{path}': {err}") from None
        if data.get("version") != __version__:
            raise CheckpointError(f"checkpoint '{path}' was written by capslide {data.get('version')}, this is {__version__}")
        if data.get("config_yaml") != config_yaml:
            raise CheckpointError(f"checkpoint '{path}' was written for a different configuration")
        return cls(path, config_yaml, every, records=data["records"], snapshots=data["snapshots"],
                   finished=data["finished"], resume_stage=data["stage"], resume_state=data["state"],
                   anchors=data["anchors"], elapsed=data["elapsed"])

    # -- replay -------------------------------------------------------------
    def begin_stage(self) -> tuple[int, str]:
        """Number the next stage; 'done' (finished before), 'resume' (interrupted) or 'run'."""
        self.stage += 1
        if self.stage in self.finished:
            return self.stage, "done"
        if self.stage == self.resume_stage:
            return self.stage, "resume"
        return self.stage, "run"

    def replaying(self) -> bool:
        """True while the next stage was already started before the interruption (its set-up is done)."""
        return self.stage + 1 <= self.resume_stage

    def end_stage(self, status: str, reason: str, cutbacks: int, smallest: float, x: np.ndarray) -> None:
        self.finished[self.stage] = (status, reason, cutbacks, smallest, x)

    # -- saving -------------------------------------------------------------
    def after_step(self, state_of, solver, anchors: np.ndarray | None) -> None:
        """Count a converged step; every ``every`` steps save ``state_of()`` and renew the solver's factors."""
        if not self.every or self.path is None:
            return
        self._since += 1
        if self._since < self.every:
            return
        self._since = 0
        solver.invalidate()  # the same renewal happens in every run: resumed runs repeat the arithmetic
        data = {"version": __version__, "config_yaml": self.config_yaml, "stage": self.stage, "state": state_of(),
                "finished": self.finished, "records": self.records, "snapshots": self.snapshots, "anchors": anchors,
                "elapsed": self.wall_time()}
        with replacing(self.path) as tmp, open(tmp, "wb") as f:
            pickle.dump(data, f, protocol=pickle.HIGHEST_PROTOCOL)

    def wall_time(self) -> float:
        return self.elapsed + time.perf_counter() - self._t0

    def remove(self) -> None:
        if self.path is not None:
            self.path.unlink(missing_ok=True)
