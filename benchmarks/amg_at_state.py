"""Benchmark: a fresh pyamg hierarchy's CG iterations at a run's zero-load state, against DOF (issue 39, item 5).

Along the load path (``benchmarks/amg_load_path.py``) the CG iterations per Newton iteration mix two things: how
well a hierarchy built for the matrix preconditions it, and how stale the reused hierarchy is when the rebuild rule
(``capslide.solvers.amg``: rebuild once the iterations beyond a fresh hierarchy's add up to a setup's cost, which
grows with the DOF) lets it be. This separates them. For each result file of ``capslide run --scene sphere ...
--set loading.ubar_max=0`` it rebuilds the model from the file's configuration, takes the state of its snapshot at
ubar = 0 (the nodal displacements and the last step's height: the preloaded state), checks that it is the converged
zero-load state (the residual's norms are printed), and solves, with a hierarchy built for each matrix, the tangent
against the force-controlled border c = dR/dh (the solve every force-controlled Newton iteration makes) at that
state and at rest (u = 0, the flat far away). Printed per file: DOF, the CG iterations at rest and in contact, the
setup and solve times in contact and the run's own CG per Newton iteration. Nothing is asserted.

    OMP_NUM_THREADS=1 .venv/bin/python benchmarks/amg_at_state.py s100.nc s60.nc s40.nc
"""

from __future__ import annotations

import argparse

import numpy as np
import xarray as xr
import yaml

from capslide.config import validate
from capslide.model.build import build_model
from capslide.model.constraints import FixedForce
from capslide.model.system import History
from capslide.params import Parameters
from capslide.solvers.amg import AMGSolver


def zero_load_state(ds: xr.Dataset) -> np.ndarray:
    """[u, h] of the snapshot at ubar = 0: nodal displacements (L0) interleaved per node, the last step's height."""
    snap = ds.sel(snapshot_ubar=0.0)
    u = np.column_stack([snap[k].values for k in ("u_node", "v_node", "w_node")]).ravel()
    return np.concatenate([u, [float(ds["h"].values[-1])]])


def fresh_solve(solver: AMGSolver, K, b: np.ndarray) -> tuple[int, float, float]:
    """CG iterations, setup and solve seconds of ``K z = b`` with a hierarchy built for K."""
    _, info = solver.solve(K, b, rebuild=True)
    return info.iterations, info.setup_time, info.solve_time


def row(path: str) -> str:
    ds = xr.open_dataset(path)
    params = Parameters.from_config(validate(yaml.safe_load(ds.attrs["config_yaml"])))
    model = build_model(params)
    if not isinstance(model.solver, AMGSolver):
        raise SystemExit(f"{path}: the run's linear solver is {type(model.solver).__name__}, not AMG")
    x = zero_load_state(ds)
    history, constraint = History(), FixedForce(0.0)
    res = model.residual(x, constraint, history)
    scale = np.linalg.norm(model.internal_force(x[:-1], history))
    _, contact = model.linearize(x, constraint, history)
    its, setup, solve = fresh_solve(model.solver, contact.K, contact.c)
    rest = np.concatenate([np.zeros(model.n_dofs), [x[-1] + 100.0]])
    _, at_rest = model.linearize(rest, constraint, history)
    load = np.zeros(model.n_dofs)  # at rest the border is zero (no contact force): a load on the apex instead
    load[model.apex_y_dof] = -1.0
    load[model.bc.dofs] = 0.0
    its_rest, _, _ = fresh_solve(model.solver, at_rest.K, load)
    run = float(ds["krylov_iterations"].sum()) / float(ds["newton_iterations"].sum())
    return (f"| {path} | {model.n_dofs:,} | {np.linalg.norm(res[:-1]) / scale:.1e} | {res[-1]:+.1e} | {its_rest} | "
            f"{its} | {setup:.1f} | {solve:.1f} | {run:.1f} |")


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("files", nargs="+", help="results of capslide run --scene sphere ... --set loading.ubar_max=0")
    args = ap.parse_args(argv)
    print("| file | DOF | residual / internal force | Fn residual (E L0^2) | CG at rest | CG at zero load | "
          "setup (s) | solve (s) | the run's CG per Newton |")
    print("|---|---|---|---|---|---|---|---|---|")
    for path in args.files:
        print(row(path), flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
