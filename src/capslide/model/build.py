"""The setup seam: parameters -> mesh spec -> mesh -> model with its linear solver (near-null space passed in)."""

from __future__ import annotations

import math

from ..config import SPHERE_ELEMENTS, ConfigError
from ..fem.assembly import rigid_body_modes
from ..fem.hex_mesh import SphereCapSpec, sphere_cap_mesh
from ..fem.mesh import H0_AT_SIZE_1, CapMeshSpec, Mesh, cap_mesh
from ..fem.quality import poorly_shaped_dofs
from ..laws import analytic, sphere
from ..params import Parameters
from ..solvers.linsolve import choose_linear_solver, make_solver
from .cost import check_factorization
from .system import CapModel

__all__ = ["cap_mesh_spec", "sphere_cap_spec", "mesh_spec", "mesh_from_spec", "mesh_of", "build_model"]


def cap_mesh_spec(params: Parameters) -> CapMeshSpec:
    """Mesh inputs of a configuration.

    The default band half-width covers every contact position up to ubar_max: the 2D JKR zero-load half-width of
    the cap (rigid flat, plane strain) plus |ubar_max|.
    """
    g, m = params.geometry, params.mesh
    band = m.band_half_width
    if band is None:
        E_star = analytic.effective_modulus(params.material.E, params.material.nu)
        band = analytic.jkr_cylinder_half_width(0.0, g.R, E_star, params.adhesion.W_adh) + abs(params.loading.ubar_max)
    return CapMeshSpec(R=g.R, H=g.H, h0=H0_AT_SIZE_1 * m.size, band_half_width=band, element=m.element,
                       max_size_over_H=m.max_size_over_H)


def sphere_cap_spec(params: Parameters) -> SphereCapSpec:
    """Mesh inputs of a 3D configuration (mesh.element = H1 or H2). The default band radius covers the contact up to a
    compressive load of twice the JKR pull-off force's size: 1.3 times the JKR radius at that load (a sphere,
    rigid flat), at least 1.3 times the radius at the compressive load pi W R."""
    g, m, mat = params.geometry, params.mesh, params.material
    band = m.band_half_width
    if band is None:
        K = 4.0 / 3.0 * analytic.effective_modulus(mat.E, mat.nu)
        W, R = params.adhesion.W_adh, g.R
        scale = (math.pi * W * R**2 / K) ** (1.0 / 3.0)  # a = A scale (Johnson and Greenwood's A)
        P = max(1.0, -params.loading.preload / (math.pi * W * R))  # P = F / (pi W R), compressive
        band = 1.3 * scale * float(sphere.jkr_radius(P))
    h0 = H0_AT_SIZE_1 * m.size
    if m.line_band is not None and m.line_band[1] > band:
        raise ConfigError(f"mesh.line_band = {list(m.line_band)!r} is not allowed here: its outer radius passes the "
                          f"contact band's radius {band:.4g} L0 (mesh.band_half_width)")
    return SphereCapSpec(R=g.R, H=g.H, h0=h0, band_radius=band, max_size_over_H=m.max_size_over_H,
                         max_layer_aspect=m.max_layer_aspect, whole=not m.symmetry_plane, line_band=m.line_band,
                         line_size=None if m.line_band is None else h0 / m.line_refinement,
                         order=2 if m.element == "H2" else 1)


def mesh_spec(params: Parameters) -> CapMeshSpec | SphereCapSpec:
    """Mesh inputs of a configuration: the 2D cap (Q1, Q2) or the 3D sphere's half model (H1, H2)."""
    return sphere_cap_spec(params) if params.mesh.element in SPHERE_ELEMENTS else cap_mesh_spec(params)


def mesh_from_spec(spec: CapMeshSpec | SphereCapSpec) -> Mesh:
    return sphere_cap_mesh(spec) if isinstance(spec, SphereCapSpec) else cap_mesh(spec)


def mesh_of(params: Parameters) -> Mesh:
    """The graded mesh of a configuration (:func:`mesh_spec`)."""
    return mesh_from_spec(mesh_spec(params))


def build_model(params: Parameters, mesh: Mesh | None = None, solver: str | None = None) -> CapModel:
    """The cap model of ``params`` on ``mesh`` (default: the graded cap mesh of :func:`cap_mesh_spec`), with the
    linear solver ``solver`` (default: ``solver.linear``; 'auto' resolved by :func:`choose_linear_solver`) given
    the rigid-body modes as near-null space and, for AMG, the DOFs of the poorly shaped cells to solve exactly
    around each multigrid cycle."""
    check_factorization(params)
    mesh = mesh or mesh_of(params)
    mixed = params.mesh.formulation == "mixed"
    kind = choose_linear_solver(solver or params.solver.linear, mesh.n_dofs, mixed, params.solver.amg_above_dofs,
                                mesh.dim)
    exact = poorly_shaped_dofs(mesh.nodes, mesh.cells) if kind == "amg" and mesh.dim == 2 else None
    linear = make_solver(kind, rtol=params.solver.krylov_rtol, near_null_space=rigid_body_modes(mesh.nodes),
                         diagonal_pivoting=mixed, exact_dofs=exact, factorization=params.solver.factorization,
                         single=params.solver.factor_precision == "single")
    return CapModel(mesh, params, linear)
