"""Checkpoints: a killed case resumed from its checkpoint gives the history of an uninterrupted run, bit for bit."""

import os
import re
import subprocess
import sys

import numpy as np
import pytest
import xarray as xr

from capslide.config import apply_overrides, validate
from capslide.driver.case import run_case
from capslide.driver.observers import AfterSteps, Observer
from capslide.io.checkpoint import CheckpointBusy, CheckpointError, CheckpointWriter, config_text, load_checkpoint
from capslide.params import Parameters
from capslide.states import Phase

from conftest import FOLD, PAPER_CONFIG, default_sigint, step_lines

COARSE = ["preset=fast", "mesh.size=32", "loading.ubar_max=2.6", "loading.max_slide_step=0.2", "output.snapshot_ubar=[0, 1, 2]",
          "loading.slide_back=true"]
STEP_FIELDS = ("phase", "ubar", "h", "Fn", "Ft", "area", "area_compressive", "area_stick", "x_left", "x_right",
               "newton_iterations", "krylov_iterations", "traction_t", "slip_state", "gap", "area_reference",
               "x_stick_left", "x_stick_right", "elastic_energy", "adhesion_energy", "penalty_energy", "slip", "steady_step")


class Killed(Exception):
    pass


def kill_after_steps(n: int) -> AfterSteps:
    """Raises after ``n`` converged steps, as a kill would end the process there."""

    def kill():
        raise Killed

    return AfterSteps(n, kill)


@pytest.fixture(scope="module")
def setup(paper_config):
    config = validate(apply_overrides(paper_config, COARSE))
    return Parameters.from_config(config), config_text(config)


def run_saving(params, path, every, **kwargs):
    """run_case saving checkpoints to ``path`` every ``every`` steps (the writer released afterwards, as at exit)."""
    with CheckpointWriter(path, config_text(params.config)) as writer:
        return run_case(params, checkpoint=writer, checkpoint_every=every, **kwargs)


@pytest.fixture(scope="module")
def uninterrupted(setup, tmp_path_factory):
    params, _ = setup
    return run_saving(params, tmp_path_factory.mktemp("full") / "ckpt", 7)


def assert_same_history(a, b):
    assert len(a.records) == len(b.records)
    for name in STEP_FIELDS:
        np.testing.assert_array_equal(np.array([getattr(r, name) for r in b.records]),
                                      np.array([getattr(r, name) for r in a.records]), err_msg=name)
    assert b.scalars == a.scalars and b.status == a.status and b.reason == a.reason
    assert (b.cutbacks, b.min_step) == (a.cutbacks, a.min_step)
    assert [s.ubar for s in b.snapshots] == [s.ubar for s in a.snapshots]
    for s1, s2 in zip(a.snapshots, b.snapshots):
        np.testing.assert_array_equal(s2.u, s1.u)
        np.testing.assert_array_equal(s2.I1_sigma, s1.I1_sigma)


@pytest.mark.parametrize("kill_after", [30, 95], ids=["step30", "step95"])
def test_resume_repeats_the_uninterrupted_history(setup, uninterrupted, tmp_path, kill_after):
    params, text = setup
    path = tmp_path / "ckpt"
    with pytest.raises(Killed):
        run_saving(params, path, 7, observers=[kill_after_steps(kill_after)])
    saved = load_checkpoint(path, text)
    assert len(saved.records) == 7 * ((kill_after - 1) // 7)  # the last checkpoint before the kill
    resumed = run_saving(params, path, 7, resume=saved)
    assert len(resumed.records) > kill_after
    assert_same_history(uninterrupted, resumed)


@pytest.mark.slow
def test_a_checkpoint_in_steady_sliding_resumes_it(setup, uninterrupted, tmp_path):
    """A checkpoint saved where the slide has just become steady (the loop's step infinite: the next step goes to
    the end of the leg in one) resumes into the uninterrupted history."""
    params, text = setup
    first = next(i for i, r in enumerate(uninterrupted.records) if r.steady_step)  # steps before the first long one
    full = run_saving(params, tmp_path / "full", first)  # saves (and refactorizes) where the interrupted run does
    with pytest.raises(Killed):
        run_saving(params, tmp_path / "ckpt", first, observers=[kill_after_steps(first + 1)])
    saved = load_checkpoint(tmp_path / "ckpt", text)
    assert len(saved.records) == first and saved.state.loop.step == float("inf")
    assert_same_history(full, run_saving(params, tmp_path / "ckpt", first, resume=saved))


@pytest.fixture(scope="module")
def viscous(paper_config, tmp_path_factory):
    """A viscoelastic case (one branch, a dwell of 4 tau, then a slide to 1.2 L0), run uninterrupted."""
    sets = ["loading.slide_back=false", "loading.ubar_max=1.2", "loading.velocity=1e-6", "material.model=viscoelastic",
            "material.prony=[{g: 1.0, tau: 0.5}]", "loading.dwell=2.0"]
    config = validate(apply_overrides(paper_config, [*COARSE, *sets]))
    params = Parameters.from_config(config)
    return params, config_text(config), run_saving(params, tmp_path_factory.mktemp("viscous") / "ckpt", 7)


@pytest.mark.parametrize("kill_after, phase", [(40, Phase.DWELL), (60, Phase.SLIDE)], ids=["dwell", "slide"])
def test_a_viscous_case_resumes_with_its_networks_and_time(viscous, tmp_path, kill_after, phase):
    """A viscoelastic case killed in its dwell or its slide and resumed from the last checkpoint gives the
    uninterrupted history, times included: the checkpoint carries the branches' networks and the time."""
    params, text, full = viscous
    assert full.records[kill_after - 1].phase == phase
    with pytest.raises(Killed):
        run_saving(params, tmp_path / "ckpt", 7, observers=[kill_after_steps(kill_after)])
    resumed = run_saving(params, tmp_path / "ckpt", 7, resume=load_checkpoint(tmp_path / "ckpt", text))
    assert_same_history(full, resumed)
    assert [r.time for r in resumed.records] == [r.time for r in full.records]


def test_a_checkpoint_at_the_end_of_the_preload_resumes_into_the_slide(setup, uninterrupted, tmp_path):
    """The slide's first state (its ubar = 0 snapshot, its friction anchors) is set up again after a resume from
    the last preload step."""
    params, text = setup
    n = [r.phase for r in uninterrupted.records].index(Phase.SLIDE)  # steps before the slide
    reference = run_saving(params, tmp_path / "ref", n)  # the same renewal schedule
    path = tmp_path / "ckpt"
    with pytest.raises(Killed):
        run_saving(params, path, n, observers=[kill_after_steps(n + 2)])
    saved = load_checkpoint(path, text)
    assert saved.state.leg == "slide" and saved.state.loop is None and [s.ubar for s in saved.snapshots] == [0.0]
    assert_same_history(reference, run_saving(params, path, n, resume=saved))


def test_checkpoint_of_another_configuration_is_refused(setup, tmp_path):
    params, text = setup
    path = tmp_path / "ckpt"
    with pytest.raises(Killed):
        run_saving(params, path, 1, observers=[kill_after_steps(3)])
    assert path.is_dir() and len(load_checkpoint(path, text).records) == 2
    with pytest.raises(CheckpointError, match="different configuration"):
        load_checkpoint(path, text.replace("eps_t: 100.0", "eps_t: 200.0"))


def test_a_save_writes_only_the_new_steps(setup, tmp_path):
    """Each save adds one chunk of the records since the previous save: O(new steps), not O(all steps)."""
    import numpy as np

    params, text = setup
    path = tmp_path / "ckpt"
    with pytest.raises(Killed):
        run_saving(params, path, 5, observers=[kill_after_steps(23)])
    chunks = sorted(path.glob("records-*.npz"))
    assert [len(np.load(c)["phase"]) for c in chunks] == [5, 5, 5, 5]
    assert len(load_checkpoint(path, text).records) == 20


@pytest.mark.parametrize("damage", ["flip a byte of the state", "flip a byte of a chunk", "drop a chunk", "a file",
                                    "empty directory"])
def test_a_damaged_checkpoint_is_refused(setup, tmp_path, damage):
    params, text = setup
    path = tmp_path / "ckpt"
    with pytest.raises(Killed):
        run_saving(params, path, 4, observers=[kill_after_steps(10)])
    load_checkpoint(path, text)
    if damage.startswith("flip"):
        target = path / "state.npz" if "state" in damage else sorted(path.glob("records-*.npz"))[0]
        data = bytearray(target.read_bytes())
        data[len(data) // 2] ^= 0x10
        target.write_bytes(bytes(data))
    elif damage == "drop a chunk":
        sorted(path.glob("records-*.npz"))[-1].unlink()
    elif damage == "a file":
        import shutil

        shutil.rmtree(path)
        path.write_bytes(b"\x80\x04not a checkpoint")
    else:
        for f in path.iterdir():
            f.unlink()
    with pytest.raises(CheckpointError):
        load_checkpoint(path, text)


def test_one_writer_per_checkpoint(setup, tmp_path):
    params, text = setup
    with CheckpointWriter(tmp_path / "ckpt", text), pytest.raises(CheckpointBusy, match="another run"):
        CheckpointWriter(tmp_path / "ckpt", text)
    CheckpointWriter(tmp_path / "ckpt", text).close()  # free again once the first is done


def test_cli_resume_after_ctrl_c(tmp_path):
    """capslide run interrupted by SIGINT after a known step (the CAPSLIDE_INTERRUPT_AFTER_STEP hook) leaves no case
    file but a checkpoint; --resume finishes with the same history, bit for bit. Its log shows every step once:
    the checkpoint's steps as the interrupted run logged them (Snakemake empties a job's log before a rerun)."""
    sets = sum((["--set", s] for s in COARSE + ["output.checkpoint_every=5"]), [])
    cmd = [sys.executable, "-m", "capslide", "run", str(PAPER_CONFIG), *sets]
    ref = subprocess.run([*cmd, "-q", "-o", str(tmp_path / "ref.nc")], capture_output=True, text=True)
    assert ref.returncode == 0, ref.stderr
    with xr.open_dataset(tmp_path / "ref.nc") as ds:
        kill_at = int(np.flatnonzero(ds["phase"].values == Phase.SLIDE)[0]) + 12  # inside the slide
    out, ckpt = tmp_path / "case.nc", tmp_path / ".case.nc.checkpoint"
    env = {**os.environ, "CAPSLIDE_INTERRUPT_AFTER_STEP": str(kill_at)}
    res = subprocess.run([*cmd, "-o", str(out)], env=env, capture_output=True, text=True, start_new_session=True,
                         preexec_fn=default_sigint)
    assert res.returncode == 130 and "interrupted" in res.stderr, res.stderr
    assert not out.exists() and ckpt.is_dir()
    logged = step_lines(res.stderr)
    res = subprocess.run([*cmd, "--resume", "-o", str(out)], capture_output=True, text=True)
    assert res.returncode == 0 and f"resuming from {ckpt} (" in res.stderr, res.stderr
    assert not ckpt.exists()  # removed once the case file is written
    saved = int(re.search(r"\((\d+) converged steps\)", res.stderr)[1])
    assert 0 < saved < len(logged) == kill_at and step_lines(res.stderr)[:saved] == logged[:saved]
    with xr.open_dataset(tmp_path / "ref.nc") as a, xr.open_dataset(out) as b:
        assert a.sizes == b.sizes and len(step_lines(res.stderr)) == a.sizes["step"]
        for name in a.data_vars:
            if name != "wall_time":
                np.testing.assert_array_equal(b[name].values, a[name].values, err_msg=name)


def test_a_resumed_sweep_shows_its_saved_steps_first(setup, uninterrupted, tmp_path):
    """capslide verify --resume writes the step lines of the sweep's checkpoint before it goes on, as a resumed case
    does (Snakemake empties a job's log before a rerun)."""
    import io
    from types import SimpleNamespace

    from capslide.cli.progress import ProgressDisplay, log_line
    from capslide.cli.studies import _sweep_checkpoint
    from capslide.io.sweep_checkpoint import SavedSweep, save_sweep, sweep_checkpoint_path

    params, text = setup
    out = tmp_path / "t.csv"
    save_sweep(sweep_checkpoint_path(out), text, SavedSweep(uninterrupted.final_x, 1.0, uninterrupted.records[:9]))
    shown = io.StringIO()
    _, saved, _ = _sweep_checkpoint(SimpleNamespace(resume=True), params, out, ProgressDisplay(stream=shown))
    assert len(saved.records) == 9
    assert shown.getvalue() == "".join(log_line(r) for r in uninterrupted.records[:9])


def test_a_checkpoint_holds_every_field_of_a_record():
    from dataclasses import fields

    from capslide.loadpath.measures import RECORD_PROFILES, RECORD_SCALARS, StepRecord

    assert sorted(RECORD_SCALARS + RECORD_PROFILES) == sorted(f.name for f in fields(StepRecord))


def _run_cmd(out, *extra):
    sets = sum((["--set", s] for s in COARSE + ["output.checkpoint_every=5", *extra]), [])
    return [sys.executable, "-m", "capslide", "run", str(PAPER_CONFIG), *sets, "-q", "-o", str(out)]


def test_sighup_leaves_like_ctrl_c(tmp_path):
    """SIGHUP (a closed terminal) ends a run as SIGINT and SIGTERM do: exit 130, no case file, the checkpoint kept."""
    out = tmp_path / "case.nc"
    env = {**os.environ, "CAPSLIDE_INTERRUPT_AFTER_STEP": "12", "CAPSLIDE_INTERRUPT_SIGNAL": "HUP"}
    res = subprocess.run(_run_cmd(out), env=env, capture_output=True, text=True, start_new_session=True)
    assert res.returncode == 130 and "interrupted" in res.stderr, res.stderr
    assert not out.exists() and (tmp_path / ".case.nc.checkpoint").is_dir()
    assert not list(tmp_path.glob(".*.tmp"))


def test_two_runs_writing_one_file_both_finish(tmp_path):
    """Two `capslide run -o o.nc` at once: both exit 0, one keeps the checkpoint to itself, the file is complete."""
    out = tmp_path / "o.nc"
    procs = [subprocess.Popen(_run_cmd(out, "loading.ubar_max=0.6"), stderr=subprocess.PIPE, text=True) for _ in range(2)]
    errs = [p.communicate()[1] for p in procs]
    assert [p.returncode for p in procs] == [0, 0], errs
    assert sum("this run keeps no checkpoint" in e for e in errs) <= 1 and not any("Traceback" in e for e in errs)
    with xr.open_dataset(out) as ds:
        assert ds.attrs["status"] == "completed" and float(ds["ubar"].max()) == pytest.approx(0.6)  # forth and back
    assert sorted(p.name for p in tmp_path.iterdir()) == ["o.nc"]  # no temporary, no checkpoint left


@pytest.mark.slow
def test_resume_carries_the_accumulated_slip_of_slip_weakening(paper_config, tmp_path):
    """The weakening threshold depends on each point's accumulated slip: a resume mid-weakening repeats the
    uninterrupted history bit for bit only if the checkpoint carries it."""
    config = validate(apply_overrides(paper_config, [*COARSE, "loading.slide_back=false",
                                                     "friction.static_over_kinetic=1.2",
                                                     "friction.slip_weakening_distance=1.0"]))
    params, text = Parameters.from_config(config), config_text(config)
    full = run_saving(params, tmp_path / "full", 5)
    after = [i for i, r in enumerate(full.records) if r.phase == Phase.SLIDE and r.area_stick == 0.0][0] + 3
    with pytest.raises(Killed):
        run_saving(params, tmp_path / "ckpt", 5, observers=[kill_after_steps(after)])
    saved = load_checkpoint(tmp_path / "ckpt", text)
    assert saved.state.history.slip is not None and saved.state.history.slip.max() > 0.0
    assert_same_history(full, run_saving(params, tmp_path / "ckpt", 5, resume=saved))


@pytest.mark.slow
@pytest.mark.parametrize("threshold_at", ["step_start", "step_predicted"])
def test_resume_carries_the_thresholds_a_step_holds(paper_config, tmp_path, threshold_at):
    """With friction.threshold_at = step_start each step takes the thresholds of its start state (step_predicted:
    extrapolated from it and the state before): a resume mid-slide repeats the uninterrupted history bit for bit
    only if the checkpoint carries them."""
    config = validate(apply_overrides(paper_config, [*COARSE, "loading.slide_back=false",
                                                     f"friction.threshold_at={threshold_at}"]))
    params, text = Parameters.from_config(config), config_text(config)
    full = run_saving(params, tmp_path / "full", 5)
    after = [i for i, r in enumerate(full.records) if r.phase == Phase.SLIDE][0] + 6
    with pytest.raises(Killed):
        run_saving(params, tmp_path / "ckpt", 5, observers=[kill_after_steps(after)])
    saved = load_checkpoint(tmp_path / "ckpt", text)
    assert saved.state.history.thresholds is not None and saved.state.history.thresholds.max() > 0.0
    assert_same_history(full, run_saving(params, tmp_path / "ckpt", 5, resume=saved))


class OnsetCeilings(Observer):
    """Records, after every converged step, the path's onset ceiling and whether the stick zone is still open."""

    def __init__(self):
        self.seen = []

    def step(self, step):
        self.seen.append((step.state.onset_ceiling, step.record.area_stick > 0.0))


@pytest.mark.slow
def test_a_checkpoint_within_the_onset_search_resumes_it(paper_config, tmp_path):
    """A checkpoint saved after a step cut back for closing the stick zone (the onset ceiling set, the stick zone
    still open) carries the ceiling: the resumed search takes the uninterrupted run's steps, bit for bit."""
    config = validate(apply_overrides(paper_config, [*COARSE, "loading.slide_back=false"]))
    params, text = Parameters.from_config(config), config_text(config)
    watch = OnsetCeilings()
    run_saving(params, tmp_path / "watch", 10_000, observers=[watch])
    n = next(i + 1 for i, (ceiling, sticking) in enumerate(watch.seen) if np.isfinite(ceiling) and sticking)
    reference = run_saving(params, tmp_path / "ref", n)  # the same renewal schedule
    path = tmp_path / "ckpt"
    with pytest.raises(Killed):
        run_saving(params, path, n, observers=[kill_after_steps(n + 1)])
    saved = load_checkpoint(path, text)
    assert len(saved.records) == n and np.isfinite(saved.state.onset_ceiling)
    assert_same_history(reference, run_saving(params, path, n, resume=saved))


def test_a_saved_state_is_tied_to_the_source_digest_not_to_the_commit(tmp_path, monkeypatch):
    """A commit of the docs alone leaves checkpoints and normal states valid (a long study resumes across it);
    another source digest (code that computes) does not."""
    import capslide.io.checkpoint as ck
    from capslide.version import source_digest

    arrays = {"x": np.arange(3.0)}
    for version, accepted in ((f"0.1.0+gdeadbeef0000.src{source_digest()}", True),
                              (f"0.1.0+gdeadbeef0000.dirty.src{source_digest()}", True),
                              (f"0.1.0+src{source_digest()}", True), ("0.1.0+src000000000000", False)):
        monkeypatch.setattr(ck, "software_version", lambda: version)
        ck.write_signed(tmp_path / "s.npz", arrays, {"kind": "test"})
        monkeypatch.undo()
        if accepted:
            data, meta = ck.read_signed(tmp_path / "s.npz", "checkpoint", ck.CheckpointError)
            assert meta["version"] == version and np.array_equal(data["x"], arrays["x"])
        else:
            with pytest.raises(ck.CheckpointError, match="was written by capslide 0.1.0[+]src000000000000"):
                ck.read_signed(tmp_path / "s.npz", "checkpoint", ck.CheckpointError)


@pytest.mark.slow
def test_a_checkpoint_right_after_a_snap_resumes_with_the_thresholds_held(paper_config, tmp_path):
    """With ``step_predicted`` the step after a snap holds the thresholds at its start (continuation.held_history):
    a checkpoint saved right after the snap carries that, and the resumed run repeats the uninterrupted one bit for
    bit. The 2D cap's fold of tests/test_snap_through.py."""
    config = validate(apply_overrides(paper_config, [*FOLD, "friction.threshold_at=step_predicted"]))
    params, text = Parameters.from_config(config), config_text(config)
    full = run_saving(params, tmp_path / "full", 10_000)
    n = next(i + 1 for i, r in enumerate(full.records) if r.snapped)
    reference = run_saving(params, tmp_path / "ref", n)  # the same renewal schedule
    path = tmp_path / "ckpt"
    with pytest.raises(Killed):
        run_saving(params, path, n, observers=[kill_after_steps(n + 1)])
    saved = load_checkpoint(path, text)
    assert len(saved.records) == n and saved.state.loop.snapped
    assert_same_history(reference, run_saving(params, path, n, resume=saved))
