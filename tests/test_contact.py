"""Contact laws: exact derivatives against central finite differences, limits, return map."""

import numpy as np
import pytest

from capslide.laws import contact
from capslide.params import cgcm_constants

# Several parameter sets, not only the paper's: (T_max, W_adh, g_reg / g_eq)
PARAMETER_SETS = [(0.165, 0.0135, 1.0), (1.0, 0.3, 0.5), (0.02, 0.01, 1.15), (2.5, 0.05, 0.8)]


def _central_difference(f, g, h):
    return (f(g + h) - f(g - h)) / (2 * h)


def _assert_derivative(f, g, rtol=1e-6):
    value, deriv = f(g)
    h = 1e-6 * np.maximum(np.abs(g), 1e-3)
    fd = _central_difference(lambda x: f(x)[0], g, h)
    scale = np.max(np.abs(deriv)) + 1e-300
    np.testing.assert_allclose(deriv, fd, rtol=rtol, atol=rtol * scale)


def _gaps_avoiding(c, points, n=400, lo=-0.5, hi=4.0):
    """Gaps in [lo r0, hi r0] on both sides of the given points, not within 1e-4 r0 of them."""
    g = np.linspace(lo, hi, n) * c["r0"]
    for p in points:
        g = g[np.abs(g - p) > 1e-4 * c["r0"]]
    return g


@pytest.mark.parametrize("T_max, W_adh, reg", PARAMETER_SETS)
def test_normal_traction_derivative(T_max, W_adh, reg):
    c = cgcm_constants(T_max, W_adh)
    g_reg = reg * c["g_eq"]
    g = _gaps_avoiding(c, [g_reg])
    _assert_derivative(lambda x: contact.normal_traction(x, c["T0"], c["r0"], g_reg), g)
    assert np.sum(g < g_reg) > 50 and np.sum(g > g_reg) > 50


@pytest.mark.parametrize("T_max, W_adh, reg", PARAMETER_SETS)
def test_normal_traction_regularization(T_max, W_adh, reg):
    c = cgcm_constants(T_max, W_adh)
    g_reg = reg * c["g_eq"]
    f = lambda x: contact.normal_traction(x, c["T0"], c["r0"], g_reg)  # noqa: E731
    # continuous with continuous slope at g_reg; finite and repulsive at and below zero gap
    below, above = f(g_reg * (1 - 1e-9)), f(g_reg * (1 + 1e-9))
    assert below[0] == pytest.approx(above[0], rel=1e-6, abs=1e-6 * c["T0"])
    assert below[1] == pytest.approx(above[1], rel=1e-6)
    Tn0, dTn0 = f(np.array([-c["r0"], 0.0]))
    assert np.all(np.isfinite(Tn0)) and np.all(Tn0 > 0) and np.all(dTn0 < 0)
    # unchanged above g_reg
    g = np.linspace(g_reg, 5 * c["r0"], 50)
    np.testing.assert_array_equal(f(g)[0], contact.normal_traction_unregularized(g, c["T0"], c["r0"])[0])


@pytest.mark.parametrize("T_max, W_adh, reg", PARAMETER_SETS)
@pytest.mark.parametrize("k_r0", [10.0, 50.0, 500.0])
def test_di_threshold(T_max, W_adh, reg, k_r0):
    c = cgcm_constants(T_max, W_adh)
    tau, g_cut, k = 0.7 * T_max, c["g_max"], k_r0 / c["r0"]
    f = lambda x: contact.di_threshold(x, tau, k, g_cut)  # noqa: E731
    _assert_derivative(f, _gaps_avoiding(c, []), rtol=1e-5)
    assert f(g_cut)[0] == pytest.approx(tau / 2, rel=1e-14)
    far, close = f(np.array([1e3 * c["r0"], -1e3 * c["r0"]]))[0]
    assert far == 0.0 and close == pytest.approx(tau)  # no overflow far away


@pytest.mark.parametrize("T_max, W_adh, reg", PARAMETER_SETS)
@pytest.mark.parametrize("s_cut", [0.0, 0.3, 0.5, 1.0])
def test_ea_threshold(T_max, W_adh, reg, s_cut):
    c = cgcm_constants(T_max, W_adh)
    g_reg, mu = reg * c["g_eq"], 0.6
    g_cut = contact.ea_g_cut(s_cut, c["g_eq"], c["g_max"])
    f = lambda x: contact.ea_threshold(x, mu, g_cut, c["T0"], c["r0"], g_reg)  # noqa: E731
    _assert_derivative(f, _gaps_avoiding(c, [g_reg, g_cut]))
    g = np.linspace(-0.5, 4, 1000) * c["r0"]
    T, _ = f(g)
    assert np.all(T >= 0.0) and np.all(T[g >= g_cut] == 0.0)
    assert f(g_cut)[0] == 0.0 and f(g_cut * (1 - 1e-9))[0] == pytest.approx(0.0, abs=1e-6 * T_max)


def test_ea_scut0_is_coulomb():
    c = cgcm_constants(0.165, 0.0135)
    mu = 0.4
    g = np.linspace(-0.5, 4, 2001) * c["r0"]
    Tn, _ = contact.normal_traction(g, c["T0"], c["r0"], c["g_eq"])
    T, _ = contact.ea_threshold(g, mu, c["g_eq"], c["T0"], c["r0"], c["g_eq"])
    np.testing.assert_allclose(T, mu * np.maximum(Tn, 0.0), rtol=1e-12, atol=1e-13 * c["T0"])


def test_ea_scut1_is_smooth_at_g_cut():
    c = cgcm_constants(0.165, 0.0135)
    T, dT = contact.ea_threshold(c["g_max"] * (1 - 1e-7), 1.0, c["g_max"], c["T0"], c["r0"], c["g_eq"])
    assert abs(dT) < 1e-5 * c["T0"] / c["r0"]  # C1: Tn'(g_max) = 0


def test_return_map():
    rng = np.random.default_rng(1)
    trial = rng.normal(size=1000)
    thr = rng.uniform(0.0, 1.5, size=1000)
    T, slip, dT_dtrial, dT_dthr = contact.return_map(trial, thr)
    stick = ~slip
    assert stick.any() and slip.any()
    np.testing.assert_array_equal(T[stick], trial[stick])
    np.testing.assert_array_equal(np.abs(T[slip]), thr[slip])
    np.testing.assert_array_equal(np.sign(T[slip]), np.sign(trial[slip]))
    assert np.all(np.abs(T) <= thr + 0.0)
    # derivatives against finite differences away from the switch
    h = 1e-7
    away = np.abs(np.abs(trial) - thr) > 1e-4
    fd_trial = (contact.return_map(trial + h, thr)[0] - contact.return_map(trial - h, thr)[0]) / (2 * h)
    fd_thr = (contact.return_map(trial, thr + h)[0] - contact.return_map(trial, thr - h)[0]) / (2 * h)
    np.testing.assert_allclose(dT_dtrial[away], fd_trial[away], atol=1e-7)
    np.testing.assert_allclose(dT_dthr[away], fd_thr[away], atol=1e-7)
    # zero threshold: never sticks unless the trial is zero
    T0, slip0, *_ = contact.return_map(np.array([0.3, -0.2]), np.zeros(2))
    np.testing.assert_array_equal(T0, 0.0)
    assert slip0.all()


@pytest.mark.parametrize("ratio", [1.0, 1.5])
def test_weakening_return_map_branches_and_derivatives(ratio):
    """Stick, weakening and kinetic slip of the slip-weakening return map: values against the closed forms, the
    traction against the threshold of its new slip, derivatives against finite differences; ratio 1 is the plain
    map."""
    D_c, eps = 0.1, 100.0
    kin = np.full(6, 0.2)
    slip = np.array([0.0, 0.0, 0.02, 0.05, 0.09, 0.2])
    trial = np.array([0.25, -0.31, 0.33, -0.5, 0.9, 0.21])
    T, slipping, dT_dtrial, dT_dkin = contact.weakening_return_map(trial, kin, slip, ratio, D_c, eps)
    m = lambda s: ratio - (ratio - 1.0) * np.minimum(s, D_c) / D_c  # noqa: E731
    stick = np.abs(trial) <= m(slip) * kin
    np.testing.assert_array_equal(slipping, ~stick)
    np.testing.assert_array_equal(T[stick], trial[stick])
    new_slip = slip + np.abs(trial - T) / eps
    np.testing.assert_allclose(np.abs(T[~stick]), (m(new_slip) * kin)[~stick], rtol=1e-12)  # on the new threshold
    if ratio == 1.0:
        plain = contact.return_map(trial, kin)
        for got, want in zip((T, slipping, dT_dtrial, dT_dkin), plain):
            np.testing.assert_allclose(got, want, rtol=1e-15)
    else:
        assert stick.any() and (~stick & (new_slip < D_c)).any() and (~stick & (new_slip > D_c)).any()
    h = 1e-7
    fd_trial = (contact.weakening_return_map(trial + h, kin, slip, ratio, D_c, eps)[0]
                - contact.weakening_return_map(trial - h, kin, slip, ratio, D_c, eps)[0]) / (2 * h)
    fd_kin = (contact.weakening_return_map(trial, kin + h, slip, ratio, D_c, eps)[0]
              - contact.weakening_return_map(trial, kin - h, slip, ratio, D_c, eps)[0]) / (2 * h)
    np.testing.assert_allclose(dT_dtrial, fd_trial, atol=1e-7)
    np.testing.assert_allclose(dT_dkin, fd_kin, atol=1e-7)


def test_weakening_faster_than_the_penalty_has_no_local_solution():
    T, *_ = contact.weakening_return_map(np.array([7.0, 0.1]), np.array([3.0, 3.0]), np.zeros(2), 2.0, 0.01, 100.0)
    assert np.isnan(T[0]) and T[1] == 0.1  # 1 - c kinetic = 1 - 3/1 < 0 where it slips; the sticking point is fine


@pytest.mark.parametrize("g_far", [np.inf, 2.0])
def test_normal_potential_is_the_integral_of_the_traction(paper, g_far):
    """-dphi/dg = Tn on both sides of g_reg, phi(inf) = 0 (or 0 beyond g_far), and the work of adhesion W_adh =
    -phi(g_eq) without regularization below g_eq (paper eq. Wadh)."""
    a = paper.adhesion
    g = np.array([-0.05, 0.5 * a.g_reg, 0.999 * a.g_reg, 1.001 * a.g_reg, a.g_eq, a.g_max, 0.5, 1.5, 1.9])
    h = 1e-7
    fd = -(contact.normal_potential(g + h, a.T0, a.r0, a.g_reg, g_far)
           - contact.normal_potential(g - h, a.T0, a.r0, a.g_reg, g_far)) / (2 * h)
    Tn, _ = contact.normal_traction(g, a.T0, a.r0, a.g_reg)
    np.testing.assert_allclose(fd, Tn, rtol=1e-6, atol=1e-8)
    assert contact.normal_potential(1e6 if np.isinf(g_far) else 2.5, a.T0, a.r0, a.g_reg, g_far) == pytest.approx(0.0, abs=1e-12)
    if np.isinf(g_far):
        assert -contact.normal_potential(a.g_eq, a.T0, a.r0, 0.5 * a.g_eq) == pytest.approx(a.W_adh, rel=1e-12)
