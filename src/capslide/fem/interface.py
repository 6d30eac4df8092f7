"""Contact of the cap's top surface with the rigid flat substrate.

The substrate's lower face is the line y = h; it slides in +x by ubar. At a
surface Gauss point with current position x = X + u the normal gap is
g_n = h - y (no closest-point search: the substrate is flat), the substrate
normal is n_p = (0, -1), and the traction on the cap per reference length is
T = theta_k Tn(g_n) n_p (J_l = 1, the substrate is rigid; Mergel et al. 2019,
eq. Tn): theta_k = 1 as in the paper, or theta_k = J_s = |dx/dX|, the cap's
surface stretch, with ``normal_per_current_area`` (Tn then acts per current
area: the approximation of theta_k that the paper attributes to Mergel's
thesis, analogous to J_l = J_cl). Sign
conventions: Fn = integral of T_y (positive = tensile); the residual of the
cap is R = f_int - f_contact.

Friction (docs/theory.md section 3): each Gauss point keeps an anchor xi, a material
point of the substrate in the substrate's frame; the tangential gap is
g_t = x - (xi + ubar), the trial traction per reference area -eps_t g_t,
returned to the threshold J_s t_slide(g_n) (model DI, J_s = |dx/dX| the
surface stretch) or T_slide(g_n) (model EA). The traction on the cap is
T_t e_x (positive in the sliding direction). The anchors are the friction
history: they are passed in explicitly (None: friction not started) and
renewed only by :meth:`SurfaceContact.committed_anchors` at converged steps.
With static and kinetic thresholds (``weakening``), the threshold weakens with
each point's accumulated slip (:func:`capslide.laws.contact.weakening_return_map`),
also an explicit input (``slip``, None: no weakening).

Only points with g_n below ``far_gap`` are evaluated and assembled: the
law's tail beyond it is dropped (the error it makes is a measured knob).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..laws import contact
from ..laws.friction import FrictionLaw, ReturnMapSettings
from ..params import Adhesion
from ..states import SlipState
from .element import QUADS, gauss_legendre, gauss_quad, line_shape
from .mesh import Mesh

__all__ = ["SurfaceQuadrature", "SurfaceContact", "ContactLinearization"]


@dataclass(frozen=True)
class SurfaceQuadrature:
    """Gauss points on the top-surface facets: line elements in 2D, ordered by reference x; bilinear quadrilateral
    faces in 3D (an n_gauss x n_gauss rule on each)."""

    segments: np.ndarray  # (s, p+1) node ids (3D: (s, 4))
    N: np.ndarray  # (g, p+1) shape functions at the Gauss points
    dN: np.ndarray  # (g, p+1) d/ds (3D: (g, 4, 2), d/dxi and d/deta)
    weight: np.ndarray  # (s, g) Gauss weight times the reference length (3D: area) element
    X: np.ndarray  # (s, g, d) reference positions
    X_nodes: np.ndarray  # (s, p+1, d) reference positions of the segment nodes

    @classmethod
    def on(cls, mesh: Mesh, n_gauss: int) -> SurfaceQuadrature:
        seg = mesh.surface_segments
        Xn = mesh.nodes[seg]  # (s, a, d)
        if mesh.dim == 3:
            points, w = gauss_quad(n_gauss)
            N, dN = QUADS["Q1"].shape(points)
            dX = np.einsum("gak,sai->sgik", dN, Xn)
            return cls(seg, N, dN, w * np.linalg.norm(np.cross(dX[..., 0], dX[..., 1]), axis=-1),
                       np.einsum("ga,sai->sgi", N, Xn), Xn)
        s, w = gauss_legendre(n_gauss)
        N, dN = line_shape(seg.shape[1] - 1, s)
        X = np.einsum("ga,sai->sgi", N, Xn)
        dX = np.einsum("ga,sai->sgi", dN, Xn)
        return cls(seg, N, dN, w * np.linalg.norm(dX, axis=-1), X, Xn)

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


@dataclass
class ContactLinearization:
    """Contact terms of the residual and their derivatives.

    ``f`` (n_dofs) contact force on the cap; ``Fn``, ``Ft`` its integrated y
    and x components; ``blocks`` (k, 2(p+1), 2(p+1)) dR/du of the active segments
    ``active_segments`` (R = f_int - f); ``dR_dh`` (n_dofs); ``dFn_du``
    (n_dofs); ``dFn_dh`` (scalar).
    """

    f: np.ndarray
    Fn: float
    Ft: float
    blocks: np.ndarray
    active_segments: np.ndarray
    dR_dh: np.ndarray
    dFn_du: np.ndarray
    dFn_dh: float


def _stretch(t: np.ndarray, ref_len: np.ndarray) -> np.ndarray:
    """The surface stretch J_s = |dx/ds| / |dX/ds| from the current tangents (..., 2) and reference lengths."""
    return np.linalg.norm(t, axis=-1) / ref_len


@dataclass
class _Points:
    """Pointwise contact quantities on the active segments (k, g)."""

    act: np.ndarray
    g: np.ndarray
    Tn: np.ndarray
    dTn: np.ndarray
    Tt: np.ndarray | None = None
    dTt_dx: np.ndarray | None = None  # d T_t / d x (tangential position)
    dTt_dg: np.ndarray | None = None  # d T_t / d g_n
    dTt_dJ: np.ndarray | None = None  # d T_t / d J_s (DI)
    t: np.ndarray | None = None  # current tangent dx/ds (k, g, 2)
    T_len: np.ndarray | None = None  # |dX/ds| (k, g)
    slipping: np.ndarray | None = None
    theta: np.ndarray | float = 1.0  # theta_k: 1, or the surface stretch J_s (k, g)

    @property
    def Tn_ref(self) -> np.ndarray:
        """The normal traction per reference area, theta_k Tn."""
        return self.theta * self.Tn

    def dJ_du(self) -> np.ndarray:
        """dJ_s/du_bi = dN_b t_i / (|t| |dX/ds|), without dN_b: (k, g, 2)."""
        return self.t / (np.linalg.norm(self.t, axis=-1) * self.T_len)[..., None]


class SurfaceContact:
    """CGCM normal contact and (optionally) DI/EA friction of the cap against the rigid flat y = h (z = h in 3D:
    the gap is measured along the last axis).

    ``law`` is the friction law (None: frictionless) and ``return_map`` its penalty and slip weakening; friction
    acts where anchors are given. ``normal_per_current_area``: theta_k = J_s instead of 1. In 3D the contact is
    frictionless with theta_k = 1 (friction and J_s on faces: issue 40). On a half model (a mesh with a plane of
    symmetry) the integrated quantities, Fn, Ft and the adhesion energy, and their derivatives, are the whole
    body's: twice the half's (``multiplicity``); the force vector is the half's.
    """

    def __init__(self, mesh: Mesh, adhesion: Adhesion, n_gauss: int, far_gap: float, repulsion_only: bool = False,
                 law: FrictionLaw | None = None, return_map: ReturnMapSettings | None = None,
                 contact_gap: float = np.inf, normal_per_current_area: bool = False):
        self.mesh, self.adhesion, self.law = mesh, adhesion, law
        return_map = return_map or ReturnMapSettings(0.0)
        self.eps_t, self.weakening = return_map.eps_t, return_map.weakening
        self.normal_per_current_area = normal_per_current_area
        self.contact_gap = contact_gap  # points with g_n <= contact_gap count as in contact
        self.quad = SurfaceQuadrature.on(mesh, n_gauss)
        self.far_gap = far_gap
        self.repulsion_only = repulsion_only
        self.dim = d = mesh.dim
        self.multiplicity = 2.0 if len(mesh.symmetry) else 1.0
        self.vertical = d - 1  # the axis of the gap and of the normal traction
        if d == 3 and (law is not None or normal_per_current_area):
            raise ValueError("3D contact is frictionless with the normal traction per reference area (issue 40)")
        seg = mesh.surface_segments
        self.seg_dofs = np.stack([d * seg + i for i in range(d)], axis=-1).reshape(len(seg), -1)  # (s, d(p+1))
        self.n_dofs = mesh.n_dofs
        if d == 2:
            dX = np.einsum("ga,sai->sgi", self.quad.dN, self.quad.X_nodes)
            self.ref_len = np.linalg.norm(dX, axis=-1)  # |dX/ds|, (s, g)

    def friction_active(self, anchors: np.ndarray | None) -> bool:
        return anchors is not None and self.law is not None

    # -- pointwise laws ---------------------------------------------------
    def traction(self, g: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Tn(g) and dTn/dg (regularized CGCM; repulsion only if asked: max(Tn, 0))."""
        a = self.adhesion
        Tn, dTn = contact.normal_traction(g, a.T0, a.r0, a.g_reg)
        if self.repulsion_only:
            dTn = np.where(Tn > 0.0, dTn, 0.0)
            Tn = np.maximum(Tn, 0.0)
        return Tn, dTn

    def theta(self, u: np.ndarray) -> np.ndarray | float:
        """theta_k of every point (s, g): the surface stretch J_s with ``normal_per_current_area``, else 1."""
        if not self.normal_per_current_area:
            return 1.0
        _, t = self.quad.current(u)
        return _stretch(t, self.ref_len)

    def gaps(self, u: np.ndarray, h: float) -> tuple[np.ndarray, np.ndarray]:
        """Normal gaps (s, g) and current positions (s, g, d)."""
        x, _ = self.quad.current(u)
        return h - x[..., self.vertical], x

    def active(self, g: np.ndarray) -> np.ndarray:
        """Segments with at least one Gauss point closer than far_gap."""
        return np.flatnonzero(np.any(g < self.far_gap, axis=1))

    def _points(self, u: np.ndarray, h: float, ubar: float, anchors: np.ndarray | None,
                slip: np.ndarray | None = None) -> _Points:
        x, t = self.quad.current(u)
        g = h - x[..., self.vertical]
        act = self.active(g)
        g, x, t = g[act], x[act], t[act]
        near = g < self.far_gap
        Tn, dTn = self.traction(np.where(near, g, self.far_gap))
        pts = _Points(act, g, np.where(near, Tn, 0.0), np.where(near, dTn, 0.0), t=t,
                      T_len=self.ref_len[act] if self.dim == 2 else None)
        friction = self.friction_active(anchors)
        J = _stretch(t, pts.T_len) if friction or self.normal_per_current_area else None
        if self.normal_per_current_area:
            pts.theta = J
        if friction:
            eps_t = self.eps_t
            thr, dthr_dg, dthr_dJ = (np.where(near, v, 0.0) for v in self.law.threshold(g, J))
            trial = -eps_t * (x[..., 0] - anchors[act] - ubar)
            if self.weakening is not None and slip is not None:
                ratio, D_c = self.weakening
                Tt, slipping, dT_dtrial, dT_dthr = contact.weakening_return_map(trial, thr, slip[act], ratio, D_c,
                                                                                eps_t)
            else:
                Tt, slipping, dT_dtrial, dT_dthr = contact.return_map(trial, thr)
            pts.Tt, pts.slipping = Tt, slipping
            pts.dTt_dx = -eps_t * dT_dtrial
            pts.dTt_dg = dT_dthr * dthr_dg
            pts.dTt_dJ = dT_dthr * dthr_dJ
        return pts

    # -- residual and linearization --------------------------------------
    def force(self, u: np.ndarray, h: float, ubar: float = 0.0, anchors: np.ndarray | None = None,
              slip: np.ndarray | None = None) -> tuple[np.ndarray, float, float]:
        """Contact force vector on the cap (n_dofs), Fn and Ft."""
        pts = self._points(u, h, ubar, anchors, slip)
        W, N, seg = self.quad.weight[pts.act], self.quad.N, self.quad.segments[pts.act]
        f = np.zeros(self.n_dofs)
        np.add.at(f, self.dim * seg + self.vertical, -np.einsum("ga,sg,sg->sa", N, pts.Tn_ref, W))  # T_y = -theta_k Tn
        Ft = 0.0
        if pts.Tt is not None:
            np.add.at(f, 2 * seg, np.einsum("ga,sg,sg->sa", N, pts.Tt, W))
            Ft = float(np.sum(pts.Tt * W))
        return f, self.whole(float(-np.sum(pts.Tn_ref * W))), self.whole(Ft)

    def whole(self, value):
        """An integral over the modelled part as the whole body's (half model: twice it)."""
        return value if self.multiplicity == 1.0 else self.multiplicity * value

    def linearize(self, u: np.ndarray, h: float, ubar: float = 0.0, anchors: np.ndarray | None = None,
                  slip: np.ndarray | None = None) -> ContactLinearization:
        pts = self._points(u, h, ubar, anchors, slip)
        act = pts.act
        W, N, dN = self.quad.weight[act], self.quad.N, self.quad.dN
        seg = self.quad.segments[act]
        p1, d, v = N.shape[1], self.dim, self.vertical
        f = np.zeros(self.n_dofs)
        np.add.at(f, d * seg + v, -np.einsum("ga,sg,sg->sa", N, pts.Tn_ref, W))
        blocks = np.zeros((len(act), p1, d, p1, d))
        dTn = pts.theta * pts.dTn  # theta_k Tn'
        # normal: dT_y/dy = theta_k Tn'(g) (g = h - y), so dR_ay/du_by = -int N_a N_b theta_k Tn' dA
        blocks[:, :, v, :, v] = -np.einsum("ga,gb,sg,sg->sab", N, N, dTn, W)
        dR_dh = np.zeros(self.n_dofs)
        np.add.at(dR_dh, d * seg + v, np.einsum("ga,sg,sg->sa", N, dTn, W))  # -d(T_y)/dh = theta_k Tn'
        dFn_du = dR_dh.copy()  # Fn = -int theta_k Tn dA: dFn/du_by = int theta_k Tn' N_b dA
        NW = N[None] * W[..., None]  # (k, g, a)
        if self.normal_per_current_area:  # theta_k = J_s: R_ay = ... + int N_a Tn J_s dA, Fn = -int Tn J_s dA
            dJ = pts.dJ_du()
            blocks[:, :, 1, :, :] += np.einsum("sga,gb,sg,sgi->sabi", NW, dN, pts.Tn, dJ)
            np.add.at(dFn_du, self.seg_dofs[act], -np.einsum("sg,gb,sg,sgi->sbi", W, dN, pts.Tn, dJ).reshape(len(act), -1))
        Ft = 0.0
        if pts.Tt is not None:
            np.add.at(f, 2 * seg, np.einsum("ga,sg,sg->sa", N, pts.Tt, W))
            Ft = float(np.sum(pts.Tt * W))
            # R_ax = ... - int N_a T_t dA; T_t depends on x_x (stick), g_n = h - y and J_s (slip)
            blocks[:, :, 0, :, 0] -= np.einsum("sga,gb,sg->sab", NW, N, pts.dTt_dx)
            blocks[:, :, 0, :, 1] += np.einsum("sga,gb,sg->sab", NW, N, pts.dTt_dg)  # dg/dy = -1
            blocks[:, :, 0, :, :] -= np.einsum("sga,gb,sg,sgi->sabi", NW, dN, pts.dTt_dJ, pts.dJ_du())
            np.add.at(dR_dh, 2 * seg, -np.einsum("sga,sg->sa", NW, pts.dTt_dg))
        return ContactLinearization(
            f=f, Fn=self.whole(float(-np.sum(pts.Tn_ref * W))), Ft=self.whole(Ft),
            blocks=blocks.reshape(len(act), d * p1, d * p1), active_segments=act, dR_dh=dR_dh,
            dFn_du=self.whole(dFn_du), dFn_dh=self.whole(float(-np.sum(dTn * W))),
        )

    def adhesion_energy(self, u: np.ndarray, h: float) -> float:
        """The adhesive potential of the interface per unit width (E L0^2), sum of phi(g_n) dA
        (:func:`capslide.laws.contact.normal_potential`, the tail beyond far_gap dropped as the force drops it;
        NaN with theta_k = J_s, whose traction has no such potential)."""
        a = self.adhesion
        g, _ = self.gaps(u, h)
        W = self.quad.weight
        phi = contact.normal_potential(g, a.T0, a.r0, a.g_reg, self.far_gap)
        if self.repulsion_only:  # max(Tn, 0): the potential of the repulsive part, zero beyond g_eq
            phi = np.maximum(phi - contact.normal_potential(a.g_eq, a.T0, a.r0, a.g_reg, self.far_gap), 0.0)
        return self.whole(float(np.sum(phi * W))) if not self.normal_per_current_area else float("nan")

    # -- friction history ---------------------------------------------------
    def anchors_at(self, u: np.ndarray, ubar: float = 0.0) -> np.ndarray:
        """Anchors of every point where it is: zero tangential gap, (s, g)."""
        x, _ = self.quad.current(u)
        return x[..., 0] - ubar

    def tangential_state(self, u: np.ndarray, h: float, ubar: float, anchors: np.ndarray | None,
                         slip: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
        """Per point (s, g): tangential traction T_t and slip states (:class:`capslide.states.SlipState`).

        Points in contact where no friction acts (no law, or no anchors yet) report FRICTIONLESS.
        """
        Tt = np.zeros(self.quad.weight.shape)
        state = np.full(Tt.shape, SlipState.FREE, dtype=np.int8)
        g, _ = self.gaps(u, h)
        in_contact = g <= self.contact_gap
        if self.friction_active(anchors):
            pts = self._points(u, h, ubar, anchors, slip)
            Tt[pts.act] = pts.Tt
            st = np.where(pts.slipping, SlipState.SLIP, SlipState.STICK).astype(np.int8)
            state[pts.act] = st
            state[~in_contact] = SlipState.FREE
        else:
            state[in_contact] = SlipState.FRICTIONLESS
        return Tt, state

    def committed_anchors(self, u: np.ndarray, h: float, ubar: float, anchors: np.ndarray | None,
                          slip: np.ndarray | None = None) -> np.ndarray | None:
        """The anchors after the converged state (u, h, ubar): slipping points move with the return map."""
        if not self.friction_active(anchors):
            return anchors
        x, _ = self.quad.current(u)
        Tt, _ = self.tangential_state(u, h, ubar, anchors, slip)
        # anchor such that -eps_t (x - xi - ubar) = T_t
        return x[..., 0] - ubar + Tt / self.eps_t
