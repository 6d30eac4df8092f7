"""Reliability: legs of zero length, the dwell after a normal state, damaged and ill-typed saved states, the
snap under a tensile preload, and the inputs that used to be accepted although they did nothing (issue 42)."""

import hashlib
import json
import os
import subprocess
import sys

import numpy as np
import pytest
from test_normal_state import COARSE, assert_same_case, normal_state, params_of, run_checkpointed

from capslide.config import ConfigError, apply_overrides, apply_settings, validate
from capslide.driver.case import run_case
from capslide.io.checkpoint import SavedCase, read_signed, write_arrays, write_signed
from capslide.io.normal_state import NormalStateError, read_normal_state, write_normal_state
from capslide.io.state_check import SavedStateMismatch
from capslide.loadpath import cap
from capslide.loadpath.continuation import LegEnd
from capslide.loadpath.measures import peeling_off
from capslide.params import Parameters
from capslide.states import Phase, Status

from conftest import PAPER_CONFIG, default_sigint

VISCOUS = {"material__model": "viscoelastic", "material__prony": [{"g": 1.0, "tau": 1.0}], "loading__velocity": 1e-6}
SETS = sum((["--set", s] for s in COARSE), [])


@pytest.fixture(scope="module")
def base(paper_config):
    return validate(apply_overrides(paper_config, COARSE))


def capslide(*args, timeout=120, env=None):
    """``capslide ARGS`` in a subprocess (a hang fails the test after ``timeout`` s)."""
    return subprocess.run([sys.executable, "-m", "capslide", *map(str, args)], capture_output=True, text=True,
                          timeout=timeout, env=env, start_new_session=True, preexec_fn=default_sigint)


def one_line_error(res, *words):
    err = res.stderr.strip()
    assert res.returncode == 2 and err.count("\n") == 0 and "Traceback" not in err, res.stderr
    for w in words:
        assert w in err, err


def normal_state_file(params, path):
    pre = run_case(params, stop_before="dwell")
    assert pre.status == Status.COMPLETED, pre.reason
    write_normal_state(path, SavedCase(pre.state, pre.records, [], pre.wall_time), params.config)
    return path


# -- 1. legs of zero length are skipped; no leg repeats without progress -------------------------------------------
@pytest.mark.parametrize("sets", [["loading.ubar_max=1e-13"], ["loading.ubar_max=1e-13", "loading.slide_back=true"],
                                  ["loading.dwell=1e-300", "loading.velocity=1e-6"], ["contact.repulsion_only=true"]],
                         ids=["ubar_max", "slide_back", "dwell", "repulsion_only"])
def test_a_leg_of_zero_length_ends_with_a_recorded_status(tmp_path, sets):
    """Before: each looped forever at 100 % CPU with no step printed."""
    out = tmp_path / "o.nc"
    res = capslide("run", PAPER_CONFIG, *SETS, *sum((["--set", s] for s in sets), []), "-q", "-o", out)
    assert res.returncode in (0, 3, 4), res.stderr
    assert out.exists()


def test_a_zero_length_slide_is_skipped(base):
    p = params_of(base, loading__ubar_max=1e-13, loading__slide_back=True)
    res = run_case(p)
    assert res.status == Status.COMPLETED and not any(r.phase == Phase.SLIDE for r in res.records)
    assert res.state.leg == "done"


def test_a_leg_that_ends_without_moving_the_path_ends_it_diverged(base, monkeypatch):
    """The guard: a leg runner that returns 'completed' with no step and leaves the path where it was."""

    def stuck(model, state, snapshot_ubar):
        return LegEnd(Status.COMPLETED)
        yield  # a generator

    monkeypatch.setitem(cap._LEG_RUNNERS, "approach", stuck)
    res = run_case(params_of(base))
    assert res.status == Status.DIVERGED and "approach: the leg ended without a step" in res.reason


# -- 2. the leg after a normal state follows the run's own settings ------------------------------------------------
@pytest.mark.parametrize("state_dwell", [0.0, pytest.param(3.0, marks=pytest.mark.slow)])
def test_a_slide_from_a_state_dwells_as_the_case_alone(base, tmp_path, state_dwell):
    """From one state (computed with dwell 0, or 3) the cases with dwell 0 and 2 (and 3, from the state of dwell 3)
    are each the case alone, bit for bit. Before: a state of dwell 0 skipped every dwell (peak Ft 6 % low), one of
    dwell 3 hung a case of dwell 0."""
    path = tmp_path / "state.npz"
    normal_state(params_of(base, **VISCOUS, loading__dwell=state_dwell), path, tmp_path)  # checkpoints as the cases
    for dwell in (0.0, 2.0, 3.0) if state_dwell else (0.0, 2.0):
        p = params_of(base, **VISCOUS, loading__dwell=dwell)
        shared = run_checkpointed(p, tmp_path / f"shared{dwell}", resume=read_normal_state(path, p.config))
        alone = run_checkpointed(p, tmp_path / f"alone{dwell}")
        assert (sum(r.phase == Phase.DWELL for r in alone.records) > 0) == (dwell > 0)
        assert_same_case(alone, shared)


# -- 3. empty files: a checkpoint starts afresh, a state is refused ------------------------------------------------
def _interrupted_run(tmp_path, after=12):
    out = tmp_path / "case.nc"
    env = {**os.environ, "CAPSLIDE_INTERRUPT_AFTER_STEP": str(after)}
    res = capslide("run", PAPER_CONFIG, *SETS, "--set", "output.checkpoint_every=5", "-q", "-o", out, env=env)
    assert res.returncode == 130, res.stderr
    return out, tmp_path / ".case.nc.checkpoint"


@pytest.mark.parametrize("part", ["state", "chunk"])
def test_an_empty_checkpoint_file_starts_afresh_in_one_line(tmp_path, part):
    out, ckpt = _interrupted_run(tmp_path)
    victim = ckpt / "state.npz" if part == "state" else sorted(ckpt.glob("records-*.npz"))[0]
    victim.write_bytes(b"")
    res = capslide("run", PAPER_CONFIG, *SETS, "--set", "output.checkpoint_every=5", "-q", "--resume", "-o", out)
    assert res.returncode == 0, res.stderr
    lines = [ln for ln in res.stderr.splitlines() if ln.startswith("capslide:")]
    assert len(lines) == 1 and "cannot read checkpoint" in lines[0] and "starting afresh" in lines[0], res.stderr
    assert out.exists() and not ckpt.exists()


def test_an_empty_normal_state_is_refused_in_one_line(tmp_path):
    (tmp_path / "st.npz").write_bytes(b"")
    res = capslide("run", PAPER_CONFIG, *SETS, "--from-state", tmp_path / "st.npz", "-q", "-o", tmp_path / "o.nc")
    one_line_error(res, "st.npz", "cannot read normal state")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["st.npz"]


def test_writes_are_flushed_to_disk(tmp_path, monkeypatch):
    """The temporary file and the directory after the rename are fsynced: a crash leaves old or new, not empty."""
    from capslide.io import atomic

    synced = []
    real = os.fsync
    monkeypatch.setattr(atomic.os, "fsync", lambda fd: (synced.append(os.readlink(f"/proc/self/fd/{fd}")), real(fd)))
    with atomic.replacing(tmp_path / "f.txt") as tmp:
        tmp.write_text("x")
    assert synced[-1] == str(tmp_path) and synced[0].endswith(".tmp") and len(synced) == 2


# -- 4. a snap under a tensile preload is a snap -----------------------------------------------------------------
def test_a_snap_under_a_tensile_preload_is_reported_snapped(tmp_path):
    """Before: 'detached' (exit 3), the peel-off test accepting a contact that shrank by 5e-6 per step."""
    res = capslide("run", PAPER_CONFIG, "--set", "preset=fast", "--set", "friction.static_over_kinetic=3", "--set",
                   "friction.slip_weakening_distance=1e-3", "--set", "loading.preload=0.288", "-q", "-o", tmp_path / "o.nc")
    assert res.returncode == 5 and "snapped" in res.stdout, res.stdout + res.stderr


def _records(area, h, ubar):
    from types import SimpleNamespace

    return [SimpleNamespace(phase=Phase.SLIDE, area=a, h=z, ubar=u) for a, z, u in zip(area, h, ubar)]


def test_peeling_needs_a_real_trend_and_a_fast_shrinking_contact():
    u = np.array([0.70, 0.71, 0.715, 0.7175])
    peel = _records(5.2 - 40.0 * (u - 0.7) ** 0.5, 10.0 + 0.5 * (u - 0.7), u)  # |dA/du| > 1, growing
    assert peeling_off(peel, 0.35)
    assert not peeling_off(peel, -0.1)  # a compressive load never peels
    slow = _records(8.4 - 0.43 * (u - 0.7), 10.1 + 0.02 * (u - 0.7), u)  # the snap's contact: |dA/du| = 0.43
    assert not peeling_off(slow, 0.288)
    noise = _records(9.4 + np.array([0, -4e-15, -8e-15, -1.2e-14]), 9.97 + np.array([0, 2e-15, 4e-15, 6e-15]),
                     u * 1e-12)  # round-off while sliding steadily
    assert not peeling_off(noise, 0.288)


# -- 5. the content of a checksummed state is checked before anything is computed -----------------------------------
@pytest.fixture(scope="module")
def state(base, tmp_path_factory):
    """A valid normal state of the coarse cap: (path, its arrays, its header)."""
    path = normal_state_file(params_of(base), tmp_path_factory.mktemp("state") / "Fn0.npz")
    data, meta = read_signed(path, "normal state", NormalStateError)
    return path, data, meta


def rewritten(state, path, arrays=None, header=None, raw_header=None):
    """The state with some arrays or header entries replaced, written with valid checksums."""
    _, data, meta = state
    data = {**data, **(arrays or {})}
    meta = {k: v for k, v in {**meta, **(header or {})}.items() if k not in ("version", "arrays_sha256")}
    if raw_header is None:
        write_signed(path, data, meta)
        return path
    text = json.dumps(raw_header)  # a header of another shape, with a valid checksum
    write_arrays(path, {**data, "header": np.array(text), "header_sha256": np.array(hashlib.sha256(text.encode()).hexdigest())})
    return path


CORRUPT = {
    "x too short": ({"x": "short"}, None, "field 'x' has shape"),
    "x too long": ({"x": "long"}, None, "field 'x' has shape"),
    "x 2-D": ({"x": "2d"}, None, "field 'x' has 2 dimensions"),
    "x strings": ({"x": "str"}, None, "field 'x' has dtype"),
    "x integers": ({"x": "int"}, None, "field 'x' has dtype"),
    "x NaN": ({"x": "nan"}, None, "field 'x' holds values that are not finite"),
    "anchors of the wrong shape": ({"anchors": "anchors"}, None, "field 'anchors' has shape"),
    "networks for an elastic bulk": ({"viscous_networks": "nets"}, None, "field 'viscous_c_inv' is missing"),
    "a profile of the wrong shape": ({"record_gap": "profile"}, None, "field 'records[0].gap' has shape"),
    "a leg that does not exist": (None, {"leg": "glide"}, "field 'leg' = 'glide' is not one of"),
    "an elapsed time as text": (None, {"elapsed": "12 s"}, "field 'elapsed' = '12 s' is not a number"),
    "targets as text": (None, {"targets": ["a"]}, "field 'targets'"),
    "a loop of another shape": (None, {"loop": [1, 2]}, "field 'loop'"),
}


def _array(kind, x, data):
    return {"short": x[:-3], "long": np.concatenate([x, [0.0]]), "2d": np.stack([x, x]), "str": x.astype(str),
            "int": x.astype(np.int64), "nan": np.where(np.arange(len(x)) == 3, np.nan, x), "anchors": np.zeros((3, 2)),
            "nets": np.zeros((2, 2, 1, 2, 2)), "profile": data["record_gap"][:, :-1]}[kind]


@pytest.mark.parametrize("case", list(CORRUPT))
def test_a_state_of_the_wrong_content_is_refused_naming_the_field(base, state, tmp_path, case):
    """Before: a ValueError, TypeError or AttributeError deep in the run, or a case computed and ended diverged."""
    arrays, header, words = CORRUPT[case]
    data = state[1]
    arrays = {k: _array(v, data["x"], data) for k, v in (arrays or {}).items()}
    path = rewritten(state, tmp_path / "bad.npz", arrays, header)
    p = params_of(base)
    with pytest.raises((NormalStateError, SavedStateMismatch)) as err:
        run_case(p, resume=read_normal_state(path, p.config))
    message = str(err.value)
    assert "bad.npz" in message and words in message and "\n" not in message, message


def test_a_header_that_is_a_list_is_refused(base, state, tmp_path):
    path = rewritten(state, tmp_path / "list.npz", raw_header=[1, 2, 3])
    with pytest.raises(NormalStateError, match=r"list.npz': field 'header' is a list, not a mapping"):
        read_normal_state(path, base)


def test_the_cli_refuses_an_ill_shaped_state_in_one_line(state, tmp_path):
    path = rewritten(state, tmp_path / "bad.npz", {"x": state[1]["x"][:-3]})
    out = tmp_path / "o.nc"
    res = capslide("run", PAPER_CONFIG, *SETS, "--from-state", path, "-q", "-o", out)
    one_line_error(res, "normal state", "bad.npz", "field 'x' has shape")
    assert not out.exists() and not list(tmp_path.glob(".o.nc*"))


def test_the_version_names_the_source():
    from capslide.version import software_version, source_digest

    assert software_version().endswith(f"src{source_digest()}") and len(source_digest()) == 12
    check = ("import hashlib, pathlib, sys; sys.path.insert(0, sys.argv[1]); from capslide.version import source_digest;"
             " print(source_digest())")
    import shutil
    import tempfile

    import capslide

    with tempfile.TemporaryDirectory() as tmp:
        shutil.copytree(os.path.dirname(capslide.__file__), f"{tmp}/capslide", ignore=shutil.ignore_patterns("__pycache__"))
        digest = lambda: subprocess.run([sys.executable, "-c", check, tmp], capture_output=True, text=True,  # noqa: E731
                                        check=True).stdout.strip()
        assert digest() == source_digest()
        with open(f"{tmp}/capslide/laws/contact.py", "a") as fh:
            fh.write("\n# a local change\n")
        assert digest() != source_digest()


# -- 6. temporaries of killed writers are removed -------------------------------------------------------------------
def test_the_temporaries_of_a_killed_writer_are_removed(tmp_path):
    from capslide.io.atomic import _host, replacing

    dead = subprocess.Popen([sys.executable, "-c", "pass"])
    dead.wait()
    stale = tmp_path / f".o.nc.{_host()}-{dead.pid}.abc123.tmp"
    alive = tmp_path / f".o.nc.{_host()}-{os.getppid()}.def456.tmp"
    other = tmp_path / f".o.nc.elsewhere-{dead.pid}.ghi789.tmp"
    for f in (stale, alive, other):
        f.write_text("partial")
    with replacing(tmp_path / "o.nc") as tmp:
        tmp.write_text("complete")
    assert not stale.exists() and alive.exists() and other.exists()


# -- 7. an interrupt before the first checkpoint leaves none ---------------------------------------------------------
def test_an_interrupt_before_the_first_save_leaves_no_checkpoint(tmp_path):
    out, ckpt = _interrupted_run(tmp_path, after=3)
    assert not ckpt.exists() and not out.exists()


def test_an_empty_checkpoint_directory_starts_afresh(tmp_path):
    ckpt = tmp_path / ".o.nc.checkpoint"
    ckpt.mkdir()
    (ckpt / "lock").write_text("")
    res = capslide("run", PAPER_CONFIG, *SETS, "-q", "--resume", "-o", tmp_path / "o.nc")
    assert res.returncode == 0 and "holds no saved step yet; starting afresh" in res.stderr, res.stderr
    assert "state file" not in res.stderr


def test_ctrl_c_names_the_checkpoint_and_resume(tmp_path):
    out = tmp_path / "case.nc"
    env = {**os.environ, "CAPSLIDE_INTERRUPT_AFTER_STEP": "12"}
    res = capslide("run", PAPER_CONFIG, *SETS, "--set", "output.checkpoint_every=5", "-q", "-o", out, env=env)
    assert res.returncode == 130 and ".case.nc.checkpoint' is kept" in res.stderr and "--resume" in res.stderr


# -- 8, 9: the hertz sweep at P <= 0, pull-off of a case that did not detach -----------------------------------------
def test_a_hertz_sweep_at_zero_load_is_refused(tmp_path):
    res = capslide("verify", PAPER_CONFIG.parent / "scenes" / "hertz.yaml", "--scene", "hertz", "--set", "mesh.size=40",
                   "--set", "verification.loads=[0.0]", "-o", tmp_path / "h.csv")
    one_line_error(res, "verification.loads = [0.0]", "compressive")
    assert not (tmp_path / "h.csv").exists()


@pytest.mark.slow
def test_a_damaged_sweep_checkpoint_starts_afresh_and_goes_with_the_table(tmp_path):
    """capslide verify --resume with an unreadable checkpoint beside the table: one line saying why, the sweep
    afresh, and no checkpoint left once the table is written."""
    out = tmp_path / "h.csv"
    checkpoint = tmp_path / ".h.csv.checkpoint.npz"
    checkpoint.write_bytes(b"not a checkpoint")
    res = capslide("verify", PAPER_CONFIG.parent / "scenes" / "hertz.yaml", "--scene", "hertz", "--set", "mesh.size=40",
                   "--set", "verification.loads=[0.3]", "-q", "--resume", "-o", out)
    assert res.returncode == 0, res.stderr
    assert "cannot read sweep checkpoint" in res.stderr and "starting afresh" in res.stderr
    assert out.exists() and not checkpoint.exists()


def test_pull_off_of_a_completed_case_is_refused(tmp_path):
    case = tmp_path / "c.nc"
    assert capslide("run", PAPER_CONFIG, *SETS, "--set", "loading.ubar_max=0", "-q", "-o", case).returncode == 0
    res = capslide("pull-off", case, "--fraction", "0.5", "-o", tmp_path / "p.yaml")
    one_line_error(res, "ended completed", "detached in its preload")
    assert not (tmp_path / "p.yaml").exists()


# -- 10-13: inputs refused at parse time ---------------------------------------------------------------------------
@pytest.mark.parametrize("sets, words", [
    ({"loading.normal_control": "spring", "loading.spring_stiffness": 2e15}, "at most 100000 x material.E"),
    ({"loading.velocity": 5e-324}, "infinite time"),
    ({"loading.spring_stiffness": 2e5}, "normal_control = force"),
    ({"friction.model": "EA", "friction.DI_area": "reference"}, "friction.model = EA"),
    ({"friction.model": "none", "friction.threshold_at": "step_start"}, "friction.model = none"),
    ({"loading.dwell": 2.0}, "loading.velocity = None"),
    ({"mesh.line_band": [5.0, 8.0]}, "mesh.element = Q1"),
    ({"mesh.line_refinement": 8.0}, "mesh.line_refinement = 8.0 is not allowed with mesh.line_band = None"),
])
def test_inputs_that_fail_or_do_nothing_are_refused(paper_config, sets, words):
    with pytest.raises(ConfigError, match=words.replace("(", r"\(")):
        Parameters.from_config(validate(apply_settings(paper_config, sets)))


@pytest.mark.parametrize("band, words", [([8.0, 7.0], "inner radius must be below"), ([6.0, 40.0], "contact band's radius")])
def test_a_contact_line_annulus_off_the_band_is_refused(band, words):
    from capslide.config import load_config, scene_path
    from capslide.model.build import mesh_spec

    with pytest.raises(ConfigError, match=words):
        mesh_spec(Parameters.from_config(load_config([scene_path("sphere")], [f"mesh.line_band={band}"])))


def test_a_ring_refinement_without_its_annulus_is_refused_not_ignored():
    """The sphere scene has no contact-line annulus: mesh.line_refinement alone would mesh the same cells."""
    from capslide.config import load_config, scene_path

    with pytest.raises(ConfigError, match=r"mesh.line_refinement = 8 is not allowed with mesh.line_band = None"):
        load_config([scene_path("sphere")], ["mesh.line_refinement=8"])
    for sets in (["mesh.line_refinement=4"], ["mesh.line_band=[4.5,7.5]", "mesh.line_refinement=8"]):
        load_config([scene_path("sphere")], sets)


def test_a_spring_at_the_bound_is_accepted(paper_config):
    E = paper_config["material"]["E"]
    validate(apply_settings(paper_config, {"loading.normal_control": "spring", "loading.spring_stiffness": 1e5 * E}))


def test_pardiso_in_a_study_model_is_refused_at_parse_time(monkeypatch):
    from capslide.model import cost
    from capslide.studies.expansion import check_runs

    monkeypatch.setattr(cost, "mkl_runtime", lambda: None)
    with pytest.raises(ConfigError, match="run DI_fast: solver.factorization = 'pardiso' needs Intel MKL"):
        check_runs({"DI_fast": {"solver.factorization": "pardiso"}}, [PAPER_CONFIG])



# -- 14. a state of another active_from is refused naming active_from ------------------------------------------------
def test_a_state_for_friction_from_the_slide_is_refused_naming_active_from(state, tmp_path):
    """Before: the message named friction.DI_area, the first friction key in alphabetical order."""
    res = capslide("run", PAPER_CONFIG, *SETS, "--set", "friction.active_from=contact", "--from-state", state[0], "-q",
                   "-o", tmp_path / "o.nc")
    one_line_error(res, "friction.active_from = 'slide' there, 'contact' here")


def test_a_checkpoint_names_its_chunks_inside_itself():
    """A chunk entry that points outside the checkpoint directory is refused before anything is read."""
    from capslide.io.state_check import BadField, check_header

    meta = {"leg": "slide", "loop": None, "targets": [], "marks": [], "cutbacks": 0, "smallest": 1.0, "stage_h": None,
            "time": 0.0, "onset_ceiling": float("nan"), "elapsed": 1.0,
            "chunks": [{"file": "records-a-0000.npz", "kind": "records", "count": 3, "sha256": "x"}]}
    check_header(meta, "checkpoint")
    for bad in ("../records.npz", "/etc/passwd", "..", ""):
        meta["chunks"][0]["file"] = bad
        with pytest.raises(BadField, match="chunks"):
            check_header(meta, "checkpoint")
