"""The Python interface: ``import capslide`` and use ``load_config``, ``run``, ``open_case``, ``open_cases``,
``config_of``.

    import capslide
    config = capslide.load_config("config/config.yaml", preset="fast", friction={"model": "EA", "s_cut": 0.0})
    case = capslide.run(config)                      # an xarray.Dataset in the layout of a case file
    case.Ft.plot(x="ubar")
    cube = capslide.open_cases("results/cases.nc")   # model x preload x step
    cube.sel(model="DI", preload=0.0).Ft.plot(x="ubar")
    capslide.config_of(cube, model="DI", preload=0.0)["friction"]   # the configuration of one case, a dict

Datasets keep attributes a netCDF file can hold, so ``case.to_netcdf(...)`` works on whatever these return.
"""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np
import xarray as xr
import yaml

from .config import flatten
from .config import load_config as _load_config
from .driver.case import run_case
from .io.cube import collect as _collect
from .io.reading import open_result, scale_and_unit
from .io.results import case_dataset
from .params import Parameters
from .states import Phase

__all__ = ["load_config", "run", "open_case", "open_cases", "config_of", "collect", "slide", "to_si"]


def load_config(*paths: str | Path, settings: Mapping[str, Any] | None = None, **overrides: Any) -> dict:
    """A validated configuration: the YAML files ``paths`` merged in order, then ``overrides`` (keyword per section
    or top-level key: ``preset="fast"``, ``friction={"s_cut": 0.5}``), then ``settings`` (dotted keys:
    ``{"friction.s_cut": 0.5}``). Raises :class:`capslide.config.ConfigError` (one line) when it is bad."""
    typed = flatten(overrides)
    typed.update(settings or {})
    return _load_config(paths, settings=typed)


def run(config: Mapping[str, Any], progress: bool = False) -> xr.Dataset:
    """Run one case of a validated configuration; its dataset in the layout of a case file (docs/data.md).

    ``progress=True`` shows a progress bar on a terminal (one line per step elsewhere). A case beyond ``limits``
    (mesh size, memory, steps) raises :class:`capslide.config.ConfigError` before anything is computed (the case
    driver checks it).
    """
    params = Parameters.from_config(config)
    observers = []
    if progress:
        from .cli.progress import ProgressDisplay

        observers.append(ProgressDisplay(params.loading))
    try:
        result = run_case(params, observers=observers)
    finally:
        for obs in observers:
            obs.close()
    return case_dataset(result, history="capslide.run (Python)")


def config_of(ds: xr.Dataset, model: str | None = None, preload: float | None = None) -> dict:
    """The validated configuration a case was computed with, parsed from its ``config_yaml``: of a case dataset, or
    of the case (``model``, ``preload``) of a collected one. KeyError when the collected dataset has no such case."""
    if "config_yaml" in ds.attrs:
        return yaml.safe_load(ds.attrs["config_yaml"])
    if model is None or preload is None:
        raise ValueError("a collected dataset holds many cases: name one by model and preload")
    try:
        text = str(ds["config_yaml"].sel(model=model, preload=preload).values)
    except KeyError:
        text = ""
    if not text:
        raise KeyError(f"no case of model {model!r} at preload {preload!r} in this dataset")
    return yaml.safe_load(text)


def open_case(path: str | Path) -> xr.Dataset:
    """A case file (``capslide run``) in memory; ResultFileError (one line) for anything else."""
    return open_result(path, "case")


def open_cases(path: str | Path) -> xr.Dataset:
    """A collected file (``capslide collect``, model x preload x step) in memory, with the labels of the flag
    variables ``status`` and ``slide_end`` as coordinates ``status_label`` and ``slide_end_label``."""
    ds = open_result(path, "cases")
    for name in ("status", "slide_end"):
        meanings = str(ds[name].attrs["flag_meanings"]).split()
        labels = [[meanings[v] if v >= 0 else "" for v in row] for row in ds[name].values.tolist()]
        ds = ds.assign_coords({f"{name}_label": (ds[name].dims, labels)})
    return ds


def collect(paths) -> xr.Dataset:
    """Case files (``{model}_Fn{preload:+.3f}.nc``) stacked into the model x preload x step cube, in memory (what
    ``capslide collect`` writes)."""
    return _collect([str(p) for p in paths], history="capslide.collect (Python)")


def slide(ds: xr.Dataset) -> xr.Dataset:
    """The forward slide of one case, indexed by ``ubar``: its slide steps up to the largest ubar (a slide back is
    left out), with ``ubar`` as the dimension, so that ``slide(case).sel(ubar=2.0, method="nearest")`` works. ``ds``:
    a case dataset, or one case of a cube (``cube.sel(model="DI", preload=0.0)``)."""
    if ds["phase"].ndim != 1:
        raise ValueError("slide() takes one case: select it from a cube first, e.g. cube.sel(model='DI', preload=0.0)")
    on = (ds["phase"] == int(Phase.SLIDE)).values
    steps = ds.isel(step=on)
    if steps.sizes["step"]:
        last = int(np.argmax(steps["ubar"].values))
        steps = steps.isel(step=slice(0, last + 1))
    return steps.swap_dims(step="ubar")


def to_si(ds: xr.Dataset) -> xr.Dataset:
    """``ds`` with every variable whose ``units`` is '<scale> <SI unit>' (capslide stores normalized values: Ft in
    units of '2 N/m' for the paper's E and L0) multiplied by its scale and its ``units`` set to the SI unit, which
    UDUNITS and pint both read: ``capslide.to_si(case).pint.quantify()`` (pint-xarray) gives pint quantities."""
    out = ds.copy()
    for name in [*ds.data_vars, *ds.coords]:
        parsed = scale_and_unit(ds[name].attrs.get("units", ""))
        if parsed is None or ds[name].dtype.kind not in "fiu":
            continue
        scale, unit = parsed
        converted = ds[name] * scale
        converted.attrs = {**ds[name].attrs, "units": unit}
        out[name] = converted
    return out
