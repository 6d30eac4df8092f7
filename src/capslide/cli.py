"""Command-line interface: ``capslide <command> ...``.

Bad input ends with a one-line ``capslide: error: ...`` message on stderr and
exit code 2, never a traceback; nothing is written before the input is known
to be good.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
from pathlib import Path
from typing import Sequence

from . import __version__
from .config import ConfigError, load_config
from .params import Parameters

EXIT_BAD_INPUT = 2


class InputError(ValueError):
    """Bad command-line input other than the configuration."""


def _add_config_args(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("configs", nargs="+", metavar="CONFIG", help="YAML config file(s), later ones update earlier ones")
    parser.add_argument("--set", dest="overrides", action="append", default=[], metavar="KEY=VALUE",
                        help="override a config value by its dotted key, e.g. --set friction.s_cut=0 (repeatable)")


def _parameters(args) -> Parameters:
    return Parameters.from_config(load_config(args.configs, args.overrides))


def _check_outputs(paths: Sequence[str], suffixes: set[str]) -> list[Path]:
    out = []
    for text in paths:
        path = Path(text)
        if path.suffix.lstrip(".") not in suffixes:
            raise InputError(f"output '{path}': unsupported file type (allowed: {', '.join(sorted(suffixes))})")
        parent = path.parent if str(path.parent) else Path(".")
        existing = next((d for d in [parent, *parent.parents] if d.exists()), Path("."))
        if not existing.is_dir() or not os.access(existing, os.W_OK):
            raise InputError(f"output '{path}': directory '{existing}' is not writable")
        out.append(path)
    return out


def cmd_constants(args) -> int:
    """Print the derived CGCM and friction constants as JSON."""
    params = _parameters(args)
    print(json.dumps(params.derived_constants(), indent=2))
    return 0


def cmd_figure(args) -> int:
    """Render one model/experiment figure to PDF and/or PNG."""
    from . import figures  # matplotlib only when a figure is drawn

    if args.name not in figures.MODEL_FIGURES:
        raise InputError(f"unknown figure '{args.name}' (allowed: {', '.join(figures.MODEL_FIGURES)})")
    params = _parameters(args)
    outputs = _check_outputs(args.output, {"pdf", "png", "svg"})
    with figures.journal_style():
        fig = figures.MODEL_FIGURES[args.name](params)
        figures.save(fig, outputs)
    return 0


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="capslide", description=__doc__.splitlines()[0])
    parser.add_argument("--version", action="version", version=f"capslide {__version__}")
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")

    p = sub.add_parser("constants", help="print derived CGCM constants as JSON (internal units and SI)")
    _add_config_args(p)
    p.set_defaults(func=cmd_constants)

    p = sub.add_parser("figure", help="render a model or experiment figure (Tn, modelCA, modelAM, TnTt, exp_FnJKR)")
    p.add_argument("name", help="figure name")
    _add_config_args(p)
    p.add_argument("-o", "--output", action="append", required=True, metavar="FILE", help="output .pdf/.png (repeatable)")
    p.set_defaults(func=cmd_figure)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        return args.func(args)
    except (ConfigError, InputError) as err:
        print(f"capslide: error: {err}", file=sys.stderr)
        return EXIT_BAD_INPUT
