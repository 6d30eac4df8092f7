"""Figures of the cap study (Mergel et al. 2019, section 5): f:cap:setup, f:cap:PxAndAc, f:cap:PxOverAc,
f:cap:Aczoom, f:cap:xn; drawn from a mesh file, the collected dataset or one case file."""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np

from ..config import SPHERE_ELEMENTS
from ..fem.mesh import Mesh
from ..params import Parameters
from ..states import Phase
from .style import BLUE, DOUBLE_COLUMN, ORANGE, PURPLE, SINGLE_COLUMN

__all__ = ["fig_cap_setup", "fig_cap_PxAndAc", "fig_cap_PxOverAc", "fig_cap_Aczoom", "fig_cap_xn", "fig_cap_FtOverA"]


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
             bbox={"facecolor": "white", "edgecolor": "none", "pad": 1})
    ax1.add_patch(Rectangle((-b - 4, -1.2), 2 * b + 8, 1.2, facecolor="white", edgecolor="k", lw=0.6, hatch="////"))
    ax1.text(0, -0.6, r"base fixed, $\mathbf{u} = \mathbf{0}$", ha="center", va="center", fontsize=7,
             bbox={"facecolor": "white", "edgecolor": "none", "pad": 1})
    ax1.add_patch(FancyArrowPatch((b - 12, g.H + gap + 3.6), (b - 4, g.H + gap + 3.6), arrowstyle="-|>", mutation_scale=8,
                                  lw=0.8))
    ax1.text(b - 8, g.H + gap + 4.0, r"$\bar{u}$", ha="center", fontsize=8)
    ax1.add_patch(FancyArrowPatch((-6, g.H + gap + 5.5), (-6, g.H + gap + 3.1), arrowstyle="-|>", mutation_scale=8, lw=0.8))
    ax1.text(-5.4, g.H + gap + 4.6, r"$F_\mathrm{n}$ held fixed", fontsize=7)
    ax1.add_patch(Rectangle((-band, g.H - 1.0), 2 * band, 1.25, fill=False, edgecolor=ORANGE, lw=0.8, ls="--"))
    ax1.text(band + 0.5, g.H - 0.6, "contact band", color=ORANGE, fontsize=7)
    ax1.annotate("", xy=(b + 1.5, 0), xytext=(b + 1.5, g.H), arrowprops={"arrowstyle": "<->", "lw": 0.6})
    ax1.text(b + 1.2, 0.3 * g.H, fr"$H = {g.H:g}\,L_0$", va="center", ha="right", fontsize=7)
    ax1.text(-b - 2, 6.0, fr"$R = {g.R:g}\,L_0$" + "\nneo-Hooke,\nplane strain,\n" + fr"$\nu = {p.material.nu:g}$", fontsize=7,
             va="center")
    ax1.set(xlim=(-b - 3, b + 5), ylim=(-1.5, g.H + gap + 6), aspect="equal", xlabel=r"$X\,/\,L_0$", ylabel=r"$Y\,/\,L_0$",
            title=fr"(a) setup and mesh: {mesh.n_cells:,} {mesh.element} elements, {mesh.n_dofs:,} DOF")
    _mesh_lines(ax2, mesh, lw=0.2)
    w = min(1.5, max(band, 0.5))
    ax2.set(xlim=(-w, w), ylim=(g.H - 0.45 * w, g.H + 0.05 * w), aspect="equal", xlabel=r"$X\,/\,L_0$", ylabel=r"$Y\,/\,L_0$",
            title=fr"(b) zoom on the contact band (surface elements {mesh.info.get('h0', float('nan')):g} $L_0$ wide)")
    fig.tight_layout()
    return fig


MODEL_STYLE = {("DI", None): (BLUE, "-", r"DI, $g_\mathrm{cut} = g_\mathrm{max}$"),
               ("EA", 1.0): (ORANGE, "--", r"EA, $s_\mathrm{cut} = 1$"),
               ("EA", 0.0): (PURPLE, "-.", r"EA, $s_\mathrm{cut} = 0$ (Coulomb)")}
PRELOAD_MARKERS = ("v", "s", "o", "D", "^", "P", "X")


def _model_style(cases, model: str):
    """Colour, line style and label of a study model (from its coordinates friction_model and s_cut)."""
    kind = str(cases["friction_model"].sel(model=model).values) if "friction_model" in cases.coords else model
    s_cut = float(cases["s_cut"].sel(model=model)) if "s_cut" in cases.coords else float("nan")
    key = (kind, None if kind != "EA" else s_cut)
    return MODEL_STYLE.get(key, ("0.3", ":", f"{model} ({kind}, s_cut = {s_cut:g})" if kind == "EA" else model))


def _units(cases) -> dict[str, str]:
    """Axis texts of the cube's forces and areas: per unit width W of the 2D cap, the whole sphere's in 3D."""
    if str(cases.attrs.get("mesh_element")) in SPHERE_ELEMENTS:
        return {"Ft": r"$F_\mathrm{t}\,/\,(E L_0^2)$", "area": r"contact area $A\,/\,L_0^2$", "Fn": r"F_\mathrm{n}/E L_0^2"}
    return {"Ft": r"$F_\mathrm{t}\,/\,(E L_0 W)$", "area": r"contact area $A\,/\,L_0$", "Fn": r"F_\mathrm{n}^*"}


def _slide_curve(cases, model: str, preload: float) -> dict[str, np.ndarray]:
    """ubar, Ft and area over the slide of one case of the cube."""
    case = cases.sel(model=model, preload=preload)
    sel = np.flatnonzero(case["phase"].values == Phase.SLIDE)
    return {k: case[k].values[sel] for k in ("ubar", "Ft", "area", *(["Ft_over_area"] if "Ft_over_area" in case else []))}


def _cases(cases, full_slides: bool | None = None):
    """(model, preload) of every case in the cube; only full slides (True) or only onset-only ones (False)."""
    out = []
    for m in cases["model"].values:
        for f in cases["preload"].values:
            end = int(cases["slide_end"].sel(model=m, preload=f))
            if end >= 0 and (full_slides is None or (end == 0) == full_slides):
                out.append((str(m), float(f)))
    return out


def fig_cap_PxAndAc(cases, snapshot_ubar=(0.5, 1.0, 1.5, 2.0, 2.5, 3.0, 3.5, 4.0)):
    """f:cap:PxAndAc: Ft and contact area against ubar, one row per preload, the models per panel.

    Only cases that slid to ubar_max are drawn (``slide_end`` = 0); squares mark the onset of full sliding, dots
    the snapshot positions of DI at zero load.
    """
    full = _cases(cases, full_slides=True)
    preloads = sorted({f for _, f in full})
    units = _units(cases)
    fig, axes = plt.subplots(len(preloads), 2, figsize=(DOUBLE_COLUMN, 2.0 * len(preloads) + 0.4), squeeze=False)
    for row, F in zip(axes, preloads):
        for model in [m for m, f in full if f == F]:
            col, ls, label = _model_style(cases, model)
            c = _slide_curve(cases, model, F)
            onset = float(cases["onset_ubar"].sel(model=model, preload=F))
            for ax, key in zip(row, ("Ft", "area")):
                ax.plot(c["ubar"], c[key], ls, color=col, label=label)
                if np.isfinite(onset):
                    ax.plot(onset, np.interp(onset, c["ubar"], c[key]), "s", color=col, ms=4, mfc="white")
                if label.startswith("DI") and abs(F) < 1e-9:
                    su = [u for u in snapshot_ubar if u <= c["ubar"].max()]
                    ax.plot(su, np.interp(su, c["ubar"], c[key]), "o", color=col, ms=2.5)
        kind = "compression" if F < 0 else ("tension" if F > 0 else "zero load")
        F_text = f"{F:+.3g}" if F else "0"
        row[0].set(ylabel=units["Ft"], title=fr"friction force, {kind}, ${units['Fn']} = {F_text}$")
        row[1].set(ylabel=units["area"], title=fr"contact area, {kind}, ${units['Fn']} = {F_text}$")
    for ax in axes[-1]:
        ax.set_xlabel(r"tangential displacement $\bar{u}\,/\,L_0$")
    handles, labels = axes[0, 0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="lower center", ncol=len(labels), bbox_to_anchor=(0.5, 0.0))
    fig.tight_layout(rect=(0, 0.06, 1, 1))
    return fig


def fig_cap_FtOverA(cases, tau_DI: float | None = None):
    """Ft/A against ubar (the experiment's shear stress over time, the paper's tauTime panel) for the full slides,
    one panel per preload, the models per panel; squares at the onset of full sliding; dotted: tau_DI."""
    full = _cases(cases, full_slides=True)
    preloads = sorted({f for _, f in full})
    fig, axes = plt.subplots(1, len(preloads), figsize=(DOUBLE_COLUMN, 2.5), squeeze=False, sharey=True)
    for ax, F in zip(axes[0], preloads):
        for model in [m for m, f in full if f == F]:
            col, ls, label = _model_style(cases, model)
            c = _slide_curve(cases, model, F)
            ax.plot(c["ubar"], c["Ft_over_area"], ls, color=col, label=label)
            onset = float(cases["onset_ubar"].sel(model=model, preload=F))
            if np.isfinite(onset):
                ax.plot(onset, np.interp(onset, c["ubar"], c["Ft_over_area"]), "s", color=col, ms=4, mfc="white")
        if tau_DI:
            ax.axhline(tau_DI, color="0.5", ls=":", lw=0.8)
            ax.text(0.02, tau_DI, r" $\tau_\mathrm{DI}$", transform=ax.get_yaxis_transform(), va="bottom", fontsize=7)
        kind = "compression" if F < 0 else ("tension" if F > 0 else "zero load")
        ax.set(xlabel=r"tangential displacement $\bar{u}\,/\,L_0$",
               title=fr"{kind}, ${_units(cases)['Fn']} = {F:+.3g}$" if F else fr"zero load, ${_units(cases)['Fn']} = 0$")
    axes[0, 0].set_ylabel(r"mean shear stress $F_\mathrm{t}\,/\,(A\,E)$")
    handles, labels = axes[0, 0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="lower center", ncol=len(labels), bbox_to_anchor=(0.5, 0.0))
    fig.tight_layout(rect=(0, 0.1, 1, 1))
    return fig


def fig_cap_PxOverAc(cases, tau_DI: float | None = None):
    """f:cap:PxOverAc: contact area against Ft up to the onset of full sliding, all preloads and models.

    Models by colour and line style, preloads by the marker at each curve's start (Ft = 0) and its onset (open);
    Coulomb-Amontons (EA, s_cut = 0), which slides at the smallest force, is drawn on top.
    """
    from matplotlib.lines import Line2D

    fig, ax = plt.subplots(figsize=(SINGLE_COLUMN, 3.0))
    preloads = sorted({f for _, f in _cases(cases)})
    marker = {f: PRELOAD_MARKERS[i % len(PRELOAD_MARKERS)] for i, f in enumerate(preloads)}
    seen = {}
    for model, F in _cases(cases):
        col, ls, label = _model_style(cases, model)
        on_top = 3 if "Coulomb" in label else 2
        c = _slide_curve(cases, model, F)
        onset = float(cases["onset_ubar"].sel(model=model, preload=F))
        keep = c["ubar"] <= (onset if np.isfinite(onset) else np.inf)
        (line,) = ax.plot(c["Ft"][keep], c["area"][keep], ls, color=col, lw=1.0, zorder=on_top)
        seen.setdefault(label, line)
        ax.plot(c["Ft"][0], c["area"][0], marker[F], color=col, ms=3.5, zorder=on_top + 1)
        if np.isfinite(onset):
            ax.plot(float(cases["onset_Ft"].sel(model=model, preload=F)),
                    float(cases["onset_area"].sel(model=model, preload=F)), marker[F], color=col, ms=4, mfc="white",
                    zorder=on_top + 1)
    handles, labels = list(seen.values()), list(seen)
    if tau_DI:
        A = np.linspace(0, ax.get_ylim()[1], 10)
        handles += ax.plot(tau_DI * A, A, ":", color="k", lw=0.8, zorder=1)
        labels.append(r"$F_\mathrm{t} = \tau_\mathrm{DI} A$")
    ax.set(xlabel=_units(cases)["Ft"], ylabel=_units(cases)["area"], xlim=(0, None), ylim=(0, None),
           title="contact area against friction force up to full sliding")
    first = ax.legend(handles, labels, loc="lower right", fontsize=5.5)
    ax.add_artist(first)
    keys = [Line2D([], [], ls="none", marker=marker[f], color="0.3", ms=3.5, label=fr"${_units(cases)['Fn']} = {f:+.3g}$")
            for f in preloads]
    # right of the tau A line, above the models' key: the one region no curve of the study crosses
    ax.legend(handles=keys, loc="lower right", bbox_to_anchor=(1.0, 0.27), fontsize=5.5,
              title="preload (filled: start,\nopen: onset)", title_fontsize=5.5)
    fig.tight_layout()
    return fig


def _snapshot_geometry(case, k: int):
    """Deformed cell corners (n_cells, 4, 2), I1(sigma)/E per cell and substrate height h of snapshot k."""
    X = np.column_stack([case["X_node"].values, case["Y_node"].values])
    x = X + np.column_stack([case["u_node"][k].values, case["v_node"][k].values])
    corners = x[case["cell_nodes"].values[:, :4]]
    ubar = float(case["snapshot_ubar"][k])
    slide = np.flatnonzero(case["phase"].values == Phase.SLIDE)
    steps = slide if slide.size else np.arange(case.sizes["step"])
    step = int(steps[np.argmin(np.abs(case["ubar"].values[steps] - ubar))])
    return corners, case["I1_sigma"][k].values, float(case["h"][step]), step


def _deformed_nodes(case, k: int) -> np.ndarray:
    """Node positions (n_nodes, 2) of snapshot k."""
    X = np.column_stack([case["X_node"].values, case["Y_node"].values])
    return X + np.column_stack([case["u_node"][k].values, case["v_node"][k].values])


def _cells_in_window(corners, xlim, ylim):
    """Cells whose bounding box overlaps the window (so the window is filled to its edges)."""
    lo, hi = corners.min(axis=1), corners.max(axis=1)
    return (hi[:, 0] >= xlim[0]) & (lo[:, 0] <= xlim[1]) & (hi[:, 1] >= ylim[0]) & (lo[:, 1] <= ylim[1])


def _stress_cells(ax, corners, I1, norm, **kw):
    from matplotlib.collections import PolyCollection

    pc = PolyCollection(corners, array=I1, cmap="RdBu_r", norm=norm, edgecolors="face", linewidths=0.05, rasterized=True, **kw)
    ax.add_collection(pc)
    return pc


def _stress_smooth(ax, nodes, cells, I1, norm):
    """I1(sigma) over the quadrilateral ``cells`` (corner node ids) as a smooth field: the cell averages averaged at
    the nodes and shaded between them (Gouraud), so the element facets do not show."""
    total, count = np.zeros(len(nodes)), np.zeros(len(nodes))
    np.add.at(total, cells, np.repeat(I1[:, None], cells.shape[1], axis=1))
    np.add.at(count, cells, 1.0)
    nodal = np.divide(total, count, out=np.zeros_like(total), where=count > 0)
    triangles = np.concatenate([cells[:, [0, 1, 2]], cells[:, [0, 2, 3]]])
    return ax.tripcolor(nodes[:, 0], nodes[:, 1], triangles, nodal, shading="gouraud", cmap="RdBu_r", norm=norm,
                        rasterized=True)


def _substrate(ax, h, xlim, thickness):
    from matplotlib.patches import Rectangle

    ax.add_patch(Rectangle((xlim[0] - 1, h), xlim[1] - xlim[0] + 2, thickness, facecolor="0.85", edgecolor="none", zorder=0))
    ax.axhline(h, color="0.3", lw=0.6, zorder=1)


def _symmetric_norm(values):
    from matplotlib.colors import TwoSlopeNorm

    vmax = float(np.nanpercentile(np.abs(values), 99.5)) if values.size else 1.0
    return TwoSlopeNorm(vcenter=0.0, vmin=-max(vmax, 1e-12), vmax=max(vmax, 1e-12))


def _fit_height(fig, axes, rect) -> None:
    """Lay out panels of a fixed aspect, then shrink the figure's height to what they use: no blank band between
    the title and the panels."""
    fig.tight_layout(rect=rect)
    fig.canvas.draw()
    shown = [ax for ax in axes.flat if ax.get_visible()]
    slack = sum(ax.get_position(original=True).height - ax.get_position(original=False).height
                for ax in shown[::axes.shape[1]])  # one panel per row
    height = fig.get_figheight()
    if slack > 0.01:
        fig.set_figheight(height * (1.0 - slack))
        fig.tight_layout(rect=rect)


ACZOOM_UBAR = (0.5, 1.0, 1.5, 2.0, 2.5, 3.0, 3.5, 4.0)  # f:cap:Aczoom's snapshots (L0)


def aczoom_snapshots(snapshot_ubar, panels=ACZOOM_UBAR) -> list[int]:
    """The indices of the snapshots (ubar in L0) that f:cap:Aczoom shows: those at its panels' ubar."""
    snaps = np.asarray(snapshot_ubar, dtype=float)
    return [int(np.argmin(np.abs(snaps - u))) for u in panels if snaps.size and np.min(np.abs(snaps - u)) < 1e-9]


def fig_cap_Aczoom(case, stretch: float = 3.93, panels=ACZOOM_UBAR):
    """f:cap:Aczoom: the contact interface at the snapshots ubar = 0.5 ... 4.0 L0 (vertical axis stretched).

    Cap frame (base fixed, substrate moved by ubar in +x); cells coloured by
    I1(sigma)/E; the ubar = 0 configuration in orange behind, its surface as an
    orange line; the substrate in grey above y = h.
    """
    snaps = case["snapshot_ubar"].values
    ks = aczoom_snapshots(snaps, panels)
    if not ks:
        raise ValueError(f"no snapshots at ubar = {', '.join(f'{u:g}' for u in panels)} in the case file")
    k0 = int(np.argmin(np.abs(snaps))) if np.min(np.abs(snaps)) < 1e-9 else None
    s0 = int(np.flatnonzero(case["phase"].values == Phase.SLIDE)[0]) if np.any(case["phase"].values == Phase.SLIDE) else 0
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
        x0, y0 = case["x_current"][s0].values, case["y_current"][s0].values
    pc = None
    for ax, k, (_, I1, h, _), m in zip(axes.flat, ks, geo, picked):
        _substrate(ax, h, xlim, depth)
        if k0 is not None:
            from matplotlib.collections import PolyCollection

            ax.add_collection(PolyCollection(c0, facecolors=ORANGE, edgecolors="none", alpha=0.35, rasterized=True))
        pc = _stress_smooth(ax, _deformed_nodes(case, k), case["cell_nodes"].values[m, :4], I1[m], norm)
        if x0 is not None:
            ax.plot(x0, y0, "-", color=ORANGE, lw=0.8)
        ax.set(xlim=xlim, ylim=ylim, aspect=stretch)
        ax.text(0.03, 0.06, fr"$\bar{{u}} = {float(snaps[k]):.1f}\,L_0$", transform=ax.transAxes, fontsize=7,
                bbox={"facecolor": "white", "edgecolor": "none", "pad": 1, "alpha": 0.8})
    for ax in axes.flat[len(ks):]:
        ax.set_visible(False)
    for ax in axes[-1]:
        ax.set_xlabel(r"$x\,/\,L_0$")
    for ax in axes[:, 0]:
        ax.set_ylabel(r"$y\,/\,L_0$")
    fig.suptitle(fr"contact interface during sliding, vertical axis stretched by {stretch:g} "
                 r"(orange: $\bar{u} = 0$)", fontsize=8)
    _fit_height(fig, axes, rect=(0, 0, 0.92, 1))
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
    Fn_text = "0" if abs(Fn) < 5e-4 else f"{Fn:+.3g}"
    ax1.set_title(fr"(a) deformed cap at $\bar{{u}} = {float(snaps[k]):g}\,L_0$, $F_\mathrm{{n}}^* = {Fn_text}$, "
                  fr"$F_\mathrm{{t}} = {float(case['Ft'][step]):.3g}\,E L_0 W$")
    ax2.set_title("(b) zoom on the contact (true scale)")
    fig.colorbar(pc, ax=[ax1, ax2], label=r"$I_1(\sigma)\,/\,E$ (colour range from the zoom)", shrink=0.8,
                 extend="both")
    return fig
