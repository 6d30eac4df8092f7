"""The options study (config/options.yaml, docs/options.md): each option beyond the paper switched on alone, for
each model, compared with the reference option (the paper's model) in a table and two figures.

A case file per run, ``{cases}/{model}_{option}.nc``. The table gives each case's status, peak Ft, onset of full
sliding, steady Ft and Ft/A at the end of the slide, its peak against the steady force, and the change of its peak
Ft and onset ubar from the reference option of the same model (%).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from ..io.reading import ResultFileError, open_result
from ..states import Phase

__all__ = ["TABLE_COLUMNS", "read_cases", "table_rows"]

TABLE_COLUMNS = ["model", "option", "status", "end_ubar", "peak_Ft", "onset_ubar", "onset_area", "final_Ft",
                 "final_Ft_over_area", "peak_over_final", "peak_change_pct", "onset_change_pct", "what"]


def _curves(path: Path) -> dict:
    """Per-step arrays of the slide of one case (ubar, forces, area, edges), its scalars and its status."""
    ds = open_result(path, "case")
    slide = np.flatnonzero(ds["phase"].values == Phase.SLIDE)
    c = {k: ds[k].values[slide] for k in ("ubar", "Ft", "Fn", "h", "area", "area_stick", "x_left", "x_right",
                                          "x_stick_left", "x_stick_right", "Ft_over_area")}
    c.update(status=str(ds.attrs["status"]), peak_Ft=float(ds["peak_Ft"]), onset_ubar=float(ds["onset_ubar"]),
             onset_area=float(ds["onset_area"]))
    return c


def read_cases(spec: dict, cases_dir: str | Path, curves=None, target: str = "options") -> dict[tuple[str, str], dict]:
    """(model, option) -> ``curves(path)`` of its case file (default: the slide against ubar); ResultFileError
    naming a missing file and the Snakemake ``target`` that makes it."""
    read = curves or _curves
    out = {}
    for option, o in spec["options"].items():
        for model in o.get("models", list(spec["models"])):
            path = Path(cases_dir) / f"{model}_{option}.nc"
            if not path.is_file():
                raise ResultFileError(f"case file '{path}' does not exist (run: snakemake --cores 2 {target})")
            out[(model, option)] = read(path)
    return out


def _change(value: float, reference: float) -> float:
    return 100.0 * (value / reference - 1.0) if reference and math.isfinite(reference) else math.nan


def table_rows(spec: dict, curves: dict[tuple[str, str], dict]) -> list[dict]:
    """The table's rows, in the spec's order of options, models within."""
    rows = []
    for (model, option), c in curves.items():
        ref = curves.get((model, spec["reference"]))
        final = float(c["Ft"][-1]) if len(c["Ft"]) else math.nan
        rows.append({
            "model": model, "option": option, "status": c["status"],
            "end_ubar": float(c["ubar"][-1]) if len(c["ubar"]) else math.nan,
            "peak_Ft": c["peak_Ft"], "onset_ubar": c["onset_ubar"], "onset_area": c["onset_area"], "final_Ft": final,
            "final_Ft_over_area": float(c["Ft_over_area"][-1]) if len(c["Ft"]) else math.nan,
            "peak_over_final": c["peak_Ft"] / final if final else math.nan,
            "peak_change_pct": _change(c["peak_Ft"], ref["peak_Ft"]) if ref else math.nan,
            "onset_change_pct": _change(c["onset_ubar"], ref["onset_ubar"]) if ref else math.nan,
            "what": spec["options"][option].get("what", ""),
        })
    return rows
