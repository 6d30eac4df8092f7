"""Meshes: the Mesh dataclass and the graded mesher of the cylindrical cap.

The cap is the circular segment of radius R and height H whose flat base
lies on y = 0 between x = -b and b (b = sqrt(H (2R - H))) and whose apex is
(0, H). It is meshed in a logical rectangle (u, v) in [-U, U] x [0, H] and
mapped onto the segment by a transfinite (Coons) patch with four logical
corners: the two base corners and two arc points P_L, P_R. The logical top
edge is the arc between P_L and P_R (u is arc length), the logical sides are
the arc pieces down to the base corners, so no element degenerates at the
corners where the arc meets the base.

Grading: square elements of size h0 along the top surface inside the contact
band |u| <= band_half_width, columns growing geometrically toward the sides,
layers growing with depth; below every few layers a transition layer merges
three narrow columns into one with the conforming 3:1 template
(fine: three quads on top; coarse: one trapezoid below, two interior nodes).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..laws import material
from .element import CELLS

__all__ = ["Mesh", "CapMeshSpec", "cap_mesh", "cell_and_node_counts", "band_limit", "BandTooWide", "rectangle_mesh",
           "circular_segment_area", "arc_angles", "coons_map", "H0_AT_SIZE_1"]

# Surface element size (L0) at mesh.size = 1, with 4 layers per level: the
# paper's cap then has 41,720 Q1 cells, its 42,300-element level
# (Mergel et al. 2019, section 5). Element sizes scale with mesh.size.
H0_AT_SIZE_1 = 0.0045


@dataclass(frozen=True)
class Mesh:
    """An unstructured quadrilateral (2D) or hexahedral (3D) mesh with named boundary sets; the vertical axis is
    the last (y in 2D, z in 3D).

    ``nodes`` (n_nodes, d) reference coordinates (L0); ``cells`` (n_cells,
    n_per_cell) node ids in :mod:`capslide.fem.element` order; ``base`` node ids
    of the clamped base; ``surface_segments`` the top surface's facets: in 2D (n_segments, order + 1) node ids of
    the edges in line order, left to right, sorted by reference x; in 3D (n_faces, 4 or 9) node ids of the
    quadrilateral faces (Q1 or Q2 order), counter-clockwise seen from outside; ``symmetry`` node ids on the plane
    of symmetry y = 0 of a 3D half model (none in 2D).
    """

    element: str
    nodes: np.ndarray
    cells: np.ndarray
    base: np.ndarray
    surface_segments: np.ndarray
    info: dict = field(default_factory=dict, compare=False)
    symmetry: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=np.int64))

    @property
    def n_nodes(self) -> int:
        return len(self.nodes)

    @property
    def n_cells(self) -> int:
        return len(self.cells)

    @property
    def dim(self) -> int:
        return self.nodes.shape[1]

    @property
    def n_dofs(self) -> int:
        return self.dim * len(self.nodes)

    @property
    def surface_quads(self) -> np.ndarray:
        """3D: the top's faces as bilinear quadrilaterals (n, 4), counter-clockwise from above: the faces themselves
        (H1), or each 9-node face as its four quarters (H2), face k's quarters at rows 4k to 4k + 3."""
        seg = self.surface_segments
        if seg.shape[1] == 4:
            return seg
        quarters = [[0, 4, 8, 7], [4, 1, 5, 8], [8, 5, 2, 6], [7, 8, 6, 3]]  # Q2 order: corners, mid-edges, centre
        return seg[:, quarters].reshape(-1, 4)

    @property
    def surface_nodes(self) -> np.ndarray:
        """Top-surface node ids ordered by reference x."""
        seg = self.surface_segments
        return np.concatenate([seg[:, :-1].ravel(), seg[-1:, -1]])

    def jacobians(self, points=None) -> np.ndarray:
        """det(dX/dxi) at the Gauss points (or given local points): (n_cells, n_points)."""
        ref = CELLS[self.element]
        if points is None:
            points, _ = ref.gauss()
        _, dN = ref.shape(points)
        X = self.nodes[self.cells]  # (e, a, d)
        return material.det(np.einsum("eai,pak->epik", X, dN))  # (e, p)

    def area(self) -> float:
        """The reference area (2D) or volume (3D) of the mesh (L0^2 or L0^3)."""
        ref = CELLS[self.element]
        pts, w = ref.gauss(ref.order + 2)
        return float(np.sum(self.jacobians(pts) * w))


def circular_segment_area(R: float, H: float) -> float:
    """Area of a circular segment of radius R and height H."""
    return R**2 * math.acos((R - H) / R) - (R - H) * math.sqrt(2 * R * H - H**2)


@dataclass(frozen=True)
class CapMeshSpec:
    """Geometric and grading inputs of :func:`cap_mesh` (lengths in L0)."""

    R: float
    H: float
    h0: float  # element size on the top surface inside the band
    band_half_width: float
    element: str = "Q1"
    layers_per_level: int = 4  # plain layers before each 3:1 transition
    side_growth: float = 1.15  # column width ratio outside the band
    max_size_over_H: float = 0.25  # largest element size / H


def _arc(R: float, H: float, phi) -> np.ndarray:
    phi = np.asarray(phi, dtype=float)
    return np.stack([R * np.sin(phi), R * np.cos(phi) - (R - H)], axis=-1)


def _right_half_columns(U: float, h0: float, band: float, growth: float, max_size: float) -> list[float]:
    """Column widths from the centre to u = U: uniform h0 in the band, then growing."""
    n_band = max(1, int(round(band / h0)))
    widths = [h0] * n_band
    u, w = n_band * h0, h0
    while u < U - 1e-12:
        w = min(w * growth, max_size)
        widths.append(min(w, U - u))
        u += widths[-1]
    if len(widths) > n_band + 1 and widths[-1] < 0.5 * widths[-2]:  # no sliver at the edge
        widths[-2] += widths.pop()
    return widths


def _merge_groups(widths: list[float], size: float) -> list[int]:
    """Group sizes (3 = merge, 1 = keep) for the right half, from the centre out."""
    groups, i = [], 0
    while i < len(widths):
        if i + 3 <= len(widths) and sum(widths[i : i + 3]) <= 3.5 * size:
            groups.append(3)
            i += 3
        else:
            groups.append(1)
            i += 1
    return groups


@dataclass(frozen=True)
class _Layer:
    """One layer of the logical mesh from height v down to v_next: plain (``groups`` None, the columns of ``widths``)
    or a 3:1 transition (``groups`` per right-half column group of the top row, 3 = merged, 1 = kept)."""

    widths: list[float]  # right-half column widths of the layer's top row
    v: float
    v_next: float
    groups: list[int] | None = None


def _layers(spec: CapMeshSpec, U: float):
    """The layers of the logical Q1 mesh, top down (the grading of the module docstring)."""
    max_size = spec.max_size_over_H * spec.H
    widths = _right_half_columns(U, spec.h0, spec.band_half_width, spec.side_growth, max_size)
    v = spec.H
    size, plain_left = spec.h0, spec.layers_per_level
    while v > 1e-12:
        transition = False
        if plain_left <= 0:
            transition = any(w < 1.5 * size for w in widths) and 3 * size <= max_size
            if not transition:  # columns already coarse: let the layers grow
                size = min(size * 1.5, max_size)
        d = 2 * size if transition else size
        if v - d < 0.75 * size:  # last layer: close at the base, never a sliver
            d, transition = v, False
        v_next = max(v - d, 0.0)
        if not transition:
            yield _Layer(widths, v, v_next)
            plain_left -= 1
        else:
            groups = _merge_groups(widths, size)
            yield _Layer(widths, v, v_next, groups)
            widths = _merged(widths, groups)
            size *= 3.0
            plain_left = spec.layers_per_level
        v = v_next


def _merged(widths: list[float], groups: list[int]) -> list[float]:
    out, i = [], 0
    for g in groups:
        out.append(sum(widths[i : i + g]))
        i += g
    return out


def cell_and_node_counts(spec: CapMeshSpec) -> tuple[int, int]:
    """Cells and nodes of :func:`cap_mesh` for ``spec``, counted from the layer plan without building the mesh."""
    phi0, phi1 = arc_angles(spec)
    cells = 0
    nodes = 2 * len(_right_half_columns(spec.R * phi1, spec.h0, spec.band_half_width, spec.side_growth,
                                        spec.max_size_over_H * spec.H)) + 1  # the top row
    for layer in _layers(spec, spec.R * phi1):
        if layer.groups is None:
            cells += 2 * len(layer.widths)
            nodes += 2 * len(layer.widths) + 1
        else:
            merged = sum(g == 3 for g in layer.groups)
            cells += 2 * (len(layer.groups) + 3 * merged)
            nodes += 2 * len(layer.groups) + 1 + 4 * merged
    if spec.element == "Q2":  # plus one node per edge (E = V + F - 1 for a mesh of a disc) and per cell
        nodes += (nodes + cells - 1) + cells
    return cells, nodes


def _logical_q1(spec: CapMeshSpec, U: float):
    """Q1 topology in logical coordinates: (nodes (n, 2), cells (m, 4), rows of node ids)."""
    nodes: list[tuple[float, float]] = []

    def add_row(us, v):
        start = len(nodes)
        nodes.extend((u, v) for u in us)
        return list(range(start, len(nodes)))

    def bounds_of(widths_r):
        b = np.concatenate([[0.0], np.cumsum(widths_r)])
        b[-1] = U
        return np.concatenate([-b[::-1], b[1:]])

    cells: list[list[int]] = []
    top, rows = None, []
    for layer in _layers(spec, U):
        if top is None:
            top = add_row(bounds_of(layer.widths), layer.v)
            rows.append(top)
        if layer.groups is None:
            bottom = add_row(bounds_of(layer.widths), layer.v_next)
            for j in range(len(top) - 1):
                cells.append([bottom[j], bottom[j + 1], top[j + 1], top[j]])
        else:
            groups = layer.groups[::-1] + layer.groups  # mirror: the centre is a node
            bounds_top = bounds_of(layer.widths)
            bottom = add_row(bounds_of(_merged(layer.widths, layer.groups)), layer.v_next)
            v_mid = 0.5 * (layer.v + layer.v_next)
            j = 0  # column index in the top row
            for k, g in enumerate(groups):
                b0, b1 = bottom[k], bottom[k + 1]
                if g == 1:
                    cells.append([b0, b1, top[j + 1], top[j]])
                else:
                    m1, m2 = add_row(bounds_top[j + 1 : j + 3], v_mid)
                    t0, t1, t2, t3 = top[j : j + 4]
                    cells += [[b0, m1, t1, t0], [m1, m2, t2, t1], [m2, b1, t3, t2], [b0, b1, m2, m1]]
                j += g
        top = bottom
        rows.append(top)
    return np.array(nodes), np.array(cells, dtype=np.int64), rows


def coons_map(uv: np.ndarray, spec: CapMeshSpec, U: float, phi0: float, phi1: float) -> np.ndarray:
    """Map logical (u, v) to the circular segment (transfinite interpolation)."""
    R, H = spec.R, spec.H
    b = R * math.sin(phi0)
    xi = (uv[:, 0] + U) / (2 * U)
    eta = uv[:, 1] / H
    bottom = np.stack([-b + 2 * b * xi, np.zeros_like(xi)], axis=-1)
    top = _arc(R, H, -phi1 + 2 * phi1 * xi)
    left = _arc(R, H, -phi0 + (phi0 - phi1) * eta)
    right = _arc(R, H, phi0 - (phi0 - phi1) * eta)
    P00, P10 = _arc(R, H, -phi0), _arc(R, H, phi0)
    P01, P11 = _arc(R, H, -phi1), _arc(R, H, phi1)
    x, e = xi[:, None], eta[:, None]
    X = (1 - e) * bottom + e * top + (1 - x) * left + x * right
    X -= (1 - x) * (1 - e) * P00 + x * (1 - e) * P10 + (1 - x) * e * P01 + x * e * P11
    # exact corners and base
    X[eta == 0.0, 1] = 0.0
    return X


def _to_q2(nodes: np.ndarray, cells: np.ndarray):
    """Add mid-edge and centre nodes (logical coordinates); return nodes, cells, edge-midpoint map."""
    edges = np.concatenate([cells[:, [0, 1]], cells[:, [1, 2]], cells[:, [2, 3]], cells[:, [3, 0]]])
    key = np.sort(edges, axis=1)
    uniq, inverse = np.unique(key, axis=0, return_inverse=True)
    inverse = inverse.ravel()
    n0 = len(nodes)
    mids = 0.5 * (nodes[uniq[:, 0]] + nodes[uniq[:, 1]])
    centres = nodes[cells].mean(axis=1)
    m = len(cells)
    mid_ids = (n0 + inverse).reshape(4, m).T  # (m, 4): bottom, right, top, left edges
    centre_ids = n0 + len(uniq) + np.arange(m)
    cells9 = np.column_stack([cells, mid_ids, centre_ids])
    edge_mid = {tuple(e): n0 + i for i, e in enumerate(uniq)}
    return np.vstack([nodes, mids, centres]), cells9, edge_mid


class BandTooWide(ValueError):
    """The refined contact band does not fit on the cap's top (the message gives the largest band that does)."""


def band_limit(spec: CapMeshSpec) -> float:
    """The largest contact-band half-width (L0) that fits on the cap top of ``spec``."""
    return 0.85 * math.acos((spec.R - spec.H) / spec.R) * spec.R - 4 * spec.h0


def arc_angles(spec: CapMeshSpec) -> tuple[float, float]:
    """Half-angle of the cap's arc and of the logical top edge (the band plus a margin of four elements)."""
    R, H = spec.R, spec.H
    if not 0 < H <= R:
        raise ValueError(f"cap height H = {H} must be in (0, R = {R}]")
    phi0 = math.acos((R - H) / R)  # half-angle of the arc
    phi1 = max(0.5 * phi0, (spec.band_half_width + 4 * spec.h0) / R)
    if phi1 > 0.85 * phi0:
        raise BandTooWide(f"contact band half-width {spec.band_half_width:g} L0 does not fit on the cap top "
                          f"(at most {band_limit(spec):.3g} L0)")
    return phi0, phi1


def cap_mesh(spec: CapMeshSpec) -> Mesh:
    """Graded Q1 or Q2 mesh of the cap (see the module docstring)."""
    R = spec.R
    phi0, phi1 = arc_angles(spec)
    U = R * phi1
    uv, cells, rows = _logical_q1(spec, U)
    left_edge = [row[0] for row in rows[::-1]]  # from the base corner up to P_L
    right_edge = [row[-1] for row in rows]  # from P_R down to the base corner
    surface = left_edge[:-1] + rows[0] + right_edge[1:]
    seg = np.column_stack([surface[:-1], surface[1:]])
    if spec.element == "Q2":
        uv, cells, edge_mid = _to_q2(uv, cells)
        mids = [edge_mid[tuple(sorted(map(int, s)))] for s in seg]
        seg = np.column_stack([seg[:, 0], mids, seg[:, 1]])
    elif spec.element != "Q1":
        raise ValueError(f"element must be Q1 or Q2, not {spec.element!r}")
    X = coons_map(uv, spec, U, phi0, phi1)
    base = np.flatnonzero(uv[:, 1] == 0.0)
    info = {"h0": spec.h0, "band_half_width": spec.band_half_width, "U": U, "phi0": phi0, "phi1": phi1}
    return Mesh(spec.element, X, cells, base, seg, info)


def rectangle_mesh(nx: int, ny: int, width: float = 1.0, height: float = 1.0, element: str = "Q1",
                   distortion: float = 0.0, seed: int = 0) -> Mesh:
    """Structured mesh of [-width/2, width/2] x [0, height]; interior nodes moved randomly.

    ``distortion`` moves every interior corner node by up to that fraction of
    the element size (Q2 mid nodes follow as edge midpoints, so edges stay
    straight). Base = the nodes on y = 0; surface segments = the top edge.
    """
    xs = np.linspace(-width / 2, width / 2, nx + 1)
    ys = np.linspace(0.0, height, ny + 1)
    X, Y = np.meshgrid(xs, ys, indexing="ij")
    uv = np.column_stack([X.ravel(), Y.ravel()])
    idx = np.arange((nx + 1) * (ny + 1)).reshape(nx + 1, ny + 1)
    if distortion:
        rng = np.random.default_rng(seed)
        interior = idx[1:-1, 1:-1].ravel()
        h = np.array([width / nx, height / ny])
        uv[interior] += distortion * h * rng.uniform(-1, 1, size=(len(interior), 2))
    cells = np.column_stack([idx[:-1, :-1].ravel(), idx[1:, :-1].ravel(), idx[1:, 1:].ravel(), idx[:-1, 1:].ravel()])
    top = idx[:, -1]
    seg = np.column_stack([top[:-1], top[1:]])
    if element == "Q2":
        uv, cells, edge_mid = _to_q2(uv, cells)
        seg = np.column_stack([seg[:, 0], [edge_mid[tuple(sorted(map(int, s)))] for s in seg], seg[:, 1]])
    elif element != "Q1":
        raise ValueError(f"element must be Q1 or Q2, not {element!r}")
    base = np.flatnonzero(np.isclose(uv[:, 1], 0.0))
    return Mesh(element, uv, cells, base, seg, {"nx": nx, "ny": ny})
