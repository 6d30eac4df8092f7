"""The FE core in 3D (issue 39): the same BulkForm on hexahedra. Exact tangent against finite differences, the six
rigid-body modes in the tangent's null space at rest, the patch test (a homogeneous deformation is exact on a
distorted mesh), the energy of a homogeneous stretch, and the graded half model of the spherical cap."""

import math

import numpy as np
import pytest
import scipy.sparse.linalg as spla

from capslide.fem.assembly import BulkForm, Dirichlet, node_dofs, rigid_body_modes
from capslide.fem.hex_mesh import SphereCapSpec, box_mesh, sphere_cap_counts, sphere_cap_mesh, spherical_cap_volume
from capslide.fem.mixed import MixedBulkForm
from capslide.laws import material

from fe_helpers import check_bulk_form_derivatives, check_mixed_form_derivatives

LAM, MU = 0.4 / (1.4 * 0.2), 1.0 / 2.8  # E = 1, nu = 0.4 (3D Lame constants)


@pytest.fixture
def distorted():
    return box_mesh(3, 2, 2, (1.5, 1.0, 1.0), distortion=0.3, seed=5)


def test_3d_tangent_is_the_residual_derivative(distorted):
    u, _, K = check_bulk_form_derivatives(BulkForm(distorted, LAM, MU), distorted.n_dofs, 0.05, seed=0)
    form2 = BulkForm(distorted, LAM, MU)
    form2.OUTER_BUDGET_BYTES = 0  # the other element-tangent path
    np.testing.assert_allclose(form2.residual_and_tangent(u)[1].toarray(), K.toarray(), atol=1e-12)


@pytest.mark.parametrize("lam", [LAM, 100.0, np.inf], ids=["nu0.4", "nu0.498", "incompressible"])
def test_mean_dilatation_tangent_is_the_residual_derivative(distorted, lam):
    """H1/P0 (mesh.formulation = mixed in 3D): the condensed tangent against finite differences of the residual, the
    residual against the energy's gradient, and one dilatation per cell."""
    form = MixedBulkForm(distorted, lam, MU)
    assert form.Np.shape[-1] == 1
    u = check_mixed_form_derivatives(form, distorted, 0.05, seed=1)
    theta = form.dilatation(u)
    np.testing.assert_allclose(theta, theta[:, :1] * np.ones_like(theta))  # constant in each cell
    J = material.det(form.deformation_gradient(u))
    np.testing.assert_allclose(theta[:, 0], np.sum(J * form.wdetJ, axis=1) / form.wdetJ.sum(axis=1))


def test_rigid_body_modes_span_the_null_space_at_rest(distorted):
    B = rigid_body_modes(distorted.nodes)
    assert B.shape == (distorted.n_dofs, 6)
    assert np.linalg.matrix_rank(B) == 6
    _, K = BulkForm(distorted, LAM, MU).residual_and_tangent(np.zeros(distorted.n_dofs))
    np.testing.assert_allclose(K @ B, 0.0, atol=1e-10)
    assert np.linalg.matrix_rank(K.toarray(), tol=1e-8) == distorted.n_dofs - 6


def test_patch_test_homogeneous_deformation_is_exact(distorted):
    """Boundary nodes moved by (F - I) X: the interior nodes follow exactly, the energy is W(F) times the volume."""
    F = np.array([[1.1, 0.05, 0.0], [0.02, 0.95, 0.03], [0.0, -0.04, 1.05]])
    X = distorted.nodes
    exact = (X @ (F - np.eye(3)).T).ravel()
    inner = np.flatnonzero(np.all((X > 1e-9) & (X < np.array([1.5, 1.0, 1.0]) - 1e-9), axis=1))
    boundary = np.setdiff1d(np.arange(len(X)), inner)
    form = BulkForm(distorted, LAM, MU)
    bc = Dirichlet.on_nodes(boundary, form.pattern, dim=3)
    np.testing.assert_array_equal(bc.dofs, node_dofs(boundary, 3))
    u = np.where(np.isin(np.arange(distorted.n_dofs), bc.dofs), exact, 0.0)
    for _ in range(8):  # Newton on the interior nodes
        r, data = form.residual_and_tangent_data(u)
        bc.apply(data, r)
        u -= spla.spsolve(form.pattern.matrix(data).tocsc(), r)
    np.testing.assert_allclose(u, exact, atol=1e-10)
    volume = distorted.area()
    assert volume == pytest.approx(1.5)
    assert form.strain_energy(u) == pytest.approx(material.strain_energy_density(F[None], LAM, MU)[0] * volume)


@pytest.mark.parametrize("h0", [0.6, 0.3])
def test_sphere_cap_mesh_is_the_half_cap(h0):
    spec = SphereCapSpec(R=47.1, H=10.0, h0=h0, band_radius=9.0)
    mesh = sphere_cap_mesh(spec)
    assert sphere_cap_counts(spec) == (mesh.n_cells, mesh.n_nodes)  # the plan counts without meshing
    assert mesh.dim == 3 and mesh.n_dofs == 3 * mesh.n_nodes
    corners = np.array([[a, b, c] for a in (-1, 1) for b in (-1, 1) for c in (-1, 1)], dtype=float)
    assert mesh.jacobians(corners).min() > 0.0  # no inverted cell, at any corner
    assert 2 * mesh.area() == pytest.approx(spherical_cap_volume(47.1, 10.0), rel=5e-3)
    X = mesh.nodes
    np.testing.assert_allclose(X[mesh.base, 2], 0.0)
    np.testing.assert_allclose(X[mesh.symmetry, 1], 0.0)
    assert np.all(X[:, 1] >= 0.0)
    assert len(mesh.symmetry) == np.sum(X[:, 1] == 0.0)
    top = np.unique(mesh.surface_segments)
    np.testing.assert_allclose(np.linalg.norm(X[top] - [0.0, 0.0, 10.0 - 47.1], axis=1), 47.1, rtol=1e-12)
    # the facets face up (counter-clockwise from above) and are at most 1.4 h0 wide in the band
    P = X[mesh.surface_segments]
    normal = np.cross(P[:, 1] - P[:, 0], P[:, 3] - P[:, 0])
    assert np.all(normal[:, 2] > 0.0)
    in_band = np.linalg.norm(P.mean(axis=1)[:, :2], axis=1) < 9.0
    edges = np.linalg.norm(np.roll(P, -1, axis=1) - P, axis=2).max(axis=1)
    assert edges[in_band].max() <= 1.4 * h0
    assert edges[in_band].min() >= 0.5 * h0
    assert mesh.nodes[:, 2].max() == pytest.approx(10.0)
    assert math.isclose(mesh.info["U"], 47.1 * mesh.info["phi1"])


def test_a_contact_line_annulus_refines_its_rings_and_top_layer_alone():
    """mesh.line_band: inside the annulus the surface cells are line_size wide radially, at most h0 along the
    circumference, and the top layer as thin; away from it the rings widen; the plan still counts the mesh."""
    plain = SphereCapSpec(R=47.1, H=10.0, h0=0.6, band_radius=9.0)
    spec = SphereCapSpec(R=47.1, H=10.0, h0=0.6, band_radius=9.0, line_band=(5.0, 7.0), line_size=0.15)
    mesh = sphere_cap_mesh(spec)
    assert sphere_cap_counts(spec) == (mesh.n_cells, mesh.n_nodes)
    corners = np.array([[a, b, c] for a in (-1, 1) for b in (-1, 1) for c in (-1, 1)], dtype=float)
    assert mesh.jacobians(corners).min() > 0.0
    assert 2 * mesh.area() == pytest.approx(spherical_cap_volume(47.1, 10.0), rel=5e-3)
    X = mesh.nodes
    P = X[mesh.surface_segments]
    r = np.linalg.norm(P[..., :2], axis=2)
    radial = r.max(axis=1) - r.min(axis=1)  # a ring cell's radial width
    mid = r.mean(axis=1)
    in_line = (mid > 5.1) & (mid < 6.9) & (P[:, :, 1].min(axis=1) > 1.0)  # ring cells (off the O-grid's corners)
    assert radial[in_line].max() <= 0.15 * 1.05
    assert radial[(mid > 2.7) & (mid < 3.5)].min() > 0.2  # wider rings away from the annulus
    theta = np.arctan2(P[..., 1], P[..., 0])
    along = (theta.max(axis=1) - theta.min(axis=1)) * mid  # a ring cell's width along the circumference
    assert along[in_line].max() <= 0.6  # at most h0
    # the top layer under the annulus is as thin as its rings, thicker at the apex
    top, second = X[mesh.cells[:, 4:]], X[mesh.cells[:, :4]]  # a cell's upper face (level k) and lower (level k + 1)
    thickness = np.abs(top[..., 2] - second[..., 2]).mean(axis=1)
    upper = np.isin(mesh.cells[:, 4:], np.unique(mesh.surface_segments)).all(axis=1)
    cell_r = np.linalg.norm(top[..., :2], axis=2).mean(axis=1)
    assert thickness[upper & (cell_r > 5.2) & (cell_r < 6.8)].max() <= 0.16
    assert thickness[upper & (cell_r < 1.0)].min() > 0.4  # near h0 (at most H / layers) at the apex
    assert mesh.info["layers"] > sphere_cap_mesh(plain).info["layers"]
