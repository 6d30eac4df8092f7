"""Hertz and JKR closed forms against independently derived numbers."""

import math

import numpy as np
import pytest
from scipy.integrate import quad

from capslide.laws import analytic

R, E_star, w = 47.1, 1 / (1 - 0.4**2), 0.0135


def test_hertz_line_consistency():
    P = 0.37
    a = analytic.hertz_line_half_width(P, R, E_star)
    assert analytic.hertz_line_load(a, R, E_star) == pytest.approx(P, rel=1e-14)
    # the pressure integrates to the load, its peak is 2P / (pi a)
    total, _ = quad(lambda x: analytic.hertz_line_pressure(x, P, R, E_star), -a, a, epsabs=0, epsrel=1e-12)
    assert total == pytest.approx(P, rel=1e-9)
    assert analytic.hertz_line_pressure(0.0, P, R, E_star) == pytest.approx(2 * P / (math.pi * a), rel=1e-14)
    assert analytic.hertz_line_pressure(1.01 * a, P, R, E_star) == 0.0
    # independent number: E* = 1, R = 1, P = pi  ->  a = 2
    assert analytic.hertz_line_half_width(math.pi, 1.0, 1.0) == pytest.approx(2.0, rel=1e-15)


@pytest.mark.parametrize("R_, E_, w_", [(47.1, 1 / 0.84, 0.0135), (1.0, 1.0, 1.0), (3.0, 0.2, 5.0)])
def test_jkr_cylinder_pull_off_nondimensional(R_, E_, w_):
    unit = (math.pi * E_ * w_**2 * R_) ** (1 / 3)
    assert analytic.jkr_cylinder_pull_off(R_, E_, w_) / unit == pytest.approx(-0.75 * 4 ** (1 / 3), rel=1e-12)
    assert -0.75 * 4 ** (1 / 3) == pytest.approx(-1.1906, abs=5e-5)
    # the pull-off is the minimum of P(a)
    a = np.linspace(1e-6, 10, 200001) * analytic.jkr_cylinder_critical_half_width(R_, E_, w_)
    assert analytic.jkr_cylinder_load(a, R_, E_, w_).min() >= analytic.jkr_cylinder_pull_off(R_, E_, w_) * (1 + 1e-12)


def test_jkr_cylinder_branches():
    a_c = analytic.jkr_cylinder_critical_half_width(R, E_star, w)
    P_c = analytic.jkr_cylinder_pull_off(R, E_star, w)
    for P in [0.5 * P_c, 0.9 * P_c, 0.999 * P_c]:
        a_s = analytic.jkr_cylinder_half_width(P, R, E_star, w, "stable")
        a_u = analytic.jkr_cylinder_half_width(P, R, E_star, w, "unstable")
        assert a_u < a_c < a_s
        for a in (a_s, a_u):
            assert analytic.jkr_cylinder_load(a, R, E_star, w) == pytest.approx(P, rel=1e-10)
    for P in [0.0, 0.2, 3.0]:
        a = analytic.jkr_cylinder_half_width(P, R, E_star, w)
        assert analytic.jkr_cylinder_load(a, R, E_star, w) == pytest.approx(P, abs=1e-12)
    # zero load: pi E* a / (4R) a = sqrt(2 pi E* w a)  ->  a0 = (32 w R^2 / (pi E*))^(1/3)
    a0 = analytic.jkr_cylinder_half_width(0.0, R, E_star, w)
    assert a0 == pytest.approx((32 * w * R**2 / (math.pi * E_star)) ** (1 / 3), rel=1e-12)
    # no adhesion: Hertz
    assert analytic.jkr_cylinder_half_width(0.3, R, E_star, 0.0) == pytest.approx(analytic.hertz_line_half_width(0.3, R, E_star))
    with pytest.raises(ValueError):
        analytic.jkr_cylinder_half_width(1.01 * P_c, R, E_star, w)
    with pytest.raises(ValueError):
        analytic.jkr_cylinder_half_width(0.1, R, E_star, w, "unstable")


def test_jkr_sphere():
    Rs, Es, ws = 9.42e-3, 1.6e6 / 0.75, 0.027
    assert analytic.jkr_sphere_pull_off(Rs, Es, ws) == pytest.approx(-1.5 * math.pi * ws * Rs, rel=1e-12)
    P_c = analytic.jkr_sphere_pull_off(Rs, Es, ws)
    for P in [0.5 * P_c, 0.0, 5e-3]:
        a = analytic.jkr_sphere_radius(P, Rs, Es, ws)
        assert analytic.jkr_sphere_load(a, Rs, Es, ws) == pytest.approx(P, abs=1e-12)
    a_u = analytic.jkr_sphere_radius(0.5 * P_c, Rs, Es, ws, "unstable")
    assert a_u < analytic.jkr_sphere_critical_radius(Rs, Es, ws)
    assert analytic.jkr_sphere_load(a_u, Rs, Es, ws) == pytest.approx(0.5 * P_c, rel=1e-10)
    # zero load: a0^3 = 9 pi w R^2 / (2 E*)  (JKR 1971 with P = 0)
    a0 = analytic.jkr_sphere_radius(0.0, Rs, Es, ws)
    assert a0**3 == pytest.approx(4.5 * math.pi * ws * Rs**2 / Es, rel=1e-10)
    # Hertz sphere without adhesion: a^3 = 3 P R / (4 E*)
    assert analytic.jkr_sphere_radius(1e-3, Rs, Es, 0.0) ** 3 == pytest.approx(3e-3 * Rs / (4 * Es), rel=1e-10)


def test_maugis_parameter_scaling():
    lam = analytic.maugis_parameter_cylinder(R, E_star, w, 0.165)
    # doubling sigma0 doubles lambda; lambda ~ R^(1/3)
    assert analytic.maugis_parameter_cylinder(R, E_star, w, 0.33) == pytest.approx(2 * lam)
    assert analytic.maugis_parameter_cylinder(8 * R, E_star, w, 0.165) == pytest.approx(2 * lam)
