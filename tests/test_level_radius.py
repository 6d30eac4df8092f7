"""The radius read from a 3D contact's gap at a level inside the cohesive zone (studies/verification_3d.py): its
reading on radial lines of surface points, and why the verification reads it rather than the contact area's
radius (benchmarks/area_measure_bias.py: the same law's exact gap profile read from nodes a ring width apart)."""

import math

import numpy as np
import pytest
from scipy.interpolate import CubicSpline

from capslide.config import load_config, scene_path
from capslide.params import Parameters
from capslide.studies.halfspace_sphere import halfspace_of, pull_off, reference_radii
from capslide.studies.verification_3d import LEVEL_OVER_RANGE, level_radius

LEVEL = 0.1


def radial_lines(radii_at_level, nodes, stray: int = 3):
    """Points on radial lines at angles in [0, pi], the gap crossing LEVEL at ``radii_at_level`` (one per line)
    with slope 0.5, plus ``stray`` points near the axis at angles of their own (no line)."""
    angles = np.linspace(0.0, math.pi, len(radii_at_level))
    rho = np.concatenate([np.repeat(nodes[None, :], len(angles), axis=0).ravel(), np.full(stray, 0.01)])
    theta = np.concatenate([np.repeat(angles, nodes.size), 0.3 + 0.01 * np.arange(stray)])
    r0 = np.concatenate([np.repeat(radii_at_level, nodes.size), np.full(stray, np.inf)])
    gap = np.where(np.isinf(r0), 0.0, LEVEL + 0.5 * (rho - np.where(np.isinf(r0), 0.0, r0)))
    return rho * np.cos(theta), rho * np.sin(theta), gap


def test_the_level_radius_is_the_mean_crossing_of_the_radial_lines():
    crossings = 5.0 + 0.013 * np.arange(9)
    x, y, g = radial_lines(crossings, np.arange(0.05, 8.0, 0.2))
    assert level_radius(x, y, g, LEVEL) == pytest.approx(crossings.mean(), abs=1e-12)


def test_the_first_crossing_going_out_counts():
    """A gap that falls back below the level further out (a second crossing) does not move the radius."""
    nodes = np.arange(0.05, 8.0, 0.2)
    x, y, g = radial_lines(np.full(4, 3.0), nodes, stray=0)
    rho = np.hypot(x, y)
    g = np.where(rho > 6.0, LEVEL - 1.0 + 0.5 * (rho - 6.0), g)
    assert level_radius(x, y, g, LEVEL) == pytest.approx(3.0, abs=1e-12)


def test_no_crossing_is_nan():
    x, y, g = radial_lines(np.full(4, 3.0), np.arange(0.05, 8.0, 0.2), stray=0)
    assert math.isnan(level_radius(x, y, np.full(g.shape, LEVEL - 1.0), LEVEL))


def _crossing_from_nodes(r, gap, level, width, offset):
    """The level radius read from nodes ``width`` apart on one radial line, the gap (r, gap) between them linear."""
    nodes = np.arange(offset, r[-1], width)
    return level_radius(nodes, np.zeros_like(nodes), np.interp(nodes, r, gap), level)


def test_on_the_laws_exact_profile_the_level_radius_reads_the_load_the_area_radius_misses():
    """sphere_dugdale3's law on a half-space, read from nodes 0.2 L0 apart (the scene's rings) at the zero-load
    radius: the contact edge (where the gap touches g_max with zero slope) reads the load more than 2 % of |P_c|
    off on average over the nodes' offsets, the level radius within 1 % at every offset."""
    params = Parameters.from_config(load_config([scene_path("sphere_dugdale3")]))
    ad = params.adhesion
    errors = {}
    for name, level in {"edge": ad.g_max, "level": ad.g_eq + LEVEL_OVER_RANGE * ad.W_adh / ad.T_max}.items():
        halfspace = halfspace_of(params, edge_gap=level)
        path = halfspace.edge_path(np.union1d(reference_radii(params, 12.0), [11.5]))
        P_c, _ = pull_off(path)
        load_at = CubicSpline([s.a for s in path], [s.P for s in path])
        sol = next(s for s in path if s.a == 11.5)
        read = [_crossing_from_nodes(halfspace.r, sol.g, level, 0.2, o) for o in np.linspace(0.0, 0.2, 10, False)]
        errors[name] = (sol.P - load_at(np.array(read))) / abs(P_c)
    assert np.mean(errors["edge"]) > 0.02
    assert np.max(np.abs(errors["level"])) < 0.01
