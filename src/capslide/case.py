"""One case end to end: mesh, approach, preload, slide -> arrays and a status.

A thin driver over :mod:`capslide.loading`; no file IO here (see
:mod:`capslide.results`).
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from typing import Callable

import numpy as np

from .checkpoint import Checkpointer
from .loading import PathResult, StepRecord, run_load_path, sliding_onset
from .mesh import Mesh, cap_mesh, cap_mesh_spec
from .model import CapModel
from .params import Parameters

__all__ = ["Snapshot", "CaseResult", "run_case"]


@dataclass
class Snapshot:
    """Field state at one tangential displacement."""

    ubar: float
    u: np.ndarray  # (n_nodes, 2), L0
    I1_sigma: np.ndarray  # (n_cells,), E


@dataclass
class CaseResult:
    params: Parameters
    mesh: Mesh
    records: list[StepRecord]
    status: str
    reason: str
    scalars: dict[str, float]
    snapshots: list[Snapshot] = field(default_factory=list)
    cutbacks: int = 0
    min_step: float = float("nan")
    wall_time: float = 0.0
    final_x: np.ndarray | None = None  # last converged [u, h]


def run_case(params: Parameters, progress: Callable[[StepRecord], None] | None = None,
             mesh: Mesh | None = None, ckpt: Checkpointer | None = None) -> CaseResult:
    """Run one case; failures end with a status (``detached``, ``diverged``) and the last state.

    ``ckpt`` saves the running case every few steps, or continues a loaded
    checkpoint (see :mod:`capslide.checkpoint`).
    """
    t0 = time.perf_counter()
    mesh = mesh or cap_mesh(cap_mesh_spec(params))
    model = CapModel(mesh, params)
    snapshots: list[Snapshot] = ckpt.snapshots if ckpt is not None else []
    L = params.loading
    wanted = tuple(b for b in params.config["output"]["snapshot_ubar"]
                   if (0.0 <= b <= L.ubar_max) or (L.ubar_max <= b <= 0.0))

    def on_snapshot(ubar: float, x: np.ndarray) -> None:
        u = x[:-1]
        snapshots.append(Snapshot(ubar, u.reshape(-1, 2).copy(), model.bulk.cell_first_invariant(u)))

    res: PathResult = run_load_path(model, progress, wanted, on_snapshot, ckpt)
    wall = ckpt.wall_time() if ckpt is not None else time.perf_counter() - t0
    return CaseResult(params, mesh, res.records, res.status, res.reason, sliding_onset(res.records), snapshots,
                      res.cutbacks, res.min_step, wall, res.x)
