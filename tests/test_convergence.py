"""Convergence study: orders, Richardson reference, Pareto front, run ids; a small study against its raw case files."""

import csv
import math

import numpy as np
import pytest
import xarray as xr
import yaml

from capslide.config import ConfigError
from capslide.studies.convergence import (
    QOIS,
    RunResult,
    error_rows,
    observed_orders,
    pareto_front,
    quantities,
    reference,
    study_runs,
)
from capslide.studies.expansion import runs as expand

from conftest import snakemake


def test_observed_order_and_richardson_recover_a_known_limit():
    h = np.array([16.0, 8.0, 4.0, 2.0, 1.0])
    q = 1.5 + 0.3 * h**2 * (1 + 0.01 * h)  # order 2 with a small higher-order term
    p = observed_orders(h, q)
    assert p[-1] == pytest.approx(2.0, abs=0.05)
    value, kind, order = reference(h, q)
    assert kind == "richardson" and order == pytest.approx(2.0, abs=0.05)
    assert abs(value - 1.5) < 0.05 * abs(q[-1] - 1.5)  # far closer to the limit than the finest value
    # irregular (oscillating) differences: the finest value is the reference
    q_bad = 1.0 + np.array([1e-2, -3e-3, 4e-3, -1e-4, 2e-4])
    assert reference(h, q_bad)[1] == "finest" and reference(h, q_bad)[0] == q_bad[-1]


def test_pareto_front():
    t = np.array([1.0, 2.0, 3.0, 4.0, 0.5, np.nan])
    e = np.array([0.1, 0.2, 0.01, 0.001, 0.5, 1e-9])
    assert pareto_front(t, e).tolist() == [True, False, True, True, True, False]


SPEC = {
    "cases": {"A": {"friction.model": "DI"}, "B": {"friction.model": "EA"}},
    "base": {"mesh.size": 8, "mesh.surface_gauss_points": 4},
    "reference": {"sweep": "mesh", "value": 2},
    "sweeps": {"mesh": {"key": "mesh.size", "values": [8, 4, 2]},
               "gauss": {"key": "mesh.surface_gauss_points", "values": [2, 4], "set": {"mesh.size": 8}, "cases": ["A"]}},
}


def test_runs_share_files_and_ids_name_the_changes():
    runs = study_runs(SPEC)
    assert len(runs) == 3 + 3 + 2
    ids = {(r.case, r.run_id) for r in runs}
    assert ("A", "default") in ids and ("A", "surface_gauss_points-2") in ids and ("B", "size-2") in ids
    assert len(ids) == 7  # gauss = 4 at size 8 is the mesh run at size 8
    for bad, message in (({**SPEC, "reference": {"sweep": "mesh", "value": 1}}, "reference.value = 1"),
                         ({**SPEC, "sweeps": {"x": {"key": "friction.eps_t", "values": [1]}}}, "must have a value in 'base'"),
                         ({**SPEC, "cases": []}, "'cases' must be a section"),
                         ({**SPEC, "sweeps": {"m": {"key": "mesh.size"}}}, "missing key 'sweeps.m.values'")):
        with pytest.raises(ConfigError, match=message):
            expand(bad, "convergence")


def test_error_rows_against_the_reference():
    runs = study_runs(SPEC)
    qoi = lambda v: dict(zip(QOIS, (v, 2 * v, 3 * v, 4 * v)))  # noqa: E731
    values = {"default": 1.1, "size-4": 1.02, "size-2": 1.0, "surface_gauss_points-2": 1.05}
    results = {(r.case, r.run_id): RunResult("completed", qoi(values[r.run_id]), 10.0, 100, 5, 10, 50) for r in runs
               if r.case == "A"}
    rows, refs = error_rows({**SPEC, "cases": {"A": SPEC["cases"]["A"]}}, [r for r in runs if r.case == "A"], results)
    by = {(r["sweep"], r["value"]): r for r in rows}
    assert refs["A"]["peak_Ft"] == (1.0, "finest", pytest.approx(2.0))  # differences 0.08, 0.02; 3 levels: no Richardson
    assert by[("mesh", "8")]["error"] == pytest.approx(0.1)
    assert by[("gauss", "2")]["err_onset_area"] == pytest.approx(0.05)
    assert by[("gauss", "2")]["change"] == pytest.approx(abs(1.05 - 1.1) / 1.1)  # against size 8 with 4 points
    assert by[("mesh", "4")]["change"] == pytest.approx(abs(1.02 - 1.1) / 1.1)  # against the base size 8


def test_quantities_interpolate_Ft_at_4():
    phase = np.array([0, 1, 2, 2, 2])
    ubar = np.array([0.0, 0.0, 0.0, 3.0, 5.0])
    Ft = np.array([0.0, 0.0, 0.0, 1.0, 2.0])
    q = quantities(phase, ubar, Ft, 2.0, 1.0, 9.0)
    assert q["Ft_at_4"] == pytest.approx(1.5) and q["onset_area"] == 9.0
    assert math.isnan(quantities(phase, ubar / 2, Ft, 2.0, 1.0, 9.0)["Ft_at_4"])


SMALL = """
cases:
  DI_Fn+0.000: {friction.model: DI, loading.preload: 0.0}
base: {mesh.size: 32, mesh.element: Q1, mesh.surface_gauss_points: 4, loading.ubar_max: 4.0,
       loading.max_slide_step: 0.25, output.snapshot_ubar: [], output.surface_profiles: false}
reference: {sweep: mesh, value: 16}
sweeps:
  mesh: {key: mesh.size, values: [32, 16]}
  gauss: {key: mesh.surface_gauss_points, values: [2, 4], set: {mesh.size: 32}}
"""


@pytest.mark.slow
def test_small_study_table_matches_the_raw_case_files(workdir):
    """snakemake convergence on a tiny spec; every error in the table recomputed from the case files."""
    (workdir / "config" / "convergence.yaml").write_text(SMALL)
    res = snakemake(workdir, "convergence")
    assert res.returncode == 0, res.stdout[-3000:] + res.stderr[-3000:]
    out = workdir / "results" / "paper" / "studies" / "convergence"  # the default configuration's folder
    rows = list(csv.DictReader((out / "table.csv").open()))
    assert [(r["sweep"], r["value"]) for r in rows] == [("mesh", "32"), ("mesh", "16"), ("gauss", "2"), ("gauss", "4")]
    raw = {}
    for r in rows:
        with xr.open_dataset(out / "cases" / r["case"] / f"{r['run']}.nc") as ds:
            slide = ds["phase"].values == 2
            assert ds["ubar"].values[slide][-1] == pytest.approx(4.0, abs=1e-12)
            assert "gap" not in ds  # surface profiles off in studies
            raw[r["run"]] = {"peak_Ft": float(ds["peak_Ft"]), "onset_ubar": float(ds["onset_ubar"]),
                             "onset_area": float(ds["onset_area"]), "Ft_at_4": float(ds["Ft"].values[slide][-1]),
                             "wall": ds.attrs["case_wall_time"], "n_dofs": ds.attrs["n_dofs"], "steps": ds.sizes["step"]}
    ref = raw["size-16"]
    for r in rows:
        q = raw[r["run"]]
        errs = [abs(q[k] - ref[k]) / abs(ref[k]) for k in QOIS]
        for k, e in zip(QOIS, errs):
            assert float(r[k]) == pytest.approx(q[k], rel=1e-12)
            assert float(r[f"err_{k}"]) == pytest.approx(e, rel=1e-9, abs=1e-15)
        assert float(r["error"]) == pytest.approx(max(errs), rel=1e-9, abs=1e-15)
        assert float(r["wall_time_s"]) == pytest.approx(q["wall"], abs=0.01)
        assert int(r["n_dofs"]) == q["n_dofs"] and int(r["steps"]) == q["steps"]
    assert rows[1]["error"] in ("0", "0.0") and rows[1]["pareto"] == "True"  # the reference itself
    assert rows[0]["run"] == rows[3]["run"] == "default"  # one file for size 32 with 4 Gauss points
    assert float(rows[0]["error"]) > 1e-4  # the coarse mesh differs from the reference
    assert (out / "error_vs_time.png").stat().st_size > 20000
    assert (out / "orders.csv").read_text().startswith("case,sweep,qoi,sizes,order")  # two levels: no triplet
    assert "| mesh | mesh.size | 32 |" in (out / "table.md").read_text()
    spec = yaml.safe_load(SMALL)
    assert len({r["run"] for r in rows}) == len({(r.case, r.run_id) for r in study_runs(spec)})


def test_cheapest_run_within_a_threshold_over_all_cases():
    from capslide.studies.convergence import cheapest_within

    def row(case, run, err, t, status="completed"):
        return {"case": case, "run": run, "error": err, "wall_time_s": t, "status": status}

    rows = [row(c, "a", e, 2.0) for c, e in (("A", 0.03), ("B", 0.01))] \
        + [row(c, "b", 0.005, 9.0) for c in "AB"] + [row(c, "c", 0.2, 1.0) for c in "AB"] \
        + [row("A", "only_A", 0.0, 0.1)] + [row(c, "d", 0.001, 0.5, "diverged") for c in "AB"]
    assert cheapest_within(rows, 0.05) == {"run": "a", "error": 0.03, "wall_time_s": 4.0}
    assert cheapest_within(rows, 0.01)["run"] == "b"
    assert cheapest_within(rows, 1e-4) is None
