"""Speed against error: the runs of a convergence study, their errors, orders and Pareto front.

A study spec (``config/convergence.yaml``) names
base cases (config overrides) and sweeps: each sweep varies one config key over
a list of values on top of its own fixed overrides. Every (case, sweep, value)
becomes a run; runs with the same overrides share one case file.
:func:`evaluate` reads the case files into :class:`RunResult` records and
turns them into the table, the observed convergence orders and the
error-versus-time front that the figure draws; the rest are pure functions.

Quantities of interest (QoIs), normalized as in the case files: peak Ft
(E L0 W), onset ubar (L0), contact area at onset (L0), Ft at ubar = 4 L0
(E L0 W). Errors are relative: |q - q_ref| / |q_ref|.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..io.reading import ResultFileError, open_result
from ..states import Phase

__all__ = ["QOIS", "Run", "RunResult", "check_spec", "study_runs", "run_overrides", "quantities", "reference",
           "observed_orders", "pareto_front", "error_rows", "order_rows", "cheapest_within", "TABLE_COLUMNS", "ORDER_COLUMNS",
           "markdown_table", "read_results", "evaluate"]

QOIS = ("peak_Ft", "onset_ubar", "onset_area", "Ft_at_4")
QOI_UBAR = 4.0  # L0: the ubar of the QoI Ft_at_4
REFINEMENT_KEYS = ("mesh.size", "mesh.max_size_over_H")  # sweeps that refine: observed orders are reported


@dataclass(frozen=True)
class Run:
    """One row of the study: base case, sweep, swept value, and the case file it reads (``run_id``)."""

    case: str
    sweep: str
    value: object
    run_id: str


@dataclass
class RunResult:
    """What the table needs from one case file."""

    status: str
    qoi: dict[str, float]
    wall_time: float
    n_dofs: int
    steps: int
    newton_iterations: int
    krylov_iterations: int


def check_spec(spec) -> None:
    """Raise ValueError naming the first cross-reference of a convergence spec that does not hold (its types and
    keys are checked by the schema, :func:`capslide.studies.expansion.runs`)."""
    for name, sw in spec["sweeps"].items():
        for c in sw.get("cases", []):
            if c not in spec["cases"]:
                raise ValueError(f"sweeps.{name}.cases: '{c}' is not a case (cases: {', '.join(spec['cases'])})")
        if sw["key"] not in spec.get("base", {}):
            raise ValueError(f"sweeps.{name}.key = {sw['key']!r} must have a value in 'base' (the default of the knob)")
    ref = spec["reference"]
    if ref["sweep"] not in spec["sweeps"]:
        raise ValueError(f"reference.sweep = {ref['sweep']!r} is not a sweep (sweeps: {', '.join(spec['sweeps'])})")
    if ref["value"] not in spec["sweeps"][ref["sweep"]]["values"]:
        raise ValueError(f"reference.value = {ref['value']!r} is not a value of sweeps.{ref['sweep']}")


def _fmt(value) -> str:
    return f"{value:g}" if isinstance(value, float) else str(value)


def run_overrides(spec: dict, case: str, sweep: str, value) -> dict:
    """The config overrides of one run: study base, base case, the sweep's fixed set, the swept key."""
    sw = spec["sweeps"][sweep]
    sets = {**spec.get("base", {}), **spec["cases"][case], **sw.get("set", {})}
    sets[sw["key"]] = value
    return sets


def _run_id(spec: dict, sets: dict, case: str) -> str:
    """File stem of a run: its overrides that differ from the study base and the base case, sorted
    ("default" when none do). The base states every knob a sweep varies, so ids do not depend on config files."""
    common = {**spec.get("base", {}), **spec["cases"][case]}
    missing = object()
    parts = [f"{k.split('.')[-1]}-{_fmt(v)}" for k, v in sorted(sets.items()) if common.get(k, missing) != v]
    return "__".join(parts) or "default"


def study_runs(spec: dict) -> list[Run]:
    """Every (case, sweep, value) of the spec; runs with equal overrides share a ``run_id``, hence a case file."""
    runs = []
    for sweep, sw in spec["sweeps"].items():
        for case in sw.get("cases", list(spec["cases"])):
            for value in sw["values"]:
                runs.append(Run(case, sweep, value, _run_id(spec, run_overrides(spec, case, sweep, value), case)))
    return runs


def quantities(phase: np.ndarray, ubar: np.ndarray, Ft: np.ndarray, peak_Ft: float, onset_ubar: float,
               onset_area: float) -> dict[str, float]:
    """The QoIs of one case from its step arrays and scalars; Ft at ubar = 4 L0 interpolated over the slide
    (exact when a step ends there, as when ubar_max = 4); NaN when the slide did not reach it."""
    slide = phase == Phase.SLIDE
    u, f = ubar[slide], Ft[slide]
    at4 = float(np.interp(QOI_UBAR, u, f)) if u.size and u.min() <= QOI_UBAR <= u.max() else math.nan
    return {"peak_Ft": float(peak_Ft), "onset_ubar": float(onset_ubar), "onset_area": float(onset_area), "Ft_at_4": at4}


def observed_orders(h: np.ndarray, q: np.ndarray) -> np.ndarray:
    """Observed orders p_i = log(|q_i - q_{i+1}| / |q_{i+1} - q_{i+2}|) / log(h_i / h_{i+1}) of a sequence refined
    by a constant ratio (h decreasing); NaN where a difference is zero."""
    h, q = np.asarray(h, float), np.asarray(q, float)
    d = np.abs(np.diff(q))
    with np.errstate(divide="ignore", invalid="ignore"):
        p = np.log(d[:-1] / d[1:]) / np.log(h[:-2] / h[1:-1])
    return np.where(np.isfinite(p), p, np.nan)


def reference(h: np.ndarray, q: np.ndarray, regular: float = 0.3) -> tuple[float, str, float]:
    """Reference value of a refinement sequence (h decreasing): the finest value, or its Richardson extrapolation
    q_f + (q_f - q_c) / (r^p - 1) when the last two observed orders p agree within ``regular`` (relative) and
    lie in [0.5, 4]. Returns (value, 'richardson' or 'finest', p)."""
    h, q = np.asarray(h, float), np.asarray(q, float)
    finest = float(q[-1])
    last = slice(-4, None) if len(q) >= 4 else slice(None)
    p = observed_orders(h[last], q[last]) if len(q) >= 3 else np.array([math.nan])
    p_last = float(p[-1]) if np.isfinite(p[-1]) else math.nan
    if len(p) >= 2 and np.all(np.isfinite(p)) and 0.5 <= p[-1] <= 4.0 and abs(p[-1] - p[-2]) <= regular * abs(p[-1]):
        r = h[-2] / h[-1]
        return finest + (finest - float(q[-2])) / (r ** p[-1] - 1.0), "richardson", p_last
    return finest, "finest", p_last


def pareto_front(time: np.ndarray, error: np.ndarray) -> np.ndarray:
    """Boolean mask of the runs no other run beats in both wall time and error (NaN errors never on it)."""
    t, e = np.asarray(time, float), np.asarray(error, float)
    ok = np.isfinite(t) & np.isfinite(e)
    mask = np.zeros(len(t), dtype=bool)
    best = math.inf
    for i in sorted(np.flatnonzero(ok), key=lambda i: (t[i], e[i])):
        if e[i] < best:
            mask[i], best = True, e[i]
    return mask


def error_rows(spec: dict, runs: list[Run], results: dict[str, RunResult]) -> tuple[list[dict], dict]:
    """Table rows (one per run) with QoIs, relative errors against the reference and the run's cost, and the
    reference of each case: {case: {qoi: (value, kind, order)}}. ``results`` maps (case, run_id) -> RunResult.

    The reference comes from the reference sweep, Richardson-extrapolated per QoI where regular.
    ``error`` is the largest relative error over the QoIs; ``change`` the same against the run of the same sweep
    at the knob's default (the study base), which isolates the knob.
    """
    ref_sweep, ref_value = spec["reference"]["sweep"], spec["reference"]["value"]
    refs: dict[str, dict] = {}
    for case in spec["cases"]:
        seq = [r for r in runs if r.case == case and r.sweep == ref_sweep and (r.case, r.run_id) in results]
        if not any(r.value == ref_value for r in seq):
            raise ValueError(f"the reference run ({ref_sweep} = {ref_value}) of case {case} is missing")
        # coarse to the reference (larger values are coarser)
        upto = sorted((r for r in seq if float(r.value) >= float(ref_value)), key=lambda r: -float(r.value))
        h = np.array([float(r.value) for r in upto])
        refs[case] = {}
        for qname in QOIS:
            q = np.array([results[(r.case, r.run_id)].qoi[qname] for r in upto])
            refs[case][qname] = reference(h, q)
    rows = []
    for r in runs:
        res = results.get((r.case, r.run_id))
        if res is None:
            continue
        row = {"case": r.case, "sweep": r.sweep, "key": spec["sweeps"][r.sweep]["key"], "value": _fmt(r.value),
               "run": r.run_id, "status": res.status, "n_dofs": res.n_dofs, "steps": res.steps,
               "newton_iterations": res.newton_iterations, "krylov_iterations": res.krylov_iterations,
               "wall_time_s": round(res.wall_time, 2)}
        errs = []
        for qname in QOIS:
            q, (qr, _, _) = res.qoi[qname], refs[r.case][qname]
            err = abs(q - qr) / abs(qr) if qr != 0 and math.isfinite(q) else math.nan
            row[qname], row[f"err_{qname}"] = q, err
            errs.append(err)
        row["error"] = max(errs) if all(math.isfinite(e) for e in errs) else math.nan
        rows.append(row)
    _add_changes(spec, rows)
    return rows, refs


def order_rows(spec: dict, rows: list[dict]) -> list[dict]:
    """Observed orders of every refinement sweep (key in ``REFINEMENT_KEYS``), per case and QoI, from consecutive
    triplets of the table's runs (coarse to fine): p = log(|q1 - q2| / |q2 - q3|) / log(h1 / h2)."""
    out = []
    for sweep, sw in spec["sweeps"].items():
        if sw["key"] not in REFINEMENT_KEYS:
            continue
        for case in spec["cases"]:
            seq = sorted((r for r in rows if r["case"] == case and r["sweep"] == sweep), key=lambda r: -float(r["value"]))
            if len(seq) < 3:
                continue
            h = np.array([float(r["value"]) for r in seq])
            for qname in QOIS:
                p = observed_orders(h, np.array([float(r[qname]) for r in seq]))
                for i, pi in enumerate(p):
                    out.append({"case": case, "sweep": sweep, "qoi": qname,
                                "sizes": "/".join(_fmt(float(v)) for v in h[i:i + 3]), "order": float(pi)})
    return out


def cheapest_within(rows: list[dict], threshold: float) -> dict | None:
    """The run (same overrides in every case) whose largest error over all cases is below ``threshold`` at the
    least total wall time: {"run", "error", "wall_time_s"}, or None. This is how presets are chosen."""
    cases = {r["case"] for r in rows}
    by_run: dict[str, list[dict]] = {}
    for r in rows:
        by_run.setdefault(r["run"], []).append(r)
    best = None
    for run, rs in by_run.items():
        per_case = {r["case"]: r for r in rs}
        if set(per_case) != cases or any(r["status"] != "completed" for r in rs):
            continue
        err = max(float(r["error"]) for r in per_case.values())
        wall = sum(float(r["wall_time_s"]) for r in per_case.values())
        if err < threshold and (best is None or wall < best["wall_time_s"]):
            best = {"run": run, "error": err, "wall_time_s": wall}
    return best


def _add_changes(spec: dict, rows: list[dict]) -> None:
    """``change``: largest relative QoI change against the run of the same sweep and case whose swept key has its
    study-base value (the knob at its default, everything else equal); NaN when the sweep has no such run."""
    base = spec.get("base", {})
    for row in rows:
        key = spec["sweeps"][row["sweep"]]["key"]
        ref = next((o for o in rows if o["case"] == row["case"] and o["sweep"] == row["sweep"]
                    and key in base and o["value"] == _fmt(base[key])), None)
        ch = [abs(row[q] - ref[q]) / abs(ref[q]) if ref is not None and ref[q] else math.nan for q in QOIS]
        row["change"] = max(ch) if all(math.isfinite(c) for c in ch) else math.nan


ORDER_COLUMNS = ["case", "sweep", "qoi", "sizes", "order"]
TABLE_COLUMNS = ["case", "sweep", "key", "value", "run", "status", "n_dofs", "steps", "newton_iterations",
                 "krylov_iterations", "wall_time_s", *QOIS, *(f"err_{q}" for q in QOIS), "error", "change", "pareto"]


def _cell(value) -> str:
    if isinstance(value, float):
        if not math.isfinite(value):
            return "-"
        return f"{value:.2e}" if value != 0 and abs(value) < 1e-3 else f"{value:.5g}"
    if isinstance(value, bool):
        return "yes" if value else ""
    return str(value)


def markdown_table(rows: list[dict], columns: list[str] | None = None) -> str:
    cols = columns or TABLE_COLUMNS
    lines = ["| " + " | ".join(cols) + " |", "|" + "---|" * len(cols)]
    lines += ["| " + " | ".join(_cell(r.get(c, "")) for c in cols) + " |" for r in rows]
    return "\n".join(lines) + "\n"


def read_results(spec: dict, cases_dir: str | Path) -> tuple[list[Run], dict[tuple[str, str], RunResult]]:
    """The runs of the spec and what the table needs of each case file ``cases_dir/{case}/{run_id}.nc``."""
    runs = study_runs(spec)
    results = {}
    for key in dict.fromkeys((r.case, r.run_id) for r in runs):
        path = Path(cases_dir) / key[0] / f"{key[1]}.nc"
        if not path.is_file():
            raise ResultFileError(f"case file '{path}' does not exist (run: snakemake --cores 2 convergence)")
        ds = open_result(path, "case")
        q = quantities(ds["phase"].values, ds["ubar"].values, ds["Ft"].values, float(ds["peak_Ft"]),
                       float(ds["onset_ubar"]), float(ds["onset_area"]))
        results[key] = RunResult(str(ds.attrs.get("status")), q, float(ds.attrs.get("case_wall_time", np.nan)),
                                 int(ds.attrs["n_dofs"]), int(ds.sizes["step"]), int(ds["newton_iterations"].sum()),
                                 int(ds["krylov_iterations"].sum()))
    return runs, results


def evaluate(spec: dict, cases_dir: str | Path) -> tuple[list[dict], dict, list[dict]]:
    """Table rows (Pareto front marked per case), the reference of each case, and the observed orders."""
    runs, results = read_results(spec, cases_dir)
    rows, refs = error_rows(spec, runs, results)
    for case in spec["cases"]:
        idx = [i for i, row in enumerate(rows) if row["case"] == case]
        mask = pareto_front([rows[i]["wall_time_s"] for i in idx], [rows[i]["error"] for i in idx])
        for i, on in zip(idx, mask):
            rows[i]["pareto"] = bool(on)
    return rows, refs, order_rows(spec, rows)
