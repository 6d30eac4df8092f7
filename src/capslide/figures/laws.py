"""Figures of the contact laws (Mergel et al. 2019, section 4): f:Tn, f:modelCA, f:modelAM, f:TnTt.

Drawn from :mod:`capslide.laws.contact` with the CGCM constants of the configuration; the illustration values that
the paper's captions state (tau_DI = 0.5 T_max, g_cut = 1.1 r0, mu_EA = 0.2) are the keyword defaults.
"""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np

from ..laws import contact
from ..params import Adhesion, Parameters
from .style import BLUE, DOUBLE_COLUMN, GREEN, ORANGE, PURPLE, SINGLE_COLUMN, YELLOW
from .style import star as _star

__all__ = ["fig_Tn", "fig_modelCA", "fig_modelAM", "fig_TnTt"]


def _gap_axis(a: Adhesion, lo: float = 0.0, hi: float = 2.5, n: int = 2001) -> np.ndarray:
    return np.linspace(lo, hi, n) * a.r0


def _tn(a: Adhesion, g, regularized: bool = True):
    if regularized:
        return contact.normal_traction(g, a.T0, a.r0, a.g_reg)[0]
    return contact.normal_traction_unregularized(g, a.T0, a.r0)[0]


def fig_Tn(p: Parameters):
    """f:Tn: CGCM normal traction Tn / T0 against g / r0, regularized below g_reg."""
    a = p.adhesion
    fig, ax = plt.subplots(figsize=(SINGLE_COLUMN, 2.5))
    g = _gap_axis(a, 0.55, 2.5)
    ax.plot(g / a.r0, _tn(a, g, False) / a.T0, color=BLUE, label=r"$T_\mathrm{n}(g_\mathrm{n})$")
    gr = _gap_axis(a, 0.0, a.g_reg / a.r0, 200)
    ax.plot(gr / a.r0, _tn(a, gr) / a.T0, "--", color=BLUE, label=r"regularized, $g_\mathrm{n} < g_\mathrm{reg}$")
    ax.axhline(0.0, color="k", lw=0.4)
    ax.axhline(-a.T_max / a.T0, color="0.5", lw=0.6, ls=":")
    ax.text(2.45, -a.T_max / a.T0 + 0.04, r"$-T_\mathrm{n}^\mathrm{max}$", ha="right", va="bottom", fontsize=7)
    _star(ax, a.g_eq / a.r0, 0.0, ORANGE, r"$g_\mathrm{eq}$ ($T_\mathrm{n} = 0$)")
    _star(ax, a.g_max / a.r0, -a.T_max / a.T0, YELLOW, r"$g_\mathrm{max}$")
    ax.set(xlim=(0, 2.5), ylim=(-0.7, 2.0), xlabel=r"normal gap $g_\mathrm{n}\,/\,r_0$",
           ylabel=r"normal traction $T_\mathrm{n}\,/\,T_0$")
    ax.text(0.03, 0.97, "repulsion", transform=ax.transAxes, va="top", fontsize=7)
    ax.text(1.6, -0.38, "attraction", ha="center", fontsize=7)
    ax.legend(loc="upper right")
    return fig


def _friction_law_panel(ax, thresholds, colors, labels, eps_t: float, scale_t: float, scale_g: float):
    """Tangential traction against tangential slip at fixed gaps (return map)."""
    t_hi = max(max(thresholds), 1e-12)
    g_t = np.linspace(-2.5, 2.5, 1001) * t_hi / eps_t
    styles = ["-", "--", ":"]  # equal thresholds stay visible on top of each other
    for i, (thr, col, lab) in enumerate(zip(thresholds, colors, labels)):
        T, *_ = contact.return_map(-eps_t * g_t, thr)
        ax.plot(g_t / scale_g, -T / scale_t, styles[i % 3], color=col, lw=2.0 - 0.4 * i, label=lab)
    ax.axhline(0.0, color="k", lw=0.4)
    ax.axvline(0.0, color="k", lw=0.4)
    ax.set(xlabel=r"tangential slip $g_\mathrm{t}\,/\,r_0$")


def fig_modelCA(p: Parameters, tau_over_T_max: float = 0.5, g_cut_over_r0: float = 1.1):
    """f:modelCA: model DI threshold (a) against g_n and (b) friction law at fixed g_n."""
    a, f = p.adhesion, p.friction
    tau, g_cut = tau_over_T_max * a.T_max, g_cut_over_r0 * a.r0
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(DOUBLE_COLUMN, 2.5))
    g = _gap_axis(a, 0.0, 2.0)
    t, _ = contact.di_threshold(g, tau, f.k_DI, g_cut)
    ax1.plot(g / a.r0, np.where(g <= g_cut, tau, 0.0) / a.T0, "--", color="0.4", lw=0.8, label="original (step)")
    ax1.plot(g / a.r0, t / a.T0, color=BLUE, label=fr"logistic, $k_\mathrm{{DI}} r_0 = {f.k_DI * a.r0:g}$")
    marks = [(a.g_eq, ORANGE, r"$g_\mathrm{eq}$"), (a.g_max, YELLOW, r"$g_\mathrm{max}$"),
             (1.2 * g_cut, PURPLE, r"$1.2\,g_\mathrm{cut}$")]
    for gm, col, lab in marks:
        _star(ax1, gm / a.r0, contact.di_threshold(gm, tau, f.k_DI, g_cut)[0] / a.T0, col, lab)
    ax1.axvline(g_cut / a.r0, color="0.6", lw=0.5, ls=":")
    ax1.text(g_cut / a.r0 - 0.03, 0.02, r"$g_\mathrm{cut}$", fontsize=7, ha="right")  # clear of the curve
    ax1.set(xlim=(0, 2), ylim=(0, 0.35), xlabel=r"normal gap $g_\mathrm{n}\,/\,r_0$",
            ylabel=r"sliding threshold $t_\mathrm{slide}\,/\,T_0$", title="(a) sliding threshold")
    ax1.legend(loc="upper right")
    thresholds = [float(contact.di_threshold(gm, tau, f.k_DI, g_cut)[0]) for gm, _, _ in marks]
    _friction_law_panel(ax2, thresholds, [m[1] for m in marks], [m[2] for m in marks], f.eps_t, a.T0, a.r0)
    ax2.set(ylabel=r"tangential traction $t_\mathrm{t}\,/\,T_0$", title=r"(b) friction law at fixed $g_\mathrm{n}$")
    ax2.legend(loc="upper left")
    fig.suptitle(fr"Model DI: $\tau_\mathrm{{DI}} = {tau_over_T_max:g}\,T_\mathrm{{n}}^\mathrm{{max}}$, "
                 fr"$g_\mathrm{{cut}} = {g_cut_over_r0:g}\,r_0$", y=1.0)
    fig.tight_layout()
    return fig


def fig_modelAM(p: Parameters, mu: float = 0.2, s_cuts=(0.0, 0.5, 1.0)):
    """f:modelAM: model EA threshold against g_n and friction law, for several s_cut."""
    a, f = p.adhesion, p.friction
    fig, axes = plt.subplots(len(s_cuts), 2, figsize=(DOUBLE_COLUMN, 2.2 * len(s_cuts)), squeeze=False)
    g_lo = _gap_axis(a, 0.0, a.g_reg / a.r0, 200)
    g_hi = _gap_axis(a, a.g_reg / a.r0, 2.0, 1500)
    marks = [(0.5 * a.r0, GREEN, r"$0.5\,r_0$"), (a.g_eq, ORANGE, r"$g_\mathrm{eq}$"), (a.g_max, YELLOW, r"$g_\mathrm{max}$")]
    for row, s_cut in zip(axes, s_cuts):
        g_cut = contact.ea_g_cut(s_cut, a.g_eq, a.g_max)
        law = lambda g: contact.ea_threshold(g, mu, g_cut, a.T0, a.r0, a.g_reg)[0]  # noqa: E731
        ax1, ax2 = row
        Tn_cut = float(_tn(a, g_cut))
        ax1.plot(g_hi / a.r0, law(g_hi) / a.T0, color=BLUE, label=r"$T_\mathrm{slide}$")
        unreg = np.where(g_lo < g_cut, mu * (_tn(a, np.maximum(g_lo, 0.3 * a.r0), False) - Tn_cut), 0.0)
        ax1.plot(g_lo / a.r0, unreg / a.T0, color=BLUE, lw=0.7, label="unregularized")
        ax1.plot(g_lo / a.r0, law(g_lo) / a.T0, "--", color=BLUE, label="regularized")
        ax1.plot(g_hi / a.r0, mu * (_tn(a, g_hi) - Tn_cut) / a.T0, ":", color="0.5", lw=0.7,
                 label=r"$\mu_\mathrm{EA}\,[T_\mathrm{n} - T_\mathrm{n}(g_\mathrm{cut})]$")
        for gm, col, lab in marks:
            _star(ax1, gm / a.r0, float(law(gm)) / a.T0, col, lab)
        ax1.axhline(0.0, color="k", lw=0.4)
        ax1.set(xlim=(0, 2), ylim=(-0.15, 0.5), ylabel=r"$T_\mathrm{slide}\,/\,T_0$",
                title=fr"(s$_\mathrm{{cut}}$ = {s_cut:g}) sliding threshold")
        thresholds = [float(law(gm)) for gm, _, _ in marks]
        _friction_law_panel(ax2, thresholds, [m[1] for m in marks], [m[2] for m in marks], f.eps_t, a.T0, a.r0)
        ax2.set(ylabel=r"$T_\mathrm{t}\,/\,T_0$",
                title=fr"(s$_\mathrm{{cut}}$ = {s_cut:g}) friction law at fixed $g_\mathrm{{n}}$")
    axes[0, 0].legend(loc="upper right", ncol=2)
    axes[0, 1].legend(loc="upper left")
    axes[-1, 0].set_xlabel(r"normal gap $g_\mathrm{n}\,/\,r_0$")
    fig.suptitle(fr"Model EA: $\mu_\mathrm{{EA}} = {mu:g}$, $J_\mathrm{{c\ell}} = 1$", y=1.0)
    fig.tight_layout()
    return fig


def _arrow_along(ax, x, y, idx, color):
    ax.annotate("", xy=(x[idx + 1], y[idx + 1]), xytext=(x[idx], y[idx]),
                arrowprops={"arrowstyle": "-|>", "color": color, "lw": 0.8, "mutation_scale": 8})


def fig_TnTt(p: Parameters, mu: float = 0.2, tau_over_T_max: float = 0.5, g_cut_over_r0: float = 1.1):
    """f:TnTt: directed sliding traction against normal traction, g_n from 0 to infinity."""
    a, f = p.adhesion, p.friction
    g = np.concatenate([np.linspace(0.0, 3.0, 3000), np.linspace(3.0, 40.0, 500)[1:]]) * a.r0
    Tn = _tn(a, g)
    panels = []
    for s_cut, name in ((0.0, r"$g_\mathrm{cut} = g_\mathrm{eq}$"),
                        (0.5, r"$g_\mathrm{cut} = (g_\mathrm{eq} + g_\mathrm{max})/2$"),
                        (1.0, r"$g_\mathrm{cut} = g_\mathrm{max}$")):
        g_cut = contact.ea_g_cut(s_cut, a.g_eq, a.g_max)
        panels.append((f"EA, {name}", lambda gg, gc=g_cut: contact.ea_threshold(gg, mu, gc, a.T0, a.r0, a.g_reg)[0],
                       [(0.5 * a.r0, GREEN), (a.g_eq, ORANGE), (a.g_max, YELLOW)]))
    tau, g_cut_di = tau_over_T_max * a.T_max, g_cut_over_r0 * a.r0
    panels.append(("DI", lambda gg: contact.di_threshold(gg, tau, f.k_DI, g_cut_di)[0],
                   [(a.g_eq, ORANGE), (a.g_max, YELLOW), (1.2 * g_cut_di, PURPLE)]))
    fig, axes = plt.subplots(2, 2, figsize=(DOUBLE_COLUMN, 4.6))
    for ax, (title, law, marks), letter in zip(axes.flat, panels, "abcd"):
        T = law(g)
        x, y = Tn / a.T0, T / a.T0
        # arrows in the direction of growing g_n: on the compressive branch (Tn = 1.2, 0.4 T0) and the far one
        beyond_max = np.flatnonzero(g > a.g_max)
        marks_at = [int(np.argmin(np.abs(np.where(g < a.g_eq, x, np.inf) - t))) for t in (1.2, 0.4)]
        marks_at.append(int(beyond_max[np.argmin(np.abs(x[beyond_max] + 0.25))]))
        for sgn in (1.0, -1.0):
            ax.plot(x, sgn * y, color=BLUE)
            for i in marks_at:
                _arrow_along(ax, x, sgn * y, min(i, len(g) - 2), BLUE)
        for gm, col in marks:
            tn, tt = float(_tn(a, gm)) / a.T0, float(law(gm)) / a.T0
            _star(ax, tn, tt, col)
            _star(ax, tn, -tt, col)
        ax.axhline(0.0, color="k", lw=0.4)
        ax.axvline(0.0, color="k", lw=0.4)
        ax.set(xlim=(-0.6, 2.0), ylim=(-0.45, 0.45), title=f"({letter}) {title}",
               xlabel=r"normal traction $T_\mathrm{n}\,/\,T_0$", ylabel=r"sliding traction $\pm T_\mathrm{slide}\,/\,T_0$")
    # what the stars mark: the states at these normal gaps
    keys = [(GREEN, r"$g_\mathrm{n} = r_0/2$"), (ORANGE, r"$g_\mathrm{n} = g_\mathrm{eq}$"),
            (YELLOW, r"$g_\mathrm{n} = g_\mathrm{max}$"), (PURPLE, r"$g_\mathrm{n} = 1.2\,g_\mathrm{cut}$ (DI)")]
    handles = [plt.Line2D([], [], ls="", marker="*", color=c, markersize=8, markeredgewidth=0.4, markeredgecolor="k",
                          label=text) for c, text in keys]
    fig.tight_layout(rect=(0, 0.06, 1, 1))
    fig.legend(handles=handles, loc="lower center", ncol=4, frameon=False)
    return fig
