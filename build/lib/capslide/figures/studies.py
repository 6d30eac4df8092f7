"""Figures of the studies: the Hertz/JKR verification against the closed forms, and speed against error."""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np

from ..laws import analytic
from .style import BLUE, DOUBLE_COLUMN, ORANGE, PURPLE

__all__ = ["fig_verification", "fig_convergence"]


def _max_abs_error(rows, scene, quantity):
    return float(np.max(np.abs([float(r["rel_error"]) for r in rows if r["scene"] == scene and r["quantity"] == quantity])))


def fig_verification(rows: list[dict]):
    """FE half-width against load for the Hertz and JKR scenes, with the closed forms; ``rows`` are the rows of
    the verification tables (:func:`capslide.studies.verification.read_tables`)."""
    fig, axes = plt.subplots(1, 2, figsize=(DOUBLE_COLUMN, 2.8))
    for ax, scene, title in ((axes[0], "hertz", "(a) Hertz (adhesion off)"), (axes[1], "jkr", "(b) JKR (full CGCM law)")):
        hw = [r for r in rows if r["scene"] == scene and r["quantity"] == "half_width"]
        if not hw:
            ax.set_axis_off()
            continue
        P = np.array([float(r["load_P"]) for r in hw])
        a_fe = np.array([float(r["fe"]) for r in hw])
        a_th = np.array([float(r["theory"]) for r in hw])
        c = dict(kv.split("=", 1) for kv in hw[0]["extra"].split(";") if "=" in kv)
        if {"R", "E_star", "w"} <= c.keys():  # the closed form as a smooth curve
            R, E_star, w = float(c["R"]), float(c["E_star"]), float(c["w"])
            a_lo = 0.95 * min(a_th.min(), a_fe.min())
            if w > 0:  # down past the critical half-width: the curve's minimum is the pull-off load
                a_lo = min(a_lo, 0.6 * analytic.jkr_cylinder_critical_half_width(R, E_star, w))
            a = np.linspace(a_lo, 1.03 * max(a_th.max(), a_fe.max()), 200)
            ax.plot(a, analytic.jkr_cylinder_load(a, R, E_star, w), "-", color=BLUE, label="closed form")
        else:
            order = np.argsort(a_th)
            ax.plot(a_th[order], P[order], "-", color=BLUE, label="closed form")
        ax.plot(a_fe, P, "o", mfc="none", color=ORANGE, label="finite elements")
        po = [r for r in rows if r["scene"] == scene and r["quantity"] == "pull_off"]
        for r in po:
            ax.axhline(float(r["theory"]), color="0.5", ls=":", lw=0.8)
            ax.axhline(float(r["fe"]), color=ORANGE, ls="--", lw=0.8)
            ax.text(0.98, max(float(r["theory"]), float(r["fe"])), "pull-off: closed form (dotted), FE (dashed) ",
                    fontsize=6, ha="right", va="bottom", transform=ax.get_yaxis_transform())
            low = min(float(r["theory"]), float(r["fe"]))
            top = ax.get_ylim()[1]
            ax.set_ylim(low - 0.06 * (top - low), top)
        errors = f"largest errors: a {100 * _max_abs_error(rows, scene, 'half_width'):.2f}%"
        if any(r["scene"] == scene and r["quantity"] == "load_at_half_width" for r in rows):
            errors += f", P(a) {100 * _max_abs_error(rows, scene, 'load_at_half_width'):.2f}%"
        pressure = [float(r["fe"]) for r in rows if r["scene"] == scene and r["quantity"] == "pressure_L2"]
        if pressure:  # L2 difference from the Hertz pressure, already relative to p0
            errors += f", p(x) {100 * max(pressure):.2f}%"
        ax.set(xlabel=r"contact half-width $a\,/\,L_0$", ylabel=r"load $P = -F_\mathrm{n}\,/\,(E L_0 W)$",
               title=f"{title}\n{errors}")
        ax.axhline(0.0, color="k", lw=0.4)
        ax.legend(loc="upper left")
    fig.tight_layout()
    return fig


SWEEP_MARKERS = {"mesh": ("o", BLUE), "Q2": ("s", ORANGE), "gauss": ("^", PURPLE), "slide_step": ("v", "0.35"),
                 "eps_t": ("D", "tab:green"), "k_DI": ("P", "tab:red"), "solver": ("X", "tab:brown"),
                 "bulk": ("h", "k"), "bulk_Q2": ("p", "tab:olive")}


def fig_convergence(rows, error_floor: float = 1e-6):
    """Largest relative QoI error against wall time (log-log), one panel per base case; the line joins the runs
    on the Pareto front. ``rows``: the convergence table (dicts with case, sweep, value, wall_time_s, error,
    pareto). Errors below ``error_floor`` (the reference run itself) are drawn at the floor (open markers)."""
    cases = list(dict.fromkeys(r["case"] for r in rows))
    fig, axes = plt.subplots(1, len(cases), figsize=(DOUBLE_COLUMN, 2.9), squeeze=False)
    for k, (ax, case) in enumerate(zip(axes[0], cases)):
        mine = [r for r in rows if r["case"] == case and np.isfinite(float(r["error"]))]
        seen = set()
        for r in mine:
            marker, color = SWEEP_MARKERS.get(r["sweep"], ("o", "k"))
            err = float(r["error"])
            label = r["sweep"] if r["sweep"] not in seen else None
            seen.add(r["sweep"])
            ax.plot(float(r["wall_time_s"]), max(err, error_floor), marker, color=color, ms=4,
                    mfc=color if err >= error_floor else "none", label=label, ls="none")
            if r["sweep"] == "mesh":
                ax.annotate(r["value"], (float(r["wall_time_s"]), max(err, error_floor)), fontsize=5,
                            xytext=(3, 2), textcoords="offset points")
        front = sorted((float(r["wall_time_s"]), max(float(r["error"]), error_floor)) for r in mine
                       if str(r["pareto"]).lower() in ("true", "1", "yes"))
        if front:
            t, e = zip(*front)
            ax.step(t, e, where="post", color="k", lw=0.7, ls="--", label="Pareto front")
        ax.set(xscale="log", yscale="log", xlabel="wall time of the run (s)",
               ylabel="largest relative error of the QoIs", title=f"({'ab'[k] if k < 2 else k}) {case}")
        for level in (0.01, 0.05):  # the error bounds of the 'paper' and 'fast' presets
            ax.axhline(level, color="0.6", lw=0.5, ls=":")
            ax.text(0.55, level, f"{level:.0%}", transform=ax.get_yaxis_transform(), ha="center", va="bottom",
                    fontsize=5.5, color="0.4")
        ax.legend(loc="lower left", fontsize=5.5, ncol=2)
    fig.tight_layout()
    return fig
