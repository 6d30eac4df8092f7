"""Contact of the cap's top surface with the rigid flat substrate.

The substrate's lower face is the line y = h; it slides in +x by ubar. At a
surface Gauss point with current position x = X + u the normal gap is
g_n = h - y (no closest-point search: the substrate is flat), the substrate
normal is n_p = (0, -1), and the traction on the cap per reference length is
T = Tn(g_n) n_p (theta = J_l = 1; Mergel et al. 2019, eq. Tn). Sign
conventions: Fn = integral of T_y (positive = tensile); the residual of the
cap is R = f_int - f_contact.

Only points with g_n below ``far_gap`` are evaluated and assembled: the
law's tail beyond it is dropped (the error it makes is a measured knob).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from . import contact
from .element import gauss_legendre, line_shape
from .mesh import Mesh
from .params import Adhesion

__all__ = ["SurfaceQuadrature", "NormalContact", "ContactLinearization", "interval_measures"]


@dataclass(frozen=True)
class SurfaceQuadrature:
    """Gauss points on the top-surface line elements, ordered by reference x."""

    segments: np.ndarray  # (s, p+1) node ids
    N: np.ndarray  # (g, p+1) shape functions at the Gauss points
    dN: np.ndarray  # (g, p+1) d/ds
    weight: np.ndarray  # (s, g) Gauss weight times reference length element |dX/ds|
    X: np.ndarray  # (s, g, 2) reference positions
    X_nodes: np.ndarray  # (s, p+1, 2) reference positions of the segment nodes

    @classmethod
    def on(cls, mesh: Mesh, n_gauss: int) -> "SurfaceQuadrature":
        seg = mesh.surface_segments
        s, w = gauss_legendre(n_gauss)
        N, dN = line_shape(seg.shape[1] - 1, s)
        Xn = mesh.nodes[seg]  # (s, a, 2)
        X = np.einsum("ga,sai->sgi", N, Xn)
        dX = np.einsum("ga,sai->sgi", dN, Xn)
        return cls(seg, N, dN, w * np.linalg.norm(dX, axis=-1), X, Xn)

    @property
    def n_points(self) -> int:
        return self.weight.size

    def current(self, u: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Current positions (s, g, 2) and tangents dx/ds (s, g, 2)."""
        xn = self.X_nodes + u.reshape(-1, 2)[self.segments]
        return np.einsum("ga,sai->sgi", self.N, xn), np.einsum("ga,sai->sgi", self.dN, xn)


@dataclass
class ContactLinearization:
    """Contact terms of the residual and their derivatives.

    ``f`` (n_dofs) contact force on the cap; ``Fn`` its integrated y
    component; ``blocks`` (k, 2(p+1), 2(p+1)) dR/du of the active segments
    ``active_segments`` (R = f_int - f); ``dR_dh`` (n_dofs); ``dFn_du``
    (n_dofs); ``dFn_dh`` (scalar).
    """

    f: np.ndarray
    Fn: float
    blocks: np.ndarray
    active_segments: np.ndarray
    dR_dh: np.ndarray
    dFn_du: np.ndarray
    dFn_dh: float


class NormalContact:
    """CGCM normal contact of the cap surface against the rigid flat y = h."""

    def __init__(self, mesh: Mesh, adhesion: Adhesion, n_gauss: int, far_gap: float, repulsion_only: bool = False):
        self.mesh, self.adhesion = mesh, adhesion
        self.quad = SurfaceQuadrature.on(mesh, n_gauss)
        self.far_gap = far_gap
        self.repulsion_only = repulsion_only
        seg = mesh.surface_segments
        self.seg_dofs = np.stack([2 * seg, 2 * seg + 1], axis=-1).reshape(len(seg), -1)  # (s, 2(p+1))
        self.n_dofs = mesh.n_dofs

    # -- pointwise law ---------------------------------------------------
    def traction(self, g: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Tn(g) and dTn/dg (regularized CGCM; repulsion only if asked: max(Tn, 0))."""
        a = self.adhesion
        Tn, dTn = contact.normal_traction(g, a.T0, a.r0, a.g_reg)
        if self.repulsion_only:
            dTn = np.where(Tn > 0.0, dTn, 0.0)
            Tn = np.maximum(Tn, 0.0)
        return Tn, dTn

    def gaps(self, u: np.ndarray, h: float) -> tuple[np.ndarray, np.ndarray]:
        """Normal gaps (s, g) and current positions (s, g, 2)."""
        x, _ = self.quad.current(u)
        return h - x[..., 1], x

    def active(self, g: np.ndarray) -> np.ndarray:
        """Segments with at least one Gauss point closer than far_gap."""
        return np.flatnonzero(np.any(g < self.far_gap, axis=1))

    # -- residual and linearization --------------------------------------
    def _point_values(self, g: np.ndarray):
        near = g < self.far_gap
        Tn, dTn = self.traction(np.where(near, g, self.far_gap))
        return np.where(near, Tn, 0.0), np.where(near, dTn, 0.0)

    def force(self, u: np.ndarray, h: float) -> tuple[np.ndarray, float]:
        """Contact force vector on the cap (n_dofs) and Fn."""
        g, _ = self.gaps(u, h)
        act = self.active(g)
        Tn, _ = self._point_values(g[act])
        W = self.quad.weight[act]
        fy = -np.einsum("ga,sg,sg->sa", self.quad.N, Tn, W)  # T_y = -Tn
        f = np.zeros(self.n_dofs)
        np.add.at(f, 2 * self.quad.segments[act] + 1, fy)
        return f, float(-np.sum(Tn * W))

    def linearize(self, u: np.ndarray, h: float) -> ContactLinearization:
        g, _ = self.gaps(u, h)
        act = self.active(g)
        Tn, dTn = self._point_values(g[act])
        W = self.quad.weight[act]
        N = self.quad.N
        seg = self.quad.segments[act]
        f = np.zeros(self.n_dofs)
        np.add.at(f, 2 * seg + 1, -np.einsum("ga,sg,sg->sa", N, Tn, W))
        # dT_y/dy = Tn'(g) (g = h - y), so dR_ay/du_by = -int N_a N_b Tn' dA
        kyy = -np.einsum("ga,gb,sg,sg->sab", N, N, dTn, W)
        p1 = N.shape[1]
        blocks = np.zeros((len(act), p1, 2, p1, 2))
        blocks[:, :, 1, :, 1] = kyy
        dR_dh = np.zeros(self.n_dofs)
        np.add.at(dR_dh, 2 * seg + 1, np.einsum("ga,sg,sg->sa", N, dTn, W))  # -d(T_y)/dh = Tn'
        # Fn = -int Tn dA: dFn/du_by = int Tn' N_b dA, dFn/dh = -int Tn' dA
        return ContactLinearization(
            f=f, Fn=float(-np.sum(Tn * W)), blocks=blocks.reshape(len(act), 2 * p1, 2 * p1), active_segments=act,
            dR_dh=dR_dh, dFn_du=dR_dh.copy(), dFn_dh=float(-np.sum(dTn * W)),
        )


def interval_measures(x: np.ndarray, v: np.ndarray) -> tuple[float, float, float]:
    """Length and edges of the part of a polyline where an interpolated value is <= 0.

    ``x`` (n, 2) points ordered along the surface, ``v`` (n,) values at them
    (for the contact area: g_n - threshold). Linear interpolation of v
    between neighbours. Returns (length, x_left, x_right); edges are NaN
    when no part qualifies.
    """
    v0, v1 = v[:-1], v[1:]
    seg = np.linalg.norm(np.diff(x, axis=0), axis=1)
    both = (v0 <= 0) & (v1 <= 0)
    cross = (v0 <= 0) != (v1 <= 0)
    t = np.where(cross, v0 / np.where(cross, v0 - v1, 1.0), 0.0)  # where v crosses zero, from the first point
    frac = np.where(both, 1.0, np.where(cross, np.where(v0 <= 0, t, 1.0 - t), 0.0))
    length = float(np.sum(frac * seg))
    inside = np.flatnonzero(v <= 0)
    if len(inside) == 0:
        return length, float("nan"), float("nan")
    i, j = inside[0], inside[-1]
    if i > 0:
        ti = v[i - 1] / (v[i - 1] - v[i])
        xl = x[i - 1, 0] + ti * (x[i, 0] - x[i - 1, 0])
    else:
        xl = x[0, 0]
    if j < len(v) - 1:
        tj = v[j] / (v[j] - v[j + 1])
        xr = x[j, 0] + tj * (x[j + 1, 0] - x[j, 0])
    else:
        xr = x[-1, 0]
    return length, float(xl), float(xr)
