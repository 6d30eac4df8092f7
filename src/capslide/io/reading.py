"""Reading result files back: a dataset in memory, the configuration it was computed with, its mesh.

Every failure is a :class:`ResultFileError` naming the file, never a traceback of the netCDF library.
"""

from __future__ import annotations

from pathlib import Path

import xarray as xr
import yaml

from ..config import validate
from ..fem.mesh import Mesh
from .results import mesh_from_dataset

__all__ = ["ResultFileError", "open_result", "config_of", "read_mesh"]


class ResultFileError(ValueError):
    """A result file that is missing, unreadable or not what the caller needs (the message names it)."""


def open_result(path: str | Path) -> xr.Dataset:
    """A result file loaded into memory."""
    try:
        with xr.open_dataset(path, engine="netcdf4") as ds:
            return ds.load()
    except (OSError, ValueError) as err:
        raise ResultFileError(f"cannot read netCDF file '{path}': {err}") from None


def config_of(path: str | Path) -> dict:
    """The validated configuration stored in a capslide result file (attribute ``config_yaml``)."""
    text = open_result(path).attrs.get("config_yaml")
    if text is None:
        raise ResultFileError(f"'{path}' holds no configuration (attribute config_yaml)")
    return validate(yaml.safe_load(text))


def read_mesh(path: str | Path) -> Mesh:
    """The mesh stored in a mesh file (``capslide mesh``)."""
    return mesh_from_dataset(open_result(path))
