"""The contact outline of a 3D snapshot (issue 40): the zero curve of a nodal field on the half model's top faces,
closed with its mirror image, against shapes whose area and extents are known."""

import numpy as np
import pytest

from capslide.fem.hex_mesh import SphereCapSpec, sphere_cap_mesh
from capslide.loadpath.contact_patch import snapshot_outlines, zero_contour
from capslide.states import SlipState


@pytest.fixture(scope="module")
def top():
    mesh = sphere_cap_mesh(SphereCapSpec(R=47.1, H=10.0, h0=0.5, band_radius=8.0, max_size_over_H=0.4))
    return mesh.nodes, mesh.surface_segments


def _loops(curve):
    """The polylines of a NaN-separated curve."""
    cut = np.flatnonzero(np.isnan(curve[:, 0]))
    return [c for c in np.split(curve, cut) if len(c)] if len(cut) else [curve]


def _area(loop):
    loop = loop[~np.isnan(loop[:, 0])]
    x, y = loop[:, 0], loop[:, 1]
    return 0.5 * abs(np.sum(x[:-1] * y[1:] - x[1:] * y[:-1]))


def test_an_ellipse_is_closed_across_the_plane_of_symmetry(top):
    X, faces = top
    a, b = 5.5, 5.0
    curve = zero_contour(X[:, :2], (X[:, 0] / a) ** 2 + (X[:, 1] / b) ** 2 - 1.0, faces, mirror_y=True)
    assert not np.isnan(curve).any()  # one loop
    np.testing.assert_allclose(curve[0], curve[-1])  # closed
    assert curve[:, 1].min() < -0.99 * b and curve[:, 1].max() > 0.99 * b  # the mirror image is there
    assert curve[:, 0].min() == pytest.approx(-a, rel=1e-3) and curve[:, 0].max() == pytest.approx(a, rel=1e-3)
    # every point lies on the ellipse to the faces' linear interpolation (cells of 0.5 L0)
    np.testing.assert_allclose((curve[:, 0] / a) ** 2 + (curve[:, 1] / b) ** 2, 1.0, atol=5e-3)
    assert _area(curve) == pytest.approx(np.pi * a * b, rel=5e-3)


def test_islands_off_and_on_the_plane_each_make_a_loop(top):
    X, faces = top
    off = np.hypot(X[:, 0] - 4.0, X[:, 1] - 3.5) - 2.0  # a disk inside y > 0: it and its mirror image
    on = np.hypot(X[:, 0] + 4.0, X[:, 1]) - 2.5  # a disk across y = 0: one loop
    loops = _loops(zero_contour(X[:, :2], np.minimum(off, on), faces, mirror_y=True))
    assert len(loops) == 3
    areas = sorted(_area(c) for c in loops)
    assert areas == pytest.approx([4 * np.pi, 4 * np.pi, 6.25 * np.pi], rel=2e-2)  # polygons inscribed in circles
    assert not zero_contour(X[:, :2], np.ones(len(X)), faces).size  # no sign change, no curve


def test_snapshot_outlines_of_a_pressed_sphere(top):
    """A gap field of a sphere pressed to a radius of 4 L0 and a stick zone of the faces within 2.5 L0."""
    X, faces = top
    r2 = X[:, 0] ** 2 + X[:, 1] ** 2
    positions = X.copy()
    gap = (r2 - 16.0) / (2 * 47.1) + 0.1  # equal to the contact gap 0.1 at r = 4
    centre = X[faces].mean(axis=1)
    stick = (np.hypot(centre[:, 0], centre[:, 1]) < 2.5).astype(float)
    contact, sticking = snapshot_outlines(positions, gap, faces, stick, 0.1)
    assert _area(contact) == pytest.approx(np.pi * 16.0, rel=5e-3)
    radius = np.sqrt(_area(sticking) / np.pi)
    assert abs(radius - 2.5) < 0.5  # within a face (0.5 L0)
    assert int(SlipState.STICK) == 1
