"""Atomic file writes: every result file is written to a temporary name beside it, then renamed onto it.

The temporary name is unique per writer (``.NAME.<host>-<pid>.<random>.tmp``), so two processes writing the same
file do not disturb each other: the last rename wins, and a reader never sees a partial file. The file's data and
the rename are flushed to disk (fsync), so that a crashed node leaves the old file or the new one, never an empty
one. A writer that was killed leaves its temporary file; the next write of the same file on the same host removes
those of writers that no longer run.
"""

from __future__ import annotations

import contextlib
import os
import socket
import tempfile
from collections.abc import Iterator
from pathlib import Path

__all__ = ["replacing", "stale_temporaries"]


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def _fsync(path: Path, directory: bool = False) -> None:
    fd = os.open(path, os.O_RDONLY | (os.O_DIRECTORY if directory else 0))
    try:
        os.fsync(fd)
    finally:
        os.close(fd)


def _host() -> str:
    return socket.gethostname().replace(".", "_").replace("-", "_") or "host"


def _running(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:  # another user's process
        return True
    return True


def stale_temporaries(path: str | Path) -> list[Path]:
    """The temporary files beside ``path`` left by writers of it on this host that no longer run (POSIX only: on
    Windows ``os.kill`` would end the process it asks about, so nothing is removed there)."""
    if os.name != "posix":
        return []
    path = Path(path)
    prefix, host, out = f".{path.name}.", _host(), []
    for tmp in path.parent.glob(f".{path.name}.*.tmp"):
        writer = tmp.name[len(prefix):].split(".")[0]  # HOST-PID
        name, _, pid = writer.rpartition("-")
        if name == host and pid.isdigit() and int(pid) != os.getpid() and not _running(int(pid)):
            out.append(tmp)
    return out


@contextlib.contextmanager
def replacing(path: str | Path) -> Iterator[Path]:
    """Yield a fresh temporary path beside ``path`` to write to; rename it onto ``path`` when the block ends
    normally (with the permissions of a new file under the umask, flushed to disk), remove it when it raises."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    for stale in stale_temporaries(path):
        stale.unlink(missing_ok=True)
    fd, name = tempfile.mkstemp(prefix=f".{path.name}.{_host()}-{os.getpid()}.", suffix=".tmp", dir=path.parent)
    os.close(fd)
    tmp = Path(name)
    try:
        yield tmp
        os.chmod(tmp, 0o666 & ~_umask())  # as open() would have made it (mkstemp makes it private)
        _fsync(tmp)
        os.replace(tmp, path)
        _fsync(path.parent, directory=True)
    finally:
        tmp.unlink(missing_ok=True)
