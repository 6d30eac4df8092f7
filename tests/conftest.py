import re
import shutil
import signal
import subprocess
import sys
from pathlib import Path

import pytest

from capslide.config import load_config
from capslide.params import Parameters

ROOT = Path(__file__).resolve().parents[1]
PAPER_CONFIG = ROOT / "config" / "config.yaml"
# the 2D cap's fold (with the paper config at preset fast): past the onset of full sliding the area jumps and a slide
# step fails at the minimum step (tests/test_snap_through.py)
FOLD = ["preset=fast", "mesh.size=32", "loading.preload=0", "loading.max_slide_step=0.2", "loading.ubar_max=2.2",
        "solver.snap_through=true", "output.snapshot_ubar=[]"]


@pytest.fixture(scope="session")
def paper_config() -> dict:
    """The paper's config at the 'fast' numerical preset (Q1 elements): tests choose their own coarse meshes."""
    return load_config([PAPER_CONFIG], ["preset=fast"])


@pytest.fixture(scope="session")
def paper(paper_config) -> Parameters:
    return Parameters.from_config(paper_config)


SNAKEMAKE = Path(sys.executable).with_name("snakemake")


@pytest.fixture()
def workdir(tmp_path):
    """A scratch copy of the workflow (Snakefile, rules, configs, sources, profiles)."""
    for name in ("Snakefile", "workflow", "config", "src", "profiles"):
        src = ROOT / name
        if src.is_dir():
            shutil.copytree(src, tmp_path / name, symlinks=True, ignore=shutil.ignore_patterns("__pycache__"))
        else:
            shutil.copy(src, tmp_path / name)
    return tmp_path


def default_sigint():
    """preexec_fn for test subprocesses: SIGINT as on a terminal (a background test run inherits it ignored)."""
    signal.signal(signal.SIGINT, signal.SIG_DFL)


def snakemake(workdir, *args):
    """Run Snakemake on 2 cores in ``workdir``; the completed process."""
    return subprocess.run([str(SNAKEMAKE), "--cores", "2", *args], cwd=workdir, capture_output=True, text=True)


def step_lines(log: str, untimed: bool = False) -> list[str]:
    """The step lines of a case's log (its progress without a terminal), without their wall times if ``untimed``."""
    lines = [line for line in log.splitlines() if re.match(r"[a-z]+ +ubar=", line)]
    return [re.sub(r" t= *[0-9.]+s$", "", line) for line in lines] if untimed else lines
