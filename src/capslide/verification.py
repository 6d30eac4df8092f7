"""Normal-contact verification against Hertz and JKR line-contact solutions.

A scene is swept through compressive line loads P = -Fn (largest first,
then retracting, as in the experiment); at each load the FE half-width is
compared with the closed form of :mod:`capslide.analytic`. The half-width
is half the current length where g_n <= g_max (JKR: the edge of the
surfaces held together; the tensile cohesive zone beyond it is small when
the Maugis parameter is large) or where Tn > 0 (Hertz, repulsion only).
The JKR load at the FE half-width is compared relative to the larger of
its own size and the pull-off load |P_c| (the load scale of the JKR curve;
near zero load a relative error of P itself is meaningless).
With adhesion, the sweep finally retracts past the closed-form pull-off and
reports the largest tensile force that still had an equilibrium.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from . import analytic
from .loading import StepRecord, continuation
from .mesh import cap_mesh, cap_mesh_spec
from .model import CapModel, FixedApexGap, FixedForce
from .params import Parameters

__all__ = ["VerificationFailed", "VerificationRow", "sweep", "pressure_error"]


class VerificationFailed(RuntimeError):
    """A step of the sweep found no equilibrium (the solver gave up); no table is written."""


@dataclass
class VerificationRow:
    scene: str
    quantity: str  # half_width, load_at_half_width, pressure_L2, pull_off
    load: float  # P = -Fn (E L0 W)
    fe: float
    theory: float
    extra: dict = field(default_factory=dict)  # "relative_to": the error's scale, |theory| if absent

    @property
    def rel_error(self) -> float:
        scale = self.extra.get("relative_to", abs(self.theory))
        return (self.fe - self.theory) / scale if scale else math.nan


def pressure_error(rec: StepRecord, P: float, R: float, E_star: float) -> float:
    """L2 difference of Tn and the Hertz pressure over |x| <= 1.2 a, relative to p0."""
    a = float(analytic.hertz_line_half_width(P, R, E_star))
    x = rec.x_surface
    sel = np.abs(x) <= 1.2 * a
    p_h = analytic.hertz_line_pressure(x[sel], P, R, E_star)
    p0 = 2 * P / (math.pi * a)
    return float(np.sqrt(np.mean((rec.traction_n[sel] - p_h) ** 2)) / p0)


def sweep(params: Parameters, scene: str, progress=None) -> list[VerificationRow]:
    """Run the scene's load sweep and compare with the closed forms."""
    mesh = cap_mesh(cap_mesh_spec(params))
    model = CapModel(mesh, params)
    a, L, g = params.adhesion, params.loading, params.geometry
    E_star = analytic.effective_modulus(params.material.E, params.material.nu)
    adhesive = not params.contact.repulsion_only
    w = a.W_adh if adhesive else 0.0
    records: list[StepRecord] = []
    x = np.zeros(model.n_dofs + 1)
    x[-1] = g.H + L.approach_start_gap
    res = continuation(model, x, FixedApexGap, L.approach_start_gap, L.approach_end_gap, L.approach_step, "approach",
                       records, min_step=1e-4 * a.r0, max_step=L.approach_step, progress=progress)
    if res.status != "completed":
        raise VerificationFailed(res.reason)
    x = res.x
    rows: list[VerificationRow] = []
    loads = sorted(params.config["verification"]["loads"], reverse=True)
    P_c = analytic.jkr_cylinder_pull_off(g.R, E_star, w) if adhesive else math.nan
    closed_form = {"R": g.R, "E_star": E_star, "w": w}  # P(a) = pi E* a^2/(4R) - sqrt(2 pi E* w a); w = 0: Hertz
    for P in loads:
        res = continuation(model, x, FixedForce, records[-1].Fn, -P, L.force_step, "preload", records,
                           min_step=L.min_force_step, max_step=L.force_step, progress=progress)
        if res.status != "completed":
            raise VerificationFailed(f"at P = {P}: {res.reason}")
        x, rec = res.x, records[-1]
        if adhesive:
            a_fe = 0.5 * rec.area
            rows.append(VerificationRow(scene, "half_width", P, a_fe, analytic.jkr_cylinder_half_width(P, g.R, E_star, w),
                                        dict(closed_form)))
            P_a = float(analytic.jkr_cylinder_load(a_fe, g.R, E_star, w))
            rows.append(VerificationRow(scene, "load_at_half_width", P, P, P_a,
                                        {"half_width": a_fe, "relative_to": max(abs(P_a), abs(P_c))}))
        else:
            a_fe = 0.5 * rec.area_compressive
            rows.append(VerificationRow(scene, "half_width", P, a_fe, float(analytic.hertz_line_half_width(P, g.R, E_star)),
                                        dict(closed_form)))
            rows.append(VerificationRow(scene, "pressure_L2", P, pressure_error(rec, P, g.R, E_star), 0.0))
    if adhesive:  # retract past the closed-form pull-off: the last equilibrium is the FE pull-off
        res = continuation(model, x, FixedForce, records[-1].Fn, -1.5 * P_c, L.force_step, "preload", records,
                           min_step=L.min_force_step, max_step=L.force_step, progress=progress,
                           stop=lambda r: "detached" if r.area < 1e-3 * g.R else None)
        F_max = max(r.Fn for r in records)
        rows.append(VerificationRow(scene, "pull_off", P_c, -F_max, P_c, {"status": res.status}))
    return rows
