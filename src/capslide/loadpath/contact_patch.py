"""The contact patch of a 3D state: the area and extents of the part of the top surface where a nodal field is
at or below zero (for the contact area: the gap minus the contact gap).

The field and the positions are interpolated bilinearly on each top face, as the trilinear cells carry them. A face
whose four nodes are all in (or all out) is wholly in (out): a bilinear function takes its extremes at the corners.
A face wholly in counts with its area (2 x 2 Gauss points); a face with nodes on both sides is sampled at the
midpoints of an m x m grid of sub-squares, each weighted by its area |dx/dxi x dx/deta| (2/m)^2 (m = 16).

Values are the half model's, times ``multiplicity`` for the whole body's area and lateral width. The outlines of a
snapshot (:func:`snapshot_outlines`) are the whole body's: a half model's curves closed with their mirror images.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..fem.element import QUADS, gauss_quad

__all__ = ["Patch", "contact_patch", "zero_contour", "snapshot_outlines", "SUBDIVISION"]

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


def zero_contour(points: np.ndarray, value: np.ndarray, faces: np.ndarray, mirror_y: bool = False) -> np.ndarray:
    """The curve where a nodal field crosses zero on quadrilateral ``faces`` (n_faces, 4) of nodes at ``points``
    (n_nodes, 2), as polylines joined end to end with a row of NaN between them (n, 2); empty when the field does not
    change sign. The field is linear along each face edge, so each crossing is interpolated on its edge; a face
    with four crossings (a saddle) pairs them by the sign of the mean of its nodal values. ``mirror_y``: the faces
    are a half model's (y >= 0), and a polyline with both ends on y = 0 is closed with its mirror image (the whole
    body's curve)."""
    v = value[faces]
    below = v <= 0.0
    crossed = np.flatnonzero(below.any(axis=1) & ~below.all(axis=1))
    point_of: dict[tuple[int, int], np.ndarray] = {}
    links: dict[tuple[int, int], list[tuple[int, int]]] = {}
    for f in crossed:
        nodes, vals, ins = faces[f], v[f], below[f]
        edges = [(k, (k + 1) % 4) for k in range(4) if ins[k] != ins[(k + 1) % 4]]
        keys = []
        for a, b in edges:
            key = (min(nodes[a], nodes[b]), max(nodes[a], nodes[b]))
            t = vals[a] / (vals[a] - vals[b])
            point_of[key] = points[nodes[a]] + t * (points[nodes[b]] - points[nodes[a]])
            keys.append(key)
        if len(keys) == 4 and (vals.mean() <= 0.0) != ins[0]:  # a saddle whose centre is on node 1's side:
            keys = [keys[1], keys[2], keys[3], keys[0]]  # cut off the corners 0 and 2, not 1 and 3
        for p, q in zip(keys[0::2], keys[1::2]):
            links.setdefault(p, []).append(q)
            links.setdefault(q, []).append(p)
    return _polylines(point_of, links, mirror_y)


def _polylines(point_of: dict, links: dict, mirror_y: bool) -> np.ndarray:
    """The crossing points chained along their links into polylines (open chains start at an end)."""
    unused = set(point_of)
    curves = []
    while unused:
        ends = [k for k in unused if len(links.get(k, [])) == 1]
        start = min(ends) if ends else min(unused)
        chain, prev = [start], None
        unused.discard(start)
        while True:
            nxt = [k for k in links.get(chain[-1], []) if k != prev and k in unused]
            if not nxt:
                break
            prev = chain[-1]
            chain.append(nxt[0])
            unused.discard(nxt[0])
        xy = np.array([point_of[k] for k in chain])
        if len(chain) > 2 and chain[0] in links.get(chain[-1], []):  # a closed loop (and its mirror image)
            curves += [np.vstack([xy, xy[:1]])] + ([np.vstack([xy, xy[:1]]) * [1.0, -1.0]] if mirror_y else [])
            continue
        if mirror_y and len(xy) > 1:  # ends on y = 0: closed with its mirror image
            xy = np.vstack([xy, (xy * [1.0, -1.0])[::-1], xy[:1]])
        curves.append(xy)
    curves.sort(key=len, reverse=True)
    out = []
    for xy in curves:
        out += [xy, np.full((1, 2), np.nan)]
    return np.vstack(out[:-1]) if out else np.zeros((0, 2))


def snapshot_outlines(positions: np.ndarray, gap: np.ndarray, faces: np.ndarray, stick_fraction: np.ndarray,
                      area_gap: float, mirror_y: bool = True) -> tuple[np.ndarray, np.ndarray]:
    """The whole body's contact outline and stick-zone outline in the contact plane (current x, y; L0), each as
    :func:`zero_contour` gives it, from a half model's top ``faces`` (``mirror_y``; else the whole model's) with
    nodes at ``positions`` (n_nodes, 3):
    the contact edge where the nodal gap equals ``area_gap``; the stick zone's edge where the nodal share of
    sticking surface points (``stick_fraction`` per face, averaged at the nodes) is one half, which places it
    within about a face of the points' states."""
    xy = positions[:, :2]
    contact = zero_contour(xy, gap - area_gap, faces, mirror_y)
    share, count = np.zeros(len(positions)), np.zeros(len(positions))
    np.add.at(share, faces, np.repeat(stick_fraction[:, None], faces.shape[1], axis=1))
    np.add.at(count, faces, 1.0)
    nodal = np.divide(share, count, out=np.zeros_like(share), where=count > 0)
    return contact, zero_contour(xy, 0.5 - nodal, faces, mirror_y)
