"""Verification rows: how errors are scaled, and the figure drawn from the CSV tables."""

import csv
import math

import pytest

from capslide import analytic, figures
from capslide.verification import VerificationRow

R, E_STAR, W = 200.0, 1.0 / 0.84, 0.013478


def test_half_width_error_is_relative_to_the_closed_form():
    row = VerificationRow("jkr", "half_width", 0.0, 16.0, 16.5)
    assert row.rel_error == pytest.approx(-0.5 / 16.5)


def test_load_error_near_zero_load_is_relative_to_the_pull_off_load():
    """At P = 0 the JKR load at the FE half-width is small; the error is scaled by |P_c| instead."""
    P_c = analytic.jkr_cylinder_pull_off(R, E_STAR, W)
    a0 = analytic.jkr_cylinder_half_width(0.0, R, E_STAR, W)
    P_a = float(analytic.jkr_cylinder_load(0.97 * a0, R, E_STAR, W))
    row = VerificationRow("jkr", "load_at_half_width", 0.0, 0.0, P_a, {"relative_to": max(abs(P_a), abs(P_c))})
    assert abs(P_a) < abs(P_c)
    assert row.rel_error == pytest.approx(-P_a / abs(P_c))
    # P = c1 a^2 - c2 sqrt(a) with c1 a0^2 = c2 sqrt(a0) and a_c = 4^(-2/3) a0: 3 % short of a0 is 9.3 % of |P_c|
    expected = (0.97**0.5 - 0.97**2) / (4 ** (-1 / 3) - 4 ** (-4 / 3))
    assert row.rel_error == pytest.approx(expected, rel=1e-9)
    assert 0.09 < expected < 0.095


def test_pressure_row_without_scale_is_nan():
    assert math.isnan(VerificationRow("hertz", "pressure_L2", 0.3, 0.02, 0.0).rel_error)


def test_verification_figure_from_tables(tmp_path):
    P_c = analytic.jkr_cylinder_pull_off(R, E_STAR, W)
    rows = []
    for P in (0.3, 0.0, -0.3):
        a = analytic.jkr_cylinder_half_width(P, R, E_STAR, W)
        rows.append(["jkr", "half_width", P, 0.98 * a, a, -0.02, f"R={R};E_star={E_STAR};w={W}"])
        rows.append(["jkr", "load_at_half_width", P, P, float(analytic.jkr_cylinder_load(0.98 * a, R, E_STAR, W)), 0.05, ""])
        h = float(analytic.hertz_line_half_width(P + 0.5, R, E_STAR))
        rows.append(["hertz", "half_width", P + 0.5, 0.99 * h, h, -0.01, ""])
        rows.append(["hertz", "pressure_L2", P + 0.5, 0.02 + 0.01 * P, 0.0, "nan", ""])
    rows.append(["jkr", "pull_off", P_c, P_c * 1.003, P_c, -0.003, "status=diverged"])
    table = tmp_path / "v.csv"
    with open(table, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["scene", "quantity", "load_P", "fe", "theory", "rel_error", "extra"])
        w.writerows(rows)
    with figures.journal_style():
        fig = figures.fig_verification([table])
    titles = [ax.get_title() for ax in fig.axes]
    assert "a 1.00%" in titles[0] and "p(x) 2.30%" in titles[0] and "P(a)" not in titles[0]
    assert "a 2.00%" in titles[1] and "P(a) 5.00%" in titles[1]
    out = [tmp_path / "v.pdf", tmp_path / "v.png"]
    figures.save(fig, out)
    assert all(p.stat().st_size > 5000 for p in out)
