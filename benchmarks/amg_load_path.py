"""Benchmark: pyamg's CG iterations per Newton iteration along the `sphere` scene's load path, against DOF (issue 39,
item 5: iterations flat within 1.5x from about 50k to 1M DOF).

For each mesh.size, ``capslide run --scene sphere --set preset=fine --set mesh.size=S --set loading.ubar_max=0``:
the approach, the edge-controlled spread and the preload to Fn = 0, on the `fine` preset's mesh (layers under the
band capped at 4 h0) and its solver (``solver.linear: auto``, AMG in 3D). The steps are set in lengths and forces,
not in cells, so every mesh takes the same path; ``--steps N`` stops each run after its N-th converged step
(``CAPSLIDE_INTERRUPT_AFTER_STEP``) where the whole path would take hours. ``--logs`` tabulates the logs of runs
made by hand instead (their stderr). ``--fresh-hierarchy`` sets the rebuild rule's setup cost to zero in the runs
(``capslide.solvers.amg.setup_cost_iterations``, patched in the process): a hierarchy built for every matrix, so
that the iterations show how well smoothed aggregation preconditions, apart from how stale the reuse lets it be.
Printed per run: DOF, steps, Newton and CG iterations, CG per Newton iteration over the run and over the steps every
run has, the wall time (the steps' sum) and the peak RSS (``/usr/bin/time -f peak_rss_kb=%M``, in a log where the
run was timed so). Nothing is asserted.

    OMP_NUM_THREADS=1 .venv/bin/python benchmarks/amg_load_path.py --sizes 100 60 40 [--steps 12] [--fresh-hierarchy]
    .venv/bin/python benchmarks/amg_load_path.py --logs s100.log s60.log s40.log
"""

from __future__ import annotations

import argparse
import os
import re
import signal
import subprocess
import sys
import tempfile
from pathlib import Path

STEP = re.compile(r"^[a-z]+ +ubar=.* newton= *(\d+) krylov= *(\d+) t= *([0-9.]+)s$")
DOFS = re.compile(r"building the mesh: .*?([\d,]+) DOF")
RESUMED = re.compile(r"resuming from .* \((\d+) converged steps")


def parse_log(text: str) -> dict:
    """DOF and the per-step (Newton, CG, seconds) of a case's log, resumed or not."""
    dofs = DOFS.search(text)
    steps = []
    for line in text.splitlines():
        if m := STEP.match(line):
            steps.append((int(m[1]), int(m[2]), float(m[3])))
        elif m := RESUMED.search(line):
            # a resume replays its checkpoint's N steps just before this line, and the steps the run logged past
            # its checkpoint were lost and run again: the path is the first N steps, then those after this line
            del steps[int(m[1]):]
    rss = re.search(r"peak_rss_kb=(\d+)", text)  # /usr/bin/time -f peak_rss_kb=%M, where the run was timed so
    return {"dofs": int(dofs[1].replace(",", "")) if dofs else 0, "steps": steps,
            "rss": int(rss[1]) / 1e6 if rss else float("nan")}


# capslide's command line with the AMG rebuild rule's setup cost patched to zero: a rebuild before every solve
FRESH = ("import sys; import capslide.solvers.amg as amg; amg.setup_cost_iterations = lambda n_dofs: 0.0; "
         "from capslide.cli import main; raise SystemExit(main(sys.argv[1:]))")


def run_size(size: float, steps: int | None, folder: Path, fresh: bool = False) -> dict:
    """One run of the `fine` preset at ``mesh.size`` = ``size``; its parsed log and peak RSS (GB)."""
    cli = ["-c", FRESH] if fresh else ["-m", "capslide"]
    cmd = [sys.executable, *cli, "run", "--scene", "sphere", "--set", "preset=fine", "--set",
           f"mesh.size={size}", "--set", "loading.ubar_max=0", "-o", str(folder / f"s{size:g}.nc")]
    timer = "/usr/bin/time" if Path("/usr/bin/time").exists() else None
    if timer:
        cmd = [timer, "-f", "peak_rss_kb=%M", *cmd]
    env = dict(os.environ, **({"CAPSLIDE_INTERRUPT_AFTER_STEP": str(steps)} if steps else {}))
    # SIGINT back to its default in the run: a background shell (nohup ... &) starts its jobs with it ignored, and
    # the interruption after --steps would then go unheard (the run went on to the end of the path).
    res = subprocess.run(cmd, capture_output=True, text=True, env=env, start_new_session=True,
                         preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    row = parse_log(res.stderr)
    if not row["steps"]:
        raise SystemExit(f"mesh.size {size:g}: exit {res.returncode}: {res.stderr.strip().splitlines()[-1]}")
    return {**row, "name": f"{size:g}"}


def table(rows: list[dict]) -> list[str]:
    """Markdown rows: the iterations over each run and over the steps all runs have."""
    common = min(len(r["steps"]) for r in rows)
    lines = [f"| run | DOF | steps | Newton | CG | CG per Newton | CG per Newton, first {common} steps | wall (s) | "
             "peak RSS (GB) |", "|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        newton, cg, wall = (sum(s[i] for s in r["steps"]) for i in range(3))
        n0, c0 = (sum(s[i] for s in r["steps"][:common]) for i in range(2))
        lines.append(f"| {r['name']} | {r['dofs']:,} | {len(r['steps'])} | {newton} | {cg:,} | {cg / newton:.1f} | "
                     f"{c0 / n0:.1f} | {wall:,.0f} | {r.get('rss', float('nan')):.1f} |")
    per_newton = [sum(s[1] for s in r["steps"][:common]) / sum(s[0] for s in r["steps"][:common]) for r in rows]
    lines.append(f"\nlargest over smallest CG per Newton iteration on the first {common} steps: "
                 f"{max(per_newton) / min(per_newton):.2f}x")
    return lines


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    source = parser.add_mutually_exclusive_group(required=True)
    source.add_argument("--sizes", nargs="+", type=float, help="mesh.size of each run (the fine preset's is 60)")
    source.add_argument("--logs", nargs="+", type=Path, help="logs (stderr) of capslide run to tabulate")
    parser.add_argument("--steps", type=int, default=None, help="stop each run after this many converged steps")
    parser.add_argument("--fresh-hierarchy", action="store_true", help="rebuild the AMG hierarchy before every solve")
    args = parser.parse_args(argv)
    if args.logs:
        rows = [{**parse_log(p.read_text()), "name": p.stem} for p in args.logs]
    else:
        print(f"threads: OMP {os.environ.get('OMP_NUM_THREADS', 'unset')}", flush=True)
        with tempfile.TemporaryDirectory() as tmp:
            rows = [run_size(s, args.steps, Path(tmp), args.fresh_hierarchy) for s in args.sizes]
    if any(not r["steps"] for r in rows):
        raise SystemExit("a log has no step lines")
    print("\n".join(table(rows)))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
