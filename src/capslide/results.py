"""Result files: xarray datasets with CF attributes, written atomically.

The only module that imports xarray. Every variable carries ``units`` and
``long_name``; global attributes hold the software version, ``Conventions``,
the configuration as YAML text and every parameter flattened to
``section.key`` attributes.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any, Mapping

import numpy as np
import xarray as xr
import yaml

from . import __version__
from .config import flatten
from .mesh import Mesh

__all__ = ["CONVENTIONS", "config_attrs", "write_netcdf", "mesh_dataset", "mesh_from_dataset", "read_mesh"]

CONVENTIONS = "CF-1.10"


def _attr_value(value: Any):
    """netCDF attributes hold numbers and strings only."""
    if value is None:
        return "null"
    if isinstance(value, bool):
        return int(value)
    if isinstance(value, (int, float, str, np.number)):
        return value
    return str(value)


def config_attrs(config: Mapping[str, Any]) -> dict[str, Any]:
    """Global attributes: version, conventions, config as YAML, flattened parameters."""
    attrs = {"Conventions": CONVENTIONS, "software": "capslide", "software_version": __version__,
             "config_yaml": yaml.safe_dump(dict(config), sort_keys=False)}
    attrs.update({k: _attr_value(v) for k, v in flatten(config).items()})
    return attrs


def write_netcdf(ds: xr.Dataset, path: str | Path) -> Path:
    """Write ``ds`` to ``path`` via a temporary file in the same directory and a rename."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(f".{path.name}.tmp")
    try:
        ds.to_netcdf(tmp, engine="netcdf4")
        os.replace(tmp, path)
    finally:
        tmp.unlink(missing_ok=True)
    return path


def mesh_dataset(mesh: Mesh, config: Mapping[str, Any] | None = None) -> xr.Dataset:
    """The mesh as a dataset (reference coordinates in L0)."""
    order = mesh.surface_segments.shape[1] - 1
    ds = xr.Dataset(
        {
            "X_node": ("node", mesh.nodes[:, 0], {"units": "L0", "long_name": "reference x coordinate of node"}),
            "Y_node": ("node", mesh.nodes[:, 1], {"units": "L0", "long_name": "reference y coordinate of node"}),
            "cell_nodes": (("cell", "cell_node"), mesh.cells.astype(np.int64),
                           {"units": "1", "long_name": "node ids of cell (Q1: counter-clockwise; Q2: corners, mid-edges, centre)"}),
            "base_nodes": ("base_node", mesh.base.astype(np.int64), {"units": "1", "long_name": "node ids on the fixed base y = 0"}),
            "surface_segment_nodes": (("surface_segment", "segment_node"), mesh.surface_segments.astype(np.int64),
                                      {"units": "1", "long_name": f"node ids of top-surface line elements (order {order}), sorted by reference x"}),
        },
        attrs={"element": mesh.element, "n_dofs": mesh.n_dofs,
               **{f"mesh_{k}": _attr_value(v) for k, v in mesh.info.items()}},
    )
    if config is not None:
        ds.attrs.update(config_attrs(config))
    else:
        ds.attrs.update({"Conventions": CONVENTIONS, "software_version": __version__})
    return ds


def mesh_from_dataset(ds: xr.Dataset) -> Mesh:
    nodes = np.column_stack([ds["X_node"].values, ds["Y_node"].values])
    info = {k[5:]: v for k, v in ds.attrs.items() if k.startswith("mesh_")}
    return Mesh(str(ds.attrs["element"]), nodes, ds["cell_nodes"].values, ds["base_nodes"].values,
                ds["surface_segment_nodes"].values, info)


def read_mesh(path: str | Path) -> Mesh:
    with xr.open_dataset(path, engine="netcdf4") as ds:
        return mesh_from_dataset(ds.load())
