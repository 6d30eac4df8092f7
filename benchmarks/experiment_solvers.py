"""The linear solver of the `experiment` scene's slide (issue 40, item 6): one case, A0 = 0.27 mm^2, preloaded to its
area from the study's normal state and slid to --ubar um, with each solver in one run.

The tangent of the slide (21,420 DOF at the coarse preset, H1/P0 at nu = 0.49; stick, slip and adhesion at the
contact edge) is solved by pyamg smoothed aggregation preconditioning CG/BiCGStab (solver.linear: amg, the 3D
default), by a reused SuperLU factorization preconditioning GMRES (lu_krylov), or by reused MKL PARDISO factors
(lu_krylov with solver.factorization: pardiso, the scene's). The path's steps, cut-backs and iterations are those
each solver lets the continuation take. One BLAS thread; the run of each solver is timed once (a run is minutes: its
steps are the repeats), with the median seconds per step.

    capslide preload --scene experiment --set preset=coarse --set loading.preload=0.0 \\
        --set loading.preload_area=null -o lambda2_coarse.npz                # the normal state, once
    OMP_NUM_THREADS=1 .venv/bin/python benchmarks/experiment_solvers.py --preset coarse \\
        --state lambda2_coarse.npz --ubar 25
"""

from __future__ import annotations

import argparse
import statistics
import time
from dataclasses import replace

from capslide.config import load_config, scene_path
from capslide.driver.case import run_case
from capslide.io.normal_state import read_normal_state_at_any_preload
from capslide.loadpath.cap import continued_from
from capslide.params import Parameters
from capslide.states import Phase
from capslide.studies.experiment_3d import study_cases

SOLVERS = {
    "amg (CG/BiCGStab + smoothed aggregation)": {"solver.linear": "amg"},
    "lu_krylov, SuperLU factors": {"solver.linear": "lu_krylov", "solver.factorization": "superlu"},
    "lu_krylov, PARDISO factors (the scene's)": {"solver.linear": "lu_krylov", "solver.factorization": "pardiso"},
}


def one_run(state: str, case: dict, ubar: float, solver: dict) -> dict:
    """Preload and slide of ``case`` (its settings, the preset among them) from the normal state file ``state`` with
    ``solver``'s settings."""
    scene = load_config([scene_path("experiment")], settings=case)
    saved, reached = read_normal_state_at_any_preload(state, scene)
    approached = [r.Fn for r in saved.records if r.phase in (Phase.APPROACH, Phase.SPREAD)]
    params = Parameters.from_config(load_config([scene_path("experiment")],
                                                settings={**case, **solver, "loading.ubar_max": ubar}))
    start = replace(saved, state=continued_from(params.loading, saved.state, reached, approached[-1]))
    cutbacks = start.state.cutbacks  # before the run, which may continue the saved loop in place
    t = time.perf_counter()
    res = run_case(params, resume=start)
    wall = time.perf_counter() - t
    new = res.records[len(saved.records):]
    return {"status": res.status.label, "steps": len(new), "cutbacks": res.cutbacks - cutbacks, "wall": wall,
            "newton": sum(r.newton_iterations for r in new), "krylov": sum(r.krylov_iterations for r in new),
            "per_step": statistics.median(r.wall_time for r in new), "Ft": new[-1].Ft, "area": new[-1].area}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--state", required=True, help="the study's normal state at the scene's lambda (npz)")
    ap.add_argument("--ubar", type=float, default=25.0, help="slide distance (um)")
    ap.add_argument("--area", default="A0.270", help="the study's case")
    ap.add_argument("--preset", default=None, help="the scene's mesh preset (default: the scene's own), as the state's")
    args = ap.parse_args()
    case = study_cases(load_config([scene_path("experiment")]))[args.area]
    if args.preset is not None:
        case = {**case, "preset": args.preset}
    rows = {name: one_run(args.state, case, args.ubar, s) for name, s in SOLVERS.items()}
    fastest = min(r["wall"] for r in rows.values())
    print(f"{args.area}: preload to its area and slide to ubar = {args.ubar:g} um")
    print("| solver | status | steps | cut-backs | Newton | Krylov | median s/step | total s | x fastest | Ft at end "
          "| area at end |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for name, r in rows.items():
        print(f"| {name} | {r['status']} | {r['steps']} | {r['cutbacks']} | {r['newton']} | {r['krylov']} | "
              f"{r['per_step']:.2f} | {r['wall']:.0f} | {r['wall'] / fastest:.1f} | {r['Ft']:.1f} | {r['area']:.0f} |",
              flush=True)


if __name__ == "__main__":
    main()
