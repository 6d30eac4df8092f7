"""The surface quadrature of a kinked normal law (studies/surface_quadrature.py): the Dugdale verification law on
sphere_dugdale3's mesh, integrated over its exact gap profile (the law's half-space solution) as the contact edge
passes a ring of points (benchmarks/surface_quadrature_error.py)."""

import numpy as np

from capslide.config import load_config, scene_path
from capslide.model.build import mesh_of, mesh_spec
from capslide.params import Parameters
from capslide.studies.surface_quadrature import quadrature_loads
from capslide.studies.verification import pull_off_reference


def test_the_dugdale_law_needs_four_points_per_face_edge_on_the_scenes_rings():
    """At the zero-load radius, in 16 phases of the edge across a ring (0.2 L0): 2 points per face edge miss the
    load of 16 by more than 1 % of |P_c| at some phase, 4 points stay within 0.6 % at every phase; the scene
    integrates with at least 4."""
    params = Parameters.from_config(load_config([scene_path("sphere_dugdale3")]))
    ring = mesh_spec(params).line_size
    radii = 11.5 + ring * np.arange(16) / 16
    loads = quadrature_loads(params, mesh_of(params), radii, [2, 4, 16])
    error = {n: np.max(np.abs(loads[n] - loads[16])) / abs(pull_off_reference(params)) for n in (2, 4)}
    assert error[2] > 0.01
    assert error[4] < 0.006
    assert params.mesh.surface_gauss_points >= 4


def test_the_smooth_cgcm_law_is_integrated_by_two_points():
    """The scene's mesh and radii under the CGCM law (smooth, no kinks): 2 points per face edge stay within 0.2 %
    of |P_c| of 16 at every phase (0.13 % measured), so what the test above measures is the Dugdale law's kinks."""
    params = Parameters.from_config(load_config([scene_path("sphere_dugdale3")], ["adhesion.law=cgcm"]))
    radii = 11.5 + mesh_spec(params).line_size * np.arange(16) / 16
    loads = quadrature_loads(params, mesh_of(params), radii, [2, 16])
    assert np.max(np.abs(loads[2] - loads[16])) / abs(pull_off_reference(params)) < 0.002
