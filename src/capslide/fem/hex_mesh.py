"""Hexahedral meshes: a box, and the graded half model of a spherical cap.

The spherical cap of radius R and height H stands on the base z = 0 (a disk of radius b = sqrt(H (2R - H))); its
apex is (0, 0, H). The half model keeps y >= 0: the plane y = 0 through the sliding direction x is a plane of
symmetry. The mesh is the 2D cap mesh's meridional Coons map (:mod:`capslide.fem.mesh`) turned about the z axis,
without its 3:1 transitions:

- a logical half disk of radius U (U = the arc length from the apex to the logical corner on the sphere): a core
  rectangle [-c, c] x [0, c] of square cells of size h0, and rings around it whose radii grow geometrically with
  4 n cells each (n = c / h0), so that the ring cells stay square; the rings blend from the rectangle to circles
  (an O-grid, no cell degenerates on the axis);
- inside the band, an optional annulus about the contact line (``line_band``, reference radii) takes rings
  ``line_size`` wide, their width growing by ``LINE_GRADING`` times the distance outside it (never wider than
  square): the cohesive zone at the contact's edge is narrow against the contact radius, and only its radial
  extent needs the fine size (the contact stays near-circular); the top layer there is as thin as the rings, the
  core shrinks to half the annulus's inner radius (rings are circles across the annulus) and its cells to what
  keeps the ring cells at most h0 wide along the annulus's outer circumference;
- outside the band the rings widen by ``ring_growth`` per ring (never narrower than square);
- layers from the top down: in the band the first is h0 thick, each ``layer_growth`` times the one above, at
  most ``max_size_over_H`` H (and ``max_layer_aspect`` h0 if given): this plan sets the number of layers; every column
  has that many, in a geometric series that closes on the base, its top layer h0 thick in the band and as thick
  as the rings are wide beyond it;
- a logical point P of the half disk at height v maps to (r P / |P|, z), where (r, z) is the 2D cap's Coons map at
  (|P|, v): the logical top (|P| <= U, v = H) is the sphere up to the polar angle phi1, the logical side (|P| = U) is
  the sphere from phi1 down to the base.

Cells inside the band (reference radius <= ``band_radius`` on the top) are h0 wide or less. The cell and node
counts follow from the plan alone (:func:`sphere_cap_counts`). With ``order`` 2 the same cells are triquadratic
(H2): the logical half disk gains its edges' midpoints and its quadrilaterals' centres, each column's depths are
its corners' mean, the layers gain their mid levels, and every node goes through the same map (so the top's nodes
lie on the sphere).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .mesh import BandTooWide, CapMeshSpec, Mesh, arc_angles, coons_map

LINE_GRADING = 0.3  # growth of the ring width per unit distance from the contact-line annulus (-)

__all__ = ["SphereCapSpec", "sphere_cap_mesh", "sphere_cap_counts", "box_mesh", "half_disk", "mirrored_disk",
           "spherical_cap_volume"]


@dataclass(frozen=True)
class SphereCapSpec:
    """Inputs of :func:`sphere_cap_mesh` (lengths in L0)."""

    R: float
    H: float
    h0: float  # cell size on the top surface inside the band
    band_radius: float  # radius of the refined contact band (reference, on the top surface)
    layer_growth: float = 1.25  # thickness ratio of a layer to the one above, in the band (it sets the layer count)
    ring_growth: float = 1.15  # width ratio of a ring to the one inside it, outside the band
    max_layer_aspect: float | None = None  # layers counted as if none under the band were thicker than this x h0
    max_size_over_H: float = 0.25  # largest layer thickness / H
    whole: bool = False  # the whole cap (no plane of symmetry) instead of the half y >= 0
    line_band: tuple[float, float] | None = None  # reference radii (inner, outer) of the annulus refined radially
    line_size: float | None = None  # ring width and top layer thickness in that annulus (L0)
    order: int = 1  # 1: trilinear hexahedra (H1); 2: triquadratic (H2, 27 nodes) on the same cells

    def line(self) -> tuple[float, float, float] | None:
        """The contact-line annulus as (inner, outer, size), or None."""
        return None if self.line_band is None else (*self.line_band, self.line_size)

    def finest_top(self) -> float:
        """The thinnest top layer: h0, or line_size in the contact-line annulus."""
        return self.h0 if self.line_size is None else min(self.h0, self.line_size)

    def meridian(self) -> CapMeshSpec:
        """The 2D cap whose meridional map this mesh turns about the axis."""
        return CapMeshSpec(R=self.R, H=self.H, h0=self.h0, band_half_width=self.band_radius, element="Q1",
                           max_size_over_H=self.max_size_over_H)


def spherical_cap_volume(R: float, H: float) -> float:
    """The volume of a spherical cap of radius R and height H (L0^3): pi H^2 (3 R - H) / 3."""
    return math.pi * H**2 * (3 * R - H) / 3


def _ring_plan(U: float, h0: float, band: float, growth: float, line=None) -> tuple[int, np.ndarray]:
    """n (core cells per half width) and the ring radii (the core's "radius" c first, U last): steps of gamma rho
    (square ring cells) inside the band, or narrower in the contact-line annulus ``line`` = (inner, outer, size),
    then steps growing by ``growth`` per ring, never below gamma rho.

    With an annulus the core shrinks to half its inner radius, so that the rings are circles across it, and n is
    large enough for ring cells at most h0 wide along the circumference at its outer radius."""
    if line is None:
        c = band / 1.5  # ring cells are h0 * pi / 4 wide at c and reach h0 at 4 c / pi: <= 1.2 h0 inside the band
        n = max(2, math.ceil(c / h0))
        c = n * h0
    else:
        c = min(band / 1.5, line[0] / 2.0)
        n = max(2, math.ceil(c / h0), math.ceil(math.pi * line[1] / (4.0 * h0)))
    if 1.5 * c >= U:
        raise BandTooWide(f"contact band radius {band:g} L0 leaves no room for the rings around it on the cap top "
                          f"(at most about {U:.3g} L0)")
    gamma = math.pi / (4 * n)  # a ring step of gamma rho keeps the ring cells square
    radii, step = [c], 0.0
    while radii[-1] < U:
        rho = radii[-1]
        if rho < band:
            step = gamma * rho if line is None else min(gamma * rho, float(_line_width(rho, *line)))
        else:
            step = max(gamma * rho, growth * step)
        radii.append(rho + step)
    if len(radii) > 2 and U - radii[-2] < 0.5 * step:  # no sliver: the last ring moves out to U
        radii.pop()
    radii[-1] = U
    return n, np.array(radii)


def _line_width(rho, inner: float, outer: float, size: float):
    """The ring width (L0) the contact-line annulus asks for at reference radius rho: ``size`` inside it, growing
    by LINE_GRADING times the distance outside it."""
    return size + LINE_GRADING * (np.maximum(inner - rho, 0.0) + np.maximum(rho - outer, 0.0))


def half_disk(U: float, h0: float, band: float, growth: float = 1.15, line=None) -> tuple[np.ndarray, np.ndarray]:
    """Quadrilateral mesh of the half disk {|P| <= U, P_y >= 0}: points (m, 2) and cells (k, 4), counter-clockwise
    (:func:`_ring_plan` for the rings; with a contact-line annulus they are circles from its inner radius on)."""
    n, radii = _ring_plan(U, h0, band, growth, line)
    c = radii[0]
    xs = np.linspace(-c, c, 2 * n + 1)
    ys = np.linspace(0.0, c, n + 1)
    X, Y = np.meshgrid(xs, ys, indexing="ij")
    points = [np.column_stack([X.ravel(), Y.ravel()])]
    core = np.arange((2 * n + 1) * (n + 1)).reshape(2 * n + 1, n + 1)
    cells = [np.column_stack([core[:-1, :-1].ravel(), core[1:, :-1].ravel(), core[1:, 1:].ravel(),
                              core[:-1, 1:].ravel()])]
    # the core's outer boundary, counter-clockwise from (c, 0) to (-c, 0): 4 n + 1 points
    chain = np.concatenate([core[-1, :], core[::-1, -1][1:], core[0, ::-1][1:]])
    square = points[0][chain] / c  # on the unit rectangle
    theta = np.linspace(0.0, math.pi, 4 * n + 1)
    circle = np.column_stack([np.cos(theta), np.sin(theta)])
    circle[[0, -1]] = [[1.0, 0.0], [-1.0, 0.0]]  # on y = 0 exactly: sin(pi) = 1.2e-16 put points off the plane
    previous, start = chain, len(points[0])
    blend = min(1.0, math.log(U / c)) if line is None else math.log(line[0] / c)
    for rho in radii[1:]:
        beta = min(1.0, math.log(rho / c) / blend)  # rectangle to circle over a factor e (or to U, or to the annulus)
        points.append(rho * ((1.0 - beta) * square + beta * circle))
        ring = start + np.arange(4 * n + 1)
        cells.append(np.column_stack([previous[1:], previous[:-1], ring[:-1], ring[1:]]))
        previous, start = ring, start + 4 * n + 1
    return np.vstack(points), np.vstack(cells)


def mirrored_disk(points: np.ndarray, cells: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The whole disk of a half disk (:func:`half_disk`): its mirror image in y = 0 added, sharing the points on
    y = 0, its cells counter-clockwise too."""
    upper = np.flatnonzero(points[:, 1] != 0.0)
    image = np.arange(len(points))
    image[upper] = len(points) + np.arange(len(upper))
    mirrored = image[cells][:, ::-1]  # a reflection reverses the order of the corners
    return np.vstack([points, points[upper] * [1.0, -1.0]]), np.vstack([cells, mirrored])


def _layer_count(H: float, h0: float, growth: float, max_size: float) -> int:
    """Layers of a column whose top layer is h0 thick, each layer ``growth`` times the one above, at most max_size."""
    layers, v, t = 0, H, h0
    while v > 1e-12:
        v -= t if v - t >= 0.75 * t else v  # the last layer closes on the base, never a sliver
        layers += 1
        t = min(t * growth, max_size)
    return layers


def _depths(top: np.ndarray, H: float, layers: int) -> np.ndarray:
    """Depths below the top of the layers' interfaces (layers + 1, m) for columns whose top layer is ``top`` (m,)
    thick: a geometric series per column that ends on the base (ratio q solving top = H (q - 1) / (q^K - 1))."""
    top = np.minimum(top, H / layers)
    lo, hi = np.full(top.shape, 1e-9), np.full(top.shape, 1.0 + 1e-9)
    while np.any(H * (hi - 1) / (hi**layers - 1) > top):  # bracket q: the top layer thins as q grows
        hi = np.where(H * (hi - 1) / (hi**layers - 1) > top, 2 * hi, hi)
    for _ in range(100):  # bisection, vectorized over the columns
        q = 0.5 * (lo + hi)
        thick = H * (q - 1) / np.where(np.abs(q - 1) < 1e-12, np.nan, q**layers - 1)
        thick = np.where(np.isnan(thick), H / layers, thick)
        lo, hi = np.where(thick > top, q, lo), np.where(thick > top, hi, q)
    q = 0.5 * (lo + hi)
    k = np.arange(layers + 1)[:, None]
    with np.errstate(invalid="ignore", divide="ignore"):
        d = H * (q**k - 1) / (q**layers - 1)
    d = np.where(np.abs(q - 1) < 1e-9, H * k / layers, d)
    d[-1] = H
    return d


def sphere_cap_counts(spec: SphereCapSpec) -> tuple[int, int]:
    """Cells and nodes of :func:`sphere_cap_mesh` for ``spec``, from the plan alone."""
    _, phi1 = arc_angles(spec.meridian())
    n, radii = _ring_plan(spec.R * phi1, spec.h0, spec.band_radius, spec.ring_growth, spec.line())
    quads = 2 * n * n + 4 * n * (len(radii) - 1)
    points = (2 * n + 1) * (n + 1) + (4 * n + 1) * (len(radii) - 1)
    if spec.whole:  # the mirror image of the half disk, sharing the points on y = 0
        quads, points = 2 * quads, 2 * points - (2 * n + 1) - 2 * (len(radii) - 1)
    layers = _layer_count(spec.H, spec.finest_top(), spec.layer_growth, _max_thickness(spec))
    if spec.order == 2:  # a disk's edges number points + quads - 1 (Euler); every level gains a mid level
        return quads * layers, (2 * points + 2 * quads - 1) * (2 * layers + 1)
    return quads * layers, points * (layers + 1)


def _quadratic_disk(disk: np.ndarray, quads: np.ndarray, U: float) -> tuple[np.ndarray, ...]:
    """The logical disk's points with its edges' midpoints and its quadrilaterals' centres appended (an edge on
    the rim |P| = U has its midpoint on the rim); each quad's edge ids (q, 4) in the order of its edges 0-1, 1-2,
    2-3, 3-0, and its centre ids (q,) (both numbered after the points); and the parents of every new point as a
    (new, 4) index array (an edge's two ends twice)."""
    pairs = np.sort(quads[:, [0, 1, 1, 2, 2, 3, 3, 0]].reshape(-1, 2), axis=1)
    ends, edge_of = np.unique(pairs, axis=0, return_inverse=True)
    m, e = len(disk), len(ends)
    parents = np.vstack([ends[:, [0, 1, 0, 1]], quads])
    new = disk[parents].mean(axis=1)
    rim = np.all(np.isclose(np.linalg.norm(disk[ends], axis=2), U, rtol=1e-12), axis=1)
    new[:e][rim] *= U / np.linalg.norm(new[:e][rim], axis=1, keepdims=True)
    return np.vstack([disk, new]), m + edge_of.reshape(-1, 4), m + e + np.arange(len(quads)), parents


def _triquadratic_cells(quads: np.ndarray, edges: np.ndarray, centres: np.ndarray, layers: int, m: int) -> np.ndarray:
    """The H2 cells (VTK order) of the layers between levels 2k (upper) and 2k + 2 (lower), with mid level 2k + 1,
    of m logical points per level."""
    cells = []
    for k in range(layers):
        lo, mid, up = (2 * k + 2) * m, (2 * k + 1) * m, 2 * k * m
        cells.append(np.hstack([quads + lo, quads + up, edges + lo, edges + up, quads + mid,
                                edges[:, [3, 1, 0, 2]] + mid, centres[:, None] + [lo, up, mid]]))
    return np.vstack(cells)


def _max_thickness(spec: SphereCapSpec) -> float:
    """The thickest layer of the plan that sets the number of layers: max_size_over_H H, or max_layer_aspect h0 if
    smaller (more layers, so flatter cells under the band's h0-wide columns; each column then spreads them in its
    geometric series, whose deepest layer may be thicker than the plan's)."""
    size = spec.max_size_over_H * spec.H
    return size if spec.max_layer_aspect is None else min(size, spec.max_layer_aspect * spec.h0)


def sphere_cap_mesh(spec: SphereCapSpec) -> Mesh:
    """The graded trilinear (H1) half model of the spherical cap (see the module docstring); with ``spec.whole``
    the whole cap, the half's mirror image added (a check of the plane of symmetry).

    ``base``: the nodes on z = 0; ``symmetry``: the nodes on y = 0 (none for the whole cap); ``surface_segments``:
    the logical top's faces (the contact facets), counter-clockwise seen from above.
    """
    meridian = spec.meridian()
    phi0, phi1 = arc_angles(meridian)
    U = spec.R * phi1
    disk, quads = half_disk(U, spec.h0, spec.band_radius, spec.ring_growth, spec.line())
    if spec.whole:
        disk, quads = mirrored_disk(disk, quads)
    layers = _layer_count(spec.H, spec.finest_top(), spec.layer_growth, _max_thickness(spec))
    s = np.linalg.norm(disk, axis=1)
    # the top layer: h0 in the band, beyond it as thick as the rings are wide there (near-cubic surface cells)
    _, radii = _ring_plan(U, spec.h0, spec.band_radius, spec.ring_growth, spec.line())
    widths = np.diff(radii)
    top = np.maximum(spec.h0, np.interp(s, radii[:-1], widths, left=spec.h0) * (s > spec.band_radius))
    if spec.line_band is not None:  # as thin as the rings about the contact line
        top = np.where(s <= spec.band_radius, np.minimum(top, _line_width(s, *spec.line())), top)
    depths = _depths(top, spec.H, layers)
    if spec.order == 2:
        disk, edges, centres, parents = _quadratic_disk(disk, quads, U)
        depths = np.hstack([depths, depths[:, parents].mean(axis=2)])  # (layers + 1, all points)
        depths = np.vstack([np.vstack([depths[:-1], 0.5 * (depths[:-1] + depths[1:])]).reshape(2, layers, -1)
                            .transpose(1, 0, 2).reshape(2 * layers, -1), depths[-1:]])
        s = np.linalg.norm(disk, axis=1)
    levels = len(depths)
    v = (spec.H - depths).ravel()  # level k of point i at k * m + i
    m = len(disk)
    rz = coons_map(np.column_stack([np.tile(s, levels), v]), meridian, U, phi0, phi1)
    scale = np.divide(rz[:, 0], np.tile(s, levels), out=np.zeros(len(rz)), where=np.tile(s, levels) > 0)
    nodes = np.column_stack([np.tile(disk, (levels, 1)) * scale[:, None], rz[:, 1]])
    if spec.order == 2:
        cells = _triquadratic_cells(quads, edges, centres, layers, m)
        quads = np.hstack([quads, edges, centres[:, None]])  # the top's faces: Q2 order
    else:  # layer k lies between level k (upper) and level k + 1 (lower): VTK order, the lower face first
        cells = np.vstack([np.hstack([quads + (k + 1) * m, quads + k * m]) for k in range(layers)])
    base = np.arange((levels - 1) * m, levels * m)
    symmetry = np.flatnonzero(np.tile(disk[:, 1], levels) == 0.0) if not spec.whole else np.zeros(0, dtype=np.int64)
    info = {"h0": spec.h0, "band_radius": spec.band_radius, "U": U, "phi0": phi0, "phi1": phi1, "layers": layers}
    if spec.line_band is not None:
        info |= {"line_band": spec.line_band, "line_size": spec.line_size}
    return Mesh("H2" if spec.order == 2 else "H1", nodes, cells, base, quads.copy(), info, symmetry=symmetry)


def box_mesh(nx: int, ny: int, nz: int, size=(1.0, 1.0, 1.0), distortion: float = 0.0, seed: int = 0) -> Mesh:
    """Structured H1 mesh of [0, Lx] x [0, Ly] x [0, Lz]; interior nodes moved randomly by up to ``distortion`` of
    the cell size. ``base``: z = 0; ``symmetry``: y = 0; ``surface_segments``: the faces on z = Lz."""
    axes = [np.linspace(0.0, L, k + 1) for L, k in zip(size, (nx, ny, nz))]
    grid = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1)
    nodes = grid.reshape(-1, 3)
    idx = np.arange(len(nodes)).reshape(nx + 1, ny + 1, nz + 1)
    if distortion:
        inner = idx[1:-1, 1:-1, 1:-1].ravel()
        h = np.array(size) / np.array([nx, ny, nz])
        nodes[inner] += distortion * h * np.random.default_rng(seed).uniform(-1, 1, size=(len(inner), 3))

    def corner(i, j, k):
        return idx[i: nx + i, j: ny + j, k: nz + k].ravel()

    cells = np.column_stack([corner(0, 0, 0), corner(1, 0, 0), corner(1, 1, 0), corner(0, 1, 0),
                             corner(0, 0, 1), corner(1, 0, 1), corner(1, 1, 1), corner(0, 1, 1)])
    top = idx[:, :, -1]
    faces = np.column_stack([top[:-1, :-1].ravel(), top[1:, :-1].ravel(), top[1:, 1:].ravel(), top[:-1, 1:].ravel()])
    return Mesh("H1", nodes, cells, idx[:, :, 0].ravel(), faces, {"n": (nx, ny, nz)},
                symmetry=idx[:, 0, :].ravel())
