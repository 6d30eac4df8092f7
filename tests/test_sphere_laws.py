"""Closed forms of the sphere (laws/sphere.py): Hertz, and the Maugis-Dugdale sphere against its JKR and DMT limits
and the values of ../shared/reference/sphere-facts.md (the references of the 3D verification)."""

import math

import numpy as np
import pytest

from capslide.laws import analytic, sphere

# sphere-facts.md: lambda -> (pull-off P, zero-load A, zero-load area against JKR)
FACTS = {1: (-1.601, 1.636, -0.189), 3: (-1.517, 1.775, -0.046), 5: (-1.506, 1.800, -0.019), 10: (-1.502, 1.813, -0.005)}


@pytest.mark.parametrize("lam", list(FACTS))
def test_maugis_dugdale_matches_the_reference_table(lam):
    P_c, A_0, area = FACTS[lam]
    P, _ = sphere.md_pull_off(lam)
    A = sphere.md_zero_load_radius(lam)
    assert P == pytest.approx(P_c, abs=6e-4) and A == pytest.approx(A_0, abs=6e-4)
    assert A**2 / 6.0 ** (2.0 / 3.0) - 1.0 == pytest.approx(area, abs=6e-4)


def test_the_limits_are_jkr_and_dmt():
    A = np.array([0.6, 1.0, 1.5, 2.5])
    np.testing.assert_allclose(sphere.md_load(A, 1e5), A**3 - np.sqrt(6.0 * A**3), rtol=1e-5)
    np.testing.assert_allclose(sphere.md_approach(A, 1e5), A**2 - np.sqrt(8.0 * A / 3.0), rtol=1e-5)
    assert sphere.md_pull_off(1e5)[0] == pytest.approx(-1.5, abs=1e-4)  # JKR: -3/2 pi w R
    assert sphere.md_pull_off(0.01)[0] == pytest.approx(-2.0, abs=0.01)  # DMT: -2 pi w R


def test_the_scales_give_jkr_in_units():
    """At large lambda, the dimensionless solution scaled back is the JKR sphere of analytic.py (the experiment's
    sphere: E = 1.6 MPa, nu = 0.5, R = 9.42 mm, w = 27 mJ/m^2; sphere-facts.md gives a0 = 251.3 um, pull-off
    -1.199 mN at 0.0788 mm^2)."""
    E_star, R, w = analytic.effective_modulus(1.6e6, 0.5), 9.42e-3, 0.027
    s = sphere.md_scales(R, E_star, w)
    a0 = analytic.jkr_sphere_radius(0.0, R, E_star, w)
    assert a0 == pytest.approx(251.3e-6, rel=2e-4) and math.pi * a0**2 == pytest.approx(0.1985e-6, rel=5e-4)
    assert sphere.md_zero_load_radius(1e5) * s["radius"] == pytest.approx(a0, rel=1e-5)
    P_c, A_c = sphere.md_pull_off(1e5)
    assert P_c * s["load"] == pytest.approx(analytic.jkr_sphere_pull_off(R, E_star, w), rel=1e-5)
    assert -P_c * s["load"] == pytest.approx(1.199e-3, rel=5e-4)
    assert math.pi * (A_c * s["radius"]) ** 2 == pytest.approx(0.0788e-6, rel=2e-3)


def test_hertz_sphere():
    E_star, R, P = 2.0e6 / (1 - 0.4**2), 47.1e-6, 1e-6
    a = sphere.hertz_sphere_radius(P, R, E_star)
    assert float(sphere.hertz_sphere_peak_pressure(P, R, E_star)) == pytest.approx(2.0 * E_star * a / (math.pi * R))
    assert float(sphere.hertz_sphere_approach(P, R, E_star)) == pytest.approx(a**2 / R)
    assert float(analytic.jkr_sphere_load(a, R, E_star, 0.0)) == pytest.approx(P)  # JKR without adhesion is Hertz



def test_the_maugis_parameter_of_the_experiment():
    """sphere-facts.md: at lambda = 3 the experiment's sphere has sigma0 of about 0.063 MPa, a range w / sigma0 of
    about 0.44 um."""
    E_star, R, w = analytic.effective_modulus(1.6e6, 0.5), 9.42e-3, 0.027
    sigma0 = sphere.dugdale_stress_for_lambda(3.0, R, E_star, w)
    assert sigma0 == pytest.approx(0.063e6, rel=0.02) and w / sigma0 == pytest.approx(0.44e-6, rel=0.03)
    assert sphere.maugis_parameter_sphere(R, E_star, w, sigma0) == pytest.approx(3.0, rel=1e-14)


def test_the_moment_radius_of_the_hertz_pressure_is_its_radius():
    """a^2 = 5/2 int p r^2 dA / int p dA for p = p0 sqrt(1 - r^2 / a^2), on fine rings."""
    edges = np.linspace(0.0, 3.0, 30001)
    r = 0.5 * (edges[1:] + edges[:-1])
    p = np.sqrt(np.clip(1.0 - (r / 2.0) ** 2, 0.0, None))
    assert sphere.hertz_moment_radius(p * np.pi * np.diff(edges**2), r**2) == pytest.approx(2.0, rel=1e-6)
