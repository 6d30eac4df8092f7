"""Checkpoints of a running case, so that ``capslide run --resume`` continues where a killed run stopped.

A checkpoint holds one :class:`SavedCase`: the load path's state (:class:`capslide.loadpath.cap.PathState`: leg,
loop variables, current state, friction anchors, preload targets, last steps, totals), the step records and field
snapshots so far, and the wall time spent. It is a directory beside the case file, ``.NAME.nc.checkpoint/``:

* ``state.npz``: the path state and a JSON header (capslide version, SHA-256 of the configuration, the chunks so far
  with their SHA-256, the header's own SHA-256);
* ``records-G-K.npz`` / ``snapshots-G-K.npz``: the records and snapshots added since the previous save, so that a
  save costs O(new steps); G names the writing process, K counts its saves.

A save writes the new chunks, then the state file atomically; files of other writers are removed once the state no
longer names them. Reading checks every checksum, the version and the configuration, and loads arrays without
pickle (nothing in a checkpoint can execute code); any mismatch is a :class:`CheckpointError`, and the caller
starts afresh. One process writes a checkpoint at a time (an advisory lock); a second run of the same output keeps
none.
"""

from __future__ import annotations

import hashlib
import json
import shutil
import uuid
import zipfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import yaml

from ..fem.viscous import Networks
from ..loadpath.cap import Mark, PathState
from ..loadpath.continuation import Loop
from ..loadpath.measures import RECORD_PROFILES, RECORD_SCALARS, Snapshot, StepRecord
from ..model.system import History
from ..states import Phase, Status
from ..version import software_version
from .atomic import replacing
from .state_check import check_arrays, check_header, check_record_arrays, check_snapshot_arrays

__all__ = ["STATE", "SavedCase", "CheckpointError", "CheckpointBusy", "CheckpointWriter", "checkpoint_path", "config_text",
           "load_checkpoint", "write_arrays", "read_arrays", "array_sha", "record_arrays", "records_of",
           "prefixed_record_arrays", "records_in", "state_arrays",
           "path_state", "write_signed", "read_signed"]

STATE = "state.npz"


class CheckpointError(ValueError):
    """A checkpoint that cannot be used for this run (the message says why)."""


class CheckpointBusy(RuntimeError):
    """Another process is writing this checkpoint."""


@dataclass
class SavedCase:
    """Everything a resumed case needs: where the path stands and what it has produced."""

    state: PathState
    records: list[StepRecord]
    snapshots: list[Snapshot]
    elapsed: float  # wall time of the case before this process (s)
    ended: tuple[Status, str] | None = None  # a path that ended there (a failed preload): status and reason
    source: str = ""  # the file it was read from, as messages name it ("checkpoint 'PATH'")


def checkpoint_path(output: str | Path) -> Path:
    """Where the checkpoint of the case file ``output`` lives: ``.<name>.checkpoint`` beside it."""
    output = Path(output)
    return output.with_name(f".{output.name}.checkpoint")


def config_text(config) -> str:
    """The configuration as the canonical YAML text a checkpoint is tied to, without the ``study`` section (read by
    the workflow only: it changes nothing a case computes)."""
    return yaml.safe_dump({k: v for k, v in dict(config).items() if k != "study"}, sort_keys=True)


def array_sha(*arrays: np.ndarray) -> str:
    """SHA-256 of the arrays' bytes, in the order given."""
    h = hashlib.sha256()
    for a in arrays:
        h.update(np.ascontiguousarray(a).tobytes())
    return h.hexdigest()


def write_arrays(path: Path, arrays: dict[str, np.ndarray]) -> str:
    """Write arrays atomically; the SHA-256 of their bytes (in name order)."""
    with replacing(path) as tmp, open(tmp, "wb") as fh:
        np.savez(fh, **arrays)
    return array_sha(*(arrays[k] for k in sorted(arrays)))


def read_arrays(path: Path, sha: str | None = None) -> dict[str, np.ndarray]:
    with np.load(path, allow_pickle=False) as archive:
        data = {name: archive[name] for name in archive.files}
    if sha is not None and array_sha(*(data[k] for k in sorted(data))) != sha:
        raise CheckpointError(f"checkpoint file '{path}' does not match its checksum")
    return data


def write_signed(path: Path, arrays: dict[str, np.ndarray], header: dict) -> None:
    """Write arrays with a JSON header that names this capslide version and the arrays' SHA-256, itself
    checksummed (a checkpoint's state file, a normal state)."""
    header = {**header, "version": software_version(), "arrays_sha256": array_sha(*(arrays[k] for k in sorted(arrays)))}
    text = json.dumps(header)
    write_arrays(path, {**arrays, "header": np.array(text),
                        "header_sha256": np.array(hashlib.sha256(text.encode()).hexdigest())})


def _source_part(version) -> str | None:
    """The ``src<digest>`` of a version string (capslide.version.software_version): the code that computes. A
    checkpoint is tied to it, not to the commit, so that a change of the docs alone leaves it valid."""
    return str(version).rsplit(".", 1)[-1].rsplit("+", 1)[-1] if version else None


def read_signed(path: Path, what: str, error: type[Exception]) -> tuple[dict[str, np.ndarray], dict]:
    """The arrays and header of :func:`write_signed`'s file; ``error`` naming ``what`` and ``path`` when a checksum
    does not match or another version of the code (its source digest) wrote it."""
    data = read_arrays(path)
    text = str(data.pop("header"))
    if hashlib.sha256(text.encode()).hexdigest() != str(data.pop("header_sha256")):
        raise error(f"{what} '{path}' does not match its checksum")
    meta = json.loads(text)
    if not isinstance(meta, dict):
        raise error(f"{what} '{path}': field 'header' is a {type(meta).__name__}, not a mapping")
    if _source_part(meta.get("version")) != _source_part(software_version()):
        raise error(f"{what} '{path}' was written by capslide {meta.get('version')}, this is {software_version()}")
    if array_sha(*(data[k] for k in sorted(data))) != meta.get("arrays_sha256"):
        raise error(f"{what} '{path}' does not match its checksum")
    return data, meta


def read_guarded(load, path: Path, what: str, error: type[Exception]):
    """``load()``; any failure to read the file (damaged, truncated, foreign) as one ``error`` naming ``what`` and
    ``path`` (``error`` itself passes through)."""
    try:
        return load()
    except error:
        raise
    except (OSError, EOFError, ValueError, KeyError, TypeError, IndexError, AttributeError, zipfile.BadZipFile,
            json.JSONDecodeError) as err:  # an empty file: EOFError; a header of another shape: AttributeError
        raise error(f"cannot read {what} '{path}': {err}") from None


RECORD_PREFIX = "record_"  # the records' arrays in a file that holds more than records


def record_arrays(records: list[StepRecord]) -> dict[str, np.ndarray]:
    out = {name: np.array([getattr(r, name) for r in records], dtype=float) for name in RECORD_SCALARS}
    out.update({name: np.array([getattr(r, name) for r in records]) for name in RECORD_PROFILES})
    return out


def records_of(data: dict[str, np.ndarray]) -> list[StepRecord]:
    """The step records of :func:`record_arrays`' arrays, checked first (BadField naming a field)."""
    check_record_arrays(data, RECORD_PREFIX)
    out = []
    for i in range(len(data["phase"])):
        kw = {name: float(data[name][i]) for name in RECORD_SCALARS if name in data}  # older files: no time
        kw["phase"] = Phase(int(kw["phase"]))
        kw["newton_iterations"] = int(kw["newton_iterations"])
        kw["krylov_iterations"] = int(kw["krylov_iterations"])
        kw["steady_step"] = bool(kw.get("steady_step", 0.0))
        kw["snapped"] = bool(kw.get("snapped", 0.0))
        kw.update({name: data[name][i] for name in RECORD_PROFILES if name in data})  # older files: no y parts
        out.append(StepRecord(**kw))
    return out


def prefixed_record_arrays(records: list[StepRecord]) -> dict[str, np.ndarray]:
    """:func:`record_arrays` under :data:`RECORD_PREFIX`, for a file that holds other arrays too."""
    return {RECORD_PREFIX + name: values for name, values in record_arrays(records).items()}


def records_in(data: dict[str, np.ndarray]) -> list[StepRecord]:
    """The step records stored by :func:`prefixed_record_arrays` among a file's arrays ``data``."""
    return records_of({k.removeprefix(RECORD_PREFIX): v for k, v in data.items() if k.startswith(RECORD_PREFIX)})


def _mark_rows(marks) -> list[list]:
    """Marks as JSON rows [phase, ubar, Fn, area_stick, Ft, area]."""
    return [[int(m.phase), m.ubar, m.Fn, m.area_stick, m.Ft, m.area] for m in marks]


def _marks_of(rows) -> list[Mark]:
    return [Mark(Phase(int(m[0])), *m[1:]) for m in rows]


def state_arrays(s: PathState) -> tuple[dict[str, np.ndarray], dict]:
    """A path state as arrays (current state, loop states, friction, pressure and viscous history) and JSON-able
    header entries."""
    arrays = {"x": s.x}
    if s.loop is not None:
        arrays["loop_x"] = s.loop.x
        if s.loop.x_prev is not None:
            arrays["loop_x_prev"] = s.loop.x_prev
    if s.history.anchors is not None:
        arrays["anchors"] = s.history.anchors
    if s.history.slip is not None:
        arrays["accumulated_slip"] = s.history.slip
    if s.history.thresholds is not None:
        arrays["frozen_thresholds"] = s.history.thresholds
    if s.history.pressure is not None:
        arrays["pressure_multiplier"] = s.history.pressure
    if s.history.networks is not None:
        arrays["viscous_networks"] = s.history.networks.networks
        arrays["viscous_c_inv"] = s.history.networks.c_inv
    loop = None if s.loop is None else {
        "value": s.loop.value, "step": s.loop.step, "value_prev": s.loop.value_prev, "smallest": s.loop.smallest,
        "cutbacks": s.loop.cutbacks, "pending": list(s.loop.pending), "snapped": s.loop.snapped}
    header = {"leg": s.leg, "loop": loop, "targets": list(s.targets),
              "marks": _mark_rows(s.marks), "cutbacks": s.cutbacks,
              "smallest": s.smallest, "stage_h": s.stage_h, "time": s.history.time,
              "onset_ceiling": s.onset_ceiling, "preload_Fn": s.preload_Fn,
              "area_bracket": _mark_rows(s.area_bracket)}
    return arrays, header


def path_state(data: dict[str, np.ndarray], meta: dict) -> PathState:
    """The path state of :func:`state_arrays`' arrays and header entries, both checked first (BadField naming a
    field)."""
    check_arrays(data, meta)
    lm = meta["loop"]
    loop = None if lm is None else Loop(lm["value"], lm["step"], data["loop_x"], data.get("loop_x_prev"),
                                        lm["value_prev"], lm["smallest"], lm["cutbacks"], list(lm["pending"]),
                                        lm.get("snapped", False))
    networks = None if "viscous_networks" not in data else Networks(data["viscous_networks"], data["viscous_c_inv"])
    history = History(data.get("anchors"), data.get("accumulated_slip"), data.get("pressure_multiplier"), networks,
                      meta.get("time", 0.0), data.get("frozen_thresholds"))
    return PathState(meta["leg"], data["x"], history, loop, list(meta["targets"]),
                     _marks_of(meta["marks"]), meta["cutbacks"], meta["smallest"],
                     meta.get("stage_h"), meta.get("onset_ceiling", float("nan")), meta.get("preload_Fn"),
                     _marks_of(meta.get("area_bracket", [])))


def _flock(fh, exclusive: bool) -> None:
    """Take (non-blocking; OSError when another process holds it) or release the advisory lock of ``fh``. POSIX
    only (fcntl): elsewhere nothing is locked, and two runs of one output may both write its checkpoint."""
    try:
        import fcntl
    except ImportError:  # not POSIX (Windows): capslide is tested on Linux only
        return
    fcntl.flock(fh, (fcntl.LOCK_EX | fcntl.LOCK_NB) if exclusive else fcntl.LOCK_UN)


class CheckpointWriter:
    """Saves a running case into the checkpoint directory ``path``, new records and snapshots only at each save.

    Raises :class:`CheckpointBusy` when another process holds the checkpoint.
    """

    def __init__(self, path: Path, config_yaml: str):
        self.path, self.config_sha = Path(path), hashlib.sha256(config_yaml.encode()).hexdigest()
        if self.path.exists() and not self.path.is_dir():
            self.path.unlink()  # a stale file where the directory goes
        self.path.mkdir(parents=True, exist_ok=True)
        self._lock = open(self.path / "lock", "w")  # noqa: SIM115 (held until the writer is done)
        try:
            _flock(self._lock, exclusive=True)
        except OSError:
            self._lock.close()
            raise CheckpointBusy(f"another run is writing the checkpoint '{self.path}'") from None
        self.generation = uuid.uuid4().hex[:8]
        self.chunks: list[dict] = []
        self.n_records = self.n_snapshots = 0

    def _chunk(self, kind: str, arrays: dict[str, np.ndarray], count: int) -> None:
        name = f"{kind}-{self.generation}-{len(self.chunks):04d}.npz"
        self.chunks.append({"file": name, "kind": kind, "count": count, "sha256": write_arrays(self.path / name, arrays)})

    def save(self, saved: SavedCase) -> None:
        new_records = saved.records[self.n_records:]
        if new_records:
            self._chunk("records", record_arrays(new_records), len(new_records))
        new_snaps = saved.snapshots[self.n_snapshots:]
        if new_snaps:
            self._chunk("snapshots", {"ubar": np.array([sn.ubar for sn in new_snaps]),
                                      "u": np.stack([sn.u for sn in new_snaps]),
                                      "I1_sigma": np.stack([sn.I1_sigma for sn in new_snaps]),
                                      "h": np.array([sn.h for sn in new_snaps]),
                                      "slip_state": np.stack([sn.slip_state for sn in new_snaps])}, len(new_snaps))
        self.n_records, self.n_snapshots = len(saved.records), len(saved.snapshots)
        arrays, state = state_arrays(saved.state)
        write_signed(self.path / STATE, arrays, {"config_sha256": self.config_sha, **state, "elapsed": saved.elapsed,
                                                 "chunks": self.chunks})
        keep = {c["file"] for c in self.chunks} | {STATE, "lock"}
        for other in self.path.iterdir():
            if other.name not in keep and not other.name.startswith("."):  # chunks of earlier writers
                other.unlink(missing_ok=True)

    def __enter__(self) -> CheckpointWriter:
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def remove(self) -> None:
        """Delete the checkpoint (the case file is written) and release it."""
        shutil.rmtree(self.path, ignore_errors=True)
        self.close()

    def close(self) -> None:
        if not self._lock.closed:
            _flock(self._lock, exclusive=False)
            self._lock.close()


def _load(path: Path, config_yaml: str) -> SavedCase:
    if not path.is_dir():
        raise CheckpointError(f"checkpoint '{path}' is not a checkpoint directory")
    data, meta = read_signed(path / STATE, "checkpoint", CheckpointError)
    check_header(meta, "checkpoint")
    if meta.get("config_sha256") != hashlib.sha256(config_yaml.encode()).hexdigest():
        raise CheckpointError(f"checkpoint '{path}' was written for a different configuration")
    records, snapshots = [], []
    for chunk in meta["chunks"]:
        part = read_arrays(path / chunk["file"], chunk["sha256"])
        if chunk["kind"] == "records":
            records += records_of(part)
        else:
            check_snapshot_arrays(part)
            n = len(part["ubar"])  # older files: no height and friction states
            h, states = part.get("h", np.full(n, np.nan)), part.get("slip_state", np.zeros((n, 0), dtype=np.int8))
            snapshots += [Snapshot(float(u), part["u"][k], part["I1_sigma"][k], float(h[k]), states[k].astype(np.int8))
                          for k, u in enumerate(part["ubar"])]
    return SavedCase(path_state(data, meta), records, snapshots, meta["elapsed"], source=f"checkpoint '{path}'")


def load_checkpoint(path: str | Path, config_yaml: str) -> SavedCase:
    """Read a checkpoint written for the same configuration and capslide version (CheckpointError otherwise)."""
    path = Path(path)
    return read_guarded(lambda: _load(path, config_yaml), path, "checkpoint", CheckpointError)
