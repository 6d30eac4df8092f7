"""The experiment study (config/experiment.yaml, docs/experiment.md): does a viscous bulk give the experiment's
features? The paper (section 5) names two that its elastic models miss: Ft drops after its static peak before
steady sliding, and the right (leading) contact edge moves inward late.

A case file per run, ``{cases}/{model}_{option}.nc`` (the options study's format, :mod:`capslide.studies.options`).
Each slide is read against time from the start of the slide (the experiment's t_start, when the motor starts). The
features, from the files:

* ``drop_pct``: the fall of Ft from its peak to the end of the slide, % of the peak (0: no drop);
* ``drop_time``: the time from the peak to where Ft has made half of that fall (s);
* ``right_edge_inward``: how far the right contact edge moves left after the peak, its current x at the peak minus
  its smallest later x (L0, in the frame of the cap's base, as the experiment's camera; 0: it never does);
* ``De``: the Deborah number tau v / L0 of the run's longest relaxation time (NaN for the elastic bulk);
* ``area_start``: the contact area the slide starts from (L0), after the dwell.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import yaml

from ..io.reading import ResultFileError, open_result
from ..states import Phase
from . import options

__all__ = ["TABLE_COLUMNS", "read_cases", "features", "table_rows", "findings"]

ROUNDING = 1e-9  # relative changes below this are the Newton tolerance's, not a drop or a motion
TABLE_COLUMNS = ["model", "option", "De", "status", "area_start", "peak_Ft", "t_peak", "onset_ubar", "final_Ft", "drop_pct",
                 "drop_time", "right_edge_inward", "area_at_peak", "final_Ft_over_area", "what"]


def _deborah(config: dict) -> float:
    prony = config["material"].get("prony") or []
    v = config["loading"].get("velocity")
    if config["material"].get("model") != "viscoelastic" or not prony or not v:
        return math.nan
    return max(b["tau"] for b in prony) * v / config["geometry"]["L0"]


def _curves(path: Path) -> dict:
    """The slide of one case against time from its start, its scalars, status and Deborah number."""
    ds = open_result(path, "case")
    slide = np.flatnonzero(ds["phase"].values == Phase.SLIDE)
    if "time" not in ds.coords:
        raise ResultFileError(f"case file '{path}' has no time (run it with loading.velocity)")
    c = {k: ds[k].values[slide] for k in ("ubar", "time", "Ft", "Fn", "area", "x_left", "x_right", "Ft_over_area")}
    start = slide[0] - 1 if len(slide) and slide[0] > 0 else 0  # the state the slide starts from
    if ds.sizes["step"]:
        c["time"] = c["time"] - ds["time"].values[start]
    c["area_start"] = float(ds["area"].values[start]) if ds.sizes["step"] else math.nan
    c.update(status=str(ds.attrs["status"]), peak_Ft=float(ds["peak_Ft"]), onset_ubar=float(ds["onset_ubar"]),
             De=_deborah(yaml.safe_load(ds.attrs["config_yaml"])), path=str(path))
    return c


def read_cases(spec: dict, cases_dir: str | Path) -> dict[tuple[str, str], dict]:
    """(model, option) -> the slide of its case file against time; ResultFileError naming a missing file."""
    return options.read_cases(spec, cases_dir, _curves, "experiment")


def features(c: dict) -> dict:
    """The experiment's features of one slide (see the module's docstring)."""
    Ft, t, xr = c["Ft"], c["time"], c["x_right"]
    if not len(Ft):
        return {"t_peak": math.nan, "final_Ft": math.nan, "drop_pct": math.nan, "drop_time": math.nan,
                "right_edge_inward": math.nan, "area_at_peak": math.nan}
    k = int(np.argmax(np.abs(Ft)))
    peak, final = float(Ft[k]), float(Ft[-1])
    drop = peak - final if abs(peak - final) > ROUNDING * abs(peak) else 0.0  # a steady slide: no drop
    half = np.flatnonzero(np.abs(Ft[k:] - peak) >= 0.5 * abs(drop)) if drop != 0.0 else np.array([], dtype=int)
    later = xr[k:][np.isfinite(xr[k:])]
    inward = float(xr[k] - later.min()) if len(later) else math.nan
    return {"t_peak": float(t[k]), "final_Ft": final, "drop_pct": 100.0 * drop / peak if peak else math.nan,
            "drop_time": float(t[k + half[0]] - t[k]) if len(half) and half[0] > 0 else math.nan,
            "right_edge_inward": inward if not inward <= ROUNDING * max(abs(xr[k]), 1.0) else 0.0,
            "area_at_peak": float(c["area"][k])}


def table_rows(spec: dict, curves: dict[tuple[str, str], dict]) -> list[dict]:
    """The table's rows, in the spec's order of options, models within."""
    rows = []
    for (model, option), c in curves.items():
        rows.append({"model": model, "option": option, "De": c["De"], "status": c["status"],
                     "area_start": c.get("area_start", math.nan), "peak_Ft": c["peak_Ft"],
                     "onset_ubar": c["onset_ubar"], **features(c),
                     "final_Ft_over_area": float(c["Ft_over_area"][-1]) if len(c["Ft"]) else math.nan,
                     "what": spec["options"][option].get("what", "")})
    return rows


def findings(rows: list[dict], drop_threshold_pct: float = 0.5, inward_threshold: float = 0.01) -> str:
    """What the table shows, in sentences with its numbers: per model and normal control, at which De Ft drops
    after its peak by more than ``drop_threshold_pct`` %, and where the right edge moves inward after the peak by
    more than ``inward_threshold`` L0."""
    lines = []
    groups: dict[tuple[str, str], list[dict]] = {}
    for r in rows:
        groups.setdefault((r["model"], r["option"].split("_")[0]), []).append(r)
    for (model, control), rs in groups.items():
        rs = sorted(rs, key=lambda r: -1.0 if math.isnan(r["De"]) else r["De"])
        parts = []
        for r in rs:
            name = "elastic" if math.isnan(r["De"]) else f"De = {r['De']:g}"
            drop = (f"Ft drops {r['drop_pct']:.2f} % after its peak {r['peak_Ft']:.4f}"
                    + (f" (half of it in {r['drop_time']:.3g} s)" if math.isfinite(r["drop_time"]) else "")
                    if r["drop_pct"] > drop_threshold_pct else f"no drop of Ft after its peak ({r['drop_pct']:.2f} %)")
            edge = (f"the right edge moves inward by {r['right_edge_inward']:.3f} L0 after the peak"
                    if r["right_edge_inward"] > inward_threshold else
                    f"the right edge does not move inward after the peak ({r['right_edge_inward']:.3f} L0)")
            parts.append(f"{name}: {drop}; {edge}")
        lines.append(f"- {model}, {control} control: " + "; ".join(parts) + ".")
    return "\n".join(lines) + "\n"
