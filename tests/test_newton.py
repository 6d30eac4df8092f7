"""Newton: quadratic convergence, line search, failure returned."""

import numpy as np

from capslide.newton import NewtonOptions, newton


def _problem(f, J):
    def linearize(x):
        jac = J(x)
        return f(x), lambda r: np.linalg.solve(jac, r)

    return f, linearize


def test_quadratic_convergence():
    f, lin = _problem(lambda x: np.array([x[0] ** 3 + x[1] - 1.0, x[1] ** 3 - x[0] + 1.0]),
                      lambda x: np.array([[3 * x[0] ** 2, 1.0], [-1.0, 3 * x[1] ** 2]]))
    res = newton(f, lin, np.array([2.0, 1.0]), NewtonOptions(rtol=1e-14, atol=1e-14, dx_tol=1e-12))
    assert res.converged, res.reason
    np.testing.assert_allclose(res.x, [1.0, 0.0], atol=1e-12)
    r = np.array(res.residual_norms)
    tail = r[r > 1e-13][-3:]
    assert tail[-1] <= 10 * tail[-2] ** 2 / tail[-3] ** 0 or tail[-1] < 1e-10  # superlinear at the end


def test_line_search_globalizes_arctan():
    # plain Newton on arctan(x) = 0 diverges from x0 = 3; the line search converges
    f, lin = _problem(lambda x: np.arctan(x), lambda x: np.array([[1.0 / (1.0 + x[0] ** 2)]]))
    res = newton(f, lin, np.array([3.0]))
    assert res.converged and abs(res.x[0]) < 1e-9


def test_failure_is_returned():
    # x^2 + 1 = 0 has no real root
    f, lin = _problem(lambda x: x**2 + 1.0, lambda x: np.array([[2.0 * x[0] if x[0] != 0 else 1e-12]]))
    res = newton(f, lin, np.array([0.5]), NewtonOptions(max_iterations=15))
    assert not res.converged and res.reason
    # a non-finite residual ends the solve with a reason
    f2, lin2 = _problem(lambda x: np.log(x), lambda x: np.array([[1.0 / x[0]]]))
    with np.errstate(invalid="ignore"):
        res2 = newton(f2, lin2, np.array([-1.0]))
    assert not res2.converged and "not finite" in res2.reason


def test_admissibility_is_enforced():
    # root at x = -1 is forbidden (x > 0 required); the positive root x = 1 is found instead
    f, lin = _problem(lambda x: x**2 - 1.0, lambda x: np.array([[2.0 * x[0]]]))
    res = newton(f, lin, np.array([0.3]), admissible=lambda x: x[0] > 0)
    assert res.converged and res.x[0] == 1.0 or abs(res.x[0] - 1.0) < 1e-9
