"""Checkpoints of a running case, so that ``capslide run --resume`` continues where a killed run stopped.

A checkpoint is one :class:`SavedCase`: the load path's state (:class:`capslide.loadpath.cap.PathState`: leg,
loop variables, current state, friction anchors, preload targets, last steps, totals), the step records and
field snapshots so far, and the wall time spent. It is written atomically beside the case file as a NumPy
``.npz`` archive read back without pickle (it cannot execute code), with the capslide version and the
configuration it was written for; a checkpoint of another version or configuration is refused.
"""

from __future__ import annotations

import json
import zipfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import yaml

from ..loadpath.cap import Mark, PathState
from ..loadpath.continuation import Loop
from ..loadpath.measures import RECORD_PROFILES, RECORD_SCALARS, Snapshot, StepRecord
from ..model.system import History
from ..states import Phase
from ..version import __version__
from .atomic import replacing

__all__ = ["SavedCase", "CheckpointError", "checkpoint_path", "config_text", "save_checkpoint", "load_checkpoint"]


class CheckpointError(ValueError):
    """A checkpoint that cannot be used for this run (the message says why)."""


@dataclass
class SavedCase:
    """Everything a resumed case needs: where the path stands and what it has produced."""

    state: PathState
    records: list[StepRecord]
    snapshots: list[Snapshot]
    elapsed: float  # wall time of the case before this process (s)


def checkpoint_path(output: str | Path) -> Path:
    """Where the checkpoint of the case file ``output`` lives: ``.<name>.checkpoint`` beside it."""
    output = Path(output)
    return output.with_name(f".{output.name}.checkpoint")


def config_text(config) -> str:
    """The configuration as the canonical YAML text a checkpoint is tied to."""
    return yaml.safe_dump(dict(config), sort_keys=True)


def _loop_meta(loop: Loop | None) -> dict | None:
    if loop is None:
        return None
    return {"value": loop.value, "step": loop.step, "value_prev": loop.value_prev, "smallest": loop.smallest,
            "cutbacks": loop.cutbacks, "pending": list(loop.pending)}


def save_checkpoint(path: Path, saved: SavedCase, config_yaml: str) -> None:
    """Write ``saved`` to ``path`` (atomically)."""
    s = saved.state
    meta = {"version": __version__, "config_yaml": config_yaml, "leg": s.leg, "loop": _loop_meta(s.loop),
            "targets": list(s.targets), "marks": [[int(m.phase), m.ubar, m.Fn, m.area_stick] for m in s.marks],
            "cutbacks": s.cutbacks, "smallest": s.smallest, "elapsed": saved.elapsed, "n_records": len(saved.records),
            "snapshot_ubar": [sn.ubar for sn in saved.snapshots]}
    arrays = {"meta": np.array(json.dumps(meta)), "x": s.x}
    if s.loop is not None:
        arrays["loop_x"] = s.loop.x
        if s.loop.x_prev is not None:
            arrays["loop_x_prev"] = s.loop.x_prev
    if s.history.anchors is not None:
        arrays["anchors"] = s.history.anchors
    for name in RECORD_SCALARS:
        arrays[f"record_{name}"] = np.array([getattr(r, name) for r in saved.records], dtype=float)
    for name in RECORD_PROFILES:
        arrays[f"record_{name}"] = np.array([getattr(r, name) for r in saved.records])
    if saved.snapshots:
        arrays["snapshot_u"] = np.stack([sn.u for sn in saved.snapshots])
        arrays["snapshot_I1"] = np.stack([sn.I1_sigma for sn in saved.snapshots])
    with replacing(path) as tmp, open(tmp, "wb") as fh:
        np.savez(fh, **arrays)


def _records(data, n: int) -> list[StepRecord]:
    out = []
    for i in range(n):
        kw = {name: float(data[f"record_{name}"][i]) for name in RECORD_SCALARS}
        kw["phase"] = Phase(int(kw["phase"]))
        kw["newton_iterations"] = int(kw["newton_iterations"])
        kw["krylov_iterations"] = int(kw["krylov_iterations"])
        kw.update({name: data[f"record_{name}"][i] for name in RECORD_PROFILES})
        out.append(StepRecord(**kw))
    return out


def load_checkpoint(path: Path, config_yaml: str) -> SavedCase:
    """Read a checkpoint written for the same configuration and capslide version (CheckpointError otherwise)."""
    try:
        with np.load(path, allow_pickle=False) as archive:
            data = {name: archive[name] for name in archive.files}
            meta = json.loads(str(data["meta"]))
            if meta.get("version") != __version__:
                raise CheckpointError(f"checkpoint '{path}' was written by capslide {meta.get('version')}, "
                                      f"this is {__version__}")
            if meta.get("config_yaml") != config_yaml:
                raise CheckpointError(f"checkpoint '{path}' was written for a different configuration")
            lm = meta["loop"]
            loop = None if lm is None else Loop(
                lm["value"], lm["step"], data["loop_x"], data["loop_x_prev"] if "loop_x_prev" in data else None,
                lm["value_prev"], lm["smallest"], lm["cutbacks"], list(lm["pending"]))
            state = PathState(meta["leg"], data["x"], History(data["anchors"] if "anchors" in data else None), loop,
                              list(meta["targets"]), [Mark(Phase(int(p)), u, F, a) for p, u, F, a in meta["marks"]],
                              meta["cutbacks"], meta["smallest"])
            snapshots = [Snapshot(u, data["snapshot_u"][k], data["snapshot_I1"][k])
                         for k, u in enumerate(meta["snapshot_ubar"])]
            return SavedCase(state, _records(data, meta["n_records"]), snapshots, meta["elapsed"])
    except CheckpointError:
        raise
    except (OSError, ValueError, KeyError, TypeError, zipfile.BadZipFile, json.JSONDecodeError) as err:
        raise CheckpointError(f"cannot read checkpoint '{path}': {err}") from None
