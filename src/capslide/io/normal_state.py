"""Normal states: a cap approached and preloaded, saved once and slid by every friction model (issue 19); a dwell
at the preload (``loading.dwell``) runs after the state, under the slide's normal control.

Friction acts from the slide on (docs/theory.md section 5): the approach and the preload of a case depend on its
configuration except the keys :data:`SLIDE_ONLY`, so the cases of a study that differ only in those keys share
them. The limits that refuse a configuration before computing (:data:`GUARDS`) never change a state, nor does
``limits.max_steps`` one that completed (a case over it ends at its next step), nor ``loading.ubar_max`` where it
does not size the mesh (the 3D sphere, or the 2D cap with a given ``mesh.band_half_width``).

A normal state file (``.npz``, read without pickle) holds the path state at the end of the preload
(:class:`capslide.loadpath.cap.PathState`), the step records up to there, the wall time spent, how the path ended
when the preload failed, and the *normal configuration* it was computed for (:func:`normal_config`): the
configuration without the slide-only keys (points in contact report ``frictionless`` before the slide, whatever
the friction law). With ``friction.active_from = contact`` friction acts through the approach and the preload, so
the friction keys belong to the normal configuration and each friction model preloads itself. A case starts from
the file only when its own normal configuration is the same; otherwise :func:`read_normal_state` names the first
key that differs.
"""

from __future__ import annotations

import json
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from ..config import SPHERE_ELEMENTS, flatten
from ..states import Status
from .checkpoint import (
    SavedCase,
    path_state,
    prefixed_record_arrays,
    read_guarded,
    read_signed,
    records_in,
    state_arrays,
    write_signed,
)
from .state_check import check_header

__all__ = ["SLIDE_ONLY", "GUARDS", "NormalStateError", "normal_config", "slide_only", "write_normal_state",
           "read_normal_state", "read_normal_state_at_any_preload"]

FORMAT = "capslide normal state 1"

# dotted keys (or sections, ending in '.') that act from the slide on: they change nothing before it
SLIDE_ONLY = ("friction.", "loading.slide_step", "loading.max_slide_step", "loading.min_slide_step",
              "loading.slide_growth_iterations",
              "loading.slide_back", "loading.stop_at_onset", "loading.readhesion_snap",
              "loading.normal_control", "loading.spring_stiffness",
              "loading.dwell", "output.snapshot_ubar", "study.")

# limits that refuse a configuration before any computation: a state computed under one holds under any other
GUARDS = ("limits.max_dofs", "limits.max_memory_gb", "limits.refuse_locking")


# the preload's target: the state at one target is the start of the path to another (loadpath.cap.continued_from)
PRELOAD_KEYS = ("loading.preload", "loading.preload_area", "loading.preload_area_rtol")


class NormalStateError(ValueError):
    """A normal state file that this case cannot start from (the message says why, in one line)."""


def slide_only(key: str) -> bool:
    """Whether the dotted configuration ``key`` acts only from the slide on."""
    return any(key.startswith(k) if k.endswith(".") else key == k for k in SLIDE_ONLY)


def _number_as_float(value: Any) -> Any:
    """1 and 1.0 are the same setting (YAML and --set write either)."""
    if isinstance(value, int) and not isinstance(value, bool):
        return float(value)
    if isinstance(value, list):
        return [_number_as_float(v) for v in value]
    return value


def _belongs(key: str, flat: Mapping[str, Any], completed: bool) -> bool:
    """Whether ``key`` of the flat configuration ``flat`` can change the approach and preload (``completed``:
    of a path that completed, which no step limit stopped)."""
    if slide_only(key):
        return flat.get("friction.active_from") == "contact" and key.startswith("friction.")
    if key == "loading.ubar_max":  # it sizes the 2D cap's default band only (model.build.cap_mesh_spec)
        return flat.get("mesh.element") not in SPHERE_ELEMENTS and flat.get("mesh.band_half_width") is None
    return key not in GUARDS and not (completed and key == "limits.max_steps")


def normal_config(config: Mapping, completed: bool = True) -> dict[str, Any]:
    """Dotted key -> value of the configuration the approach and preload depend on (numbers as floats); with
    ``friction.active_from = contact`` friction acts before the slide, and every friction key belongs to it.
    ``completed``: the configuration of a normal path that completed, for which ``limits.max_steps`` does not
    count; a path that ended otherwise may have ended on it."""
    flat = flatten(config)
    return {k: _number_as_float(v) for k, v in flat.items() if _belongs(k, flat, completed)}


def _text(normal: Mapping[str, Any]) -> str:
    return json.dumps(normal, sort_keys=True)


def write_normal_state(path: str | Path, saved: SavedCase, config: Mapping) -> None:
    """Write the normal state ``saved`` (records, path state, wall time, ``ended``) computed for ``config``."""
    arrays, state = state_arrays(saved.state)
    arrays.update(prefixed_record_arrays(saved.records))
    status, reason = saved.ended if saved.ended is not None else (Status.COMPLETED, "")
    normal = normal_config(config, completed=status == Status.COMPLETED)
    write_signed(Path(path), arrays, {"format": FORMAT, "normal_config": _text(normal), **state,
                                      "elapsed": saved.elapsed, "status": int(status), "reason": reason})


def _first_difference(saved: Mapping[str, Any], own: Mapping[str, Any]) -> str:
    """The first key whose value differs; friction.active_from first, which decides whether the friction keys
    belong to the normal configuration at all (absent: 'slide', its default)."""
    absent = {"friction.active_from": "slide"}
    for key in sorted(set(saved) | set(own) | set(absent), key=lambda k: (k != "friction.active_from", k)):
        there, here = saved.get(key, absent.get(key)), own.get(key, absent.get(key))
        if there != here:
            return f"{key} = {there!r} there, {here!r} here"
    return "none"


def _load(path: Path, config: Mapping, any_preload: bool) -> tuple[SavedCase, float]:
    data, meta = read_signed(path, "normal state", NormalStateError)
    if not isinstance(meta, dict) or meta.get("format") != FORMAT:
        raise NormalStateError(f"'{path}' is not a normal state file ({FORMAT})")
    check_header(meta, "normal state")
    completed = Status(meta["status"]) == Status.COMPLETED
    theirs, own = json.loads(meta["normal_config"]), normal_config(config, completed)
    preload = float(theirs["loading.preload"])
    if any_preload:  # the preload's target: a force, or a contact area
        for key in PRELOAD_KEYS:
            own.pop(key, None)
            if key in theirs:
                own[key] = theirs[key]
    if _text(theirs) != _text(own):
        raise NormalStateError(f"normal state '{path}' was computed for another configuration "
                               f"({_first_difference(theirs, own)})")
    records = records_in(data)
    status = Status(meta["status"])
    ended = None if status == Status.COMPLETED else (status, meta["reason"])
    return SavedCase(path_state(data, meta), records, [], meta["elapsed"], ended, f"normal state '{path}'"), preload


def _read(path: str | Path, config: Mapping, any_preload: bool) -> tuple[SavedCase, float]:
    path = Path(path)
    if path.is_dir():
        raise NormalStateError(f"normal state '{path}' is a directory")
    if not path.is_file():
        raise NormalStateError(f"normal state '{path}' does not exist")
    return read_guarded(lambda: _load(path, config, any_preload), path, "normal state", NormalStateError)


def read_normal_state(path: str | Path, config: Mapping) -> SavedCase:
    """The normal state in ``path``, checked against the normal configuration of ``config``; NormalStateError
    (one line) when the file is damaged, foreign or for another configuration."""
    return _read(path, config, any_preload=False)[0]


def read_normal_state_at_any_preload(path: str | Path, config: Mapping) -> tuple[SavedCase, float]:
    """The normal state in ``path`` and the preload Fn* it was computed for, checked against the normal
    configuration of ``config`` at that preload (a path that may go on to ``config``'s own preload)."""
    return _read(path, config, any_preload=True)
