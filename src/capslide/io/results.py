"""Result files: xarray datasets with CF attributes, written atomically.

The only module that imports xarray. Every variable carries ``units`` and
``long_name``; global attributes hold the software version, ``Conventions``,
the configuration as YAML text and every parameter flattened to
``section.key`` attributes.
"""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np
import xarray as xr
import yaml

from ..config import flatten
from ..fem.element import gauss_legendre, line_shape
from ..fem.mesh import Mesh
from ..states import Phase, SlipState, Status, flag_attributes
from ..version import __version__
from .atomic import replacing
from .reading import open_result

__all__ = ["CONVENTIONS", "config_attrs", "write_netcdf", "mesh_dataset",
           "case_dataset", "collect", "STEP_VARIABLES", "CASE_SCALARS"]

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
    """Write ``ds`` to ``path`` via a temporary file in the same directory and a rename.

    Numeric variables are stored with lossless zlib compression (byte shuffle),
    which readers undo transparently; far-from-contact tractions and flags
    compress to almost nothing.
    """
    path = Path(path)
    encoding = {name: {"zlib": True, "complevel": 4, "shuffle": True}
                for name, var in ds.variables.items() if var.dtype.kind in "fiub" and var.ndim > 0}
    with replacing(path) as tmp:
        ds.to_netcdf(tmp, engine="netcdf4", encoding=encoding)
    return path


def mesh_dataset(mesh: Mesh, config: Mapping[str, Any] | None = None) -> xr.Dataset:
    """The mesh as a dataset (reference coordinates in L0)."""
    order = mesh.surface_segments.shape[1] - 1
    ds = xr.Dataset(
        {
            "X_node": ("node", mesh.nodes[:, 0], {"units": "L0", "long_name": "reference x coordinate of node"}),
            "Y_node": ("node", mesh.nodes[:, 1], {"units": "L0", "long_name": "reference y coordinate of node"}),
            "cell_nodes": (("cell", "cell_node"), mesh.cells.astype(np.int64),
                           {"units": "1",
                            "long_name": "node ids of cell (Q1: counter-clockwise; Q2: corners, mid-edges, centre)"}),
            "base_nodes": ("base_node", mesh.base.astype(np.int64),
                           {"units": "1", "long_name": "node ids on the fixed base y = 0"}),
            "surface_segment_nodes": (("surface_segment", "segment_node"), mesh.surface_segments.astype(np.int64),
                                      {"units": "1", "long_name": f"node ids of top-surface line elements (order {order}), "
                                                                  "sorted by reference x"}),
        },
        attrs={"element": mesh.element, "n_dofs": mesh.n_dofs,
               **{f"mesh_{k}": _attr_value(v) for k, v in mesh.info.items()}},
    )
    if config is not None:
        ds.attrs.update(config_attrs(config))
    else:
        ds.attrs.update({"Conventions": CONVENTIONS, "software_version": __version__})
    return ds


def _normalized(long_name: str, si_units: str, si_scale: float) -> dict:
    """Attributes of a normalized quantity: multiply by si_scale to get si_units."""
    return {"units": "1", "long_name": long_name, "si_units": si_units, "si_scale": si_scale}


def case_dataset(result) -> xr.Dataset:
    """A :class:`capslide.driver.case.CaseResult` as the case file of DESIGN section 7."""
    p, recs, mesh = result.params, result.records, result.mesh
    E, L0 = p.units.E, p.units.L0
    F, S, L = E * L0, E, L0  # SI scales: force per width (N/m), stress (Pa), length (m)
    step = lambda name: np.array([getattr(r, name) for r in recs], dtype=float)  # noqa: E731
    n_pts = len(recs[0].gap) if recs else 0
    prof = lambda name, dt=float: (np.stack([getattr(r, name) for r in recs]).astype(dt)  # noqa: E731
                                   if recs else np.zeros((0, n_pts), dtype=dt))
    X_surface = np.einsum("ga,sa->sg", *(_surface_shape(mesh, p))).ravel() if recs else np.zeros(0)
    data = {
        "phase": ("step", np.array([int(r.phase) for r in recs], dtype=np.int8), flag_attributes(Phase, "load phase")),
        "ubar": ("step", step("ubar"), _normalized("tangential substrate displacement / L0", "m", L)),
        "h": ("step", step("h"), _normalized("height of the substrate's lower face above the base / L0", "m", L)),
        "Fn": ("step", step("Fn"), _normalized("normal contact force on the cap / (E L0 W), positive = tensile", "N/m", F)),
        "Ft": ("step", step("Ft"),
               _normalized("tangential contact force on the cap / (E L0 W), positive in the sliding direction", "N/m", F)),
        "area": ("step", step("area"),
                 _normalized(f"contact area: current length where g_n <= {p.contact.area_gap:.5g} L0, / L0", "m", L)),
        "area_compressive": ("step", step("area_compressive"),
                             _normalized("current length where Tn >= 0 (compressive), / L0", "m", L)),
        "area_stick": ("step", step("area_stick"), _normalized("current length of sticking points in contact, / L0", "m", L)),
        "x_left": ("step", step("x_left"), _normalized("current x of the left (trailing) contact edge / L0", "m", L)),
        "x_right": ("step", step("x_right"), _normalized("current x of the right (leading) contact edge / L0", "m", L)),
        "newton_iterations": ("step", step("newton_iterations").astype(np.int32),
                              {"units": "1", "long_name": "Newton iterations of the step"}),
        "krylov_iterations": ("step", step("krylov_iterations").astype(np.int32),
                              {"units": "1", "long_name": "Krylov iterations of the step"}),
        "wall_time": ("step", step("wall_time"), {"units": "s", "long_name": "wall time of the step"}),
        "base_force_x": ("step", np.array([r.reaction[0] for r in recs], dtype=float),
                         _normalized("x force of the clamped base on the cap / (E L0 W); force balance: Ft + base_force_x = 0",
                                     "N/m", F)),
        "base_force_y": ("step", np.array([r.reaction[1] for r in recs], dtype=float),
                         _normalized("y force of the clamped base on the cap / (E L0 W); force balance: Fn + base_force_y = 0",
                                     "N/m", F)),
        "X_surface": ("surface_point", X_surface, _normalized("reference x of the surface Gauss point / L0", "m", L)),
        "x_surface": (("step", "surface_point"), prof("x_surface"), _normalized("current x of the surface point / L0", "m", L)),
        "y_surface": (("step", "surface_point"), prof("y_surface"), _normalized("current y of the surface point / L0", "m", L)),
        "gap": (("step", "surface_point"), prof("gap"), _normalized("normal gap g_n / L0", "m", L)),
        "traction_n": (("step", "surface_point"), prof("traction_n"),
                       _normalized("normal traction Tn per reference area / E, positive = repulsive", "Pa", S)),
        "traction_t": (("step", "surface_point"), prof("traction_t"),
                       _normalized("tangential traction on the cap per reference area / E, positive = +x", "Pa", S)),
        "slip_state": (("step", "surface_point"), prof("slip_state", np.int8),
                       flag_attributes(SlipState, "friction state of the surface point")),
    }
    if not p.config["output"]["surface_profiles"]:
        for name in ("x_surface", "y_surface", "gap", "traction_n", "traction_t", "slip_state"):
            del data[name]
    scal = result.scalars
    data.update({
        "peak_Ft": ((), scal["peak_Ft"], _normalized("largest |Ft| while sliding (signed) / (E L0 W)", "N/m", F)),
        "onset_ubar": ((), scal["onset_ubar"], _normalized("ubar at the onset of full sliding / L0 (NaN: not reached)", "m", L)),
        "onset_Ft": ((), scal["onset_Ft"], _normalized("Ft at the onset of full sliding / (E L0 W)", "N/m", F)),
        "onset_area": ((), scal["onset_area"], _normalized("contact area at the onset of full sliding / L0", "m", L)),
    })
    snaps = result.snapshots
    data.update({
        "snapshot_ubar": ("snapshot", np.array([sn.ubar for sn in snaps], dtype=float),
                          _normalized("ubar of the field snapshot / L0", "m", L)),
        "X_node": ("node", mesh.nodes[:, 0], _normalized("reference x of the mesh node / L0", "m", L)),
        "Y_node": ("node", mesh.nodes[:, 1], _normalized("reference y of the mesh node / L0", "m", L)),
        "cell_nodes": (("cell", "cell_node"), mesh.cells.astype(np.int64),
                       {"units": "1", "long_name": "node ids of the cell (element.py order)"}),
        "u_node": (("snapshot", "node"), np.array([sn.u[:, 0] for sn in snaps]).reshape(len(snaps), mesh.n_nodes),
                   _normalized("x displacement of the node / L0", "m", L)),
        "v_node": (("snapshot", "node"), np.array([sn.u[:, 1] for sn in snaps]).reshape(len(snaps), mesh.n_nodes),
                   _normalized("y displacement of the node / L0", "m", L)),
        "I1_sigma": (("snapshot", "cell"), np.array([sn.I1_sigma for sn in snaps]).reshape(len(snaps), mesh.n_cells),
                     _normalized("first invariant of the Cauchy stress (with sigma_zz), cell average / E", "Pa", S)),
    })
    ds = xr.Dataset({k: xr.Variable(v[0], v[1], v[2]) for k, v in data.items()})
    ds.attrs.update(config_attrs(p.config))
    ds.attrs.update({
        "status": result.status.label, "status_reason": result.reason or "none",
        "status_step": len(recs) - 1, "cutbacks": result.cutbacks,
        "min_step": float(result.min_step), "case_wall_time": float(result.wall_time),
        "element": mesh.element, "n_cells": mesh.n_cells, "n_dofs": mesh.n_dofs,
        "title": "capslide case: soft cap sliding on a rigid substrate",
    })
    return ds


def _surface_shape(mesh: Mesh, p):
    """Shape values at the surface Gauss points and the reference x of segment nodes."""
    s, _ = gauss_legendre(p.mesh.surface_gauss_points)
    N, _ = line_shape(mesh.surface_segments.shape[1] - 1, s)
    return N, mesh.nodes[mesh.surface_segments, 0]


STEP_VARIABLES = ("phase", "ubar", "h", "Fn", "Ft", "area", "area_compressive", "area_stick", "x_left", "x_right",
                  "newton_iterations", "krylov_iterations", "wall_time")
CASE_SCALARS = ("peak_Ft", "onset_ubar", "onset_Ft", "onset_area")


def collect(paths) -> xr.Dataset:
    """Stack case files over a ``case`` dimension (coordinates model, s_cut, preload).

    Step variables are padded to the longest case (NaN; integers and flags
    with -1 as _FillValue); per-case scalars and the status become
    variables over ``case``. Surface profiles and field snapshots stay in
    the case files.
    """
    cases = []
    for path in paths:
        ds = open_result(path, "case")
        cases.append(ds[list(STEP_VARIABLES) + list(CASE_SCALARS)].assign_attrs(ds.attrs))
    n_steps = max(c.sizes["step"] for c in cases)
    data: dict[str, tuple] = {}
    for name in STEP_VARIABLES:
        first = cases[0][name]
        integer = np.issubdtype(first.dtype, np.integer)
        fill = -1 if integer else np.nan
        arr = np.full((len(cases), n_steps), fill, dtype=first.dtype if integer else float)
        for i, c in enumerate(cases):
            arr[i, : c.sizes["step"]] = c[name].values
        attrs = dict(first.attrs)
        data[name] = (("case", "step"), arr, attrs)
    for name in CASE_SCALARS:
        data[name] = ("case", np.array([float(c[name]) for c in cases]), dict(cases[0][name].attrs))
    status = np.array([Status.from_label(c.attrs.get("status", "diverged")) for c in cases], dtype=np.int8)
    data["status"] = ("case", status, flag_attributes(Status, "final status of the case"))
    onset_only = [str(c.attrs.get("loading.stop_at_onset", "false")).lower() in ("true", "1") for c in cases]
    data["slide_end"] = ("case", np.array(onset_only, dtype=np.int8),
                         {"long_name": "where the slide was set to end (loading.stop_at_onset)", "units": "1",
                          "flag_values": np.array([0, 1], dtype=np.int8), "flag_meanings": "ubar_max onset"})
    data["n_steps"] = ("case", np.array([c.sizes["step"] for c in cases], dtype=np.int32),
                       {"units": "1", "long_name": "number of converged steps of the case"})
    model = [str(c.attrs["friction.model"]) for c in cases]
    s_cut = [float(c.attrs["friction.s_cut"]) if m == "EA" else np.nan for c, m in zip(cases, model)]
    coords = {
        "model": ("case", np.array(model, dtype=object), {"long_name": "friction model (DI, EA, none)", "units": "1"}),
        "s_cut": ("case", np.array(s_cut), {"long_name": "EA cut-off parameter s_cut (NaN for DI)", "units": "1"}),
        "preload": ("case", np.array([float(c.attrs["loading.preload"]) for c in cases]),
                    _normalized("target normal force Fn* / (E L0 W), positive = tensile", "N/m",
                                float(cases[0].attrs["material.E"]) * float(cases[0].attrs["geometry.L0"]))),
        "case_file": ("case", np.array([str(p) for p in paths], dtype=object), {"long_name": "source case file", "units": "1"}),
    }
    out = xr.Dataset({k: xr.Variable(*v) for k, v in data.items()}, coords={k: xr.Variable(*v) for k, v in coords.items()})
    common = {k: v for k, v in cases[0].attrs.items()
              if all(k in c.attrs and np.array_equal(np.asarray(c.attrs[k]), np.asarray(v)) for c in cases)}
    out.attrs.update({k: v for k, v in common.items() if not k.startswith(("status", "case_wall", "cutbacks", "min_step"))})
    out.attrs.update({"Conventions": CONVENTIONS, "software_version": __version__,
                      "config_yaml": cases[0].attrs.get("config_yaml", ""),
                      "title": "capslide: all cases of a study", "n_cases": len(cases)})
    for name in STEP_VARIABLES:
        if np.issubdtype(out[name].dtype, np.integer):
            out[name].encoding["_FillValue"] = -1
    return out
