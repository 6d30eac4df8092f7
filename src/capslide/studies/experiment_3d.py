"""The experiment in numbers (issue 40, docs/experiment3d.md): the `experiment` scene's study section, one case per
initial contact area A0, each preloaded to its area and slid on the cantilever; and what each case gives against the
paper's section 3.

Cases (:func:`study_cases`): ``A0.270`` for A0 = 0.27 mm^2 at the scene's lambda, ``A0.270_lambda2`` for a lambda
check. Each sets ``loading.preload_area`` (L0^2) and ``loading.preload`` (the first guess: the Maugis-Dugdale force
at that area, Maugis 1992); all slide by the scene's ``loading.ubar_max``, so that the cases of one lambda start
from one normal state at zero load (:func:`normal_states`). The paper's window, to the peak and on by half a contact
width, is :func:`window`.

Per case (:func:`features`), from its file, in SI units (forces mN, areas mm^2, lengths um, time s):
``A0_target``, ``loading.preload_area`` (NaN for a preload to a force); ``A0``, the area the slide starts from (a
preload to an area ends within its tolerance, or, where the area jumps over the target as the contact edge snaps
by a face, on one side of the jump); ``Fn0``, its normal load (compressive > 0, as the paper's figure 5);
``peak_Ft`` and ``Ft_over_A_at_peak`` (MPa); ``area_loss_pct``, 1 - A / A0 at the peak; ``extent_ratio_at_peak``
(the x extent over the y width); ``travel_to_peak`` (the stage's travel, um), ``step_to_peak`` (the slide step that
reached the peak, um: the step error's scale there, set by the cut-backs, not by ``loading.max_slide_step``) and
``t_peak`` = travel / v;
``outcome``: ``sliding`` (the contact reached full sliding, at ``Ft_end`` = its Ft there), ``vanished`` (the
contact came off, at ``Ft_end`` = the last Ft), ``re-adhered`` (the regrowth rule ended the slide: the contact
snapped to a state with more area, :func:`capslide.loadpath.slide_rules.regrowth_check`; whether it came
off is read from ``area_end_pct``), ``stopped`` (the slide found no equilibrium on: a fold, or no convergence at the
smallest step; ``Ft_end`` = the last Ft), ``running`` (none of these, within the slide) or ``no slide`` (a case
preloaded only, ``loading.ubar_max`` = 0); ``ubar_end`` (um) and
``area_end_pct`` (A / A0, %) at the slide's last converged step: how much contact a case that ended short had left.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import yaml

from ..io.reading import ResultFileError, open_result
from ..laws import analytic, sphere
from ..loadpath.slide_rules import REGROWTH
from ..states import Phase

__all__ = ["TABLE_COLUMNS", "study_cases", "normal_states", "case_name", "preload_guess", "features", "read_cases",
           "window"]
TABLE_COLUMNS = ["case", "lambda", "status", "A0_target", "A0", "Fn0", "peak_Ft", "Ft_over_A_at_peak", "area_loss_pct",
                 "extent_ratio_at_peak", "travel_to_peak", "step_to_peak", "t_peak", "outcome", "Ft_end", "ubar_end",
                 "area_end_pct"]


def case_name(area_mm2: float, lam: float | None = None) -> str:
    return f"A{area_mm2:.3f}" + ("" if lam is None else f"_lambda{lam:g}")


def preload_guess(config: dict, area_mm2: float, lam: float) -> float:
    """The Maugis-Dugdale normal force at the contact area ``area_mm2`` (Fn / (E L0^2), positive = tensile) on a
    half-space with the configuration's sphere radius, E*, work of adhesion and Maugis parameter ``lam``."""
    mat, geo, adh = config["material"], config["geometry"], config["adhesion"]
    R, L0 = geo["R"] * geo["L0"], geo["L0"]
    scales = sphere.md_scales(R, analytic.effective_modulus(mat["E"], mat["nu"]), adh["W_adh"])
    a = math.sqrt(area_mm2 * 1e-6 / math.pi)
    P = float(sphere.md_load(a / scales["radius"], lam)) * scales["load"]  # N, compressive > 0
    return -P / (mat["E"] * L0**2)


def _case(config: dict, area_mm2: float, lam: float) -> dict:
    L0 = config["geometry"]["L0"]
    return {"loading.preload_area": round(area_mm2 * 1e-6 / L0**2, 6),
            "loading.preload": round(preload_guess(config, area_mm2, lam), 3), "adhesion.maugis_lambda": lam}


def normal_states(cases: dict[str, dict]) -> dict[str, dict]:
    """State name -> config overrides of the normal states the cases start from: one per lambda, the zero-load
    state (a preload to the force 0, not to an area)."""
    lams = sorted({sets["adhesion.maugis_lambda"] for sets in cases.values()})
    return {f"lambda{lam:g}": {"adhesion.maugis_lambda": lam, "loading.preload": 0.0, "loading.preload_area": None}
            for lam in lams}


def study_cases(config: dict) -> dict[str, dict]:
    """Case name -> config overrides of the scene's study section (``config``: the scene's validated config)."""
    spec, lam = config["study"], config["adhesion"]["maugis_lambda"]
    out = {case_name(A): _case(config, A, lam) for A in spec["areas_mm2"]}
    if spec["lambda_checks"]:
        A = spec["lambda_check_area_mm2"]
        out.update({case_name(A, other): _case(config, A, other) for other in spec["lambda_checks"]})
    return out


def window(c: dict) -> np.ndarray:
    """The slide steps the experiment's figure shows: to the peak and on by half the contact's width at the peak
    (the paper's time window), or all of them when the slide ends before."""
    if not len(c["ubar"]) or math.isnan(c["travel_to_peak"]):
        return np.arange(len(c["ubar"]))
    end = c["travel_to_peak"] + 0.5 * c["width_at_peak"]
    return np.flatnonzero(c["ubar"] <= end + 1e-9)


_CONTACT_3D = ("extent_ratio", "width_y", "x_left", "x_right")  # the contact's extents, which only 3D cases write


def features(path: Path) -> dict:
    """The slide of one case file in SI units, and the numbers of :data:`TABLE_COLUMNS`."""
    ds = open_result(path, "case")
    missing = [k for k in _CONTACT_3D if k not in ds]
    if missing:
        ds.close()
        raise ResultFileError(f"'{path}' has no {missing[0]}: not a 3D sphere case (a 2D case has no contact extents)")
    config = yaml.safe_load(ds.attrs["config_yaml"])
    L0, E = config["geometry"]["L0"], config["material"]["E"]
    mN, mm2, um = E * L0**2 * 1e3, L0**2 * 1e6, L0 * 1e6
    phase = ds["phase"].values
    slide = np.flatnonzero(phase == Phase.SLIDE)
    pre = np.flatnonzero(phase == Phase.PRELOAD)
    start = int(pre[-1]) if len(pre) else 0
    v = config["loading"]["velocity"]
    c = {k: np.asarray(ds[k].values[slide], dtype=float) for k in ("ubar", "Ft", "Fn", "area", "extent_ratio", "width_y")}
    c["x_extent"] = np.asarray(ds["x_right"].values[slide] - ds["x_left"].values[slide], dtype=float) * um
    c["ubar"], c["Ft"], c["Fn"], c["area"] = c["ubar"] * um, c["Ft"] * mN, c["Fn"] * mN, c["area"] * mm2
    c["width_y"] = c["width_y"] * um
    c["time"] = c["ubar"] * 1e-6 / v if v else np.full(len(slide), math.nan)
    A0 = float(ds["area"].values[start]) * mm2
    k = int(np.argmax(np.abs(c["Ft"]))) if len(slide) else None
    status = str(ds.attrs["status"])
    onset = float(ds["onset_ubar"]) * um
    if not len(slide):
        outcome, Ft_end = "no slide", math.nan
    elif math.isfinite(onset):
        outcome, Ft_end = "sliding", float(ds["onset_Ft"]) * mN
    elif status == "detached":
        outcome = "re-adhered" if REGROWTH in str(ds.attrs.get("status_reason", "")) else "vanished"
        Ft_end = float(c["Ft"][-1]) if len(slide) else math.nan
    elif status == "diverged":  # no equilibrium found on (a fold, or Newton's failure): the last converged Ft
        outcome, Ft_end = "stopped", float(c["Ft"][-1]) if len(slide) else math.nan
    else:
        outcome, Ft_end = "running", math.nan
    peak = {"peak_Ft": math.nan, "Ft_over_A_at_peak": math.nan, "area_loss_pct": math.nan,
            "extent_ratio_at_peak": math.nan, "travel_to_peak": math.nan, "step_to_peak": math.nan, "t_peak": math.nan,
            "width_at_peak": math.nan}
    if k is not None:
        peak = {"peak_Ft": abs(float(c["Ft"][k])), "Ft_over_A_at_peak": abs(float(c["Ft"][k])) / float(c["area"][k]) * 1e-3,
                "area_loss_pct": 100.0 * (1.0 - float(c["area"][k]) / A0), "extent_ratio_at_peak": float(c["extent_ratio"][k]),
                "travel_to_peak": float(c["ubar"][k]), "step_to_peak": float(c["ubar"][k] - (c["ubar"][k - 1] if k else 0.0)),
                "t_peak": float(c["time"][k]), "width_at_peak": float(c["x_extent"][k])}
    target = config["loading"].get("preload_area")
    c.update(peak, case=Path(path).stem, status=status, A0=A0, A0_target=math.nan if target is None else target * mm2,
             Fn0=-float(ds["Fn"].values[start]) * mN,
             outcome=outcome, Ft_end=Ft_end, v=v, path=str(path),
             ubar_end=float(c["ubar"][-1]) if len(slide) else math.nan,
             area_end_pct=100.0 * float(c["area"][-1]) / A0 if len(slide) else math.nan,
             **{"lambda": float(config["adhesion"]["maugis_lambda"] or math.nan)})
    ds.close()
    return c


def read_cases(paths) -> list[dict]:
    """:func:`features` of each case file, by initial area, the lambda checks last."""
    out = [features(Path(p)) for p in paths]
    return sorted(out, key=lambda c: ("_lambda" in c["case"], c["A0"]))
