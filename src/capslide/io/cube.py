"""All cases of a study as one cube over ``model`` x ``preload`` x ``step`` (docs/data.md).

The model names are the study's (``DI``, ``EA1``, ``EA0``: the part of a case file's name before ``_Fn``); the
configuration keys that tell the models apart (``friction.model``, ``friction.s_cut``, ...) become coordinates
along ``model`` (``friction_model``, ``s_cut``: NaN for non-EA models, where it means nothing). Absent cases and the
steps past a case's end are NaN (integers and flags: -1). Step quantities keep their coordinates (``ubar``, ``h``,
``phase`` over model x preload x step), so ``cube.sel(model="DI", preload=0.0).Ft.plot(x="ubar")`` works. Surface
profiles and field snapshots stay in the case files.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import xarray as xr
import yaml

from ..config import flatten
from ..states import Status, flag_attributes
from .reading import ResultFileError, open_result
from .results import CASE_SCALARS, STEP_COORDINATES, STEP_VARIABLES, global_attrs, key_parameters, quantity

__all__ = ["collect", "model_name"]


def model_name(path: str | Path) -> str:
    """The study model of a case file: ``DI`` for ``DI_Fn+0.000.nc`` (the whole stem if it has no ``_Fn``)."""
    stem = Path(path).stem
    return stem.split("_Fn")[0] if "_Fn" in stem else stem


def _configs(cases: list[xr.Dataset]) -> list[dict]:
    return [flatten(yaml.safe_load(c.attrs["config_yaml"])) for c in cases]


def collect(paths, history: str | None = None) -> xr.Dataset:
    """Stack case files into the model x preload x step cube."""
    cases = [open_result(p, "case") for p in paths]
    models = list(dict.fromkeys(model_name(p) for p in paths))
    configs = _configs(cases)
    preloads = sorted({float(c["loading.preload"]) for c in configs})
    where = {}
    for path, c in zip(paths, configs):
        key = (model_name(path), float(c["loading.preload"]))
        if key in where:
            raise ResultFileError(f"'{path}' and '{paths[where[key]]}' are both model {key[0]} at preload {key[1]:g}")
        where[key] = len(where)
    shape, n_steps = (len(models), len(preloads)), max(c.sizes["step"] for c in cases)

    def cube(name: str, per_case) -> tuple[np.ndarray, np.dtype]:
        first = cases[0][name]
        integer = np.issubdtype(first.dtype, np.integer)
        arr = np.full(shape + np.shape(per_case(0)), -1 if integer else np.nan, dtype=first.dtype if integer else float)
        for (m, f), i in where.items():
            arr[models.index(m), preloads.index(f)] = per_case(i)
        return arr

    def padded(name: str):
        return lambda i: np.concatenate([cases[i][name].values, np.full(n_steps - cases[i].sizes["step"],
                                                                         -1 if cases[i][name].dtype.kind == "i" else np.nan)])

    dims3 = ("model", "preload", "step")
    present = lambda names: [n for n in names if all(n in c.variables for c in cases)]  # noqa: E731 (time: with a velocity)
    _check_units(paths, cases, present([*STEP_VARIABLES, *CASE_SCALARS, *STEP_COORDINATES]))
    data = {name: (dims3, cube(name, padded(name)), dict(cases[0][name].attrs)) for name in present(STEP_VARIABLES)}
    data.update({name: (("model", "preload"), cube(name, lambda i, n=name: float(cases[i][n])),
                        dict(cases[0][name].attrs)) for name in CASE_SCALARS})
    status = np.full(shape, -1, dtype=np.int8)
    slide_end = np.full(shape, -1, dtype=np.int8)
    n_case_steps = np.zeros(shape, dtype=np.int32)
    case_file = np.full(shape, "", dtype=object)
    config_yaml = np.full(shape, "", dtype=object)
    for (m, f), i in where.items():
        at = (models.index(m), preloads.index(f))
        status[at] = Status.from_label(cases[i].attrs["status"])
        slide_end[at] = int(bool(configs[i]["loading.stop_at_onset"]))
        n_case_steps[at] = cases[i].sizes["step"]
        case_file[at] = str(paths[i])
        config_yaml[at] = cases[i].attrs["config_yaml"]
    data.update({
        "status": (("model", "preload"), status, flag_attributes(Status, "final status (-1: no case)")),
        "slide_end": (("model", "preload"), slide_end,
                      {"long_name": "where the slide ends", "units": "1",
                       "description": "where the slide was set to end (loading.stop_at_onset; -1: no case)",
                       "flag_values": np.array([0, 1], dtype=np.int8), "flag_meanings": "ubar_max onset"}),
        "n_steps": (("model", "preload"), n_case_steps, quantity("number of converged steps of the case", "1")),
        "case_file": (("model", "preload"), case_file, quantity("source case file", None)),
        "config_yaml": (("model", "preload"), config_yaml, quantity("configuration of the case (YAML)", None)),
    })
    coords = {name: (dims3, cube(name, padded(name)), dict(cases[0][name].attrs)) for name in present(STEP_COORDINATES)}
    coords.update({
        "model": ("model", np.array(models, dtype=object), quantity("study model", None, description="a model of study.models")),
        "preload": ("preload", np.array(preloads), quantity("preload Fn*", cases[0]["Fn"].attrs["units"],
                                                            "E L0 W", "target normal force, positive = tensile")),
        "step": ("step", np.arange(n_steps, dtype=np.int32), quantity("converged load step", "1")),
    })
    coords.update(_model_coordinates(paths, models, configs))
    out = xr.Dataset({k: xr.Variable(*v) for k, v in data.items()}, coords={k: xr.Variable(*v) for k, v in coords.items()})
    for name, var in out.variables.items():
        if var.dtype.kind == "i" and var.ndim > 1:
            out[name].encoding["_FillValue"] = -1
    common = {k: v for k, v in configs[0].items() if all(c.get(k) == v for c in configs)}
    out.attrs.update(global_attrs(None, "capslide: all cases of a study", history))
    out.attrs.update({k: v for k, v in key_parameters(common).items() if k != "loading_preload"})
    out.attrs["n_cases"] = len(cases)
    return out


def _check_units(paths, cases: list[xr.Dataset], names: list[str]) -> None:
    """The cube keeps the first case's units, so every case must have them (the scales E L0 and E L0^2 differ
    with geometry.L0, material.E and the dimension): a ResultFileError naming the first variable that differs."""
    for name in names:
        first = cases[0][name].attrs.get("units")
        for path, case in zip(paths[1:], cases[1:]):
            units = case[name].attrs.get("units")
            if units != first:
                raise ResultFileError(f"'{path}' has {name} in {units!r}, '{paths[0]}' in {first!r}: the cases of one "
                                      "cube share their units (geometry.L0, material.E, 2D or 3D)")


def _model_coordinates(paths, models: list[str], configs: list[dict]) -> dict:
    """friction.model, friction.s_cut and the other friction keys that differ between models (and not within one),
    as coordinates along ``model``."""
    by_model = {m: [c for p, c in zip(paths, configs) if model_name(p) == m] for m in models}
    out = {}
    for key in configs[0]:
        if not key.startswith("friction."):
            continue
        values = [by_model[m][0].get(key) for m in models]
        if len({repr(v) for v in values}) < 2 and key not in ("friction.model", "friction.s_cut"):
            continue
        if any(len({repr(c.get(key)) for c in by_model[m]}) > 1 for m in models):
            continue  # varies within a model: not a property of the model
        name = "friction_model" if key == "friction.model" else key.split(".", 1)[1]
        if key == "friction.s_cut":  # meaningful for EA only
            values = [v if by_model[m][0]["friction.model"] == "EA" else np.nan for v, m in zip(values, models)]
        out[name] = ("model", np.array(values, dtype=object if isinstance(values[0], str) else float),
                     quantity(f"{key} of the model"[:40], None if isinstance(values[0], str) else "1"))
    return out
