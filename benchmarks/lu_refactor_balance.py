"""What a PARDISO refactorization costs in triangular solves with its factors, measured and as the LU-Krylov
solver's refactor rule estimates it from PARDISO's counted flops and fill
(:func:`capslide.solvers.linsolve.factorization_cost_in_solves`).

Matrices: the `experiment` scene's bulk tangent at rest (H1/P0, its boundary conditions), at the presets given,
and model grids of the same sizes (a 9-point 2D and a 27-point 3D stencil with dense 2x2 and 3x3 node blocks,
random entries, diagonally dominant). One thread (PARDISO runs on one anyway); refactorization and solve times are
the medians of --repeats and 5 x --repeats runs.

    OMP_NUM_THREADS=1 .venv/bin/python benchmarks/lu_refactor_balance.py
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np
import scipy.sparse as sp

from capslide.config import load_config, scene_path
from capslide.model.build import build_model
from capslide.params import Parameters
from capslide.solvers.linsolve import factorization_cost_in_solves
from capslide.solvers.pardiso import PardisoFactors


def scene_tangent(preset: str) -> sp.csr_matrix:
    """The experiment scene's bulk tangent at rest with its boundary conditions applied."""
    model = build_model(Parameters.from_config(load_config([scene_path("experiment")], [f"preset={preset}"])))
    _, data = model.bulk.residual_and_tangent_data(np.zeros(model.n_dofs), None)
    model.bc.apply(data, np.zeros(model.n_dofs))
    return model.bulk.pattern.matrix(data).tocsr()


def grid(n: int, dim: int, block: int) -> sp.csr_matrix:
    """A (3^dim)-point stencil on an n^dim grid with dense block x block node couplings."""
    line = sp.diags([1.0, 1.0, 1.0], [-1, 0, 1], shape=(n, n))
    stencil = line
    for _ in range(dim - 1):
        stencil = sp.kron(stencil, line)
    A = sp.kron(stencil, np.ones((block, block))).tocsr()
    A.data = np.random.default_rng(0).standard_normal(A.nnz)
    return (A + 30.0 * sp.eye(A.shape[0])).tocsr()


def measure(A: sp.csr_matrix, repeats: int, single: bool = False) -> dict:
    """Median refactorization and solve times of PARDISO's factors of A (in single precision with ``single``)."""
    A = A.tocsr()
    A.sort_indices()
    f = PardisoFactors(A, single=single)
    refactor, solve = [], []
    b = np.ones(A.shape[0])
    for _ in range(repeats):
        t = time.perf_counter()
        f.refactor(A)
        refactor.append(time.perf_counter() - t)
    for _ in range(5 * repeats):
        t = time.perf_counter()
        f.solve(b)
        solve.append(time.perf_counter() - t)
    tf, ts = statistics.median(refactor), statistics.median(solve)
    return {"dofs": A.shape[0], "fill": f.fill, "mflop": f.factorization_flops / 1e6, "refactor": tf, "solve": ts,
            "measured": tf / ts, "estimated": factorization_cost_in_solves(f), "factors": f}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--presets", nargs="*", default=["coarse", "annulus"])
    ap.add_argument("--repeats", type=int, default=3)
    args = ap.parse_args()
    cases = [(f"experiment, {p}", lambda p=p: scene_tangent(p)) for p in args.presets]
    cases += [("2D grid, 2x2 blocks", lambda: grid(99, 2, 2)), ("3D grid, 3x3 blocks", lambda: grid(19, 3, 3)),
              ("3D grid, 3x3 blocks", lambda: grid(28, 3, 3))]
    print("| matrix | DOF | fill of L + U | factorization (MFLOP) | refactorization (ms) | solve (ms) "
          "| refactorization / solve, measured | estimated | estimated / measured |")
    print("|---|---|---|---|---|---|---|---|---|")
    for name, make in cases:
        r = measure(make(), args.repeats)
        print(f"| {name} | {r['dofs']:,} | {r['fill']:,} | {r['mflop']:,.0f} | {1e3 * r['refactor']:.1f} "
              f"| {1e3 * r['solve']:.2f} | {r['measured']:.1f} | {r['estimated']:.1f} "
              f"| {r['estimated'] / r['measured']:.2f} |", flush=True)


if __name__ == "__main__":
    main()
