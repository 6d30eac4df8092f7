"""The setup seam: parameters -> mesh spec -> mesh -> model with its linear solver (near-null space passed in)."""

from __future__ import annotations

from ..fem.assembly import rigid_body_modes
from ..fem.mesh import H0_AT_SIZE_1, CapMeshSpec, Mesh, cap_mesh
from ..fem.quality import poorly_shaped_dofs
from ..laws import analytic
from ..params import Parameters
from ..solvers.linsolve import choose_linear_solver, make_solver
from .cost import check_factorization
from .system import CapModel

__all__ = ["cap_mesh_spec", "build_model"]


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


def build_model(params: Parameters, mesh: Mesh | None = None, solver: str | None = None) -> CapModel:
    """The cap model of ``params`` on ``mesh`` (default: the graded cap mesh of :func:`cap_mesh_spec`), with the
    linear solver ``solver`` (default: ``solver.linear``; 'auto' resolved by :func:`choose_linear_solver`) given
    the rigid-body modes as near-null space and, for AMG, the DOFs of the poorly shaped cells to solve exactly
    around each multigrid cycle."""
    check_factorization(params)
    mesh = mesh or cap_mesh(cap_mesh_spec(params))
    mixed = params.mesh.formulation == "mixed"
    kind = choose_linear_solver(solver or params.solver.linear, mesh.n_dofs, mixed, params.solver.amg_above_dofs)
    exact = poorly_shaped_dofs(mesh.nodes, mesh.cells) if kind == "amg" else None
    linear = make_solver(kind, rtol=params.solver.krylov_rtol, near_null_space=rigid_body_modes(mesh.nodes),
                         diagonal_pivoting=mixed, exact_dofs=exact, factorization=params.solver.factorization)
    return CapModel(mesh, params, linear)
