"""Reading result files back: a dataset in memory, what kind of capslide file it is, its configuration, its mesh.

Every failure is a :class:`ResultFileError` naming the file, never a traceback of the netCDF library.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import xarray as xr
import yaml

from ..config import validate
from ..fem.mesh import Mesh

__all__ = ["ResultFileError", "KINDS", "kind_of", "open_result", "config_of", "mesh_from_dataset", "read_mesh",
           "scale_and_unit"]

KINDS = {"case": "a case file (capslide run)", "cases": "a collected file (capslide collect)",
         "mesh": "a mesh file (capslide mesh)"}


class ResultFileError(ValueError):
    """A result file that is missing, unreadable or not what the caller needs (the message names it)."""


def kind_of(ds: xr.Dataset) -> str | None:
    """'case', 'cases' or 'mesh' for the files capslide writes; None for any other dataset."""
    if "status" not in ds.attrs and "status" not in ds:
        return "mesh" if {"cell_nodes", "X_node"} <= set(ds.variables) and "element" in ds.attrs else None
    if {"model", "preload"} <= set(ds.dims) and "status" in ds:
        return "cases"
    if "step" in ds.dims and "phase" in ds and "status" in ds.attrs:
        return "case"
    return None


def open_result(path: str | Path, kind: str | None = None) -> xr.Dataset:
    """A result file loaded into memory; with ``kind``, it must be that kind of capslide file (see KINDS)."""
    path = Path(path)
    if path.is_dir():
        raise ResultFileError(f"'{path}' is a directory, not a netCDF file")
    try:
        with xr.open_dataset(path, engine="netcdf4") as ds:
            ds = ds.load()
    except (OSError, ValueError, RuntimeError, KeyError) as err:  # RuntimeError: 'NetCDF: HDF error' of a damaged chunk
        raise ResultFileError(f"cannot read netCDF file '{path}': {str(err).splitlines()[0]}") from None
    if kind is not None and kind_of(ds) != kind:
        found = KINDS.get(kind_of(ds), "not a file capslide wrote")
        raise ResultFileError(f"'{path}' is {found}; {KINDS[kind]} is needed here")
    return ds


def config_of(path: str | Path) -> dict:
    """The validated configuration stored in a capslide result file (attribute ``config_yaml``)."""
    text = open_result(path).attrs.get("config_yaml")
    if text is None:
        raise ResultFileError(f"'{path}' holds no configuration (attribute config_yaml)")
    return validate(yaml.safe_load(text))


def mesh_from_dataset(ds: xr.Dataset) -> Mesh:
    nodes = np.column_stack([ds["X_node"].values, ds["Y_node"].values])
    info = {k[len("grading_"):]: v for k, v in ds.attrs.items() if k.startswith("grading_")}
    return Mesh(str(ds.attrs["element"]), nodes, ds["cell_nodes"].values, ds["base_nodes"].values,
                ds["surface_segment_nodes"].values, info)


def read_mesh(path: str | Path) -> Mesh:
    """The mesh stored in a mesh file (``capslide mesh``)."""
    return mesh_from_dataset(open_result(path, "mesh"))


def scale_and_unit(units: str) -> tuple[float, str] | None:
    """(scale, SI unit) of a units attribute '<scale> <unit>' ('2 N/m', '1e-06 m'); None for '1' or no number."""
    head, _, tail = str(units).partition(" ")
    try:
        scale = float(head)
    except ValueError:
        return None
    return (scale, tail.strip()) if tail.strip() else None
