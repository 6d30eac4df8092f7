"""Figures of the experiment in numbers (issue 40, docs/experiment3d.md): the four panels of the paper's experimental
figure (its f:exp:results) drawn from the 3D model, and the contact seen from above at the experiment's snapshot
times (its f:exp:snapshots)."""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np

from ..states import Phase
from ..studies.experiment_3d import window
from .sphere import outline_loops
from .style import BLUE, DOUBLE_COLUMN, GREEN, ORANGE, PURPLE, SINGLE_COLUMN

__all__ = ["fig_experiment3d_panels", "fig_experiment3d_outlines", "snapshot_panels"]

_COLORS = ("k", BLUE, ORANGE, GREEN, PURPLE, "0.55", "tab:red", "tab:brown")
_ENDED = {"vanished": " (vanished)", "re-adhered": " (ended by a snap)"}  # the legend's note on a slide ended short


def fig_experiment3d_panels(cases: list[dict]):
    """(a) Ft and (b) A against time from the start of the slide, (c) A against Ft up to the peak, (d) Ft / A against
    time for the largest initial area (against the stage travel in um where a case has no stage speed); squares at
    the peaks, each curve to the peak plus half a contact width (the paper's window). ``cases``:
    :func:`capslide.studies.experiment_3d.read_cases` (the lambda checks are left out, unless they are all)."""
    main = [c for c in cases if "_lambda" not in c["case"]] or cases  # the lambda checks alone: drawn
    timed = all(c["v"] for c in main)  # quasi-static cases (no stage speed) are drawn against the stage travel
    key, xlabel = ("time", r"$t - t_\mathrm{start}$ (s)") if timed else ("ubar", r"$\bar u$ ($\mu$m)")
    fig, axes = plt.subplots(2, 2, figsize=(DOUBLE_COLUMN, 0.72 * DOUBLE_COLUMN))
    (a, b), (c_ax, d) = axes
    areas = [f"{c['A0']:.2f}" for c in main]
    for k, c in enumerate(main):
        w, color = window(c), _COLORS[k % len(_COLORS)]
        t, Ft, A = c[key][w], c["Ft"][w], c["area"][w]
        label = (f"$A_0 = {areas[k]}$ mm$^2$" + (f", {c['case']}" if areas.count(areas[k]) > 1 else "")  # a check of
                 + _ENDED.get(c["outcome"], ""))  # one area (mesh, step): told apart by the file's name
        a.plot(t, Ft, color=color, lw=1.0, label=label)
        b.plot(t, A, color=color, lw=1.0)
        if np.isfinite(c["travel_to_peak"]):
            kp = int(np.argmax(np.abs(c["Ft"])))
            a.plot(c[key][kp], c["peak_Ft"], "s", ms=3.5, color=color)
            b.plot(c[key][kp], c["area"][kp], "s", ms=3.5, color=color)
            up = w[w <= kp]
            c_ax.plot(c["Ft"][up], c["area"][up], color=color, lw=1.0)
            c_ax.plot(c["peak_Ft"], c["area"][kp], "s", ms=3.5, color=color)
    a.set_ylabel(r"$F_t$ (mN)")
    b.set_ylabel(r"$A$ (mm$^2$)")
    for ax in (a, b, d):
        ax.set_xlabel(xlabel)
    c_ax.set_xlabel(r"$F_t$ (mN)")
    c_ax.set_ylabel(r"$A$ (mm$^2$)")
    if main:
        big = max(main, key=lambda c: c["A0"])
        w = window(big)
        Ft, A = big["Ft"][w], big["area"][w]
        stress = np.divide(Ft, A, out=np.full_like(Ft, np.nan), where=A > 0) * 1e-3  # none once the contact is gone
        d.plot(big[key][w], stress, color="k", lw=1.0)
        d.set_title(f"$A_0 = {big['A0']:.2f}$ mm$^2$", fontsize=8)
    d.set_ylabel(r"$F_t / A$ (MPa)")
    a.legend(frameon=False, fontsize=6.5, loc="upper left")
    for ax, tag in zip(axes.ravel(), "abcd"):
        ax.text(-0.16, 1.02, f"({tag})", transform=ax.transAxes, fontsize=8)
    fig.tight_layout()
    return fig


def snapshot_panels(snapshot_times, times_s, t_end: float) -> tuple[list[tuple[float, int]], str]:
    """Which of the experiment's times ``times_s`` (s) a case shows: (time, snapshot index) for each time within 1 ms
    of a snapshot time (s), and a note on the rest, those after the slide's end ``t_end`` (s) named as such."""
    snapshot_times = np.asarray(snapshot_times, dtype=float)
    shown, late, absent = [], [], []
    for t in times_s:
        k = int(np.argmin(np.abs(snapshot_times - t))) if len(snapshot_times) else -1
        if k >= 0 and abs(snapshot_times[k] - t) <= 1e-3:
            shown.append((t, k))
        else:
            (late if t > t_end else absent).append(t)
    parts = []
    if late:
        parts.append(f"{_listed(late)} s: after the slide's end at {t_end:.3g} s")
    if absent:
        parts.append(f"{_listed(absent)} s: no snapshot in the file")
    return shown, "; ".join(parts)


def _listed(times) -> str:
    words = [f"{t:g}" for t in times]
    return words[0] if len(words) == 1 else ", ".join(words[:-1]) + " and " + words[-1]


def fig_experiment3d_outlines(case, times_s=(0.0, 0.45, 0.62, 0.73, 0.88, 1.25, 1.75)):
    """The contact (line) and its stick zone (shaded) seen from above at the experiment's snapshot times (s after
    the start of the slide, at the case's stage speed), in um; the plate slides along +x. ``case``: a case file
    (xarray) whose snapshots lie at those times; the times it has no snapshot of are named under the panels (those
    after a slide that ended early)."""
    import yaml

    config = yaml.safe_load(case.attrs["config_yaml"])
    um, v = config["geometry"]["L0"] * 1e6, config["loading"]["velocity"]
    seconds = um * 1e-6 / v  # s per L0 of stage travel
    slide = np.flatnonzero(case.phase.values == Phase.SLIDE)
    t_end = float(case.ubar.values[slide[-1]]) * seconds if len(slide) else 0.0
    shown, note = snapshot_panels(np.asarray(case.snapshot_ubar.values, dtype=float) * seconds, times_s, t_end)
    n = max(len(shown), 1)
    width = DOUBLE_COLUMN if n >= 4 else max(SINGLE_COLUMN, 1.9 * n)
    fig, axes = plt.subplots(1, n, figsize=(width, 1.55 + (0.25 if note else 0.0)), sharex=True, sharey=True,
                             squeeze=False)
    for ax, (t, k) in zip(axes[0], shown):
        stick = np.column_stack([case.stick_outline_x[k].values, case.stick_outline_y[k].values]) * um
        outline = np.column_stack([case.outline_x[k].values, case.outline_y[k].values]) * um
        for loop in outline_loops(stick):
            ax.fill(loop[:, 0], loop[:, 1], color=BLUE, alpha=0.35, lw=0)
        for loop in outline_loops(outline):
            ax.plot(loop[:, 0], loop[:, 1], color="k", lw=0.8)
        ax.set_aspect("equal")
        ax.set_title(f"{t:g} s", fontsize=7)
        ax.set_xlabel(r"$x$ ($\mu$m)")
    if not shown:
        axes[0, 0].set_axis_off()
    axes[0, 0].set_ylabel(r"$y$ ($\mu$m)")
    fig.tight_layout()
    if note:
        fig.subplots_adjust(bottom=fig.subplotpars.bottom + 0.12)
        fig.text(0.5, 0.01, note, ha="center", va="bottom", fontsize=6.5)
    return fig
