"""The viscoelastic bulk (issue 18): Green and Tobolsky's transient-network branches on the neo-Hooke law.

Checks: relaxation of a homogeneous block under a step shear and a step stretch against the closed-form Prony
series; the limits tau -> 0 and tau -> infinity against neo-Hooke cases run with the long-time and the
instantaneous modulus; the exact algorithmic tangent against finite differences mid-relaxation; dissipation >= 0 at
every quadrature point and step of a sliding cap, equal to the energy the branches' stress works off; the observed
order of the time integration.
"""

from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from capslide.config import ConfigError, apply_overrides, load_config, validate
from capslide.driver.case import run_case
from capslide.driver.observers import Observer
from capslide.fem.assembly import BulkForm
from capslide.fem.mesh import rectangle_mesh
from capslide.fem.mixed import MixedBulkForm
from capslide.fem.viscous import Networks, ViscousBranches
from capslide.io.checkpoint import path_state, state_arrays
from capslide.io.results import case_dataset
from capslide.laws import viscoelastic as ve
from capslide.loadpath.cap import PathState
from capslide.model.build import build_model
from capslide.model.system import History
from capslide.params import Parameters, lame_plane_strain
from capslide.states import Phase, Status

ROOT = Path(__file__).resolve().parents[1]
CONFIG = ROOT / "config" / "config.yaml"
LAM, MU = lame_plane_strain(1.0, 0.4)
G, TAU = np.array([0.5, 1.2]), np.array([0.3, 4.0])  # two branches: relative moduli, relaxation times (s)
COARSE = ["preset=fast", "mesh.size=32", "loading.ubar_max=2.6", "loading.max_slide_step=0.2", "output.snapshot_ubar=[]",
          "loading.preload=0.0", "loading.velocity=1e-6"]  # v = 1 L0/s


def viscoelastic(tau, g=0.5):
    return ["material.model=viscoelastic", f"material.prony=[{{g: {g}, tau: {tau}}}]"]


def block_response(F_of_t, times, element="Q1", mixed=False):
    """Drive a one-cell block through the homogeneous deformations F_of_t(t) at ``times`` (the first at t = 0 from
    the undeformed state, instantaneously); the first Piola stress (bulk + branches) at each time from the
    boundary forces: P_x2 and P_y2 from the top edge, P_x1 from the right edge."""
    mesh = rectangle_mesh(1, 1, 1.0, 1.0, element)
    bulk = MixedBulkForm(mesh, LAM, MU) if mixed else BulkForm(mesh, LAM, MU)
    branches = ViscousBranches(bulk, MU, G, TAU)
    X = mesh.nodes
    top, right = X[:, 1] > 1 - 1e-12, X[:, 0] > 0.5 - 1e-12  # the block is [-1/2, 1/2] x [0, 1]
    state, t_prev, out = None, 0.0, []
    for t in times:
        F = F_of_t(t)
        u = (X @ (F - np.eye(2)).T).ravel()
        dt = t - t_prev
        f = (bulk.residual(u) + branches.residual(u, state, dt)).reshape(-1, 2)
        out.append([f[top, 0].sum(), f[top, 1].sum(), f[right, 0].sum()])
        state, t_prev = branches.committed(u, state, dt), t
    return np.array(out)


def test_step_shear_relaxes_as_the_prony_series():
    """Simple shear gamma = 0.01 applied at t = 0 and held: sigma_xy(t) = gamma mu (1 + sum g_i exp(-t/tau_i))
    to 1e-3 (the branch is exact at finite strain in simple shear: measured ~1e-12)."""
    gamma = 0.01
    times = np.concatenate([[0.0], np.geomspace(1e-3, 30.0, 25)])
    P = block_response(lambda t: np.array([[1.0, gamma], [0.0, 1.0]]), times)
    sigma_xy = P[:, 0]  # J = 1, sigma = P F^T: sigma_xy = P_x2
    expected = gamma * ve.prony_shear_modulus(times, MU, G, TAU)
    np.testing.assert_allclose(sigma_xy, expected, rtol=1e-3)
    assert sigma_xy[0] / sigma_xy[-1] == pytest.approx(1 + G.sum(), rel=1e-3)  # instantaneous over relaxed


def test_step_stretch_relaxes_as_the_prony_series():
    """Plane-strain stretch eps = 1e-3 applied at t = 0 and held: sigma_xx(t) = (Lambda + 2 mu(t)) eps with mu(t)
    the Prony series (the branches relax mu at fixed Lambda), to 1e-3; sigma_yy = Lambda eps does not relax."""
    eps = 1e-3
    times = np.concatenate([[0.0], np.geomspace(1e-3, 30.0, 25)])
    P = block_response(lambda t: np.diag([1.0 + eps, 1.0]), times)
    sigma_xx, sigma_yy = P[:, 2], P[:, 1] / (1.0 + eps)  # sigma = P F^T / J, F = diag(1 + eps, 1)
    np.testing.assert_allclose(sigma_xx, (LAM + 2 * ve.prony_shear_modulus(times, MU, G, TAU)) * eps, rtol=1e-3)
    np.testing.assert_allclose(sigma_yy, LAM * eps, rtol=1e-3)


def test_the_mixed_bulk_carries_the_branches():
    """With the mixed Q2/P1 bulk at nu = 0.5 the branches add the same shear relaxation (isochoric simple shear:
    theta = 1, no pressure)."""
    gamma = 0.01
    times = np.array([0.0, 0.1, 1.0, 10.0])
    mesh = rectangle_mesh(1, 1, 1.0, 1.0, "Q2")
    bulk = MixedBulkForm(mesh, np.inf, MU)
    branches = ViscousBranches(bulk, MU, G, TAU)
    u = (mesh.nodes @ np.array([[0.0, gamma], [0.0, 0.0]]).T).ravel()
    top = mesh.nodes[:, 1] > 1 - 1e-12
    state, t_prev = None, 0.0
    for t in times:
        f = (bulk.residual(u) + branches.residual(u, state, t - t_prev)).reshape(-1, 2)
        assert f[top, 0].sum() == pytest.approx(gamma * ve.prony_shear_modulus(t, MU, G, TAU), rel=1e-3)
        state, t_prev = branches.committed(u, state, t - t_prev), t


@pytest.mark.parametrize("form", [BulkForm, MixedBulkForm])
def test_tangent_is_the_exact_derivative_mid_relaxation(form):
    """After two committed steps (networks away from I and from C^-1), the branches' tangent at a step of dt =
    0.4 s equals central differences of their forces (error ~ eps^2) and is symmetric."""
    rng = np.random.default_rng(3)
    mesh = rectangle_mesh(3, 2, 1.0, 0.7, "Q2", distortion=0.3, seed=1)
    branches = ViscousBranches(form(mesh, LAM, MU), MU, G, TAU)
    state = None
    for dt in (0.0, 0.5):
        state = branches.committed(0.01 * rng.standard_normal(mesh.n_dofs), state, dt)
    assert np.abs(state.networks - np.eye(2)).max() > 1e-3
    assert np.abs(state.networks - state.c_inv[..., None, :, :]).max() > 1e-3
    u = 0.01 * rng.standard_normal(mesh.n_dofs)
    assert branches.bulk.min_jacobian(u) > 0.5
    f, data = branches.residual_and_tangent_data(u, state, 0.4)
    K = branches.bulk.pattern.matrix(data)
    np.testing.assert_array_equal(f, branches.residual(u, state, 0.4))
    v = rng.standard_normal(mesh.n_dofs)
    errors = []
    for eps in (1e-5, 1e-6):
        fd = (branches.residual(u + eps * v, state, 0.4) - branches.residual(u - eps * v, state, 0.4)) / (2 * eps)
        errors.append(np.abs(fd - K @ v).max() / np.abs(K @ v).max())
    assert errors[1] < 1e-9 and errors[1] < 0.05 * errors[0]  # falls as eps^2 (measured 1.9e-8, 1.9e-10)
    assert abs(K - K.T).max() < 1e-12 * abs(K).max()


def test_time_integration_is_second_order():
    """P_x1 = S_xx + gamma S_xy at the end of a finite simple-shear ramp (gamma 0 -> 0.5 over 2 s, then held 1 s)
    with the step halved three times: the observed order is 2. (C^-1_xx = 1 + gamma^2 is not linear in time, so the
    integrator is not exact there; sigma_xy would be, as C^-1_xy = -gamma is.)"""
    def F(t):
        return np.array([[1.0, 0.25 * min(t, 2.0)], [0.0, 1.0]])

    def final(n):
        return block_response(F, np.linspace(0.0, 3.0, n + 1))[-1, 2]

    reference = final(8192)
    errors = np.array([abs(final(n) - reference) for n in (12, 24, 48, 96)])
    orders = np.log2(errors[:-1] / errors[1:])
    assert np.all(np.abs(orders - 2.0) < 0.1), orders


def test_step_dissipation_is_the_work_the_branches_lose():
    """Along a step, the branch stress's work minus the change of the branch energy equals the time integral of
    the dissipation rate (>= 0): the update is consistent with the energy. A wrong update breaks it."""
    rng = np.random.default_rng(5)
    F0 = np.eye(2) + 0.1 * rng.standard_normal((50, 2, 2))
    F1 = F0 + 0.05 * rng.standard_normal((50, 2, 2))
    A = ve.updated_networks(np.broadcast_to(np.eye(2), (50, 2, 2, 2)), np.broadcast_to(np.eye(2), (50, 2, 2)),
                            ve.inverse_right_cauchy_green(F0 + 0.1 * rng.standard_normal((50, 2, 2))),
                            *ve.step_weights(0.7, TAU))
    for dt in (0.05, 0.5, 5.0):
        by_work, by_rate = ve.step_dissipation(F0, F1, A, G * MU, TAU, dt, points=64)
        assert by_rate.min() > 0.0
        np.testing.assert_allclose(by_work, by_rate, rtol=1e-11)  # the quadrature's error: measured 1e-14


def run_limit(paper_config, tau):
    p = Parameters.from_config(validate(apply_overrides(paper_config, [*COARSE, *viscoelastic(tau)])))
    return p, run_case(p)


def step_table(result):
    return np.array([[r.Fn, r.Ft, r.h, r.area, r.ubar] for r in result.records])


@pytest.mark.parametrize("tau, modulus", [pytest.param(1e-12, "long-time", marks=pytest.mark.slow),
                                          (1e12, "instantaneous")])
def test_limits_are_neo_hooke_cases(paper_config, tau, modulus):
    """tau -> 0 reproduces the neo-Hooke case with the long-time mu, tau -> infinity the one with the
    instantaneous mu (1 + g) and the same Lambda: every step's Fn, Ft, h, area to 1e-6 (DI, zero load, coarse)."""
    p, visco = run_limit(paper_config, tau)
    mu = p.material.mu * (1.0 + 0.5 if modulus == "instantaneous" else 1.0)
    elastic = replace(p, material=replace(p.material, mu=mu, prony_g=(), prony_tau=()))
    plain = run_case(elastic)
    assert visco.status == plain.status == Status.COMPLETED
    a, b = step_table(visco), step_table(plain)
    assert a.shape == b.shape
    difference = np.abs(a - b).max(axis=0) / np.abs(b).max(axis=0)
    assert difference.max() < 1e-6, difference
    assert visco.records[-1].time > 0.0


class StateKeeper(Observer):
    """Keeps (record, x, history after the step) of every converged step (the path state is a live object)."""

    def __init__(self):
        self.steps = []

    def step(self, step):
        self.steps.append((step.record, step.x, step.state.history))


def dissipation_and_balance(paper_config, *sets):
    """A sliding cap at Deborah number tau v / L0 = 1 (DI, zero load, coarse): per step after the first, the
    energy the branches dissipate (summed over the cap), what the case file's energy balance leaves over
    (energy_residual: the loads' work minus the stored energy and the frictional dissipation), and the phase.
    Asserts at every quadrature point and step that the dissipation, the branch stress's work minus the change of
    the branch energy, is >= 0 and equals the integrated rate."""
    p = Parameters.from_config(validate(apply_overrides(paper_config, [*COARSE, *viscoelastic(1.0), *sets])))
    keeper = StateKeeper()
    result = run_case(p, observers=[keeper])
    assert result.status == Status.COMPLETED
    model = build_model(p)
    bulk, branches = model.bulk, model.branches
    before, F0, t0 = branches.start(), bulk.deformation_gradient(np.zeros(model.n_dofs)).copy(), 0.0
    # the rounding of the energy's O(1) terms tr(C A) - 2 - ln det C - ln det A: 1e-14 of g mu (measured 1e-16
    # absolute where D ~ 1e-13 in the first steps); the quadrature's error in time: rtol
    rounding = 1e-14 * branches.moduli.sum()
    dissipated = []
    for record, x, history in keeper.steps:
        F1 = bulk.deformation_gradient(x[:-1]).copy()
        by_work, by_rate = ve.step_dissipation(F0, F1, before.networks, branches.moduli, branches.tau,
                                               record.time - t0, points=16)
        assert by_rate.min() >= 0.0 and by_work.min() >= -rounding
        np.testing.assert_allclose(by_work, by_rate, rtol=1e-6, atol=rounding)
        dissipated.append(float(np.sum(by_work * bulk.wdetJ)))
        before, F0, t0 = history.networks, F1, record.time
    left_over = np.diff(case_dataset(result).energy_residual.values)
    return np.array(dissipated)[1:], left_over, np.array([r.phase for r in result.records])[1:]


def test_dissipation_is_nonnegative_and_closes_the_energy_balance(paper_config):
    """The branches' dissipation is what the energy balance leaves over at every preload and slide step, up to
    the trapezoidal rule of the loads' work: over each leg to 1 % (measured 0.65 % in the preload, 0.08 % in the
    slide), and with the force steps halved the preload's worst step closes 4x better at least (third order:
    measured 7.6x). The approach is left out: its jump-in is a snap, a jump of the balance in the elastic case
    too."""
    dissipated, left_over, phase = dissipation_and_balance(paper_config)
    for leg in (Phase.PRELOAD, Phase.SLIDE):
        mine = phase == leg
        assert left_over[mine].sum() == pytest.approx(dissipated[mine].sum(), rel=1e-2)
    assert dissipated[phase == Phase.SLIDE].sum() > 0.1  # E L0^2: the branches do dissipate
    worst = np.abs(left_over - dissipated)[phase == Phase.PRELOAD].max()
    dissipated, left_over, phase = dissipation_and_balance(paper_config, "loading.force_step=0.01", "loading.ubar_max=0")
    assert np.abs(left_over - dissipated)[phase == Phase.PRELOAD].max() < worst / 4


def test_dwell_relaxes_at_fixed_force(paper_config):
    """A dwell of 5 tau at the preload under force control: time advances by the dwell, Fn stays at the preload,
    and the relaxing bulk lets the contact grow (creep) at every step."""
    p = Parameters.from_config(validate(apply_overrides(paper_config, [*COARSE, *viscoelastic(1.0),
                                                                       "loading.dwell=5.0", "loading.ubar_max=0"])))
    result = run_case(p)
    assert result.status == Status.COMPLETED
    dwell = [r for r in result.records if r.phase == Phase.DWELL]
    preload_end = [r for r in result.records if r.phase == Phase.PRELOAD][-1]
    assert dwell[-1].time - preload_end.time == pytest.approx(5.0, rel=1e-12)
    assert np.abs([r.Fn for r in dwell]).max() < 1e-9
    area = np.array([preload_end.area] + [r.area for r in dwell])
    assert np.all(np.diff(area) > 0.0)


def test_checkpoints_carry_the_networks_and_time():
    networks = Networks(np.random.default_rng(0).random((2, 4, 3, 2, 2)), np.random.default_rng(1).random((2, 4, 2, 2)))
    arrays, header = state_arrays(PathState("slide", np.zeros(5), History(networks=networks, time=2.5)))
    back = path_state(arrays, header).history
    np.testing.assert_array_equal(back.networks.networks, networks.networks)
    np.testing.assert_array_equal(back.networks.c_inv, networks.c_inv)
    assert back.time == 2.5


@pytest.mark.parametrize("sets, key", [
    (["material.model=viscoelastic"], "material.prony"),
    (["material.model=viscoelastic", "material.prony=[{g: 0.5, tau: 1.0}]"], "loading.velocity"),
    (["material.prony=[{g: 0.5, tau: 1.0}]", "loading.velocity=1e-6"], "material.prony"),
    (["material.model=viscoelastic", "material.prony=[{g: 0.5, tau: 0}]", "loading.velocity=1e-6"], "tau"),
    (["loading.velocity=-1"], "loading.velocity"),
])
def test_bad_viscoelastic_inputs_are_refused(sets, key):
    with pytest.raises(ConfigError, match=key.replace(".", r"\.")):
        load_config([CONFIG], sets)
