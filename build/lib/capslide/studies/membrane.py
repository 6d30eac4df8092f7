"""Cook's membrane: the classic locking benchmark for the bulk elements (Cook 1974).

A tapered panel with corners (0, 0), (48, 44), (48, 60), (0, 44), plane strain, clamped on the left edge and
loaded on the right edge by a uniform shear traction (total force ``load`` per unit width, upward, dead load in
the reference configuration). The reported quantity is the vertical displacement of the top right corner (48, 60).
Near incompressibility a locking element is far too stiff there. Units are those of the inputs (mu and the load
in one stress unit, lengths as above); the neo-Hooke law is capslide's (laws.material), whose linearization at
F = I is linear elasticity with the Lame constants (Lambda, mu).

Settings with published values (``benchmarks/cooks_membrane.py``, docs/options.md):

* compressible, linear (small load): plane strain, E = 70, nu = 1/3, load 100: 32.27 on very fine quadratic
  meshes (CoFEA benchmark 002);
* finite strain: mu = 80.1938, bulk modulus 400942 (nu = 0.4999) and load 100 (de Souza Neto et al. 1996):
  6.891 by OpenGeoSys's F-bar Q1 benchmark on 30 x 30 cells, still rising.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse.linalg as spla

from ..fem.assembly import BulkForm, Dirichlet
from ..fem.mesh import Mesh, rectangle_mesh
from ..fem.mixed import MixedBulkForm
from ..solvers.newton import NewtonOptions, newton

__all__ = ["cook_mesh", "MembraneResult", "tip_deflection"]


def cook_mesh(n: int, element: str = "Q2") -> Mesh:
    """n x n cells on the panel: the unit square's structured mesh mapped bilinearly onto it."""
    square = rectangle_mesh(n, n, 1.0, 1.0, element)
    s, t = square.nodes[:, 0] + 0.5, square.nodes[:, 1]
    X = np.column_stack([48.0 * s, 44.0 * s + t * (44.0 - 28.0 * s)])
    return Mesh(element, X, square.cells, np.flatnonzero(np.isclose(s, 0.0)), square.surface_segments, {"n": n})


def _edge_load(mesh: Mesh, load: float) -> np.ndarray:
    """Consistent nodal forces of a uniform vertical traction on the right edge (x = 48), total ``load``."""
    right = np.flatnonzero(np.isclose(mesh.nodes[:, 0], 48.0))
    right = right[np.argsort(mesh.nodes[right, 1])]
    y = mesh.nodes[right, 1]
    f = np.zeros(mesh.n_dofs)
    traction = load / (y[-1] - y[0])
    step = 2 if mesh.element == "Q2" else 1  # nodes per edge element, less one
    weights = np.array([1.0, 4.0, 1.0]) / 6.0 if step == 2 else np.array([0.5, 0.5])
    for k in range(0, len(right) - 1, step):
        nodes = right[k : k + step + 1]
        f[2 * nodes + 1] += traction * (y[k + step] - y[k]) * weights
    return f


@dataclass(frozen=True)
class MembraneResult:
    tip: float  # vertical displacement of the corner (48, 60)
    newton_iterations: int
    volume_error: float  # max |theta - 1| (mixed), or NaN


def tip_deflection(n: int, lam: float, mu: float, load: float, element: str = "Q2", formulation: str = "mixed",
                   steps: int = 1) -> MembraneResult:
    """The tip's vertical displacement on an n x n mesh, the load applied in ``steps`` equal increments (Newton
    at each, Uzawa's updates at lam = inf)."""
    mesh = cook_mesh(n, element)
    bulk = MixedBulkForm(mesh, lam, mu) if formulation == "mixed" else BulkForm(mesh, lam, mu)
    bc = Dirichlet.on_nodes(mesh.base, bulk.pattern)
    f_ext = _edge_load(mesh, load)
    u, its, multiplier = np.zeros(mesh.n_dofs), 0, None
    # residuals relative to the load (round-off leaves about Lambda 1e-16 times the cell size); increments below
    # 1e-9 of the panel's width; full Newton steps (near incompressibility the residual norm first grows)
    options = NewtonOptions(rtol=1e-6, atol=0.0, dx_tol=48e-9, max_iterations=50, line_search_steps=0)

    def equations(u, scale, multiplier):
        r = bulk.residual(u, multiplier) - scale * f_ext
        r[bc.dofs] = 0.0
        return r

    def linearize(u, scale, multiplier):
        f, data = bulk.residual_and_tangent_data(u, multiplier)
        r = f - scale * f_ext
        bc.apply(data, r)
        K = bulk.pattern.matrix(data).tocsc()
        return r, lambda rhs: spla.spsolve(K, rhs)

    for k in range(1, steps + 1):
        scale = k / steps
        for _ in range(50):
            res = newton(lambda z: equations(z, scale, multiplier), lambda z: linearize(z, scale, multiplier), u,
                         options, r_ref=abs(load), admissible=lambda z: bulk.min_jacobian(z) > 0.0)
            if not res.converged:
                raise RuntimeError(f"Cook's membrane n = {n}: load step {k} failed ({res.reason})")
            u, its = res.x, its + res.iterations
            updated = bulk.updated_multiplier(u, multiplier)
            if updated is None:
                break
            multiplier = updated
    tip = int(np.argmin(np.hypot(mesh.nodes[:, 0] - 48.0, mesh.nodes[:, 1] - 60.0)))
    volume = bulk.volume_error(u) if isinstance(bulk, MixedBulkForm) else float("nan")
    return MembraneResult(float(u[2 * tip + 1]), its, volume)
