"""Result datasets with CF attributes and units that UDUNITS reads, written atomically (docs/data.md).

Values are stored normalized (lengths / L0, stresses / E, forces per width / (E L0 W)); each ``units`` attribute is
the scaled physical unit of that normalization (for the paper's E = 2 MPa and L0 = 1 um: "1e-06 m", "2e+06 Pa",
"2 N/m"), so a unit-aware reader gets physical values by multiplying, and ``normalization`` names the scale.
Quantities a user plots against are coordinates (``ubar`` on ``step``, ``X_reference`` on ``surface_point``, the
node positions on ``node``); snapshots are indexed by their ``snapshot_ubar``. Global attributes: ``Conventions``,
``title``, ``history``, the software version, the configuration as YAML text and flattened with ``_`` in the names.
"""

from __future__ import annotations

import datetime
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np
import xarray as xr
import yaml

from ..config import flatten
from ..fem.mesh import Mesh
from ..loadpath.contact_patch import snapshot_outlines
from ..loadpath.measures import case_energies, surface_reference_x
from ..states import Phase, SlipState, flag_attributes
from ..version import software_version
from .atomic import replacing
from .catalog import case_scalars, cube_step_coordinates, cube_step_variables, recorded_step_variables, variable

__all__ = ["CONVENTIONS", "LONG_NAME_MAX", "KEY_PARAMETERS", "key_parameters", "scaled_units", "quantity", "global_attrs",
           "write_netcdf", "mesh_dataset", "case_dataset", "STEP_VARIABLES", "STEP_COORDINATES", "CASE_SCALARS"]

CONVENTIONS = "CF-1.10"
LONG_NAME_MAX = 40  # characters: a long_name is an axis label
CELL_NODE_ORDER = "Q1: counter-clockwise; Q2: corners, mid-edges, centre; H1, H2: VTK's hexahedron orders"
# The configuration keys a file carries as global attributes (``section_key``), those a reader labels a case with;
# the whole configuration is the attribute ``config_yaml``.
KEY_PARAMETERS = ("material.E", "material.nu", "material.model", "adhesion.T_max", "adhesion.W_adh", "geometry.L0",
                  "geometry.R", "geometry.H", "friction.model", "friction.mu_DI", "friction.mu_EA", "friction.s_cut",
                  "mesh.element", "mesh.size", "mesh.formulation", "preset", "loading.preload", "loading.ubar_max",
                  "loading.normal_control", "loading.velocity")
STEP_VARIABLES = cube_step_variables()  # what the collected cube keeps of a case (io.catalog)
STEP_COORDINATES = cube_step_coordinates()
CASE_SCALARS = case_scalars()
PROFILE = ("step", "surface_point")


def scaled_units(E: float, L0: float, dim: int = 2) -> dict[str, str]:
    """UDUNITS strings of the internal units: length L0 (m), stress E (Pa); in 2D a contact area is a length, the
    force per unit out-of-plane width E L0 (N/m; plane strain, W = 1), the energy per unit width E L0^2 (J/m); in 3D
    area L0^2 (m2), force E L0^2 (N), energy E L0^3 (J)."""
    if dim == 3:
        return {"length": f"{L0:g} m", "area": f"{L0 * L0:g} m2", "stress": f"{E:g} Pa", "force": f"{E * L0 * L0:g} N",
                "energy": f"{E * L0**3:g} J"}
    return {"length": f"{L0:g} m", "area": f"{L0:g} m", "stress": f"{E:g} Pa", "force": f"{E * L0:g} N/m",
            "energy": f"{E * L0 * L0:g} J/m"}


def quantity(long_name: str, units: str | None, normalization: str | None = None,
             description: str | None = None) -> dict:
    """CF attributes of a stored quantity: a short ``long_name`` (an axis label, at most 40 characters), ``units``
    (None: a text variable, which has none), ``normalization`` (what it is divided by: "L0", "E", "E L0 W") and the
    details in ``description``."""
    if len(long_name) > LONG_NAME_MAX:
        raise ValueError(f"long_name {long_name!r} is longer than {LONG_NAME_MAX} characters: put the details in a "
                         "description")
    attrs = {"long_name": long_name} if units is None else {"long_name": long_name, "units": units}
    if normalization:
        attrs["normalization"] = f"divided by {normalization}"
    if description:
        attrs["description"] = description
    return attrs


def _attr_value(value: Any):
    """netCDF attributes hold numbers and strings only."""
    if value is None:
        return "null"
    if isinstance(value, bool):
        return int(value)
    if isinstance(value, (int, float, str, np.number)):
        return value
    return str(value)


def key_parameters(flat: Mapping[str, Any]) -> dict[str, Any]:
    """The :data:`KEY_PARAMETERS` of a flattened configuration as attributes (``section_key``); unset ones left out."""
    return {k.replace(".", "_"): _attr_value(flat[k]) for k in KEY_PARAMETERS if flat.get(k) is not None}


def global_attrs(config: Mapping[str, Any] | None, title: str, history: str | None = None) -> dict[str, Any]:
    """Conventions, title, history, software version, the configuration as YAML and its key parameters."""
    now = datetime.datetime.now(datetime.UTC).strftime("%Y-%m-%dT%H:%M:%SZ")
    attrs = {"Conventions": CONVENTIONS, "title": title,
             "history": f"{now}: {history or 'written by capslide ' + software_version()}",
             "source": "capslide finite element model (https://doi.org/10.1080/00218464.2018.1479258)",
             "software": "capslide", "software_version": software_version()}
    if config is not None:
        attrs["config_yaml"] = yaml.safe_dump(dict(config), sort_keys=False)
        attrs.update(key_parameters(flatten(config)))
    return attrs


def write_netcdf(ds: xr.Dataset, path: str | Path) -> Path:
    """Write ``ds`` to ``path`` via a temporary file in the same directory and a rename.

    Numeric variables are stored with lossless zlib compression (byte shuffle), which readers undo transparently;
    far-from-contact tractions and flags compress to almost nothing.
    """
    path = Path(path)
    encoding = {name: {"zlib": True, "complevel": 4, "shuffle": True}
                for name, var in ds.variables.items() if var.dtype.kind in "fiub" and var.ndim > 0}
    with replacing(path) as tmp:
        ds.to_netcdf(tmp, engine="netcdf4", encoding=encoding)
    return path


def _index(name: str) -> dict:
    return quantity(f"{name} (position in the list)", "1")


def mesh_dataset(mesh: Mesh, config: Mapping[str, Any] | None = None, history: str | None = None) -> xr.Dataset:
    """The mesh as a dataset: node positions (coordinates), cells, base nodes and top-surface segments."""
    L0 = float(config["geometry"]["L0"]) if config is not None else 1.0e-6
    length = scaled_units(1.0, L0)["length"]
    order = mesh.surface_segments.shape[1] - 1
    ds = xr.Dataset(
        {
            "cell_nodes": (("cell", "cell_node"), mesh.cells.astype(np.int64),
                           quantity("node ids of the cell", "1", description=CELL_NODE_ORDER)),
            "base_nodes": ("base_node", mesh.base.astype(np.int64), quantity("node ids on the fixed base y = 0", "1")),
            "surface_segment_nodes": (("surface_segment", "segment_node"), mesh.surface_segments.astype(np.int64),
                                      quantity("node ids of the surface segment", "1",
                                               description=f"top-surface line elements of order {order}, sorted by "
                                               "reference x")),
        },
        coords={"X_node": ("node", mesh.nodes[:, 0], quantity("reference x of the node", length, "L0")),
                "Y_node": ("node", mesh.nodes[:, 1], quantity("reference y of the node", length, "L0")),
                **({"Z_node": ("node", mesh.nodes[:, 2], quantity("reference z of the node", length, "L0"))}
                   if mesh.dim == 3 else {})},
        attrs={"element": mesh.element, "n_dofs": mesh.n_dofs,
               **{f"grading_{k}": _attr_value(v) for k, v in mesh.info.items()}},
    )
    ds.attrs.update(global_attrs(config, "capslide mesh of the cap", history))
    return ds


def _attrs(name: str, units: Mapping[str, str], dim: int = 2, **values) -> dict:
    """CF attributes of the catalog's variable ``name`` (:mod:`capslide.io.catalog`) in a case of dimension ``dim``:
    its unit scaled by ``units`` (:func:`scaled_units`), its description with ``values`` filled in."""
    v = variable(name)
    return quantity(v.long_name, units.get(v.unit, v.unit), v.normalization_in(dim),
                    v.description.format(**values) if values else v.description)


def _slip_profiles(recs, slip: np.ndarray, u: Mapping[str, str], slip_y: np.ndarray | None = None) -> dict:
    """Accumulated slip and slip rate per unit ubar of each surface point in contact (slip: the anchors' moves of
    the steps along x, signed; 3D: ``slip_y`` their moves along y, and the accumulated slip sums the moves' lengths)."""
    state = np.stack([r.slip_state for r in recs]) if recs else np.zeros(slip.shape, dtype=np.int8)
    in_contact = (state == SlipState.STICK) | (state == SlipState.SLIP)
    slip = np.where(in_contact, slip, 0.0)
    dubar = np.diff([r.ubar for r in recs], prepend=recs[0].ubar if recs else 0.0)[:, None]
    rate = np.divide(slip, dubar, out=np.full(slip.shape, np.nan), where=dubar != 0.0)
    moved = np.abs(slip) if slip_y is None else np.hypot(slip, np.where(in_contact, slip_y, 0.0))
    return {"slip": (PROFILE, np.cumsum(moved, axis=0), _attrs("slip", u)),
            "slip_rate": (PROFILE, rate, _attrs("slip_rate", u))}


def _outline_variables(mesh: Mesh, snaps, area_gap: float, u: Mapping[str, str]) -> dict:
    """3D: each snapshot's contact outline and stick-zone outline in the contact plane (the whole body's, closed
    polylines joined by a NaN row, padded with NaN; :func:`capslide.loadpath.contact_patch.snapshot_outlines`)."""
    faces, n = mesh.surface_quads, len(mesh.surface_segments)
    curves = {"outline": [], "stick_outline": []}
    for sn in snaps:
        x = mesh.nodes + sn.u
        states = sn.slip_state.reshape(n, -1) if sn.slip_state.size else np.zeros((n, 1))
        stick = np.repeat(np.mean(states == SlipState.STICK, axis=1), len(faces) // n)  # a face's share on its quarters
        contact, stick = snapshot_outlines(x, sn.h - x[:, 2], faces, stick, area_gap, mirror_y=len(mesh.symmetry) > 0)
        curves["outline"].append(contact)
        curves["stick_outline"].append(stick)
    what = {"outline": "the contact's edge (g_n = the contact gap, from the nodal gaps)",
            "stick_outline": "the stick zone's edge (where half the surface points about a node stick; within about a "
                             "face)"}
    out = {}
    for name, polys in curves.items():
        n = max((len(c) for c in polys), default=0)
        padded = np.full((len(polys), n, 2), np.nan)
        for k, c in enumerate(polys):
            padded[k, :len(c)] = c
        for axis, label in enumerate("xy"):
            out[f"{name}_{label}"] = (("snapshot_ubar", f"{name}_point"), padded[..., axis],
                                      quantity(f"{label} of the {name.replace('_', ' ')}", u["length"], "L0",
                                               f"3D: current {label} of {what[name]}, seen from above: closed polylines "
                                               "of the whole body, a row of NaN between two, NaN-padded"))
    return out


def case_dataset(result, history: str | None = None) -> xr.Dataset:
    """A :class:`capslide.driver.case.CaseResult` as a case file (docs/data.md); every variable over the steps and
    the surface points, and every case scalar, as the catalog (:mod:`capslide.io.catalog`) gives it."""
    p, recs, mesh = result.params, result.records, result.mesh
    u, d = scaled_units(p.units.E, p.units.L0, mesh.dim), mesh.dim
    step = lambda name, dt=float: np.array([getattr(r, name) for r in recs], dtype=dt)  # noqa: E731
    n_pts = len(recs[0].gap) if recs else 0
    prof = lambda name, dt=float: (np.stack([getattr(r, name) for r in recs]).astype(dt)  # noqa: E731
                                   if recs else np.zeros((0, n_pts), dtype=dt))
    data = {v.name: ("step", step(v.record, v.dtype), _attrs(v.name, u, d, area_gap=p.contact.area_gap))
            for v in recorded_step_variables() if v.present != "3d" or d == 3}
    area = step("area")
    data["Ft_over_area"] = ("step", np.divide(step("Ft"), area, out=np.full(len(recs), np.nan), where=area > 0),
                            _attrs("Ft_over_area", u, d))
    energies = case_energies(recs, mesh, p.mesh.surface_gauss_points)
    data.update({name: ("step", energies[name], _attrs(name, u, d))
                 for name in ("dissipation", "external_work", "energy_residual")})
    data.update({
        "base_force_x": ("step", np.array([r.reaction[0] for r in recs], dtype=float), _attrs("base_force_x", u, d)),
        "base_force_y": ("step", np.array([r.reaction[1] for r in recs], dtype=float), _attrs("base_force_y", u, d)),
    })
    if d == 3:
        width = step("width_y")
        data["extent_ratio"] = ("step", np.divide(step("x_right") - step("x_left"), width,
                                                  out=np.full(len(recs), np.nan), where=width > 0),
                                _attrs("extent_ratio", u, d))
        data["base_force_z"] = ("step", np.array([r.reaction[2] for r in recs], dtype=float), _attrs("base_force_z", u, d))
    if p.output.surface_profiles:
        data.update({name: (PROFILE, prof(variable(name).record), _attrs(name, u, d))
                     for name in ("x_current", "y_current", "gap", "traction_n", "traction_t")})
        data["slip_state"] = (PROFILE, prof("slip_state", np.int8),
                              flag_attributes(SlipState, variable("slip_state").long_name))
        if d == 3:
            data["traction_t_y"] = (PROFILE, prof("traction_t_y"), _attrs("traction_t_y", u, d))
        data.update(_slip_profiles(recs, prof("slip"), u, prof("slip_y") if d == 3 else None))
    data.update({name: ((), result.scalars[name], _attrs(name, u, d)) for name in case_scalars()})
    snaps = result.snapshots
    k, nn, nc = len(snaps), mesh.n_nodes, mesh.n_cells
    data.update({
        "cell_nodes": (("cell", "cell_node"), mesh.cells.astype(np.int64),
                       quantity("node ids of the cell", "1", description=CELL_NODE_ORDER)),
        "u_node": (("snapshot_ubar", "node"), np.array([sn.u[:, 0] for sn in snaps]).reshape(k, nn),
                   quantity("x displacement of the node", u["length"], "L0")),
        "v_node": (("snapshot_ubar", "node"), np.array([sn.u[:, 1] for sn in snaps]).reshape(k, nn),
                   quantity("y displacement of the node", u["length"], "L0")),
        **({"w_node": (("snapshot_ubar", "node"), np.array([sn.u[:, 2] for sn in snaps]).reshape(k, nn),
                       quantity("z displacement of the node", u["length"], "L0"))} if d == 3 else {}),
        "I1_sigma": (("snapshot_ubar", "cell"), np.array([sn.I1_sigma for sn in snaps]).reshape(k, nc),
                     quantity("I1(sigma)", u["stress"], "E",
                             "first invariant of the Cauchy stress (with sigma_zz), cell average")),
    })
    if d == 3 and snaps and all(np.isfinite(sn.h) for sn in snaps):
        data.update(_outline_variables(mesh, snaps, p.contact.area_gap, u))
    coords = {
        "step": ("step", np.arange(len(recs), dtype=np.int32), quantity("converged load step", "1")),
        "phase": ("step", step("phase", np.int8), flag_attributes(Phase, variable("phase").long_name)),
        "ubar": ("step", step("ubar"), _attrs("ubar", u, d)),
        "h": ("step", step("h"), _attrs("h", u, d)),
        "X_reference": ("surface_point", surface_reference_x(mesh, p.mesh.surface_gauss_points) if recs else np.zeros(0),
                        quantity("reference x of the surface Gauss point", u["length"], "L0")),
        **({"Y_reference": ("surface_point", surface_reference_x(mesh, p.mesh.surface_gauss_points, 1) if recs else np.zeros(0),
                            quantity("reference y of the surface Gauss point", u["length"], "L0"))} if d == 3 else {}),
        "snapshot_ubar": ("snapshot_ubar", np.array([sn.ubar for sn in snaps], dtype=float),
                          quantity("ubar of the field snapshot", u["length"], "L0")),
        "X_node": ("node", mesh.nodes[:, 0], quantity("reference x of the node", u["length"], "L0")),
        "Y_node": ("node", mesh.nodes[:, 1], quantity("reference y of the node", u["length"], "L0")),
        **({"Z_node": ("node", mesh.nodes[:, 2], quantity("reference z of the node", u["length"], "L0"))} if d == 3 else {}),
    }
    if p.loading.velocity is not None:  # time is tracked
        coords["time"] = ("step", step("time"), _attrs("time", u, d))
    if p.material.prony_g:
        data["elastic_energy"][2]["long_name"] = "stored energy"
        data["elastic_energy"][2]["description"] = ("stored energy of the cap per unit width: the neo-Hooke part and "
                                                    "the viscous branches' (energy_residual then holds their "
                                                    "dissipation)")
    ds = xr.Dataset({name: xr.Variable(*v) for name, v in data.items()},
                    coords={name: xr.Variable(*v) for name, v in coords.items()})
    ds.attrs.update(global_attrs(p.config, "capslide case: soft cap sliding on a rigid substrate", history))
    ds.attrs.update({
        "status": result.status.label, "status_reason": result.reason or "none",
        "status_step": len(recs) - 1, "cutbacks": result.cutbacks,
        "min_step": float(result.min_step), "case_wall_time": float(result.wall_time),
        "element": mesh.element, "n_cells": mesh.n_cells, "n_dofs": mesh.n_dofs,
    })
    return ds
