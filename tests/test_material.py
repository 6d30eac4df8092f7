"""Neo-Hooke, plane strain (and 3D where the same checks apply): stress-free reference, objectivity, small-strain
limit, exact tangent."""

import numpy as np
import pytest

from capslide.laws import material
from capslide.params import lame_plane_strain

LAM, MU = lame_plane_strain(1.0, 0.4)


def random_F(n, scale=0.3, seed=0, dim=2):
    rng = np.random.default_rng(seed)
    F = np.eye(dim) + scale * rng.uniform(-1, 1, size=(n, dim, dim))
    assert np.all(material.det(F) > 0)
    return F


def rotation(theta):
    c, s = np.cos(theta), np.sin(theta)
    return np.array([[c, -s], [s, c]])


def test_zero_stress_at_identity():
    F = np.broadcast_to(np.eye(2), (3, 2, 2)).copy()
    np.testing.assert_allclose(material.first_piola(F, LAM, MU), 0.0, atol=1e-15)
    np.testing.assert_allclose(material.cauchy(F, LAM, MU), 0.0, atol=1e-15)
    np.testing.assert_allclose(material.first_invariant(F, LAM, MU), 0.0, atol=1e-15)


def test_objectivity():
    Q = rotation(0.7)
    # a rigid rotation is stress free
    np.testing.assert_allclose(material.cauchy(Q[None], LAM, MU), 0.0, atol=1e-14)
    F = random_F(20)
    s, sQ = material.cauchy(F, LAM, MU), material.cauchy(Q @ F, LAM, MU)
    np.testing.assert_allclose(sQ, Q @ s @ Q.T, atol=1e-13)
    np.testing.assert_allclose(material.first_piola(Q @ F, LAM, MU), Q @ material.first_piola(F, LAM, MU), atol=1e-13)
    np.testing.assert_allclose(material.first_invariant(Q @ F, LAM, MU), material.first_invariant(F, LAM, MU), atol=1e-13)


def test_small_strain_limit_is_plane_strain_elasticity():
    rng = np.random.default_rng(3)
    H = 1e-7 * rng.uniform(-1, 1, size=(10, 2, 2))
    eps = 0.5 * (H + np.swapaxes(H, 1, 2))
    tr = np.trace(eps, axis1=1, axis2=2)
    linear = LAM * tr[:, None, None] * np.eye(2) + 2 * MU * eps
    np.testing.assert_allclose(material.cauchy(np.eye(2) + H, LAM, MU), linear, rtol=0, atol=1e-6 * np.abs(linear).max())
    np.testing.assert_allclose(material.cauchy_zz(np.eye(2) + H, LAM, MU), LAM * tr, atol=1e-6 * np.abs(linear).max())
    # E = 1, nu = 0.4: sigma_zz = nu (sigma_xx + sigma_yy) in plane strain
    np.testing.assert_allclose(LAM * tr, 0.4 * np.trace(linear, axis1=1, axis2=2), rtol=1e-12)


def test_cauchy_from_piola():
    F = random_F(15, seed=5)
    P, s = material.first_piola(F, LAM, MU), material.cauchy(F, LAM, MU)
    J = material.det2(F)
    np.testing.assert_allclose(s, P @ np.swapaxes(F, 1, 2) / J[:, None, None], atol=1e-13)


@pytest.mark.parametrize("dim", [2, 3])
def test_tangent_against_finite_differences(dim):
    F = random_F(25, scale=0.3 if dim == 2 else 0.2, seed=7, dim=dim)
    P, A = material.first_piola_and_tangent(F, LAM, MU)
    np.testing.assert_allclose(P, material.first_piola(F, LAM, MU), atol=1e-15)
    h = 1e-6
    for k in range(dim):
        for L in range(dim):
            dF = np.zeros((dim, dim))
            dF[k, L] = h
            fd = (material.first_piola(F + dF, LAM, MU) - material.first_piola(F - dF, LAM, MU)) / (2 * h)
            np.testing.assert_allclose(A[:, :, :, k, L], fd, atol=1e-8)
    # hyperelastic: major symmetry A_iJkL = A_kLiJ
    np.testing.assert_allclose(A, A.transpose(0, 3, 4, 1, 2), atol=1e-13)
