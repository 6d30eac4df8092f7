"""The cap's top surface as a quadrature: Gauss points on its facets, their current positions and tangents, and
the surface stretch J_s with its gradient.

The facets are line elements in 2D (ordered by reference x) and bilinear (H1) or biquadratic (H2) quadrilateral
faces in 3D. J_s is the
ratio of current to reference measure at a point: |dx/ds| / |dX/ds| in 2D (a length ratio), |x,xi x x,eta| /
|X,xi x X,eta| in 3D (an area ratio, Nanson's formula; Sauer and De Lorenzis 2013, CMAME 253, 369).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .element import QUADS, gauss_legendre, gauss_quad, line_shape
from .mesh import Mesh

__all__ = ["SurfaceQuadrature", "stretch", "stretch_gradient_3d"]


@dataclass(frozen=True)
class SurfaceQuadrature:
    """Gauss points on the top-surface facets: line elements in 2D, ordered by reference x; bilinear or biquadratic
    quadrilateral faces in 3D (an n_gauss x n_gauss rule on each)."""

    segments: np.ndarray  # (s, p+1) node ids (3D: (s, 4) or (s, 9))
    N: np.ndarray  # (g, p+1) shape functions at the Gauss points
    dN: np.ndarray  # (g, p+1) d/ds (3D: (g, 4 or 9, 2), d/dxi and d/deta)
    weight: np.ndarray  # (s, g) Gauss weight times the reference length (3D: area) element
    X: np.ndarray  # (s, g, d) reference positions
    X_nodes: np.ndarray  # (s, p+1, d) reference positions of the segment nodes
    ref_measure: np.ndarray  # (s, g) |dX/ds| in 2D, |X,xi x X,eta| in 3D

    @classmethod
    def on(cls, mesh: Mesh, n_gauss: int) -> SurfaceQuadrature:
        seg = mesh.surface_segments
        Xn = mesh.nodes[seg]  # (s, a, d)
        if mesh.dim == 3:
            points, w = gauss_quad(n_gauss)
            N, dN = QUADS["Q1" if seg.shape[1] == 4 else "Q2"].shape(points)
            dX = np.einsum("gak,sai->sgik", dN, Xn)
            area = np.linalg.norm(np.cross(dX[..., 0], dX[..., 1]), axis=-1)
            return cls(seg, N, dN, w * area, np.einsum("ga,sai->sgi", N, Xn), Xn, area)
        s, w = gauss_legendre(n_gauss)
        N, dN = line_shape(seg.shape[1] - 1, s)
        X = np.einsum("ga,sai->sgi", N, Xn)
        length = np.linalg.norm(np.einsum("ga,sai->sgi", dN, Xn), axis=-1)
        return cls(seg, N, dN, w * length, X, Xn, length)

    @property
    def n_points(self) -> int:
        return self.weight.size

    @property
    def dim(self) -> int:
        return self.X.shape[-1]

    def current(self, u: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Current positions (s, g, d) and tangents: dx/ds (s, g, 2) in 2D, (dx/dxi, dx/deta) (s, g, 3, 2) in 3D."""
        xn = self.X_nodes + u.reshape(-1, self.dim)[self.segments]
        tangents = "gak,sai->sgik" if self.dN.ndim == 3 else "ga,sai->sgi"
        return np.einsum("ga,sai->sgi", self.N, xn), np.einsum(tangents, self.dN, xn)


def stretch(t: np.ndarray, ref_measure: np.ndarray, dim: int) -> np.ndarray:
    """The surface stretch J_s from the current tangents (2D: (..., 2); 3D: (..., 3, 2)) and the reference measure."""
    if dim == 3:
        return np.linalg.norm(np.cross(t[..., 0], t[..., 1]), axis=-1) / ref_measure
    return np.linalg.norm(t, axis=-1) / ref_measure


def stretch_gradient_3d(t: np.ndarray, ref_measure: np.ndarray, dN: np.ndarray) -> np.ndarray:
    """dJ_s/dx_bi (..., b, 3) of the area stretch at points with tangents t (..., 3, 2), for face nodes b with shape
    gradients dN (g, b, 2): with c = x,xi x x,eta and n = c / |c|, d|c|/dx_b = N_b,xi (x,eta x n) + N_b,eta (n x
    x,xi)."""
    a, b = t[..., 0], t[..., 1]
    c = np.cross(a, b)
    n = c / np.linalg.norm(c, axis=-1, keepdims=True)
    along_xi, along_eta = np.cross(b, n), np.cross(n, a)  # (..., 3)
    grad = (dN[..., 0][..., None] * along_xi[..., None, :] + dN[..., 1][..., None] * along_eta[..., None, :])
    return grad / ref_measure[..., None, None]
