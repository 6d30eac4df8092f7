"""Small drivers for the bulk-only tests: Newton on a mesh with Dirichlet nodes."""

import numpy as np
import pytest

from capslide.fem.assembly import BulkForm, Dirichlet, rigid_body_modes
from capslide.params import lame_plane_strain
from capslide.solvers.linsolve import make_solver
from capslide.solvers.newton import NewtonOptions, newton

LAM, MU = lame_plane_strain(1.0, 0.4)


def solve_dirichlet(mesh, nodes, values, solver="direct", options=None, form=None, steps=4):
    """Prescribe u[nodes] = values (n, 2) in ``steps`` equal load steps, return (u, last result, form)."""
    form = form or BulkForm(mesh, LAM, MU)
    options = options or NewtonOptions()
    bc = Dirichlet.on_nodes(np.asarray(nodes), form.pattern)
    lin = make_solver(solver, near_null_space=rigid_body_modes(mesh.nodes))
    u = np.zeros(mesh.n_dofs)

    def residual(u):
        r = form.residual(u)
        r[bc.dofs] = 0.0
        return r

    def linearize(u):
        r, data = form.residual_and_tangent_data(u)
        bc.apply(data, r)
        A = form.pattern.matrix(data)

        def solve(rhs):
            x, info = lin.solve(A, rhs)
            solve.iterations = info.iterations
            return x

        return r, solve

    admissible = lambda x: form.min_jacobian(x) > 0.0  # noqa: E731
    prescribed = np.zeros(mesh.n_dofs)
    prescribed.reshape(-1, 2)[nodes] = values / steps
    for k in range(1, steps + 1):
        # linearized predictor: move the free DOFs with the prescribed increment
        r, data = form.residual_and_tangent_data(u)
        lift = form.pattern.matrix(data) @ prescribed
        bc.apply(data, r)
        rhs = r + lift
        rhs[bc.dofs] = 0.0
        u = u + prescribed - lin.solve(form.pattern.matrix(data), rhs)[0]
        u.reshape(-1, 2)[nodes] = values * (k / steps)
        res = newton(residual, linearize, u, options, r_ref=1.0, admissible=admissible)
        if not res.converged:
            return res.x, res, form
        u = res.x
    return u, res, form


def apply_bordered_jacobian(solve, v):
    """J v for the bordered Jacobian [K c; d^T e] of a model's linearization (v = [u, h])."""
    u, h = v[:-1], v[-1]
    return np.concatenate([solve.K @ u + solve.c * h, [solve.d @ u + solve.e * h]])


def check_bordered_jacobian(model, x, constraint, history, directions: int, seed: int = 3, eps: float = 1e-7):
    """The model's residual at x is the linearization's, and J v matches central differences of the residual in
    ``directions`` random directions (free DOFs and h), to 1e-6 of the largest difference."""
    r, solve = model.linearize(x, constraint, history)
    np.testing.assert_allclose(r, model.residual(x, constraint, history), atol=1e-13)
    rng = np.random.default_rng(seed)
    free = np.ones(model.n_dofs + 1)
    free[model.bc.dofs] = 0.0
    for _ in range(directions):
        v = rng.normal(size=model.n_dofs + 1) * free
        v[-1] = rng.normal()
        fd = (model.residual(x + eps * v, constraint, history) - model.residual(x - eps * v, constraint, history)) / (2 * eps)
        np.testing.assert_allclose(apply_bordered_jacobian(solve, v), fd, atol=1e-6 * np.abs(fd).max())


def pressed_sphere_state(model, shear: float = 0.0, seed: int = 0):
    """A state [u, h] of a 3D sphere cap model (R = 47.1, H = 10) pressed up into the band of the adhesion law:
    gaps on both sides of g_eq and beyond g_max; ``shear``: an x displacement growing to that at the top."""
    rng = np.random.default_rng(seed)
    X = model.mesh.nodes
    a = model.params.adhesion
    u = np.zeros(model.n_dofs)
    r2 = X[:, 0] ** 2 + X[:, 1] ** 2
    u[2::3] = 0.3 * a.r0 * np.exp(-r2 / 9.0) * X[:, 2] / 10
    if shear:
        u[0::3] = shear * X[:, 2] / 10
    u += 1e-3 * a.r0 * rng.normal(size=model.n_dofs)
    u[model.bc.dofs] = 0.0
    return np.concatenate([u, [10.0 + 0.3 * a.r0 + 0.9 * a.g_eq]])


def check_bulk_form_derivatives(form, n_dofs: int, amplitude: float, seed: int):
    """A displacement bulk form at a random displacement of ``amplitude``: its tangent against central differences
    of the residual, and the residual against the energy's gradient. Returns (u, du, tangent)."""
    rng = np.random.default_rng(seed)
    u = amplitude * rng.standard_normal(n_dofs)
    f, K = form.residual_and_tangent(u)
    du = rng.standard_normal(n_dofs)
    h = 1e-6
    fd = (form.residual(u + h * du) - form.residual(u - h * du)) / (2 * h)
    np.testing.assert_allclose(K @ du, fd, rtol=1e-6, atol=1e-8 * np.abs(fd).max())
    dW = (form.strain_energy(u + h * du) - form.strain_energy(u - h * du)) / (2 * h)
    assert dW == pytest.approx(f @ du, rel=1e-6)  # the internal force is the energy's gradient
    return u, du, K


def check_mixed_form_derivatives(form, mesh, amplitude: float, seed: int):
    """A mixed bulk form at a random displacement of ``amplitude`` (a random multiplier if incompressible): its
    condensed tangent against central differences of the residual, and the residual against the energy's gradient.
    Returns that displacement."""
    rng = np.random.default_rng(seed)
    u = amplitude * rng.standard_normal(mesh.n_dofs)
    m = form.Np.shape[-1]
    multiplier = 0.3 * rng.standard_normal((mesh.n_cells, m)) if form.incompressible else None
    f, data = form.residual_and_tangent_data(u, multiplier)
    K = form.pattern.matrix(data)
    du = rng.standard_normal(mesh.n_dofs)
    h = 1e-6
    fd = (form.residual(u + h * du, multiplier) - form.residual(u - h * du, multiplier)) / (2 * h)
    np.testing.assert_allclose(K @ du, fd, rtol=1e-6, atol=1e-7 * np.abs(fd).max())
    dW = (form.strain_energy(u + h * du, multiplier) - form.strain_energy(u - h * du, multiplier)) / (2 * h)
    assert dW == pytest.approx(f @ du, rel=1e-6)
    return u
