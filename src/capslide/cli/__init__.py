"""Command-line interface: ``capslide <command> ...``.

Bad input ends with a one-line ``capslide: error: ...`` message on stderr and exit code 2, never a traceback;
nothing is written before the input is known to be good.
"""

from __future__ import annotations

import argparse
import os
import signal
import sys
from collections.abc import Sequence

from ..config import ConfigError
from ..io.reading import ResultFileError
from ..version import __version__
from .cases import cmd_collect, cmd_config, cmd_constants, cmd_inspect, cmd_mesh, cmd_preload, cmd_run, cmd_vtk
from .common import EXIT_BAD_INPUT, EXIT_INTERRUPTED, InputError, add_config_args
from .figures import FIGURE_HELP, cmd_figure
from .studies import cmd_convergence, cmd_experiment, cmd_experiment3d, cmd_options, cmd_pull_off, cmd_stability, cmd_verify

__all__ = ["main", "build_parser"]


class _Parser(argparse.ArgumentParser):
    """argparse with a one-line error: ``capslide: error: ...`` (no usage block), exit 2."""

    def error(self, message: str):
        command = self.prog.removeprefix("capslide").strip()
        help_call = " ".join(["capslide", *([command] if command else []), "--help"])
        self.exit(EXIT_BAD_INPUT, f"capslide: error: {command + ': ' if command else ''}{message} ({help_call})\n")


def _add_path_args(p: argparse.ArgumentParser, output: str, output_help: str, from_state_help: str) -> None:
    """The options of the commands that run a load path: config, output, progress, resume, start state."""
    add_config_args(p)
    p.add_argument("-o", "--output", required=True, metavar=output, help=output_help)
    p.add_argument("-q", "--quiet", action="store_true", help="no per-step progress")
    p.add_argument("--resume", action="store_true",
                   help=f"continue from the checkpoint a killed run left beside {output} (output.checkpoint_every)")
    p.add_argument("--from-state", metavar="STATE.npz", help=from_state_help)


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(prog="capslide", description="capslide: finite element simulations of a soft adhesive cap sliding "
                     "on a rigid substrate (Mergel et al. 2019). Exit codes: 0 done, 2 bad input, 3 contact detached, "
                     "4 no equilibrium found, 5 a slide with slip weakening snapped, 130 interrupted.")
    parser.add_argument("--version", action="version", version=f"capslide {__version__}")
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")

    p = sub.add_parser("config", help="the validated configuration as YAML (presets applied, defaults filled)")
    add_config_args(p)
    p.add_argument("-o", "--output", metavar="CONFIG.yaml", help="write it to this file (default: print it)")
    p.set_defaults(func=cmd_config)

    p = sub.add_parser("constants", help="print derived CGCM constants as JSON (internal units and SI)")
    add_config_args(p)
    p.set_defaults(func=cmd_constants)

    p = sub.add_parser("figure", help=FIGURE_HELP, description=f"capslide figure: {FIGURE_HELP}")
    p.add_argument("name", help="figure name (listed above)")
    p.add_argument("configs", nargs="*", metavar="CONFIG", help="YAML config file(s) or scene names (model figures)")
    p.add_argument("--scene", metavar="NAME", help="start from the packaged scene NAME (model figures)")
    p.add_argument("--set", dest="overrides", action="append", default=[], metavar="KEY=VALUE", help="config override")
    p.add_argument("--input", metavar="FILE.nc", help="result file to draw from (cap_setup: a mesh file)")
    p.add_argument("--table", dest="tables", action="append", default=[], metavar="FILE.csv",
                   help="table(s) to draw from (verification), repeatable")
    p.add_argument("-o", "--output", action="append", required=True, metavar="FILE", help="output .pdf/.png (repeatable)")
    p.set_defaults(func=cmd_figure)

    p = sub.add_parser("run", help="run one case (mesh, approach, preload, slide), write its netCDF file")
    _add_path_args(p, "CASE.nc", "the case file to write (netCDF)",
                   "start the slide from this normal state (capslide preload) instead of approaching and preloading "
                   "again; it must be computed for this configuration but its slide-only keys")
    p.set_defaults(func=cmd_run)

    p = sub.add_parser("preload", help="approach and preload the cap, write the normal state every slide of it starts from")
    _add_path_args(p, "STATE.npz", "the normal state file to write",
                   "go on from this normal state, computed for the same configuration at a preload this path passes "
                   "(loading.retract_from for a tensile preload, or one of loading.preload_via)")
    p.set_defaults(func=cmd_preload)

    p = sub.add_parser("verify", help="sweep a Hertz/JKR/Maugis-Dugdale verification scene, write a CSV table of "
                       "errors")
    add_config_args(p, scene_help="start from the packaged scene NAME (2D: hertz, jkr; 3D: sphere_hertz, sphere_md3, "
                    "sphere_md5, sphere_dugdale3); a 2D configuration must be that kind of scene (hertz = "
                    "contact.repulsion_only)")
    p.add_argument("-o", "--output", required=True, metavar="TABLE.csv", help="the table of FE against closed forms")
    p.add_argument("-q", "--quiet", action="store_true")
    p.add_argument("--resume", action="store_true", help="continue an edge-controlled sweep from the checkpoint a "
                   "killed run left beside TABLE.csv (saved after the approach and after each load)")
    p.set_defaults(func=cmd_verify)

    p = sub.add_parser("collect", help="collect case files into one dataset: the model x preload x step cube")
    p.add_argument("files", nargs="+", metavar="CASE.nc")
    p.add_argument("-o", "--output", required=True, metavar="CASES.nc", help="the collected file to write (netCDF)")
    p.set_defaults(func=cmd_collect)

    p = sub.add_parser("inspect", help="print parameters, status and case scalars of a case file")
    p.add_argument("file", metavar="CASE.nc")
    p.set_defaults(func=cmd_inspect)

    p = sub.add_parser("stability", help="evaluate the hard cases of a stability spec, write the table (.csv/.md)")
    p.add_argument("spec", metavar="SPEC.yaml", help="the suite (config/stability.yaml)")
    p.add_argument("configs", nargs="+", metavar="CONFIG", help="base config file(s) of the cases")
    p.add_argument("--cases", required=True, metavar="DIR", help="directory with one <case>.nc per hard case")
    p.add_argument("-o", "--output", action="append", required=True, metavar="FILE", help="table.csv / table.md")
    p.set_defaults(func=cmd_stability)

    p = sub.add_parser("pull-off", help="write a config overlay: loading.preload = a fraction of a case's pull-off force")
    p.add_argument("file", metavar="CASE.nc", help="a case that ended detached in its preload (the pull-off force)")
    p.add_argument("--fraction", type=float, required=True, help="fraction of the pull-off force, in (0, 1]")
    p.add_argument("-o", "--output", required=True, metavar="OVERLAY.yaml", help="the config overlay to write")
    p.set_defaults(func=cmd_pull_off)

    p = sub.add_parser("convergence", help="evaluate a convergence study: table (.csv/.md), error-vs-time figure (.pdf/.png)")
    p.add_argument("spec", metavar="SPEC.yaml", help="the study (config/convergence.yaml)")
    p.add_argument("--cases", required=True, metavar="DIR", help="directory with <case>/<run>.nc per run")
    p.add_argument("--orders", metavar="FILE.csv", help="also write the observed convergence orders (CSV)")
    p.add_argument("-o", "--output", action="append", required=True, metavar="FILE",
                   help="table.csv / table.md / figure .pdf / .png")
    p.set_defaults(func=cmd_convergence)

    p = sub.add_parser("options", help="evaluate the options study: table (.csv/.md), Ft and area figure, edge figure")
    p.add_argument("spec", metavar="SPEC.yaml", help="the study (config/options.yaml)")
    p.add_argument("--cases", required=True, metavar="DIR", help="directory with one <model>_<option>.nc per run")
    p.add_argument("-o", "--output", action="append", required=True, metavar="FILE", help="table.csv / table.md")
    p.add_argument("--forces", action="append", metavar="FILE", help="Ft and area against ubar (.pdf / .png)")
    p.add_argument("--edges", action="append", metavar="FILE", help="contact and stick-zone edges (.pdf / .png)")
    p.set_defaults(func=cmd_options)

    p = sub.add_parser("experiment", help="evaluate the experiment study: table, findings, panels, edges, interfaces")
    p.add_argument("spec", metavar="SPEC.yaml", help="the study (config/experiment.yaml)")
    p.add_argument("--cases", required=True, metavar="DIR", help="directory with one <model>_<option>.nc per run")
    p.add_argument("-o", "--output", action="append", required=True, metavar="FILE", help="table.csv / table.md")
    p.add_argument("--findings", metavar="FILE.md", help="what the table shows, in sentences with its numbers")
    p.add_argument("--figures", metavar="DIR", help="write panels_*, edges_* and interface_* (.pdf, .png) here")
    p.set_defaults(func=cmd_experiment)

    p = sub.add_parser("experiment3d", help="evaluate the experiment in numbers (3D): table, panels, outlines")
    p.add_argument("files", nargs="+", metavar="CASE.nc", help="the cases of the experiment scene's study")
    p.add_argument("-o", "--output", action="append", required=True, metavar="FILE", help="table.csv / table.md")
    p.add_argument("--panels", action="append", metavar="FILE", help="the four panels (.pdf / .png)")
    p.add_argument("--outlines", action="append", metavar="FILE", help="outlines at the snapshot times (.pdf / .png)")
    p.set_defaults(func=cmd_experiment3d)

    p = sub.add_parser("vtk", help="export the field snapshots of a case file for ParaView (.vtu series + .pvd)")
    p.add_argument("file", metavar="CASE.nc")
    p.add_argument("-o", "--output", required=True, metavar="DIR", help="output directory")
    p.add_argument("--stem", help="file name stem (default: the case file's)")
    p.set_defaults(func=cmd_vtk)

    p = sub.add_parser("mesh", help="build the cap mesh of a configuration, write it as netCDF")
    add_config_args(p)
    p.add_argument("-o", "--output", required=True, metavar="MESH.nc", help="the mesh file to write (netCDF)")
    p.set_defaults(func=cmd_mesh)
    return parser


def _terminate(signum, frame):
    raise KeyboardInterrupt  # SIGTERM, SIGHUP (kill, a time limit, a closed terminal): leave like Ctrl-C, nothing partial


def main(argv: Sequence[str] | None = None) -> int:
    parser = build_parser()
    try:
        args = parser.parse_args(argv)
    except SystemExit as done:  # --help, --version, or a one-line usage error (exit 2)
        return int(done.code or 0)
    signal.signal(signal.SIGTERM, _terminate)
    signal.signal(signal.SIGHUP, _terminate)
    try:
        code = args.func(args)
        sys.stdout.flush()  # here, where a closed pipe can be handled, not at exit
        return code
    except (ConfigError, InputError, ResultFileError) as err:
        print(f"capslide: error: {err}", file=sys.stderr)
        return EXIT_BAD_INPUT
    except KeyboardInterrupt:  # Ctrl-C or a scheduler's SIGINT: results are written atomically, nothing partial remains
        print("capslide: interrupted; no output written", file=sys.stderr)
        return EXIT_INTERRUPTED
    except BrokenPipeError:  # the reader of standard output went away (capslide ... | head): stop quietly
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 128 + signal.SIGPIPE
