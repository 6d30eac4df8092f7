"""The linear solver of the `sphere` scene's study (issue 40): the normal state to zero load and model DI's slide
from it to --ubar L0, on the study's mesh (the `fast` preset: 36,450 DOF), with each solver in one run.

The solvers: pyamg smoothed aggregation preconditioning CG/BiCGStab (solver.linear: amg, what `auto` takes in 3D),
a reused SuperLU factorization preconditioning GMRES (lu_krylov), and reused MKL PARDISO factors (lu_krylov with
solver.factorization: pardiso; needs `make setup-pardiso`). The path's steps and iterations are those each solver
lets the continuation take. One BLAS thread; each run timed once (a run is minutes: its steps are the repeats), with
the median seconds per step.

    OMP_NUM_THREADS=1 .venv/bin/python benchmarks/sphere_solvers.py --ubar 1.0
"""

from __future__ import annotations

import argparse
import statistics
import time

from capslide.config import load_config, scene_path
from capslide.driver.case import run_case
from capslide.io.checkpoint import SavedCase
from capslide.params import Parameters
from capslide.states import Phase, Status

SOLVERS = {
    "amg (CG/BiCGStab + smoothed aggregation)": {"solver.linear": "amg"},
    "lu_krylov, SuperLU factors": {"solver.linear": "lu_krylov", "solver.factorization": "superlu"},
    "lu_krylov, PARDISO factors": {"solver.linear": "lu_krylov", "solver.factorization": "pardiso"},
}


def _part(records: list, wall: float) -> dict:
    """Steps, iterations and times of one part of a path (its records)."""
    return {"steps": len(records), "newton": sum(r.newton_iterations for r in records),
            "krylov": sum(r.krylov_iterations for r in records), "wall": wall,
            "per_step": statistics.median(r.wall_time for r in records)}


def one_run(preset: str, ubar: float, solver: dict) -> dict:
    """The normal state to zero load, then DI's slide to ``ubar`` (L0), with ``solver``'s settings: each part's
    counts and times, and Ft and the area at the end."""
    settings = {"preset": preset, "friction.model": "DI", "loading.preload": 0.0, "output.snapshot_ubar": [],
                "loading.ubar_max": ubar, **solver}
    params = Parameters.from_config(load_config([scene_path("sphere")], settings=settings))
    t = time.perf_counter()
    pre = run_case(params, stop_before="dwell")
    t_state = time.perf_counter() - t
    if pre.status != Status.COMPLETED:
        raise SystemExit(f"{solver}: the normal state ended {pre.status.label}: {pre.reason}")
    t = time.perf_counter()
    res = run_case(params, resume=SavedCase(pre.state, pre.records, [], pre.wall_time))
    t_slide = time.perf_counter() - t
    slide = [r for r in res.records if r.phase == Phase.SLIDE]
    return {"dofs": pre.mesh.n_dofs, "state": _part(pre.records, t_state), "slide": _part(slide, t_slide),
            "status": res.status.label, "area0": pre.records[-1].area, "Ft": slide[-1].Ft, "area": slide[-1].area}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--ubar", type=float, default=1.0, help="slide distance (L0)")
    ap.add_argument("--preset", default="fast", help="the scene's mesh preset")
    ap.add_argument("--solvers", nargs="+", choices=list(SOLVERS), default=list(SOLVERS), metavar="NAME")
    args = ap.parse_args()
    rows = {name: one_run(args.preset, args.ubar, SOLVERS[name]) for name in args.solvers}
    fastest = min(r["state"]["wall"] + r["slide"]["wall"] for r in rows.values())
    print(f"sphere, preset {args.preset} ({next(iter(rows.values()))['dofs']:,} DOF): normal state to Fn = 0, "
          f"then DI slid to ubar = {args.ubar:g} L0")
    print("| solver | part | steps | Newton | Krylov | median s/step | s | total s | x fastest | area at Fn = 0 "
          "| Ft at end | area at end |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    for name, r in rows.items():
        total = r["state"]["wall"] + r["slide"]["wall"]
        for part in ("state", "slide"):
            p = r[part]
            end = ([f"{total:.0f}", f"{total / fastest:.1f}", f"{r['area0']:.4f}", f"{r['Ft']:.5f}", f"{r['area']:.4f}"]
                   if part == "slide" else [""] * 5)
            cells = [name if part == "state" else "", part, p["steps"], p["newton"], p["krylov"], f"{p['per_step']:.2f}",
                     f"{p['wall']:.0f}", *end]
            print("| " + " | ".join(map(str, cells)) + " |", flush=True)


if __name__ == "__main__":
    main()
