"""Contact integral and the bordered system: exact linearization, force measures."""

import numpy as np
import pytest

from capslide.config import apply_overrides, validate
from capslide.fem.mesh import CapMeshSpec, cap_mesh
from capslide.loadpath.measures import interval_measures
from capslide.model.build import build_model
from capslide.model.constraints import FixedApexGap, FixedEdgeGap, FixedForce, FixedHeight, SlideAtForce, SlideOnSpring
from capslide.model.system import History
from capslide.params import Parameters
from capslide.states import SlipState

from fe_helpers import apply_bordered_jacobian, check_bordered_jacobian


def _model(paper_config, element, overrides=()):
    cfg = validate(apply_overrides(paper_config, ["solver.linear=direct", *overrides]))
    p = Parameters.from_config(cfg)
    mesh = cap_mesh(CapMeshSpec(R=47.1, H=10.0, h0=0.25, band_half_width=6.0, element=element))
    return build_model(p, mesh)


def _state(model, seed=0):
    """A deformed state with the surface near the substrate: gaps spread over both sides of g_eq and g_max."""
    rng = np.random.default_rng(seed)
    X = model.mesh.nodes
    a = model.params.adhesion
    u = np.zeros(model.n_dofs)
    u[1::2] = 0.3 * a.r0 * np.exp(-(X[:, 0] / 3.0) ** 2) * X[:, 1] / 10
    u[0::2] = 0.05 * X[:, 1] / 10
    u += 1e-3 * a.r0 * rng.normal(size=model.n_dofs)
    u[model.bc.dofs] = 0.0
    h = 10.0 + 0.3 * a.r0 + 0.9 * a.g_eq
    return np.concatenate([u, [h]])


@pytest.mark.parametrize("element", ["Q1", "Q2"])
@pytest.mark.parametrize("constraint", [FixedHeight(10.1), FixedForce(-0.1), FixedApexGap(0.09), FixedEdgeGap(0.37, 0.09),
                                        SlideOnSpring(0.0, -0.1, 10.05, 3.0)],
                         ids=["h", "Fn", "apex", "edge", "spring"])
@pytest.mark.parametrize("normal_area", ["reference", "current"])
def test_bordered_jacobian_against_finite_differences(paper_config, element, constraint, normal_area):
    model = _model(paper_config, element, [f"contact.normal_traction_area={normal_area}"])
    x = _state(model)
    g, _ = model.contact.gaps(x[:-1], x[-1])
    a = model.params.adhesion
    assert (g < a.g_reg).any() and ((g > a.g_eq) & (g < a.g_max)).any() and (g > a.g_max).any()
    check_bordered_jacobian(model, x, constraint, History(), directions=4)


@pytest.mark.parametrize("element", ["Q1", "Q2"])
def test_edge_gap_interpolates_the_surface_between_nodes(paper_config, element):
    model = _model(paper_config, element)
    x = _state(model)
    assert model.edge_gap(x, 0.0) == pytest.approx(model.apex_gap(x), abs=1e-14)
    nodes = model.mesh.surface_nodes
    Xs = model.mesh.nodes[nodes, 0]
    ys = model.mesh.nodes[nodes, 1] + x[2 * nodes + 1]
    for X in (0.37, 1.0, 2.9):
        mean_y = 0.5 * (np.interp(-X, Xs, ys) + np.interp(X, Xs, ys))
        assert model.edge_gap(x, X) == pytest.approx(x[-1] - mean_y, abs=1e-13)
        assert model.edge_gap(x, -X) == model.edge_gap(x, X)
    with pytest.raises(ValueError, match="outside the top surface"):
        model.edge_gap(x, 1.01 * Xs[-1])


def test_bordered_solve_inverts_the_jacobian(paper_config):
    model = _model(paper_config, "Q1")
    x = _state(model)
    _, solve = model.linearize(x, FixedForce(0.0), History())
    w = np.random.default_rng(5).normal(size=model.n_dofs + 1)
    w[model.bc.dofs] = 0.0
    dx = solve(w)
    np.testing.assert_allclose(apply_bordered_jacobian(solve, dx), w, atol=1e-9 * np.abs(w).max())


def test_far_points_skipped_and_cost_nothing(paper_config):
    model = _model(paper_config, "Q1")
    x = _state(model)
    g, _ = model.contact.gaps(x[:-1], x[-1])
    act = model.contact.active(g)
    assert 0 < len(act) < len(g)
    lin = model.contact.linearize(x[:-1], x[-1])
    assert lin.blocks.shape[0] == len(act)


def test_interval_measures():
    x = np.column_stack([np.linspace(-2, 2, 5), np.zeros(5)])
    v = np.array([1.0, -1.0, -1.0, -1.0, 1.0])  # crosses at -1.5 and 1.5
    length, xl, xr = interval_measures(x, v)
    assert (length, xl, xr) == pytest.approx((3.0, -1.5, 1.5))
    length, xl, xr = interval_measures(x, np.ones(5))
    assert length == 0.0 and np.isnan(xl)


FRICTION_CASES = [("DI", 1.0, ()), ("EA", 0.0, ()), ("EA", 0.5, ()), ("EA", 1.0, ()),
                  ("DI", 1.0, ("friction.DI_area=reference",)), ("DI", 1.0, ("contact.normal_traction_area=current",)),
                  ("EA", 1.0, ("contact.normal_traction_area=current",)),
                  ("DI", 1.0, ("friction.static_over_kinetic=1.5",)), ("EA", 0.0, ("friction.static_over_kinetic=1.5",))]


@pytest.mark.parametrize("element", ["Q1", "Q2"])
@pytest.mark.parametrize("model_name, s_cut, options", FRICTION_CASES,
                         ids=[f"{m}-{s}{'-' + o[0].split('=')[0] if o else ''}" for m, s, o in FRICTION_CASES])
@pytest.mark.parametrize("ubar", [0.0, 0.0016, 2.0], ids=["stick", "mixed", "slip"])
def test_friction_tangent_against_finite_differences(paper_config, element, model_name, s_cut, options, ubar):
    model = _model(paper_config, element, [f"friction.model={model_name}", f"friction.s_cut={s_cut}", *options])
    x0 = _state(model)
    history = model.start_friction(x0, 0.0)
    rng = np.random.default_rng(11)
    if history.slip is not None:  # slip weakening: points before, inside and past the weakening distance
        history = History(history.anchors, rng.uniform(0.0, 1.5 * model.params.friction.slip_weakening_distance,
                                                        history.anchors.shape))
    x = x0.copy()
    x[:-1] += 1e-4 * rng.normal(size=model.n_dofs)  # move away from the anchors, not uniformly
    x[model.bc.dofs] = 0.0
    constraint = SlideAtForce(ubar, -0.05)
    _, state = model.contact.tangential_state(x[:-1], x[-1], ubar, history.anchors, history.slip)
    n_stick, n_slip = np.sum(state == SlipState.STICK), np.sum(state == SlipState.SLIP)
    if ubar == 0.0:
        assert n_stick > 0
    if ubar == 2.0:
        assert n_slip > 0 and n_stick == 0
    if ubar == 0.0016:  # trial tractions near tau_DI = 0.165 = eps_t 0.00165
        assert n_stick > 0 and n_slip > 0
        if history.slip is not None:  # some slipping points still weakening
            assert np.any((state == SlipState.SLIP) & (history.slip < model.params.friction.slip_weakening_distance))
    r, solve = model.linearize(x, constraint, history)
    np.testing.assert_allclose(r, model.residual(x, constraint, history), atol=1e-13)
    free = np.ones(model.n_dofs + 1)
    free[model.bc.dofs] = 0.0
    eps = 1e-8
    for _ in range(4):
        v = rng.normal(size=model.n_dofs + 1) * free
        fd = (model.residual(x + eps * v, constraint, history) - model.residual(x - eps * v, constraint, history)) / (2 * eps)
        Jv = apply_bordered_jacobian(solve, v)
        # points within eps of a stick/slip switch or the EA kink make a few entries non-smooth
        err = np.abs(Jv - fd)
        bad = err > 1e-5 * np.abs(fd).max() + 1e-6
        assert bad.sum() == 0, (bad.sum(), err.max(), np.abs(fd).max())
    if model_name == "DI" and ubar == 2.0 and not options:  # sliding friction makes the tangent unsymmetric
        K = solve.K
        assert abs(K - K.T).max() > 1e-6
