"""Load path (DESIGN section 5): approach, force-controlled preload, sliding at fixed Fn.

Every phase is an adaptive continuation in one scalar load parameter: the
apex gap during the approach (local displacement control follows the
jump-in instability through its turning point, so every recorded state is
an exact equilibrium with no artificial term), optionally followed by the
half-width of the contact (its edge held at the end gap while it spreads:
for stiff, short-range laws the apex gap turns too), then the normal force.
Steps grow after easy Newton solves and are halved after failures; below
the minimum step the phase ends with a reason instead of looping.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from typing import Callable

import numpy as np

from . import contact
from .checkpoint import Checkpointer, ContinuationState
from .interface import STICK, interval_measures
from .mesh import H0_AT_SIZE_1
from .model import CapModel, FixedApexGap, FixedEdgeGap, FixedForce, SlideAtForce
from .newton import NewtonOptions, newton

__all__ = ["PHASES", "StepRecord", "PathResult", "measure", "newton_options", "solve_constrained", "continuation", "approach", "approach_apex",
           "spread_contact", "approach_and_preload", "slide", "run_load_path", "sliding_onset", "fully_sliding",
           "peeling_off"]

PHASES = ("approach", "preload", "slide")


@dataclass
class StepRecord:
    """One converged load step (internal units)."""

    phase: str
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


@dataclass
class PathResult:
    records: list[StepRecord]
    x: np.ndarray
    status: str  # completed, detached, diverged
    reason: str = ""
    min_step: float = math.inf
    cutbacks: int = 0
    value: float = math.nan  # load parameter of the last converged state (continuation only)
    x_prev: np.ndarray | None = field(default=None, repr=False)  # the converged state one step before x
    value_prev: float = math.nan  # its load parameter


def measure(model: CapModel, x: np.ndarray, phase: str, ubar: float, newton_its: int, krylov_its: int,
            wall: float) -> StepRecord:
    """Per-step scalars and surface profiles of a converged state."""
    u, h = model.split(x)
    g, xs = model.contact.gaps(u, h)
    Tn, _ = model.contact.traction(g)
    a = model.params.adhesion
    Tn_full, _ = contact.normal_traction(g, a.T0, a.r0, a.g_reg)  # compressive where > 0, also when repulsion only
    _, Fn, Ft = model.contact.force(u, h, ubar)
    Tt, state = model.contact.tangential_state(u, h, ubar)
    pts, gg, tn, st = xs.reshape(-1, 2), g.ravel(), Tn.ravel(), state.ravel()
    area, xl, xr = interval_measures(pts, gg - model.params.contact.area_gap)
    area_c, _, _ = interval_measures(pts, -Tn_full.ravel())
    area_s, _, _ = interval_measures(pts, np.where(st == STICK, -1.0, 1.0))
    return StepRecord(phase, ubar, h, Fn, Ft, area, area_c, area_s, xl, xr, newton_its, krylov_its, wall,
                      pts[:, 0].copy(), pts[:, 1].copy(), gg.copy(), tn.copy(), Tt.ravel().copy(), st.copy(),
                      model.base_reaction(x))


def newton_options(model: CapModel) -> NewtonOptions:
    """Newton tolerances of the configuration."""
    s = model.params.solver
    return NewtonOptions(rtol=s.newton_rtol, atol=s.newton_atol, max_iterations=s.newton_max_iterations)


def solve_constrained(model: CapModel, constraint, x0: np.ndarray, opts: NewtonOptions):
    """Newton from x0 on the cap's equations plus the scalar ``constraint`` (forces in E L0, r_ref = 1)."""
    return newton(lambda z: model.residual(z, constraint), lambda z: model.linearize(z, constraint), x0, opts,
                  r_ref=1.0, admissible=model.admissible)


def continuation(
    model: CapModel,
    x: np.ndarray,
    constraint: Callable[[float], object],
    start: float,
    end: float,
    first_step: float,
    phase: str,
    records: list[StepRecord],
    min_step: float,
    max_step: float,
    progress: Callable[[StepRecord], None] | None = None,
    stop: Callable[[StepRecord], str | None] | None = None,
    breakpoints: tuple[float, ...] = (),
    on_breakpoint: Callable[[float, np.ndarray], None] | None = None,
    step_limit: Callable[[list[StepRecord], float], float] | None = None,
    ckpt: Checkpointer | None = None,
    easy_iterations: int = 4,
) -> PathResult:
    """Adaptive continuation of the load parameter from ``start`` to ``end``.

    ``constraint(value)`` builds the model constraint for a parameter value.
    ``stop(record)`` may end the phase early with a status ("detached").
    Steps end exactly on every value in ``breakpoints``, where
    ``on_breakpoint(value, x)`` is called. ``step_limit(records, value)``
    may cap the next step. The step grows by 1.5 after a solve of at most
    ``easy_iterations`` Newton iterations. With a checkpointer ``ckpt`` the
    stage is numbered, saved every few steps, and replayed or resumed on a
    restart.
    """
    if ckpt is None:
        return _continuation(model, x, constraint, start, end, first_step, phase, records, min_step, max_step, progress,
                             stop, breakpoints, on_breakpoint, step_limit, None, None, easy_iterations)
    stage, mode = ckpt.begin_stage()
    if mode == "done":
        status, reason, cutbacks, smallest, x_end = ckpt.finished[stage]
        return PathResult(records, x_end, status, reason, smallest, cutbacks)
    resume = None
    if mode == "resume":
        resume = ckpt.resume_state
        model.contact.anchors = None if ckpt.anchors is None else ckpt.anchors.copy()
    res = _continuation(model, x, constraint, start, end, first_step, phase, records, min_step, max_step, progress, stop,
                        breakpoints, on_breakpoint, step_limit, ckpt, resume, easy_iterations)
    ckpt.end_stage(res.status, res.reason, res.cutbacks, res.min_step, res.x)
    return res


def _continuation(model, x, constraint, start, end, first_step, phase, records, min_step, max_step, progress, stop,
                  breakpoints, on_breakpoint, step_limit, ckpt, resume: ContinuationState | None,
                  easy_iterations: int = 4) -> PathResult:
    direction = 1.0 if end >= start else -1.0
    value, step = start, min(abs(first_step), max_step)
    x_prev, value_prev = None, None
    smallest, cutbacks = math.inf, 0
    opts = newton_options(model)
    tol = 1e-12 * max(1.0, abs(end))
    pending = sorted((b for b in breakpoints if direction * (b - start) > tol and direction * (end - b) >= -tol),
                     key=lambda b: direction * b)
    if resume is not None:
        value, step, x, x_prev = resume.value, resume.step, resume.x.copy(), resume.x_prev
        value_prev, smallest, cutbacks, pending = resume.value_prev, resume.smallest, resume.cutbacks, list(resume.pending)
        direction = 1.0 if end >= value else -1.0
    while direction * (end - value) > tol:
        step = min(step, abs(end - value))
        if step_limit is not None:
            step = max(min(step, step_limit(records, value)), min_step)
        if pending:
            step = min(step, abs(pending[0] - value))
        target = value + direction * step
        if pending and abs(target - pending[0]) <= tol:
            target = pending[0]
        t0 = time.perf_counter()
        x0 = x
        if x_prev is not None and value_prev != value:  # secant predictor
            x0 = x + (x - x_prev) * ((target - value) / (value - value_prev))
            if not model.admissible(x0):
                x0 = x
        c = constraint(target)
        res = solve_constrained(model, c, x0, opts)
        if not res.converged:
            cutbacks += 1
            step *= 0.5
            if cutbacks > model.params.loading.max_cutbacks:
                return PathResult(records, x, "diverged", f"{phase}: more than {model.params.loading.max_cutbacks} "
                                  f"cut-backs, stopped at {value:.6g} ({res.reason})", smallest, cutbacks)
            if step < min_step:
                return PathResult(records, x, "diverged", f"{phase}: step below minimum {min_step:g} at "
                                  f"{value:.6g} ({res.reason})", smallest, cutbacks)
            continue
        x_prev, value_prev = x, value
        x, value = res.x, target
        smallest = min(smallest, step)
        ubar = getattr(c, "ubar", 0.0)
        rec = measure(model, x, phase, ubar, res.iterations, res.linear_iterations, time.perf_counter() - t0)
        model.contact.commit(x[:-1], x[-1], ubar)  # friction history only at converged steps, after recording
        records.append(rec)
        if progress:
            progress(rec)
        if pending and target == pending[0]:
            pending.pop(0)
            if on_breakpoint:
                on_breakpoint(target, x)
        if stop and (status := stop(rec)):
            return PathResult(records, x, status, f"{phase}: {status} at {value:.6g}", smallest, cutbacks, value, x_prev,
                              math.nan if value_prev is None else value_prev)
        if res.iterations <= easy_iterations:
            step = min(step * 1.5, max_step)
        if ckpt is not None:
            ckpt.after_step(lambda: ContinuationState(value, step, x, x_prev, value_prev, smallest, cutbacks, list(pending)),
                            model.solver, model.contact.anchors)
    return PathResult(records, x, "completed", "", smallest, cutbacks, value, x_prev,
                      math.nan if value_prev is None else value_prev)


def approach(model: CapModel, records: list[StepRecord], progress=None, ckpt: Checkpointer | None = None) -> PathResult:
    """Approach from above the apex until adhesive contact forms.

    The apex gap goes from ``approach_start_gap`` down to ``approach_end_gap``;
    with ``approach_edge_step`` > 0 the contact then spreads under edge control
    (:func:`spread_contact`) until Fn <= 0.
    """
    res = approach_apex(model, records, progress, ckpt)
    if res.status != "completed" or model.params.loading.approach_edge_step == 0.0:
        return res
    res2 = spread_contact(model, res.x, 0.0, records, lambda rec: rec.Fn <= 0.0, progress, ckpt)
    res2.cutbacks += res.cutbacks
    res2.min_step = min(res.min_step, res2.min_step)
    return res2


def approach_apex(model: CapModel, records: list[StepRecord], progress=None, ckpt: Checkpointer | None = None) -> PathResult:
    """The apex gap from ``approach_start_gap`` down to ``approach_end_gap``, starting undeformed."""
    p = model.params
    a, L = p.adhesion, p.loading
    x = np.zeros(model.n_dofs + 1)
    x[-1] = p.geometry.H + L.approach_start_gap
    return continuation(model, x, FixedApexGap, L.approach_start_gap, L.approach_end_gap, L.approach_step, "approach",
                        records, min_step=1e-4 * a.r0, max_step=L.approach_step, progress=progress, ckpt=ckpt)


def spread_contact(model: CapModel, x: np.ndarray, X_start: float, records: list[StepRecord],
                   until: Callable[[StepRecord], bool], progress=None, ckpt: Checkpointer | None = None) -> PathResult:
    """Spread the contact under edge control, from edge abscissa ``X_start`` until ``until(record)`` (status
    completed, the edge abscissa in ``value``) or the end of the top surface.

    The surface points at reference abscissa +-X are held at the approach's
    end gap while X grows in steps of at most ``approach_edge_step``. X is the
    contact half-width when the end gap is the contact gap g_max; the load is
    a single-valued function of it through the snap-in, where force, h and
    the apex gap all turn, and on through the pull-off point (JKR: P(a)).
    """
    L = model.params.loading
    X_surface = model.mesh.nodes[model.mesh.surface_nodes[[0, -1]], 0]
    X_end = float(np.min(np.abs(X_surface)))
    step = L.approach_edge_step
    # easy_iterations 6: each step moves a steep cohesive zone, Newton takes 5-7 iterations even for short steps
    return continuation(model, x, lambda X: FixedEdgeGap(X, L.approach_end_gap), X_start, X_end, 0.25 * step, "approach",
                        records, min_step=1e-4 * step, max_step=step, progress=progress,
                        stop=lambda rec: "completed" if until(rec) else None, ckpt=ckpt, easy_iterations=6)


def approach_and_preload(model: CapModel, progress=None, ckpt: Checkpointer | None = None) -> PathResult:
    """Approach from above the apex, then ramp Fn to the target preload.

    Tensile targets are reached by retracting from a compressed state
    (``loading.retract_from``), as in the experiment.
    """
    p = model.params
    L = p.loading
    records: list[StepRecord] = ckpt.records if ckpt is not None else []
    # 1. approach until contact forms
    res = approach(model, records, progress, ckpt)
    if res.status != "completed":
        return res
    x, cut, smallest = res.x, res.cutbacks, res.min_step
    # 2. preload: force control to the target (through a compressed state for tensile targets)
    targets = [L.preload]
    approach_Fn = [r for r in records if r.phase == "approach"][-1].Fn  # (records may run further on a resume)
    if L.preload > 0.0 and L.retract_from < min(approach_Fn, L.preload):
        targets = [L.retract_from, L.preload]
    min_area = 2.0 * H0_AT_SIZE_1 * p.mesh.size

    def detached(rec: StepRecord) -> str | None:
        return "detached" if rec.area < min_area else None

    for target in targets:
        retracting = target > records[-1].Fn  # only a retraction can pull the contact off
        res = continuation(model, x, FixedForce, records[-1].Fn, target, L.force_step, "preload", records,
                           min_step=L.min_force_step, max_step=L.force_step, progress=progress,
                           stop=detached if retracting else None, ckpt=ckpt)
        cut += res.cutbacks
        smallest = min(smallest, res.min_step)
        if res.status == "diverged" and target > records[-1].Fn and target > 0:
            # no equilibrium at the requested tensile force: pull-off
            return PathResult(records, res.x, "detached", f"pull-off: no equilibrium beyond Fn = {records[-1].Fn:.6g}",
                              smallest, cut)
        if res.status != "completed":
            res.cutbacks, res.min_step = cut, smallest
            return res
        x = res.x
    return PathResult(records, x, "completed", "", smallest, cut)


def slide(model: CapModel, x: np.ndarray, records: list[StepRecord], progress=None, snapshot_ubar=(),
          on_snapshot=None, ckpt: Checkpointer | None = None) -> PathResult:
    """Slide the substrate from ubar = 0 to ubar_max at the fixed normal force (the last record's Fn).

    With ``loading.stop_at_onset`` the slide ends at the onset of full
    sliding; with ``loading.slide_back`` it returns to ubar = 0 afterwards.
    """
    p = model.params
    L = p.loading
    Fn = L.preload
    fresh = ckpt is None or not ckpt.replaying()  # on a resume, anchors and snapshot come from the checkpoint
    if fresh:
        model.contact.start_friction(x[:-1], 0.0)
    min_area = 2.0 * H0_AT_SIZE_1 * p.mesh.size

    def stop(rec: StepRecord) -> str | None:
        if rec.area < min_area:
            return "detached"
        if L.stop_at_onset and fully_sliding(rec):
            return "completed"  # asked to end at the onset of full sliding
        return None

    if fresh and on_snapshot is not None and any(b == 0.0 for b in snapshot_ubar):
        on_snapshot(0.0, x)
    res = continuation(model, x, lambda ubar: SlideAtForce(ubar, Fn), 0.0, L.ubar_max, L.slide_step, "slide",
                       records, min_step=L.min_slide_step, max_step=L.max_slide_step, progress=progress,
                       stop=stop, breakpoints=tuple(snapshot_ubar), on_breakpoint=on_snapshot,
                       step_limit=onset_step_limit, ckpt=ckpt)
    if res.status == "diverged" and peeling_off(records, Fn):
        last = records[-1]
        res.status = "detached"
        res.reason = (f"slide: no equilibrium at Fn = {Fn:.6g} beyond ubar = {last.ubar:.6g}; the contact was peeling off "
                      f"(area {last.area:.4g}, shrinking, h rising)")
    elif res.status == "completed" and res.reason:
        res.reason = f"slide: stopped at the onset of full sliding, ubar = {records[-1].ubar:.6g}"
    elif res.status == "completed" and L.slide_back and L.ubar_max != 0.0:
        back = continuation(model, res.x, lambda ubar: SlideAtForce(ubar, Fn), L.ubar_max, 0.0, L.slide_step, "slide",
                            records, min_step=L.min_slide_step, max_step=L.max_slide_step, progress=progress,
                            stop=stop, step_limit=onset_step_limit, ckpt=ckpt)
        back.cutbacks += res.cutbacks
        back.min_step = min(back.min_step, res.min_step)
        if back.reason:
            back.reason = back.reason.replace("slide:", "slide back:", 1)
        return back
    return res


def peeling_off(records: list[StepRecord], Fn: float, n: int = 4) -> bool:
    """A slide that lost its equilibrium under a tensile load while the contact peeled: over the last ``n``
    slide steps the contact area shrank and the substrate rose at every step. Shear-induced pull-off: the
    contact's pull-off force fell below the applied Fn (as in the paper's experiments, where small contacts
    vanish on shearing)."""
    last = [r for r in records[-n:] if r.phase == "slide"]
    if Fn <= 0.0 or len(last) < n:
        return False
    area, h = np.array([r.area for r in last]), np.array([r.h for r in last])
    return bool(np.all(np.diff(area) < 0) and np.all(np.diff(h) > 0))


def fully_sliding(rec: StepRecord) -> bool:
    """A slide step with contact and no sticking point (DESIGN section 5: the onset test)."""
    return rec.phase == "slide" and rec.ubar != 0.0 and rec.area > 0.0 and not np.any(rec.slip_state == STICK)


def onset_step_limit(records: list[StepRecord], ubar: float, tolerance: float = 0.005) -> float:
    """Largest next slide step while the stick zone closes: the onset of full sliding is then found to
    about ``tolerance`` |ubar|, whatever the step size elsewhere.

    The onset is predicted by extrapolating the stick area of the last two
    slide steps linearly to zero; the step is at most half the predicted
    remaining distance, and at least ``tolerance`` |ubar|.
    """
    last = [r for r in records[-2:] if r.phase == "slide"]
    if len(last) < 2 or last[-1].area_stick <= 0.0:
        return math.inf
    (u0, a0), (u1, a1) = [(r.ubar, r.area_stick) for r in last]
    if a1 >= a0 or u1 == u0:
        return math.inf
    u_onset = u1 + a1 * (u1 - u0) / (a0 - a1)
    # approach the predicted onset in halving steps: the stick zone shrinks faster than linearly at the end
    return max(0.5 * abs(u_onset - ubar), tolerance * abs(ubar))


def run_load_path(model: CapModel, progress=None, snapshot_ubar=(), on_snapshot=None,
                  ckpt: Checkpointer | None = None) -> PathResult:
    """Approach, preload and slide; the result carries every converged step.

    With a checkpointer the path is saved every few steps (and resumed from a loaded checkpoint)."""
    res = approach_and_preload(model, progress, ckpt)
    if res.status != "completed" or model.params.loading.ubar_max == 0.0:
        return res
    res2 = slide(model, res.x, res.records, progress, snapshot_ubar, on_snapshot, ckpt)
    res2.cutbacks += res.cutbacks
    res2.min_step = min(res.min_step, res2.min_step)
    return res2


def sliding_onset(records: list[StepRecord]) -> dict[str, float]:
    """Peak Ft and the onset of full sliding (first slide step with no sticking point in contact)."""
    slide_recs = [r for r in records if r.phase == "slide"]
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
