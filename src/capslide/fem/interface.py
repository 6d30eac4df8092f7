"""Contact of the cap's top surface with the rigid flat substrate.

The substrate's lower face is the line y = h (the plane z = h in 3D: the gap
and the normal traction act along the last axis); it slides in +x by ubar. At a
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
T_t e_x (positive in the sliding direction). In 3D the anchor, the tangential
gap and the traction are vectors (x, y) in the contact plane, returned radially
(:func:`capslide.laws.contact.vector_return_map`), and J_s is the area stretch
(:mod:`capslide.fem.surface`). The anchors are the friction
history: they are passed in explicitly (None: friction not started) and
renewed only by :meth:`SurfaceContact.committed_anchors` at converged steps.
With static and kinetic thresholds (``weakening``), the threshold weakens with
each point's accumulated slip (:func:`capslide.laws.contact.weakening_return_map`),
also an explicit input (``slip``, None: no weakening). With the threshold fixed
over a step (``friction.threshold_at = step_start``), the thresholds of the
step's start state (:meth:`SurfaceContact.point_thresholds`) are a third
explicit input (``thresholds``): the return map then takes them as they are,
with no derivative in g_n or J_s.

Only points with g_n below ``far_gap`` are evaluated and assembled: the
law's tail beyond it is dropped (the error it makes is a measured knob).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..laws import contact
from ..laws.friction import FrictionLaw, ReturnMapSettings
from ..laws.normal import normal_law
from ..params import Adhesion
from ..states import SlipState
from .mesh import Mesh
from .surface import SurfaceQuadrature, stretch, stretch_gradient_3d

__all__ = ["SurfaceQuadrature", "SurfaceContact", "ContactLinearization"]


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
    t: np.ndarray | None = None  # current tangent dx/ds (k, g, 2); 3D: (x,xi, x,eta) (k, g, 3, 2)
    T_len: np.ndarray | None = None  # reference measure |dX/ds| (k, g); 3D: |X,xi x X,eta|
    slipping: np.ndarray | None = None
    theta: np.ndarray | float = 1.0  # theta_k: 1, or the surface stretch J_s (k, g)

    @property
    def Tn_ref(self) -> np.ndarray:
        """The normal traction per reference area, theta_k Tn."""
        return self.theta * self.Tn

    def dJ_du(self) -> np.ndarray:
        """dJ_s/du_bi = dN_b t_i / (|t| |dX/ds|), without dN_b: (k, g, 2)."""
        return self.t / (np.linalg.norm(self.t, axis=-1) * self.T_len)[..., None]

    def dJ_du_3d(self, dN: np.ndarray) -> np.ndarray:
        """3D: dJ_s/du_bi with the shape gradients dN (g, b, 2) of the face: (k, g, b, 3)."""
        return stretch_gradient_3d(self.t, self.T_len, dN)


class SurfaceContact:
    """CGCM normal contact and (optionally) DI/EA friction of the cap against the rigid flat y = h (z = h in 3D:
    the gap is measured along the last axis).

    ``law`` is the friction law (None: frictionless) and ``return_map`` its penalty and slip weakening; friction
    acts where anchors are given. ``normal_per_current_area``: theta_k = J_s instead of 1. On a half model (a mesh
    with a plane of symmetry) the integrated quantities, Fn, Ft and the adhesion energy, and their derivatives, are
    the whole body's: twice the half's (``multiplicity``); the force vector is the half's.
    """

    def __init__(self, mesh: Mesh, adhesion: Adhesion, n_gauss: int, far_gap: float, repulsion_only: bool = False,
                 law: FrictionLaw | None = None, return_map: ReturnMapSettings | None = None,
                 contact_gap: float = np.inf, normal_per_current_area: bool = False):
        self.mesh, self.adhesion, self.law = mesh, adhesion, law
        self.normal_law = normal_law(adhesion)
        return_map = return_map or ReturnMapSettings(0.0)
        self.eps_t, self.weakening = return_map.eps_t, return_map.weakening
        self.threshold_at_step_start = return_map.threshold_at_step_start
        self.normal_per_current_area = normal_per_current_area
        self.contact_gap = contact_gap  # points with g_n <= contact_gap count as in contact
        self.quad = SurfaceQuadrature.on(mesh, n_gauss)
        self.far_gap = far_gap
        self.repulsion_only = repulsion_only
        self.dim = d = mesh.dim
        self.multiplicity = 2.0 if len(mesh.symmetry) else 1.0
        self.vertical = d - 1  # the axis of the gap and of the normal traction
        seg = mesh.surface_segments
        self.seg_dofs = np.stack([d * seg + i for i in range(d)], axis=-1).reshape(len(seg), -1)  # (s, d(p+1))
        self.n_dofs = mesh.n_dofs
        self.ref_len = self.quad.ref_measure  # |dX/ds| (s, g); 3D: |X,xi x X,eta|

    def friction_active(self, anchors: np.ndarray | None) -> bool:
        return anchors is not None and self.law is not None

    # -- pointwise laws ---------------------------------------------------
    def traction(self, g: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Tn(g) and dTn/dg (the normal law: regularized CGCM, or Dugdale's; repulsion only if asked: max(Tn, 0))."""
        Tn, dTn = self.normal_law.traction(g)
        if self.repulsion_only:
            dTn = np.where(Tn > 0.0, dTn, 0.0)
            Tn = np.maximum(Tn, 0.0)
        return Tn, dTn

    def theta(self, u: np.ndarray) -> np.ndarray | float:
        """theta_k of every point (s, g): the surface stretch J_s with ``normal_per_current_area``, else 1."""
        if not self.normal_per_current_area:
            return 1.0
        _, t = self.quad.current(u)
        return stretch(t, self.ref_len, self.dim)

    def gaps(self, u: np.ndarray, h: float) -> tuple[np.ndarray, np.ndarray]:
        """Normal gaps (s, g) and current positions (s, g, d)."""
        x, _ = self.quad.current(u)
        return h - x[..., self.vertical], x

    def active(self, g: np.ndarray) -> np.ndarray:
        """Segments with at least one Gauss point closer than far_gap."""
        return np.flatnonzero(np.any(g < self.far_gap, axis=1))

    def _points(self, u: np.ndarray, h: float, ubar: float, anchors: np.ndarray | None,
                slip: np.ndarray | None = None, thresholds: np.ndarray | None = None) -> _Points:
        x, t = self.quad.current(u)
        g = h - x[..., self.vertical]
        act = self.active(g)
        g, x, t = g[act], x[act], t[act]
        near = g < self.far_gap
        Tn, dTn = self.traction(np.where(near, g, self.far_gap))
        pts = _Points(act, g, np.where(near, Tn, 0.0), np.where(near, dTn, 0.0), t=t,
                      T_len=self.ref_len[act])
        friction = self.friction_active(anchors)
        J = stretch(t, pts.T_len, self.dim) if friction or self.normal_per_current_area else None
        if self.normal_per_current_area:
            pts.theta = J
        if friction:
            eps_t = self.eps_t
            if self.threshold_at_step_start and thresholds is not None:  # fixed over the step
                thr = thresholds[act]
                dthr_dg = dthr_dJ = np.zeros_like(thr)
            else:
                thr, dthr_dg, dthr_dJ = (np.where(near, v, 0.0) for v in self.law.threshold(g, J))
            if self.dim == 3:  # the vector tangential gap in the plane, (x, y) - anchor - (ubar, 0)
                trial = -eps_t * (x[..., :2] - anchors[act] - np.array([ubar, 0.0]))
                dthr_dg, dthr_dJ = dthr_dg[..., None], dthr_dJ[..., None]
            else:
                trial = -eps_t * (x[..., 0] - anchors[act] - ubar)
            Tt, slipping, dT_dtrial, dT_dthr = self._return_map(trial, thr, None if slip is None else slip[act])
            pts.Tt, pts.slipping = Tt, slipping
            pts.dTt_dx = -eps_t * dT_dtrial
            pts.dTt_dg = dT_dthr * dthr_dg
            pts.dTt_dJ = dT_dthr * dthr_dJ
        return pts

    def _return_map(self, trial: np.ndarray, threshold: np.ndarray, slip: np.ndarray | None):
        """The return map of the trial tractions (scalar in 2D, vector in 3D), weakening with the accumulated
        ``slip`` when the thresholds are static and kinetic."""
        if self.weakening is not None and slip is not None:
            ratio, D_c = self.weakening
            magnitude = lambda T, thr: contact.weakening_return_map(T, thr, slip, ratio, D_c, self.eps_t)  # noqa: E731
        else:
            magnitude = contact.return_map
        return magnitude(trial, threshold) if self.dim == 2 else contact.vector_return_map(trial, threshold, magnitude)

    # -- residual and linearization --------------------------------------
    def force(self, u: np.ndarray, h: float, ubar: float = 0.0, anchors: np.ndarray | None = None,
              slip: np.ndarray | None = None, thresholds: np.ndarray | None = None) -> tuple[np.ndarray, float, float]:
        """Contact force vector on the cap (n_dofs), Fn and Ft."""
        pts = self._points(u, h, ubar, anchors, slip, thresholds)
        W, N, seg = self.quad.weight[pts.act], self.quad.N, self.quad.segments[pts.act]
        f = np.zeros(self.n_dofs)
        np.add.at(f, self.dim * seg + self.vertical, -np.einsum("ga,sg,sg->sa", N, pts.Tn_ref, W))  # T_y = -theta_k Tn
        Ft = 0.0
        if pts.Tt is not None:
            Ft = self._add_tangential_force(f, pts, W, seg)
        return f, self.whole(float(-np.sum(pts.Tn_ref * W))), self.whole(Ft)

    def _add_tangential_force(self, f: np.ndarray, pts: _Points, W: np.ndarray, seg: np.ndarray) -> float:
        """Adds the friction tractions' nodal forces to f; returns their integrated x component (the half's)."""
        N = self.quad.N
        if self.dim == 3:
            np.add.at(f, 3 * seg[..., None] + np.arange(2), np.einsum("ga,sgi,sg->sai", N, pts.Tt, W))
            return float(np.sum(pts.Tt[..., 0] * W))
        np.add.at(f, 2 * seg, np.einsum("ga,sg,sg->sa", N, pts.Tt, W))
        return float(np.sum(pts.Tt * W))

    def whole(self, value):
        """An integral over the modelled part as the whole body's (half model: twice it)."""
        return value if self.multiplicity == 1.0 else self.multiplicity * value

    def linearize(self, u: np.ndarray, h: float, ubar: float = 0.0, anchors: np.ndarray | None = None,
                  slip: np.ndarray | None = None, thresholds: np.ndarray | None = None) -> ContactLinearization:
        pts = self._points(u, h, ubar, anchors, slip, thresholds)
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
        dJ = None
        if self.normal_per_current_area:  # theta_k = J_s: R_ay = ... + int N_a Tn J_s dA, Fn = -int Tn J_s dA
            if d == 3:
                dJ = pts.dJ_du_3d(dN)  # (k, g, b, 3)
                blocks[:, :, v, :, :] += np.einsum("sga,sg,sgbi->sabi", NW, pts.Tn, dJ)
                dFn_dJ = -np.einsum("sg,sg,sgbi->sbi", W, pts.Tn, dJ)
            else:
                dJ = pts.dJ_du()
                blocks[:, :, 1, :, :] += np.einsum("sga,gb,sg,sgi->sabi", NW, dN, pts.Tn, dJ)
                dFn_dJ = -np.einsum("sg,gb,sg,sgi->sbi", W, dN, pts.Tn, dJ)
            np.add.at(dFn_du, self.seg_dofs[act], dFn_dJ.reshape(len(act), -1))
        Ft = 0.0
        if pts.Tt is not None:
            Ft = self._add_tangential_force(f, pts, W, seg)
            if d == 3:
                self._friction_blocks_3d(blocks, dR_dh, pts, NW, seg, dJ if dJ is not None else pts.dJ_du_3d(dN))
            else:
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

    def _friction_blocks_3d(self, blocks, dR_dh, pts: _Points, NW: np.ndarray, seg: np.ndarray, dJ: np.ndarray):
        """3D: adds the friction tractions' derivatives to the blocks (k, a, 3, b, 3) and dR/dh. R_ai (i = x, y)
        = ... - int N_a T_i dA; T depends on the in-plane position (stick), on g_n = h - z and on J_s (slip)."""
        N = self.quad.N
        blocks[:, :, :2, :, :2] -= np.einsum("sga,gb,sgij->saibj", NW, N, pts.dTt_dx)
        blocks[:, :, :2, :, 2] += np.einsum("sga,gb,sgi->saib", NW, N, pts.dTt_dg)  # dg/dz = -1
        blocks[:, :, :2, :, :] -= np.einsum("sga,sgi,sgbj->saibj", NW, pts.dTt_dJ, dJ)
        np.add.at(dR_dh, 3 * seg[..., None] + np.arange(2), -np.einsum("sga,sgi->sai", NW, pts.dTt_dg))

    def adhesion_energy(self, u: np.ndarray, h: float) -> float:
        """The adhesive potential of the interface per unit width (E L0^2), sum of phi(g_n) dA
        (the normal law's potential, :mod:`capslide.laws.normal`, the tail beyond far_gap dropped as the force drops it;
        NaN with theta_k = J_s, whose traction has no such potential)."""
        a = self.adhesion
        g, _ = self.gaps(u, h)
        W = self.quad.weight
        phi = self.normal_law.potential(g, self.far_gap)
        if self.repulsion_only:  # max(Tn, 0): the potential of the repulsive part, zero beyond g_eq
            phi = np.maximum(phi - self.normal_law.potential(a.g_eq, self.far_gap), 0.0)
        return self.whole(float(np.sum(phi * W))) if not self.normal_per_current_area else float("nan")

    def friction_energy(self, u: np.ndarray, h: float, ubar: float, anchors: np.ndarray | None,
                        thresholds: np.ndarray | None) -> float:
        """The friction's potential over a step whose thresholds are held at its start (``thresholds``), sum of
        psi(|tangential gap|) dA on the active segments' points (:func:`capslide.laws.contact.tangential_potential`;
        E L0^2 per unit width, in 3D E L0^3, the whole body's): its gradient is the negative of the friction forces
        of :meth:`force`. 0 without friction; NaN where the threshold follows the state (no such potential)."""
        if not self.friction_active(anchors):
            return 0.0
        if thresholds is None or self.weakening is not None or not self.threshold_at_step_start:
            return float("nan")
        x, _ = self.quad.current(u)
        act = self.active(h - x[..., self.vertical])
        gap = self._in_plane(x[act], ubar) - anchors[act]
        d = np.linalg.norm(gap, axis=-1) if self.dim == 3 else gap
        psi = contact.tangential_potential(d, thresholds[act], self.eps_t)
        return self.whole(float(np.sum(psi * self.quad.weight[act])))

    # -- friction history ---------------------------------------------------
    def _in_plane(self, x: np.ndarray, ubar: float) -> np.ndarray:
        """Positions in the substrate's frame: x - ubar (s, g) in 2D, (x - ubar, y) (s, g, 2) in 3D."""
        return x[..., 0] - ubar if self.dim == 2 else x[..., :2] - np.array([ubar, 0.0])

    def anchors_at(self, u: np.ndarray, ubar: float = 0.0) -> np.ndarray:
        """Anchors of every point where it is: zero tangential gap, (s, g); 3D: (s, g, 2)."""
        x, _ = self.quad.current(u)
        return self._in_plane(x, ubar)

    def tangential_state(self, u: np.ndarray, h: float, ubar: float, anchors: np.ndarray | None,
                         slip: np.ndarray | None = None, thresholds: np.ndarray | None = None
                         ) -> tuple[np.ndarray, np.ndarray]:
        """Per point (s, g): tangential traction T_t (3D: (s, g, 2), x and y) and slip states
        (:class:`capslide.states.SlipState`).

        Points in contact where no friction acts (no law, or no anchors yet) report FRICTIONLESS.
        """
        points = self.quad.weight.shape
        Tt = np.zeros(points if self.dim == 2 else (*points, 2))
        state = np.full(points, SlipState.FREE, dtype=np.int8)
        g, _ = self.gaps(u, h)
        in_contact = g <= self.contact_gap
        if self.friction_active(anchors):
            pts = self._points(u, h, ubar, anchors, slip, thresholds)
            Tt[pts.act] = pts.Tt
            st = np.where(pts.slipping, SlipState.SLIP, SlipState.STICK).astype(np.int8)
            state[pts.act] = st
            state[~in_contact] = SlipState.FREE
        else:
            state[in_contact] = SlipState.FRICTIONLESS
        return Tt, state

    def committed_anchors(self, u: np.ndarray, h: float, ubar: float, anchors: np.ndarray | None,
                          slip: np.ndarray | None = None, thresholds: np.ndarray | None = None) -> np.ndarray | None:
        """The anchors after the converged state (u, h, ubar): slipping points move with the return map."""
        if not self.friction_active(anchors):
            return anchors
        x, _ = self.quad.current(u)
        Tt, _ = self.tangential_state(u, h, ubar, anchors, slip, thresholds)
        # anchor such that -eps_t (x - xi - ubar) = T_t
        return self._in_plane(x, ubar) + Tt / self.eps_t

    def point_thresholds(self, u: np.ndarray, h: float, before: tuple[np.ndarray, float] | None = None,
                         ratio: float = 0.0) -> np.ndarray | None:
        """The law's sliding threshold per reference area at every point (s, g) of the state (u, h), zero beyond
        far_gap: the thresholds a step from this state holds fixed (``threshold_at_step_start``); None when the
        threshold follows the current state or there is no law. With ``before``, the state (u, h) one step earlier:
        the thresholds at the gap and surface stretch extrapolated linearly from the two states to the end of a step
        ``ratio`` times the last one's (``friction.threshold_at = step_predicted``)."""
        if not self.threshold_at_step_start or self.law is None:
            return None
        g, J = self._gap_and_stretch(u, h)
        if before is not None:
            g_before, J_before = self._gap_and_stretch(*before)
            g, J = g + ratio * (g - g_before), J + ratio * (J - J_before)
        near = g < self.far_gap
        thr, _, _ = self.law.threshold(np.where(near, g, self.far_gap), J)
        return np.where(near, thr, 0.0)

    def _gap_and_stretch(self, u: np.ndarray, h: float) -> tuple[np.ndarray, np.ndarray]:
        x, t = self.quad.current(u)
        return h - x[..., self.vertical], stretch(t, self.ref_len, self.dim)
