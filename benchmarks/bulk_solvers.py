"""Benchmark: bulk assembly and linear solvers on the graded cap meshes.

Prints a Markdown table over mesh sizes (median of repeats, seconds):
residual + tangent refill with the reused pattern; AMG (as ``solver.linear:
amg`` builds it: capslide's smoothed aggregation with the rigid-body modes and,
since issue 19, the exact solve on the poorly shaped cells) setup, fresh solve
and solve with the hierarchy reused for the tangent of a deformed state, with
iteration counts; the same with pyamg's default (constant) near-null space at
the smallest size; a stored LU factorization preconditioning GMRES; and
SuperLU factor + solve.

    OMP_NUM_THREADS=1 .venv/bin/python benchmarks/bulk_solvers.py [--sizes 8 4 2 1 0.5 0.25 0.15] [--repeats 3]
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np

from capslide.fem.assembly import BulkForm, Dirichlet, rigid_body_modes
from capslide.fem.mesh import H0_AT_SIZE_1, CapMeshSpec, cap_mesh
from capslide.fem.quality import poorly_shaped_dofs
from capslide.params import lame_plane_strain
from capslide.solvers.linsolve import AMGSolver, DirectSolver, LUKrylovSolver


def median_time(fn, repeats):
    times, out = [], None
    for _ in range(repeats):
        t = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t)
    return statistics.median(times), out


def system(size):
    mesh = cap_mesh(CapMeshSpec(R=47.1, H=10.0, h0=H0_AT_SIZE_1 * size, band_half_width=11.35))
    lam, mu = lame_plane_strain(1.0, 0.4)
    form = BulkForm(mesh, lam, mu)
    bc = Dirichlet.on_nodes(mesh.base, form.pattern)
    X = mesh.nodes
    # a smooth deformed state (compression under the apex plus shear), for a "later" tangent
    u1 = np.column_stack([0.02 * X[:, 1] / 10, -0.05 * (X[:, 1] / 10) ** 2 * np.exp(-(X[:, 0] / 10) ** 2)]).ravel()
    b = np.zeros(mesh.n_dofs)
    b[2 * mesh.surface_nodes + 1] = -1e-3
    b[bc.dofs] = 0.0
    return mesh, form, bc, u1, b


def matrix(form, bc, u):
    _, data = form.residual_and_tangent_data(u)
    bc.apply(data)
    return form.pattern.matrix(data)


def run(sizes, repeats, const_nullspace_sizes):
    rows = []
    for size in sizes:
        mesh, form, bc, u1, b = system(size)
        form.residual_and_tangent_data(u1)  # warm up (static products)
        t_asm, _ = median_time(lambda: form.residual_and_tangent_data(u1), repeats)
        t_res, _ = median_time(lambda: form.residual(u1), repeats)
        A0, A1 = matrix(form, bc, np.zeros(mesh.n_dofs)), matrix(form, bc, u1)
        B = rigid_body_modes(mesh.nodes)

        exact = poorly_shaped_dofs(mesh.nodes, mesh.cells)  # as build_model passes them
        amg = AMGSolver(near_null_space=B, exact_dofs=exact, symmetric=True, rtol=1e-8)
        t_setup, _ = median_time(lambda: amg.setup(A0), repeats)
        t_fresh, (x, info_fresh) = median_time(lambda: amg.solve(A0, b), repeats)
        t_reuse, (x, info_reuse) = median_time(lambda: amg.solve(A1, b), repeats)
        if size in const_nullspace_sizes:
            plain = AMGSolver(near_null_space=None, exact_dofs=exact, symmetric=True, rtol=1e-8)
            plain.setup(A0)
            t_plain, (_, info_plain) = median_time(lambda: plain.solve(A0, b), 1)
            plain_txt = f"{t_plain:.2f} ({info_plain.iterations})"
        else:
            plain_txt = "-"

        lu = LUKrylovSolver(rtol=1e-8)
        t_factor, _ = median_time(lambda: lu.factor(A0), repeats)
        t_lu_reuse, (_, info_lu) = median_time(lambda: lu.solve(A1, b), repeats)
        direct = DirectSolver()
        t_direct, (_, info_direct) = median_time(lambda: direct.solve(A1, b), repeats)
        rows.append((mesh.n_cells, mesh.n_dofs, t_asm, t_res, t_setup, t_fresh, info_fresh.iterations, t_reuse,
                     info_reuse.iterations, plain_txt, t_factor, t_lu_reuse, info_lu.iterations, t_direct,
                     info_direct.solve_time))
        print(f"size {size}: done ({mesh.n_dofs} DOF)", flush=True)
    header = ("| cells | DOF | res+tangent | res only | AMG setup | AMG solve (its) | AMG reused (its) "
              "| AMG const. null space (its) "
              "| LU factor | LU-GMRES reused (its) | SuperLU factor+solve | of which solve | AMG solve / DOF (us) |")
    print()
    print(header)
    print("|" + "|".join(["---"] * (header.count("|") - 1)) + "|")
    for r in rows:
        (cells, dofs, t_asm, t_res, t_setup, t_fresh, it_fresh, t_reuse, it_reuse, plain_txt, t_factor, t_lu, it_lu,
         t_direct, t_direct_solve) = r
        print(f"| {cells:,} | {dofs:,} | {t_asm:.3f} | {t_res:.3f} | {t_setup:.2f} | {t_fresh:.2f} ({it_fresh}) "
              f"| {t_reuse:.2f} ({it_reuse}) | {plain_txt} | {t_factor:.2f} | {t_lu:.3f} ({it_lu}) | {t_direct:.2f} "
              f"| {t_direct_solve:.3f} | {1e6 * t_fresh / dofs:.1f} |")


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--sizes", type=float, nargs="+", default=[8, 4, 2, 1, 0.5, 0.25, 0.15], help="mesh.size values")
    p.add_argument("--repeats", type=int, default=3)
    p.add_argument("--const-nullspace-sizes", type=float, nargs="*", default=[1.0])
    a = p.parse_args()
    run(a.sizes, a.repeats, set(a.const_nullspace_sizes))


if __name__ == "__main__":
    main()
