"""Bulk assembly: exact tangent, rigid-body null space, patch tests, convergence rates."""

import numpy as np
import pytest
import scipy.sparse as sp

from capslide.fem.assembly import BulkForm, cell_dofs, rigid_body_modes
from capslide.fem.mesh import CapMeshSpec, cap_mesh, rectangle_mesh

from fe_helpers import LAM, MU, solve_dirichlet


@pytest.fixture(params=["Q1", "Q2"])
def distorted(request):
    return rectangle_mesh(5, 4, 2.0, 1.5, request.param, distortion=0.35, seed=3)


def test_pattern_matches_plain_coo_assembly(distorted):
    form = BulkForm(distorted, LAM, MU)
    u = 0.05 * np.random.default_rng(0).normal(size=distorted.n_dofs)
    _, K = form.residual_and_tangent(u)
    form2 = BulkForm(distorted, LAM, MU)
    form2.OUTER_BUDGET_BYTES = 0  # exercise the other element-tangent path too
    _, K2 = form2.residual_and_tangent(u)
    np.testing.assert_allclose(K.toarray(), K2.toarray(), atol=1e-12)
    dofs = cell_dofs(distorted.cells)
    assert K.nnz == len(np.unique(dofs[:, :, None] * distorted.n_dofs + dofs[:, None, :]))


def test_tangent_data_assembles_the_element_tangents_of_any_material_tangent(distorted):
    """tangent_data (element blocks left in (a, b, i, k) order, a permuted slot map) gives exactly the numbers of the
    (a, i), (b, k) blocks, and both the plain COO assembly of sum_q dN_aJ A_iJkL dN_bL w. A is random, with none of
    a material tangent's symmetries, so that a swapped index in the permutation shows."""
    form = BulkForm(distorted, LAM, MU)
    e, q, a, _ = form.dN.shape
    A = np.random.default_rng(4).normal(size=(e, q, 2, 2, 2, 2))
    data = form.tangent_data(A)
    np.testing.assert_array_equal(data, form.pattern.values(form.element_tangents(A)))
    K_e = np.einsum("eqaJ,eqiJkL,eqbL->eaibk", form.dNw, A, form.dN).reshape(e, 2 * a, 2 * a)
    dofs = cell_dofs(distorted.cells)
    rows, cols = np.broadcast_arrays(dofs[:, :, None], dofs[:, None, :])
    K = sp.coo_matrix((K_e.ravel(), (rows.ravel(), cols.ravel())), shape=(distorted.n_dofs,) * 2).toarray()
    np.testing.assert_allclose(form.pattern.matrix(data).toarray(), K, atol=1e-12 * np.abs(K).max())


def test_tangent_against_finite_differences(distorted):
    form = BulkForm(distorted, LAM, MU)
    rng = np.random.default_rng(1)
    X = distorted.nodes
    smooth = np.column_stack([0.2 * X[:, 1] ** 2 - 0.1 * X[:, 0], 0.15 * np.sin(X[:, 0]) - 0.2 * X[:, 1]])
    u = smooth.ravel() + 0.01 * rng.normal(size=distorted.n_dofs)
    assert form.min_jacobian(u) > 0.1  # a large but valid deformation
    _, K = form.residual_and_tangent(u)
    K = K.toarray()
    h = 1e-6
    for _ in range(6):
        v = rng.normal(size=distorted.n_dofs)
        fd = (form.residual(u + h * v) - form.residual(u - h * v)) / (2 * h)
        np.testing.assert_allclose(K @ v, fd, atol=1e-7 * np.abs(fd).max())
    np.testing.assert_allclose(K, K.T, atol=1e-12)  # hyperelastic bulk: symmetric


def test_rigid_body_modes_in_null_space(distorted):
    form = BulkForm(distorted, LAM, MU)
    _, K = form.residual_and_tangent(np.zeros(distorted.n_dofs))
    B = rigid_body_modes(distorted.nodes)
    assert np.abs(K @ B).max() < 1e-12 * abs(K).max()
    # and nothing else: the unconstrained stiffness has exactly three zero eigenvalues
    w = np.linalg.eigvalsh(K.toarray())
    assert np.sum(np.abs(w) < 1e-10 * w.max()) == 3


def _boundary_nodes(mesh, width, height):
    X = mesh.nodes
    return np.flatnonzero(np.isclose(np.abs(X[:, 0]), width / 2) | np.isclose(X[:, 1], 0) | np.isclose(X[:, 1], height))


@pytest.mark.parametrize("F0", [np.array([[1.1, 0.2], [-0.05, 0.9]]), np.array([[0.8, -0.3], [0.25, 1.15]])])
def test_patch_test_homogeneous_deformation(distorted, F0):
    nodes = _boundary_nodes(distorted, 2.0, 1.5)
    exact = distorted.nodes @ (F0 - np.eye(2)).T
    u, res, form = solve_dirichlet(distorted, nodes, exact[nodes])
    assert res.converged, res.reason
    interior = np.setdiff1d(np.arange(distorted.n_nodes), nodes)
    assert len(interior) > 5
    np.testing.assert_allclose(u.reshape(-1, 2)[interior], exact[interior], atol=1e-10)
    np.testing.assert_allclose(form.deformation_gradient(u), np.broadcast_to(F0, form.deformation_gradient(u).shape), atol=1e-10)


def test_force_balance_reaction_equals_applied():
    mesh = rectangle_mesh(6, 3, 2.0, 1.0, "Q1", distortion=0.2)
    top = np.flatnonzero(np.isclose(mesh.nodes[:, 1], 1.0))
    nodes = np.concatenate([mesh.base, top])
    values = np.zeros((len(nodes), 2))
    values[len(mesh.base):] = [0.1, -0.05]
    u, res, form = solve_dirichlet(mesh, nodes, values)
    f = form.residual(u).reshape(-1, 2)
    # internal forces vanish at free nodes; base reaction balances the top reaction
    free = np.setdiff1d(np.arange(mesh.n_nodes), nodes)
    assert np.abs(f[free]).max() < 1e-10
    np.testing.assert_allclose(f[mesh.base].sum(axis=0), -f[top].sum(axis=0), atol=1e-10)


def _cap_energy(element, h):
    """Strain energy of the cap with a smooth prescribed top displacement, uniform mesh size h."""
    R, H = 47.1, 10.0
    mesh = cap_mesh(CapMeshSpec(R=R, H=H, h0=h, band_half_width=5.0, element=element, side_growth=1.0,
                                max_size_over_H=h / H))
    b = np.sqrt(H * (2 * R - H))
    top = mesh.surface_nodes[1:-1]  # the corners are base nodes
    x = mesh.nodes[top, 0]
    values = np.column_stack([0.1 * (1 - (x / b) ** 2) ** 2, -0.2 * (1 - (x / b) ** 2) ** 2])
    nodes = np.concatenate([mesh.base, top])
    vals = np.vstack([np.zeros((len(mesh.base), 2)), values])
    u, res, form = solve_dirichlet(mesh, nodes, vals)
    assert res.converged
    return form.strain_energy(u), mesh.n_cells


@pytest.mark.parametrize("element, sizes, expected", [("Q1", [2.0, 1.0, 0.5, 0.25], 2.0), ("Q2", [2.0, 1.0, 0.5, 0.25], 4.0)])
def test_energy_convergence_rate(element, sizes, expected):
    energies = np.array([_cap_energy(element, h)[0] for h in sizes])
    # displacement-driven problem: the FE energy decreases monotonically to the exact one
    assert np.all(np.diff(energies) < 0)
    # fitted slope of log |E_h - E_h/2| against log h: the order, with no reference solution needed
    diffs = energies[:-1] - energies[1:]
    slope = np.polyfit(np.log(sizes[:-1]), np.log(diffs), 1)[0]
    print(element, energies, "fitted order", slope)
    assert slope == pytest.approx(expected, abs=0.35)


def test_deformation_gradient_cache_follows_the_state(distorted):
    """The cached F is recomputed when u changes, also in place, and cannot be modified by a caller."""
    form = BulkForm(distorted, 1.0, 1.0)
    u = 0.01 * np.random.default_rng(7).normal(size=distorted.n_dofs)
    F1 = form.deformation_gradient(u)
    assert form.deformation_gradient(u) is F1
    u[::3] += 0.02
    F2 = form.deformation_gradient(u)
    np.testing.assert_array_equal(F2, BulkForm(distorted, 1.0, 1.0).deformation_gradient(u))
    assert not np.allclose(F1, F2)
    with pytest.raises(ValueError):
        F2[0, 0, 0, 0] = 5.0


@pytest.mark.parametrize("mesh", [rectangle_mesh(4, 3, element="Q1"), rectangle_mesh(3, 2, element="Q2"),
                                  CapMeshSpec(R=47.1, H=10.0, h0=0.5, band_half_width=5.0, element="Q2"), "H1"],
                         ids=["Q1", "Q2", "Q2 cap", "H1"])
def test_the_pattern_from_node_pairs_is_the_pattern_from_dof_blocks(mesh):
    """SparsePattern.from_cells (node pairs, what BulkForm builds) gives from_blocks's arrays, the same to the
    entry: the same CSR matrix and the same map from the element blocks."""
    from capslide.fem.assembly import SparsePattern
    from capslide.fem.hex_mesh import SphereCapSpec, sphere_cap_mesh

    if isinstance(mesh, CapMeshSpec):
        mesh = cap_mesh(mesh)
    elif mesh == "H1":
        mesh = sphere_cap_mesh(SphereCapSpec(R=47.1, H=10.0, h0=0.8, band_radius=4.0))
    blocks = SparsePattern.from_blocks(cell_dofs(mesh.cells, mesh.dim), mesh.n_dofs)
    pairs = SparsePattern.from_cells(mesh.cells, mesh.dim, mesh.n_nodes)
    assert pairs.n == blocks.n
    for name in ("indptr", "indices", "slot"):
        np.testing.assert_array_equal(getattr(pairs, name), getattr(blocks, name))
        assert getattr(pairs, name).dtype == getattr(blocks, name).dtype
