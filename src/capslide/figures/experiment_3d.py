"""Figures of the experiment in numbers (issue 40, docs/experiment3d.md): the four panels of the paper's experimental
figure (its f:exp:results) drawn from the 3D model, and the contact seen from above at the experiment's snapshot
times (its f:exp:snapshots)."""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np

from ..studies.experiment_3d import window
from .sphere import outline_loops
from .style import BLUE, DOUBLE_COLUMN, GREEN, ORANGE, PURPLE

__all__ = ["fig_experiment3d_panels", "fig_experiment3d_outlines"]

_COLORS = ("k", BLUE, ORANGE, GREEN, PURPLE, "0.55", "tab:red", "tab:brown")
_ENDED = {"vanished": " (vanished)", "re-adhered": " (ended by a snap)"}  # the legend's note on a slide ended short


def fig_experiment3d_panels(cases: list[dict]):
    """(a) Ft and (b) A against time from the start of the slide, (c) A against Ft up to the peak, (d) Ft / A against
    time for the largest initial area; squares at the peaks, each curve to the peak plus half a contact width (the
    paper's window). ``cases``: :func:`capslide.studies.experiment_3d.read_cases` (the lambda checks are left out)."""
    main = [c for c in cases if "_lambda" not in c["case"]]
    fig, axes = plt.subplots(2, 2, figsize=(DOUBLE_COLUMN, 0.72 * DOUBLE_COLUMN))
    (a, b), (c_ax, d) = axes
    for k, c in enumerate(main):
        w, color = window(c), _COLORS[k % len(_COLORS)]
        t, Ft, A = c["time"][w], c["Ft"][w], c["area"][w]
        label = f"$A_0 = {c['A0']:.2f}$ mm$^2$" + _ENDED.get(c["outcome"], "")
        a.plot(t, Ft, color=color, lw=1.0, label=label)
        b.plot(t, A, color=color, lw=1.0)
        if np.isfinite(c["t_peak"]):
            kp = int(np.argmax(np.abs(c["Ft"])))
            a.plot(c["t_peak"], c["peak_Ft"], "s", ms=3.5, color=color)
            b.plot(c["t_peak"], c["area"][kp], "s", ms=3.5, color=color)
            up = w[w <= kp]
            c_ax.plot(c["Ft"][up], c["area"][up], color=color, lw=1.0)
            c_ax.plot(c["peak_Ft"], c["area"][kp], "s", ms=3.5, color=color)
    a.set_ylabel(r"$F_t$ (mN)")
    b.set_ylabel(r"$A$ (mm$^2$)")
    for ax in (a, b):
        ax.set_xlabel(r"$t - t_\mathrm{start}$ (s)")
    c_ax.set_xlabel(r"$F_t$ (mN)")
    c_ax.set_ylabel(r"$A$ (mm$^2$)")
    if main:
        big = max(main, key=lambda c: c["A0"])
        w = window(big)
        d.plot(big["time"][w], big["Ft"][w] / big["area"][w] * 1e-3, color="k", lw=1.0)
        d.set_title(f"$A_0 = {big['A0']:.2f}$ mm$^2$", fontsize=8)
    d.set_xlabel(r"$t - t_\mathrm{start}$ (s)")
    d.set_ylabel(r"$F_t / A$ (MPa)")
    a.legend(frameon=False, fontsize=6.5, loc="upper left")
    for ax, tag in zip(axes.ravel(), "abcd"):
        ax.text(-0.16, 1.02, f"({tag})", transform=ax.transAxes, fontsize=8)
    fig.tight_layout()
    return fig


def fig_experiment3d_outlines(case, times_s=(0.0, 0.45, 0.62, 0.73, 0.88, 1.25, 1.75)):
    """The contact (line) and its stick zone (shaded) seen from above at the experiment's snapshot times (s after
    the start of the slide, at the case's stage speed), in um; the plate slides along +x. ``case``: a case file
    (xarray) whose snapshots lie at those times."""
    import yaml

    config = yaml.safe_load(case.attrs["config_yaml"])
    um, v = config["geometry"]["L0"] * 1e6, config["loading"]["velocity"]
    ubar = np.asarray(case.snapshot_ubar.values, dtype=float)
    fig, axes = plt.subplots(1, len(times_s), figsize=(DOUBLE_COLUMN, 1.55), sharex=True, sharey=True, squeeze=False)
    for ax, t in zip(axes[0], times_s):
        k = int(np.argmin(np.abs(ubar * um * 1e-6 / v - t)))
        if abs(ubar[k] * um * 1e-6 / v - t) > 1e-3:
            ax.set_visible(False)
            continue
        stick = np.column_stack([case.stick_outline_x[k].values, case.stick_outline_y[k].values]) * um
        outline = np.column_stack([case.outline_x[k].values, case.outline_y[k].values]) * um
        for loop in outline_loops(stick):
            ax.fill(loop[:, 0], loop[:, 1], color=BLUE, alpha=0.35, lw=0)
        for loop in outline_loops(outline):
            ax.plot(loop[:, 0], loop[:, 1], color="k", lw=0.8)
        ax.set_aspect("equal")
        ax.set_title(f"{t:g} s", fontsize=7)
        ax.set_xlabel(r"$x$ ($\mu$m)")
    axes[0, 0].set_ylabel(r"$y$ ($\mu$m)")
    fig.tight_layout()
    return fig
