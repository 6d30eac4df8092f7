"""The installed capslide version, and the version a result file records (with the git commit when there is one)."""

from __future__ import annotations

import functools
import subprocess
from importlib.metadata import PackageNotFoundError, version
from pathlib import Path

try:
    __version__ = version("capslide")
except PackageNotFoundError:  # running from a source tree without installation
    __version__ = "0+unknown"

__all__ = ["__version__", "software_version"]


@functools.cache
def software_version() -> str:
    """``0.1.0`` or, from a git checkout, ``0.1.0+g1234abcd5678`` (``.dirty`` with uncommitted changes)."""
    checkout = Path(__file__).resolve().parents[2]  # src/capslide/version.py in a source checkout
    if not (checkout / ".git").exists():
        return __version__
    try:
        out = subprocess.run(["git", "describe", "--always", "--dirty=.dirty", "--abbrev=12", "--exclude=*"],
                             cwd=checkout, capture_output=True, text=True, timeout=5)
    except (OSError, subprocess.SubprocessError):
        return __version__
    commit = out.stdout.strip()
    return f"{__version__}+g{commit}" if out.returncode == 0 and commit else __version__
