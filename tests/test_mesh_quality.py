"""Cell shape measures: exact values on rectangles and a degenerate quadrilateral; the cap mesh's poor cells."""

import numpy as np
import pytest

from capslide.fem.mesh import CapMeshSpec, cap_mesh, rectangle_mesh
from capslide.fem.quality import aspect_ratio, dofs_of_cells, largest_interior_angle, poorly_shaped_cells


@pytest.mark.parametrize("element", ["Q1", "Q2"])
def test_rectangle_cells_have_right_angles_and_their_side_ratio(element):
    mesh = rectangle_mesh(4, 2, width=8.0, height=0.5, element=element)  # cells 2 x 0.25
    np.testing.assert_allclose(largest_interior_angle(mesh.nodes, mesh.cells), 90.0, atol=1e-12)
    np.testing.assert_allclose(aspect_ratio(mesh.nodes, mesh.cells), 8.0, rtol=1e-14)
    assert poorly_shaped_cells(mesh.nodes, mesh.cells, max_aspect=7.9).all()
    assert not poorly_shaped_cells(mesh.nodes, mesh.cells, max_aspect=8.1).any()


def test_angles_of_a_rhombus_and_of_a_degenerate_quadrilateral():
    nodes = np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0], [1.0, 1.0],  # three corners on a line: 180 degrees
                      [0.0, 0.0], [1.0, -0.5], [2.0, 0.0], [1.0, 0.5]])  # a rhombus: 2 atan(2) = 126.87 degrees
    cells = np.array([[0, 1, 2, 3], [4, 5, 6, 7]])
    np.testing.assert_allclose(largest_interior_angle(nodes, cells), [180.0, np.degrees(2 * np.arctan(2.0))])
    np.testing.assert_allclose(aspect_ratio(nodes, cells), [np.sqrt(2.0), 1.0])


def test_dofs_of_cells_are_both_components_of_every_node_of_the_cells():
    cells = np.array([[0, 1, 4, 3], [1, 2, 5, 4]])
    np.testing.assert_array_equal(dofs_of_cells(cells, np.array([False, True])), [2, 3, 4, 5, 8, 9, 10, 11])


def test_cap_mesh_poor_cells_are_at_the_logical_corners_and_outside_the_band():
    """The near-180-degree cells sit next to where the top and side edges of the Coons patch meet on the arc (x =
    +-15.1 L0 here), in the columns that fan toward that point; the poor cells are few, and none lies in the inner
    three quarters of the contact band (transition cells next to its edges do, angles up to 162 degrees)."""
    band = 8.0
    mesh = cap_mesh(CapMeshSpec(R=47.1, H=10.0, h0=0.05, band_half_width=band))
    centres = mesh.nodes[mesh.cells[:, :4]].mean(axis=1)
    angle = largest_interior_angle(mesh.nodes, mesh.cells)
    corner = angle > 170.0  # the worst of them
    assert corner.sum() >= 2
    x = np.abs(centres[corner, 0])
    assert (x > 12.5).all() and (x < 18.0).all()  # P_L and P_R are at |x| = 15.1 L0, the band ends at 8
    depth = 47.1 - np.linalg.norm(centres[corner] - [0.0, 10.0 - 47.1], axis=1)
    assert depth.max() < 0.5  # in the thin layers under the arc
    poor = poorly_shaped_cells(mesh.nodes, mesh.cells)
    assert poor.sum() < 0.1 * mesh.n_cells
    assert (np.abs(centres[poor, 0]) > 0.75 * band).all()


def test_build_model_gives_amg_the_poor_cells_above_the_dof_limit(paper_config):
    """solver.linear auto: SuperLU reuse on the paper's cap; AMG with the exact block once the mesh has more DOF
    than solver.amg_above_dofs."""
    from capslide.config import apply_overrides, validate
    from capslide.model.build import build_model
    from capslide.params import Parameters
    from capslide.solvers.amg import AMGSolver
    from capslide.solvers.linsolve import LUKrylovSolver

    def solver(*overrides):
        return build_model(Parameters.from_config(validate(apply_overrides(paper_config, list(overrides))))).solver

    assert paper_config["solver"]["linear"] == "auto"
    assert isinstance(solver(), LUKrylovSolver)
    amg = solver("solver.amg_above_dofs=1000")
    assert isinstance(amg, AMGSolver) and amg.exact_dofs is not None and len(amg.exact_dofs) > 0
