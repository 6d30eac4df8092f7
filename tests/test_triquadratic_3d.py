"""The triquadratic hexahedron H2 (27 nodes) and its mixed pair H2/P1 on the spherical cap (issue 39's second
candidate against H1/P0): the mesh is the cap to its curvature, the nodes are in VTK's order, the 9-node top faces
integrate the cap's top, and the tangents are the residuals' derivatives. The Hertz sphere on H2:
benchmarks/hertz_sphere.py --element H2 (docs/three_d.md)."""

import math

import numpy as np
import pytest
import xarray as xr

from capslide.config import apply_overrides, load_config, validate
from capslide.driver.case import run_case
from capslide.fem.assembly import BulkForm, rigid_body_modes
from capslide.fem.element import HEXES
from capslide.fem.hex_mesh import SphereCapSpec, sphere_cap_counts, sphere_cap_mesh, spherical_cap_volume
from capslide.fem.interface import SurfaceContact
from capslide.fem.mixed import MixedBulkForm
from capslide.fem.surface import SurfaceQuadrature, stretch
from capslide.io.results import case_dataset
from capslide.laws import material
from capslide.model.constraints import FixedHeight, SlideAtForce
from capslide.model.system import CapModel
from capslide.params import Parameters
from capslide.solvers.linsolve import make_solver
from capslide.states import Phase, SlipState

from conftest import PAPER_CONFIG
from fe_helpers import check_bordered_jacobian, check_bulk_form_derivatives, check_mixed_form_derivatives, pressed_sphere_state

LAM, MU = 0.4 / (1.4 * 0.2), 1.0 / 2.8  # E = 1, nu = 0.4


@pytest.mark.parametrize("whole", [False, True], ids=["half", "whole"])
def test_the_triquadratic_cap_mesh_is_the_cap_to_its_curvature(whole):
    spec = SphereCapSpec(R=47.1, H=10.0, h0=1.5, band_radius=9.0, whole=whole, order=2)
    mesh = sphere_cap_mesh(spec)
    linear = sphere_cap_mesh(SphereCapSpec(R=47.1, H=10.0, h0=1.5, band_radius=9.0, whole=whole))
    assert mesh.element == "H2" and mesh.cells.shape == (linear.n_cells, 27)
    assert sphere_cap_counts(spec) == (mesh.n_cells, mesh.n_nodes)
    assert len(np.unique(mesh.cells)) == mesh.n_nodes  # every node in a cell, none twice
    assert len(np.unique(np.round(mesh.nodes, 9), axis=0)) == mesh.n_nodes
    assert mesh.jacobians(HEXES["H2"].nodes).min() > 0.0
    exact = spherical_cap_volume(47.1, 10.0) / (1 if whole else 2)
    assert mesh.area() == pytest.approx(exact, rel=2e-5)  # curved cells: H1's is 1 % short
    assert abs(linear.area() / exact - 1) > 5e-3
    # the corners are H1's cells; every node lies where the corners' trilinear map puts its reference point, to
    # within the cap's curvature (a node order other than VTK's would put some a cell width away)
    np.testing.assert_allclose(mesh.nodes[mesh.cells[:, :8]], linear.nodes[linear.cells])
    N1, _ = HEXES["H1"].shape(HEXES["H2"].nodes)
    mapped = np.einsum("ka,eai->eki", N1, mesh.nodes[mesh.cells[:, :8]])
    size = np.linalg.norm(mesh.nodes[mesh.cells[:, 6]] - mesh.nodes[mesh.cells[:, 0]], axis=1)
    assert (np.linalg.norm(mapped - mesh.nodes[mesh.cells], axis=2).max(axis=1) / size).max() < 0.05
    X = mesh.nodes
    top = np.unique(mesh.surface_segments)
    np.testing.assert_allclose(np.linalg.norm(X[top] - [0.0, 0.0, 10.0 - 47.1], axis=1), 47.1, rtol=1e-12)
    np.testing.assert_allclose(X[mesh.base, 2], 0.0, atol=1e-12)
    if not whole:
        np.testing.assert_array_equal(mesh.symmetry, np.flatnonzero(X[:, 1] == 0.0))
    # the faces' quarters face up
    P = X[mesh.surface_quads]
    assert np.all(np.cross(P[:, 1] - P[:, 0], P[:, 3] - P[:, 0])[:, 2] > 0.0)


def test_the_triquadratic_top_faces_integrate_the_caps_top():
    """The contact integral's quadrature on the 9-node faces: the top's area is the spherical zone's, pi R^2 (1 -
    cos phi1) for the half model, to 1e-5 (H1's bilinear faces: 0.6 % short)."""
    error = {}
    for order in (1, 2):
        mesh = sphere_cap_mesh(SphereCapSpec(R=47.1, H=10.0, h0=1.5, band_radius=9.0, order=order))
        zone = math.pi * 47.1**2 * (1.0 - math.cos(mesh.info["phi1"]))
        error[order] = SurfaceQuadrature.on(mesh, 3).weight.sum() / zone - 1.0
    assert abs(error[2]) < 1e-5
    assert abs(error[1]) > 1e-3


@pytest.fixture(scope="module")
def small_cap():
    return sphere_cap_mesh(SphereCapSpec(R=12.0, H=3.0, h0=1.5, band_radius=1.2, order=2))


def test_the_triquadratic_tangent_is_the_residual_derivative(small_cap):
    check_bulk_form_derivatives(BulkForm(small_cap, LAM, MU), small_cap.n_dofs, 0.002, seed=2)


@pytest.mark.parametrize("lam", [LAM, np.inf], ids=["nu0.4", "incompressible"])
def test_the_h2_p1_tangent_is_the_residual_derivative(small_cap, lam):
    """H2/P1: a dilatation linear in each cell (four coefficients), the condensed tangent against finite
    differences, the residual against the energy's gradient."""
    form = MixedBulkForm(small_cap, lam, MU)
    assert form.Np.shape[-1] == 4
    u = check_mixed_form_derivatives(form, small_cap, 0.002, seed=3)
    # theta is J's projection onto P1: a field linear in the reference coordinates is kept
    Xq = np.einsum("qa,eai->eqi", HEXES["H2"].shape(HEXES["H2"].gauss()[0])[0], small_cap.nodes[small_cap.cells])
    linear = 1.0 + 0.01 * Xq[..., 0] - 0.02 * Xq[..., 2]
    np.testing.assert_allclose(form.project(linear), linear, atol=1e-12)
    J = material.det(form.deformation_gradient(u))
    assert not np.allclose(form.project(J), J)  # J itself is not linear in a cell


@pytest.mark.parametrize("formulation", ["displacement", "mixed"])
def test_the_h2_models_bordered_jacobian_with_friction(formulation):
    """The whole linearization on H2 (the contact integral on 9-node faces, DI per current area with theta_k = J_s,
    stick and slip at once; H2/P1 too) against central differences of the residual."""
    cfg = validate(apply_overrides(load_config([PAPER_CONFIG], ["preset=fast"]), [
        "mesh.element=H2", f"mesh.formulation={formulation}", "friction.model=DI",
        "contact.normal_traction_area=current"]))
    mesh = sphere_cap_mesh(SphereCapSpec(R=47.1, H=10.0, h0=1.0, band_radius=4.0, max_size_over_H=0.4, order=2))
    model = CapModel(mesh, Parameters.from_config(cfg), make_solver("amg", near_null_space=rigid_body_modes(mesh.nodes)))
    x0 = pressed_sphere_state(model)
    history = model.start_friction(x0)
    x = x0.copy()
    X = mesh.nodes
    x[:-1:3] += 0.0012 * X[:, 2] / 10
    x[1:-1:3] += 0.0006 * X[:, 2] / 10 * (X[:, 1] > 0)
    x[model.bc.dofs] = 0.0
    ubar = 1e-4
    g, _ = model.contact.gaps(x[:-1], x[-1])
    a = model.params.adhesion
    assert (g < a.g_reg).any() and ((g > a.g_eq) & (g < a.g_max)).any()
    _, state = model.contact.tangential_state(x[:-1], x[-1], ubar, *history.friction)
    assert (state == 1).any() and (state == 2).any()  # stick and slip
    for constraint in (FixedHeight(x[-1], ubar), SlideAtForce(ubar, -0.1)):
        check_bordered_jacobian(model, x, constraint, history, directions=2)


@pytest.mark.slow
def test_a_triquadratic_sphere_runs_to_zero_load_and_slides_at_tau_times_area(tmp_path):
    """The whole path on H2 (coarse: 13,041 DOF, about 3.5 minutes):
    approach, spread and preload to zero load, then DI slides to full sliding; the case file holds the 27-node cells
    and the contact's outline, a circle of the file's area at zero load; at full sliding Ft = tau A within 0.5 % with
    the area on the surface points (as H1 in tests/test_sliding_3d.py)."""
    p = Parameters.from_config(load_config(["sphere"], [
        "mesh.element=H2", "mesh.size=440", "mesh.surface_gauss_points=4", "loading.approach_edge_step=1.0",
        "loading.max_slide_step=0.3", "friction.model=DI", "loading.ubar_max=3.0", "output.snapshot_ubar=[0.0]",
        "solver.linear=lu_krylov"]))
    result = run_case(p)
    case_dataset(result).to_netcdf(tmp_path / "h2.nc")
    ds = xr.open_dataset(tmp_path / "h2.nc")
    assert ds.attrs["status"] == "completed", ds.attrs.get("status_reason")
    assert ds["cell_nodes"].shape[1] == 27
    x, y = ds["outline_x"].values[0], ds["outline_y"].values[0]
    radius = np.hypot(x, y)[np.isfinite(x)]
    zero_load = float(ds["area"].values[ds["phase"].values == int(Phase.PRELOAD)][-1])
    assert math.pi * np.mean(radius) ** 2 == pytest.approx(zero_load, rel=0.03)  # 2.2 % at this mesh
    state = ds.isel(step=-1).slip_state.values
    assert (state == SlipState.SLIP).any() and not (state == SlipState.STICK).any()
    c = SurfaceContact(result.mesh, p.adhesion, p.mesh.surface_gauss_points, far_gap=p.contact.far_gap)
    u, h = result.final_x[:-1], result.final_x[-1]
    g, _ = c.gaps(u, h)
    J = stretch(c.quad.current(u)[1], c.quad.ref_measure, 3)
    A_points = 2.0 * float(np.sum((c.quad.weight * J)[g <= p.contact.area_gap]))
    assert float(ds.isel(step=-1).Ft) / (p.friction.tau_DI * A_points) == pytest.approx(1.0, abs=0.005)
