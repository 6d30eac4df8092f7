"""The 3D pieces of the FE core (issue 39, first steps): the trilinear hexahedron's shape functions and Gauss rule,
and the neo-Hooke law in 3D (the same functions as plane strain, the dimension read from F), its stress and exact
tangent against finite differences."""

import numpy as np
import pytest

from capslide.fem.element import HEXES, gauss_hex
from capslide.laws import material

H1 = HEXES["H1"]
LAM, MU = 0.4 / (1.4 * 0.2), 1.0 / 2.8  # E = 1, nu = 0.4


def test_hexahedron_isoparametric_identity():
    """x = sum N_a x_a (partition of unity, nodality and gradients: tests/test_element.py, with Q1 and Q2)."""
    pts = np.random.default_rng(1).uniform(-1, 1, (20, 3))
    N, _ = H1.shape(pts)
    np.testing.assert_allclose(np.einsum("pa,ai->pi", N, H1.nodes), pts)


def test_hexahedron_gauss_rule_integrates_the_element():
    x, w = gauss_hex(2)
    assert w.sum() == pytest.approx(8.0)
    assert np.sum(w * x[:, 0] ** 2 * x[:, 1] ** 2 * x[:, 2] ** 2) == pytest.approx(8.0 / 27.0)  # degree 3 per axis
    N, _ = H1.shape(x)
    np.testing.assert_allclose(w @ N, np.ones(8))  # each node's share of the volume


def _random_F(seed, n=6):
    return np.eye(3) + 0.25 * np.random.default_rng(seed).standard_normal((n, 3, 3))


def test_3d_law_is_at_rest_and_objective():
    eye = np.eye(3)[None]
    assert material.strain_energy_density(eye, LAM, MU)[0] == pytest.approx(0.0, abs=1e-15)
    np.testing.assert_allclose(material.first_piola(eye, LAM, MU), 0.0, atol=1e-15)
    F = _random_F(2)
    Q, _ = np.linalg.qr(np.random.default_rng(3).standard_normal((3, 3)))
    Q *= np.sign(np.linalg.det(Q))
    np.testing.assert_allclose(material.strain_energy_density(Q @ F, LAM, MU), material.strain_energy_density(F, LAM, MU))
    np.testing.assert_allclose(material.det(F), np.linalg.det(F))
    np.testing.assert_allclose(material.inv_transpose(F), np.linalg.inv(F).transpose(0, 2, 1))


def test_3d_stress_is_the_energy_derivative():
    """P = dW/dF by finite differences (A = dP/dF: tests/test_material.py, in 2D and 3D), and I1(sigma) is the trace
    of the Cauchy stress P F^T / J."""
    F = _random_F(4)
    P = material.first_piola(F, LAM, MU)
    h = 1e-6
    for k in range(3):
        for L in range(3):
            dF = np.zeros((3, 3))
            dF[k, L] = h
            dW = (material.strain_energy_density(F + dF, LAM, MU) - material.strain_energy_density(F - dF, LAM, MU)) / (2 * h)
            np.testing.assert_allclose(P[:, k, L], dW, rtol=1e-6, atol=1e-8)
    sigma = np.einsum("...iJ,...kJ->...ik", P, F) / np.linalg.det(F)[:, None, None]
    np.testing.assert_allclose(material.first_invariant(F, LAM, MU), np.trace(sigma, axis1=1, axis2=2))
