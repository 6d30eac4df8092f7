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
