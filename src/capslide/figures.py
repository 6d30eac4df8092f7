"""Paper-style figures; the only module that imports matplotlib.

One function per figure, each returning a ``matplotlib.figure.Figure``;
:func:`save` writes it (PDF, PNG) atomically. Figure names are the paper's
labels (Mergel et al. 2019) without the ``f:`` prefix. Model figures are
drawn from the contact laws in :mod:`capslide.contact` with the CGCM
constants of the configuration; the illustration values that the paper's
captions state (tau_DI = 0.5 T_max, g_cut = 1.1 r0, mu_EA = 0.2) are the
keyword defaults.
"""

from __future__ import annotations

import contextlib
from pathlib import Path
from typing import Callable, Iterator

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from . import analytic, contact  # noqa: E402
from .atomic import replacing  # noqa: E402
from .mesh import Mesh  # noqa: E402
from .params import Adhesion, Parameters, JKRSphereExperiment, PDMS_SPHERE  # noqa: E402

__all__ = ["MODEL_FIGURES", "MESH_FIGURES", "journal_style", "save", "fig_Tn", "fig_modelCA", "fig_modelAM", "fig_TnTt",
           "fig_exp_FnJKR", "fig_cap_setup", "fig_verification", "TABLE_FIGURES", "CASES_FIGURES", "fig_cap_PxAndAc",
           "fig_cap_PxOverAc", "CASE_FIGURES", "fig_cap_Aczoom", "fig_cap_xn"]

# Marker colours of the paper's asterisks (its captions name them).
BLUE, ORANGE, YELLOW, PURPLE, GREEN = "#0072BD", "#D95319", "#EDB120", "#7E2F8E", "#77AC30"
SINGLE_COLUMN = 3.4  # inch
DOUBLE_COLUMN = 7.0  # inch

_STYLE = {
    "font.family": "serif",
    "font.serif": ["STIXGeneral", "DejaVu Serif"],
    "mathtext.fontset": "stix",
    "font.size": 8,
    "axes.labelsize": 8,
    "axes.titlesize": 8,
    "legend.fontsize": 7,
    "xtick.labelsize": 7,
    "ytick.labelsize": 7,
    "xtick.direction": "in",
    "ytick.direction": "in",
    "xtick.top": True,
    "ytick.right": True,
    "axes.linewidth": 0.6,
    "lines.linewidth": 1.2,
    "lines.markersize": 5,
    "legend.frameon": False,
    "savefig.dpi": 300,
    "savefig.bbox": "tight",
    "savefig.pad_inches": 0.02,
    "pdf.fonttype": 42,
}


@contextlib.contextmanager
def journal_style() -> Iterator[None]:
    """Matplotlib settings of a journal figure (serif, 8 pt, inward ticks)."""
    with plt.rc_context(_STYLE):
        yield


def save(fig, paths) -> None:
    """Write ``fig`` to every path (format from the suffix), atomically; then close it."""
    for path in map(Path, paths):
        with replacing(path) as tmp:
            fig.savefig(tmp, format=path.suffix.lstrip("."))
    plt.close(fig)


def _gap_axis(a: Adhesion, lo: float = 0.0, hi: float = 2.5, n: int = 2001) -> np.ndarray:
    return np.linspace(lo, hi, n) * a.r0


def _tn(a: Adhesion, g, regularized: bool = True):
    if regularized:
        return contact.normal_traction(g, a.T0, a.r0, a.g_reg)[0]
    return contact.normal_traction_unregularized(g, a.T0, a.r0)[0]


def _star(ax, x, y, color, label=None):
    ax.plot(x, y, "*", color=color, markersize=8, markeredgewidth=0.4, markeredgecolor="k", label=label, zorder=5)


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
    ax1.text(g_cut / a.r0 + 0.03, 0.02, r"$g_\mathrm{cut}$", fontsize=7)
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
        ax1.plot(g_hi / a.r0, law(g_hi) / a.T0, color=BLUE, label=r"$T_\mathrm{slide}$")
        ax1.plot(g_lo / a.r0, law(g_lo) / a.T0, "--", color=BLUE, label="regularized")
        Tn_cut = float(_tn(a, g_cut))
        ax1.plot(g_hi / a.r0, mu * (_tn(a, g_hi) - Tn_cut) / a.T0, ":", color="0.5", lw=0.7,
                 label=r"$\mu_\mathrm{EA}\,[T_\mathrm{n} - T_\mathrm{n}(g_\mathrm{cut})]$")
        for gm, col, lab in marks:
            _star(ax1, gm / a.r0, float(law(gm)) / a.T0, col, lab)
        ax1.axhline(0.0, color="k", lw=0.4)
        ax1.set(xlim=(0, 2), ylim=(-0.15, 0.5), ylabel=r"$T_\mathrm{slide}\,/\,T_0$",
                title=fr"(s$_\mathrm{{cut}}$ = {s_cut:g}) sliding threshold")
        thresholds = [float(law(gm)) for gm, _, _ in marks]
        _friction_law_panel(ax2, thresholds, [m[1] for m in marks], [m[2] for m in marks], f.eps_t, a.T0, a.r0)
        ax2.set(ylabel=r"$T_\mathrm{t}\,/\,T_0$", title=fr"(s$_\mathrm{{cut}}$ = {s_cut:g}) friction law at fixed $g_\mathrm{{n}}$")
    axes[0, 0].legend(loc="upper right", ncol=2)
    axes[0, 1].legend(loc="upper left")
    axes[-1, 0].set_xlabel(r"normal gap $g_\mathrm{n}\,/\,r_0$")
    fig.suptitle(fr"Model EA: $\mu_\mathrm{{EA}} = {mu:g}$, $J_\mathrm{{c\ell}} = 1$", y=1.0)
    fig.tight_layout()
    return fig


def _arrow_along(ax, x, y, idx, color):
    ax.annotate("", xy=(x[idx + 1], y[idx + 1]), xytext=(x[idx], y[idx]),
                arrowprops=dict(arrowstyle="-|>", color=color, lw=0.8, mutation_scale=8))


def fig_TnTt(p: Parameters, mu: float = 0.2, tau_over_T_max: float = 0.5, g_cut_over_r0: float = 1.1):
    """f:TnTt: directed sliding traction against normal traction, g_n from 0 to infinity."""
    a, f = p.adhesion, p.friction
    g = np.concatenate([np.linspace(0.0, 3.0, 3000), np.linspace(3.0, 40.0, 500)[1:]]) * a.r0
    Tn = _tn(a, g)
    panels = []
    for s_cut, name in ((0.0, r"$g_\mathrm{cut} = g_\mathrm{eq}$"), (0.5, r"$g_\mathrm{cut} = (g_\mathrm{eq} + g_\mathrm{max})/2$"),
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
        for sgn in (1.0, -1.0):
            ax.plot(x, sgn * y, color=BLUE)
            for frac in (0.08, 0.2):
                i = int(np.searchsorted(g, frac * a.r0 * 10))
                _arrow_along(ax, x, sgn * y, min(i, len(g) - 2), BLUE)
        for gm, col in marks:
            tn, tt = float(_tn(a, gm)) / a.T0, float(law(gm)) / a.T0
            _star(ax, tn, tt, col)
            _star(ax, tn, -tt, col)
        ax.axhline(0.0, color="k", lw=0.4)
        ax.axvline(0.0, color="k", lw=0.4)
        ax.set(xlim=(-0.6, 2.0), ylim=(-0.45, 0.45), title=f"({letter}) {title}",
               xlabel=r"normal traction $T_\mathrm{n}\,/\,T_0$", ylabel=r"sliding traction $\pm T_\mathrm{slide}\,/\,T_0$")
    fig.tight_layout()
    return fig


def _jkr_force_mN(area_mm2, e: JKRSphereExperiment, E: float, w: float):
    """Normal force (mN, tensile > 0, the paper's sign) from contact area by JKR for a sphere."""
    a = np.sqrt(np.asarray(area_mm2) * 1e-6 / np.pi)
    return -1e3 * analytic.jkr_sphere_load(a, e.R, analytic.effective_modulus(E, e.nu), w)


def fig_exp_FnJKR(p: Parameters | None = None, e: JKRSphereExperiment = PDMS_SPHERE, n_bars: int = 10):
    """f:exp:FnJKR: initial normal force from contact area (a) and radius (b), JKR sphere.

    Bars show the range of the force over E +- dE and dgamma +- d(dgamma).
    """
    area = np.linspace(0.0, e.area_max_mm2, 400)
    area_bars = np.linspace(e.area_max_mm2 / n_bars, e.area_max_mm2, n_bars)
    E_grid = np.linspace(e.E - e.dE, e.E + e.dE, 21)[:, None, None]
    w_grid = np.array([e.w - e.dw, e.w + e.dw])[None, :, None]
    F_nom = _jkr_force_mN(area, e, e.E, e.w)
    F_all = _jkr_force_mN(area_bars[None, None, :], e, E_grid, w_grid)
    F_lo, F_hi = F_all.min(axis=(0, 1)), F_all.max(axis=(0, 1))
    F_band = _jkr_force_mN(area[None, None, :], e, E_grid, w_grid)
    P_c = -1e3 * analytic.jkr_sphere_pull_off(e.R, analytic.effective_modulus(e.E, e.nu), e.w)
    a_c = analytic.jkr_sphere_critical_radius(e.R, analytic.effective_modulus(e.E, e.nu), e.w)
    fig, axes = plt.subplots(1, 2, figsize=(DOUBLE_COLUMN, 2.6))
    for ax, scale, ylabel, letter in (
        (axes[0], lambda A: A, r"initial contact area $A^0_\mathrm{real}$ (mm$^2$)", "a"),
        (axes[1], lambda A: np.sqrt(A / np.pi), r"contact radius $r^0_\mathrm{real} = \sqrt{A^0_\mathrm{real}/\pi}$ (mm)", "b"),
    ):
        ax.fill_betweenx(scale(area), F_band.min(axis=(0, 1)), F_band.max(axis=(0, 1)), color=BLUE, alpha=0.15, lw=0,
                         label=fr"range: $E = {e.E/1e6:g} \pm {e.dE/1e6:g}$ MPa, $\Delta\gamma = {e.w*1e3:g} \pm {e.dw*1e3:g}$ mJ/m$^2$")
        ax.plot(F_nom, scale(area), color=BLUE, label="JKR, nominal parameters")
        colors = plt.cm.viridis(np.linspace(0.0, 0.9, n_bars))
        for A, lo, hi, col in zip(area_bars, F_lo, F_hi, colors):
            ax.errorbar(0.5 * (lo + hi), scale(A), xerr=[[0.5 * (hi - lo)], [0.5 * (hi - lo)]], fmt="none",
                        ecolor=col, elinewidth=1.6, capsize=2)
        ax.plot(P_c, scale(np.pi * (a_c * 1e3) ** 2), "s", color=ORANGE, ms=4, label="pull-off (load control)")
        ax.axvline(0.0, color="k", lw=0.4)
        ax.set(xlabel=r"initial normal force $F^0_\mathrm{n}$ (mN), tensile $> 0$", ylabel=ylabel,
               title=f"({letter})", ylim=(0, scale(e.area_max_mm2) * 1.02))
    axes[0].legend(loc="lower left")
    fig.tight_layout()
    return fig


def _mesh_lines(ax, mesh: Mesh, lw=0.15, color="0.25"):
    from matplotlib.collections import PolyCollection

    corners = mesh.nodes[mesh.cells[:, :4]]
    ax.add_collection(PolyCollection(corners, facecolors="#dbe9f6", edgecolors=color, linewidths=lw))


def fig_cap_setup(mesh: Mesh, p: Parameters):
    """f:cap:setup: the cap, the rigid substrate above it, the mesh and a zoom on the contact band."""
    from matplotlib.patches import FancyArrowPatch, Rectangle

    g = p.geometry
    b = g.half_base
    band = float(mesh.info.get("band_half_width", 0.0))
    fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(DOUBLE_COLUMN, 5.2), gridspec_kw={"height_ratios": [1.25, 1]})
    _mesh_lines(ax1, mesh, lw=0.08)
    gap = 0.6
    ax1.add_patch(Rectangle((-b - 4, g.H + gap), 2 * b + 8, 3.0, facecolor="0.75", edgecolor="k", lw=0.6, hatch="////"))
    ax1.text(b - 1, g.H + gap + 1.5, "rigid substrate", ha="right", va="center", fontsize=7,
             bbox=dict(facecolor="white", edgecolor="none", pad=1))
    ax1.add_patch(Rectangle((-b - 4, -1.2), 2 * b + 8, 1.2, facecolor="white", edgecolor="k", lw=0.6, hatch="////"))
    ax1.text(0, -0.6, r"base fixed, $\mathbf{u} = \mathbf{0}$", ha="center", va="center", fontsize=7,
             bbox=dict(facecolor="white", edgecolor="none", pad=1))
    ax1.add_patch(FancyArrowPatch((b - 12, g.H + gap + 3.6), (b - 4, g.H + gap + 3.6), arrowstyle="-|>", mutation_scale=8, lw=0.8))
    ax1.text(b - 8, g.H + gap + 4.0, r"$\bar{u}$", ha="center", fontsize=8)
    ax1.add_patch(FancyArrowPatch((-6, g.H + gap + 5.5), (-6, g.H + gap + 3.1), arrowstyle="-|>", mutation_scale=8, lw=0.8))
    ax1.text(-5.4, g.H + gap + 4.6, r"$F_\mathrm{n}$ held fixed", fontsize=7)
    ax1.add_patch(Rectangle((-band, g.H - 1.0), 2 * band, 1.25, fill=False, edgecolor=ORANGE, lw=0.8, ls="--"))
    ax1.text(band + 0.5, g.H - 0.6, "contact band", color=ORANGE, fontsize=7)
    ax1.annotate("", xy=(b + 1.5, 0), xytext=(b + 1.5, g.H), arrowprops=dict(arrowstyle="<->", lw=0.6))
    ax1.text(b + 1.2, 0.3 * g.H, fr"$H = {g.H:g}\,L_0$", va="center", ha="right", fontsize=7)
    ax1.text(-b - 2, 6.0, fr"$R = {g.R:g}\,L_0$" + "\nneo-Hooke,\nplane strain,\n" + fr"$\nu = {p.material.nu:g}$", fontsize=7, va="center")
    ax1.set(xlim=(-b - 3, b + 5), ylim=(-1.5, g.H + gap + 6), aspect="equal", xlabel=r"$X\,/\,L_0$", ylabel=r"$Y\,/\,L_0$",
            title=fr"(a) setup and mesh: {mesh.n_cells:,} {mesh.element} elements, {mesh.n_dofs:,} DOF")
    _mesh_lines(ax2, mesh, lw=0.2)
    w = min(1.5, max(band, 0.5))
    ax2.set(xlim=(-w, w), ylim=(g.H - 0.45 * w, g.H + 0.05 * w), aspect="equal", xlabel=r"$X\,/\,L_0$", ylabel=r"$Y\,/\,L_0$",
            title=fr"(b) zoom on the contact band (surface elements {mesh.info.get('h0', float('nan')):g} $L_0$ wide)")
    fig.tight_layout()
    return fig


def _read_table(paths):
    import csv

    rows = []
    for path in paths:
        with open(path, newline="") as fh:
            rows += list(csv.DictReader(fh))
    return rows


def _max_abs_error(rows, scene, quantity):
    return float(np.max(np.abs([float(r["rel_error"]) for r in rows if r["scene"] == scene and r["quantity"] == quantity])))


def fig_verification(tables):
    """FE half-width against load for the Hertz and JKR scenes, with the closed forms (from the CSV tables)."""
    rows = _read_table(tables)
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


MODEL_STYLE = {("DI", None): (BLUE, "-", r"DI, $g_\mathrm{cut} = g_\mathrm{max}$"),
               ("EA", 1.0): (ORANGE, "--", r"EA, $s_\mathrm{cut} = 1$"),
               ("EA", 0.0): (PURPLE, "-.", r"EA, $s_\mathrm{cut} = 0$ (Coulomb)")}


def _case_style(model: str, s_cut: float):
    key = (model, None if model != "EA" else float(s_cut))
    return MODEL_STYLE.get(key, ("0.3", ":", f"{model}, s_cut = {s_cut:g}" if model == "EA" else model))


def _slide_curve(ds, i):
    n = int(ds["n_steps"][i])
    phase = ds["phase"][i, :n].values
    sel = np.flatnonzero(phase == 2)
    return {k: ds[k][i, :n].values[sel] for k in ("ubar", "Ft", "area")}


def fig_cap_PxAndAc(cases, snapshot_ubar=(0.5, 1.0, 1.5, 2.0, 2.5, 3.0, 3.5, 4.0)):
    """f:cap:PxAndAc: Ft and contact area against ubar, one row per preload, the models per panel.

    Only cases that slid to ubar_max are drawn (``slide_end`` = 0).
    """
    if "slide_end" in cases:
        cases = cases.isel(case=np.flatnonzero(cases["slide_end"].values == 0))
    preloads = sorted(set(np.round(cases["preload"].values, 6)))
    fig, axes = plt.subplots(len(preloads), 2, figsize=(DOUBLE_COLUMN, 2.0 * len(preloads) + 0.4), squeeze=False)
    for row, F in zip(axes, preloads):
        for i in np.flatnonzero(np.isclose(cases["preload"].values, F)):
            col, ls, label = _case_style(str(cases["model"][i].values), float(cases["s_cut"][i]))
            c = _slide_curve(cases, i)
            for ax, key in zip(row, ("Ft", "area")):
                ax.plot(c["ubar"], c[key], ls, color=col, label=label)
                onset = float(cases["onset_ubar"][i])
                if np.isfinite(onset):
                    ax.plot(onset, np.interp(onset, c["ubar"], c[key]), "s", color=col, ms=4, mfc="white")
                if str(cases["model"][i].values) == "DI" and abs(F) < 1e-9:
                    su = [u for u in snapshot_ubar if u <= c["ubar"].max()]
                    ax.plot(su, np.interp(su, c["ubar"], c[key]), "o", color=col, ms=2.5)
        kind = "compression" if F < 0 else ("tension" if F > 0 else "zero load")
        row[0].set(ylabel=r"$F_\mathrm{t}\,/\,(E L_0 W)$", title=fr"friction force, {kind}, $F_\mathrm{{n}}^* = {F:g}$")
        row[1].set(ylabel=r"contact area $A\,/\,L_0$", title=fr"contact area, {kind}, $F_\mathrm{{n}}^* = {F:g}$")
    for ax in axes[-1]:
        ax.set_xlabel(r"tangential displacement $\bar{u}\,/\,L_0$")
    handles, labels = axes[0, 0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="lower center", ncol=len(labels), bbox_to_anchor=(0.5, 0.0))
    fig.tight_layout(rect=(0, 0.06, 1, 1))
    return fig


def fig_cap_PxOverAc(cases, tau_DI: float | None = None):
    """f:cap:PxOverAc: contact area against Ft up to the onset of full sliding, all preloads and models."""
    fig, ax = plt.subplots(figsize=(SINGLE_COLUMN, 2.8))
    preloads = sorted(set(np.round(cases["preload"].values, 6)))
    shades = dict(zip(preloads, np.linspace(1.0, 0.45, max(len(preloads), 1))))
    seen = set()
    for i in range(cases.sizes["case"]):
        model, s_cut = str(cases["model"][i].values), float(cases["s_cut"][i])
        col, ls, label = _case_style(model, s_cut)
        c = _slide_curve(cases, i)
        onset = float(cases["onset_ubar"][i])
        keep = c["ubar"] <= (onset if np.isfinite(onset) else np.inf)
        alpha = shades[round(float(cases["preload"][i]), 6)]
        ax.plot(c["Ft"][keep], c["area"][keep], ls, color=col, alpha=alpha, label=None if label in seen else label)
        seen.add(label)
        if np.isfinite(onset):
            ax.plot(float(cases["onset_Ft"][i]), float(cases["onset_area"][i]), "s", color=col, ms=3.5, mfc="white")
    if tau_DI:
        A = np.linspace(0, ax.get_ylim()[1], 10)
        ax.plot(tau_DI * A, A, ":", color="k", lw=0.8, label=r"$F_\mathrm{t} = \tau_\mathrm{DI} A$")
    ax.set(xlabel=r"$F_\mathrm{t}\,/\,(E L_0 W)$", ylabel=r"contact area $A\,/\,L_0$", xlim=(0, None), ylim=(0, None),
           title=f"up to full sliding, preloads {', '.join(f'{F:g}' for F in preloads)}")
    ax.legend(loc="lower right", fontsize=6)
    fig.tight_layout()
    return fig


def _snapshot_geometry(case, k: int):
    """Deformed cell corners (n_cells, 4, 2), I1(sigma)/E per cell and substrate height h of snapshot k."""
    X = np.column_stack([case["X_node"].values, case["Y_node"].values])
    x = X + np.column_stack([case["u_node"][k].values, case["v_node"][k].values])
    corners = x[case["cell_nodes"].values[:, :4]]
    ubar = float(case["snapshot_ubar"][k])
    slide = np.flatnonzero(case["phase"].values == 2)
    steps = slide if slide.size else np.arange(case.sizes["step"])
    step = int(steps[np.argmin(np.abs(case["ubar"].values[steps] - ubar))])
    return corners, case["I1_sigma"][k].values, float(case["h"][step]), step


def _cells_in_window(corners, xlim, ylim):
    """Cells whose bounding box overlaps the window (so the window is filled to its edges)."""
    lo, hi = corners.min(axis=1), corners.max(axis=1)
    return (hi[:, 0] >= xlim[0]) & (lo[:, 0] <= xlim[1]) & (hi[:, 1] >= ylim[0]) & (lo[:, 1] <= ylim[1])


def _stress_cells(ax, corners, I1, norm, **kw):
    from matplotlib.collections import PolyCollection

    pc = PolyCollection(corners, array=I1, cmap="RdBu_r", norm=norm, edgecolors="face", linewidths=0.05, rasterized=True, **kw)
    ax.add_collection(pc)
    return pc


def _substrate(ax, h, xlim, thickness):
    from matplotlib.patches import Rectangle

    ax.add_patch(Rectangle((xlim[0] - 1, h), xlim[1] - xlim[0] + 2, thickness, facecolor="0.85", edgecolor="none", zorder=0))
    ax.axhline(h, color="0.3", lw=0.6, zorder=1)


def _symmetric_norm(values):
    from matplotlib.colors import TwoSlopeNorm

    vmax = float(np.nanpercentile(np.abs(values), 99.5)) if values.size else 1.0
    return TwoSlopeNorm(vcenter=0.0, vmin=-max(vmax, 1e-12), vmax=max(vmax, 1e-12))


def fig_cap_Aczoom(case, stretch: float = 3.93, panels=(0.5, 1.0, 1.5, 2.0, 2.5, 3.0, 3.5, 4.0)):
    """f:cap:Aczoom: the contact interface at the snapshots ubar = 0.5 ... 4.0 L0 (vertical axis stretched).

    Cap frame (base fixed, substrate moved by ubar in +x); cells coloured by
    I1(sigma)/E; the ubar = 0 configuration in orange behind, its surface as an
    orange line; the substrate in grey above y = h.
    """
    snaps = case["snapshot_ubar"].values
    ks = [int(np.argmin(np.abs(snaps - u))) for u in panels if np.min(np.abs(snaps - u)) < 1e-9]
    if not ks:
        raise ValueError(f"no snapshots at ubar = {', '.join(f'{u:g}' for u in panels)} in the case file")
    k0 = int(np.argmin(np.abs(snaps))) if np.min(np.abs(snaps)) < 1e-9 else None
    s0 = int(np.flatnonzero(case["phase"].values == 2)[0]) if np.any(case["phase"].values == 2) else 0
    half = 0.5 * float(case["area"][s0])
    xc = 0.5 * (float(case["x_left"][s0]) + float(case["x_right"][s0]))
    xlim = (xc - 1.4 * max(half, 0.5), xc + 1.4 * max(half, 0.5))
    depth = (xlim[1] - xlim[0]) / (1.35 * stretch)  # panels about 4:3 on paper
    geo = [_snapshot_geometry(case, k) for k in ks]
    h_ref = geo[0][2]
    ylim = (h_ref - depth, h_ref + 0.12 * depth)
    picked = [_cells_in_window(c, xlim, ylim) for c, _, _, _ in geo]
    norm = _symmetric_norm(np.concatenate([I1[m] for (_, I1, _, _), m in zip(geo, picked)]))
    ncol = min(4, len(ks))
    nrow = -(-len(ks) // ncol)
    panel_w = 0.9 * DOUBLE_COLUMN / 4
    panel_h = panel_w * stretch * (ylim[1] - ylim[0]) / (xlim[1] - xlim[0])
    fig, axes = plt.subplots(nrow, ncol, figsize=(DOUBLE_COLUMN, nrow * (panel_h + 0.3) + 0.45), squeeze=False,
                             sharex=True, sharey=True)
    x0 = y0 = None
    if k0 is not None:
        c0, _, _, _ = _snapshot_geometry(case, k0)
        c0 = c0[_cells_in_window(c0, xlim, ylim)]
        x0, y0 = case["x_surface"][s0].values, case["y_surface"][s0].values
    pc = None
    for ax, k, (corners, I1, h, _), m in zip(axes.flat, ks, geo, picked):
        _substrate(ax, h, xlim, depth)
        if k0 is not None:
            from matplotlib.collections import PolyCollection

            ax.add_collection(PolyCollection(c0, facecolors=ORANGE, edgecolors="none", alpha=0.35, rasterized=True))
        pc = _stress_cells(ax, corners[m], I1[m], norm)
        if x0 is not None:
            ax.plot(x0, y0, "-", color=ORANGE, lw=0.8)
        ax.set(xlim=xlim, ylim=ylim, aspect=stretch)
        ax.text(0.03, 0.06, fr"$\bar{{u}} = {float(snaps[k]):.1f}\,L_0$", transform=ax.transAxes, fontsize=7,
                bbox=dict(facecolor="white", edgecolor="none", pad=1, alpha=0.8))
    for ax in axes.flat[len(ks):]:
        ax.set_visible(False)
    for ax in axes[-1]:
        ax.set_xlabel(r"$x\,/\,L_0$")
    for ax in axes[:, 0]:
        ax.set_ylabel(r"$y\,/\,L_0$")
    fig.suptitle(fr"contact interface during sliding, vertical axis stretched by {stretch:g} "
                 r"(orange: $\bar{u} = 0$)", fontsize=8)
    fig.tight_layout(rect=(0, 0, 0.92, 1))
    cax = fig.add_axes((0.93, 0.15, 0.012, 0.7))
    fig.colorbar(pc, cax=cax, label=r"$I_1(\sigma)\,/\,E$")
    return fig


def fig_cap_xn(case, ubar: float | None = None):
    """f:cap:xn: I1(sigma)/E over the deformed cap during sliding, with a zoom on the contact (true scale).

    ``ubar`` picks the snapshot; default: the last one before the onset of full sliding.
    """
    snaps = case["snapshot_ubar"].values
    if snaps.size == 0:
        raise ValueError("the case file holds no field snapshots")
    if ubar is None:
        onset = float(case["onset_ubar"])
        before = snaps[(snaps > 0) & (snaps <= onset)] if np.isfinite(onset) else snaps[snaps > 0]
        ubar = float(before.max()) if before.size else float(snaps.max())
    k = int(np.argmin(np.abs(snaps - ubar)))
    corners, I1, h, step = _snapshot_geometry(case, k)
    fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(DOUBLE_COLUMN, 4.6), gridspec_kw={"height_ratios": [1.0, 1.1]})
    lo, hi = corners[..., 0].min(), corners[..., 0].max()
    xlim1 = (lo - 0.5, hi + 0.5)
    half = 0.5 * float(case["area"][step])
    xc = 0.5 * (float(case["x_left"][step]) + float(case["x_right"][step]))
    w = 1.6 * max(half, 0.5)
    xlim2, ylim2 = (xc - w, xc + w), (h - 0.55 * w, h + 0.08 * w)
    zoom = _cells_in_window(corners, xlim2, ylim2)
    norm = _symmetric_norm(I1[zoom])
    for ax, cells, xlim, ylim in ((ax1, np.ones(len(I1), bool), xlim1, (-0.5, h + 1.5)), (ax2, zoom, xlim2, ylim2)):
        _substrate(ax, h, xlim, 0.2 * (ylim[1] - ylim[0]) + 2.0)
        pc = _stress_cells(ax, corners[cells], I1[cells], norm)
        ax.set(xlim=xlim, ylim=ylim, aspect="equal", xlabel=r"$x\,/\,L_0$", ylabel=r"$y\,/\,L_0$")
    from matplotlib.patches import Rectangle

    ax1.add_patch(Rectangle((xlim2[0], ylim2[0]), xlim2[1] - xlim2[0], ylim2[1] - ylim2[0], fill=False, ec="k", lw=0.6))
    Fn = round(float(case["Fn"][step]), 6)
    ax1.set_title(fr"(a) deformed cap at $\bar{{u}} = {float(snaps[k]):g}\,L_0$, $F_\mathrm{{n}}^* = {Fn + 0.0:+.3f}$, "
                  fr"$F_\mathrm{{t}} = {float(case['Ft'][step]):.3g}\,E L_0 W$")
    ax2.set_title("(b) zoom on the contact (true scale)")
    fig.colorbar(pc, ax=[ax1, ax2], label=r"$I_1(\sigma)\,/\,E$ (colour range from the zoom)", shrink=0.8,
                 extend="both")
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


MESH_FIGURES: dict[str, Callable] = {"cap_setup": fig_cap_setup}
CASES_FIGURES: dict[str, Callable] = {"cap_PxAndAc": fig_cap_PxAndAc, "cap_PxOverAc": fig_cap_PxOverAc}
TABLE_FIGURES: dict[str, Callable] = {"verification": fig_verification}
CASE_FIGURES: dict[str, Callable] = {"cap_Aczoom": fig_cap_Aczoom, "cap_xn": fig_cap_xn}

MODEL_FIGURES: dict[str, Callable] = {
    "Tn": fig_Tn,
    "modelCA": fig_modelCA,
    "modelAM": fig_modelAM,
    "TnTt": fig_TnTt,
    "exp_FnJKR": fig_exp_FnJKR,
}
