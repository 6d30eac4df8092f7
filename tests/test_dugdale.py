"""The Dugdale verification law (laws/dugdale.py, adhesion.law = dugdale): its work, slopes and potential; on a
half-space it is the Maugis-Dugdale sphere (Maugis 1992); the 3D contact's tangent with it against finite
differences; and the configuration rules that keep it a frictionless verification law."""

import numpy as np
import pytest

from capslide.config import ConfigError, apply_overrides, load_config, scene_path, validate
from capslide.fem.assembly import rigid_body_modes
from capslide.fem.hex_mesh import SphereCapSpec, sphere_cap_mesh
from capslide.laws import analytic, sphere
from capslide.laws.dugdale import DugdaleLaw
from capslide.laws.normal import CGCMLaw, normal_law
from capslide.model.constraints import FixedForce, FixedHeight
from capslide.model.system import CapModel, History
from capslide.params import Parameters
from capslide.solvers.linsolve import make_solver
from capslide.studies.halfspace_sphere import same_law_reference

from fe_helpers import check_bordered_jacobian, pressed_sphere_state

LAW = DugdaleLaw.from_work(sigma0=0.2, W=0.03, g_eq=0.1, ramp=0.8, penalty=0.005)


def test_the_law_has_dugdales_stress_work_and_edge():
    h0 = 0.03 / 0.2
    assert LAW.g_edge == pytest.approx(0.1 + 0.005 * h0)
    g = np.array([LAW.g_eq, LAW.g_edge, LAW.g_edge + 0.01 * h0, LAW.g_end - 0.5 * LAW.rho, LAW.g_end,
                  LAW.g_end + 0.5 * LAW.rho, 10.0])
    Tn, _ = LAW.traction(g)
    np.testing.assert_allclose(Tn, [0.0, -0.2, -0.2, -0.2, -0.1, 0.0, 0.0], atol=1e-15)
    assert LAW.potential(LAW.g_eq) == pytest.approx(-0.03, rel=1e-13)  # the work of separation is W
    assert LAW.potential(10.0) == 0.0
    assert LAW.traction(LAW.g_eq - 1e-3)[0] == pytest.approx(0.2 * 1e-3 / (0.005 * h0))  # the repulsion's slope


def test_the_slope_and_the_potential_against_central_differences():
    """dTn/dg and -dphi/dg = Tn away from the four kinks (a central difference across a kink is neither slope)."""
    g = np.linspace(0.05, 0.4, 3001)
    kinks = np.array([LAW.g_edge, LAW.g_end - 0.5 * LAW.rho, LAW.g_end + 0.5 * LAW.rho])
    g = g[np.min(np.abs(g[:, None] - kinks[None, :]), axis=1) > 1e-6]
    eps = 1e-8
    Tn, dTn = LAW.traction(g)
    fd = (LAW.traction(g + eps)[0] - LAW.traction(g - eps)[0]) / (2 * eps)
    np.testing.assert_allclose(dTn, fd, atol=1e-6 * np.abs(dTn).max())
    dphi = (LAW.potential(g + eps) - LAW.potential(g - eps)) / (2 * eps)
    np.testing.assert_allclose(-dphi, Tn, atol=1e-6 * 0.2)
    # the cut at g_far: phi(g) - phi(g_far) below it, zero from it on
    cut = LAW.potential(g, g_far=0.15)
    np.testing.assert_allclose(cut, np.where(g < 0.15, LAW.potential(g) - LAW.potential(0.15), 0.0), atol=1e-16)


def test_the_configuration_chooses_the_law():
    cgcm = Parameters.from_config(load_config([scene_path("sphere_md3")]))
    dugdale = Parameters.from_config(load_config([scene_path("sphere_dugdale3")]))
    assert isinstance(normal_law(cgcm.adhesion), CGCMLaw)
    law = normal_law(dugdale.adhesion)
    assert isinstance(law, DugdaleLaw) and law.sigma0 == dugdale.adhesion.T_max
    # the contact edge is the law's (the area's gap); the edge control holds a gap on the tension's plateau, away
    # from the law's kinks (at the kink the spread moved by hundredths of L0 a step: docs/three_d.md)
    assert dugdale.adhesion.g_max == pytest.approx(law.g_edge, rel=1e-15)
    assert dugdale.contact.area_gap == dugdale.adhesion.g_max
    h0 = dugdale.adhesion.W_adh / dugdale.adhesion.T_max
    assert law.g_edge + 0.2 * h0 < dugdale.loading.approach_end_gap < law.g_end - 0.5 * law.rho - 0.2 * h0


@pytest.mark.parametrize("override, message", [
    ("friction.model=DI", "friction.model = DI is not allowed with adhesion.law = dugdale"),
    ("adhesion.law=cgcm", "adhesion.dugdale_ramp = 0.5 is not allowed with adhesion.law = cgcm"),
])
def test_the_dugdale_law_is_a_frictionless_verification_law(override, message):
    cfg = load_config([scene_path("sphere_dugdale3")])
    with pytest.raises(ConfigError, match=message):
        validate(apply_overrides(cfg, ["adhesion.dugdale_ramp=0.5" if "cgcm" in override else "friction.tau_DI=null",
                                       override]))


@pytest.mark.parametrize("lam", [3.0, pytest.param(5.0, marks=pytest.mark.slow)])  # lambda = 5: 3 min
def test_on_a_half_space_the_law_is_the_maugis_dugdale_sphere(lam):
    """The scene's law on the half-space with MD's paraboloid (studies/halfspace_sphere.py): the pull-off within
    0.5 % of Maugis-Dugdale's and P(a) within 1 % of |P_c| up to past the zero-load radius; the CGCM law at the
    same lambda misses both (docs/three_d.md), so this checks the law's shape, not only its constants."""
    p = Parameters.from_config(load_config([scene_path("sphere_dugdale3")], [f"adhesion.maugis_lambda={lam}"]))
    E_star = analytic.effective_modulus(p.material.E, p.material.nu)
    scales = sphere.md_scales(p.geometry.R, E_star, p.adhesion.W_adh)
    P_c = sphere.md_pull_off(lam)[0] * scales["load"]
    ref = same_law_reference(p, 1.05 * sphere.md_zero_load_radius(lam) * scales["radius"], profile="paraboloid")
    assert ref.P_c == pytest.approx(P_c, rel=5e-3)
    P_md = np.array([float(sphere.md_load(a / scales["radius"], lam)) * scales["load"] for a in ref.radii])
    assert np.max(np.abs(ref.loads - P_md)) < 0.01 * abs(P_c)


@pytest.fixture(scope="module")
def dugdale_model(paper_config):
    cfg = validate(apply_overrides(paper_config, ["friction.model=none", "adhesion.law=dugdale"]))
    p = Parameters.from_config(cfg)
    mesh = sphere_cap_mesh(SphereCapSpec(R=47.1, H=10.0, h0=0.8, band_radius=4.0, max_size_over_H=0.4))
    return CapModel(mesh, p, make_solver("amg", near_null_space=rigid_body_modes(mesh.nodes)))


@pytest.mark.parametrize("constraint", [FixedHeight(10.1), FixedForce(-0.1)], ids=["h", "Fn"])
def test_the_3d_contact_tangent_with_the_dugdale_law(dugdale_model, constraint):
    x = pressed_sphere_state(dugdale_model, shear=0.05)
    g, _ = dugdale_model.contact.gaps(x[:-1], x[-1])
    law = dugdale_model.contact.normal_law
    pieces = [g < law.g_edge, (g > law.g_edge) & (g < law.g_end - 0.5 * law.rho),
              np.abs(g - law.g_end) < 0.5 * law.rho, g > law.g_end + 0.5 * law.rho]
    assert all(piece.any() for piece in pieces)  # points in the repulsion, on the plateau, on the ramp, beyond
    check_bordered_jacobian(dugdale_model, x, constraint, History(), directions=3)


def test_the_dugdale_contact_energy_is_the_potential_of_its_force(dugdale_model):
    """d(adhesion energy)/dh = Fn-consistent: the energy's derivative in the height is the contact force's z sum
    (twice the half's), by central differences."""
    x = pressed_sphere_state(dugdale_model, shear=0.05)
    c, u, h = dugdale_model.contact, x[:-1], x[-1]
    eps = 1e-7
    dE = (c.adhesion_energy(u, h + eps) - c.adhesion_energy(u, h - eps)) / (2 * eps)
    _, Fn, _ = c.force(u, h)
    assert dE == pytest.approx(Fn, rel=1e-6)
