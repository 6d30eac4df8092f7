"""The Snakemake workflow, run in a scratch copy of the repository."""

import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from conftest import ROOT

SNAKEMAKE = Path(sys.executable).with_name("snakemake")


@pytest.fixture()
def workdir(tmp_path):
    for name in ("Snakefile", "workflow", "config", "src"):
        src = ROOT / name
        if src.is_dir():
            shutil.copytree(src, tmp_path / name, symlinks=True, ignore=shutil.ignore_patterns("__pycache__"))
        else:
            shutil.copy(src, tmp_path / name)
    return tmp_path


def snakemake(workdir, *args):
    return subprocess.run([str(SNAKEMAKE), "--cores", "2", *args], cwd=workdir, capture_output=True, text=True)


def test_dry_run_is_clean(workdir):
    res = snakemake(workdir, "-n")
    assert res.returncode == 0, res.stderr
    assert "Warning" not in res.stdout + res.stderr


def test_model_figures_render(workdir):
    res = snakemake(workdir, "results/figures/Tn.png", "results/figures/exp_FnJKR.pdf")
    assert res.returncode == 0, res.stdout + res.stderr
    for name in ("Tn.png", "Tn.pdf", "exp_FnJKR.pdf", "exp_FnJKR.png"):
        assert (workdir / "results" / "figures" / name).stat().st_size > 5000
    assert (workdir / "logs" / "figures" / "Tn.log").exists()
    assert (workdir / "results" / "benchmarks" / "figures" / "Tn.tsv").exists()


def test_bad_config_is_one_clear_line(workdir):
    bad = workdir / "bad.yaml"
    bad.write_text("friction:\n  s_cut: 2\n")
    res = snakemake(workdir, "-n", "--configfile", "config/config.yaml", "bad.yaml")
    assert res.returncode != 0
    assert "config error: friction.s_cut = 2 is not allowed: must be number >= 0 and <= 1" in res.stdout + res.stderr


def test_smoke_workflow_end_to_end(workdir):
    """The CI smoke study: coarse mesh, three cases, collected dataset and cap figures, through Snakemake."""
    import xarray as xr

    res = snakemake(workdir, "--configfile", "config/smoke.yaml")
    assert res.returncode == 0, res.stdout[-3000:] + res.stderr[-3000:]
    results = workdir / "results"
    cases = sorted((results / "cases").glob("*.nc"))
    assert [p.name for p in cases] == ["DI_Fn+0.000.nc", "EA0_Fn+0.000.nc", "EA1_Fn+0.000.nc"]
    with xr.open_dataset(results / "cases.nc") as ds:
        assert ds.sizes["case"] == 3 and set(ds["model"].values) == {"DI", "EA"}
        assert (ds["status"].values == 0).all()
        for name, var in ds.variables.items():
            assert "units" in var.attrs and "long_name" in var.attrs, name
    for name in ("Tn", "modelCA", "modelAM", "TnTt", "exp_FnJKR", "cap_setup", "cap_PxAndAc", "cap_PxOverAc"):
        for ext in ("pdf", "png"):
            assert (results / "figures" / f"{name}.{ext}").stat().st_size > 5000, name
    # nothing left to do: a second run is a no-op
    again = snakemake(workdir, "--configfile", "config/smoke.yaml", "-n")
    assert "Nothing to be done" in again.stdout + again.stderr
