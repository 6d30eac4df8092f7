"""Hard-case stability suite: the checks that apply to a finished case, and the summary table.

Pure functions of per-step arrays (no file IO): the CLI reads the case
files and the suite's spec (``config/stability.yaml``) and writes the table.
Checks (forces normalized by E L0 W):

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
from dataclasses import dataclass

import numpy as np

__all__ = ["CHECKS", "CaseSummary", "summarize", "check", "pull_off_force", "TABLE_COLUMNS", "markdown_table",
           "case_overrides", "validate_spec", "EXPECTED"]

EXPECTED = ("completed", "detached", "diverged", "rejected")

SLIDE = 2  # phase flag of the slide (results.PHASE_FLAGS)
PRELOAD = 1


@dataclass
class CaseSummary:
    """What the table reports of one case (arrays from its file, scalars from its attributes)."""

    status: str
    steps: int
    cutbacks: int
    min_step: float
    newton_iterations: int
    krylov_iterations: int
    wall_time: float


def summarize(status: str, newton: np.ndarray, krylov: np.ndarray, cutbacks: int, min_step: float,
              wall_time: float) -> CaseSummary:
    return CaseSummary(status, len(newton), int(cutbacks), float(min_step), int(np.sum(newton)), int(np.sum(krylov)),
                       float(wall_time))


def validate_spec(spec: dict) -> None:
    """Raise ValueError naming the first bad entry of a stability spec (config/stability.yaml)."""
    if not isinstance(spec, dict) or not isinstance(spec.get("cases"), dict) or not spec["cases"]:
        raise ValueError("the spec needs a non-empty mapping 'cases'")
    for name, case in spec["cases"].items():
        if not isinstance(case, dict):
            raise ValueError(f"cases.{name} must be a mapping")
        if case.get("expect") not in EXPECTED:
            raise ValueError(f"cases.{name}.expect = {case.get('expect')!r} is not allowed (allowed: {', '.join(EXPECTED)})")
        if case.get("check", "none") not in (*CHECKS, "none"):
            raise ValueError(f"cases.{name}.check = {case.get('check')!r} is not allowed (allowed: {', '.join(CHECKS)}, none)")
        if "pull_off_fraction" in case and "pull_off" not in spec["cases"]:
            raise ValueError(f"cases.{name}.pull_off_fraction needs a case named 'pull_off'")


def case_overrides(spec: dict, name: str, pull_off: float | None = None) -> list[str]:
    """The ``key=value`` overrides of one hard case: the spec's base, then the case's own, then the preload
    as a fraction of ``pull_off`` when the case asks for it."""
    case = spec["cases"][name]
    sets = {**spec.get("base", {}), **case.get("set", {})}
    if "pull_off_fraction" in case:
        if pull_off is None or not math.isfinite(pull_off):
            raise ValueError(f"case {name} needs the pull-off force (from the case 'pull_off')")
        sets["loading.preload"] = round(float(case["pull_off_fraction"]) * pull_off, 6)
    return [f"{k}={str(v).lower() if isinstance(v, bool) else v}" for k, v in sets.items()]


def pull_off_force(phase: np.ndarray, Fn: np.ndarray) -> float:
    """Largest tensile Fn reached in the preload phase (E L0 W)."""
    pre = Fn[phase == PRELOAD]
    return float(np.max(pre)) if pre.size else math.nan


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
