"""Hard-case stability suite: the checks that apply to a finished case, and the summary table.

The checks are pure functions of per-step arrays; :func:`evaluate` reads
the case files of a suite (``config/stability.yaml``, expanded by
:func:`capslide.studies.expansion.runs`) into table rows. Checks (forces normalized by E L0 W):

- ``force_balance``: max over steps of |Fn + base_force_y| and |Ft + base_force_x|
  (contact force against the clamped base's reaction), passes below 1e-8;
- ``di_tau_area``: at the last step, |Ft / (tau_DI A) - 1| (DI at full
  sliding), passes below 2 % (the logistic edge of the DI law makes the rest);
- ``closed_loop``: after sliding forward and back, ubar returns to 0 and Ft
  changes sign; the value is the final Ft over the peak forward Ft;
- ``recovered``: the case needed cut-backs and still completed (value: the
  number of cut-backs);
- ``pull_off``: the case ended ``detached`` in the preload; the value is the
  largest tensile Fn reached (the pull-off force);
- ``detached_while_sliding``: the contact came off during the slide; the value
  is the ubar of the last converged step.
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from pathlib import Path

import numpy as np

from ..config import ConfigError, load_config
from ..io.reading import ResultFileError, open_result
from ..model import cost
from ..model.build import cap_mesh_spec
from ..params import Parameters
from ..states import Phase, Status

__all__ = ["CHECKS", "check", "pull_off_force", "pull_off_preload", "case_arrays", "evaluate", "TABLE_COLUMNS",
           "markdown_table"]

SLIDE, PRELOAD = Phase.SLIDE, Phase.PRELOAD


def pull_off_force(phase: np.ndarray, Fn: np.ndarray) -> float:
    """Largest tensile Fn reached in the preload phase (E L0 W)."""
    pre = Fn[phase == PRELOAD]
    return float(np.max(pre)) if pre.size else math.nan


def pull_off_preload(case_file: str | Path, fraction: float) -> float:
    """``fraction`` of the pull-off force of a case file (rounded to 1e-6: a preload for a config overlay)."""
    ds = open_result(case_file, "case")
    return round(float(fraction) * pull_off_force(ds["phase"].values, ds["Fn"].values), 6)


def detached_in_preload(case_file: str | Path) -> str | None:
    """None when the case file ended detached in its preload (its pull-off force is the preload's last force);
    otherwise how it ended instead."""
    ds = open_result(case_file, "case")
    status, phases = str(ds.attrs.get("status")), ds["phase"].values
    last = Phase(int(phases[-1])).label if len(phases) else "no step"
    if status == Status.DETACHED.label and last == Phase.PRELOAD.label:
        return None
    return f"ended {status} in its {last}" if len(phases) else f"ended {status} with no step"


def case_arrays(path: str | Path) -> dict:
    """Step arrays and attributes of a case file that the checks use."""
    ds = open_result(path, "case")
    a = {k: ds[k].values for k in ("phase", "ubar", "Fn", "Ft", "area", "base_force_x", "base_force_y",
                                   "newton_iterations", "krylov_iterations")}
    at = ds.attrs
    a.update(status=str(at.get("status")), cutbacks=int(at.get("cutbacks", 0)), min_step=float(at.get("min_step", np.nan)),
             wall_time=float(at.get("case_wall_time", np.nan)),
             tau_DI=float(at["friction_mu_DI"]) * float(at["adhesion_T_max"]) / float(at["material_E"]))
    return a


def evaluate(spec: dict, runs: dict[str, dict], config_files: Iterable[str | Path],
             cases_dir: str | Path) -> tuple[list[dict], dict[str, dict]]:
    """Table rows of the suite (``runs``: its expansion) and the arrays of every case file read.

    A case expected to be rejected passes when its configuration is refused; every other case is read from
    ``cases_dir/{name}.nc`` and passes when it ends with the expected status, in force balance, passing its check,
    within the suite's time bound.
    """
    bound = float(spec.get("time_bound_s", np.inf))
    rows, arrays = [], {}
    for name, case in spec["cases"].items():
        row = {"case": name, "what": case.get("what", ""), "expected": case["expect"], "time_bound_s": bound,
               "check": case.get("check", "none")}
        if case["expect"] == "rejected":
            try:  # what `capslide run` refuses before computing: the configuration and its cost
                params = Parameters.from_config(load_config(config_files, settings=runs[name]))
                cost.check(params, cap_mesh_spec(params))
                row.update(status="accepted", passed=False)
            except ConfigError as err:
                row.update(status="rejected", check="config_error", check_value=str(err).split(":")[0], passed=True)
            rows.append(row)
            continue
        path = Path(cases_dir) / f"{name}.nc"
        if not path.is_file():
            raise ResultFileError(f"case file '{path}' does not exist (run: snakemake --cores 2 stability)")
        a = arrays[name] = case_arrays(path)
        fb, fb_ok = check("force_balance", a)
        value, ok = check(row["check"], a) if row["check"] != "none" else (np.nan, True)
        row.update(status=a["status"], steps=len(a["phase"]), cutbacks=a["cutbacks"], min_step=a["min_step"],
                   newton_iterations=int(a["newton_iterations"].sum()), krylov_iterations=int(a["krylov_iterations"].sum()),
                   wall_time_s=round(a["wall_time"], 1), force_balance=fb, check_value=value,
                   passed=bool(a["status"] == case["expect"] and fb_ok and ok and a["wall_time"] <= bound))
        rows.append(row)
    return rows, arrays


def _force_balance(a: dict) -> tuple[float, bool]:
    err = float(max(np.max(np.abs(a["Fn"] + a["base_force_y"])), np.max(np.abs(a["Ft"] + a["base_force_x"]))))
    return err, err <= 1e-8


def _di_tau_area(a: dict) -> tuple[float, bool]:
    err = abs(a["Ft"][-1] / (a["tau_DI"] * a["area"][-1]) - 1.0)
    return float(err), bool(err <= 0.02)


def _closed_loop(a: dict) -> tuple[float, bool]:
    slide = a["phase"] == SLIDE
    ubar, Ft = a["ubar"][slide], a["Ft"][slide]
    if ubar.size == 0:
        return math.nan, False
    ratio = float(Ft[-1] / np.max(Ft))
    return ratio, bool(abs(ubar[-1]) < 1e-12 and np.max(ubar) > 0 and ratio < 0)


def _recovered(a: dict) -> tuple[float, bool]:
    return float(a["cutbacks"]), bool(a["cutbacks"] > 0 and a["status"] == "completed")


def _pull_off(a: dict) -> tuple[float, bool]:
    F = pull_off_force(a["phase"], a["Fn"])
    return F, bool(a["status"] == "detached" and np.all(a["phase"] != SLIDE) and F > 0)


def _detached_while_sliding(a: dict) -> tuple[float, bool]:
    slide = a["phase"] == SLIDE
    return (float(a["ubar"][slide][-1]) if slide.any() else math.nan), bool(a["status"] == "detached" and slide.any())


CHECKS = {"force_balance": _force_balance, "di_tau_area": _di_tau_area, "closed_loop": _closed_loop,
          "recovered": _recovered, "pull_off": _pull_off, "detached_while_sliding": _detached_while_sliding}


def check(name: str, arrays: dict) -> tuple[float, bool]:
    """Value and verdict of one named check on a case's arrays (see the module docstring)."""
    return CHECKS[name](arrays)


TABLE_COLUMNS = ("case", "what", "expected", "status", "steps", "cutbacks", "min_step", "newton_iterations",
                 "krylov_iterations", "wall_time_s", "time_bound_s", "force_balance", "check", "check_value", "passed")


def markdown_table(rows: list[dict]) -> str:
    """The rows as a Markdown table (numbers with 4 significant digits)."""

    def fmt(v):
        if isinstance(v, bool):
            return "yes" if v else "**no**"
        if isinstance(v, float):
            return "" if math.isnan(v) else f"{v:.4g}"
        return str(v)

    lines = ["| " + " | ".join(TABLE_COLUMNS) + " |", "|" + "---|" * len(TABLE_COLUMNS)]
    lines += ["| " + " | ".join(fmt(r.get(c, "")) for c in TABLE_COLUMNS) + " |" for r in rows]
    return "\n".join(lines) + "\n"
