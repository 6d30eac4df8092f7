"""The figure command: any paper figure from a configuration or from result files."""

from __future__ import annotations

from pathlib import Path

from ..io.reading import config_of, open_result, read_mesh
from ..params import Parameters
from .common import InputError, check_outputs, parameters

__all__ = ["cmd_figure", "FIGURE_HELP"]

FIGURE_HELP = ("render a figure: model figures (Tn, modelCA, modelAM, TnTt, exp_FnJKR) from CONFIG, cap_setup from "
               "--input MESH.nc, cap_PxAndAc, cap_PxOverAc and cap_FtOverA from --input CASES.nc, cap_Aczoom and "
               "cap_xn from --input CASE.nc, sphere_Tn, sphere_Pa and sphere_Aczoom from --input CASE.nc of a 3D "
               "case, verification from --table FILE.csv")


# what each 3D case figure reads from the case file, and the key that writes it
_SPHERE_FIGURE_NEEDS = {"sphere_Tn": ("traction_n", "output.surface_profiles = true"),
                        "sphere_Pa": ("area", "the per-step contact area of a case"),
                        "sphere_Aczoom": ("outline_x", "the contact outlines of output.snapshot_ubar")}


def _tau_DI(cases) -> float | None:
    """tau_DI / E of the DI model of a collected file (mu_DI T_max / E), None without a DI model."""
    if "friction_model" not in cases.coords or "DI" not in set(map(str, cases["friction_model"].values)):
        return None
    mu = (float(cases["mu_DI"].where(cases["friction_model"] == "DI", drop=True)[0]) if "mu_DI" in cases.coords
          else float(cases.attrs["friction_mu_DI"]))
    return mu * float(cases.attrs["adhesion_T_max"]) / float(cases.attrs["material_E"])


def cmd_figure(args) -> int:
    """Render one figure to PDF and/or PNG (model figures from a config, others from result files)."""
    from .. import figures  # matplotlib only when a figure is drawn

    known = {**figures.MODEL_FIGURES, **figures.MESH_FIGURES, **figures.TABLE_FIGURES, **figures.CASES_FIGURES,
             **figures.CASE_FIGURES, **figures.SPHERE_FIGURES}
    if args.name not in known:
        raise InputError(f"unknown figure '{args.name}' (allowed: {', '.join(known)})")
    outputs = check_outputs(args.output, {"pdf", "png", "svg"})
    if args.name in figures.MODEL_FIGURES:
        if not args.configs and not args.scene:
            raise InputError(f"figure '{args.name}' needs a CONFIG file or --scene NAME")
        draw = lambda: figures.MODEL_FIGURES[args.name](parameters(args))  # noqa: E731
    elif args.name in figures.CASES_FIGURES:
        if not args.input:
            raise InputError(f"figure '{args.name}' needs --input CASES.nc (from capslide collect)")
        cases = open_result(args.input, "cases")
        kwargs = {"tau_DI": _tau_DI(cases)} if args.name.endswith(("_PxOverAc", "_FtOverA")) else {}
        draw = lambda: figures.CASES_FIGURES[args.name](cases, **kwargs)  # noqa: E731
    elif args.name in figures.CASE_FIGURES:
        if not args.input:
            raise InputError(f"figure '{args.name}' needs --input CASE.nc (from capslide run)")
        from ..figures.cap import ACZOOM_UBAR, aczoom_snapshots

        case = open_result(args.input, "case")
        element = config_of(args.input)["mesh"]["element"]
        if element in ("H1", "H2"):
            raise InputError(f"'{args.input}' is a 3D case (mesh.element = {element}); figure '{args.name}' draws "
                             "the 2D cap (a 3D case's: sphere_Tn, sphere_Pa, sphere_Aczoom)")
        if case.sizes.get("snapshot_ubar", 0) == 0:
            raise InputError(f"'{args.input}' holds no field snapshots (figure '{args.name}' needs them: "
                             "output.snapshot_ubar)")
        if args.name == "cap_Aczoom" and not aczoom_snapshots(case["snapshot_ubar"].values):
            raise InputError(f"'{args.input}' holds no snapshot at ubar = {', '.join(f'{u:g}' for u in ACZOOM_UBAR)} "
                             "(figure 'cap_Aczoom' shows those: output.snapshot_ubar)")
        draw = lambda: figures.CASE_FIGURES[args.name](case)  # noqa: E731
    elif args.name in figures.SPHERE_FIGURES:
        if not args.input:
            raise InputError(f"figure '{args.name}' needs --input CASE.nc (a 3D case from capslide run)")
        case = open_result(args.input, "case")
        if "Z_node" not in case.coords:
            raise InputError(f"'{args.input}' is not a 3D case (figure '{args.name}' needs mesh.element = H1 or H2)")
        if args.name == "sphere_Aczoom" and case.sizes.get("snapshot_ubar", 0) == 0:
            raise InputError(f"'{args.input}' holds no field snapshots (figure 'sphere_Aczoom' draws the contact at "
                             "each: output.snapshot_ubar)")
        variable, key = _SPHERE_FIGURE_NEEDS[args.name]
        if variable not in case:
            raise InputError(f"'{args.input}' holds no '{variable}' (figure '{args.name}' needs {key})")
        params = Parameters.from_config(config_of(args.input))
        draw = lambda: figures.SPHERE_FIGURES[args.name](case, params)  # noqa: E731
    elif args.name in figures.TABLE_FIGURES:
        from ..studies.verification import read_tables

        if not args.tables:
            raise InputError(f"figure '{args.name}' needs --table FILE.csv")
        for table in args.tables:
            if not Path(table).is_file():
                raise InputError(f"table '{table}' does not exist (capslide verify writes it)")
        draw = lambda: figures.TABLE_FIGURES[args.name](read_tables(args.tables))  # noqa: E731
    else:
        if not args.input:
            raise InputError(f"figure '{args.name}' needs --input MESH.nc")
        params = Parameters.from_config(config_of(args.input))
        mesh = read_mesh(args.input)
        draw = lambda: figures.MESH_FIGURES[args.name](mesh, params)  # noqa: E731
    with figures.journal_style():
        figures.save(draw(), outputs)
    return 0
