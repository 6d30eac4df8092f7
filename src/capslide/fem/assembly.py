"""Bulk finite element assembly with a sparse pattern built once per mesh.

The dimension d is the mesh's (its element's): quadrilaterals in plane strain (d = 2) or hexahedra (d = 3), with
the same code. DOFs are node-major: dof d n + i is component i of node n. Reference geometry (shape-function
gradients and weights times Jacobians) is precomputed once; each Newton iteration only refills the CSR values
through a stored COO-to-CSR map. Total Lagrangian, internal units.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np
import scipy.sparse as sp

from ..laws import material
from .element import CELLS
from .mesh import Mesh

__all__ = ["cell_dofs", "node_dofs", "SparsePattern", "Dirichlet", "BulkForm", "rigid_body_modes"]


def cell_dofs(cells: np.ndarray, dim: int = 2) -> np.ndarray:
    """(n_cells, dim n_per_cell) DOF ids in node-major order (x, y (, z) of each node)."""
    return np.stack([dim * cells + i for i in range(dim)], axis=-1).reshape(len(cells), -1)


def node_dofs(nodes: np.ndarray, dim: int = 2) -> np.ndarray:
    """The DOF ids of the given nodes, every component, sorted."""
    return np.sort(np.concatenate([dim * nodes + i for i in range(dim)]))


@dataclass(frozen=True)
class SparsePattern:
    """CSR structure of an element-block matrix and the map that fills it.

    ``slot[k]`` is the CSR data position of the k-th entry of the flattened
    element blocks (n_blocks, m, m); duplicates add up.
    """

    n: int
    indptr: np.ndarray
    indices: np.ndarray
    slot: np.ndarray

    @classmethod
    def from_blocks(cls, dofs: np.ndarray, n: int) -> SparsePattern:
        m = dofs.shape[1]
        rows = np.repeat(dofs, m, axis=1).ravel()
        cols = np.tile(dofs, (1, m)).ravel()
        keys = rows.astype(np.int64) * n + cols
        uniq, slot = np.unique(keys, return_inverse=True)
        r = uniq // n
        indptr = np.zeros(n + 1, dtype=np.int64)
        np.cumsum(np.bincount(r, minlength=n), out=indptr[1:])
        return cls(n=n, indptr=indptr, indices=(uniq % n).astype(np.int32), slot=slot.ravel())

    @classmethod
    def from_cells(cls, cells: np.ndarray, dim: int, n_nodes: int) -> SparsePattern:
        """The pattern of :meth:`from_blocks` for the cells' node-major DOF blocks (``cell_dofs(cells, dim)``), the same
        arrays, built from the node pairs: dim^2 times fewer keys to sort (the peak memory of a 3D mesh's setup).

        A node row I with neighbours J_1 < ... < J_m gives each of its dim DOF rows the columns dim J_k + c (k, then
        c); the node pair of rank k in row I puts the DOF entry (I, i; J_k, c) at d^2 start(I) + i d m + k d + c."""
        d = dim
        e, a = cells.shape
        keys = (np.repeat(cells, a, axis=1).astype(np.int64) * n_nodes + np.tile(cells, (1, a))).ravel()
        pairs, pair_of = np.unique(keys, return_inverse=True)
        row, col = pairs // n_nodes, pairs % n_nodes  # node I, node J
        count = np.bincount(row, minlength=n_nodes)  # neighbours of each node
        start = np.zeros(n_nodes + 1, dtype=np.int64)
        np.cumsum(count, out=start[1:])
        rank = np.arange(len(pairs)) - start[row]  # of each pair within its node row
        row_len = np.repeat(d * count, d)  # DOF row d I + i has d m entries
        indptr = np.zeros(d * n_nodes + 1, dtype=np.int64)
        np.cumsum(row_len, out=indptr[1:])
        i, c = np.arange(d)[:, None], np.arange(d)[None, :]
        pos = (d * d * start[row])[:, None, None] + i * (d * count[row])[:, None, None] + (rank * d)[:, None, None] + c
        indices = np.empty(len(pairs) * d * d, dtype=np.int32)
        indices[pos.ravel()] = np.broadcast_to((d * col)[:, None, None] + c, pos.shape).ravel()
        # slot of the element entry (a1, i; a2, c): the position of (I, i; J, c) for the pair (cells[a1], cells[a2])
        p = pair_of.reshape(e, a, 1, a, 1)
        pair_row = row[p]
        slot = (d * d * start[pair_row] + i.reshape(1, 1, d, 1, 1) * d * count[pair_row] + rank[p] * d
                + c.reshape(1, 1, 1, 1, d))
        return cls(n=d * n_nodes, indptr=indptr, indices=indices, slot=slot.ravel())

    @property
    def nnz(self) -> int:
        return len(self.indices)

    def values(self, blocks: np.ndarray, slot: np.ndarray | None = None) -> np.ndarray:
        """CSR data from element blocks (n_blocks, m, m); with ``slot``, from blocks whose entries come in another
        order, ``slot`` mapping each to its CSR position (a permutation of :attr:`slot` within each block)."""
        return np.bincount(self.slot if slot is None else slot, weights=blocks.ravel(), minlength=self.nnz)

    def matrix(self, data: np.ndarray) -> sp.csr_matrix:
        return sp.csr_matrix((data, self.indices, self.indptr), shape=(self.n, self.n))

    def positions(self, rows: np.ndarray, cols: np.ndarray) -> np.ndarray:
        """CSR data positions of given (row, col) pairs (all must be in the pattern)."""
        # the pattern's keys row * n + col are sorted (rows in order, columns sorted within a row)
        keys = np.repeat(np.arange(self.n, dtype=np.int64), np.diff(self.indptr)) * self.n + self.indices
        return np.searchsorted(keys, np.asarray(rows, dtype=np.int64) * self.n + np.asarray(cols, dtype=np.int64))


@dataclass(frozen=True)
class Dirichlet:
    """Whole-node Dirichlet conditions applied to a fixed CSR pattern.

    Rows and columns of constrained DOFs are zeroed and their diagonal set
    to one; the residual there is zeroed, so the Newton increment of a
    constrained DOF is zero (prescribed values are set in u beforehand).
    """

    dofs: np.ndarray
    zero_mask: np.ndarray  # CSR data positions in a constrained row or column
    diag: np.ndarray  # CSR data positions of constrained diagonals

    @classmethod
    def on_nodes(cls, nodes: np.ndarray, pattern: SparsePattern, dim: int = 2) -> Dirichlet:
        """Every component of ``nodes`` fixed."""
        return cls.on_dofs(node_dofs(nodes, dim), pattern)

    @classmethod
    def on_dofs(cls, dofs: np.ndarray, pattern: SparsePattern) -> Dirichlet:
        """The given DOFs fixed (sorted, unique)."""
        fixed = np.zeros(pattern.n, dtype=bool)
        fixed[dofs] = True
        row_of = np.repeat(np.arange(pattern.n), np.diff(pattern.indptr))
        zero_mask = np.flatnonzero(fixed[row_of] | fixed[pattern.indices])
        return cls(dofs=dofs, zero_mask=zero_mask, diag=pattern.positions(dofs, dofs))

    def apply(self, data: np.ndarray, residual: np.ndarray | None = None) -> None:
        """In place: constrain CSR data (and the residual)."""
        data[self.zero_mask] = 0.0
        data[self.diag] = 1.0
        if residual is not None:
            residual[self.dofs] = 0.0


class BulkForm:
    """Internal forces and tangent of the neo-Hooke bulk on a mesh."""

    OUTER_BUDGET_BYTES = 1 << 30  # static dN dN w products kept up to 1 GiB

    def __init__(self, mesh: Mesh, lam: float, mu: float, quadrature: int | None = None):
        ref = CELLS[mesh.element]
        self.dim = d = ref.dim
        points, weights = ref.gauss(quadrature)
        _, dN_dxi = ref.shape(points)  # (q, a, d)
        X = mesh.nodes[mesh.cells]  # (e, a, d)
        Jac = np.einsum("eai,qak->eqik", X, dN_dxi)  # dX_i/dxi_k, (e, q, d, d)
        detJ = material.det(Jac)
        if np.any(detJ <= 0.0):
            raise ValueError("mesh has inverted or degenerate elements")
        inv = material.inv_transpose(Jac, detJ)  # (dX/dxi)^{-T}
        self.dN = np.einsum("qak,eqik->eqai", dN_dxi, inv)  # dN_a/dX_i, (e, q, a, d)
        self.wdetJ = detJ * weights  # (e, q)
        self.dNw = self.dN * self.wdetJ[..., None, None]
        # the same, one (a, q*d) matrix per cell: F and f_int as one small matmul per cell, not per point
        e, q, a, _ = self.dN.shape
        self._dN_cell = np.ascontiguousarray(self.dN.transpose(0, 2, 1, 3).reshape(e, a, q * d))
        self._dNw_cell = np.ascontiguousarray(self.dNw.transpose(0, 2, 1, 3).reshape(e, a, q * d))
        self._outer_cache = None
        self._F_cache: tuple[np.ndarray, np.ndarray] | None = None
        self.mesh, self.lam, self.mu = mesh, lam, mu
        self.dofs = cell_dofs(mesh.cells, d)
        self.n_dofs = mesh.n_dofs
        self.pattern = SparsePattern.from_cells(mesh.cells, d, mesh.n_nodes)

    def deformation_gradient(self, u: np.ndarray) -> np.ndarray:
        """F = I + grad u at every quadrature point, (e, q, d, d), read-only.

        The last result is kept: Newton's line search asks for det F (admissibility)
        and the residual at the same trial state, then the tangent at the accepted one.
        """
        cached = self._F_cache
        if cached is not None and np.array_equal(cached[0], u):
            return cached[1]
        d = self.dim
        ue = u.reshape(-1, d)[self.mesh.cells]  # (e, a, d)
        # F_ij = delta_ij + sum_a u_ai dN_aj: (e, d, a) @ (e, a, q*d), then (e, q, i, j)
        e, q = self.dN.shape[:2]
        grad_u = (np.swapaxes(ue, 1, 2) @ self._dN_cell).reshape(e, d, q, d).transpose(0, 2, 1, 3)
        F = np.add(grad_u, np.eye(d), out=np.empty((e, q, d, d)))
        F.flags.writeable = False
        self._F_cache = (np.array(u, copy=True), F)
        return F

    def _gather(self, fe: np.ndarray) -> np.ndarray:
        return np.bincount(self.dofs.ravel(), weights=fe.ravel(), minlength=self.n_dofs)

    def internal_force(self, P: np.ndarray) -> np.ndarray:
        # f_ai = sum_q sum_J dN_aJ w P_iJ: (e, a, q*d) @ (e, q*d, d) with P_iJ ordered (q, J), i
        e, q, d = P.shape[:3]
        return self._gather(self._dNw_cell @ np.swapaxes(P, -1, -2).reshape(e, q * d, d))

    def residual(self, u: np.ndarray, multiplier: np.ndarray | None = None) -> np.ndarray:
        """Internal force vector f_int (E L0), node-major (``multiplier``: unused here, see fem.mixed)."""
        return self.internal_force(material.first_piola(self.deformation_gradient(u), self.lam, self.mu))

    @property
    def _outer(self) -> np.ndarray | None:
        """Static products dN_aJ dN_bL w, (e, a*b, q*d*d), or None above the memory budget."""
        if self._outer_cache is None:
            e, q, a, d = self.dN.shape
            if e * a * a * q * d * d * 8 <= self.OUTER_BUDGET_BYTES:
                G = np.einsum("eqaJ,eqbL->eabqJL", self.dNw, self.dN)
                self._outer_cache = G.reshape(e, a * a, q * d * d)
            else:
                self._outer_cache = False
        return self._outer_cache if self._outer_cache is not False else None

    def _tangents_abik(self, A: np.ndarray) -> np.ndarray | None:
        """Element tangents with their entries in (a, b, i, k) order, (e, a*b, i*k): one batched matmul
        (e, ab, qJL) @ (e, qJL, ik) with the static products; None when those are above the memory budget."""
        outer = self._outer
        if outer is None:
            return None
        e, q, d = A.shape[:3]
        return outer @ A.transpose(0, 1, 3, 5, 2, 4).reshape(e, q * d * d, d * d)

    @cached_property
    def _slot_abik(self) -> np.ndarray:
        """The pattern's slot map for element tangents in (a, b, i, k) order."""
        e, a = self.mesh.cells.shape
        d = self.dim
        return self.pattern.slot.reshape(e, a, d, a, d).transpose(0, 1, 3, 2, 4).ravel()

    def tangent_data(self, A: np.ndarray) -> np.ndarray:
        """CSR data of the tangent for the fixed pattern from the material tangent A (e, q, d, d, d, d); the same
        numbers as ``pattern.values(element_tangents(A))`` (each CSR entry sums one term per element, in element order
        either way), without reordering the element blocks in memory."""
        K = self._tangents_abik(A)
        if K is None:
            return self.pattern.values(self.element_tangents(A))
        return self.pattern.values(K, self._slot_abik)

    def element_tangents(self, A: np.ndarray) -> np.ndarray:
        """K_e[(a,i), (b,k)] = sum_q dN_aJ A_iJkL dN_bL w, (e, d a, d a)."""
        e, q, a, d = self.dN.shape
        K = self._tangents_abik(A)
        if K is not None:
            K = K.reshape(e, a, a, d, d).transpose(0, 1, 3, 2, 4)
        else:  # two batched matmuls per quadrature point, summed as they come: no array of all points' products
            At = A.transpose(0, 1, 3, 2, 4, 5).reshape(e, q, d, d**3)  # J, (i, k, L)
            K = np.zeros((e, a * d * d, a))
            for k in range(q):
                S = (self.dNw[:, k] @ At[:, k]).reshape(e, a * d * d, d)  # (a, i, k), L
                K += S @ np.swapaxes(self.dN[:, k], -1, -2)
            K = K.reshape(e, a, d, d, a).transpose(0, 1, 2, 4, 3)
        return K.reshape(e, d * a, d * a)

    def residual_and_tangent_data(self, u: np.ndarray, multiplier: np.ndarray | None = None
                                  ) -> tuple[np.ndarray, np.ndarray]:
        """(f_int, CSR data of the tangent) for the fixed pattern."""
        P, A = material.first_piola_and_tangent(self.deformation_gradient(u), self.lam, self.mu)
        return self.internal_force(P), self.tangent_data(A)

    def residual_and_tangent(self, u: np.ndarray, multiplier: np.ndarray | None = None
                             ) -> tuple[np.ndarray, sp.csr_matrix]:
        f, data = self.residual_and_tangent_data(u, multiplier)
        return f, self.pattern.matrix(data)

    def strain_energy(self, u: np.ndarray, multiplier: np.ndarray | None = None) -> float:
        """Total strain energy (E L0^2 per unit width in plane strain, E L0^3 in 3D)."""
        W = material.strain_energy_density(self.deformation_gradient(u), self.lam, self.mu)
        return float(np.sum(W * self.wdetJ))

    def updated_multiplier(self, u: np.ndarray, multiplier: np.ndarray | None) -> np.ndarray | None:
        """Uzawa's next pressure multiplier while an incompressibility constraint is violated; None here (no
        constraint; see fem.mixed)."""
        return None

    def min_jacobian(self, u: np.ndarray) -> float:
        """Smallest det F over the quadrature points (<= 0 means an inverted element)."""
        return float(material.det(self.deformation_gradient(u)).min())

    def cell_first_invariant(self, u: np.ndarray, multiplier: np.ndarray | None = None) -> np.ndarray:
        """I1(sigma) averaged over each cell's quadrature points (E), (n_cells,)."""
        return self.cell_average(material.first_invariant(self.deformation_gradient(u), self.lam, self.mu))

    def cell_average(self, values: np.ndarray) -> np.ndarray:
        """The area- (volume-) weighted average over each cell of values at the quadrature points (e, q) -> (n_cells,)."""
        return np.sum(values * self.wdetJ, axis=1) / np.sum(self.wdetJ, axis=1)


def rigid_body_modes(nodes: np.ndarray) -> np.ndarray:
    """The rigid-body modes of nodes (n, d), node-major: in 2D (2n, 3) translation x, y and the rotation; in 3D
    (3n, 6) translations x, y, z and the rotations about x, y, z (about the nodes' centroid)."""
    n, d = nodes.shape
    if d == 3:
        c = nodes - nodes.mean(axis=0)
        B = np.zeros((n, 3, 6))
        B[:, [0, 1, 2], [0, 1, 2]] = 1.0
        for k, (i, j) in enumerate([(1, 2), (2, 0), (0, 1)]):  # rotation about axis k: (e_k x c)
            B[:, i, 3 + k] = -c[:, j]
            B[:, j, 3 + k] = c[:, i]
        return B.reshape(3 * n, 6)
    B = np.zeros((2 * n, 3))
    B[0::2, 0] = 1.0
    B[1::2, 1] = 1.0
    c = nodes - nodes.mean(axis=0)
    B[0::2, 2] = -c[:, 1]
    B[1::2, 2] = c[:, 0]
    return B

