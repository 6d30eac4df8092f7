"""Reference elements and Gauss rules."""

import numpy as np
import pytest

from capslide.fem.element import HEXES, QUADS, gauss_legendre, gauss_quad, line_shape

CELLS = {**QUADS, **HEXES}  # the quadrilaterals and the hexahedron share one tensor-product implementation


@pytest.mark.parametrize("name", ["Q1", "Q2", "H1"])
def test_partition_of_unity_and_nodality(name):
    ref = CELLS[name]
    pts = np.random.default_rng(0).uniform(-1, 1, size=(50, ref.dim))
    N, dN = ref.shape(pts)
    np.testing.assert_allclose(N.sum(axis=1), 1.0, atol=1e-14)
    np.testing.assert_allclose(dN.sum(axis=1), 0.0, atol=1e-13)
    Nn, _ = ref.shape(ref.nodes)
    np.testing.assert_allclose(Nn, np.eye(ref.n_nodes), atol=1e-14)


@pytest.mark.parametrize("name", ["Q1", "Q2", "H1"])
def test_gradients_against_finite_differences(name):
    ref = CELLS[name]
    pts = np.random.default_rng(1).uniform(-0.9, 0.9, size=(20, ref.dim))
    _, dN = ref.shape(pts)
    h = 1e-6
    for k in range(ref.dim):
        e = np.zeros(ref.dim)
        e[k] = h
        fd = (ref.shape(pts + e)[0] - ref.shape(pts - e)[0]) / (2 * h)
        np.testing.assert_allclose(dN[..., k], fd, atol=1e-9)


@pytest.mark.parametrize("name", ["Q1", "Q2"])
def test_reproduces_its_polynomials(name):
    ref = QUADS[name]
    p = ref.order
    pts = np.random.default_rng(2).uniform(-1, 1, size=(30, 2))
    N, _ = ref.shape(pts)
    for i in range(p + 1):
        for j in range(p + 1):
            f = lambda x: x[:, 0] ** i * x[:, 1] ** j  # noqa: E731
            np.testing.assert_allclose(N @ f(ref.nodes), f(pts), atol=1e-13)


@pytest.mark.parametrize("n", [1, 2, 3, 4, 6])
def test_gauss_exact_to_degree(n):
    x, w = gauss_legendre(n)
    for d in range(2 * n):
        exact = 0.0 if d % 2 else 2.0 / (d + 1)
        assert np.dot(w, x**d) == pytest.approx(exact, abs=1e-14)
    assert abs(np.dot(w, x ** (2 * n)) - 2.0 / (2 * n + 1)) > 1e-6  # not exact one degree higher
    P, W = gauss_quad(n)
    d = 2 * n - 1
    assert np.dot(W, P[:, 0] ** (d - 1) * P[:, 1] ** (d - 1)) == pytest.approx((2 / d) ** 2 if (d - 1) % 2 == 0 else 0.0)


@pytest.mark.parametrize("order", [1, 2])
def test_line_shape(order):
    s = np.linspace(-1, 1, 11)
    N, dN = line_shape(order, s)
    np.testing.assert_allclose(N.sum(axis=1), 1.0)
    h = 1e-6
    np.testing.assert_allclose(dN, (line_shape(order, s + h)[0] - line_shape(order, s - h)[0]) / (2 * h), atol=1e-9)
