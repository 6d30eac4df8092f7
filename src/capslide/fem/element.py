"""Reference elements: Lagrange shape functions and Gauss rules.

Quadrilaterals live on [-1, 1]^2 with local coordinates (xi, eta). Node order:
Q1 (4 nodes) counter-clockwise from (-1, -1); Q2 (9 nodes) the four corners
as Q1, then the mid-edge nodes of the edges (bottom, right, top, left), then
the centre. Lines live on [-1, 1]; node order Q1 (-1, 1), Q2 (-1, 0, 1).
Hexahedra live on [-1, 1]^3 (xi, eta, zeta); the trilinear H1 (8 nodes) takes VTK's order: the bottom face
(zeta = -1) counter-clockwise from (-1, -1, -1), then the top face in the same order.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["ReferenceQuad", "QUADS", "ReferenceHex", "HEXES", "gauss_legendre", "gauss_quad", "gauss_hex",
           "line_shape"]

# Local coordinates of the nodes.
_Q1_NODES = np.array([[-1, -1], [1, -1], [1, 1], [-1, 1]], dtype=float)
_Q2_NODES = np.array([[-1, -1], [1, -1], [1, 1], [-1, 1], [0, -1], [1, 0], [0, 1], [-1, 0], [0, 0]], dtype=float)


def gauss_legendre(n: int) -> tuple[np.ndarray, np.ndarray]:
    """n-point Gauss-Legendre rule on [-1, 1]: points (n,), weights (n,); exact to degree 2n - 1."""
    return np.polynomial.legendre.leggauss(n)


def gauss_quad(n: int) -> tuple[np.ndarray, np.ndarray]:
    """Tensor n x n Gauss rule on [-1, 1]^2: points (n*n, 2), weights (n*n,)."""
    x, w = gauss_legendre(n)
    X, Y = np.meshgrid(x, x, indexing="ij")
    return np.column_stack([X.ravel(), Y.ravel()]), np.outer(w, w).ravel()


def gauss_hex(n: int) -> tuple[np.ndarray, np.ndarray]:
    """Tensor n x n x n Gauss rule on [-1, 1]^3: points (n^3, 3), weights (n^3,)."""
    x, w = gauss_legendre(n)
    X, Y, Z = np.meshgrid(x, x, x, indexing="ij")
    return np.column_stack([X.ravel(), Y.ravel(), Z.ravel()]), np.einsum("i,j,k->ijk", w, w, w).ravel()


def _lagrange_1d(order: int, s: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """1D Lagrange basis at nodes (-1, 1) or (-1, 0, 1): values and derivatives, (len(s), order+1)."""
    s = np.asarray(s, dtype=float)
    if order == 1:
        N = np.stack([(1 - s) / 2, (1 + s) / 2], axis=-1)
        dN = np.stack([-0.5 * np.ones_like(s), 0.5 * np.ones_like(s)], axis=-1)
    elif order == 2:
        N = np.stack([s * (s - 1) / 2, 1 - s**2, s * (s + 1) / 2], axis=-1)
        dN = np.stack([s - 0.5, -2 * s, s + 0.5], axis=-1)
    else:
        raise ValueError(f"order must be 1 or 2, not {order}")
    return N, dN


def line_shape(order: int, s) -> tuple[np.ndarray, np.ndarray]:
    """Line element shape functions and d/ds at points s: (n_points, order + 1) each."""
    return _lagrange_1d(order, s)


@dataclass(frozen=True)
class ReferenceQuad:
    """A Lagrange quadrilateral on [-1, 1]^2."""

    name: str
    order: int
    nodes: np.ndarray  # (n_nodes, 2) local coordinates

    @property
    def n_nodes(self) -> int:
        return len(self.nodes)

    def _index_1d(self) -> tuple[np.ndarray, np.ndarray]:
        # position of each node in the 1D node list (-1, [0,] 1)
        grid = np.array([-1.0, 1.0]) if self.order == 1 else np.array([-1.0, 0.0, 1.0])
        ix = np.searchsorted(grid, self.nodes[:, 0])
        iy = np.searchsorted(grid, self.nodes[:, 1])
        return ix, iy

    def shape(self, points) -> tuple[np.ndarray, np.ndarray]:
        """Values (n_points, n_nodes) and local gradients (n_points, n_nodes, 2) at points (n_points, 2)."""
        points = np.atleast_2d(np.asarray(points, dtype=float))
        Nx, dNx = _lagrange_1d(self.order, points[:, 0])
        Ny, dNy = _lagrange_1d(self.order, points[:, 1])
        ix, iy = self._index_1d()
        N = Nx[:, ix] * Ny[:, iy]
        dN = np.stack([dNx[:, ix] * Ny[:, iy], Nx[:, ix] * dNy[:, iy]], axis=-1)
        return N, dN

    def gauss(self, n: int | None = None) -> tuple[np.ndarray, np.ndarray]:
        """Default volume rule: 2x2 for Q1, 3x3 for Q2 (full integration)."""
        return gauss_quad(n if n is not None else self.order + 1)


QUADS = {"Q1": ReferenceQuad("Q1", 1, _Q1_NODES), "Q2": ReferenceQuad("Q2", 2, _Q2_NODES)}


_H1_NODES = np.array([[-1, -1, -1], [1, -1, -1], [1, 1, -1], [-1, 1, -1],
                      [-1, -1, 1], [1, -1, 1], [1, 1, 1], [-1, 1, 1]], dtype=float)


@dataclass(frozen=True)
class ReferenceHex:
    """A Lagrange hexahedron on [-1, 1]^3: the tensor product of 1D Lagrange bases."""

    name: str
    order: int
    nodes: np.ndarray  # (n_nodes, 3) local coordinates

    @property
    def n_nodes(self) -> int:
        return len(self.nodes)

    def shape(self, points) -> tuple[np.ndarray, np.ndarray]:
        """Values (n_points, n_nodes) and local gradients (n_points, n_nodes, 3) at points (n_points, 3)."""
        points = np.atleast_2d(np.asarray(points, dtype=float))
        grid = np.array([-1.0, 1.0]) if self.order == 1 else np.array([-1.0, 0.0, 1.0])
        idx = [np.searchsorted(grid, self.nodes[:, k]) for k in range(3)]
        basis = [_lagrange_1d(self.order, points[:, k]) for k in range(3)]
        N1 = [b[0][:, i] for b, i in zip(basis, idx)]  # (n_points, n_nodes) per direction
        D1 = [b[1][:, i] for b, i in zip(basis, idx)]
        N = N1[0] * N1[1] * N1[2]
        dN = np.stack([D1[0] * N1[1] * N1[2], N1[0] * D1[1] * N1[2], N1[0] * N1[1] * D1[2]], axis=-1)
        return N, dN

    def gauss(self, n: int | None = None) -> tuple[np.ndarray, np.ndarray]:
        """Default volume rule: 2x2x2 for H1 (full integration)."""
        return gauss_hex(n if n is not None else self.order + 1)


HEXES = {"H1": ReferenceHex("H1", 1, _H1_NODES)}
