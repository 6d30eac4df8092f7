"""Cell shape measures of quadrilateral meshes, from the four corner nodes of each cell (Q1 and Q2 alike).

The graded cap mesh has two kinds of poorly shaped cells, and they are where
smoothed-aggregation AMG converges slowly (docs/performance.md, issue 19):
- at the logical corners P_L and P_R, where the top and side edges of the
  Coons patch meet on the smooth arc, every thin surface layer ends in a cell
  with an interior angle near 180 degrees, and the columns that fan toward
  these points have angles above 160 degrees;
- outside the contact band, the thin surface layers meet wide columns: flat
  cells with aspect ratios up to hundreds at the finest meshes.
"""

from __future__ import annotations

import numpy as np

from .assembly import cell_dofs

__all__ = ["largest_interior_angle", "aspect_ratio", "poorly_shaped_cells", "dofs_of_cells",
           "poorly_shaped_dofs"]


def _corner_edges(nodes: np.ndarray, cells: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Edge vectors leaving each corner toward the next and the previous corner: two (n_cells, 4, 2) arrays."""
    X = nodes[cells[:, :4]]
    return np.roll(X, -1, axis=1) - X, np.roll(X, 1, axis=1) - X


def largest_interior_angle(nodes: np.ndarray, cells: np.ndarray) -> np.ndarray:
    """The largest of the four interior angles of each cell (degrees; 90 for a rectangle, 180 for a degenerate
    quadrilateral with three corners on a line)."""
    ahead, behind = _corner_edges(nodes, cells)
    cos = np.einsum("cki,cki->ck", ahead, behind) / (np.linalg.norm(ahead, axis=2) * np.linalg.norm(behind, axis=2))
    return np.degrees(np.arccos(np.clip(cos, -1.0, 1.0))).max(axis=1)


def aspect_ratio(nodes: np.ndarray, cells: np.ndarray) -> np.ndarray:
    """Longest over shortest edge of each cell (1 for a square)."""
    lengths = np.linalg.norm(_corner_edges(nodes, cells)[0], axis=2)
    return lengths.max(axis=1) / lengths.min(axis=1)


def poorly_shaped_cells(nodes: np.ndarray, cells: np.ndarray, max_angle: float = 160.0,
                        max_aspect: float = 8.0) -> np.ndarray:
    """Boolean mask of the cells with an interior angle above ``max_angle`` (degrees) or an aspect ratio above
    ``max_aspect``."""
    return (largest_interior_angle(nodes, cells) > max_angle) | (aspect_ratio(nodes, cells) > max_aspect)


def dofs_of_cells(cells: np.ndarray, mask: np.ndarray) -> np.ndarray:
    """Sorted displacement DOFs (node-major: 2 node, 2 node + 1) of all nodes of the cells in ``mask``."""
    return np.unique(cell_dofs(cells[mask]))


def poorly_shaped_dofs(nodes: np.ndarray, cells: np.ndarray) -> np.ndarray:
    """The DOFs of the poorly shaped cells at the default thresholds: what ``solver.linear: amg`` solves exactly
    around each multigrid cycle."""
    return dofs_of_cells(cells, poorly_shaped_cells(nodes, cells))
