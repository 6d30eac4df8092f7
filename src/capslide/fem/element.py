"""Reference elements: Lagrange shape functions and Gauss rules.

Quadrilaterals live on [-1, 1]^2 with local coordinates (xi, eta). Node order:
Q1 (4 nodes) counter-clockwise from (-1, -1); Q2 (9 nodes) the four corners
as Q1, then the mid-edge nodes of the edges (bottom, right, top, left), then
the centre. Lines live on [-1, 1]; node order Q1 (-1, 1), Q2 (-1, 0, 1).
Hexahedra live on [-1, 1]^3 (xi, eta, zeta) and take VTK's order. The trilinear H1 (8 nodes): the bottom face
(zeta = -1) counter-clockwise from (-1, -1, -1), then the top face in the same order. The triquadratic H2 (27
nodes, VTK_TRIQUADRATIC_HEXAHEDRON): H1's corners; the mid-edge nodes of the bottom face's edges (0-1, 1-2, 2-3,
3-0), of the top face's, and of the vertical edges (0-4, 1-5, 2-6, 3-7); the face centres of the faces
xi = -1, xi = 1, eta = -1, eta = 1, zeta = -1, zeta = 1; the centre.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

import numpy as np

__all__ = ["ReferenceCell", "QUADS", "HEXES", "CELLS", "gauss_legendre", "gauss_quad", "gauss_hex",
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
class ReferenceCell:
    """A Lagrange quadrilateral ([-1, 1]^2) or hexahedron ([-1, 1]^3): the tensor product of 1D Lagrange bases of
    ``order``, its dimension that of ``nodes``."""

    name: str
    order: int
    nodes: np.ndarray  # (n_nodes, dim) local coordinates

    @property
    def n_nodes(self) -> int:
        return len(self.nodes)

    @property
    def dim(self) -> int:
        return self.nodes.shape[1]

    def shape(self, points) -> tuple[np.ndarray, np.ndarray]:
        """Values (n_points, n_nodes) and local gradients (n_points, n_nodes, dim) at points (n_points, dim)."""
        points = np.atleast_2d(np.asarray(points, dtype=float))
        grid = np.array([-1.0, 1.0]) if self.order == 1 else np.array([-1.0, 0.0, 1.0])
        values, slopes = [], []  # per direction, (n_points, n_nodes): each node's 1D factor
        for k in range(self.dim):
            N1, dN1 = _lagrange_1d(self.order, points[:, k])
            at = np.searchsorted(grid, self.nodes[:, k])  # position of each node in the 1D node list
            values.append(N1[:, at])
            slopes.append(dN1[:, at])
        N = functools.reduce(np.multiply, values)
        dN = np.stack([functools.reduce(np.multiply, [slopes[j] if j == k else values[j] for j in range(self.dim)])
                       for k in range(self.dim)], axis=-1)
        return N, dN

    def gauss(self, n: int | None = None) -> tuple[np.ndarray, np.ndarray]:
        """Default volume rule, full integration: 2 points per direction for order 1, 3 for order 2."""
        rule = gauss_quad if self.dim == 2 else gauss_hex
        return rule(n if n is not None else self.order + 1)


QUADS = {"Q1": ReferenceCell("Q1", 1, _Q1_NODES), "Q2": ReferenceCell("Q2", 2, _Q2_NODES)}


_H1_NODES = np.array([[-1, -1, -1], [1, -1, -1], [1, 1, -1], [-1, 1, -1],
                      [-1, -1, 1], [1, -1, 1], [1, 1, 1], [-1, 1, 1]], dtype=float)


_H2_NODES = np.vstack([
    _H1_NODES,
    [[0, -1, -1], [1, 0, -1], [0, 1, -1], [-1, 0, -1], [0, -1, 1], [1, 0, 1], [0, 1, 1], [-1, 0, 1],
     [-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0]],
    [[-1, 0, 0], [1, 0, 0], [0, -1, 0], [0, 1, 0], [0, 0, -1], [0, 0, 1], [0, 0, 0]],
]).astype(float)


HEXES = {"H1": ReferenceCell("H1", 1, _H1_NODES), "H2": ReferenceCell("H2", 2, _H2_NODES)}

CELLS = {**QUADS, **HEXES}  # every reference cell by name: a mesh's element names its cell and so its dimension
