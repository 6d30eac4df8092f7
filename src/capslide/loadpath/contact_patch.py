"""The contact patch of a 3D state: the area and extents of the part of the top surface where a nodal field is
at or below zero (for the contact area: the gap minus the contact gap).

The field and the positions are interpolated bilinearly on each top face, as the trilinear cells carry them. A face
whose four nodes are all in (or all out) is wholly in (out): a bilinear function takes its extremes at the corners.
A face wholly in counts with its area (2 x 2 Gauss points); a face with nodes on both sides is sampled at the
midpoints of an m x m grid of sub-squares, each weighted by its area |dx/dxi x dx/deta| (2/m)^2 (m = 16).

Values are the half model's, times ``multiplicity`` for the whole body's area and lateral width.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..fem.element import QUADS, gauss_quad

__all__ = ["Patch", "contact_patch", "SUBDIVISION"]

SUBDIVISION = 16  # m: sub-squares per face edge where a face is partly in contact


@dataclass(frozen=True)
class Patch:
    """Area (L0^2, the whole body's), extent along x (x_left, x_right: current x of the patch's ends, L0) and width
    along y (the whole body's: twice the half model's largest y in the patch, L0); NaN extents when empty."""

    area: float
    x_left: float
    x_right: float
    width_y: float


def _subsamples(m: int) -> tuple[np.ndarray, np.ndarray, float]:
    """Q1 shape values (m*m, 4) and gradients (m*m, 4, 2) at the sub-square midpoints, and each one's reference
    area."""
    s = -1.0 + (2.0 * np.arange(m) + 1.0) / m
    X, Y = np.meshgrid(s, s, indexing="ij")
    N, dN = QUADS["Q1"].shape(np.column_stack([X.ravel(), Y.ravel()]))
    return N, dN, (2.0 / m) ** 2


def contact_patch(positions: np.ndarray, value: np.ndarray, faces: np.ndarray, multiplicity: float = 1.0,
                  m: int = SUBDIVISION) -> Patch:
    """The patch where ``value`` (n_nodes,) <= 0 on ``faces`` (n_faces, 4) of nodes at ``positions`` (n_nodes, 3)."""
    v = value[faces]  # (f, 4)
    inside = np.all(v <= 0.0, axis=1)
    mixed = ~inside & np.any(v <= 0.0, axis=1)
    N, dN, w = _subsamples(m)
    area, xs, ys = 0.0, [], []
    if inside.any():
        P = positions[faces[inside]]  # (k, 4, 3)
        points, weights = gauss_quad(2)
        J = np.einsum("gak,fai->fgik", QUADS["Q1"].shape(points)[1], P)
        area += float(np.sum(np.linalg.norm(np.cross(J[..., 0], J[..., 1]), axis=-1) * weights))
        xs.append(P[..., 0].ravel())
        ys.append(P[..., 1].ravel())
    if mixed.any():
        P = positions[faces[mixed]]
        vals = np.einsum("ga,fa->fg", N, v[mixed])
        x = np.einsum("ga,fai->fgi", N, P)
        J = np.einsum("gak,fai->fgik", dN, P)
        da = np.linalg.norm(np.cross(J[..., 0], J[..., 1]), axis=-1) * w
        hit = vals <= 0.0
        area += float(np.sum(da[hit]))
        xs.append(x[..., 0][hit])
        ys.append(x[..., 1][hit])
    if not xs or sum(len(a) for a in xs) == 0:
        return Patch(0.0, math.nan, math.nan, math.nan)
    x_all, y_all = np.concatenate(xs), np.concatenate(ys)
    width = (multiplicity * float(y_all.max())) if multiplicity != 1.0 else float(y_all.max() - y_all.min())
    return Patch(multiplicity * area, float(x_all.min()), float(x_all.max()), width)
