"""The options study (config/options.yaml): its expansion, and the table and figures from coarse case files."""

import csv

import pytest
import yaml

from capslide.cli import main
from capslide.config import ConfigError, override_args
from capslide.studies.expansion import check_runs, runs

from conftest import PAPER_CONFIG, ROOT

COARSE = {"preset": "fast", "mesh.size": 32, "loading.ubar_max": 2.6, "loading.max_slide_step": 0.2,
          "output.snapshot_ubar": [], "loading.preload": 0.0}


def test_the_shipped_spec_expands_to_valid_runs():
    spec = yaml.safe_load((ROOT / "config" / "options.yaml").read_text())
    out = runs(spec, "options")
    assert "DI_paper" in out and "EA1_paper" in out and "EA1_DI_reference_area" not in out
    assert out["EA1_spring"]["loading.normal_control"] == "spring" and out["EA1_spring"]["friction.model"] == "EA"
    check_runs(out, [PAPER_CONFIG])


@pytest.mark.parametrize("change, words", [
    ({"reference": "nothing"}, ["reference = 'nothing'"]),
    ({"options": {"paper": {"set": {}, "models": ["XY"]}}}, ["options.paper.models", "'XY'"]),
    ({"options": {"paper": {"sett": {}}}}, ["unknown key", "sett"]),
])
def test_bad_specs_are_refused_in_one_line(change, words):
    spec = {"models": {"DI": {}}, "reference": "paper", "options": {"paper": {"set": {}}}, **change}
    with pytest.raises(ConfigError) as err:
        runs(spec, "options")
    for word in words:
        assert word in str(err.value)


@pytest.fixture(scope="module")
def study(tmp_path_factory):
    """Three options of DI on the coarse cap: the paper's, height control, and a weakening that snaps."""
    root = tmp_path_factory.mktemp("options")
    spec = {"base": COARSE, "models": {"DI": {"friction.model": "DI"}}, "reference": "paper",
            "options": {"paper": {"what": "the paper", "set": {}},
                        "height": {"what": "height control", "set": {"loading.normal_control": "height"}},
                        "snap": {"set": {"friction.static_over_kinetic": 1.5}}}}
    (root / "spec.yaml").write_text(yaml.safe_dump(spec))
    for run, sets in runs(spec, "options").items():
        args = [a for s in override_args(sets) for a in ("--set", s)]
        code = main(["run", str(PAPER_CONFIG), *args, "-q", "-o", str(root / "cases" / f"{run}.nc")])
        assert code in (0, 5), run
    return root


@pytest.mark.slow
def test_table_and_figures(study, capsys):
    out = study / "out"
    code = main(["options", str(study / "spec.yaml"), "--cases", str(study / "cases"), "-o", str(out / "t.csv"),
                 "-o", str(out / "t.md"), "--forces", str(out / "f.png"), "--edges", str(out / "e.pdf")])
    assert code == 0
    rows = {r["option"]: r for r in csv.DictReader((out / "t.csv").open())}
    assert rows["paper"]["status"] == "completed" and float(rows["paper"]["peak_change_pct"]) == 0.0
    assert float(rows["height"]["peak_change_pct"]) > 5.0  # held at its height, the cap is pressed harder
    assert rows["snap"]["status"] == "snapped" and float(rows["snap"]["end_ubar"]) < 2.6
    assert "| DI | height | completed |" in (out / "t.md").read_text()
    for name in ("f.png", "e.pdf"):
        assert (out / name).stat().st_size > 10_000
    assert "snapped" in capsys.readouterr().out


@pytest.mark.slow
def test_a_missing_case_file_is_one_line(study, tmp_path, capsys):
    code = main(["options", str(study / "spec.yaml"), "--cases", str(tmp_path), "-o", str(tmp_path / "t.csv")])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(err) == 1 and "snakemake --cores 2 options" in err[0]
    assert not (tmp_path / "t.csv").exists()
