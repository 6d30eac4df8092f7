"""The repulsive law's half-space sphere (studies/halfspace_hertz.py): Hertz in the limit of a stiff law, and the
compliance of the sphere_hertz scene's law, which flattens the pressure (docs/three_d.md)."""

import numpy as np
import pytest

from capslide.config import load_config, scene_path
from capslide.laws import analytic, sphere
from capslide.params import Parameters
from capslide.studies.halfspace_hertz import hertz_law_reference, repulsive


def _errors(overrides: list[str]) -> tuple[np.ndarray, np.ndarray]:
    """The reference's moment radius and peak against Hertz at the scene's loads, smallest first."""
    p = Parameters.from_config(load_config([scene_path("sphere_hertz")], overrides))
    R, E_star = p.geometry.R, analytic.effective_modulus(p.material.E, p.material.nu)
    loads = sorted(p.verification.loads)
    ref = hertz_law_reference(p, loads)
    radius = np.array([ref[P].radius_moment / sphere.hertz_sphere_radius(P, R, E_star) - 1 for P in loads])
    peak = np.array([ref[P].peak_pressure / sphere.hertz_sphere_peak_pressure(P, R, E_star) - 1 for P in loads])
    return radius, peak


def test_repulsive_keeps_the_compressive_part():
    def law(g):
        return 1.0 - g, -np.ones_like(g)
    Tn, dTn = repulsive(law)(np.array([0.5, 1.0, 1.5]))
    assert Tn.tolist() == [0.5, 0.0, 0.0] and dTn.tolist() == [-1.0, 0.0, 0.0]


def test_the_scene_law_flattens_the_hertz_pressure_and_a_stiffer_law_does_not():
    """The scene's law: the peak 0.4 to 0.7 % below p0 and the radius 0.3 to 0.5 % above, less at larger loads.
    T_max four times (the range a quarter, the repulsive stiffness 16 times): both within 0.2 % of Hertz."""
    radius, peak = _errors([])
    assert np.all((radius > 0.003) & (radius < 0.005)) and np.all(np.diff(radius) < 0), radius
    assert np.all((peak < -0.004) & (peak > -0.007)) and np.all(np.diff(peak) > 0), peak
    radius, peak = _errors(["adhesion.T_max=1.32e6"])
    assert np.max(np.abs(radius)) < 0.002 and np.max(np.abs(peak)) < 0.002, (radius, peak)


def test_loads_off_the_path_are_refused():
    p = Parameters.from_config(load_config([scene_path("sphere_hertz")], []))
    with pytest.raises(ValueError, match="outside the reference path"):
        hertz_law_reference(p, [0.1, 40.0])
