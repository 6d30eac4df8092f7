"""Normal states: a case slid from a shared approach and preload is the case computed alone, bit for bit."""

import numpy as np
import pytest
from test_checkpoint import assert_same_history

from capslide.cli import main
from capslide.config import apply_overrides, apply_settings, load_config, validate
from capslide.driver.case import run_case
from capslide.io.checkpoint import CheckpointWriter, SavedCase, config_text
from capslide.io.normal_state import NormalStateError, normal_config, read_normal_state, write_normal_state
from capslide.loadpath.cap import continued_from
from capslide.params import Parameters
from capslide.states import Phase, Status
from capslide.studies.expansion import shares_normal_state

from conftest import PAPER_CONFIG

COARSE = ["preset=fast", "mesh.size=32", "loading.ubar_max=1.2", "loading.max_slide_step=0.2",
          "output.snapshot_ubar=[0, 0.6]"]
EA0 = {"friction.model": "EA", "friction.s_cut": 0.0}


@pytest.fixture(scope="module")
def base(paper_config):
    return validate(apply_overrides(paper_config, COARSE))


def params_of(base, **settings):
    return Parameters.from_config(validate(apply_settings(base, {k.replace("__", "."): v for k, v in settings.items()})))


def run_checkpointed(params, path, **kwargs):
    """A case saving checkpoints every 7 steps: saves renew the factorization, so the schedule must be the same
    whether the case starts at the beginning or from a normal state."""
    with CheckpointWriter(path, config_text(params.config)) as writer:
        return run_case(params, checkpoint=writer, checkpoint_every=7, **kwargs)


def normal_state(params, path, tmp_path, start=None):
    """The normal state of ``params`` written to ``path`` and read back for ``params``."""
    pre = run_checkpointed(params, tmp_path / f"{path.name}.ckpt", resume=start, stop_before="dwell")
    ended = None if pre.status == Status.COMPLETED else (pre.status, pre.reason)
    write_normal_state(path, SavedCase(pre.state, pre.records, [], pre.wall_time, ended), params.config)
    return pre


def assert_same_case(alone, shared):
    assert_same_history(alone, shared)
    assert (shared.status, shared.reason, shared.cutbacks, shared.min_step) == \
           (alone.status, alone.reason, alone.cutbacks, alone.min_step)
    assert [sn.ubar for sn in shared.snapshots] == [sn.ubar for sn in alone.snapshots] == [0.0, 0.6]
    for a, b in zip(alone.snapshots, shared.snapshots, strict=True):
        np.testing.assert_array_equal(a.u, b.u)
        np.testing.assert_array_equal(a.I1_sigma, b.I1_sigma)


def test_a_slide_from_the_shared_state_is_the_case_alone(base, tmp_path):
    """The normal state is computed with the DI law; EA0 slides from it and gets its own case, bit for bit."""
    pre = normal_state(params_of(base), tmp_path / "Fn0.npz", tmp_path)
    assert pre.status == Status.COMPLETED and {r.phase for r in pre.records} == {Phase.APPROACH, Phase.PRELOAD}
    ea0 = params_of(base, **{k.replace(".", "__"): v for k, v in EA0.items()})
    shared = run_checkpointed(ea0, tmp_path / "shared", resume=read_normal_state(tmp_path / "Fn0.npz", ea0.config))
    alone = run_checkpointed(ea0, tmp_path / "alone")
    assert alone.status == Status.COMPLETED and any(r.phase == Phase.SLIDE for r in alone.records)
    assert_same_case(alone, shared)


@pytest.mark.slow
def test_a_viscous_dwell_and_slide_from_the_shared_state_is_the_case_alone(base, tmp_path):
    """With a viscoelastic bulk the state carries the branches' networks and the time; the dwell runs after the
    state, so a state computed with another dwell (and another friction law) serves, bit for bit."""
    viscous = {"material__model": "viscoelastic", "material__prony": [{"g": 1.0, "tau": 0.5}],
               "loading__velocity": 1e-6}
    pre = normal_state(params_of(base, **viscous, loading__dwell=2.0), tmp_path / "Fn0.npz", tmp_path)
    assert pre.state.history.networks is not None and pre.state.history.time > 0.0
    ea0 = params_of(base, **viscous, loading__dwell=0.5, **{k.replace(".", "__"): v for k, v in EA0.items()})
    shared = run_checkpointed(ea0, tmp_path / "shared", resume=read_normal_state(tmp_path / "Fn0.npz", ea0.config))
    alone = run_checkpointed(ea0, tmp_path / "alone")
    assert alone.status == Status.COMPLETED and any(r.phase == Phase.DWELL for r in alone.records)
    assert_same_case(alone, shared)
    assert [r.time for r in shared.records] == [r.time for r in alone.records]


@pytest.mark.slow
def test_a_tensile_preload_goes_on_from_the_state_it_is_retracted_from(base, tmp_path):
    """+0.144 is reached by retraction from -0.288: from the -0.288 state, the same path as the case alone."""
    compressed = params_of(base, loading__preload=-0.288)
    normal_state(compressed, tmp_path / "Fn-0.288.npz", tmp_path)
    tensile = params_of(base, loading__preload=0.144)
    saved = read_normal_state(tmp_path / "Fn-0.288.npz", apply_settings(tensile.config, {"loading.preload": -0.288}))
    approached = [r.Fn for r in saved.records if r.phase == Phase.APPROACH][-1]
    start = continued_from(tensile.loading, saved.state, -0.288, approached)
    assert start is not None and start.targets == [0.144]
    normal_state(tensile, tmp_path / "Fn+0.144.npz", tmp_path, SavedCase(start, saved.records, [], saved.elapsed))
    shared = run_checkpointed(tensile, tmp_path / "shared", resume=read_normal_state(tmp_path / "Fn+0.144.npz",
                                                                                      tensile.config))
    alone = run_checkpointed(tensile, tmp_path / "alone")
    assert min(r.Fn for r in alone.records) == pytest.approx(-0.288)  # the case alone went through -0.288
    assert_same_case(alone, shared)
    # a compressive preload is not on the retraction path
    assert continued_from(compressed.loading, saved.state, -0.288, approached) is None


@pytest.mark.slow
def test_a_compressive_preload_goes_on_from_the_state_its_loading_passes(base, tmp_path, capsys):
    """With loading.preload_via the path to -0.144 lands on 0 (config.yaml lists the study's preloads):
    ``capslide preload --from-state`` at -0.144 goes on from the state at 0, and a case slid from that state is the
    case alone, bit for bit."""
    assert base["loading"]["preload_via"] == [-0.288, -0.144, 0.0, 0.144, 0.288]
    every = {"output__checkpoint_every": 7}  # the schedule of run_checkpointed, also in the CLI's run
    zero = params_of(base, **every)
    pre = normal_state(zero, tmp_path / "Fn+0.000.npz", tmp_path)
    approached = [r.Fn for r in pre.records if r.phase == Phase.APPROACH][-1]
    assert approached > 0.0  # the adhesive cap's approach ends tensile: the loading passes 0 on its way to -0.144
    compressed = params_of(base, loading__preload=-0.144, **every)
    assert continued_from(compressed.loading, pre.state, 0.0, approached).targets == [-0.144]
    assert continued_from(zero.loading, pre.state, 0.0, approached) is None  # not beyond it
    state = tmp_path / "Fn-0.144.npz"
    sets = [a for s in [*COARSE, "loading.preload=-0.144", "output.checkpoint_every=7"] for a in ("--set", s)]
    assert main(["preload", str(PAPER_CONFIG), *sets, "-q", "--from-state", str(tmp_path / "Fn+0.000.npz"),
                 "-o", str(state)]) == 0
    assert "starting afresh" not in capsys.readouterr().err
    ea0 = params_of(base, loading__preload=-0.144, **every, **{k.replace(".", "__"): v for k, v in EA0.items()})
    shared = run_checkpointed(ea0, tmp_path / "shared", resume=read_normal_state(state, ea0.config))
    alone = run_checkpointed(ea0, tmp_path / "alone")
    landed = [r.Fn for r in alone.records if r.phase == Phase.PRELOAD]
    assert min(abs(f) for f in landed) < 1e-9 and landed[-1] == pytest.approx(-0.144)  # through 0
    assert_same_case(alone, shared)


def test_a_failed_preload_ends_every_case_from_it_the_same_way(base, tmp_path):
    """Beyond the pull-off force the preload detaches: the state keeps that, and a case from it ends so."""
    pulled = params_of(base, loading__preload=3.0)
    pre = normal_state(pulled, tmp_path / "Fn+3.npz", tmp_path)
    assert pre.status == Status.DETACHED
    saved = read_normal_state(tmp_path / "Fn+3.npz", pulled.config)
    case = run_case(pulled, resume=saved)
    assert (case.status, case.reason, len(case.records)) == (pre.status, pre.reason, len(pre.records))
    np.testing.assert_array_equal(case.final_x, pre.final_x)


def test_normal_configuration(paper_config):
    """Friction and slide settings are not part of it unless friction acts from the first contact; the mesh and the
    preload are."""
    config = paper_config
    same = [{"friction.model": "EA", "friction.s_cut": 0.0, "friction.eps_t": 50.0}, {"loading.max_slide_step": 0.3},
            {"loading.stop_at_onset": True, "output.snapshot_ubar": [1.0]}, {"friction.model": "none"},
            {"loading.normal_control": "spring", "loading.spring_stiffness": 1e6}, {"friction.DI_area": "reference"}]
    for sets in same:
        assert normal_config(apply_settings(config, sets)) == normal_config(config), sets
        assert shares_normal_state(config, {**sets, "loading.preload": 0.1})
    other = [{"friction.active_from": "contact"}, {"mesh.size": 8.0}, {"loading.preload": 0.1}, {"loading.ubar_max": 2.0},
             {"loading.force_step": 0.01}, {"solver.linear": "direct"}, {"output.checkpoint_every": 5}]
    for sets in other:
        assert normal_config(apply_settings(config, sets)) != normal_config(config), sets
    assert not shares_normal_state(config, {"mesh.size": 8.0, "loading.preload": 0.1})
    assert not shares_normal_state(config, {"friction.active_from": "contact"})  # friction in the preload: its own
    contact = apply_settings(config, {"friction.active_from": "contact"})
    assert normal_config(apply_settings(contact, {"friction.model": "EA"})) != normal_config(contact)


def test_limits_and_a_mesh_free_ubar_max_leave_the_normal_configuration(paper_config):
    """The guards refuse before computing; limits.max_steps counts for a path that did not complete only;
    loading.ubar_max sizes the 2D cap's default band, nothing in 3D or beside a given band."""
    guards = {"limits.max_dofs": 1e5, "limits.max_memory_gb": 2.0, "limits.refuse_locking": False}
    assert normal_config(apply_settings(paper_config, guards)) == normal_config(paper_config)
    steps = apply_settings(paper_config, {"limits.max_steps": 77})
    assert normal_config(steps) == normal_config(paper_config)
    assert normal_config(steps, completed=False) != normal_config(paper_config, completed=False)
    assert not shares_normal_state(paper_config, {"limits.max_steps": 77, "loading.preload": 0.1})
    banded = apply_settings(paper_config, {"mesh.band_half_width": 30.0})
    sphere = load_config(["sphere"])
    for config in (banded, sphere):
        longer = apply_settings(config, {"loading.ubar_max": 7.5})
        assert normal_config(longer) == normal_config(config)
        assert shares_normal_state(config, {"loading.ubar_max": 7.5, "loading.preload": 0.1})


@pytest.fixture(scope="module")
def state_file(base, tmp_path_factory):
    path = tmp_path_factory.mktemp("state") / "Fn0.npz"
    pre = run_case(Parameters.from_config(base), stop_before="slide")
    write_normal_state(path, SavedCase(pre.state, pre.records, [], pre.wall_time), base)
    return path


def test_a_state_for_another_configuration_is_refused_naming_the_key(base, state_file):
    with pytest.raises(NormalStateError, match=r"mesh.size = 32.0 there, 16.0 here"):
        read_normal_state(state_file, apply_settings(base, {"mesh.size": 16.0}))
    with pytest.raises(NormalStateError, match=r"\(friction\.active_from = .slide. there, .contact. here\)"):
        read_normal_state(state_file, apply_settings(base, {"friction.active_from": "contact"}))
    read_normal_state(state_file, apply_settings(base, {"friction.model": "EA"}))  # slide-only: accepted


def test_a_completed_state_serves_another_step_limit(base, state_file):
    """Above the state's steps the limit leaves its path as it is; below them the case ends at its next step."""
    n = len(read_normal_state(state_file, base).records)
    for limit, status in ((n + 500, Status.COMPLETED), (n - 1, Status.DIVERGED)):
        config = apply_settings(base, {"limits.max_steps": limit})
        case = run_case(Parameters.from_config(config), resume=read_normal_state(state_file, config))
        assert case.status == status, limit
    assert "more than limits.max_steps" in case.reason and len(case.records) == n + 1


def test_damaged_or_foreign_state_files_are_refused(base, state_file, tmp_path):
    data = bytearray(state_file.read_bytes())
    data[len(data) // 2] ^= 0xFF
    (tmp_path / "damaged.npz").write_bytes(bytes(data))
    np.savez(tmp_path / "foreign.npz", x=np.zeros(3))
    (tmp_path / "text.npz").write_text("not a state")
    for name, match in (("damaged.npz", "checksum|cannot read"), ("foreign.npz", "cannot read"),
                        ("text.npz", "cannot read"), ("missing.npz", "does not exist")):
        with pytest.raises(NormalStateError, match=match):
            read_normal_state(tmp_path / name, base)


def test_the_cli_refuses_a_foreign_state_in_one_line(state_file, tmp_path, capsys):
    out = tmp_path / "case.nc"
    args = ["run", str(PAPER_CONFIG), *[a for s in COARSE for a in ("--set", s)], "--set", "mesh.size=16", "-q",
            "--from-state", str(state_file), "-o", str(out)]
    assert main(args) == 2
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0 and "mesh.size = 32.0 there, 16.0 here" in err
    assert not out.exists() and list(tmp_path.iterdir()) == []
