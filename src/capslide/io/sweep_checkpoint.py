"""Checkpoints of an edge-controlled verification sweep, so that ``capslide verify --resume`` continues a killed one.

The sweep (:func:`capslide.studies.verification.edge_controlled_sweep`) is saved where its arithmetic restarts
anyway: after the approach, after the equilibrium at each load, each load's leg starting from a fresh
factorization, and every ``verification.checkpoint_every`` converged steps inside a leg, where the sweep renews the
factorization in the uninterrupted run too. A save holds the state on the edge-controlled path (x and the edge
abscissa X), the step records so far, which record is each load's equilibrium and, inside a leg, the loop's
variables (:class:`capslide.loadpath.continuation.Loop`). It is one file beside the table, ``.NAME.csv.checkpoint.npz``,
signed like a case's state file (:func:`capslide.io.checkpoint.write_signed`: the version of the computing code, the
configuration's SHA-256, the arrays' checksums); any mismatch is a :class:`CheckpointError` and the sweep starts
afresh.
"""

from __future__ import annotations

import hashlib
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..loadpath.continuation import Loop
from ..loadpath.measures import StepRecord
from .checkpoint import CheckpointError, prefixed_record_arrays, read_guarded, read_signed, records_in, write_signed

__all__ = ["SavedSweep", "sweep_checkpoint_path", "save_sweep", "load_sweep"]


@dataclass
class SavedSweep:
    """Where an edge-controlled sweep stands: the path state (x, X), its records, and each done load's record."""

    x: np.ndarray  # displacements and the bordered variable
    X: float  # the edge abscissa (L0) of the edge-controlled path
    records: list[StepRecord]
    done: dict[float, int] = field(default_factory=dict)  # load P -> index of its equilibrium in records
    first: int = 0  # the first record of the edge-controlled path (after the approach's)
    loop: Loop | None = None  # inside a load's leg: its loop at (x, X); None between legs


def sweep_checkpoint_path(output: str | Path) -> Path:
    """``.NAME.checkpoint.npz`` beside the sweep's table ``output``."""
    output = Path(output)
    return output.with_name(f".{output.name}.checkpoint.npz")


def _config_sha(config_yaml: str) -> str:
    return hashlib.sha256(config_yaml.encode()).hexdigest()


def save_sweep(path: Path, config_yaml: str, saved: SavedSweep) -> None:
    """Write ``saved`` atomically, tied to the configuration text ``config_yaml``."""
    arrays = {"x": np.asarray(saved.x, dtype=float), **prefixed_record_arrays(saved.records)}
    header = {"kind": "verification sweep", "config_sha256": _config_sha(config_yaml), "X": float(saved.X),
              "done": [[float(P), int(i)] for P, i in saved.done.items()], "first": int(saved.first)}
    if saved.loop is not None:
        header["loop"] = _loop_header(saved.loop)
        if saved.loop.x_prev is not None:
            arrays["loop_x_prev"] = np.asarray(saved.loop.x_prev, dtype=float)
    write_signed(path, arrays, header)


def _loop_header(loop: Loop) -> dict:
    return {"step": float(loop.step), "value_prev": float(loop.value_prev), "smallest": float(loop.smallest),
            "cutbacks": int(loop.cutbacks), "pending": [float(b) for b in loop.pending], "snapped": bool(loop.snapped)}


def _loop_of(meta: dict, data: dict, x: np.ndarray, X: float) -> Loop | None:
    if "loop" not in meta:
        return None
    m = meta["loop"]
    return Loop(X, float(m["step"]), x, data.get("loop_x_prev"), float(m["value_prev"]), float(m["smallest"]),
                int(m["cutbacks"]), [float(b) for b in m["pending"]], bool(m.get("snapped", False)))


def load_sweep(path: Path, config_yaml: str) -> SavedSweep:
    """The sweep saved at ``path`` for this configuration, or CheckpointError saying why it cannot be used."""

    def load() -> SavedSweep:
        data, meta = read_signed(path, "sweep checkpoint", CheckpointError)
        if meta.get("kind") != "verification sweep":
            raise CheckpointError(f"sweep checkpoint '{path}' is not a verification sweep's")
        if meta.get("config_sha256") != _config_sha(config_yaml):
            raise CheckpointError(f"sweep checkpoint '{path}' was written for another configuration")
        records = records_in(data)
        X = float(meta["X"])
        done = {float(P): int(i) for P, i in meta["done"]}
        first = int(meta["first"])
        if any(not 0 <= i < len(records) for i in done.values()) or not 0 <= first <= len(records):
            raise CheckpointError(f"sweep checkpoint '{path}': a record index is out of range")
        return SavedSweep(data["x"], X, records, done, first, _loop_of(meta, data, data["x"], X))

    return read_guarded(load, path, "sweep checkpoint", CheckpointError)
