"""What is measured at a converged state: the step record, field snapshots, and the onset of full sliding.

Internal units (stress E, length L0, force per width E L0). Sign conventions of docs/theory.md section 3: Fn on the cap
positive when tensile, Ft positive in the sliding direction, Tn positive when repulsive.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, fields

import numpy as np

from ..fem.surface import SurfaceQuadrature, stretch
from ..model.system import CapModel, History
from ..states import Phase, SlipState
from .contact_patch import contact_patch

__all__ = ["StepRecord", "RECORD_SCALARS", "RECORD_PROFILES", "RECORD_PROFILES_3D", "Snapshot", "measure", "field_snapshot",
           "dissipation", "external_work_and_residual", "surface_reference_x", "case_energies",
           "interval_measures", "fully_sliding", "sliding_onset", "peeling_off"]


@dataclass
class StepRecord:
    """One converged load step (internal units)."""

    phase: Phase
    ubar: float
    h: float
    Fn: float
    Ft: float
    area: float
    area_compressive: float
    area_stick: float
    x_left: float
    x_right: float
    newton_iterations: int
    krylov_iterations: int
    wall_time: float
    x_surface: np.ndarray = field(repr=False)
    y_surface: np.ndarray = field(repr=False)
    gap: np.ndarray = field(repr=False)
    traction_n: np.ndarray = field(repr=False)
    traction_t: np.ndarray = field(repr=False)
    slip_state: np.ndarray = field(repr=False)
    reaction: np.ndarray = field(default_factory=lambda: np.zeros(2), repr=False)  # internal force at the clamped base
    area_reference: float = math.nan  # reference length of the contact area
    x_stick_left: float = math.nan  # current x of the stick zone's edges (NaN: nothing sticks)
    x_stick_right: float = math.nan
    elastic_energy: float = math.nan  # strain energy of the bulk (E L0^2 per width)
    adhesion_energy: float = math.nan  # adhesive potential of the interface (E L0^2 per width)
    penalty_energy: float = math.nan  # elastic energy of the tangential penalty (E L0^2 per width)
    slip: np.ndarray = field(default_factory=lambda: np.zeros(0), repr=False)  # the anchors' move in the step (L0)
    time: float = 0.0  # s, at the end of the step (0 throughout when quasi-static)
    steady_step: bool = False  # taken in one as steady sliding, to the next breakpoint or the leg's end
    snapped: bool = False  # a step passed by snap-through (solver.snap_through): a jump, not a quasi-static step
    width_y: float = math.nan  # 3D: the contact's width along y, the whole body's (L0); NaN in 2D
    traction_t_y: np.ndarray = field(default_factory=lambda: np.zeros(0), repr=False)  # 3D: T_t's y part; 2D: empty
    slip_y: np.ndarray = field(default_factory=lambda: np.zeros(0), repr=False)  # 3D: the anchors' y move; 2D: empty


# The record's fields, from its definition: scalars, and arrays (per surface point; the base reaction); the y parts of
# the tangential vectors are empty in 2D
RECORD_PROFILES = tuple(f.name for f in fields(StepRecord) if f.type == "np.ndarray")
RECORD_PROFILES_3D = ("traction_t_y", "slip_y")
RECORD_SCALARS = tuple(f.name for f in fields(StepRecord) if f.name not in RECORD_PROFILES)


@dataclass
class Snapshot:
    """Field state at one tangential displacement."""

    ubar: float
    u: np.ndarray  # (n_nodes, d), L0
    I1_sigma: np.ndarray  # (n_cells,), E
    h: float = math.nan  # the substrate's height (L0; NaN: not kept, older files)
    slip_state: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=np.int8), repr=False)  # per surface point


def measure(model: CapModel, x: np.ndarray, history: History, phase: Phase, ubar: float, newton_its: int,
            krylov_its: int, wall: float, dt: float = 0.0) -> StepRecord:
    """Per-step scalars and surface profiles of the converged state x; ``history`` is the history the step of dt
    seconds started from (its slip is the move of the anchors at the commit)."""
    u, h = model.split(x)
    c = model.contact
    g, xs = c.gaps(u, h)
    Tn, _ = c.traction(g)
    Tn = c.theta(u) * Tn  # per reference area
    _, Fn, Ft = c.force(u, h, ubar, *history.friction)
    Tt, state = c.tangential_state(u, h, ubar, *history.friction)
    pts, gg, tn, st = xs.reshape(-1, model.dim), g.ravel(), Tn.ravel(), state.ravel()
    open_gap = gg - model.params.contact.area_gap
    width = math.nan
    if model.dim == 3:
        area, xl, xr, width, area_r, area_c = _patch_measures(model, u, h)
        area_s, sl, sr = _stick_measures(model, u, xs, state)
    else:
        area, xl, xr = interval_measures(pts, open_gap)
        area_r, _, _ = interval_measures(c.quad.X.reshape(-1, 2), open_gap)
        Tn_full, _ = c.normal_law.traction(g)  # compressive where > 0, also when repulsion only
        area_c, _, _ = interval_measures(pts, -Tn_full.ravel())
        area_s, sl, sr = interval_measures(pts, np.where(st == SlipState.STICK, -1.0, 1.0))
        sl, sr = max(sl, xl), min(sr, xr)  # the stick indicator's midpoints may lie past the gap's edges (NaN stays)
    slip = np.zeros(Tt.shape)
    if c.friction_active(history.anchors):  # the anchors move by the slip of the step (zero where sticking)
        slip = c.committed_anchors(u, h, ubar, *history.friction) - history.anchors
    # the penalty's elastic energy: T_t = -eps_t times the elastic tangential gap after the step
    Tt2 = Tt.ravel() ** 2 if model.dim == 2 else np.sum(Tt**2, axis=-1).ravel()
    penalty = float(np.sum(Tt2 * c.quad.weight.ravel())) / (2.0 * c.eps_t) if c.eps_t > 0 else 0.0
    if model.dim == 3:  # the tangential vectors' x parts in the profiles, their y parts beside them
        penalty = c.whole(penalty)
        Tt, Tt_y, slip, slip_y = Tt[..., 0], Tt[..., 1].ravel().copy(), slip[..., 0], slip[..., 1].ravel().copy()
    else:
        Tt_y, slip_y = np.zeros(0), np.zeros(0)
    return StepRecord(phase, ubar, h, Fn, Ft, area, area_c, area_s, xl, xr, newton_its, krylov_its, wall,
                      pts[:, 0].copy(), pts[:, 1].copy(), gg.copy(), tn.copy(), Tt.ravel().copy(), st.copy(),
                      model.base_reaction(x, history, dt), area_reference=area_r, x_stick_left=sl, x_stick_right=sr,
                      elastic_energy=model.strain_energy(x, history, dt),
                      adhesion_energy=c.adhesion_energy(u, h), penalty_energy=penalty,
                      slip=slip.ravel(), time=history.time + dt, width_y=width, traction_t_y=Tt_y, slip_y=slip_y)


def _patch_measures(model: CapModel, u: np.ndarray, h: float) -> tuple[float, ...]:
    """3D: the contact area (g_n <= the contact gap, current), its x ends and y width, the same area in the
    reference configuration and the compressive area (g_n <= g_eq: Tn >= 0), from the nodal gaps of the top faces
    (:mod:`capslide.loadpath.contact_patch`)."""
    mesh, c = model.mesh, model.contact
    X = mesh.nodes
    x = X + u.reshape(-1, 3)
    g = h - x[:, 2]
    faces, k = mesh.surface_quads, c.multiplicity
    patch = contact_patch(x, g - model.params.contact.area_gap, faces, k)
    reference = contact_patch(X, g - model.params.contact.area_gap, faces, k)
    compressive = contact_patch(x, g - model.params.adhesion.g_eq, faces, k)
    return patch.area, patch.x_left, patch.x_right, patch.width_y, reference.area, compressive.area


def _stick_measures(model: CapModel, u: np.ndarray, xs: np.ndarray, state: np.ndarray) -> tuple[float, float, float]:
    """3D: the current area of the sticking Gauss points in contact (the whole body's: the sum of their weights times
    the area stretch J_s) and the smallest and largest current x among them (NaN: nothing sticks)."""
    c = model.contact
    stick = state == SlipState.STICK
    if not stick.any():
        return 0.0, math.nan, math.nan
    _, t = c.quad.current(u)
    J = stretch(t, c.quad.ref_measure, 3)
    x = xs[..., 0][stick]
    return c.whole(float(np.sum((c.quad.weight * J)[stick]))), float(x.min()), float(x.max())


def field_snapshot(model: CapModel, x: np.ndarray, ubar: float, history: History | None = None,
                   slip_state: np.ndarray | None = None) -> Snapshot:
    """Nodal displacements, the cell-averaged I1(sigma), the height and the surface points' friction states of the
    converged state x (``history``: the one after it, with its pressure multiplier and viscous networks;
    ``slip_state``: the step record's, None: as the contact reports them at x with ``history``)."""
    history = history or History()
    if slip_state is None:
        u, h = model.split(x)
        slip_state = model.contact.tangential_state(u, h, ubar, *history.friction)[1].ravel()
    return Snapshot(ubar, x[:-1].reshape(-1, model.dim).copy(), model.cell_first_invariant(x, history), float(x[-1]),
                    np.asarray(slip_state, dtype=np.int8).copy())


def interval_measures(x: np.ndarray, v: np.ndarray) -> tuple[float, float, float]:
    """Length and edges of the part of a polyline where an interpolated value is <= 0.

    ``x`` (n, 2) points ordered along the surface, ``v`` (n,) values at them (for the contact area: g_n minus the
    contact gap). Linear interpolation of v between neighbours. Returns (length, x_left, x_right); edges are NaN
    when no part qualifies.
    """
    v0, v1 = v[:-1], v[1:]
    seg = np.linalg.norm(np.diff(x, axis=0), axis=1)
    both = (v0 <= 0) & (v1 <= 0)
    cross = (v0 <= 0) != (v1 <= 0)
    t = np.where(cross, v0 / np.where(cross, v0 - v1, 1.0), 0.0)  # where v crosses zero, from the first point
    frac = np.where(both, 1.0, np.where(cross, np.where(v0 <= 0, t, 1.0 - t), 0.0))
    length = float(np.sum(frac * seg))
    inside = np.flatnonzero(v <= 0)
    if len(inside) == 0:
        return length, float("nan"), float("nan")
    i, j = inside[0], inside[-1]
    if i > 0:
        ti = v[i - 1] / (v[i - 1] - v[i])
        xl = x[i - 1, 0] + ti * (x[i, 0] - x[i - 1, 0])
    else:
        xl = x[0, 0]
    if j < len(v) - 1:
        tj = v[j] / (v[j] - v[j + 1])
        xr = x[j, 0] + tj * (x[j + 1, 0] - x[j, 0])
    else:
        xr = x[-1, 0]
    return length, float(xl), float(xr)


def fully_sliding(rec: StepRecord) -> bool:
    """A slide step with contact and no sticking point (docs/theory.md section 5: the onset test), not a snap's end
    state: with the thresholds held at a step's start, the points a snap brought into contact carry none in its
    step, and slip (the experiment's re-adhering snaps, docs/experiment3d.md)."""
    return (rec.phase == Phase.SLIDE and rec.ubar != 0.0 and rec.area > 0.0 and not rec.snapped
            and not np.any(rec.slip_state == SlipState.STICK))


def sliding_onset(records: list[StepRecord]) -> dict[str, float]:
    """Peak Ft and the onset of full sliding (first slide step with no sticking point in contact)."""
    slide_recs = [r for r in records if r.phase == Phase.SLIDE]
    out = {"peak_Ft": math.nan, "onset_ubar": math.nan, "onset_Ft": math.nan, "onset_area": math.nan}
    if not slide_recs:
        return out
    Ft = np.array([r.Ft for r in slide_recs])
    out["peak_Ft"] = float(Ft[np.argmax(np.abs(Ft))])
    for r in slide_recs:
        if fully_sliding(r):
            out.update(onset_ubar=r.ubar, onset_Ft=r.Ft, onset_area=r.area)
            break
    return out


ROUND_OFF = 1e-9  # relative changes of area and height at or below this are round-off, not a trend


def peeling_off(records: list[StepRecord], Fn: float, n: int = 4) -> bool:
    """A slide that lost its equilibrium under a tensile load while the contact peeled: over the last ``n`` slide
    steps the contact area shrank and the substrate rose at every step by more than round-off, and in the last step
    the contact's width shrank faster than the stage moved (|d area / d ubar| > 1): the approach to a fold, where
    that rate grows without bound. Shear-induced pull-off: the contact's pull-off force fell below the applied Fn
    (as in the paper's experiments, where small contacts vanish on shearing). A contact that shrinks slowly under
    the growing shear (|d area / d ubar| about 0.4 before a slip-weakening snap) is not peeling."""
    last = [r for r in records[-n:] if r.phase == Phase.SLIDE]
    if Fn <= 0.0 or len(last) < n:
        return False
    area, h, ubar = (np.array([getattr(r, k) for r in last]) for k in ("area", "h", "ubar"))
    dA, dh, du = np.diff(area), np.diff(h), np.diff(ubar)
    trend = np.all(dA < -ROUND_OFF * area[1:]) and np.all(dh > ROUND_OFF * np.maximum(1.0, np.abs(h[1:])))
    return bool(trend and abs(dA[-1]) > abs(du[-1]))


def dissipation(recs, weight: np.ndarray) -> np.ndarray:
    """Frictional work dissipated up to each step (E L0^2 per width): the sum over steps and surface points of
    -(T_t before + T_t after) / 2 . the anchors' move x dA (3D: both components). With the trapezoidal work of the
    loads this closes the energy balance of the return map's elastic-slip split exactly at every step (a
    spring-slider: T dx = T dx_e + T dxi, and (T0 + T1) / 2 (x_e1 - x_e0) is the exact change of the penalty
    energy T^2 / (2 eps_t))."""
    if not recs:
        return np.zeros(0)
    def work(traction: str, slip: str) -> np.ndarray:
        Tt = np.stack([getattr(r, traction) for r in recs])
        before = np.vstack([np.zeros_like(Tt[:1]), Tt[:-1]])  # friction starts with zero tangential gaps
        return -0.5 * ((before + Tt) * np.stack([getattr(r, slip) for r in recs])) @ weight

    if recs[0].traction_t_y.size == 0:  # 2D
        return np.cumsum(work("traction_t", "slip"))
    return np.cumsum(work("traction_t", "slip") + work("traction_t_y", "slip_y"))


def external_work_and_residual(recs, dissipated: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The work of the loads on the substrate, int Fn dh + Ft dubar (trapezoidal rule over the steps), and the
    balance's residual: work - (change of elastic, adhesive and penalty energy) - dissipation (E L0^2 per width)."""
    Fn, Ft, h, ubar = (np.array([getattr(r, k) for r in recs], dtype=float) for k in ("Fn", "Ft", "h", "ubar"))
    dW = 0.5 * (Fn[1:] + Fn[:-1]) * np.diff(h) + 0.5 * (Ft[1:] + Ft[:-1]) * np.diff(ubar)
    work = np.concatenate([np.zeros(min(len(recs), 1)), np.cumsum(dW)])
    stored = np.array([r.elastic_energy + r.adhesion_energy + r.penalty_energy for r in recs], dtype=float)
    return work, work - (stored - stored[:1]) - dissipated


def surface_reference_x(mesh, n_gauss: int, axis: int = 0) -> np.ndarray:
    """Reference x (or the coordinate ``axis``) of the surface Gauss points, in the order of the step records'
    profiles (2D: by reference x)."""
    return SurfaceQuadrature.on(mesh, n_gauss).X[..., axis].ravel()


def case_energies(recs, mesh, n_gauss: int) -> dict[str, np.ndarray]:
    """The energy bookkeeping of a case's steps: ``dissipation``, ``external_work`` and ``energy_residual`` (E L0^2
    per width), with the weights of the surface quadrature the records were measured on."""
    weight = SurfaceQuadrature.on(mesh, n_gauss).weight.ravel()
    dissipated = dissipation(recs, 2.0 * weight if len(mesh.symmetry) else weight)  # a half model: the whole body's
    work, residual = external_work_and_residual(recs, dissipated)
    return {"dissipation": dissipated, "external_work": work, "energy_residual": residual}
