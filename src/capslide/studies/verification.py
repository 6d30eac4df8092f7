"""Normal-contact verification against Hertz and JKR line-contact solutions.

A scene is swept through compressive line loads P = -Fn; at each load the
FE half-width is compared with the closed form of :mod:`capslide.analytic`.
The half-width is half the current length where g_n <= g_max (JKR: the
edge of the surfaces held together; the tensile cohesive zone beyond it is
small when the Maugis parameter is large) or where Tn > 0 (Hertz,
repulsion only). The JKR load at the FE half-width is compared relative to
the larger of its own size and the pull-off load |P_c| (the load scale of
the JKR curve; near zero load a relative error of P itself is meaningless).

Two ways through the loads:

* force control (Hertz; JKR scenes without ``loading.approach_edge_step``):
  approach, the loads largest first, then a retraction past the closed-form
  pull-off; the largest tensile force that still had an equilibrium is the
  FE pull-off;
* edge control (JKR scenes with ``loading.approach_edge_step``, stiff
  short-range laws whose contact edge snaps under force control): one path
  with the contact edge as the load parameter, from first contact through
  the pull-off point (its largest tensile force is the FE pull-off) to the
  largest compressive load, with an exact force-controlled equilibrium at
  every load of the sweep.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np

from ..config import SPHERE_ELEMENTS
from ..io.reading import ResultFileError
from ..io.sweep_checkpoint import SavedSweep
from ..laws import analytic, sphere
from ..loadpath.cap import load_path, spread_constraint, spread_control
from ..loadpath.continuation import Leg, LegEnd, Loop, StepControl, continuation, drain, newton_options, solve_constrained
from ..loadpath.measures import StepRecord, interval_measures, measure
from ..model import cost
from ..model.build import build_model, cap_mesh_spec, mesh_spec
from ..model.constraints import FixedEdgeGap, FixedForce
from ..model.system import CapModel, History
from ..params import Parameters
from ..states import Phase, Status

__all__ = ["VerificationFailed", "VerificationRow", "sweep", "scene_of", "pressure_error", "reference_half_width",
           "force_controlled_sweep", "edge_controlled_sweep", "MAUGIS_JKR"]

# The JKR closed form is a valid reference for Maugis parameters above about 5 (Baney & Hui 1997; Johnson &
# Greenwood 2008); below it the cohesive zone is wide and the FE state is not a JKR state (the DMT-JKR transition).
MAUGIS_JKR = 5.0


class VerificationFailed(RuntimeError):
    """A step of the sweep found no equilibrium (the solver gave up); no table is written."""


@dataclass
class VerificationRow:
    scene: str
    quantity: str  # half_width, load_at_half_width, pressure_L2, pull_off
    load: float  # P = -Fn (E L0 W) at which the row is measured; nan for the pull-off row (the load is the result)
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


def scene_of(params: Parameters) -> str:
    """The scene a configuration is: hertz (repulsion only) or jkr (the full CGCM law)."""
    return "hertz" if params.contact.repulsion_only else "jkr"


def reference_half_width(model: CapModel, rec: StepRecord, values: np.ndarray) -> float:
    """Half the reference length of the top surface where ``values`` (per surface point, as in the record) <= 0."""
    return 0.5 * interval_measures(model.contact.quad.X.reshape(-1, 2), values)[0]


def sweep(params: Parameters, scene: str | None = None, progress=None, saved=None, save=None) -> list[VerificationRow]:
    """Run the scene's load sweep and compare with the closed forms (``scene`` defaults to :func:`scene_of`);
    ``saved`` and ``save``: the edge-controlled sweep's checkpoints (:func:`edge_controlled_sweep`)."""
    scene = scene or scene_of(params)
    cost.check(params, cap_mesh_spec(params))
    model = build_model(params)
    a, L, g = params.adhesion, params.loading, params.geometry
    E_star = analytic.effective_modulus(params.material.E, params.material.nu)
    adhesive = not params.contact.repulsion_only
    w = a.W_adh if adhesive else 0.0
    loads = sorted(params.verification.loads, reverse=True)
    records: list[StepRecord] = []
    if adhesive and L.approach_edge_step > 0.0:
        states, F_max, how = edge_controlled_sweep(model, loads, records, progress, saved, save)
    else:
        states, F_max, how = force_controlled_sweep(model, loads, records, progress, adhesive)
    P_c = analytic.jkr_cylinder_pull_off(g.R, E_star, w) if adhesive else math.nan
    closed_form = {"R": g.R, "E_star": E_star, "w": w}  # P(a) = pi E* a^2/(4R) - sqrt(2 pi E* w a); w = 0: Hertz
    if adhesive:  # the Maugis parameter says whether the JKR closed form is a reference at all
        lam = analytic.maugis_parameter_cylinder(g.R, E_star, w, a.T_max)
        closed_form.update(maugis_lambda=round(lam, 3), jkr_valid="yes" if lam >= MAUGIS_JKR else "no")
    rows: list[VerificationRow] = []
    for P in loads:
        rec = states[P]
        if adhesive:
            a_fe = 0.5 * rec.area
            a_th = analytic.jkr_cylinder_half_width(P, g.R, E_star, w)
            a_ref = reference_half_width(model, rec, rec.gap - params.contact.area_gap)
            rows.append(VerificationRow(scene, "half_width", P, a_fe, a_th, dict(closed_form)))
            rows.append(VerificationRow(scene, "half_width_reference", P, a_ref, a_th, dict(closed_form)))
            P_a = float(analytic.jkr_cylinder_load(a_fe, g.R, E_star, w))
            rows.append(VerificationRow(scene, "load_at_half_width", P, P, P_a,
                                        {"half_width": a_fe, "relative_to": max(abs(P_a), abs(P_c)),
                                         "jkr_valid": closed_form["jkr_valid"]}))
        else:
            a_fe = 0.5 * rec.area_compressive
            a_th = float(analytic.hertz_line_half_width(P, g.R, E_star))
            Tn, _ = model.contact.normal_law.traction(rec.gap)
            rows.append(VerificationRow(scene, "half_width", P, a_fe, a_th, dict(closed_form)))
            rows.append(VerificationRow(scene, "half_width_reference", P, reference_half_width(model, rec, -Tn), a_th,
                                        dict(closed_form)))
            rows.append(VerificationRow(scene, "pressure_L2", P, pressure_error(rec, P, g.R, E_star), 0.0))
    if adhesive:
        rows.append(VerificationRow(scene, "pull_off", math.nan, -F_max, P_c,
                                    {"status": how, "maugis_lambda": closed_form["maugis_lambda"],
                                     "jkr_valid": closed_form["jkr_valid"]}))
    return rows


class Recording:
    """Keeps the records of the steps of a sweep and shows each to ``progress`` (a callable of a record)."""

    def __init__(self, records: list[StepRecord], progress):
        self.records, self.progress = records, progress

    def __call__(self, step) -> None:
        self.records.append(step.record)
        if self.progress:
            self.progress(step.record)

    def notice(self, notice) -> None:
        """Show a notice of the path (a cut-back) to ``progress``, where it takes notices."""
        show = getattr(self.progress, "notice", None)
        if show is not None:
            show(notice)


def force_leg(model: CapModel, x: np.ndarray, Fn: float, observe, ends=None) -> tuple[Loop, LegEnd]:
    """Force control from the state x (at the normal force of the last record) to ``Fn``."""
    L = model.params.loading
    control = StepControl(L.force_step, L.min_force_step, L.force_step, max_cutbacks=L.max_cutbacks)
    start = observe.records[-1].Fn
    loop = Loop.start(x, start, Fn, control)
    end = drain(continuation(model, loop, History(), Leg(FixedForce, Fn, control, Phase.PRELOAD, "preload", ends=ends)),
                observe)
    return loop, end


def pull_off_reference(params: Parameters) -> float:
    """The closed-form pull-off load P_c (compressive positive, so negative) of a scene: the JKR cylinder in 2D (per
    unit width), the Maugis-Dugdale sphere at the scene's Maugis parameter in 3D (:mod:`capslide.laws.sphere`)."""
    E_star = analytic.effective_modulus(params.material.E, params.material.nu)
    R, w = params.geometry.R, params.adhesion.W_adh
    if params.mesh.element in SPHERE_ELEMENTS:
        lam = sphere.maugis_parameter_sphere(R, E_star, w, params.adhesion.T_max)
        return sphere.md_pull_off(lam)[0] * math.pi * w * R
    return analytic.jkr_cylinder_pull_off(R, E_star, w)


def force_controlled_sweep(model: CapModel, loads: list[float], records: list[StepRecord], progress,
                           adhesive: bool) -> tuple[dict[float, StepRecord], float, str]:
    """Approach, then force control through the loads (largest compressive first); with adhesion, retract
    past the closed-form pull-off: the largest tensile force with an equilibrium is the FE pull-off."""
    g = model.params.geometry
    observe = Recording(records, progress)
    end = drain(load_path(model, stop_before="preload"), observe)
    if end.status != Status.COMPLETED:
        raise VerificationFailed(end.reason)
    x, states = end.x, {}
    for P in loads:
        loop, leg = force_leg(model, x, -P, observe)
        if leg.status != Status.COMPLETED:
            raise VerificationFailed(f"at P = {P}: {leg.reason}")
        x, states[P] = loop.x, records[-1]
    if not adhesive:
        return states, math.nan, ""
    P_c = pull_off_reference(model.params)
    lost = 1e-3 * g.R ** (model.dim - 1)  # a contact length (2D) or area (3D) this small is lost
    _, leg = force_leg(model, x, -1.5 * P_c, observe, ends=lambda r: Status.DETACHED if r.area < lost else None)
    return states, max(r.Fn for r in records), leg.status.label


def edge_controlled_sweep(model: CapModel, loads: list[float], records: list[StepRecord], progress,
                          saved: SavedSweep | None = None, save=None) -> tuple[dict[float, StepRecord], float, str]:
    """Apex approach, then one edge-controlled path (the ``spread`` leg of :mod:`capslide.loadpath.cap`) from first
    contact through the pull-off point to the largest compressive load; it stops on the stable branch (past the
    largest tensile force) just beyond each load in turn, where :func:`_equilibrium_at_load` finds the equilibrium
    at exactly that load between the two bracketing steps. The largest tensile force along the path is the FE
    pull-off (under force control there is no equilibrium beyond it).

    Each load's leg starts from a fresh factorization. ``save`` (a callable of a :class:`SavedSweep`) is called
    after the approach, after each load and every ``verification.checkpoint_every`` converged steps inside a leg (with
    a fresh factorization after it; not where the path's history holds state, friction or a viscous bulk);
    ``saved`` continues such a save: the same arithmetic as the uninterrupted sweep."""
    observe = Recording(records, progress)
    if saved is None:
        end = drain(load_path(model, stop_before="spread"), observe)
        if end.status != Status.COMPLETED:
            raise VerificationFailed(end.reason)
        saved = SavedSweep(end.x, 0.0, list(records), {}, len(records))
        if save:
            save(saved)
    records[:] = saved.records
    first = saved.first
    constraint_of, X_end = spread_constraint(model)
    control = spread_control(model)

    def path_forces() -> list[float]:
        return [r.Fn for r in records[first:] if r.phase == Phase.SPREAD]

    x, X = saved.x, saved.X
    done = dict(saved.done)
    states = {P: records[i] for P, i in done.items()}
    loop = saved.loop
    for P in sorted(loads):  # most tensile first
        if P in done:
            continue
        if loop is None and done and -path_forces()[-1] >= P:  # a fresh leg after a load's
            raise VerificationFailed(f"at P = {P}: the path's state of the load before is already at {-path_forces()[-1]:.6g}; "
                                     f"two loads lie within one edge step (loading.approach_edge_step)")
        model.solver.invalidate()
        until = _stop_past_load(path_forces, P)
        loop = loop if loop is not None else Loop.start(x, X, X_end, control)
        in_leg = _saving_inside_leg(observe, model, save, lambda: SavedSweep(loop.x, loop.value, list(records),
                                                                             dict(done), first, loop))
        leg = drain(continuation(model, loop, History(), Leg(constraint_of, X_end, control, Phase.SPREAD, "approach",
                                                             ends=until)), in_leg, observe.notice)
        if leg.status != Status.COMPLETED or not leg.reason:
            raise VerificationFailed(f"at P = {P}: {leg.reason or 'the contact edge reached the end of the top surface'}")
        if P < -max(path_forces()):
            raise VerificationFailed(f"P = {P} is more tensile than the FE pull-off load {-max(path_forces()):.6g}")
        edge = [r for r in records[first:] if r.phase == Phase.SPREAD]
        bracket = ((loop.value_prev, -edge[-2].Fn, loop.x_prev), (loop.value, -edge[-1].Fn, loop.x))
        states[P] = _equilibrium_at_load(model, bracket, P, records, progress)
        done[P] = len(records) - 1  # its record, the last one
        x, X, loop = loop.x, loop.value, None
        if save:
            save(SavedSweep(x, X, list(records), dict(done), first))
    return states, max(path_forces()), "largest tensile force along the edge-controlled path"


def _saving_inside_leg(observe: Recording, model: CapModel, save, saved_now):
    """``observe``, and every ``verification.checkpoint_every`` converged steps of a leg that goes on, a fresh
    factorization (whether or not it saves, so that the arithmetic is the configuration's) and
    ``save(saved_now())``: only where the step's history is empty (frictionless, elastic, compressible), since a
    leg resumes from ``History()``."""
    every, count = model.params.verification.checkpoint_every, [0]

    def step(converged) -> None:
        observe(converged)
        count[0] += 1
        if every and count[0] % every == 0 and converged.end is None and _empty(converged.history):
            model.solver.invalidate()
            if save:
                save(saved_now())

    return step


def _empty(history: History) -> bool:
    h = history
    return all(v is None for v in (h.anchors, h.slip, h.pressure, h.networks, h.thresholds)) and h.time == 0.0


def _stop_past_load(path_forces, P: float):
    """A load leg's ``ends(rec)``: completed where the step to ``rec`` crosses the load P on the stable branch.
    ``path_forces()`` is Fn along the path so far, without ``rec``: a leg calls ``ends`` before its observer
    appends the record."""
    return lambda rec: Status.COMPLETED if _crossed_on_stable_branch([*path_forces(), rec.Fn], P) else None


def _crossed_on_stable_branch(forces: list[float], P: float, n: int = 3) -> bool:
    """The last step crossed the compressive load P = -Fn upward (from below P to at least P), and the path has
    fallen in Fn at ``n`` steps in a row somewhere before: it is past its largest tensile force, on the stable
    branch. The last two states then bracket P, however jagged the path is."""
    if len(forces) < 2 or not -forces[-2] < P <= -forces[-1]:
        return False
    falls = [b < a for a, b in zip(forces[:-1], forces[1:])]
    return any(all(falls[i:i + n]) for i in range(len(falls) - n + 1))


def _equilibrium_at_load(model: CapModel, bracket, P: float, records: list[StepRecord], progress,
                         max_solves: int = 20) -> StepRecord:
    """The equilibrium at load P (phase preload) between two edge-controlled states ``bracket`` = ((X0, P0, x0),
    (X1, P1, x1)) with P0 < P <= P1: regula falsi (Illinois) on the edge abscissa X, each an edge-controlled solve
    from the interpolated state (if that fails, from the nearer bracketing state), until the load is within 1e-4 |P_c|
    of P; then one Newton solve under force control from there. (Force control straight from the bracket needs too
    many iterations for stiff laws: the edge moves a steep cohesive zone by up to a whole step.)"""
    t0 = time.perf_counter()
    p = model.params
    E_star = analytic.effective_modulus(p.material.E, p.material.nu)
    tol = 1e-4 * abs(pull_off_reference(p))
    opts = newton_options(model)
    (X0, P0, x0), (X1, P1, x1) = bracket
    if not P0 < P <= P1:
        a = p.adhesion
        raise VerificationFailed(f"at P = {P}: the load along the edge path is not monotone here ({P0:.6g}, {P1:.6g}); "
                                 f"a mesh too coarse for the cohesive zone traps the edge (E* w / T_max^2 = "
                                 f"{E_star * a.W_adh / a.T_max ** 2:.3g} L0, surface elements "
                                 f"{mesh_spec(p).h0:.3g} L0)")
    f0, f1 = P0 - P, P1 - P  # f0 < 0 <= f1: the load grows with X on the stable branch
    w0, w1 = f0, f1  # the values the interpolation uses (Illinois: an end kept twice gets half its value)
    x, side, its, lin = x1, 0, 0, 0
    for _ in range(max_solves):
        if min(abs(f0), abs(f1)) <= tol:
            x = x1 if abs(f1) <= abs(f0) else x0
            break
        t = w0 / (w0 - w1)
        X, guess = X0 + t * (X1 - X0), x0 + t * (x1 - x0)
        c = FixedEdgeGap(X, p.loading.approach_end_gap)
        res, _ = solve_constrained(model, c, History(), guess, opts)
        its, lin = its + res.iterations, lin + res.linear_iterations
        if not res.converged:  # once more from the nearer bracketing state
            res, _ = solve_constrained(model, c, History(), x0 if t < 0.5 else x1, opts)
            its, lin = its + res.iterations, lin + res.linear_iterations
        if not res.converged:
            raise VerificationFailed(f"at P = {P}: edge-controlled solve at X = {X:.6g} failed ({res.reason})")
        f = -model.contact.force(res.x[:-1], res.x[-1], 0.0)[1] - P
        if f > 0:
            X1, f1, w1, x1 = X, f, f, res.x
            w0 = 0.5 * w0 if side == 1 else w0
            side = 1
        else:
            X0, f0, w0, x0 = X, f, f, res.x
            w1 = 0.5 * w1 if side == -1 else w1
            side = -1
    else:
        raise VerificationFailed(f"at P = {P}: load not bracketed to {tol:.2g} in {max_solves} edge-controlled solves")
    c = FixedForce(-P)
    res, solved = solve_constrained(model, c, History(), x, opts)
    if not res.converged:
        raise VerificationFailed(f"at P = {P}: force-controlled solve failed ({res.reason})")
    rec = measure(model, res.x, solved, Phase.PRELOAD, 0.0, its + res.iterations, lin + res.linear_iterations,
                  time.perf_counter() - t0)
    records.append(rec)
    if progress:
        progress(rec)
    return rec


TABLE_COLUMNS = ["scene", "quantity", "load_P", "fe", "theory", "rel_error", "extra"]


def table_rows(rows: list[VerificationRow]) -> list[dict]:
    """The rows of a sweep as the CSV table's rows (strings, 8 significant digits)."""
    return [{"scene": r.scene, "quantity": r.quantity, "load_P": f"{r.load:.8g}", "fe": f"{r.fe:.8g}",
             "theory": f"{r.theory:.8g}", "rel_error": f"{r.rel_error:.6g}",
             "extra": ";".join(f"{k}={v}" for k, v in r.extra.items())} for r in rows]


def read_tables(paths) -> list[dict]:
    """The rows of verification CSV tables (``capslide verify``), in order; ResultFileError for anything else."""
    import csv

    rows = []
    for path in paths:
        try:
            with open(path, newline="", encoding="utf-8") as fh:
                reader = csv.DictReader(fh)
                part = list(reader)
        except (OSError, UnicodeDecodeError, csv.Error) as err:
            raise ResultFileError(f"cannot read table '{path}': {err}") from None
        if reader.fieldnames != TABLE_COLUMNS:
            raise ResultFileError(f"'{path}' is not a verification table (columns {', '.join(TABLE_COLUMNS)})")
        rows += part
    return rows
