"""Normal-contact verification of the 3D sphere (mesh.element = H1, H2) against the Hertz and Maugis-Dugdale spheres.

The same sweeps as the 2D line contacts (:mod:`capslide.studies.verification`: force control through the loads, or
one edge-controlled path through the pull-off point with an exact force-controlled equilibrium at each load), with
the sphere's closed forms (:mod:`capslide.laws.sphere`). Loads P = -Fn are the whole sphere's (E L0^2, compressive
positive). At each load:

* Hertz (repulsion only; the sphere is first pressed under height control to half the Hertz approach of the
  smallest load, then force control goes through the loads): the contact radius from the pressure's second moment
  (a^2 = 5/2 int p r^2 dA / int p dA, exact for the Hertz pressure), the radius sqrt(A / pi) of the compressive area
  (Tn >= 0, from the nodal gaps: first order in the mesh size), and the largest surface-point pressure against p0;
  and the second-moment radius and the peak against the same repulsive law on a half-space
  (:mod:`capslide.studies.halfspace_hertz`: Hertz but for the law's compliance);
* adhesive: the radius of the contact area (g_n <= g_max, where the tension peaks: the edge of the Maugis-Dugdale
  contact, where the Dugdale stress starts) against the Maugis-Dugdale radius at P and the scene's lambda; the load
  the Maugis-Dugdale solution gives at the FE radius, relative to |P_c|; and the pull-off (the largest tensile force
  with an equilibrium) against Maugis-Dugdale's, with JKR's (lambda -> infinity) in the row's extra;
* adhesive, the same law: the load at the FE radius and the pull-off of the scene's own CGCM law (band, far gap)
  on an elastic half-space with the sphere's profile (:mod:`capslide.studies.halfspace_sphere`). Maugis-Dugdale
  differs from it by the law's shape (2.2 % in the pull-off at lambda = 3: docs/three_d.md); the FE differs from it
  by the mesh, finite strains and the body's finite size;
* adhesive, the same law at a radius inside the cohesive zone: the contact area's radius comes from the nodal gaps
  interpolated linearly across the edge, where the gap touches g_max with zero slope (the opening grows as the
  distance to the power 3/2), so it lies short by about 0.4 ring widths (benchmarks/area_measure_bias.py). The
  radius where the gap reaches g_eq + LEVEL_OVER_RANGE W_adh / T_max (the opening's slope finite there) is read
  within a few hundredths of a ring: the load at that FE radius against the same law's, whose path steps the same
  gap.
"""

from __future__ import annotations

import math
import time

import numpy as np

from ..laws import analytic, sphere
from ..loadpath.continuation import newton_options, solve_constrained
from ..loadpath.measures import StepRecord, measure
from ..model import cost
from ..model.build import build_model, mesh_spec
from ..model.constraints import FixedHeight
from ..model.system import CapModel, History
from ..params import Parameters
from ..states import Phase
from .halfspace_hertz import hertz_law_reference
from .halfspace_sphere import same_law_reference
from .verification import (
    Recording,
    VerificationFailed,
    VerificationRow,
    edge_controlled_sweep,
    force_controlled_sweep,
    force_leg,
    pull_off_reference,
)

__all__ = ["sphere_sweep", "level_radius", "LEVEL_OVER_RANGE"]

LEVEL_OVER_RANGE = 0.3  # the level radius's opening above g_eq, in Maugis-Dugdale's range W_adh / T_max (-)


def sphere_sweep(params: Parameters, scene: str, progress=None, saved=None, save=None) -> list[VerificationRow]:
    """The verification rows of a 3D scene (Hertz, or the adhesive sphere against Maugis-Dugdale); ``saved`` and
    ``save``: the edge-controlled sweep's checkpoints."""
    cost.check(params, mesh_spec(params))
    model = build_model(params)
    a, R = params.adhesion, params.geometry.R
    E_star = analytic.effective_modulus(params.material.E, params.material.nu)
    adhesive = not params.contact.repulsion_only
    loads = sorted(params.verification.loads, reverse=True)
    records = []
    if not adhesive:
        states, F_max, how = _hertz_sweep(model, loads, records, progress)
    elif params.loading.approach_edge_step > 0.0:
        states, F_max, how = edge_controlled_sweep(model, loads, records, progress, saved, save)
    else:
        states, F_max, how = force_controlled_sweep(model, loads, records, progress, adhesive)
    rows: list[VerificationRow] = []
    if not adhesive:
        weight = model.contact.quad.weight.ravel()
        for P in loads:
            rec = states[P]
            a_hertz = float(sphere.hertz_sphere_radius(P, R, E_star))
            p = np.maximum(rec.traction_n, 0.0) * weight
            a_moment = sphere.hertz_moment_radius(p, rec.x_surface**2 + rec.y_surface**2)
            rows.append(VerificationRow(scene, "radius", P, a_moment, a_hertz))
            rows.append(VerificationRow(scene, "radius_area", P, math.sqrt(rec.area_compressive / math.pi), a_hertz))
            rows.append(VerificationRow(scene, "peak_pressure", P, float(rec.traction_n.max()),
                                        float(sphere.hertz_sphere_peak_pressure(P, R, E_star))))
        return rows + _hertz_same_law_rows(params, scene, rows)
    lam = sphere.maugis_parameter_sphere(R, E_star, a.W_adh, a.T_max)
    scales = sphere.md_scales(R, E_star, a.W_adh)
    force, length = scales["load"], scales["radius"]
    P_c = pull_off_reference(params)
    extra = {"maugis_lambda": round(lam, 3)}
    for P in loads:
        a_fe = math.sqrt(states[P].area / math.pi)
        rows.append(VerificationRow(scene, "radius", P, a_fe, sphere.md_radius(P / force, lam) * length,
                                    {**extra, "jkr": float(sphere.jkr_radius(P / force)) * length}))
        P_md = float(sphere.md_load(a_fe / length, lam)) * force
        rows.append(VerificationRow(scene, "load_at_radius", P, P, P_md,
                                    {**extra, "radius": a_fe, "relative_to": abs(P_c)}))
    rows.append(VerificationRow(scene, "pull_off", math.nan, -F_max, P_c, {**extra, "status": how, "jkr": -1.5 * force}))
    rows += _same_law_rows(params, scene, {P: math.sqrt(states[P].area / math.pi) for P in loads}, F_max)
    level = a.g_eq + LEVEL_OVER_RANGE * a.W_adh / a.T_max
    at_loads = [(P, states[P]) for P in loads]
    along_path = [(-r.Fn, r) for r in records if r.phase == Phase.SPREAD]
    return rows + _level_rows(params, scene, at_loads, along_path, level)


def level_radius(x: np.ndarray, y: np.ndarray, g: np.ndarray, level: float, min_points: int = 4) -> float:
    """The mean radius (L0) where the gap ``g`` (L0) at surface points (x, y) first rises through ``level`` (L0)
    going out from the axis, along each radial line of points (a line: the points of one polar angle, lines apart
    by more than 1e-3 rad; fewer than ``min_points`` are not a line), the gap interpolated linearly between
    neighbours on the line; NaN if no line crosses. The top's cells beyond the core are ring sectors, so their
    Gauss points lie on radial lines."""
    theta, rho = np.arctan2(y, x), np.hypot(x, y)
    order = np.argsort(theta)
    lines = np.split(order, np.flatnonzero(np.diff(theta[order]) > 1e-3) + 1)
    radii = []
    for line in lines:
        if line.size < min_points:
            continue
        line = line[np.argsort(rho[line])]
        r, gap = rho[line], g[line]
        above = gap > level
        i = int(np.argmax(above))
        if i > 0 and above[i]:
            radii.append(r[i - 1] + (r[i] - r[i - 1]) * (level - gap[i - 1]) / (gap[i] - gap[i - 1]))
    return float(np.mean(radii)) if radii else math.nan


def _same_law_rows(params: Parameters, scene: str, radii: dict[float, float], F_max: float) -> list[VerificationRow]:
    """The loads at the FE radii ``radii`` ({P: a}) and the pull-off against the same law on a half-space (none
    when its rings would be too many; nan at a radius below the reference path's first)."""
    reference = same_law_reference(params, 1.02 * max(radii.values()))
    if reference is None:
        return []
    extra = {"relative_to": abs(reference.P_c)}
    rows = [VerificationRow(scene, "load_at_radius_same_law", P, P,
                            reference.load_at(a) if a >= reference.radii[0] else math.nan, {**extra, "radius": a})
            for P, a in radii.items()]
    return rows + [VerificationRow(scene, "pull_off_same_law", math.nan, -F_max, reference.P_c,
                                   {"radius": round(reference.a_c, 4)})]


def _hertz_same_law_rows(params: Parameters, scene: str, rows: list[VerificationRow]) -> list[VerificationRow]:
    """The FE's second-moment radius and peak pressure (``rows``) against the same repulsive law's on a half-space
    at the same loads: Hertz apart from the law's compliance."""
    fe = {(r.quantity, r.load): r.fe for r in rows}
    loads = sorted({r.load for r in rows})
    reference = hertz_law_reference(params, loads)
    return [VerificationRow(scene, f"{name}_same_law", P, fe[name, P], getattr(reference[P], attr))
            for P in loads for name, attr in (("radius", "radius_moment"), ("peak_pressure", "peak_pressure"))]


def _level_rows(params: Parameters, scene: str, at_loads, along_path, level: float) -> list[VerificationRow]:
    """The loads at the FE's level radii (the gap ``level``) against the same law's path stepped by that gap: at
    the sweep's loads and along its edge-controlled path (pairs (P, record)); none when the reference would need
    too many rings."""
    radii = {name: [(P, level_radius(r.x_surface, r.y_surface, r.gap, level)) for P, r in pairs]
             for name, pairs in (("load_at_level_radius_same_law", at_loads),
                                 ("path_load_at_level_radius_same_law", along_path))}
    reach = max((r for pairs in radii.values() for _, r in pairs if math.isfinite(r)), default=math.nan)
    reference = same_law_reference(params, 1.02 * reach, edge_gap=level) if math.isfinite(reach) else None
    if reference is None:
        return []
    extra = {"relative_to": abs(reference.P_c), "level": round(level, 6)}
    return [VerificationRow(scene, name, P, P, reference.load_at(r) if r >= reference.radii[0] else math.nan,
                            {**extra, "radius": r})
            for name, pairs in radii.items() for P, r in pairs]


def _hertz_sweep(model: CapModel, loads: list[float], records: list[StepRecord], progress):
    """Press the undeformed sphere under height control by half the Hertz approach a^2 / R of the smallest load
    (a stiff repulsive law gives force control no stiffness to start from at first touch), then force control
    through the loads, largest first."""
    p = model.params
    R, E_star = p.geometry.R, analytic.effective_modulus(p.material.E, p.material.nu)
    depth = 0.5 * float(sphere.hertz_sphere_radius(min(loads), R, E_star)) ** 2 / R
    h = p.geometry.H + p.adhesion.g_eq - depth
    t = time.perf_counter()
    res, history = solve_constrained(model, FixedHeight(h), History(), np.concatenate([np.zeros(model.n_dofs), [h]]),
                                     newton_options(model))
    if not res.converged:
        raise VerificationFailed(f"pressing by {depth:.4g} L0: {res.reason}")
    observe = Recording(records, progress)
    records.append(measure(model, res.x, history, Phase.PRELOAD, 0.0, res.iterations, res.linear_iterations,
                           time.perf_counter() - t))
    x, states = res.x, {}
    for P in loads:
        loop, leg = force_leg(model, x, -P, observe)
        if leg.status.label != "completed":
            raise VerificationFailed(f"at P = {P}: {leg.reason}")
        x, states[P] = loop.x, records[-1]
    return states, math.nan, ""
