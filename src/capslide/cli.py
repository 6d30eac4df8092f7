"""Command-line interface: ``capslide <command> ...``.

Bad input ends with a one-line ``capslide: error: ...`` message on stderr and
exit code 2, never a traceback; nothing is written before the input is known
to be good.
"""

from __future__ import annotations

import argparse
import json
import signal
import sys
import tempfile
from pathlib import Path
from typing import Sequence

import numpy as np

from . import __version__
from .atomic import replacing
from .config import ConfigError, load_config
from .params import Parameters

EXIT_BAD_INPUT = 2
EXIT_INTERRUPTED = 130
EXIT_STATUS = {"completed": 0, "detached": 3, "diverged": 4}


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


def cmd_constants(args) -> int:
    """Print the derived CGCM and friction constants as JSON."""
    params = _parameters(args)
    print(json.dumps(params.derived_constants(), indent=2))
    return 0


def _config_from_netcdf(path: str) -> dict:
    """The validated configuration stored in a capslide netCDF file."""
    import xarray as xr
    import yaml

    from .config import validate

    try:
        with xr.open_dataset(path, engine="netcdf4") as ds:
            text = ds.attrs.get("config_yaml")
    except (OSError, ValueError) as err:
        raise InputError(f"cannot read netCDF file '{path}': {err}") from None
    if text is None:
        raise InputError(f"'{path}' holds no configuration (attribute config_yaml)")
    return validate(yaml.safe_load(text))


def _open_netcdf(path):
    """A result file loaded into memory (InputError when it is missing or not netCDF)."""
    import xarray as xr

    try:
        with xr.open_dataset(path, engine="netcdf4") as ds:
            return ds.load()
    except (OSError, ValueError) as err:
        raise InputError(f"cannot read netCDF file '{path}': {err}") from None


def cmd_figure(args) -> int:
    """Render one figure to PDF and/or PNG (model figures from a config, others from result files)."""
    from . import figures  # matplotlib only when a figure is drawn

    known = {**figures.MODEL_FIGURES, **figures.MESH_FIGURES, **figures.TABLE_FIGURES, **figures.CASES_FIGURES,
             **figures.CASE_FIGURES}
    if args.name not in known:
        raise InputError(f"unknown figure '{args.name}' (allowed: {', '.join(known)})")
    outputs = _check_outputs(args.output, {"pdf", "png", "svg"})
    if args.name in figures.MODEL_FIGURES:
        if not args.configs:
            raise InputError(f"figure '{args.name}' needs a CONFIG file")
        draw = lambda: figures.MODEL_FIGURES[args.name](_parameters(args))  # noqa: E731
    elif args.name in figures.CASES_FIGURES:
        if not args.input:
            raise InputError(f"figure '{args.name}' needs --input CASES.nc (from capslide collect)")
        cases = _open_netcdf(args.input)
        tau = float(cases.attrs["friction.mu_DI"]) * float(cases.attrs["adhesion.T_max"]) / float(cases.attrs["material.E"])
        kwargs = {"tau_DI": tau} if args.name == "cap_PxOverAc" else {}
        draw = lambda: figures.CASES_FIGURES[args.name](cases, **kwargs)  # noqa: E731
    elif args.name in figures.CASE_FIGURES:
        if not args.input:
            raise InputError(f"figure '{args.name}' needs --input CASE.nc (from capslide run)")
        case = _open_netcdf(args.input)
        if "snapshot_ubar" not in case:
            raise InputError(f"'{args.input}' holds no field snapshots (figure '{args.name}' needs a case file)")
        draw = lambda: figures.CASE_FIGURES[args.name](case)  # noqa: E731
    elif args.name in figures.TABLE_FIGURES:
        if not args.tables:
            raise InputError(f"figure '{args.name}' needs --table FILE.csv")
        draw = lambda: figures.TABLE_FIGURES[args.name](args.tables)  # noqa: E731
    else:
        if not args.input:
            raise InputError(f"figure '{args.name}' needs --input MESH.nc")
        from .results import read_mesh

        params = Parameters.from_config(_config_from_netcdf(args.input))
        mesh = read_mesh(args.input)
        draw = lambda: figures.MESH_FIGURES[args.name](mesh, params)  # noqa: E731
    with figures.journal_style():
        figures.save(draw(), outputs)
    return 0


def cmd_vtk(args) -> int:
    """Export the field snapshots of a case file as a .vtu series with a .pvd index (ParaView)."""
    from .vtk import write_snapshot_series

    case = _open_netcdf(args.file)
    missing = [k for k in ("snapshot_ubar", "X_node", "Y_node", "cell_nodes", "u_node", "v_node", "I1_sigma") if k not in case]
    if missing:
        raise InputError(f"'{args.file}' holds no field snapshots (missing {', '.join(missing)})")
    if case.sizes.get("snapshot", 0) == 0:
        raise InputError(f"'{args.file}' holds no field snapshots (snapshot dimension is empty)")
    out = Path(args.output)
    if out.exists() and not out.is_dir():
        raise InputError(f"output '{out}' exists and is not a directory")
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as err:
        raise InputError(f"cannot create output directory '{out}': {err.strerror}") from None
    stem = args.stem or Path(args.file).stem
    nodes = np.column_stack([case["X_node"].values, case["Y_node"].values])
    pvd = write_snapshot_series(out, stem, nodes, case["cell_nodes"].values, case["snapshot_ubar"].values,
                                case["u_node"].values, case["v_node"].values, case["I1_sigma"].values)
    print(f"{pvd}: {case.sizes['snapshot']} snapshots (time = ubar / L0)")
    return 0


def cmd_mesh(args) -> int:
    """Build the cap mesh of a configuration and write it as netCDF."""
    from .mesh import cap_mesh, cap_mesh_spec
    from .results import mesh_dataset, write_netcdf

    params = _parameters(args)
    (output,) = _check_outputs([args.output], {"nc"})
    try:
        mesh = cap_mesh(cap_mesh_spec(params))
    except ValueError as err:
        raise InputError(str(err)) from None
    write_netcdf(mesh_dataset(mesh, params.config), output)
    print(f"{output}: {mesh.n_cells} {mesh.element} cells, {mesh.n_nodes} nodes, {mesh.n_dofs} DOF, "
          f"{len(mesh.surface_segments)} surface segments")
    return 0


def _progress_printer(stream=sys.stderr):
    """One log line per step, or a self-updating line on a terminal."""
    tty = stream.isatty()

    def show(rec) -> None:
        line = (f"{rec.phase:8s} ubar={rec.ubar:7.4f} h={rec.h:9.5f} Fn={rec.Fn:+.5f} Ft={rec.Ft:+.5f} "
                f"area={rec.area:8.4f} stick={rec.area_stick:8.4f} newton={rec.newton_iterations:2d} "
                f"krylov={rec.krylov_iterations:4d} t={rec.wall_time:6.2f}s")
        stream.write(("\r" + line) if tty else line + "\n")
        stream.flush()

    return show


def cmd_run(args) -> int:
    """Run one case end to end and write its netCDF file (also when it fails)."""
    from .case import run_case
    from .results import case_dataset, write_netcdf

    import yaml

    from .checkpoint import CheckpointError, Checkpointer, checkpoint_path

    params = _parameters(args)
    (output,) = _check_outputs([args.output], {"nc"})
    output.parent.mkdir(parents=True, exist_ok=True)
    config_text = yaml.safe_dump(params.config, sort_keys=True)
    every = int(params.config["output"]["checkpoint_every"])
    path = checkpoint_path(output)
    ckpt = Checkpointer(path if every else None, config_text, every)
    if args.resume and path.is_file():
        try:
            ckpt = Checkpointer.load(path, config_text, every)
            print(f"capslide: resuming from {path} ({len(ckpt.records)} converged steps)", file=sys.stderr)
        except CheckpointError as err:
            print(f"capslide: {err}; starting afresh", file=sys.stderr)
    result = run_case(params, progress=None if args.quiet else _progress_printer(), ckpt=ckpt)
    if not args.quiet and sys.stderr.isatty():
        sys.stderr.write("\n")
    write_netcdf(case_dataset(result), output)
    ckpt.remove()
    s = result.scalars
    print(f"{output}: {result.status}{' (' + result.reason + ')' if result.reason else ''}; {len(result.records)} steps, "
          f"{result.wall_time:.1f} s; peak Ft = {s['peak_Ft']:.6g}, onset ubar = {s['onset_ubar']:.6g}")
    return EXIT_STATUS[result.status]


def cmd_collect(args) -> int:
    """Stack case files into one dataset over a case dimension."""
    from .results import collect, write_netcdf

    (output,) = _check_outputs([args.output], {"nc"})
    missing = [f for f in args.files if not Path(f).is_file()]
    if missing:
        raise InputError(f"case file '{missing[0]}' does not exist")
    try:
        ds = collect(args.files)
    except (OSError, ValueError, KeyError) as err:
        raise InputError(f"cannot collect the case files: {err}") from None
    write_netcdf(ds, output)
    print(f"{output}: {ds.sizes['case']} cases, up to {ds.sizes['step']} steps")
    return 0


def _read_spec(path: str, validate_spec=None) -> dict:
    """A study spec (YAML) checked by ``validate_spec`` (default: the stability suite's); InputError when bad."""
    import yaml

    if validate_spec is None:
        from .stability import validate_spec

    try:
        spec = yaml.safe_load(Path(path).read_text())
        validate_spec(spec)
    except OSError as err:
        raise InputError(f"cannot read '{path}': {err.strerror}") from None
    except (yaml.YAMLError, ValueError) as err:
        raise InputError(f"{path}: {str(err).splitlines()[0]}") from None
    return spec


def _csv_text(rows: list[dict], columns: list[str]) -> str:
    """Rows as CSV text with the given columns (missing cells empty)."""
    import csv
    import io

    buf = io.StringIO()
    writer = csv.DictWriter(buf, fieldnames=columns, lineterminator="\n")
    writer.writeheader()
    writer.writerows([{k: r.get(k, "") for k in columns} for r in rows])
    return buf.getvalue()


def _case_arrays(path: Path) -> dict:
    """Step arrays and attributes of a case file that the stability checks use."""
    ds = _open_netcdf(path)
    a = {k: ds[k].values for k in ("phase", "ubar", "Fn", "Ft", "area", "base_force_x", "base_force_y",
                                   "newton_iterations", "krylov_iterations")}
    at = ds.attrs
    a.update(status=str(at.get("status")), cutbacks=int(at.get("cutbacks", 0)), min_step=float(at.get("min_step", np.nan)),
             wall_time=float(at.get("case_wall_time", np.nan)),
             tau_DI=float(at["friction.mu_DI"]) * float(at["adhesion.T_max"]) / float(at["material.E"]))
    return a


def cmd_overrides(args) -> int:
    """Print the --set options of one hard case of a stability spec (used by the workflow)."""
    from .stability import case_overrides, pull_off_force

    spec = _read_spec(args.spec)
    if args.case not in spec["cases"]:
        raise InputError(f"case '{args.case}' is not in {args.spec} (cases: {', '.join(spec['cases'])})")
    pull_off = None
    if args.pull_off:
        a = _case_arrays(Path(args.pull_off))
        pull_off = pull_off_force(a["phase"], a["Fn"])
    try:
        sets = case_overrides(spec, args.case, pull_off)
    except ValueError as err:
        raise InputError(str(err)) from None
    print(" ".join(f"--set {s}" for s in sets))
    return 0


def cmd_stability(args) -> int:
    """Evaluate the hard cases of a stability spec from their case files; write the table (CSV, Markdown)."""
    from .stability import TABLE_COLUMNS, case_overrides, check, markdown_table, pull_off_force

    spec = _read_spec(args.spec)
    outputs = _check_outputs(args.output, {"csv", "md"})
    cases_dir = Path(args.cases)
    bound = float(spec.get("time_bound_s", np.inf))
    rows, arrays = [], {}
    for name, case in spec["cases"].items():
        row = {"case": name, "what": case.get("what", ""), "expected": case["expect"], "time_bound_s": bound,
               "check": case.get("check", "none")}
        if case["expect"] == "rejected":
            try:
                load_config(args.configs, case_overrides(spec, name))
                row.update(status="accepted", passed=False)
            except ConfigError as err:
                row.update(status="rejected", check="config_error", check_value=str(err).split(":")[0], passed=True)
            rows.append(row)
            continue
        path = cases_dir / f"{name}.nc"
        if not path.is_file():
            raise InputError(f"case file '{path}' does not exist (run: snakemake --cores 2 stability)")
        a = arrays[name] = _case_arrays(path)
        fb, fb_ok = check("force_balance", a)
        value, ok = check(row["check"], a) if row["check"] != "none" else (np.nan, True)
        row.update(status=a["status"], steps=len(a["phase"]), cutbacks=a["cutbacks"], min_step=a["min_step"],
                   newton_iterations=int(a["newton_iterations"].sum()), krylov_iterations=int(a["krylov_iterations"].sum()),
                   wall_time_s=round(a["wall_time"], 1), force_balance=fb, check_value=value,
                   passed=bool(a["status"] == case["expect"] and fb_ok and ok and a["wall_time"] <= bound))
        rows.append(row)
    if "pull_off" in arrays:
        print(f"pull-off force: {pull_off_force(arrays['pull_off']['phase'], arrays['pull_off']['Fn']):.6g} E L0 W")
    for out in outputs:
        text = markdown_table(rows) if out.suffix == ".md" else _csv_text(rows, TABLE_COLUMNS)
        _write_text_atomic(out, text)
    failed = [r["case"] for r in rows if not r["passed"]]
    print(f"{len(rows) - len(failed)} of {len(rows)} hard cases as expected" + (f"; not: {', '.join(failed)}" if failed else ""))
    return 0


def cmd_convergence(args) -> int:
    """Evaluate a convergence study from its case files: table (CSV, Markdown) and error-versus-time figure."""
    from .convergence import (ORDER_COLUMNS, TABLE_COLUMNS, RunResult, cheapest_within, error_rows, markdown_table,
                              order_rows, pareto_front, quantities, study_runs, validate_spec)

    spec = _read_spec(args.spec, validate_spec)
    outputs = _check_outputs(args.output, {"csv", "md", "pdf", "png"})
    orders_csv = _check_outputs([args.orders], {"csv"})[0] if args.orders else None
    runs = study_runs(spec)
    results = {}
    for key in dict.fromkeys((r.case, r.run_id) for r in runs):
        path = Path(args.cases) / key[0] / f"{key[1]}.nc"
        if not path.is_file():
            raise InputError(f"case file '{path}' does not exist (run: snakemake --cores 2 convergence)")
        ds = _open_netcdf(path)
        q = quantities(ds["phase"].values, ds["ubar"].values, ds["Ft"].values, float(ds["peak_Ft"]),
                       float(ds["onset_ubar"]), float(ds["onset_area"]))
        results[key] = RunResult(str(ds.attrs.get("status")), q, float(ds.attrs.get("case_wall_time", np.nan)),
                                 int(ds.attrs["n_dofs"]), int(ds.sizes["step"]), int(ds["newton_iterations"].sum()),
                                 int(ds["krylov_iterations"].sum()))
    try:
        rows, refs = error_rows(spec, runs, results)
    except ValueError as err:
        raise InputError(str(err)) from None
    for case in spec["cases"]:
        idx = [i for i, row in enumerate(rows) if row["case"] == case]
        mask = pareto_front([rows[i]["wall_time_s"] for i in idx], [rows[i]["error"] for i in idx])
        for i, on in zip(idx, mask):
            rows[i]["pareto"] = bool(on)
        ref = ", ".join(f"{q} {v:.6g} ({kind}{'' if kind == 'finest' else f', p = {p:.2f}'})"
                        for q, (v, kind, p) in refs[case].items())
        print(f"{case}: reference {ref}")
    orders = order_rows(spec, rows)
    for threshold in (0.05, 0.01):
        best = cheapest_within(rows, threshold)
        print(f"cheapest run with every QoI error below {threshold:.0%} in every case: "
              + (f"{best['run']} (largest error {best['error']:.2e}, {best['wall_time_s']:.1f} s over the cases)"
                 if best else "none"))
    for out in outputs:
        if out.suffix == ".md":
            _write_text_atomic(out, markdown_table(rows) + "\nObserved orders (mesh-size sweeps, consecutive triplets)"
                               ":\n\n" + markdown_table(orders, ORDER_COLUMNS))
        elif out.suffix == ".csv":
            _write_text_atomic(out, _csv_text(rows, TABLE_COLUMNS))
    if orders_csv is not None:
        _write_text_atomic(orders_csv, _csv_text(orders, ORDER_COLUMNS))
    figs = [o for o in outputs if o.suffix in (".pdf", ".png")]
    if figs:
        from . import figures

        with figures.journal_style():
            figures.save(figures.fig_convergence(rows), figs)
    print(f"{len(rows)} runs of {len(results)} case files; table and figure written")
    return 0


def _write_text_atomic(path: Path, text: str) -> None:
    with replacing(path) as tmp:
        tmp.write_text(text)


def cmd_inspect(args) -> int:
    """Print parameters, status and case scalars of a case file as a table."""
    import xarray as xr

    try:
        ds = xr.open_dataset(args.file, engine="netcdf4")
    except (OSError, ValueError) as err:
        raise InputError(f"cannot read netCDF file '{args.file}': {err}") from None
    with ds:
        rows = [("status", ds.attrs.get("status", "?")), ("status_reason", ds.attrs.get("status_reason", ""))]
        for key in ("friction.model", "friction.s_cut", "loading.preload", "mesh.element", "mesh.size", "n_dofs",
                    "cutbacks", "min_step", "case_wall_time"):
            if key in ds.attrs:
                rows.append((key, ds.attrs[key]))
        for name in ("peak_Ft", "onset_ubar", "onset_Ft", "onset_area"):
            if name in ds:
                rows.append((name, f"{float(ds[name]):.6g}  ({ds[name].attrs.get('long_name', '')})"))
        if "step" in ds.sizes:
            rows.append(("steps", ds.sizes["step"]))
    width = max(len(k) for k, _ in rows)
    for key, value in rows:
        print(f"{key:<{width}}  {value}")
    return 0


def cmd_verify(args) -> int:
    """Sweep a Hertz/JKR verification scene; write the comparison table as CSV."""
    import csv

    from .verification import VerificationFailed, sweep

    params = _parameters(args)
    if not params.config["verification"]["loads"]:
        raise InputError("verification.loads is empty: give the loads of the sweep in the scene file")
    (output,) = _check_outputs([args.output], {"csv"})
    try:
        rows = sweep(params, args.scene, progress=None if args.quiet else _progress_printer())
    except VerificationFailed as err:
        print(f"capslide: verification of scene {args.scene} stopped: {err}; no table written", file=sys.stderr)
        return EXIT_STATUS["diverged"]
    if not args.quiet and sys.stderr.isatty():
        sys.stderr.write("\n")
    with replacing(output) as tmp, open(tmp, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["scene", "quantity", "load_P", "fe", "theory", "rel_error", "extra"])
        for r in rows:
            w.writerow([r.scene, r.quantity, f"{r.load:.8g}", f"{r.fe:.8g}", f"{r.theory:.8g}", f"{r.rel_error:.6g}",
                        ";".join(f"{k}={v}" for k, v in r.extra.items())])
    for r in rows:
        print(f"{r.scene:6s} {r.quantity:20s} P={r.load:+.4f} fe={r.fe:.6g} theory={r.theory:.6g} rel={r.rel_error:+.4f}")
    return 0


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="capslide", description=__doc__.splitlines()[0])
    parser.add_argument("--version", action="version", version=f"capslide {__version__}")
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")

    p = sub.add_parser("constants", help="print derived CGCM constants as JSON (internal units and SI)")
    _add_config_args(p)
    p.set_defaults(func=cmd_constants)

    p = sub.add_parser("figure", help="render a figure: model figures (Tn, modelCA, modelAM, TnTt, exp_FnJKR) from "
                                      "CONFIG, cap_setup from --input MESH.nc, cap_PxAndAc and cap_PxOverAc from "
                                      "--input CASES.nc, cap_Aczoom and cap_xn from --input CASE.nc")
    p.add_argument("name", help="figure name")
    p.add_argument("configs", nargs="*", metavar="CONFIG", help="YAML config file(s) (model figures)")
    p.add_argument("--set", dest="overrides", action="append", default=[], metavar="KEY=VALUE", help="config override")
    p.add_argument("--input", metavar="FILE.nc", help="result file to draw from (cap_setup: a mesh file)")
    p.add_argument("--table", dest="tables", action="append", default=[], metavar="FILE.csv",
                   help="table(s) to draw from (verification), repeatable")
    p.add_argument("-o", "--output", action="append", required=True, metavar="FILE", help="output .pdf/.png (repeatable)")
    p.set_defaults(func=cmd_figure)

    p = sub.add_parser("run", help="run one case (mesh, approach, preload, slide), write its netCDF file")
    _add_config_args(p)
    p.add_argument("-o", "--output", required=True, metavar="CASE.nc")
    p.add_argument("-q", "--quiet", action="store_true", help="no per-step progress")
    p.add_argument("--resume", action="store_true",
                   help="continue from the checkpoint a killed run left beside CASE.nc (output.checkpoint_every)")
    p.set_defaults(func=cmd_run)

    p = sub.add_parser("verify", help="sweep a Hertz/JKR verification scene, write a CSV table of errors")
    _add_config_args(p)
    p.add_argument("--scene", required=True, help="scene name written into the table (hertz, jkr)")
    p.add_argument("-o", "--output", required=True, metavar="TABLE.csv")
    p.add_argument("-q", "--quiet", action="store_true")
    p.set_defaults(func=cmd_verify)

    p = sub.add_parser("collect", help="stack case files into one dataset over a case dimension")
    p.add_argument("files", nargs="+", metavar="CASE.nc")
    p.add_argument("-o", "--output", required=True, metavar="CASES.nc")
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

    p = sub.add_parser("convergence", help="evaluate a convergence study: table (.csv/.md), error-vs-time figure (.pdf/.png)")
    p.add_argument("spec", metavar="SPEC.yaml", help="the study (config/convergence.yaml)")
    p.add_argument("--cases", required=True, metavar="DIR", help="directory with <case>/<run>.nc per run")
    p.add_argument("--orders", metavar="FILE.csv", help="also write the observed convergence orders (CSV)")
    p.add_argument("-o", "--output", action="append", required=True, metavar="FILE",
                   help="table.csv / table.md / figure .pdf / .png")
    p.set_defaults(func=cmd_convergence)

    p = sub.add_parser("stability-overrides", help="print the --set options of one hard case (used by the workflow)")
    p.add_argument("spec", metavar="SPEC.yaml")
    p.add_argument("case")
    p.add_argument("--pull-off", metavar="CASE.nc", help="case file whose pull-off force sets pull_off_fraction preloads")
    p.set_defaults(func=cmd_overrides)

    p = sub.add_parser("vtk", help="export the field snapshots of a case file for ParaView (.vtu series + .pvd)")
    p.add_argument("file", metavar="CASE.nc")
    p.add_argument("-o", "--output", required=True, metavar="DIR", help="output directory")
    p.add_argument("--stem", help="file name stem (default: the case file's)")
    p.set_defaults(func=cmd_vtk)

    p = sub.add_parser("mesh", help="build the cap mesh of a configuration, write it as netCDF")
    _add_config_args(p)
    p.add_argument("-o", "--output", required=True, metavar="MESH.nc")
    p.set_defaults(func=cmd_mesh)
    return parser


def _terminate(signum, frame):
    raise KeyboardInterrupt  # SIGTERM (kill, a scheduler's time limit): leave like Ctrl-C, temporary files removed


def main(argv: Sequence[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    signal.signal(signal.SIGTERM, _terminate)
    try:
        return args.func(args)
    except (ConfigError, InputError) as err:
        print(f"capslide: error: {err}", file=sys.stderr)
        return EXIT_BAD_INPUT
    except KeyboardInterrupt:  # Ctrl-C or a scheduler's SIGINT: results are written atomically, nothing partial remains
        print("capslide: interrupted; no output written", file=sys.stderr)
        return EXIT_INTERRUPTED
