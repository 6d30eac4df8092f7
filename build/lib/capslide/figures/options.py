"""Figures of the options study (config/options.yaml, docs/options.md): Ft and A against ubar per model with every
option, and the contact and stick-zone edges against ubar per option."""

from __future__ import annotations

import math

import matplotlib.pyplot as plt
import numpy as np

from .style import BLUE, DOUBLE_COLUMN, GREEN, ORANGE, PURPLE, YELLOW

__all__ = ["fig_options", "fig_option_edges"]

COLORS = ("k", BLUE, ORANGE, PURPLE, GREEN, YELLOW, "tab:red", "tab:brown", "tab:cyan", "0.5")


def _styles(spec: dict) -> dict[str, tuple[str, str]]:
    """Colour and line style per option: the reference black and solid, the others in turn."""
    out, k = {}, 1
    for option in spec["options"]:
        if option == spec["reference"]:
            out[option] = ("k", "-")
        else:
            out[option] = (COLORS[k % len(COLORS)], ("--", "-.", ":")[(k - 1) % 3])
            k += 1
    return out


def fig_options(spec: dict, curves: dict):
    """Ft (top) and contact area (bottom) against ubar, one column per model, a line per option; squares at the
    onset of full sliding, crosses where a case snapped or ended early."""
    models = list(spec["models"])
    style = _styles(spec)
    fig, axes = plt.subplots(2, len(models), figsize=(DOUBLE_COLUMN, 4.6), squeeze=False, sharex=True)
    for j, model in enumerate(models):
        for option in spec["options"]:
            c = curves.get((model, option))
            if c is None or not len(c["ubar"]):
                continue
            col, ls = style[option]
            for ax, key in zip(axes[:, j], ("Ft", "area")):
                ax.plot(c["ubar"], c[key], ls, color=col, lw=1.0, label=option.replace("_", " "))
                if math.isfinite(c["onset_ubar"]):
                    ax.plot(c["onset_ubar"], np.interp(c["onset_ubar"], c["ubar"], c[key]), "s", color=col, ms=3.5,
                            mfc="white")
                if c["status"] != "completed":
                    ax.plot(c["ubar"][-1], c[key][-1], "x", color=col, ms=5)
        axes[0, j].set(title=f"({'ab'[j] if j < 2 else j}) model {model}, zero load", ylabel=r"$F_\mathrm{t}\,/\,(E L_0 W)$")
        axes[1, j].set(xlabel=r"tangential displacement $\bar{u}\,/\,L_0$", ylabel=r"contact area $A\,/\,L_0$")
    handles = {}
    for ax in axes[0]:
        for h, lab in zip(*ax.get_legend_handles_labels()):
            handles.setdefault(lab, h)
    fig.legend(list(handles.values()), list(handles), loc="lower center", ncol=min(len(handles), 5),
               bbox_to_anchor=(0.5, 0.0))
    fig.tight_layout(rect=(0, 0.1, 1, 1))
    return fig


def fig_option_edges(spec: dict, curves: dict, columns: int = 4):
    """Contact (grey band between its edges) and stick zone (coloured band) against ubar, a panel per model and
    option: where the stick zone closes from and when."""
    panels = [(m, o) for m in spec["models"] for o in spec["options"] if (m, o) in curves]
    per_model = {m: [p for p in panels if p[0] == m] for m in spec["models"]}
    rows = sum(math.ceil(len(v) / columns) for v in per_model.values() if v)
    fig, axes = plt.subplots(rows, columns, figsize=(DOUBLE_COLUMN, 1.55 * rows + 0.3), squeeze=False, sharex=True,
                             sharey=True)
    r = 0
    for model, mine in per_model.items():
        for k, (_, option) in enumerate(mine):
            ax = axes[r + k // columns, k % columns]
            c = curves[(model, option)]
            ax.fill_between(c["ubar"], c["x_left"], c["x_right"], color="0.85", lw=0, label="contact")
            ok = np.isfinite(c["x_stick_left"])
            ax.fill_between(c["ubar"], np.where(ok, c["x_stick_left"], np.nan), np.where(ok, c["x_stick_right"], np.nan),
                            color=BLUE, alpha=0.6, lw=0, label="stick zone")
            if math.isfinite(c["onset_ubar"]):
                ax.axvline(c["onset_ubar"], color="k", lw=0.5, ls=":")
            ax.set_title(f"{model}: {option.replace('_', ' ')}" + ("" if c["status"] == "completed" else f" ({c['status']})"),
                         fontsize=7)
        for k in range(len(mine), math.ceil(len(mine) / columns) * columns):
            axes[r + k // columns, k % columns].set_axis_off()
        r += math.ceil(len(mine) / columns)
    for ax in axes[:, 0]:
        ax.set_ylabel(r"$x\,/\,L_0$")
    for ax in axes[-1]:
        ax.set_xlabel(r"$\bar{u}\,/\,L_0$")
    handles, labels = axes[0, 0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="lower center", ncol=2, bbox_to_anchor=(0.5, 0.0))
    fig.tight_layout(rect=(0, 0.04, 1, 1))
    return fig
