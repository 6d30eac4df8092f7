"""Property-based checks (Hypothesis) that no input hangs the load path or slips past the saved-state checks: every
drawn run ends with a recorded status or a one-line refusal, within a bound on its steps (issue 42)."""

import functools
import json
import signal
import tempfile
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from test_normal_state import COARSE

from capslide.config import ConfigError, apply_overrides, apply_settings, validate
from capslide.driver.case import run_case
from capslide.io.checkpoint import SavedCase, read_signed, write_signed
from capslide.io.normal_state import NormalStateError, read_normal_state, write_normal_state
from capslide.io.state_check import SavedStateMismatch
from capslide.params import Parameters
from capslide.states import Phase, Status

from conftest import PAPER_CONFIG

SECONDS = 90  # a drawn run that takes longer has hung (the coarse cases take about a second)
PROPERTY = settings(max_examples=14, deadline=None, derandomize=True, database=None,
                    suppress_health_check=[HealthCheck.too_slow])


@functools.cache
def base() -> dict:
    from capslide.config import load_config

    return validate(apply_overrides(load_config([PAPER_CONFIG], ["preset=fast"]), [*COARSE, "output.snapshot_ubar=[]"]))


@functools.cache
def approach_end_force() -> float:
    """Fn at the end of the coarse cap's approach: a preload equal to it makes the preload leg zero-length."""
    res = run_case(Parameters.from_config(base()), stop_before="preload")
    return [r.Fn for r in res.records if r.phase == Phase.APPROACH][-1]


class Hung(Exception):
    pass


def bounded(run):
    """``run()`` under an alarm of SECONDS: a hang fails instead of blocking the suite."""
    def alarm(signum, frame):
        raise Hung(f"no end within {SECONDS} s")

    previous = signal.signal(signal.SIGALRM, alarm)
    signal.alarm(SECONDS)
    try:
        return run()
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, previous)


def assert_ended(res, params):
    assert res.status in set(Status)
    assert len(res.records) <= params.config["limits"]["max_steps"] + 1
    if res.status != Status.COMPLETED:
        assert res.reason and "\n" not in res.reason


TINY = [0.0, 1e-300, 1e-14, 1e-13, 5e-13, 1e-12]
lengths = st.one_of(st.sampled_from(TINY + [-t for t in TINY]), st.floats(-0.05, 0.05, allow_nan=False))
dwells = st.one_of(st.sampled_from(TINY), st.floats(0.0, 0.3, allow_nan=False))
preloads = st.sampled_from(["approach end", "approach end + 1e-13", 0.0, -0.05, 0.05])


@pytest.mark.slow
@PROPERTY
@given(ubar_max=lengths, dwell=dwells, preload=preloads, slide_back=st.booleans())
def test_every_load_path_ends(ubar_max, dwell, preload, slide_back):
    """Leg lengths and dwells at and below the continuation's tolerance, and a preload equal to the force the
    approach ends at, end with a status, never a loop."""
    if isinstance(preload, str):
        preload = approach_end_force() + (1e-13 if preload.endswith("1e-13") else 0.0)
    sets = {"loading.ubar_max": ubar_max, "loading.dwell": dwell, "loading.preload": preload,
            "loading.slide_back": slide_back, "loading.velocity": 1e-6 if dwell > 0 else None}
    try:
        params = Parameters.from_config(validate(apply_settings(base(), sets)))
    except ConfigError as err:
        assert "\n" not in str(err)
        return
    assert_ended(bounded(lambda: run_case(params)), params)


@functools.cache
def state() -> tuple[str, dict, dict]:
    """A valid normal state of the coarse cap, in a folder that lives as long as the test session."""
    folder = Path(tempfile.mkdtemp(prefix="capslide-state-"))
    params = Parameters.from_config(base())
    pre = run_case(params, stop_before="dwell")
    path = folder / "Fn0.npz"
    write_normal_state(path, SavedCase(pre.state, pre.records, [], pre.wall_time), params.config)
    data, meta = read_signed(path, "normal state", NormalStateError)
    return str(path), data, meta


ARRAY_FIELDS = ["x", "anchors", "accumulated_slip", "pressure_multiplier", "loop_x", "record_gap", "record_Fn",
                "record_phase"]
HEADER_FIELDS = ["leg", "loop", "targets", "marks", "cutbacks", "smallest", "stage_h", "time", "elapsed", "status",
                 "reason", "onset_ceiling"]
ARRAY_KINDS = ["shorter", "longer", "2-D", "text", "integers", "NaN", "inf", "empty", "booleans"]
header_values = st.one_of(st.none(), st.booleans(), st.integers(-3, 7), st.floats(allow_nan=True),
                          st.text(max_size=6), st.lists(st.integers(-1, 3), max_size=3),
                          st.dictionaries(st.sampled_from(["value", "step", "x"]), st.floats(), max_size=2))


def corrupted(a: np.ndarray, kind: str) -> np.ndarray:
    a = np.asarray(a)
    flat = a.reshape(-1) if a.size else np.zeros(3)
    return {"shorter": flat[:-1], "longer": np.concatenate([flat, flat[:1]]), "2-D": np.stack([flat, flat]),
            "text": flat.astype(str), "integers": flat.astype(np.int64), "NaN": np.full_like(flat, np.nan, dtype=float),
            "inf": np.full_like(flat, np.inf, dtype=float), "empty": flat[:0], "booleans": flat > 0}[kind]


@settings(max_examples=40, deadline=None, derandomize=True, database=None, suppress_health_check=[HealthCheck.too_slow])
@given(field=st.sampled_from(ARRAY_FIELDS + HEADER_FIELDS), kind=st.sampled_from(ARRAY_KINDS), value=header_values)
def test_every_saved_state_is_refused_in_one_line_or_runs(field, kind, value):
    """A state with one field of the wrong shape, type or value, with valid checksums: refused in one line naming
    the file (and the field, when the file can be read at all), or, when the change is harmless, run to a status."""
    path, data, meta = state()
    data = dict(data)
    meta = {k: v for k, v in meta.items() if k not in ("version", "arrays_sha256")}
    if field in ARRAY_FIELDS:
        data[field] = corrupted(data.get(field, data["x"][:4]), kind)
    else:
        meta[field] = value
    with tempfile.TemporaryDirectory() as tmp:
        bad = Path(tmp) / "bad.npz"
        try:
            write_signed(bad, data, meta)
        except (TypeError, ValueError):  # JSON cannot hold it (a NaN in a dict key, say): nothing to read
            return
        params = Parameters.from_config(validate(apply_settings(base(), {"loading.ubar_max": 0.02})))
        try:
            saved = read_normal_state(bad, params.config)
            res = bounded(lambda: run_case(params, resume=saved))
        except (NormalStateError, SavedStateMismatch) as err:
            message = str(err)
            assert "bad.npz" in message and "\n" not in message, message
            assert "field" in message or "another configuration" in message or "cannot read" in message, message
            return
    assert_ended(res, params)
    json.dumps(meta)  # the header was JSON


@pytest.mark.parametrize("field", ["x", "record_gap"])
def test_the_property_sees_a_broken_field(field):
    """The draw above does refuse: a shorter field of each kind fails its check (the property is not vacuous)."""
    path, data, meta = state()
    data = {**data, field: corrupted(data[field], "shorter")}
    meta = {k: v for k, v in meta.items() if k not in ("version", "arrays_sha256")}
    with tempfile.TemporaryDirectory() as tmp:
        bad = Path(tmp) / "bad.npz"
        write_signed(bad, data, meta)
        params = Parameters.from_config(base())
        with pytest.raises((NormalStateError, SavedStateMismatch), match="field"):
            run_case(params, resume=read_normal_state(bad, params.config))
