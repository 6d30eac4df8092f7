"""Model figures draw the laws they name (curve data against the laws), and save as real PDF and PNG files."""

import numpy as np
import pytest

from capslide import figures
from capslide.figures.experiment import PDMS_SPHERE
from capslide.laws import analytic, contact


def _line(ax, label):
    return next(line for line in ax.get_lines() if line.get_label() == label)


def _lines(ax):
    """The plotted curves of an axis (more than a few points; markers and reference lines left out)."""
    return [line for line in ax.get_lines() if len(line.get_xdata()) > 10]


def test_Tn_draws_the_cgcm_law_and_its_regularization(paper):
    a = paper.adhesion
    ax = figures.MODEL_FIGURES["Tn"](paper).axes[0]
    law = _line(ax, r"$T_\mathrm{n}(g_\mathrm{n})$")
    g = np.asarray(law.get_xdata()) * a.r0
    np.testing.assert_allclose(law.get_ydata(), contact.normal_traction_unregularized(g, a.T0, a.r0)[0] / a.T0, rtol=1e-12)
    reg = _line(ax, r"regularized, $g_\mathrm{n} < g_\mathrm{reg}$")
    g = np.asarray(reg.get_xdata()) * a.r0
    assert g.max() == pytest.approx(a.g_reg) and g.min() == 0.0
    np.testing.assert_allclose(reg.get_ydata(), contact.normal_traction(g, a.T0, a.r0, a.g_reg)[0] / a.T0, rtol=1e-12)
    eq, mx = _line(ax, r"$g_\mathrm{eq}$ ($T_\mathrm{n} = 0$)"), _line(ax, r"$g_\mathrm{max}$")
    assert (eq.get_xdata()[0], eq.get_ydata()[0]) == pytest.approx((a.g_eq / a.r0, 0.0), abs=1e-12)
    assert (mx.get_xdata()[0], mx.get_ydata()[0]) == pytest.approx((a.g_max / a.r0, -a.T_max / a.T0), rel=1e-12)


def test_modelCA_draws_the_DI_logistic_and_its_return_maps(paper):
    a, f = paper.adhesion, paper.friction
    tau, g_cut = 0.5 * a.T_max, 1.1 * a.r0  # the caption's illustration values
    fig = figures.MODEL_FIGURES["modelCA"](paper)
    logistic = next(line for line in fig.axes[0].get_lines() if line.get_label().startswith("logistic"))
    g = np.asarray(logistic.get_xdata()) * a.r0
    np.testing.assert_allclose(logistic.get_ydata(), contact.di_threshold(g, tau, f.k_DI, g_cut)[0] / a.T0, rtol=1e-12)
    plateaus = sorted(np.max(np.abs(line.get_ydata())) for line in _lines(fig.axes[1]))
    expected = sorted(contact.di_threshold(gm, tau, f.k_DI, g_cut)[0] / a.T0 for gm in (a.g_eq, a.g_max, 1.2 * g_cut))
    np.testing.assert_allclose(plateaus, expected, rtol=1e-9)


@pytest.mark.parametrize("row, s_cut", [(0, 0.0), (1, 0.5), (2, 1.0)])
def test_modelAM_draws_the_EA_threshold_of_each_s_cut(paper, row, s_cut):
    a = paper.adhesion
    fig = figures.MODEL_FIGURES["modelAM"](paper)
    ax = fig.axes[2 * row]
    assert f"= {s_cut:g})" in ax.get_title()
    g_cut = contact.ea_g_cut(s_cut, a.g_eq, a.g_max)
    lines = [_line(ax, r"$T_\mathrm{slide}$"), _line(ax, "regularized")]  # above and below g_reg
    g = np.concatenate([line.get_xdata() for line in lines]) * a.r0
    y = np.concatenate([line.get_ydata() for line in lines])
    np.testing.assert_allclose(y, contact.ea_threshold(g, 0.2, g_cut, a.T0, a.r0, a.g_reg)[0] / a.T0, rtol=1e-12, atol=1e-15)
    assert np.all(y[g >= g_cut] == 0.0) and np.all(y[g < g_cut] > 0)


def test_TnTt_EA_branches_are_lines_of_slope_mu_and_DI_saturates_at_tau(paper):
    """EA: T_slide = mu (Tn - Tn(g_cut)) while sliding, a straight line of slope mu = 0.2 in the (Tn, T) plane;
    DI: the threshold runs up to tau_DI = 0.5 T_max."""
    a = paper.adhesion
    axes = figures.MODEL_FIGURES["TnTt"](paper).axes
    for ax, s_cut in zip(axes[:3], (0.0, 0.5, 1.0)):
        x, y = (np.asarray(v) for v in (_lines(ax)[0].get_xdata(), _lines(ax)[0].get_ydata()))
        x_cut = contact.normal_traction(contact.ea_g_cut(s_cut, a.g_eq, a.g_max), a.T0, a.r0, a.g_reg)[0] / a.T0
        on = y > 0
        assert on.sum() > 100
        np.testing.assert_allclose(y[on], 0.2 * (x[on] - x_cut), rtol=1e-9, atol=1e-12)
    di = _lines(axes[3])[0]
    assert np.max(di.get_ydata()) == pytest.approx(0.5 * a.T_max / a.T0, rel=1e-9)
    assert [ax.get_title()[:3] for ax in axes] == ["(a)", "(b)", "(c)", "(d)"]


def test_exp_FnJKR_draws_the_JKR_sphere_and_its_pull_off(paper):
    e = PDMS_SPHERE
    ax = figures.MODEL_FIGURES["exp_FnJKR"](paper).axes[0]
    nominal = _line(ax, "JKR, nominal parameters")
    area = np.asarray(nominal.get_ydata())  # mm^2
    radius = np.sqrt(area * 1e-6 / np.pi)
    expected = -1e3 * analytic.jkr_sphere_load(radius, e.R, analytic.effective_modulus(e.E, e.nu), e.w)
    np.testing.assert_allclose(nominal.get_xdata(), expected, rtol=1e-12)
    pull_off = _line(ax, "pull-off (load control)")
    P_c = -1e3 * analytic.jkr_sphere_pull_off(e.R, analytic.effective_modulus(e.E, e.nu), e.w)
    assert pull_off.get_xdata()[0] == pytest.approx(P_c, rel=1e-12) and P_c == pytest.approx(1.5e3 * np.pi * e.w * e.R)


@pytest.mark.parametrize("name", list(figures.MODEL_FIGURES))
def test_model_figure_saves_pdf_and_png(name, paper, tmp_path):
    outputs = [tmp_path / f"{name}.pdf", tmp_path / f"{name}.png"]
    with figures.journal_style():
        figures.save(figures.MODEL_FIGURES[name](paper), outputs)
    assert outputs[0].read_bytes()[:5] == b"%PDF-" and b"/FontFile2" in outputs[0].read_bytes()  # TrueType embedded
    assert outputs[1].read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(p.name for p in outputs)  # no temporary left
