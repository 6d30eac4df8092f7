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
from ..loadpath.measures import case_energies, surface_reference_x
from ..states import Phase, SlipState, flag_attributes
from ..version import software_version
from .atomic import replacing

__all__ = ["CONVENTIONS", "LONG_NAME_MAX", "KEY_PARAMETERS", "key_parameters", "scaled_units", "quantity", "global_attrs",
           "write_netcdf", "mesh_dataset", "case_dataset", "STEP_VARIABLES", "CASE_SCALARS", "PROFILES"]

CONVENTIONS = "CF-1.10"
LONG_NAME_MAX = 40  # characters: a long_name is an axis label
CELL_NODE_ORDER = "Q1: counter-clockwise; Q2: corners, mid-edges, centre"
# The configuration keys a file carries as global attributes (``section_key``), those a reader labels a case with;
# the whole configuration is the attribute ``config_yaml``.
KEY_PARAMETERS = ("material.E", "material.nu", "material.model", "adhesion.T_max", "adhesion.W_adh", "geometry.L0",
                  "geometry.R", "geometry.H", "friction.model", "friction.mu_DI", "friction.mu_EA", "friction.s_cut",
                  "mesh.element", "mesh.size", "mesh.formulation", "preset", "loading.preload", "loading.ubar_max",
                  "loading.normal_control", "loading.velocity")
STEP_VARIABLES = ("Fn", "Ft", "area", "area_compressive", "area_stick", "x_left", "x_right", "newton_iterations",
                  "krylov_iterations", "wall_time", "steady_step", "area_reference", "x_stick_left", "x_stick_right",
                  "Ft_over_area", "elastic_energy", "dissipation", "adhesion_energy", "penalty_energy", "external_work",
                  "energy_residual")
STEP_COORDINATES = ("phase", "ubar", "h")
CASE_SCALARS = ("peak_Ft", "onset_ubar", "onset_Ft", "onset_area")
PROFILES = ("x_current", "y_current", "gap", "traction_n", "traction_t", "slip_state", "slip", "slip_rate")


def scaled_units(E: float, L0: float) -> dict[str, str]:
    """UDUNITS strings of the internal units: length L0 (m), stress E (Pa), force per unit out-of-plane width
    E L0 (N/m; plane strain, W = 1), energy per unit width E L0^2 (J/m)."""
    return {"length": f"{L0:g} m", "stress": f"{E:g} Pa", "force": f"{E * L0:g} N/m", "energy": f"{E * L0 * L0:g} J/m"}


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
                "Y_node": ("node", mesh.nodes[:, 1], quantity("reference y of the node", length, "L0"))},
        attrs={"element": mesh.element, "n_dofs": mesh.n_dofs,
               **{f"grading_{k}": _attr_value(v) for k, v in mesh.info.items()}},
    )
    ds.attrs.update(global_attrs(config, "capslide mesh of the cap", history))
    return ds


def _slip_profiles(recs, slip: np.ndarray, length: str) -> dict:
    """Accumulated slip and slip rate per unit ubar of each surface point in contact (slip: the anchors' moves of
    the steps, signed)."""
    state = np.stack([r.slip_state for r in recs]) if recs else np.zeros(slip.shape, dtype=np.int8)
    slip = np.where((state == SlipState.STICK) | (state == SlipState.SLIP), slip, 0.0)
    dubar = np.diff([r.ubar for r in recs], prepend=recs[0].ubar if recs else 0.0)[:, None]
    rate = np.divide(slip, dubar, out=np.full(slip.shape, np.nan), where=dubar != 0.0)
    return {"slip": (("step", "surface_point"), np.cumsum(np.abs(slip), axis=0),
                     quantity("accumulated slip", length, "L0",
                              "slip accumulated up to the step: the sum of |slip| of the steps, in contact")),
            "slip_rate": (("step", "surface_point"), rate,
                          quantity("slip rate per unit ubar", "1", description="slip of the step per unit ubar, signed "
                                   "(+x: the cap slips in the sliding direction relative to the substrate; NaN where "
                                   "ubar does not change)"))}


def _energy_balance(energies: dict[str, np.ndarray], energy: str) -> dict:
    """The work of the loads and the balance's residual (:func:`capslide.loadpath.measures.case_energies`) as
    step variables."""
    return {"external_work": ("step", energies["external_work"],
                              quantity("work of the loads", energy, "E L0^2 W",
                                       "work of the loads on the substrate up to the step, per unit width: "
                                       "int Fn dh + Ft dubar (trapezoidal rule)")),
            "energy_residual": ("step", energies["energy_residual"],
                                quantity("energy balance residual", energy, "E L0^2 W",
                                         "external_work - (elastic + adhesion + penalty energy, change from step 0) "
                                         "- dissipation"))}


def case_dataset(result, history: str | None = None) -> xr.Dataset:
    """A :class:`capslide.driver.case.CaseResult` as a case file (docs/data.md)."""
    p, recs, mesh = result.params, result.records, result.mesh
    u = scaled_units(p.units.E, p.units.L0)
    step = lambda name, dt=float: np.array([getattr(r, name) for r in recs], dtype=dt)  # noqa: E731
    n_pts = len(recs[0].gap) if recs else 0
    prof = lambda name, dt=float: (np.stack([getattr(r, name) for r in recs]).astype(dt)  # noqa: E731
                                   if recs else np.zeros((0, n_pts), dtype=dt))
    on_step = {
        "Fn": quantity("normal force Fn", u["force"], "E L0 W",
                       "normal contact force on the cap, positive = tensile"),
        "Ft": quantity("friction force Ft", u["force"], "E L0 W",
                       "tangential contact force on the cap, positive in the sliding direction"),
        "area": quantity("contact area A", u["length"], "L0",
                         f"current length where g_n <= {p.contact.area_gap:.5g} L0"),
        "area_compressive": quantity("compressive contact area", u["length"], "L0", "current length where Tn >= 0"),
        "area_stick": quantity("stick area", u["length"], "L0", "current length of sticking points in contact"),
        "x_left": quantity("left contact edge x", u["length"], "L0", "current x of the left (trailing) contact edge"),
        "x_right": quantity("right contact edge x", u["length"], "L0", "current x of the right (leading) contact edge"),
        "area_reference": quantity("reference contact area", u["length"], "L0",
                                   "reference length of the contact (the contact area in the reference configuration)"),
        "x_stick_left": quantity("left stick edge x", u["length"], "L0",
                                 "current x of the stick zone's left edge (NaN: nothing sticks)"),
        "x_stick_right": quantity("right stick edge x", u["length"], "L0",
                                  "current x of the stick zone's right edge (NaN: nothing sticks)"),
        "elastic_energy": quantity("strain energy", u["energy"], "E L0^2 W", "strain energy of the cap per unit width"),
        "adhesion_energy": quantity("adhesion energy", u["energy"], "E L0^2 W",
                                    "adhesive potential of the interface per unit width (NaN with theta_k = J_s)"),
        "penalty_energy": quantity("penalty energy", u["energy"], "E L0^2 W",
                                   "elastic energy of the tangential penalty per unit width"),
    }
    data = {name: ("step", step(name), attrs) for name, attrs in on_step.items()}
    area = step("area")
    data["Ft_over_area"] = ("step", np.divide(step("Ft"), area, out=np.full(len(recs), np.nan), where=area > 0),
                            quantity("Ft / A", u["stress"], "E",
                                     "mean shear stress in contact (NaN without contact)"))
    energies = case_energies(recs, mesh, p.mesh.surface_gauss_points)
    data["dissipation"] = ("step", energies["dissipation"], quantity("dissipated work", u["energy"], "E L0^2 W",
                                                        "frictional work dissipated up to the step, per unit width: "
                                                        "sum over steps of -(Tt before + Tt after) / 2 x slip x dA"))
    data.update(_energy_balance(energies, u["energy"]))
    data.update({
        "newton_iterations": ("step", step("newton_iterations", np.int32), quantity("Newton iterations of the step", "1")),
        "krylov_iterations": ("step", step("krylov_iterations", np.int32), quantity("Krylov iterations of the step", "1")),
        "wall_time": ("step", step("wall_time"), quantity("wall time of the step", "s")),
        "steady_step": ("step", step("steady_step", np.int8),
                        quantity("steady long step", "1", description="1: the step went in one to the next snapshot ubar or "
                                 "the leg's end, the sliding being steady (Ft, area and gaps unchanged to 1e-8 over "
                                 "the steps before and over it); 0: a step of the adaptive step control")),
        "base_force_x": ("step", np.array([r.reaction[0] for r in recs], dtype=float),
                         quantity("base force x", u["force"], "E L0 W",
                                  "x force of the clamped base on the cap; force balance: Ft + base_force_x = 0")),
        "base_force_y": ("step", np.array([r.reaction[1] for r in recs], dtype=float),
                         quantity("base force y", u["force"], "E L0 W",
                                  "y force of the clamped base on the cap; force balance: Fn + base_force_y = 0")),
    })
    if p.output.surface_profiles:
        data.update({
            "x_current": (("step", "surface_point"), prof("x_surface"), quantity("current x of the surface point",
                                                                                 u["length"], "L0")),
            "y_current": (("step", "surface_point"), prof("y_surface"), quantity("current y of the surface point",
                                                                                 u["length"], "L0")),
            "gap": (("step", "surface_point"), prof("gap"), quantity("normal gap g_n", u["length"], "L0")),
            "traction_n": (("step", "surface_point"), prof("traction_n"),
                           quantity("normal traction Tn", u["stress"], "E",
                                    "per reference area, positive = repulsive")),
            "traction_t": (("step", "surface_point"), prof("traction_t"),
                           quantity("tangential traction Tt", u["stress"], "E",
                                    "on the cap per reference area, positive = +x")),
            "slip_state": (("step", "surface_point"), prof("slip_state", np.int8),
                           flag_attributes(SlipState, "friction state of the surface point")),
            **_slip_profiles(recs, prof("slip"), u["length"]),
        })
    s = result.scalars
    data.update({
        "peak_Ft": ((), s["peak_Ft"], quantity("peak Ft", u["force"], "E L0 W", "largest |Ft| while sliding (signed)")),
        "onset_ubar": ((), s["onset_ubar"], quantity("onset ubar", u["length"], "L0",
                                                     "ubar at the onset of full sliding (NaN: not reached)")),
        "onset_Ft": ((), s["onset_Ft"], quantity("onset Ft", u["force"], "E L0 W", "Ft at the onset of full sliding")),
        "onset_area": ((), s["onset_area"], quantity("onset area", u["length"], "L0",
                                                     "contact area at the onset of full sliding")),
    })
    snaps = result.snapshots
    k, nn, nc = len(snaps), mesh.n_nodes, mesh.n_cells
    data.update({
        "cell_nodes": (("cell", "cell_node"), mesh.cells.astype(np.int64),
                       quantity("node ids of the cell", "1", description=CELL_NODE_ORDER)),
        "u_node": (("snapshot_ubar", "node"), np.array([sn.u[:, 0] for sn in snaps]).reshape(k, nn),
                   quantity("x displacement of the node", u["length"], "L0")),
        "v_node": (("snapshot_ubar", "node"), np.array([sn.u[:, 1] for sn in snaps]).reshape(k, nn),
                   quantity("y displacement of the node", u["length"], "L0")),
        "I1_sigma": (("snapshot_ubar", "cell"), np.array([sn.I1_sigma for sn in snaps]).reshape(k, nc),
                     quantity("I1(sigma)", u["stress"], "E",
                             "first invariant of the Cauchy stress (with sigma_zz), cell average")),
    })
    coords = {
        "step": ("step", np.arange(len(recs), dtype=np.int32), quantity("converged load step", "1")),
        "phase": ("step", step("phase", np.int8), flag_attributes(Phase, "load phase")),
        "ubar": ("step", step("ubar"), quantity("tangential displacement of the substrate", u["length"], "L0")),
        "h": ("step", step("h"), quantity("substrate height h", u["length"], "L0",
                                      "height of the substrate's lower face above the base")),
        "X_reference": ("surface_point", surface_reference_x(mesh, p.mesh.surface_gauss_points) if recs else np.zeros(0),
                        quantity("reference x of the surface Gauss point", u["length"], "L0")),
        "snapshot_ubar": ("snapshot_ubar", np.array([sn.ubar for sn in snaps], dtype=float),
                          quantity("ubar of the field snapshot", u["length"], "L0")),
        "X_node": ("node", mesh.nodes[:, 0], quantity("reference x of the node", u["length"], "L0")),
        "Y_node": ("node", mesh.nodes[:, 1], quantity("reference y of the node", u["length"], "L0")),
    }
    if p.loading.velocity is not None:  # time is tracked
        coords["time"] = ("step", step("time"), quantity("time since the start of the approach", "s"))
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
