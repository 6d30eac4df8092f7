"""Stability suite: the checks on synthetic histories, the spec, and a reduced suite through Snakemake."""

import csv
import math

import numpy as np
import pytest
import yaml

from capslide.config import ConfigError
from capslide.studies.expansion import runs
from capslide.studies.stability import check, markdown_table, pull_off_force

from conftest import ROOT, snakemake


def history(Ft, ubar, phase=None, status="completed", cutbacks=0, area=None, tau=0.165):
    n = len(Ft)
    Ft = np.asarray(Ft, float)
    return {"phase": np.full(n, 2) if phase is None else np.asarray(phase), "ubar": np.asarray(ubar, float), "Ft": Ft,
            "Fn": np.zeros(n), "base_force_x": -Ft, "base_force_y": np.zeros(n),
            "area": np.ones(n) if area is None else np.asarray(area, float), "status": status, "cutbacks": cutbacks,
            "tau_DI": tau}


def test_force_balance_check_sees_an_imbalance():
    a = history([0.1, 0.2], [0.0, 0.1])
    assert check("force_balance", a) == (0.0, True)
    a["base_force_x"] = a["base_force_x"] + np.array([0.0, 1e-6])
    value, ok = check("force_balance", a)
    assert value == pytest.approx(1e-6) and not ok


def test_di_tau_area_check():
    assert check("di_tau_area", history([0.33], [1.0], area=[2.0]))[1]  # 0.165 x 2
    value, ok = check("di_tau_area", history([0.30], [1.0], area=[2.0]))
    assert value == pytest.approx(1 - 0.30 / 0.33) and not ok


def test_closed_loop_check():
    assert check("closed_loop", history([0.5, 1.0, 0.2, -0.6], [0.0, 1.0, 0.5, 0.0]))[1]
    assert not check("closed_loop", history([0.5, 1.0, 0.2, 0.1], [0.0, 1.0, 0.5, 0.0]))[1]  # no sign change
    assert not check("closed_loop", history([0.5, 1.0, -0.2], [0.0, 1.0, 0.5]))[1]  # not back at 0


def test_pull_off_and_detachment_checks():
    a = history([0, 0, 0], [0, 0, 0], phase=[0, 1, 1], status="detached")
    a["Fn"] = np.array([0.0, 0.2, 0.31])
    assert pull_off_force(a["phase"], a["Fn"]) == 0.31 and check("pull_off", a) == (0.31, True)
    assert not check("detached_while_sliding", a)[1]
    b = history([0.1, 0.2], [0.0, 0.4], phase=[1, 2], status="detached")
    assert check("detached_while_sliding", b) == (0.4, True)
    assert check("recovered", history([0.1], [0.1], cutbacks=3)) == (3.0, True)
    assert not check("recovered", history([0.1], [0.1], cutbacks=0))[1]


def test_spec_of_the_suite_and_its_runs():
    spec = yaml.safe_load((ROOT / "config" / "stability.yaml").read_text())
    sets = runs(spec, "stability")
    assert len(sets) >= 11
    # the preload of a pull_off_fraction case comes from the overlay of `capslide pull-off`, not from the overrides
    assert sets["tensile_90"]["mesh.size"] == 16 and "loading.preload" not in sets["tensile_90"]
    assert sets["slide_back"]["loading.slide_back"] is True
    with pytest.raises(ConfigError, match="cases.x.expect = 'exploded' is not allowed"):
        runs({"cases": {"x": {"expect": "exploded"}}}, "stability")
    with pytest.raises(ConfigError, match="cases.x.pull_off_fraction needs a case named 'pull_off'"):
        runs({"cases": {"x": {"expect": "completed", "pull_off_fraction": 0.5}}}, "stability")


def test_markdown_table_marks_failures():
    text = markdown_table([{"case": "a", "passed": True, "check_value": math.nan}, {"case": "b", "passed": False}])
    assert text.count("\n") == 4 and "**no**" in text and "| a |" in text


REDUCED = """
base: {preset: fast, mesh.size: 32, loading.ubar_max: 2.0, loading.max_slide_step: 0.2, output.snapshot_ubar: []}
time_bound_s: 300
cases:
  pull_off: {set: {loading.preload: 1.0, loading.ubar_max: 0.0}, expect: detached, check: pull_off}
  tensile_70: {pull_off_fraction: 0.7, set: {}, expect: completed, check: di_tau_area}
  shear_detach: {pull_off_fraction: 0.99, set: {}, expect: detached, check: detached_while_sliding}
  EA0_tensile: {set: {friction.model: EA, friction.s_cut: 0.0, loading.preload: 0.144}, expect: completed,
                check: force_balance}
  slide_back: {set: {loading.slide_back: true, loading.ubar_max: 3.0}, expect: completed, check: closed_loop}
  big_steps: {set: {loading.approach_step_over_r0: 2.5, loading.force_step: 0.2, loading.slide_step: 0.02,
                    loading.max_slide_step: 1.0, loading.ubar_max: 2.5}, expect: completed, check: recovered}
  g_reg_1.5: {set: {adhesion.g_reg_over_g_eq: 1.5}, expect: rejected, check: none}
"""


@pytest.mark.slow
def test_reduced_suite_through_snakemake(workdir):
    """The stability target on a coarse mesh: every hard case ends as expected and passes its check."""
    tmp_path = workdir
    (tmp_path / "config" / "stability.yaml").write_text(REDUCED)
    res = snakemake(tmp_path, "stability")
    assert res.returncode == 0, res.stdout[-3000:] + res.stderr[-3000:]
    rows = list(csv.DictReader((tmp_path / "results" / "paper" / "studies" / "stability" / "table.csv").open()))
    assert [r["case"] for r in rows] == list(yaml.safe_load(REDUCED)["cases"])
    bad = [(r["case"], r["status"], r["check_value"]) for r in rows if r["passed"] != "True"]
    assert not bad
    assert "| pull_off |" in (tmp_path / "results" / "paper" / "studies" / "stability" / "table.md").read_text()
