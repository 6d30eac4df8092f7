"""Checkpoints: a killed case resumed from its checkpoint gives the history of an uninterrupted run."""

import os
import signal
import subprocess
import sys
import time

import numpy as np
import pytest
import yaml

from capslide.case import run_case
from capslide.checkpoint import CheckpointError, Checkpointer
from capslide.config import apply_overrides, validate
from capslide.params import Parameters
from conftest import PAPER_CONFIG, default_sigint

COARSE = ["preset=fast", "mesh.size=32", "loading.ubar_max=2.6", "loading.max_slide_step=0.2", "output.snapshot_ubar=[0, 1, 2]",
          "loading.slide_back=true"]


class Killed(Exception):
    pass


@pytest.fixture(scope="module")
def setup(paper_config):
    config = validate(apply_overrides(paper_config, COARSE))
    params = Parameters.from_config(config)
    text = yaml.safe_dump(config, sort_keys=True)
    return params, text


@pytest.fixture(scope="module")
def uninterrupted(setup, tmp_path_factory):
    params, text = setup
    return run_case(params, ckpt=Checkpointer(tmp_path_factory.mktemp("full") / "ckpt", text, every=7))


@pytest.mark.parametrize("kill_after", [30, 95], ids=["step30", "step95"])
def test_resume_repeats_the_uninterrupted_history(setup, uninterrupted, tmp_path, kill_after):
    params, text = setup
    path = tmp_path / "ckpt"
    count = [0]

    def progress(rec):
        count[0] += 1
        if count[0] == kill_after:
            raise Killed

    with pytest.raises(Killed):
        run_case(params, progress=progress, ckpt=Checkpointer(path, text, every=7))
    resumed = run_case(params, ckpt=Checkpointer.load(path, text, every=7))
    full = uninterrupted
    assert len(resumed.records) == len(full.records) > kill_after
    for name in ("ubar", "Fn", "Ft", "area", "h"):
        a, b = (np.array([getattr(r, name) for r in res.records]) for res in (full, resumed))
        np.testing.assert_allclose(b, a, rtol=1e-10, atol=1e-10 * np.abs(a).max(), err_msg=name)
    assert resumed.scalars == full.scalars and resumed.status == full.status
    assert [s.ubar for s in resumed.snapshots] == [s.ubar for s in full.snapshots]
    for s1, s2 in zip(full.snapshots, resumed.snapshots):
        np.testing.assert_allclose(s2.u, s1.u, rtol=0, atol=1e-12)


def test_checkpoint_of_another_configuration_is_refused(setup, tmp_path):
    params, text = setup
    path = tmp_path / "ckpt"
    steps = []

    def progress(rec):
        steps.append(rec)
        if len(steps) == 3:
            raise Killed

    with pytest.raises(Killed):
        run_case(params, progress=progress, ckpt=Checkpointer(path, text, every=1))
    assert path.is_file() and len(Checkpointer.load(path, text, every=1).records) == 2
    with pytest.raises(CheckpointError, match="different configuration"):
        Checkpointer.load(path, text.replace("eps_t: 100.0", "eps_t: 200.0"), every=1)


def test_cli_resume_after_ctrl_c(tmp_path):
    """capslide run killed by SIGINT leaves no case file but a checkpoint; --resume finishes with the same forces."""
    import xarray as xr

    sets = sum((["--set", s] for s in COARSE + ["output.checkpoint_every=5"]), [])
    cmd = [sys.executable, "-m", "capslide", "run", str(PAPER_CONFIG), *sets]
    ref = subprocess.run([*cmd, "-q", "-o", str(tmp_path / "ref.nc")], capture_output=True, text=True)
    assert ref.returncode == 0, ref.stderr
    out, ckpt = tmp_path / "case.nc", tmp_path / ".case.nc.checkpoint"
    log = open(tmp_path / "log", "w")
    proc = subprocess.Popen([*cmd, "-o", str(out)], stderr=log, stdout=log, preexec_fn=default_sigint)
    deadline = time.monotonic() + 120
    while time.monotonic() < deadline and "slide" not in (tmp_path / "log").read_text():
        time.sleep(0.1)
    assert proc.poll() is None
    os.kill(proc.pid, signal.SIGINT)
    assert proc.wait(timeout=60) == 130
    assert not out.exists() and ckpt.is_file()
    res = subprocess.run([*cmd, "--resume", "-q", "-o", str(out)], capture_output=True, text=True)
    assert res.returncode == 0 and "resuming from" in res.stderr, res.stderr
    assert not ckpt.exists()  # removed once the case file is written
    with xr.open_dataset(tmp_path / "ref.nc") as a, xr.open_dataset(out) as b:
        for name in ("ubar", "Fn", "Ft", "area"):
            np.testing.assert_allclose(b[name].values, a[name].values, rtol=1e-10, atol=1e-12, err_msg=name)
