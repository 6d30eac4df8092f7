"""The same-law half-space reference of the adhesive sphere (studies/halfspace_sphere.py) against closed forms:
Boussinesq's disk, the Hertz pressure's displacement, the Hertz load of a repulsive law, and the rigid-sphere
(Bradley) pull-off -2 pi W R of any law in the stiff limit."""

import math

import numpy as np
import pytest

from capslide.config import load_config, scene_path
from capslide.laws.normal import CGCMLaw
from capslide.params import Parameters, cgcm_constants
from capslide.studies import halfspace_sphere
from capslide.studies.halfspace_sphere import (
    SphereOnHalfSpace,
    cut_traction,
    disk_displacement,
    pull_off,
    ring_influence,
    same_law_reference,
)

E_STAR = 1.25


def test_disk_displacement_at_the_center_edge_and_far_away():
    """Johnson 1985, section 3.4: 2 p b / E* at the center, 4 p b / (pi E*) at the edge, continuous across it; far
    away the point load's w = F / (pi E* r)."""
    b = 2.0
    assert disk_displacement(0.0, b, E_STAR) == pytest.approx(2.0 * b / E_STAR, rel=1e-12)
    assert disk_displacement(b, b, E_STAR) == pytest.approx(4.0 * b / (math.pi * E_STAR), rel=1e-12)
    assert disk_displacement(b * (1 + 1e-9), b, E_STAR) == pytest.approx(4.0 * b / (math.pi * E_STAR), rel=1e-6)
    r = 1e3 * b
    assert disk_displacement(r, b, E_STAR) == pytest.approx(math.pi * b * b / (math.pi * E_STAR * r), rel=1e-5)
    assert disk_displacement(1.0, 0.0, E_STAR) == 0.0


def test_rings_give_the_hertz_pressure_its_displacement():
    """p = p0 sqrt(1 - r^2 / a^2) moves the surface by pi p0 (2 a^2 - r^2) / (4 a E*) inside a (Johnson 1985,
    section 3.4), to the ring discretization's error."""
    a, dr = 5.0, 0.05
    edges = np.arange(0.0, 3 * a + dr / 2, dr)
    r = 0.5 * (edges[1:] + edges[:-1])
    p = np.sqrt(np.clip(1.0 - (r / a) ** 2, 0.0, None))
    w = ring_influence(r, edges, E_STAR) @ p
    exact = math.pi * (2 * a * a - r**2) / (4 * a * E_STAR)
    inside = r < a
    assert np.max(np.abs(w[inside] - exact[inside])) / exact[0] < 1e-3


def _penalty(g0: float, k: float):
    def traction(g):
        return k * np.maximum(g0 - g, 0.0), np.where(g < g0, -k, 0.0)
    return traction


def test_a_repulsive_law_gives_the_hertz_load():
    """A stiff repulsive law on the paraboloid: P = 4/3 E* R^(1/2) d^(3/2) at the approach d from first touch, and
    a^2 = R d (Hertz; Johnson 1985, eqs. 4.22-4.23). The radius from the ring gaps is first order in the ring
    width: where the law has no tension, the gap is flat inside the edge."""
    R, g0, dr = 100.0, 0.1, 0.02
    halfspace = SphereOnHalfSpace(_penalty(g0, 1e4), R, E_STAR, 12.0, dr, g0, profile="paraboloid")
    for sol in halfspace.edge_path([2.0, 4.0, 6.0]):
        d = sol.delta + g0  # the apex touches (g = g0) at delta = -g0
        assert sol.P == pytest.approx(4.0 / 3.0 * E_STAR * math.sqrt(R) * d**1.5, rel=2e-4), sol.a
        assert abs(sol.a - math.sqrt(R * d)) < dr, sol.a


def test_a_stiff_sphere_pulls_off_at_bradleys_force():
    """Maugis lambda -> 0 (a stiff sphere): the pull-off tends to -2 pi W R whatever the law's shape (Bradley
    1932; the DMT limit of Maugis 1992), here at lambda = 0.002 with the band's cut tail below 0.01 %. Its apex gap
    is then g_eq, and its radius the edge gap's sqrt(2 R (g_max - g_eq))."""
    R, W, T_max = 100.0, 0.0135, 0.015
    c = cgcm_constants(T_max, W)
    traction = cut_traction(CGCMLaw(c["T0"], c["r0"], c["g_eq"]), np.inf)
    halfspace = SphereOnHalfSpace(traction, R, 3000.0, 150.0, 0.2, c["g_max"], profile="paraboloid")
    P_c, a_c = pull_off(halfspace.edge_path(np.arange(1.0, 10.0, 0.5)))
    assert P_c == pytest.approx(-2.0 * math.pi * W * R, rel=1e-3)
    assert a_c == pytest.approx(math.sqrt(2.0 * R * (c["g_max"] - c["g_eq"])), rel=1e-2)


@pytest.mark.slow
def test_the_reference_of_sphere_md3_is_converged_in_its_rings(monkeypatch):
    """Halving the ring width moves the pull-off by less than 1e-5 and P(a) by less than 0.1 % of |P_c|."""
    p = Parameters.from_config(load_config([scene_path("sphere_md3")]))
    ref = same_law_reference(p, 10.0)
    monkeypatch.setattr(halfspace_sphere, "RINGS_PER_ZONE", 2 * halfspace_sphere.RINGS_PER_ZONE)
    finer = same_law_reference(p, 10.0)
    assert ref.P_c == pytest.approx(finer.P_c, rel=1e-5)
    for a in (1.0, 4.0, 7.0, 9.5):
        assert abs(ref.load_at(a) - finer.load_at(a)) < 1e-3 * abs(ref.P_c)
    with pytest.raises(ValueError, match="outside the reference path"):
        ref.load_at(12.0)


def test_the_3d_verification_rows_compare_with_the_same_law():
    """capslide verify's rows *_same_law: the reference's load at each FE radius and its pull-off, relative to
    its |P_c|; no rows where the rings would be too many (lambda = 20 on the sphere_md3 band)."""
    from capslide.studies.verification_3d import _same_law_rows

    p = Parameters.from_config(load_config([scene_path("sphere_md3")]))
    rows = _same_law_rows(p, "sphere_md3", {0.0: 11.4, -4.0: 9.9}, 6.60)
    ref = same_law_reference(p, 1.02 * 11.4)
    assert [r.quantity for r in rows] == ["load_at_radius_same_law"] * 2 + ["pull_off_same_law"]
    assert rows[0].theory == pytest.approx(ref.load_at(11.4), rel=1e-12) and rows[0].fe == 0.0
    assert rows[1].rel_error == pytest.approx((-4.0 - ref.load_at(9.9)) / abs(ref.P_c), rel=1e-12)
    assert rows[2].fe == -6.60 and rows[2].theory == pytest.approx(ref.P_c, rel=1e-12)
    assert -6.60 < ref.P_c < -6.55  # 2.2 % beyond Maugis-Dugdale's -6.433 at lambda = 3 (docs/three_d.md)
    assert math.isnan(_same_law_rows(p, "x", {1.0: 0.05, 0.0: 11.0}, 6.5)[0].theory)  # below the path's start
    stiff = Parameters.from_config(load_config([scene_path("sphere_md3")], ["adhesion.maugis_lambda=20"]))
    assert _same_law_rows(stiff, "x", {0.0: 11.0}, 6.5) == []
