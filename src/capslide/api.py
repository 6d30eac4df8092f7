"""The Python interface: ``import capslide`` and use ``load_config``, ``run``, ``open_case``, ``open_cases``.

    import capslide
    config = capslide.load_config("config/config.yaml", preset="fast", friction={"model": "EA", "s_cut": 0.0})
    case = capslide.run(config)                      # an xarray.Dataset in the layout of a case file
    case.Ft.plot(x="ubar")
    cube = capslide.open_cases("results/cases.nc")   # model x preload x step
    cube.sel(model="DI", preload=0.0).Ft.plot(x="ubar")
"""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import Any

import xarray as xr
import yaml

from .config import flatten
from .config import load_config as _load_config
from .driver.case import run_case
from .io.reading import open_result
from .io.results import case_dataset
from .params import Parameters

__all__ = ["load_config", "run", "open_case", "open_cases"]


def load_config(*paths: str | Path, settings: Mapping[str, Any] | None = None, **overrides: Any) -> dict:
    """A validated configuration: the YAML files ``paths`` merged in order, then ``overrides`` (keyword per section
    or top-level key: ``preset="fast"``, ``friction={"s_cut": 0.5}``), then ``settings`` (dotted keys:
    ``{"friction.s_cut": 0.5}``). Raises :class:`capslide.config.ConfigError` (one line) when it is bad."""
    typed = flatten(overrides)
    typed.update(settings or {})
    return _load_config(paths, settings=typed)


def run(config: Mapping[str, Any], progress: bool = False) -> xr.Dataset:
    """Run one case of a validated configuration; its dataset in the layout of a case file (docs/data.md).

    ``progress=True`` shows a progress bar on a terminal (one line per step elsewhere).
    """
    params = Parameters.from_config(config)
    observers = []
    if progress:
        from .cli.progress import ProgressDisplay

        observers.append(ProgressDisplay(params.loading))
    result = run_case(params, observers=observers)
    for obs in observers:
        obs.close()
    return _with_config(case_dataset(result, history="capslide.run (Python)"))


def _with_config(ds: xr.Dataset) -> xr.Dataset:
    """The dataset with its configuration parsed into ``ds.attrs["config"]`` (a dict: no file can hold one)."""
    text = ds.attrs.get("config_yaml")
    if text is not None:
        ds.attrs["config"] = yaml.safe_load(text)
    return ds


def open_case(path: str | Path) -> xr.Dataset:
    """A case file (``capslide run``) in memory, its configuration in ``attrs["config"]``."""
    return _with_config(open_result(path, "case"))


def open_cases(path: str | Path) -> xr.Dataset:
    """A collected file (``capslide collect``, model x preload x step) in memory; ``attrs["configs"]`` maps
    (model, preload) to the configuration of each case (a dict), and the flag variables ``status`` and ``slide_end``
    get the labels of their values as coordinates ``status_label`` and ``slide_end_label``."""
    ds = open_result(path, "cases")
    ds.attrs["configs"] = {(str(m), float(f)): yaml.safe_load(str(ds["config_yaml"].sel(model=m, preload=f).values))
                           for m in ds["model"].values for f in ds["preload"].values
                           if int(ds["status"].sel(model=m, preload=f)) >= 0}
    for name in ("status", "slide_end"):
        meanings = str(ds[name].attrs["flag_meanings"]).split()
        labels = [[meanings[v] if v >= 0 else "" for v in row] for row in ds[name].values.tolist()]
        ds = ds.assign_coords({f"{name}_label": (ds[name].dims, labels)})
    return ds
