"""Commands on single cases: constants, mesh, run, collect, inspect, vtk."""

from __future__ import annotations

import json
import os
import signal
import sys
from dataclasses import replace
from pathlib import Path

import numpy as np

from ..driver.observers import AfterSteps
from ..io.reading import kind_of, open_result, scale_and_unit
from .common import EXIT_STATUS, InputError, check_outputs, command_line, config_sources, parameters
from .progress import ProgressDisplay

__all__ = ["cmd_config", "cmd_constants", "cmd_mesh", "cmd_run", "cmd_preload", "cmd_collect", "cmd_inspect",
           "cmd_vtk"]

# Test hook: after this many converged steps, capslide run sends SIGINT (or the signal named by
# CAPSLIDE_INTERRUPT_SIGNAL, e.g. HUP) to its own process group, as Ctrl-C does.
INTERRUPT_AFTER_STEP = "CAPSLIDE_INTERRUPT_AFTER_STEP"
INTERRUPT_SIGNAL = "CAPSLIDE_INTERRUPT_SIGNAL"


def cmd_config(args) -> int:
    """Write (or print) the validated configuration: files merged, overrides and the preset applied, defaults filled."""
    import yaml

    from ..config import load_config
    from .common import write_text_atomic

    config = load_config(config_sources(args), args.overrides)
    text = f"# {command_line()}\n" + yaml.safe_dump(config, sort_keys=False)
    if args.output is None:
        print(text, end="")
        return 0
    (output,) = check_outputs([args.output], {"yaml", "yml"})
    write_text_atomic(output, text)
    return 0


def cmd_constants(args) -> int:
    """Print the derived CGCM and friction constants as JSON."""
    from ..constants import derived_constants

    print(json.dumps(derived_constants(parameters(args)), indent=2))
    return 0


def cmd_mesh(args) -> int:
    """Build the cap mesh of a configuration and write it as netCDF."""
    from ..io.results import mesh_dataset, write_netcdf
    from ..model import cost
    from ..model.build import mesh_from_spec, mesh_spec

    params = parameters(args)
    (output,) = check_outputs([args.output], {"nc"})
    spec = mesh_spec(params)
    cost.check(params, spec, steps=False)
    mesh = mesh_from_spec(spec)
    write_netcdf(mesh_dataset(mesh, params.config, history=command_line()), output)
    print(f"{output}: {mesh.n_cells} {mesh.element} cells, {mesh.n_nodes} nodes, {mesh.n_dofs} DOF, "
          f"{len(mesh.surface_segments)} surface segments")
    return 0


def _run_checkpointed(params, output: Path, args, start=None, stop_before: str = "done", checked=None):
    """Run a case (from ``start``, a saved path, when there is no usable checkpoint) with checkpoints beside
    ``output`` (``--resume`` continues one), progress and the interrupt test hook; the case result. A checkpoint
    that cannot be used starts the case afresh (one line); a ``start`` that does not fit the model is an
    InputError. An interrupted run removes a checkpoint it never saved to, and names one it did."""
    from ..driver.case import run_case
    from ..io.checkpoint import (
        STATE,
        CheckpointBusy,
        CheckpointError,
        CheckpointWriter,
        checkpoint_path,
        config_text,
        load_checkpoint,
    )
    from ..io.state_check import SavedStateMismatch

    output.parent.mkdir(parents=True, exist_ok=True)
    every = params.output.checkpoint_every
    path = checkpoint_path(output)
    text = config_text(params.config)
    saved, writer = start, None
    if args.resume and path.is_dir() and not (path / STATE).exists():
        print(f"capslide: checkpoint '{path}' holds no saved step yet; starting afresh", file=sys.stderr)
    elif args.resume and path.exists():
        try:
            saved = load_checkpoint(path, text)
        except CheckpointError as err:
            print(f"capslide: {err}; starting afresh", file=sys.stderr)
    if every:
        try:
            writer = CheckpointWriter(path, text)
        except CheckpointBusy as err:
            print(f"capslide: {err}; this run keeps no checkpoint", file=sys.stderr)
    observers = [] if args.quiet else [ProgressDisplay(params.loading)]
    if saved is not start:  # resumed: the log goes on from the checkpoint's steps (a start's are not this run's)
        for display in observers:
            display.replay(saved.records[len(start.records) if start is not None else 0:])
        print(f"capslide: resuming from {path} ({len(saved.records)} converged steps)", file=sys.stderr)
    if os.environ.get(INTERRUPT_AFTER_STEP):
        signum = signal.Signals[f"SIG{os.environ.get(INTERRUPT_SIGNAL, 'INT')}"]
        interrupt = lambda: os.killpg(os.getpgrp(), signum)  # noqa: E731 (as Ctrl-C does to a foreground job)
        observers.append(AfterSteps(int(os.environ[INTERRUPT_AFTER_STEP]), interrupt))
    run = lambda resume: run_case(params, observers=observers, checkpoint=writer, resume=resume,  # noqa: E731
                                  stop_before=stop_before, checked=checked)
    try:
        try:
            result = run(saved)
        except SavedStateMismatch as err:
            if saved is start:  # the normal state given: refused
                raise InputError(str(err)) from None
            print(f"capslide: {err}; starting afresh", file=sys.stderr)
            result = run(start)
    except SavedStateMismatch as err:
        raise InputError(str(err)) from None
    except KeyboardInterrupt:
        _interrupted(writer, path)
        raise
    finally:
        if writer is not None and not (path / STATE).exists():
            writer.remove()  # nothing saved: no empty checkpoint stays behind
    for obs in observers:
        if isinstance(obs, ProgressDisplay):
            obs.close()
    return result, writer


def _interrupted(writer, path: Path) -> None:
    """Name the checkpoint an interrupted run leaves, and how to continue it."""
    from ..io.checkpoint import STATE

    if writer is not None and (path / STATE).exists():
        print(f"capslide: the checkpoint '{path}' is kept; the same command with --resume continues from it",
              file=sys.stderr)


def _read_state(read, path: str, config):
    """``read(path, config)`` of a normal state file; its NormalStateError as an InputError (one line)."""
    from ..io.normal_state import NormalStateError

    try:
        return read(path, config)
    except NormalStateError as err:
        raise InputError(str(err)) from None


def _normal_state(path: str, config):
    """The normal state file ``path`` for ``config`` (InputError, one line, when it cannot be used)."""
    from ..io.normal_state import read_normal_state

    return _read_state(read_normal_state, path, config)


def cmd_run(args) -> int:
    """Run one case end to end and write its netCDF file (also when it fails)."""
    from ..io.results import case_dataset, write_netcdf
    from ..model import cost
    from ..model.build import mesh_spec

    params = parameters(args)
    (output,) = check_outputs([args.output], {"nc"})
    checked = cost.check(params, mesh_spec(params))  # the preflight, once: before anything is written
    start = None
    if args.from_state:  # a preload to an area goes on from a normal state at any preload (loadpath.cap.continued_from)
        area = params.loading.preload_area is not None
        start = _continued_start(params, args.from_state) if area else _normal_state(args.from_state, params.config)
    result, writer = _run_checkpointed(params, output, args, start, checked=checked)
    write_netcdf(case_dataset(result, history=command_line()), output)
    if writer is not None:
        writer.remove()
    s = result.scalars
    print(f"{output}: {result.status.label}{' (' + result.reason + ')' if result.reason else ''}; "
          f"{len(result.records)} steps, {result.wall_time:.1f} s; peak Ft = {s['peak_Ft']:.6g}, "
          f"onset ubar = {s['onset_ubar']:.6g}")
    return EXIT_STATUS[result.status]


def _continued_start(params, path: str):
    """The path of ``params`` continued from the normal state ``path``, computed for the same configuration
    preloaded to another force that this path passes (``loading.retract_from`` for a tensile preload, or a force
    of ``loading.preload_via``); None (with a notice) when this preload is not reached through it."""
    from ..io.normal_state import read_normal_state_at_any_preload
    from ..loadpath.cap import continued_from
    from ..states import Phase

    saved, reached = _read_state(read_normal_state_at_any_preload, path, params.config)
    approached = [r.Fn for r in saved.records if r.phase in (Phase.APPROACH, Phase.SPREAD)]
    state = None
    if saved.ended is None and approached:
        state = continued_from(params.loading, saved.state, reached, approached[-1])
    if state is None:
        print(f"capslide: the path to this preload does not pass through '{path}'; starting afresh", file=sys.stderr)
        return None
    return replace(saved, state=state)


def cmd_preload(args) -> int:
    """Approach and preload a configuration's cap, write its normal state (the start of every slide of it)."""
    from ..io.checkpoint import SavedCase
    from ..io.normal_state import write_normal_state
    from ..model import cost
    from ..model.build import mesh_spec
    from ..states import Status

    params = parameters(args)
    (output,) = check_outputs([args.output], {"npz"})
    checked = cost.check(params, mesh_spec(params))
    start = _continued_start(params, args.from_state) if args.from_state else None
    result, writer = _run_checkpointed(params, output, args, start, stop_before="dwell", checked=checked)
    ended = None if result.status == Status.COMPLETED else (result.status, result.reason)
    write_normal_state(output, SavedCase(result.state, result.records, [], result.wall_time, ended), params.config)
    if writer is not None:
        writer.remove()
    Fn = result.records[-1].Fn if result.records else float("nan")
    print(f"{output}: {result.status.label}{' (' + result.reason + ')' if result.reason else ''}; "
          f"{len(result.records)} steps, {result.wall_time:.1f} s; Fn* = {Fn:.6g}")
    return EXIT_STATUS[result.status]


def cmd_collect(args) -> int:
    """Stack case files into one dataset over a case dimension."""
    from ..io.cube import collect
    from ..io.results import write_netcdf

    (output,) = check_outputs([args.output], {"nc"})
    for f in map(Path, args.files):
        if f.is_dir():
            raise InputError(f"case file '{f}' is a directory")
        if not f.is_file():
            raise InputError(f"case file '{f}' does not exist")
    ds = collect(args.files, history=command_line())
    write_netcdf(ds, output)
    print(f"{output}: {ds.attrs['n_cases']} cases ({ds.sizes['model']} models x {ds.sizes['preload']} preloads), "
          f"up to {ds.sizes['step']} steps")
    return 0


def _inspect_cases(ds) -> None:
    """One line per case of a collected file (model x preload)."""
    print(f"{'model':<8} {'preload':>8} {'status':<10} {'peak_Ft':>10} {'onset_ubar':>11} {'onset_Ft':>10} "
          f"{'onset_area':>11} {'steps':>6}")
    labels = str(ds["status"].attrs.get("flag_meanings", "")).split()
    for m in ds["model"].values:
        for f in ds["preload"].values:
            case = ds.sel(model=m, preload=f)
            status = int(case["status"])
            if status < 0:
                continue
            print(f"{str(m):<8} {float(f):>+8.3f} {labels[status]:<10} "
                  + " ".join(f"{float(case[q]):>{w}.6g}" for q, w in (("peak_Ft", 10), ("onset_ubar", 11),
                                                                       ("onset_Ft", 10), ("onset_area", 11)))
                  + f" {int(case['n_steps']):>6}")


def _scalar_text(value: float, attrs) -> str:
    """A case scalar, its long name and, where its units carry a scale ("1.6e-06 N": E L0^2), its value in SI."""
    text = f"{value:.6g}  ({attrs.get('long_name', '')})"
    parsed = scale_and_unit(attrs.get("units", ""))
    return f"{text}  = {value * parsed[0]:.6g} {parsed[1]}" if parsed and np.isfinite(value) else text


def cmd_inspect(args) -> int:
    """Print parameters, status and case scalars of a case file as a table (a collected file: one line per case)."""
    ds = open_result(args.file)
    kind = kind_of(ds)
    if kind is None:
        raise InputError(f"'{args.file}' is not a file capslide wrote (no case, collected or mesh layout)")
    if kind == "cases":
        _inspect_cases(ds)
        return 0
    if kind == "mesh":
        print(f"mesh: {ds.sizes['cell']} {ds.attrs['element']} cells, {ds.sizes['node']} nodes, "
              f"{int(ds.attrs['n_dofs'])} DOF")
        return 0
    rows = [("status", ds.attrs.get("status", "?")), ("status_reason", ds.attrs.get("status_reason", ""))]
    for key in ("friction_model", "friction_s_cut", "loading_preload", "mesh_element", "mesh_size", "n_dofs",
                "cutbacks", "min_step", "case_wall_time", "software_version"):
        if key in ds.attrs:
            rows.append((key, ds.attrs[key]))
    for name in ("peak_Ft", "onset_ubar", "onset_Ft", "onset_area"):
        if name in ds:
            rows.append((name, _scalar_text(float(ds[name]), ds[name].attrs)))
    if "step" in ds.sizes:
        rows.append(("steps", ds.sizes["step"]))
    width = max(len(k) for k, _ in rows)
    for key, value in rows:
        print(f"{key:<{width}}  {value}")
    return 0


def cmd_vtk(args) -> int:
    """Export the field snapshots of a case file as a .vtu series with a .pvd index (ParaView)."""
    from ..io.vtk import snapshot_steps, write_snapshot_series, write_surface_series
    from ..states import Phase

    case = open_result(args.file, "case")
    if case.sizes.get("snapshot_ubar", 0) == 0:
        raise InputError(f"'{args.file}' holds no field snapshots (output.snapshot_ubar)")
    out = Path(args.output)
    if out.exists() and not out.is_dir():
        raise InputError(f"output '{out}' exists and is not a directory")
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as err:
        raise InputError(f"cannot create output directory '{out}': {err.strerror}") from None
    stem = args.stem or Path(args.file).stem
    three = "Z_node" in case.coords
    nodes = np.column_stack([case[k].values for k in ("X_node", "Y_node", "Z_node")[: 3 if three else 2]])
    pvd = write_snapshot_series(out, stem, nodes, case["cell_nodes"].values, case["snapshot_ubar"].values,
                                case["u_node"].values, case["v_node"].values, case["I1_sigma"].values,
                                case["w_node"].values if three else None)
    print(f"{pvd}: {case.sizes['snapshot_ubar']} snapshots (time = ubar / L0)")
    if three and "y_current" in case:  # the surface fields of the contact plane at the snapshots (3D)
        steps = snapshot_steps(case["phase"].values, case["ubar"].values, case["snapshot_ubar"].values, int(Phase.SLIDE))
        s = case.isel(step=steps[steps >= 0])
        traction = np.stack([s[k].values for k in ("traction_t", "traction_t_y", "traction_n")], axis=-1)
        scalars = {k: s[k].values for k in ("gap", "traction_n", "slip_state", "slip") if k in s}
        pvd = write_surface_series(out, stem, case["snapshot_ubar"].values[steps >= 0], s["x_current"].values,
                                   s["y_current"].values, scalars, traction)
        print(f"{pvd}: the surface points at {len(s.step)} snapshots, on the contact plane")
    return 0
