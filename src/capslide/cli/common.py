"""What every command shares: exit codes, the one-line input error, config arguments, output checks."""

from __future__ import annotations

import argparse
import csv
import io
import tempfile
from collections.abc import Sequence
from pathlib import Path

from ..config import load_config, scene_path
from ..io.atomic import replacing
from ..params import Parameters
from ..states import Status

__all__ = ["EXIT_BAD_INPUT", "EXIT_INTERRUPTED", "EXIT_STATUS", "InputError", "add_config_args", "config_sources", "command_line",
           "parameters",
           "check_outputs", "write_text_atomic", "csv_text"]

EXIT_BAD_INPUT = 2
EXIT_INTERRUPTED = 130
EXIT_STATUS = {Status.COMPLETED: 0, Status.DETACHED: 3, Status.DIVERGED: 4, Status.SNAPPED: 5}


class InputError(ValueError):
    """Bad command-line input other than the configuration."""


def add_config_args(parser: argparse.ArgumentParser, scene_help: str | None = None) -> None:
    parser.add_argument("configs", nargs="*", metavar="CONFIG",
                        help="YAML config file(s) or packaged scene name(s), later ones update earlier ones")
    parser.add_argument("--scene", metavar="NAME", help=scene_help or "start from the packaged scene NAME (cap: the "
                        "paper's study; sphere, experiment: 3D; hertz, jkr, sphere_hertz, sphere_md3, sphere_md5, "
                        "sphere_dugdale3: verification), the config files update it")
    parser.add_argument("--set", dest="overrides", action="append", default=[], metavar="KEY=VALUE",
                        help="override a config value by its dotted key, e.g. --set friction.s_cut=0 (repeatable)")


def config_sources(args) -> list[str]:
    """The packaged scene of ``--scene`` (if any), then the config files: what ``args`` configures from."""
    sources = ([scene_path(args.scene)] if args.scene else []) + list(args.configs)
    if not sources:
        raise InputError("no configuration: give a config file or a packaged scene (--scene cap)")
    return sources


def command_line() -> str:
    """This program's command line, for the ``history`` of the files it writes."""
    import shlex
    import sys

    return shlex.join(["capslide", *sys.argv[1:]]) if Path(sys.argv[0]).name in ("capslide", "__main__.py") else \
        f"capslide (called from {Path(sys.argv[0]).name})"


def parameters(args) -> Parameters:
    return Parameters.from_config(load_config(config_sources(args), args.overrides))


def check_outputs(paths: Sequence[str], suffixes: set[str]) -> list[Path]:
    """The output paths, each with an allowed suffix in a writable directory (InputError otherwise)."""
    out = []
    for text in paths:
        path = Path(text)
        if path.suffix.lstrip(".") not in suffixes:
            raise InputError(f"output '{path}': unsupported file type (allowed: {', '.join(sorted(suffixes))})")
        if path.is_dir():
            raise InputError(f"output '{path}' is a directory")
        parent = path.parent if str(path.parent) else Path(".")
        existing = next((d for d in [parent, *parent.parents] if d.exists()), Path("."))
        if not existing.is_dir():
            raise InputError(f"output '{path}': '{existing}' is not a directory")
        try:  # a real probe: permission bits say nothing for root or on read-only mounts
            with tempfile.TemporaryFile(dir=existing):
                pass
        except OSError as err:
            raise InputError(f"output '{path}': directory '{existing}' is not writable ({err.strerror})") from None
        out.append(path)
    return out


def write_text_atomic(path: Path, text: str) -> None:
    with replacing(path) as tmp:
        tmp.write_text(text)


def csv_text(rows: list[dict], columns: Sequence[str]) -> str:
    """Rows as CSV text with the given columns (missing cells empty)."""
    buf = io.StringIO()
    writer = csv.DictWriter(buf, fieldnames=list(columns), lineterminator="\n")
    writer.writeheader()
    writer.writerows([{k: r.get(k, "") for k in columns} for r in rows])
    return buf.getvalue()
