"""The installed capslide version, and the version a result file records (with the git commit when there is one)."""

from __future__ import annotations

import functools
import hashlib
import subprocess
from importlib.metadata import PackageNotFoundError, version
from pathlib import Path

try:
    __version__ = version("capslide")
except PackageNotFoundError:  # running from a source tree without installation
    __version__ = "0+unknown"

__all__ = ["__version__", "software_version", "source_digest"]


SOURCE_SUFFIXES = (".py", ".yaml", ".yml", ".json")


@functools.cache
def source_digest() -> str:
    """The first 12 hex digits of a SHA-256 over the package's source files (path and content, in path order):
    it changes with any change of the code that computes, whether committed or not."""
    package = Path(__file__).resolve().parent
    h = hashlib.sha256()
    for path in sorted(p for p in package.rglob("*") if p.suffix in SOURCE_SUFFIXES and "__pycache__" not in p.parts):
        h.update(path.relative_to(package).as_posix().encode() + b"\0" + path.read_bytes() + b"\0")
    return h.hexdigest()[:12]


@functools.cache
def software_version() -> str:
    """``0.1.0+src<digest>`` or, from a git checkout, ``0.1.0+g1234abcd5678.src<digest>`` (``.dirty`` before
    ``.src`` with uncommitted changes): the digest of :func:`source_digest` identifies the code that wrote a file,
    also between two builds with uncommitted changes at one commit."""
    src = f"src{source_digest()}"
    checkout = Path(__file__).resolve().parents[2]  # src/capslide/version.py in a source checkout
    if not (checkout / ".git").exists():
        return f"{__version__}+{src}"
    try:
        out = subprocess.run(["git", "describe", "--always", "--dirty=.dirty", "--abbrev=12", "--exclude=*"],
                             cwd=checkout, capture_output=True, text=True, timeout=5)
    except (OSError, subprocess.SubprocessError):
        return f"{__version__}+{src}"
    commit = out.stdout.strip()
    return f"{__version__}+g{commit}.{src}" if out.returncode == 0 and commit else f"{__version__}+{src}"
