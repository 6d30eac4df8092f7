"""The cap model in 3D (issue 39): the CGCM normal contact on the top faces of the spherical cap's half model, its
consistent linearization against finite differences (the bordered Jacobian of the model: bulk, contact, the
substrate height and the constraint row), the boundary conditions of the half model, and the contact force's
integral against a direct sum."""

from dataclasses import replace

import numpy as np
import pytest

from capslide.config import apply_overrides, validate
from capslide.fem.assembly import rigid_body_modes
from capslide.fem.hex_mesh import SphereCapSpec, sphere_cap_mesh
from capslide.model.constraints import FixedApexGap, FixedForce, FixedHeight
from capslide.model.system import CapModel, History
from capslide.params import Parameters
from capslide.solvers.linsolve import make_solver

from fe_helpers import check_bordered_jacobian, pressed_sphere_state


@pytest.fixture(scope="module")
def model(paper_config):
    cfg = validate(apply_overrides(paper_config, ["friction.model=none"]))
    p = Parameters.from_config(cfg)
    mesh = sphere_cap_mesh(SphereCapSpec(R=47.1, H=10.0, h0=0.8, band_radius=4.0, max_size_over_H=0.4))
    solver = make_solver("amg", near_null_space=rigid_body_modes(mesh.nodes))
    return CapModel(mesh, p, solver)


def test_half_model_boundary_conditions(model):
    mesh = model.mesh
    fixed = set(model.bc.dofs.tolist())
    assert all(3 * n + i in fixed for n in mesh.base for i in range(3))
    assert all(3 * n + 1 in fixed for n in mesh.symmetry)
    assert not any(3 * n in fixed or 3 * n + 2 in fixed for n in np.setdiff1d(mesh.symmetry, mesh.base))
    assert model.mesh.nodes[model.apex_node].tolist() == pytest.approx([0.0, 0.0, 10.0])
    assert model.apex_y_dof == 3 * model.apex_node + 2
    x = np.zeros(model.n_dofs + 1)
    x[-1], x[model.apex_y_dof] = 10.7, 0.2
    assert model.apex_gap(x) == pytest.approx(0.5)  # the gap along z
    # the edge gap's points: the top's line on the plane of symmetry, both sides
    dofs, w = model.edge_weights(2.0)
    nodes = (dofs - 2) // 3
    assert np.all(dofs % 3 == 2) and w.sum() == pytest.approx(1.0)
    np.testing.assert_allclose(model.mesh.nodes[nodes, 1], 0.0)
    assert model.mesh.nodes[nodes, 0].min() < -1.0 and model.mesh.nodes[nodes, 0].max() > 1.0


@pytest.mark.parametrize("constraint", [FixedHeight(10.1), FixedForce(-0.1), FixedApexGap(0.09)], ids=["h", "Fn", "apex"])
def test_bordered_jacobian_against_finite_differences(model, constraint):
    x = pressed_sphere_state(model, shear=0.05)
    g, _ = model.contact.gaps(x[:-1], x[-1])
    a = model.params.adhesion
    assert (g < a.g_reg).any() and ((g > a.g_eq) & (g < a.g_max)).any() and (g > a.g_max).any()
    check_bordered_jacobian(model, x, constraint, History(), directions=3)


def test_contact_force_is_the_traction_integral(model):
    """Fn is the whole sphere's: twice the half model's sum of the traction over the Gauss points, and twice its
    force vector's z sum; the force acts along z only."""
    x = pressed_sphere_state(model, shear=0.05)
    u, h = x[:-1], x[-1]
    f, Fn, Ft = model.contact.force(u, h)
    assert Ft == 0.0
    g, _ = model.contact.gaps(u, h)
    Tn, _ = model.contact.traction(np.minimum(g, model.contact.far_gap))
    Tn = np.where(g < model.contact.far_gap, Tn, 0.0)
    assert Fn == pytest.approx(-2 * np.sum(Tn * model.contact.quad.weight), rel=1e-12)
    assert 2 * f[2::3].sum() == pytest.approx(Fn, rel=1e-12)
    np.testing.assert_allclose(f[0::3], 0.0)
    np.testing.assert_allclose(f[1::3], 0.0)
    assert model.base_reaction(x).shape == (3,)
    assert model.saved_shapes()["snapshot_u"] == (model.mesh.n_nodes, 3)


def test_every_node_on_the_plane_of_symmetry_is_held(model):
    """Before: the rings' points on y = 0 at x < 0 had y = R sin(pi) = 1e-15 and were left free."""
    on_plane = np.flatnonzero(np.abs(model.mesh.nodes[:, 1]) < 1e-9)
    np.testing.assert_array_equal(np.sort(model.mesh.symmetry), on_plane)
    assert np.all(model.mesh.nodes[on_plane, 1] == 0.0)


def test_the_whole_cap_is_the_half_and_its_mirror_image():
    from capslide.fem.hex_mesh import sphere_cap_counts

    spec = SphereCapSpec(R=47.1, H=10.0, h0=1.5, band_radius=8.0, max_size_over_H=0.4)
    half, whole = sphere_cap_mesh(spec), sphere_cap_mesh(replace(spec, whole=True))
    assert sphere_cap_counts(replace(spec, whole=True)) == (whole.n_cells, len(whole.nodes))
    assert whole.n_cells == 2 * half.n_cells and len(whole.symmetry) == 0
    assert len(whole.nodes) == 2 * len(half.nodes) - len(half.symmetry)
    assert whole.area() == pytest.approx(2 * half.area(), rel=1e-12)  # the cells' volume
    assert len(np.unique(whole.nodes.round(9), axis=0)) == len(whole.nodes)  # no point twice
    assert len(whole.surface_segments) == 2 * len(half.surface_segments)
