"""How well a 3D mesh's surface quadrature integrates the normal law over an adhesive sphere's contact.

The gap profile is the same law's exact one (:mod:`capslide.studies.halfspace_sphere`: the scene's law on a
half-space with the sphere's profile, at a given contact radius), interpolated to the top surface's Gauss points
at their reference radii; the law's traction there, times the points' weights, is the load the FE would integrate
from that gap field. A law with kinks (the Dugdale verification law: its plateau ends at the contact edge, where a
stiff repulsion begins) is integrated only to the points' spacing, so the load moves as the edge passes rings of
points. The load at ``n`` points per face edge is compared with the load at the finest count on the same faces,
which leaves the faces' own area out.
"""

from __future__ import annotations

import numpy as np

from ..fem.mesh import Mesh
from ..fem.surface import SurfaceQuadrature
from ..laws.normal import normal_law
from ..params import Parameters
from .halfspace_sphere import cut_traction, halfspace_of, reference_radii

__all__ = ["quadrature_loads"]


def quadrature_loads(params: Parameters, mesh: Mesh, radii, points) -> dict[int, np.ndarray]:
    """{n: loads (E L0^2, compressive positive, the whole sphere's)} of the law's exact gap profile at each contact
    radius in ``radii`` (L0; the law's path is followed up to the largest), integrated on ``mesh``'s top faces at
    n x n points per face for each n in ``points``."""
    halfspace = halfspace_of(params)
    if halfspace is None:
        raise ValueError("the scene's cohesive zone is too narrow for the half-space reference's rings")
    law = cut_traction(normal_law(params.adhesion), params.contact.far_gap)
    radii = np.asarray(radii, dtype=float)
    path = {s.a: s.g for s in halfspace.edge_path(np.union1d(reference_radii(params, radii.max()), radii))}
    profiles = [path[a] for a in radii]
    loads = {}
    for n in points:
        quad = SurfaceQuadrature.on(mesh, n)
        r = np.hypot(quad.X[..., 0], quad.X[..., 1]).ravel()
        weight = quad.weight.ravel() * (2.0 if len(mesh.symmetry) else 1.0)
        loads[n] = np.array([law(np.interp(r, halfspace.r, g))[0] @ weight for g in profiles])
    return loads
