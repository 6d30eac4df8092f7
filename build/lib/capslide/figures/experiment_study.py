"""Figures of the experiment study (config/experiment.yaml, docs/experiment.md): the four panels of the paper's
experimental figure drawn from the model, and the contact edges against time."""

from __future__ import annotations

import math

import matplotlib.pyplot as plt
import numpy as np

from .style import BLUE, DOUBLE_COLUMN, GREEN, ORANGE, PURPLE

__all__ = ["fig_experiment_panels", "fig_experiment_edges"]

_DE_COLORS = (BLUE, ORANGE, PURPLE, GREEN)


def _runs(spec: dict, curves: dict, control: str):
    """(model, option, curve, colour, label) of the runs of one normal control, the elastic bulk first, in black."""
    out = []
    for model in spec["models"]:
        mine = [(o, curves[(model, o)]) for o in spec["options"] if o.startswith(control + "_") and (model, o) in curves]
        mine.sort(key=lambda oc: -1.0 if math.isnan(oc[1]["De"]) else oc[1]["De"])
        k = 0
        for option, c in mine:
            if math.isnan(c["De"]):
                out.append((model, option, c, "k", "elastic"))
            else:
                out.append((model, option, c, _DE_COLORS[k % len(_DE_COLORS)], f"De = {c['De']:g}"))
                k += 1
    return out


def fig_experiment_panels(spec: dict, curves: dict, control: str):
    """One row per model: (a) Ft against time, (b) contact area against time, (c) area against Ft up to the peak,
    (d) Ft/A against time; time from the start of the slide; a line per Deborah number, squares at the peak."""
    models = list(spec["models"])
    fig, axes = plt.subplots(len(models), 4, figsize=(DOUBLE_COLUMN, 1.9 * len(models) + 0.5), squeeze=False)
    for model, _, c, color, label in _runs(spec, curves, control):
        row = axes[models.index(model)]
        t, Ft, A = c["time"], c["Ft"], c["area"]
        if not len(t):
            continue
        k = int(np.argmax(np.abs(Ft)))
        for ax, y in zip(row[[0, 1, 3]], (Ft, A, c["Ft_over_area"])):
            ax.plot(t, y, "-", color=color, lw=1.0, label=label)
            ax.plot(t[k], y[k], "s", color=color, ms=3, mfc="white")
        row[2].plot(Ft[: k + 1], A[: k + 1], "-", color=color, lw=1.0, label=label)
        row[2].plot(Ft[k], A[k], "s", color=color, ms=3, mfc="white")
    for j, model in enumerate(models):
        ax = axes[j]
        letters = "abcd" if j == 0 else "efgh"
        ax[0].set(ylabel=r"$F_\mathrm{t}\,/\,(E L_0 W)$", title=f"({letters[0]}) {model}: tangential force")
        ax[1].set(ylabel=r"contact area $A\,/\,L_0$", title=f"({letters[1]}) contact area")
        ax[2].set(xlabel=r"$F_\mathrm{t}\,/\,(E L_0 W)$", ylabel=r"$A\,/\,L_0$", title=f"({letters[2]}) area up to the peak")
        ax[3].set(ylabel=r"$F_\mathrm{t} / A\;/\;E$", title=f"({letters[3]}) mean shear stress")
        for a in ax[[0, 1, 3]]:
            a.set_xlabel(r"time since the slide started $t$ (s)")
    handles, labels = axes[0, 0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="lower center", ncol=len(labels), bbox_to_anchor=(0.5, 0.0))
    fig.suptitle(f"zero load, {control} control, v = 1 L0/s; squares: the peak of Ft", fontsize=8)
    fig.tight_layout(rect=(0, 0.05, 1, 1))
    return fig


def fig_experiment_edges(spec: dict, curves: dict, control: str):
    """The right (top row) and left (bottom row) contact edge, current x in the frame of the cap's base (as the
    experiment's camera), against time; a column per model, a colour per Deborah number; squares at the peak of
    Ft. The rows have their own scales, so a late inward motion of the right edge shows."""
    models = list(spec["models"])
    fig, axes = plt.subplots(2, len(models), figsize=(DOUBLE_COLUMN, 3.8), squeeze=False, sharex=True)
    for model, _, c, color, label in _runs(spec, curves, control):
        j = models.index(model)
        t = c["time"]
        if not len(t):
            continue
        k = int(np.argmax(np.abs(c["Ft"])))
        for ax, key in zip(axes[:, j], ("x_right", "x_left")):
            ax.plot(t, c[key], "-", color=color, lw=1.0, label=label)
            ax.plot(t[k], c[key][k], "s", color=color, ms=3, mfc="white")
    for j, model in enumerate(models):
        axes[0, j].set_title(f"({'ab'[j] if j < 2 else j}) {model}, {control} control: right (leading) edge")
        axes[1, j].set_title(f"({'cd'[j] if j < 2 else j}) {model}: left (trailing) edge")
        axes[1, j].set_xlabel(r"time since the slide started $t$ (s)")
    for ax in axes[:, 0]:
        ax.set_ylabel(r"current $x$ of the edge $/\,L_0$")
    handles, labels = axes[0, 0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="lower center", ncol=len(labels), bbox_to_anchor=(0.5, 0.0))
    fig.tight_layout(rect=(0, 0.06, 1, 1))
    return fig
