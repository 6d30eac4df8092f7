"""Graded cap meshes: valid elements, exact geometry, ordered surface, grading."""

import math

import numpy as np
import pytest

from capslide.config import apply_overrides, validate
from capslide.fem.mesh import H0_AT_SIZE_1, CapMeshSpec, cap_mesh, circular_segment_area, rectangle_mesh
from capslide.model.build import cap_mesh_spec
from capslide.params import Parameters

R, H = 47.1, 10.0


@pytest.fixture(scope="module", params=["Q1", "Q2"])
def cap(request):
    return cap_mesh(CapMeshSpec(R=R, H=H, h0=0.05, band_half_width=11.35, element=request.param))


def test_positive_jacobians_everywhere(cap):
    assert cap.jacobians().min() > 0
    corners = np.array([[-1, -1], [1, -1], [1, 1], [-1, 1], [0, 0]], dtype=float)
    assert cap.jacobians(corners).min() > 0  # also at element corners, not only Gauss points


def test_area_matches_circular_segment(cap):
    exact = circular_segment_area(R, H)
    if cap.element == "Q1":
        # a polygon with its vertices on the arc: missing exactly the chord segments
        seg = cap.surface_segments
        chord = np.linalg.norm(cap.nodes[seg[:, -1]] - cap.nodes[seg[:, 0]], axis=1)
        theta = 2 * np.arcsin(chord / (2 * R))
        missing = np.sum(0.5 * R**2 * (theta - np.sin(theta)))
        assert cap.area() == pytest.approx(exact - missing, rel=1e-10)
    else:
        assert cap.area() == pytest.approx(exact, rel=1e-6)


def test_surface_ordered_and_covering_the_arc(cap):
    nodes = cap.nodes[cap.surface_nodes]
    b = math.sqrt(H * (2 * R - H))
    assert np.all(np.diff(nodes[:, 0]) > 0)
    assert nodes[0] == pytest.approx([-b, 0.0], abs=1e-12) and nodes[-1] == pytest.approx([b, 0.0], abs=1e-12)
    np.testing.assert_allclose(np.hypot(nodes[:, 0], nodes[:, 1] + R - H), R, rtol=1e-12)
    apex = np.flatnonzero(np.isclose(nodes[:, 0], 0.0, atol=1e-12))
    assert len(apex) == 1 and nodes[apex[0], 1] == pytest.approx(H)
    # segments chain: each starts where the previous ended
    seg = cap.surface_segments
    np.testing.assert_array_equal(seg[1:, 0], seg[:-1, -1])
    if cap.element == "Q2":  # mid nodes between their ends
        x = cap.nodes[seg, 0]
        assert np.all((x[:, 0] < x[:, 1]) & (x[:, 1] < x[:, 2]))


def test_base_nodes(cap):
    assert np.all(cap.nodes[cap.base, 1] == 0.0)
    on_base = np.flatnonzero(np.abs(cap.nodes[:, 1]) < 1e-12)
    np.testing.assert_array_equal(np.sort(cap.base), on_base)


def test_grading(cap):
    seg = cap.surface_segments
    xa, xb = cap.nodes[seg[:, 0]], cap.nodes[seg[:, -1]]
    length = np.linalg.norm(xb - xa, axis=1)
    mid_x = 0.5 * (xa[:, 0] + xb[:, 0])
    in_band = np.abs(mid_x) < 11.0
    assert length[in_band] == pytest.approx(0.05, rel=0.01)
    assert length.max() > 10 * 0.05  # coarser toward the sides
    # coarser with depth: mean cell size near the base far above the surface size
    centres = cap.nodes[cap.cells[:, :4]].mean(axis=1)
    sizes = np.sqrt(np.abs(cap.jacobians(np.zeros((1, 2)))[:, 0]) * 4)
    assert sizes[centres[:, 1] < 1.0].mean() > 20 * 0.05
    # symmetric about x = 0
    X = cap.nodes
    key = lambda P: np.round(P, 9)[np.lexsort(np.round(P, 9).T)]  # noqa: E731
    np.testing.assert_allclose(key(X), key(X * [-1, 1]), atol=1e-9)


def test_paper_level_cell_count(paper_config):
    """mesh.size 1 is the paper's 42,300-element level (the 'paper' preset is coarser, see docs/performance.md)."""
    spec = cap_mesh_spec(Parameters.from_config(validate(apply_overrides(paper_config, ["mesh.size=1", "mesh.element=Q1"]))))
    assert spec.h0 == H0_AT_SIZE_1
    assert 11.0 < spec.band_half_width < 12.0  # JKR zero-load half-width ~6.35 + ubar_max 5
    mesh = cap_mesh(spec)
    assert abs(mesh.n_cells - 42_300) / 42_300 < 0.02


def test_band_too_wide_is_an_error():
    with pytest.raises(ValueError, match="does not fit"):
        cap_mesh(CapMeshSpec(R=R, H=H, h0=0.1, band_half_width=40.0))


@pytest.mark.parametrize("element", ["Q1", "Q2"])
def test_rectangle_mesh(element):
    m = rectangle_mesh(6, 4, 3.0, 2.0, element, distortion=0.3)
    assert m.jacobians().min() > 0
    assert m.area() == pytest.approx(6.0, rel=1e-12)
