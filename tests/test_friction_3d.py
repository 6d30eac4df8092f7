"""Friction in 3D (issue 40): the radial return map of a tangential traction vector, and the 3D cap model's bordered
Jacobian with DI and EA friction on the faces, against finite differences in stick, in slip and across the
transition."""

import functools

import numpy as np
import pytest

from capslide.config import apply_overrides, load_config, validate
from capslide.fem.assembly import rigid_body_modes
from capslide.fem.hex_mesh import SphereCapSpec, sphere_cap_mesh
from capslide.fem.surface import SurfaceQuadrature, stretch, stretch_gradient_3d
from capslide.laws import contact
from capslide.model.constraints import FixedHeight, SlideAtForce
from capslide.model.system import CapModel
from capslide.params import Parameters
from capslide.solvers.linsolve import make_solver

from conftest import PAPER_CONFIG
from fe_helpers import check_bordered_jacobian, pressed_sphere_state


def _trials(n=400, seed=2):
    rng = np.random.default_rng(seed)
    return rng.normal(size=(n, 2)), rng.uniform(0.05, 1.5, size=n)


def _fd_jacobian(fun, trial, h=1e-7):
    """d fun / d trial (n, 2, 2) by central differences."""
    cols = [(fun(trial + h * e) - fun(trial - h * e)) / (2 * h) for e in np.eye(2)]
    return np.stack(cols, axis=-1)


def test_vector_return_map_is_the_radial_return():
    trial, thr = _trials()
    T, slipping, _, _ = contact.vector_return_map(trial, thr)
    m = np.linalg.norm(trial, axis=1)
    assert slipping.any() and (~slipping).any()
    np.testing.assert_array_equal(slipping, m > thr)
    np.testing.assert_array_equal(T[~slipping], trial[~slipping])
    np.testing.assert_allclose(np.linalg.norm(T[slipping], axis=1), thr[slipping], rtol=1e-14)  # on the threshold
    Ts, ts = T[slipping], trial[slipping]
    np.testing.assert_allclose(Ts[:, 0] * ts[:, 1] - Ts[:, 1] * ts[:, 0], 0.0, atol=1e-14)  # along the trial
    assert np.all(np.einsum("ni,ni->n", T, trial) > 0.0)
    # one component: the scalar map
    s = contact.return_map(trial[:, 0], thr)
    v = contact.vector_return_map(trial[:, :1], thr)
    np.testing.assert_allclose(v[0][:, 0], s[0], rtol=1e-15)
    np.testing.assert_array_equal(v[1], s[1])
    np.testing.assert_allclose(v[2][:, 0, 0], s[2], atol=1e-15)
    np.testing.assert_allclose(v[3][:, 0], s[3], rtol=1e-15)


@pytest.mark.parametrize("ratio", [1.0, 1.5], ids=["plain", "weakening"])
def test_vector_return_map_derivatives(ratio):
    """dT/dT_trial and dT/dthreshold against central differences in stick, slip and on both sides of the
    transition (|T_trial| = threshold (1 -/+ 1e-4))."""
    trial, thr = _trials()
    slip = np.random.default_rng(5).uniform(0.0, 0.15, size=len(thr))
    static = thr * (ratio - (ratio - 1.0) * np.minimum(slip, 0.1) / 0.1)  # where slip starts
    n = trial / np.linalg.norm(trial, axis=1, keepdims=True)
    near = np.concatenate([static[:50, None] * (1 - 1e-4) * n[:50], static[50:100, None] * (1 + 1e-4) * n[50:100]])
    trial = np.concatenate([near, trial[100:]])
    magnitude = (contact.return_map if ratio == 1.0 else
                 lambda T, k: contact.weakening_return_map(T, k, slip, ratio, 0.1, 20.0))  # noqa: E731
    T, slipping, dT_dtrial, dT_dthr = contact.vector_return_map(trial, thr, magnitude)
    assert not slipping[:50].any() and slipping[50:100].all()
    fd = _fd_jacobian(lambda t: contact.vector_return_map(t, thr, magnitude)[0], trial)
    np.testing.assert_allclose(dT_dtrial, fd, atol=1e-6)
    h = 1e-7
    fd_thr = (contact.vector_return_map(trial, thr + h, magnitude)[0]
              - contact.vector_return_map(trial, thr - h, magnitude)[0]) / (2 * h)
    np.testing.assert_allclose(dT_dthr, fd_thr, atol=1e-6)
    if ratio == 1.0:  # the slip tangent is thr / |trial| times the projection onto the plane normal to n
        k = np.flatnonzero(slipping)[0]
        nk = trial[k] / np.linalg.norm(trial[k])
        P = np.eye(2) - np.outer(nk, nk)
        np.testing.assert_allclose(dT_dtrial[k], thr[k] / np.linalg.norm(trial[k]) * P, rtol=1e-12)


def test_area_stretch_gradient_against_finite_differences():
    mesh = sphere_cap_mesh(SphereCapSpec(R=47.1, H=10.0, h0=1.5, band_radius=4.0, max_size_over_H=0.5))
    quad = SurfaceQuadrature.on(mesh, 2)
    rng = np.random.default_rng(0)
    u = 0.05 * rng.normal(size=mesh.n_dofs)
    _, t = quad.current(u)
    J = stretch(t, quad.ref_measure, 3)
    _, t0 = quad.current(0 * u)
    np.testing.assert_allclose(stretch(t0, quad.ref_measure, 3), 1.0, rtol=1e-12)
    grad = stretch_gradient_3d(t, quad.ref_measure, quad.dN)  # (s, g, b, 3)
    v = rng.normal(size=mesh.n_dofs)
    h = 1e-6
    J_at = lambda w: stretch(quad.current(w)[1], quad.ref_measure, 3)  # noqa: E731
    fd = (J_at(u + h * v) - J_at(u - h * v)) / (2 * h)
    dv = v.reshape(-1, 3)[quad.segments]  # (s, b, 3)
    np.testing.assert_allclose(np.einsum("sgbi,sbi->sg", grad, dv), fd, atol=1e-7 * np.abs(fd).max())
    assert np.ptp(J) > 1e-3


@functools.cache
def _model(config_items: tuple) -> CapModel:
    cfg = validate(apply_overrides(load_config([PAPER_CONFIG], ["preset=fast"]), list(config_items)))
    p = Parameters.from_config(cfg)
    mesh = sphere_cap_mesh(SphereCapSpec(R=47.1, H=10.0, h0=0.8, band_radius=4.0, max_size_over_H=0.4))
    return CapModel(mesh, p, make_solver("amg", near_null_space=rigid_body_modes(mesh.nodes)))


FRICTION = {
    "DI": ("friction.model=DI",),
    "DI_current_normal": ("friction.model=DI", "contact.normal_traction_area=current"),
    "EA": ("friction.model=EA",),
    "DI_weakening": ("friction.model=DI", "friction.static_over_kinetic=1.5", "friction.slip_weakening_distance=0.2"),
    "DI_step_start": ("friction.model=DI", "friction.threshold_at=step_start"),
}


@pytest.mark.parametrize("name", list(FRICTION))
@pytest.mark.parametrize("shift", [0.0005, 0.0012, 0.01], ids=["stick", "mixed", "slip"])
def test_bordered_jacobian_with_friction(name, shift):
    """The anchors set at the pressed state, the substrate slid by ubar and the cap's top sheared by shift along x
    (and half of it along y): every point in contact sticks (tangential gaps below tau / eps_t = 0.00165 L0), some
    slip, or all slip."""
    model = _model(("mesh.element=H1", *FRICTION[name]))
    x0 = pressed_sphere_state(model)
    history = model.start_friction(x0)
    if model.contact.weakening is not None:
        history = history.__class__(history.anchors, np.full(history.slip.shape, 0.01))
    x = x0.copy()
    X = model.mesh.nodes
    sheared = shift * (1.4 if model.contact.weakening is not None else 1.0)  # the static threshold is higher
    x[:-1:3] += sheared * X[:, 2] / 10
    x[1:-1:3] += 0.5 * sheared * X[:, 2] / 10 * (X[:, 1] > 0)
    x[model.bc.dofs] = 0.0
    ubar = 1e-4
    c = model.contact
    _, state = c.tangential_state(x[:-1], x[-1], ubar, *history.friction)
    sticking, slipping = (state == 1).sum(), (state == 2).sum()
    print(name, shift, "stick", sticking, "slip", slipping)
    if shift == 0.0005:  # EA's threshold vanishes at g_cut: points near the edge slip at any shear
        assert sticking > 0 and (slipping == 0 or name == "EA")
    elif shift == 0.01:
        assert slipping > 0 and sticking == 0
    else:
        assert slipping > 0 and sticking > 0
    for constraint in (FixedHeight(x[-1], ubar), SlideAtForce(ubar, -0.1)):
        check_bordered_jacobian(model, x, constraint, history, directions=2)
