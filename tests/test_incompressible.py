"""The mixed Q2/P1 bulk (fem.mixed): exact tangent, the same material as the displacement form, the augmented
Lagrangian at nu = 0.5, Cook's membrane, Hertz line contact of an incompressible body, and the cap's contact area
as nu -> 0.5 (issue 17, item 6)."""

from pathlib import Path

import numpy as np
import pytest

from capslide.config import ConfigError, load_config
from capslide.fem.assembly import BulkForm
from capslide.fem.mesh import rectangle_mesh
from capslide.fem.mixed import VOLUME_TOLERANCE, MixedBulkForm
from capslide.io.checkpoint import path_state, state_arrays
from capslide.loadpath.cap import PathState, load_path
from capslide.loadpath.continuation import drain
from capslide.model.build import build_model
from capslide.model.system import History
from capslide.params import Parameters
from capslide.states import Status
from capslide.studies import membrane
from capslide.studies.verification import sweep

ROOT = Path(__file__).resolve().parents[1]
CONFIG = ROOT / "config" / "config.yaml"


@pytest.fixture
def mesh():
    return rectangle_mesh(3, 2, 1.0, 0.7, "Q2", distortion=0.3, seed=1)


@pytest.mark.parametrize("lam", [5.0, 4999.0, np.inf])
def test_tangent_and_forces_are_exact_derivatives(mesh, lam):
    """K = d f_int / du (central differences, error ~ eps^2) and f_int = d(strain energy)/du, with a random
    multiplier at lam = inf; K is symmetric (a potential)."""
    rng = np.random.default_rng(0)
    form = MixedBulkForm(mesh, lam, 0.4)
    u = 0.01 * rng.standard_normal(mesh.n_dofs)
    multiplier = rng.standard_normal((mesh.n_cells, 3)) if np.isinf(lam) else None
    f, K = form.residual_and_tangent(u, multiplier)
    np.testing.assert_array_equal(f, form.residual(u, multiplier))
    v = rng.standard_normal(mesh.n_dofs)
    eps = 1e-6
    fd = (form.residual(u + eps * v, multiplier) - form.residual(u - eps * v, multiplier)) / (2 * eps)
    assert np.abs(fd - K @ v).max() < 1e-8 * np.abs(K @ v).max()
    h = 1e-7
    dE = (form.strain_energy(u + h * v, multiplier) - form.strain_energy(u - h * v, multiplier)) / (2 * h)
    assert dE == pytest.approx(f @ v, rel=1e-6)
    assert abs(K - K.T).max() < 1e-10 * abs(K).max()


def test_homogeneous_deformation_gives_the_displacement_forms_forces(mesh):
    """The same neo-Hooke law: where J is uniform theta = J, so forces, energy and I1(sigma) equal those of the
    displacement form."""
    F = np.array([[1.1, 0.2], [-0.05, 0.93]])
    u = (mesh.nodes @ (F - np.eye(2)).T).ravel()
    mixed, plain = MixedBulkForm(mesh, 3.0, 0.4), BulkForm(mesh, 3.0, 0.4)
    np.testing.assert_allclose(mixed.residual(u), plain.residual(u), atol=1e-12)
    assert mixed.strain_energy(u) == pytest.approx(plain.strain_energy(u), rel=1e-13)
    np.testing.assert_allclose(mixed.cell_first_invariant(u), plain.cell_first_invariant(u), rtol=1e-12)
    np.testing.assert_allclose(mixed.dilatation(u), np.linalg.det(F), rtol=1e-13)


def test_uzawa_update_is_the_pressure_and_a_rigid_motion_is_free(mesh):
    rng = np.random.default_rng(2)
    form = MixedBulkForm(mesh, np.inf, 0.4)
    u = 0.01 * rng.standard_normal(mesh.n_dofs)
    multiplier = rng.standard_normal((mesh.n_cells, 3))
    c = form.pressure_coefficients(u, multiplier)
    np.testing.assert_allclose(np.einsum("eqm,em->eq", form.Np, c), form.pressure(u, multiplier), atol=1e-12)
    rotation = np.array([[np.cos(0.3), -np.sin(0.3)], [np.sin(0.3), np.cos(0.3)]])
    rigid = (mesh.nodes @ (rotation - np.eye(2)).T).ravel()
    assert form.volume_error(rigid) < 1e-14
    assert abs(form.residual(rigid)).max() < 1e-13 and abs(form.strain_energy(rigid)) < 1e-13  # rigid: no stress


def test_mixed_needs_q2():
    with pytest.raises(ValueError, match="Q2"):
        MixedBulkForm(rectangle_mesh(2, 2), 1.0, 1.0)


def test_nu_one_half_is_accepted_only_with_the_mixed_formulation():
    p = Parameters.from_config(load_config([CONFIG], ["material.nu=0.5", "mesh.element=Q2",
                                                       "mesh.formulation=mixed"]))
    assert np.isinf(p.material.lam) and p.material.mu == pytest.approx(1 / 3)
    for sets in (["material.nu=0.5"], ["material.nu=0.5", "mesh.element=Q2"],
                 ["mesh.formulation=mixed", "mesh.element=Q1"]):
        with pytest.raises(ConfigError, match="mesh.formulation = mixed"):
            load_config([CONFIG], sets)
    # the displacement form's refusal of locking Poisson's ratios does not apply to the mixed one
    load_config([CONFIG], ["material.nu=0.4999", "mesh.element=Q2", "mesh.formulation=mixed"])


def test_checkpoints_carry_the_pressure_multiplier():
    pressure = np.arange(12.0).reshape(4, 3)
    arrays, header = state_arrays(PathState("slide", np.zeros(5), History(pressure=pressure)))
    np.testing.assert_array_equal(path_state(arrays, header).history.pressure, pressure)


# -- Cook's membrane ------------------------------------------------------------

def test_cook_membrane_setup_matches_the_published_compressible_value():
    """Plane strain, E = 70, nu = 1/3, load 100: very fine quadratic meshes give 32.27 (Calculix, Elmer) and 32.20
    (Code_Aster), as collected by CoFEA (benchmark 002). This checks geometry, clamping and load."""
    E, nu = 70.0, 1.0 / 3.0
    lam, mu = E * nu / ((1 + nu) * (1 - 2 * nu)), E / (2 * (1 + nu))
    tip = membrane.tip_deflection(16, lam, mu, 1e-4, "Q2", "displacement").tip / 1e-4 * 100.0
    assert tip == pytest.approx(32.27, rel=0.005)


def test_cook_membrane_nearly_incompressible_converges_and_q1_locks():
    """de Souza Neto et al. (1996): mu = 80.1938, bulk modulus 400942 (nu = 0.4999), load 100, finite strain. The
    mixed element converges from below to about 6.93 (benchmarks/cooks_membrane.py); OpenGeoSys's F-bar Q1
    benchmark of the same problem gives 6.891 on 30 x 30 cells, still rising. Q1 locks at a third of it."""
    mu = 80.1938
    lam = 400942.0 - 2.0 * mu / 3.0
    tips = [membrane.tip_deflection(n, lam, mu, 100.0, "Q2", "mixed", steps=20).tip for n in (4, 8, 16)]
    assert tips[0] < tips[1] < tips[2]
    assert tips[2] - tips[1] < 0.6 * (tips[1] - tips[0])  # converging
    assert tips[2] == pytest.approx(6.891, rel=0.005)
    locked = membrane.tip_deflection(16, lam, mu, 100.0, "Q1", "displacement", steps=20).tip
    assert locked < 0.4 * tips[2]


def test_cook_membrane_exactly_incompressible_meets_the_constraint():
    """At nu = 0.5 Uzawa's iteration ends with max |theta - 1| <= VOLUME_TOLERANCE, and the tip agrees with the
    nearly incompressible one (nu = 0.4999) to the order of mu / K."""
    mu = 80.1938
    exact = membrane.tip_deflection(8, np.inf, mu, 100.0, "Q2", "mixed", steps=20)
    near = membrane.tip_deflection(8, 400942.0 - 2.0 * mu / 3.0, mu, 100.0, "Q2", "mixed", steps=20)
    assert exact.volume_error <= VOLUME_TOLERANCE
    assert exact.tip == pytest.approx(near.tip, rel=2e-3)


# -- contact ------------------------------------------------------------------------

@pytest.mark.slow
def test_hertz_line_contact_of_an_incompressible_body():
    """The Hertz scene at nu = 0.5 (E* = 4E/3) on a mesh 2x coarser than the scene's: the half-width within 1 % of
    sqrt(4 P R / (pi E*)) (measured +0.53 %). About 20 s."""
    cfg = load_config([ROOT / "config" / "scenes" / "hertz.yaml"],
                      ["mesh.size=40", "verification.loads=[0.3]", "material.nu=0.5", "mesh.formulation=mixed"])
    rows = {r.quantity: r for r in sweep(Parameters.from_config(cfg), "hertz")}
    assert rows["half_width"].theory == pytest.approx(np.sqrt(4 * 0.3 * 200.0 / (np.pi * 4.0 / 3.0)), rel=1e-12)
    assert abs(rows["half_width"].rel_error) < 0.01


def test_the_load_path_meets_the_volume_constraint_at_nu_one_half():
    """Every converged step of the load path ends Uzawa's iteration: max |theta - 1| <= VOLUME_TOLERANCE, with the
    multiplier carried in the history (the Hertz scene, coarse, preloaded to P = 0.05). About 5 s."""
    cfg = load_config([ROOT / "config" / "scenes" / "hertz.yaml"],
                      ["mesh.size=80", "material.nu=0.5", "mesh.formulation=mixed", "loading.preload=-0.05"])
    model = build_model(Parameters.from_config(cfg))
    steps = []
    assert drain(load_path(model, stop_before="slide"), steps.append).status == Status.COMPLETED
    for step in steps[-3:]:
        assert model.bulk.volume_error(step.x[:-1]) <= VOLUME_TOLERANCE
    assert np.abs(steps[-1].state.history.pressure).max() > 0.0
    assert steps[-1].record.Fn == pytest.approx(-0.05, abs=1e-9)


@pytest.mark.slow
def test_the_caps_zero_load_area_is_smooth_up_to_nu_one_half():
    """The paper's cap at zero load (Q2/P1, mesh.size 32): the contact areas at nu = 0.499, 0.4999 and 0.5 agree
    to 0.5 % (measured: 0.05 %), and the area falls monotonically from nu = 0.4. About 6 min."""
    def area(nu):
        cfg = load_config([CONFIG], ["mesh.element=Q2", "mesh.formulation=mixed", "mesh.size=32",
                                     f"material.nu={nu}", "loading.preload=0.0"])
        records = []
        drain(load_path(build_model(Parameters.from_config(cfg)), stop_before="slide"),
              lambda step: records.append(step.record))
        return records[-1].area

    areas = [area(nu) for nu in (0.4, 0.499, 0.4999, 0.5)]
    assert areas[0] > areas[1] > areas[2] > areas[3]
    assert max(areas[1:]) / min(areas[1:]) - 1.0 < 0.005
