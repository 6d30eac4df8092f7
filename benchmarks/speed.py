"""Speed of the reproduction (issue 19): the full workflow, one paper case against a fixed yardstick, and the
quantities of interest of two result trees side by side.

    .venv/bin/python benchmarks/speed.py reproduce --repo ../clone-a --repo ../clone-b --repeats 3
    OMP_NUM_THREADS=1 .venv/bin/python benchmarks/speed.py case
    .venv/bin/python benchmarks/speed.py qoi ../clone-a/results/paper/cases results/paper/cases
    .venv/bin/python benchmarks/speed.py onset ../clone-a/results/paper/cases results/paper/cases
    .venv/bin/python benchmarks/speed.py iterations ../clone-a/results/paper/cases results/paper/cases
    .venv/bin/python benchmarks/speed.py timeline ../clone-a/.snakemake/log/*.snakemake.log

``reproduce`` runs ``snakemake --cores 2`` in each clone (after ``make setup`` there) with ``results/``, ``logs/``
and ``.snakemake/`` removed before each run, the clones alternating, and prints every time and the medians.
``case`` runs the paper case DI at Fn* = 0 (slide to 5 L0) in this process and a fixed yardstick, SuperLU on the
5-point Laplacian of a 300 x 300 grid plus one solve (median of 5), and prints both and their ratio. ``qoi``
prints peak Ft, the onset of full sliding (ubar, area) and Ft at ubar = 4 L0 of every case file present in both
directories, with the largest relative difference; ``onset`` the slide steps between which the onset lies in each
tree; ``iterations`` steps, Newton iterations and cut-backs; ``timeline`` when each job of a workflow run started
and ended (whole seconds, from Snakemake's log) and the job time per rule. Nothing is asserted: the numbers are for
docs/performance.md.
"""

from __future__ import annotations

import argparse
import datetime
import math
import re
import shutil
import statistics
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
QOIS = ("peak_Ft", "onset_ubar", "onset_area", "Ft_at_4")


def yardstick(n: int = 300, repeats: int = 5) -> float:
    """Median time (s) of splu of the 5-point Laplacian on an n x n grid plus one solve."""
    import scipy.sparse as sp
    import scipy.sparse.linalg as spla

    d = sp.diags([-np.ones(n - 1), 2 * np.ones(n), -np.ones(n - 1)], [-1, 0, 1])
    A = (sp.kron(sp.identity(n), d) + sp.kron(d, sp.identity(n))).tocsc()
    b = np.ones(n * n)
    times = []
    for _ in range(repeats):
        t = time.perf_counter()
        spla.splu(A).solve(b)
        times.append(time.perf_counter() - t)
    return statistics.median(times)


def cmd_case(args) -> None:
    sys.path.insert(0, str(ROOT / "src"))
    from capslide.config import load_config
    from capslide.driver.case import run_case
    from capslide.params import Parameters

    params = Parameters.from_config(load_config([ROOT / "config" / "config.yaml"], args.set))
    t = time.perf_counter()
    result = run_case(params)
    case = time.perf_counter() - t
    ruler = yardstick()
    slide = [r for r in result.records if r.phase.label == "slide"]
    print("| case | status | steps (slide) | Newton iterations (slide) | time (s) | yardstick (s) | ratio |")
    print("|---|---|---|---|---|---|---|")
    f = params.friction
    model = f.model if f.model != "EA" else f"EA{f.s_cut:g}"
    print(f"| {model}, Fn* = {params.loading.preload:g}, {params.config['preset']} | {result.status.label} | "
          f"{len(result.records)} ({len(slide)}) | "
          f"{sum(r.newton_iterations for r in result.records)} ({sum(r.newton_iterations for r in slide)}) | "
          f"{case:.1f} | {ruler:.3f} | {case / ruler:.0f} |")


def qois(path: Path) -> dict[str, float]:
    import xarray as xr

    with xr.open_dataset(path) as ds:
        out = {name: float(ds[name]) for name in QOIS[:3]}
        at4 = (ds["phase"].values == 2) & (ds["ubar"].values == 4.0)
        out["Ft_at_4"] = float(ds["Ft"].values[at4][0]) if at4.any() else float("nan")
    return out


def common_files(before: Path, after: Path) -> list[str]:
    """Names of the case files present in both directories, sorted."""
    return sorted(p.name for p in before.glob("*.nc") if (after / p.name).is_file())


def cmd_qoi(args) -> None:
    names = common_files(args.before, args.after)
    print("| case | " + " | ".join(QOIS) + " | largest relative difference |")
    print("|---|" + "---|" * (len(QOIS) + 1))
    worst_all = 0.0
    for name in names:
        a, b = qois(args.before / name), qois(args.after / name)
        diffs = [abs(b[q] - a[q]) / abs(a[q]) for q in QOIS if np.isfinite(a[q]) and a[q] != 0]
        worst = max(diffs, default=0.0)
        worst_all = max(worst_all, worst)
        print(f"| {name[:-3]} | " + " | ".join(f"{b[q]:.6g}" for q in QOIS) + f" | {worst:.2g} |")
    print(f"\n{len(names)} cases; largest relative difference of a QoI: {worst_all:.2g}")


def onset_bracket(path: Path) -> tuple[float, float]:
    """The slide step before the first fully sliding one and that one (ubar, L0): where the onset lies."""
    import xarray as xr

    with xr.open_dataset(path) as ds:
        ubar = ds["ubar"].values[ds["phase"].values == 2]
        onset = float(ds["onset_ubar"])
    if not np.isfinite(onset):
        return math.nan, math.nan
    i = int(np.flatnonzero(ubar == onset)[0])
    return float(ubar[i - 1]), onset


def cmd_onset(args) -> None:
    names = common_files(args.before, args.after)
    print("| case | before: bracket (L0) | width (%) | after: bracket (L0) | width (%) | brackets overlap |")
    print("|---|---|---|---|---|---|")
    for name in names:
        (a0, a1), (b0, b1) = onset_bracket(args.before / name), onset_bracket(args.after / name)
        if not np.isfinite(a1):
            print(f"| {name[:-3]} | - | - | - | - | - |")
            continue
        inside = a0 - 1e-12 <= b1 <= a1 + 1e-12 or b0 - 1e-12 <= a1 <= b1 + 1e-12
        print(f"| {name[:-3]} | [{a0:.5f}, {a1:.5f}] | {100 * (a1 - a0) / a1:.2f} | [{b0:.5f}, {b1:.5f}] | "
              f"{100 * (b1 - b0) / b1:.3f} | {'yes' if inside else 'NO'} |")


def iteration_counts(path: Path) -> dict[str, float]:
    """Steps and Newton iterations of the approach and preload together and of the slide, and the case's cut-backs
    (failed attempts, the onset check's included)."""
    import xarray as xr

    with xr.open_dataset(path) as ds:
        phase, its = ds["phase"].values, ds["newton_iterations"].values
        out = {"cutbacks": int(ds.attrs["cutbacks"])}
    for code, leg in ((1, "normal"), (2, "slide")):
        mask = phase == code if code == 2 else phase != 2
        out[f"{leg}_steps"], out[f"{leg}_newton"] = int(mask.sum()), int(its[mask].sum())
    return out


def cmd_iterations(args) -> None:
    names = common_files(args.before, args.after)
    print("| case | approach + preload: steps, Newton (before -> after) | slide: steps, Newton, per step | cut-backs |")
    print("|---|---|---|---|")
    total = {"before": 0, "after": 0}
    for name in names:
        a, b = iteration_counts(args.before / name), iteration_counts(args.after / name)
        total["before"] += a["normal_newton"] + a["slide_newton"]
        total["after"] += b["normal_newton"] + b["slide_newton"]
        print(f"| {name[:-3]} | {a['normal_steps']}, {a['normal_newton']} -> {b['normal_steps']}, {b['normal_newton']} | "
              f"{a['slide_steps']}, {a['slide_newton']}, {a['slide_newton'] / max(a['slide_steps'], 1):.1f} -> "
              f"{b['slide_steps']}, {b['slide_newton']}, {b['slide_newton'] / max(b['slide_steps'], 1):.1f} | "
              f"{a['cutbacks']} -> {b['cutbacks']} |")
    print(f"\n{len(names)} cases; Newton iterations {total['before']} -> {total['after']} "
          f"({total['after'] / max(total['before'], 1):.2f}x)")


def cmd_reproduce(args) -> None:
    times: dict[Path, list[float]] = {repo: [] for repo in args.repo}
    for i in range(args.repeats):
        for repo in args.repo:
            for name in ("results", "logs", ".snakemake"):
                shutil.rmtree(repo / name, ignore_errors=True)
            t = time.perf_counter()
            extra = ["--configfile", args.configfile] if args.configfile else []
            done = subprocess.run([str(repo / ".venv" / "bin" / "snakemake"), "--cores", "2", *extra], cwd=repo,
                                  capture_output=True, text=True)
            times[repo].append(time.perf_counter() - t)
            print(f"{repo} run {i + 1}: {times[repo][-1]:.0f} s (exit {done.returncode})", flush=True)
    print("\n| clone | runs (s) | median (s) |")
    print("|---|---|---|")
    for repo, ts in times.items():
        print(f"| {repo} | {', '.join(f'{t:.0f}' for t in ts)} | {statistics.median(ts):.0f} |")


def job_timeline(log_text: str) -> list[tuple[float, float, str]]:
    """(start, end, job) in seconds from the first timestamp of a Snakemake log (.snakemake/log/*.log): a job
    starts at the timestamp before its ``rule``/``localrule`` line and ends at the one before its ``Finished jobid``
    line; ``job`` is the rule and its wildcards."""
    stamp, t0, rule, started, names, out = None, None, None, {}, {}, []
    for line in log_text.splitlines():
        if m := re.match(r"\[(\w{3} \w{3} +\d+ [\d:]+ \d{4})\]", line):
            stamp = datetime.datetime.strptime(m.group(1), "%a %b %d %H:%M:%S %Y")
            t0 = t0 or stamp
        elif m := re.match(r"(?:local)?rule (\w+):", line):
            rule = m.group(1)
        elif (m := re.match(r"\s+jobid: (\d+)", line)) and rule:
            started[m.group(1)], names[m.group(1)], rule = stamp, rule, None
            last = m.group(1)
        elif (m := re.match(r"\s+wildcards: (.*)", line)) and started:
            names[last] += " " + m.group(1)
        elif (m := re.match(r"Finished jobid: (\d+)", line)) and m.group(1) in started:
            j = m.group(1)
            out.append(((started[j] - t0).total_seconds(), (stamp - t0).total_seconds(), names[j]))
    return out


def cmd_timeline(args) -> None:
    jobs = job_timeline(args.log.read_text())
    print("| start (s) | end (s) | job (s) | job |\n|---|---|---|---|")
    for start, end, name in sorted(jobs):
        print(f"| {start:.0f} | {end:.0f} | {end - start:.0f} | {name} |")
    totals: dict[str, float] = {}
    for start, end, name in jobs:
        totals[name.split()[0]] = totals.get(name.split()[0], 0.0) + end - start
    print("\njob time per rule (s): " + ", ".join(f"{k} {v:.0f}" for k, v in sorted(totals.items())))
    print(f"wall time (s): {max(end for _, end, _ in jobs):.0f}")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    sub = ap.add_subparsers(dest="command", required=True)
    p = sub.add_parser("case", help="one paper case and the yardstick, in this process")
    p.add_argument("--set", action="append", default=[], metavar="KEY=VALUE", help="config override")
    p.set_defaults(func=cmd_case)
    p = sub.add_parser("qoi", help="QoIs of the case files in two directories")
    p.add_argument("before", type=Path)
    p.add_argument("after", type=Path)
    p.set_defaults(func=cmd_qoi)
    p = sub.add_parser("onset", help="where the onset of full sliding lies, in the case files of two directories")
    p.add_argument("before", type=Path)
    p.add_argument("after", type=Path)
    p.set_defaults(func=cmd_onset)
    p = sub.add_parser("iterations", help="steps, Newton iterations and cut-backs of the case files in two directories")
    p.add_argument("before", type=Path)
    p.add_argument("after", type=Path)
    p.set_defaults(func=cmd_iterations)
    p = sub.add_parser("reproduce", help="snakemake --cores 2 in clones, alternating")
    p.add_argument("--repo", type=Path, action="append", required=True)
    p.add_argument("--repeats", type=int, default=3)
    p.add_argument("--configfile", help="a config overlay for every run (config/smoke.yaml: a quick check)")
    p.set_defaults(func=cmd_reproduce)
    p = sub.add_parser("timeline", help="when each job of a Snakemake run started and ended, from its log")
    p.add_argument("log", type=Path, help=".snakemake/log/*.snakemake.log of the run")
    p.set_defaults(func=cmd_timeline)
    args = ap.parse_args()
    args.func(args)


if __name__ == "__main__":
    main()
