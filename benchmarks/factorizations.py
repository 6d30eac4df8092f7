"""Benchmark: sparse LU factorizations of the cap tangent, SuperLU against MKL PARDISO (issue 19, item 4).

The sparsity pattern of the tangent is fixed, so a factorization that keeps its symbolic analysis (ordering and
fill) and only redoes the numeric factorization is the candidate. SciPy's SuperLU always starts over; MKL PARDISO
(through ``pypardiso``, not a dependency: ``pip install pypardiso`` to measure it) separates analysis (phase 11),
numeric factorization (22) and solve (33). Prints a Markdown table, median of repeats, one thread: fill of L + U,
SuperLU factor and solve, PARDISO analysis, numeric refactorization and solve (no iterative refinement: as a GMRES
preconditioner the solve need not be exact), and the relative residual of each solve.

    OMP_NUM_THREADS=1 MKL_NUM_THREADS=1 .venv/bin/python benchmarks/factorizations.py [--sizes 8 4 2 1] [--npz A.npz]

Matrices: the bulk tangent of the Q1 cap meshes of ``bulk_solvers.py`` at a deformed state (Dirichlet rows at the
base), one per ``--sizes`` value, and any CSR matrices saved with ``scipy.sparse.save_npz`` (``--npz``), for
example a tangent with its contact terms.
"""

from __future__ import annotations

import argparse
import sys
import warnings
from pathlib import Path

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bulk_solvers import matrix, median_time, system  # noqa: E402


def pardiso_solver():
    """A PARDISO handle for real unsymmetric matrices with explicit settings (nested dissection, pivot perturbation
    1e-13, scaling and matching: MKL's defaults for this type), no iterative refinement, the fill reported; None
    without pypardiso."""
    try:
        from pypardiso.pardiso_wrapper import PyPardisoSolver
    except ImportError:
        return None
    solver = PyPardisoSolver(mtype=11)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for i, value in ((1, 1), (2, 2), (8, 0), (10, 13), (11, 1), (13, 1), (18, -1)):  # 1-based iparm
            solver.set_iparm(i, value)
    return solver


def rel_residual(A, x, b) -> float:
    return float(np.linalg.norm(A @ x - b) / np.linalg.norm(b))


def measure(name: str, A: sp.csr_matrix, repeats: int) -> str:
    A = A.tocsr()
    A.sort_indices()
    b = np.random.default_rng(0).standard_normal(A.shape[0])
    t_lu, lu = median_time(lambda: spla.splu(A.tocsc(), permc_spec="MMD_AT_PLUS_A"), repeats)
    t_lu_solve, x = median_time(lambda: lu.solve(b), repeats)
    row = (f"| {name} | {A.shape[0]:,} | {lu.L.nnz + lu.U.nnz:,} | {t_lu:.3f} | {1e3 * t_lu_solve:.1f} "
           f"| {rel_residual(A, x, b):.0e} |")
    pardiso = pardiso_solver()
    if pardiso is None:
        return row + " pypardiso not installed | | | | |"
    pardiso._check_A(A)
    B = np.asfortranarray(b[:, None])

    def phase(p):
        pardiso.set_phase(p)
        return pardiso._call_pardiso(A, B)
    t_analysis, _ = median_time(lambda: phase(11), 1)
    t_numeric, _ = median_time(lambda: phase(22), repeats)
    t_solve, x = median_time(lambda: phase(33), repeats)
    fill = int(pardiso.get_iparm(18))
    return row + (f" {fill:,} | {t_analysis:.3f} | {t_numeric:.3f} | {1e3 * t_solve:.1f} "
                  f"| {rel_residual(A, x.ravel(), b):.0e} |")


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--sizes", type=float, nargs="*", default=[8, 4, 2, 1], help="mesh.size values of the cap mesh")
    p.add_argument("--npz", type=Path, nargs="*", default=[], help="CSR matrices saved with scipy.sparse.save_npz")
    p.add_argument("--repeats", type=int, default=3)
    a = p.parse_args()
    print("| matrix | DOF | SuperLU fill | SuperLU factor (s) | SuperLU solve (ms) | residual | PARDISO fill "
          "| PARDISO analysis (s) | PARDISO numeric (s) | PARDISO solve (ms) | residual |")
    print("|" + "---|" * 11)
    for size in a.sizes:
        mesh, form, bc, u1, _ = system(size)
        print(measure(f"Q1 cap bulk, mesh.size {size:g}", matrix(form, bc, u1), a.repeats), flush=True)
    for path in a.npz:
        print(measure(path.name, sp.load_npz(path), a.repeats), flush=True)


if __name__ == "__main__":
    main()
