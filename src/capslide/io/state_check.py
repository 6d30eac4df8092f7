"""The content of a saved path state (a checkpoint or a normal state), checked field by field before anything is
computed from it.

A checksum says that a file is the one written; it does not say that the writer wrote what this code reads. Two
checks do: :func:`check_header` and :func:`check_arrays` when the file is read (types, enum values, finiteness,
dimensions: no model needed), and :func:`shape_problem` once the model is built (every array against the model's
DOF, surface quadrature points and, with a viscoelastic bulk, its branches). A failure names the field in one
line (:class:`BadField`, a ValueError).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

import numpy as np

from ..loadpath.cap import LEGS
from ..loadpath.measures import RECORD_PROFILES, RECORD_PROFILES_3D, RECORD_SCALARS
from ..states import Phase, SlipState, Status

__all__ = ["SavedStateMismatch", "BadField", "check_header", "check_arrays", "check_record_arrays", "check_snapshot_arrays",
           "shape_problem"]

PATH_ARRAYS = ("x", "loop_x", "loop_x_prev", "anchors", "accumulated_slip", "frozen_thresholds", "pressure_multiplier",
               "viscous_networks", "viscous_c_inv")
INTEGER_SCALARS = ("phase", "newton_iterations", "krylov_iterations", "steady_step", "snapped")


class SavedStateMismatch(ValueError):
    """A saved state whose arrays do not fit the model it is to continue (the message names the file and field)."""


class BadField(ValueError):
    """A field of a saved state that this code cannot use; the message names it."""

    def __init__(self, field: str, problem: str):
        super().__init__(f"field '{field}' {problem}")


def _is_number(v: Any) -> bool:
    return isinstance(v, int | float) and not isinstance(v, bool)


def _number(meta: Mapping, key: str, where: str, *, finite: bool = False, minimum: float | None = None,
            integer: bool = False, optional: bool = False) -> None:
    v = meta.get(key)
    name = f"{where}{key}"
    if v is None and optional:
        return
    if not _is_number(v) or (integer and not (isinstance(v, int) or (isinstance(v, float) and v.is_integer()))):
        raise BadField(name, f"= {v!r} is not {'an integer' if integer else 'a number'}")
    if math.isnan(v) and (finite or minimum is not None):
        raise BadField(name, f"= {v!r} is not a finite number")
    if finite and not math.isfinite(v):
        raise BadField(name, f"= {v!r} is not a finite number")
    if minimum is not None and v < minimum:
        raise BadField(name, f"= {v!r} is below {minimum:g}")


def _finite_list(v: Any, name: str) -> None:
    if not isinstance(v, list) or not all(_is_number(t) and math.isfinite(t) for t in v):
        raise BadField(name, f"= {v!r} is not a list of finite numbers")


def _loop(lm: Any) -> None:
    if lm is None:
        return
    if not isinstance(lm, dict):
        raise BadField("loop", f"= {lm!r} is not a mapping")
    _number(lm, "value", "loop.", finite=True)
    _number(lm, "step", "loop.", minimum=0.0)  # inf: steady, the next step goes to the next stop
    _number(lm, "value_prev", "loop.")  # nan: no earlier step
    _number(lm, "smallest", "loop.", minimum=0.0)
    _number(lm, "cutbacks", "loop.", integer=True, minimum=0)
    _finite_list(lm.get("pending"), "loop.pending")
    if not isinstance(lm.get("snapped", False), bool):
        raise BadField("loop.snapped", f"= {lm['snapped']!r} is not true or false")


def _marks(marks: Any, name: str = "marks") -> None:
    if not isinstance(marks, list):
        raise BadField(name, f"= {marks!r} is not a list")
    for m in marks:
        if (not isinstance(m, list) or len(m) != 6 or not all(_is_number(v) for v in m)
                or m[0] not in {int(p) for p in Phase}):
            raise BadField(name, f"entry {m!r} is not [phase, ubar, Fn, area_stick, Ft, area]")


def check_header(meta: Any, kind: str) -> None:
    """The JSON header of a saved path state (``kind``: 'checkpoint' or 'normal state'); BadField otherwise."""
    if not isinstance(meta, dict):
        raise BadField("header", f"is a {type(meta).__name__}, not a mapping")
    if meta.get("leg") not in LEGS:
        raise BadField("leg", f"= {meta.get('leg')!r} is not one of {', '.join(LEGS)}")
    _loop(meta.get("loop"))
    _finite_list(meta.get("targets"), "targets")
    _marks(meta.get("marks"))
    _marks(meta.get("area_bracket", []), "area_bracket")
    _number(meta, "cutbacks", "", integer=True, minimum=0)
    _number(meta, "smallest", "", minimum=0.0)
    _number(meta, "stage_h", "", finite=True, optional=True)
    _number(meta, "time", "", finite=True, minimum=0.0)
    _number(meta, "onset_ceiling", "")
    _number(meta, "preload_Fn", "", finite=True, optional=True)
    _number(meta, "elapsed", "", finite=True, minimum=0.0)
    if kind == "normal state":
        if meta.get("status") not in {int(s) for s in Status} or isinstance(meta.get("status"), bool):
            raise BadField("status", f"= {meta.get('status')!r} is not a status")
        if not isinstance(meta.get("reason"), str):
            raise BadField("reason", f"= {meta.get('reason')!r} is not a text")
    if kind == "checkpoint":
        chunks = meta.get("chunks")
        if not isinstance(chunks, list) or not all(
                isinstance(c, dict) and _plain_name(c.get("file")) and c.get("kind") in ("records", "snapshots")
                and isinstance(c.get("sha256"), str) for c in chunks):
            raise BadField("chunks", f"= {chunks!r} is not a list of chunk entries (file names inside the checkpoint)")


def _plain_name(name: Any) -> bool:
    """A file name inside the checkpoint directory: no folder, not '.' or '..'."""
    return isinstance(name, str) and name not in ("", ".", "..") and "/" not in name and "\\" not in name


def _float_array(a: np.ndarray, name: str, ndim: int | None = None, finite: bool = True, integer: bool = False) -> None:
    if not (np.issubdtype(a.dtype, np.floating) or (integer and np.issubdtype(a.dtype, np.integer))):
        raise BadField(name, f"has dtype {a.dtype}, not float")
    if ndim is not None and a.ndim != ndim:
        raise BadField(name, f"has {a.ndim} dimensions, not {ndim}")
    if finite and not np.all(np.isfinite(a)):
        raise BadField(name, "holds values that are not finite")


def check_arrays(data: Mapping[str, np.ndarray], meta: Mapping) -> None:
    """The arrays of a saved path state: each known, float and finite; the states 1-D; those the header implies
    (the loop's states) present."""
    for name, a in data.items():
        if name.startswith("record_"):
            continue
        if name not in PATH_ARRAYS:
            raise BadField(name, "is not a field of a path state")
        _float_array(a, name, 1 if name in ("x", "loop_x", "loop_x_prev") else None)
    if "x" not in data:
        raise BadField("x", "is missing")
    if meta.get("loop") is not None and "loop_x" not in data:
        raise BadField("loop_x", "is missing (the header has a running leg)")
    if ("viscous_networks" in data) != ("viscous_c_inv" in data):
        raise BadField("viscous_c_inv" if "viscous_networks" in data else "viscous_networks", "is missing")


def check_snapshot_arrays(part: Mapping[str, np.ndarray]) -> None:
    """A chunk of field snapshots: ubar (n,), u (n, nodes, 2), I1_sigma (n, cells), float and finite; h (n,) and
    slip_state (n, points), friction states, where present (older files lack them)."""
    for name, ndim in (("ubar", 1), ("u", 3), ("I1_sigma", 2), ("h", 1), ("slip_state", 2)):
        if name not in part:
            if name in ("h", "slip_state"):
                continue
            raise BadField(f"snapshots.{name}", "is missing")
        if name == "slip_state":
            if not np.all(np.isin(part[name], [int(s) for s in SlipState])):
                raise BadField("snapshots.slip_state", "holds values that are not friction states")
            if len(part[name]) != len(part["ubar"]):
                raise BadField("snapshots.slip_state", f"has {len(part[name])} entries, not {len(part['ubar'])}")
            continue
        _float_array(part[name], f"snapshots.{name}", ndim, integer=name == "ubar")  # ubar as the config gives it
        if len(part[name]) != len(part["ubar"]):
            raise BadField(f"snapshots.{name}", f"has {len(part[name])} entries, not {len(part['ubar'])}")


def check_record_arrays(data: Mapping[str, np.ndarray], where: str = "") -> int:
    """The step records' arrays: each scalar 1-D and numeric with one length n, each profile (n, m); phases and
    counts valid. The number of records."""
    if "phase" not in data:
        raise BadField(f"{where}phase", "is missing")
    n = None
    for name in RECORD_SCALARS:
        if name not in data:
            if name in ("time", "steady_step", "snapped"):  # older files
                continue
            raise BadField(f"{where}{name}", "is missing")
        a = data[name]
        if not (np.issubdtype(a.dtype, np.floating) or np.issubdtype(a.dtype, np.integer)) or a.ndim != 1:
            raise BadField(f"{where}{name}", f"is not a 1-D numeric array (dtype {a.dtype}, shape {a.shape})")
        n = len(a) if n is None else n
        if len(a) != n:
            raise BadField(f"{where}{name}", f"has {len(a)} entries, not {n}")
        if name in INTEGER_SCALARS and not (np.all(np.isfinite(a)) and np.all(a == np.round(a)) and np.all(a >= 0)):
            raise BadField(f"{where}{name}", "holds values that are not counts")
    if not np.all(np.isin(data["phase"], [int(p) for p in Phase])):
        raise BadField(f"{where}phase", "holds values that are not phases")
    for name in RECORD_PROFILES:
        if name not in data:
            if name in RECORD_PROFILES_3D:  # older files: no y parts, which are empty in 2D
                continue
            raise BadField(f"{where}{name}", "is missing")
        a = data[name]
        if not np.issubdtype(a.dtype, np.number) or a.ndim != 2 or len(a) != n:
            raise BadField(f"{where}{name}", f"is not an ({n}, m) numeric array (dtype {a.dtype}, shape {a.shape})")
    return int(n or 0)


def _path_arrays(state) -> dict[str, np.ndarray | None]:
    loop, h = state.loop, state.history
    nets = h.networks
    return {"x": state.x, "loop_x": None if loop is None else loop.x, "loop_x_prev": None if loop is None else loop.x_prev,
            "anchors": h.anchors, "accumulated_slip": h.slip, "frozen_thresholds": h.thresholds,
            "pressure_multiplier": h.pressure,
            "viscous_networks": None if nets is None else nets.networks, "viscous_c_inv": None if nets is None else nets.c_inv}


def shape_problem(saved, shapes: Mapping[str, tuple[int, ...]]) -> str | None:
    """What in the saved case ``saved`` (a :class:`capslide.io.checkpoint.SavedCase`) does not fit the model whose
    array shapes are ``shapes`` (:meth:`capslide.model.system.CapModel.saved_shapes`: the path state's arrays,
    ``profile``/``reaction`` of a step record, ``snapshot_u``/``snapshot_I1_sigma``), as one line naming the field;
    None when everything fits."""
    arrays = _path_arrays(saved.state)
    for k, rec in enumerate(saved.records):
        arrays.update({f"records[{k}].{name}": getattr(rec, name) for name in RECORD_PROFILES})
    for k, sn in enumerate(saved.snapshots):
        arrays.update({f"snapshots[{k}].u": sn.u, f"snapshots[{k}].I1_sigma": sn.I1_sigma})
        if sn.slip_state.size:
            arrays[f"snapshots[{k}].slip_state"] = sn.slip_state
    for name, a in arrays.items():
        if a is None:
            continue
        key = name.split(".")[-1] if name.startswith(("records[", "snapshots[")) else name
        key = {"u": "snapshot_u", "I1_sigma": "snapshot_I1_sigma", "reaction": "reaction", "slip_state": "profile"}.get(
            key, ("profile_3d" if key in RECORD_PROFILES_3D else "profile") if name.startswith("records[") else key)
        if key not in shapes:
            return f"field '{name}' does not belong to this model"
        if tuple(np.shape(a)) != tuple(shapes[key]):
            return f"field '{name}' has shape {tuple(np.shape(a))}, this model needs {tuple(shapes[key])}"
    return None
