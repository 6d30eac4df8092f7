"""Commands of the studies: verify (Hertz/JKR), stability, convergence, options and experiment tables, the pull-off
preload overlay."""

from __future__ import annotations

import math
import sys
from pathlib import Path

import yaml

from ..config import SPHERE_ELEMENTS, ConfigError
from ..states import Status
from .common import EXIT_STATUS, InputError, check_outputs, config_sources, csv_text, parameters, write_text_atomic

__all__ = ["cmd_verify", "cmd_stability", "cmd_convergence", "cmd_options", "cmd_experiment", "cmd_experiment3d", "cmd_pull_off",
           "read_spec"]


def read_spec(path: str, kind: str) -> tuple[dict, dict]:
    """A study spec (YAML) of ``kind`` and its expansion into runs; InputError naming the file when it is bad."""
    from ..studies.expansion import runs

    try:
        spec = yaml.safe_load(Path(path).read_text())
        return spec, runs(spec, kind)
    except OSError as err:
        raise InputError(f"cannot read '{path}': {err.strerror}") from None
    except (yaml.YAMLError, ConfigError) as err:
        raise InputError(f"{path}: {str(err).splitlines()[0]}") from None


def cmd_verify(args) -> int:
    """Sweep a Hertz/JKR verification scene; write the comparison table as CSV."""
    from ..studies.verification import MAUGIS_JKR, TABLE_COLUMNS, VerificationFailed, scene_of, sweep, table_rows
    from .progress import ProgressDisplay

    params = parameters(args)
    scene = scene_of(params)
    if args.scene in ("hertz", "jkr") and args.scene != scene:
        raise InputError(f"--scene = {args.scene!r} does not match the config: contact.repulsion_only = "
                         f"{params.contact.repulsion_only} makes it a {scene} scene")
    loads = list(params.verification.loads)
    if not loads:
        raise InputError("verification.loads is empty: give the loads of the sweep in the scene file")
    if scene == "hertz" and min(loads) <= 0.0:
        raise InputError(f"verification.loads = {loads!r} is not allowed with the hertz scene: every load must be "
                         "compressive (P > 0; at P <= 0 a Hertz contact has no width to compare)")
    (output,) = check_outputs([args.output], {"csv"})
    progress = None if args.quiet else ProgressDisplay()
    if params.mesh.element in SPHERE_ELEMENTS:  # the sphere's closed forms; rows named by the scene (its file)
        from ..studies.verification_3d import sphere_sweep as sweep

        scene = args.scene or Path(config_sources(args)[-1]).stem
    checkpoint, saved, save = _sweep_checkpoint(args, params, output, progress)
    try:
        rows = sweep(params, scene, progress=progress, saved=saved, save=save)
    except VerificationFailed as err:
        checkpoint.unlink(missing_ok=True)
        print(f"capslide: verification of scene {scene} stopped: {err}; no table written", file=sys.stderr)
        return EXIT_STATUS[Status.DIVERGED]
    except KeyboardInterrupt:
        if checkpoint.exists():
            print(f"capslide: the checkpoint '{checkpoint}' is kept; the same command with --resume continues from it",
                  file=sys.stderr)
        raise
    if progress is not None:
        progress.close()
    write_text_atomic(output, csv_text(table_rows(rows), TABLE_COLUMNS))
    checkpoint.unlink(missing_ok=True)
    lam = rows[0].extra.get("maugis_lambda")
    if lam is not None and "jkr_valid" not in rows[0].extra:
        print(f"Maugis parameter lambda = {lam}: compared with the Maugis-Dugdale sphere (JKR in the extra column), "
              "and in the rows *_same_law with the scene's law on a half-space")
    elif lam is not None:
        valid = rows[0].extra["jkr_valid"] == "yes"
        print(f"Maugis parameter lambda = {lam}: the JKR closed form is "
              + ("a valid reference" if valid else f"NOT a valid reference (needs lambda >= {MAUGIS_JKR:g}); "
                                                   "rows marked * compare with it anyway"))
    for r in rows:
        mark = "*" if r.extra.get("jkr_valid") == "no" else " "
        print(f"{mark}{r.scene:6s} {r.quantity:20s} P={r.load:+.4f} fe={r.fe:.6g} theory={r.theory:.6g} "
              f"rel={r.rel_error:+.4f}")
    return 0


def _sweep_checkpoint(args, params, output: Path, progress=None):
    """The sweep's checkpoint path beside ``output``, the saved sweep ``--resume`` continues (None: afresh; one line
    says why a checkpoint cannot be used; ``progress`` shows its steps again) and the callable that saves one."""
    from ..io.checkpoint import CheckpointError, config_text
    from ..io.sweep_checkpoint import load_sweep, save_sweep, sweep_checkpoint_path

    path, text, saved = sweep_checkpoint_path(output), config_text(params.config), None
    if args.resume and path.exists():
        try:
            saved = load_sweep(path, text)
            if progress is not None:
                progress.replay(saved.records)
            print(f"capslide: resuming from {path} ({len(saved.records)} converged steps, {len(saved.done)} loads done)",
                  file=sys.stderr)
        except CheckpointError as err:
            print(f"capslide: {err}; starting afresh", file=sys.stderr)
    return path, saved, lambda s: save_sweep(path, text, s)


def cmd_stability(args) -> int:
    """Evaluate the hard cases of a stability spec from their case files; write the table (CSV, Markdown)."""
    from ..studies.stability import TABLE_COLUMNS, evaluate, markdown_table, pull_off_force

    spec, runs = read_spec(args.spec, "stability")
    outputs = check_outputs(args.output, {"csv", "md"})
    rows, arrays = evaluate(spec, runs, args.configs, args.cases)
    if "pull_off" in arrays:
        print(f"pull-off force: {pull_off_force(arrays['pull_off']['phase'], arrays['pull_off']['Fn']):.6g} E L0 W")
    for out in outputs:
        write_text_atomic(out, markdown_table(rows) if out.suffix == ".md" else csv_text(rows, TABLE_COLUMNS))
    failed = [r["case"] for r in rows if not r["passed"]]
    print(f"{len(rows) - len(failed)} of {len(rows)} hard cases as expected" + (f"; not: {', '.join(failed)}" if failed else ""))
    return 0


def cmd_pull_off(args) -> int:
    """Write a config overlay whose loading.preload is a fraction of the pull-off force of a case file."""
    from ..studies.stability import detached_in_preload, pull_off_preload

    if not 0.0 < args.fraction <= 1.0:
        raise InputError(f"--fraction = {args.fraction!r} is not allowed: must be > 0 and <= 1")
    (output,) = check_outputs([args.output], {"yaml"})
    detached = detached_in_preload(args.file)
    if detached is not None:
        raise InputError(f"'{args.file}' {detached}: pull-off needs a case that detached in its preload")
    preload = pull_off_preload(args.file, args.fraction)
    if math.isnan(preload):  # the file reached no preload
        raise InputError(f"'{args.file}' has no preload steps: no pull-off force to take a fraction of")
    write_text_atomic(output, yaml.safe_dump({"loading": {"preload": preload}}))
    print(f"{output}: loading.preload = {preload:g} ({args.fraction:g} of the pull-off force of {args.file})")
    return 0


def cmd_convergence(args) -> int:
    """Evaluate a convergence study from its case files: table (CSV, Markdown) and error-versus-time figure."""
    from ..studies.convergence import ORDER_COLUMNS, TABLE_COLUMNS, cheapest_within, evaluate, markdown_table

    spec, _ = read_spec(args.spec, "convergence")
    outputs = check_outputs(args.output, {"csv", "md", "pdf", "png"})
    orders_csv = check_outputs([args.orders], {"csv"})[0] if args.orders else None
    try:
        rows, refs, orders = evaluate(spec, args.cases)
    except ValueError as err:
        raise InputError(str(err)) from None
    for case in spec["cases"]:
        ref = ", ".join(f"{q} {v:.6g} ({kind}{'' if kind == 'finest' else f', p = {p:.2f}'})"
                        for q, (v, kind, p) in refs[case].items())
        print(f"{case}: reference {ref}")
    for threshold in (0.05, 0.01):
        best = cheapest_within(rows, threshold)
        print(f"cheapest run with every QoI error below {threshold:.0%} in every case: "
              + (f"{best['run']} (largest error {best['error']:.2e}, {best['wall_time_s']:.1f} s over the cases)"
                 if best else "none"))
    for out in outputs:
        if out.suffix == ".md":
            write_text_atomic(out, markdown_table(rows) + "\nObserved orders (mesh-size sweeps, consecutive triplets)"
                              ":\n\n" + markdown_table(orders, ORDER_COLUMNS))
        elif out.suffix == ".csv":
            write_text_atomic(out, csv_text(rows, TABLE_COLUMNS))
    if orders_csv is not None:
        write_text_atomic(orders_csv, csv_text(orders, ORDER_COLUMNS))
    figs = [o for o in outputs if o.suffix in (".pdf", ".png")]
    if figs:
        from .. import figures

        with figures.journal_style():
            figures.save(figures.fig_convergence(rows), figs)
    print(f"{len(rows)} runs of {len({(r['case'], r['run']) for r in rows})} case files; table and figure written")
    return 0


def cmd_options(args) -> int:
    """Evaluate the options study from its case files: table (CSV, Markdown), the Ft and area figure and the
    contact and stick-zone edge figure."""
    from ..studies.convergence import markdown_table
    from ..studies.options import TABLE_COLUMNS, read_cases, table_rows

    spec, _ = read_spec(args.spec, "options")
    outputs = check_outputs(args.output, {"csv", "md"})
    forces = check_outputs(args.forces or [], {"pdf", "png"})
    edges = check_outputs(args.edges or [], {"pdf", "png"})
    curves = read_cases(spec, args.cases)
    rows = table_rows(spec, curves)
    for out in outputs:
        write_text_atomic(out, markdown_table(rows, TABLE_COLUMNS) if out.suffix == ".md" else csv_text(rows, TABLE_COLUMNS))
    if forces or edges:
        from .. import figures

        with figures.journal_style():
            if forces:
                figures.save(figures.fig_options(spec, curves), forces)
            if edges:
                figures.save(figures.fig_option_edges(spec, curves), edges)
    for r in rows:
        print(f"{r['model']:4s} {r['option']:20s} {r['status']:9s} peak Ft {r['peak_Ft']:.5g} "
              f"({r['peak_change_pct']:+.2f} %), onset ubar {r['onset_ubar']:.4g} ({r['onset_change_pct']:+.2f} %)")
    return 0


def cmd_experiment(args) -> int:
    """Evaluate the experiment study from its case files: table (CSV, Markdown), findings (Markdown), the four
    panels and the edges per normal control, and the contact interface of the spec's snapshot runs."""
    from ..studies.convergence import markdown_table
    from ..studies.experiment import TABLE_COLUMNS, findings, read_cases, table_rows

    spec, _ = read_spec(args.spec, "experiment")
    outputs = check_outputs(args.output, {"csv", "md"})
    figure_dir = Path(args.figures) if args.figures else None
    curves = read_cases(spec, args.cases)
    unknown = [run for run in spec.get("snapshots", []) if run not in {f"{m}_{o}" for m, o in curves}]
    if unknown:
        raise InputError(f"{args.spec}: snapshots = {unknown[0]!r} is not a run of the study ({{model}}_{{option}})")
    rows = table_rows(spec, curves)
    for out in outputs:
        write_text_atomic(out, markdown_table(rows, TABLE_COLUMNS) if out.suffix == ".md" else csv_text(rows, TABLE_COLUMNS))
    text = findings(rows)
    if args.findings:
        write_text_atomic(Path(args.findings), text)
    if figure_dir is not None:
        from .. import figures
        from ..io.reading import open_result

        figure_dir.mkdir(parents=True, exist_ok=True)
        controls = sorted({o.split("_")[0] for o in spec["options"]})
        with figures.journal_style():
            for control in controls:
                figures.save(figures.fig_experiment_panels(spec, curves, control),
                             [figure_dir / f"panels_{control}.{ext}" for ext in ("pdf", "png")])
                figures.save(figures.fig_experiment_edges(spec, curves, control),
                             [figure_dir / f"edges_{control}.{ext}" for ext in ("pdf", "png")])
            for run in spec.get("snapshots", []):
                case = open_result(Path(args.cases) / f"{run}.nc", "case")
                figures.save(figures.CASE_FIGURES["cap_Aczoom"](case),
                             [figure_dir / f"interface_{run}.{ext}" for ext in ("pdf", "png")])
    sys.stdout.write(text)
    return 0


def cmd_experiment3d(args) -> int:
    """Evaluate the experiment in numbers from its case files (issue 40): the table per initial area (CSV, Markdown),
    the four panels of the paper's experimental figure and the outlines at its snapshot times."""
    from ..io.reading import open_result
    from ..studies.convergence import markdown_table
    from ..studies.experiment_3d import TABLE_COLUMNS, read_cases

    outputs = check_outputs(args.output, {"csv", "md"})
    panels = check_outputs(args.panels or [], {"pdf", "png"})
    outlines = check_outputs(args.outlines or [], {"pdf", "png"})
    cases = read_cases(args.files)
    snapshots = None
    if outlines:  # the experiment's snapshots are of A0 = 0.27 mm^2 (its figure 4), at times in s
        main = [c for c in cases if "_lambda" not in c["case"]] or cases
        shown = min(main, key=lambda c: abs(c["A0"] - 0.27))
        if not shown["v"]:
            raise InputError(f"--outlines: '{shown['path']}' has loading.velocity = null: the experiment's snapshot "
                             "times (s) need a stage speed")
        snapshots = open_result(Path(shown["path"]), "case")  # in memory: drawn below, once the tables are written
        if snapshots.sizes.get("snapshot_ubar", 0) == 0:
            raise InputError(f"--outlines: '{shown['path']}' holds no field snapshots (output.snapshot_ubar: the "
                             "experiment's times)")
    rows = [{k: c[k] for k in TABLE_COLUMNS} for c in cases]
    for out in outputs:
        write_text_atomic(out, markdown_table(rows, TABLE_COLUMNS) if out.suffix == ".md" else csv_text(rows, TABLE_COLUMNS))
    if panels or outlines:
        from .. import figures
        from ..figures.experiment_3d import fig_experiment3d_outlines, fig_experiment3d_panels

        with figures.journal_style():
            if panels:
                figures.save(fig_experiment3d_panels(cases), panels)
            if outlines:
                figures.save(fig_experiment3d_outlines(snapshots), outlines)
    for r in rows:
        print(f"{r['case']:16s} {r['status']:9s} A0 {r['A0']:.4f} mm2, Fn0 {r['Fn0']:+.3f} mN, peak Ft {r['peak_Ft']:.4g} mN "
              f"at {r['travel_to_peak']:.4g} um (step {r['step_to_peak']:.3g}), Ft/A {r['Ft_over_A_at_peak']:.4g} MPa, "
              f"area loss {r['area_loss_pct']:.3g} %, "
              f"{r['outcome']} at {r['ubar_end']:.4g} um with {r['area_end_pct']:.3g} % of A0")
    return 0
