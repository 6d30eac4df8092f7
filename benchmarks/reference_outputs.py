"""Produce the files a refactor must leave unchanged: the nine paper cases at the 'fast' preset and the
collected smoke study (config/smoke.yaml), from the checkout at --repo, into --out.

    OMP_NUM_THREADS=1 .venv/bin/python benchmarks/reference_outputs.py --out /tmp/after
    OMP_NUM_THREADS=1 .venv/bin/python benchmarks/reference_outputs.py --repo ../old-checkout --out /tmp/before
    .venv/bin/python benchmarks/compare_results.py /tmp/before /tmp/after
"""

from __future__ import annotations

import argparse
import os
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

MODELS = {"DI": ["friction.model=DI"], "EA1": ["friction.model=EA", "friction.s_cut=1.0"],
          "EA0": ["friction.model=EA", "friction.s_cut=0.0"]}
PRELOADS = (-0.288, 0.0, 0.288)


def env_for(repo: Path) -> dict:
    env = dict(os.environ, PYTHONPATH=str(repo / "src"), OMP_NUM_THREADS="1", OPENBLAS_NUM_THREADS="1",
               MKL_NUM_THREADS="1", MPLBACKEND="Agg")
    return env


def paper_cases(repo: Path, out: Path, jobs: int = 2) -> None:
    out.mkdir(parents=True, exist_ok=True)
    cmds = []
    for name, sets in MODELS.items():
        for F in PRELOADS:
            args = [a for s in ["preset=fast", *sets, f"loading.preload={F}"] for a in ("--set", s)]
            cmds.append([sys.executable, "-m", "capslide", "run", str(repo / "config" / "config.yaml"), *args, "-q",
                         "-o", str(out / f"{name}_Fn{F:+.3f}.nc")])
    running = []
    for cmd in cmds:
        running.append(subprocess.Popen(cmd, env=env_for(repo)))
        if len(running) == jobs:
            running.pop(0).wait()
    for proc in running:
        proc.wait()


def smoke_study(repo: Path, out: Path) -> None:
    with tempfile.TemporaryDirectory() as tmp:
        work = Path(tmp)
        for name in ("Snakefile", "workflow", "config", "profiles", "src"):
            src = repo / name
            (shutil.copytree(src, work / name, symlinks=True) if src.is_dir() else shutil.copy(src, work / name))
        snakemake = Path(sys.executable).with_name("snakemake")
        target = "cases" if "rule cases:" in (work / "Snakefile").read_text() else "results/cases.nc"  # older layouts
        subprocess.run([str(snakemake), "--cores", "2", target, "--configfile", "config/smoke.yaml"],
                       cwd=work, env=env_for(repo), check=True)
        (results,) = {p.parent for p in (work / "results").glob("**/cases.nc")}  # results/ or results/NAME/
        (out / "smoke").mkdir(parents=True, exist_ok=True)
        shutil.copy(results / "cases.nc", out / "smoke" / "cases.nc")
        for f in (results / "cases").glob("*.nc"):
            shutil.copy(f, out / "smoke" / f.name)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repo", type=Path, default=Path(__file__).resolve().parents[1])
    ap.add_argument("--out", type=Path, required=True)
    ap.add_argument("--smoke-only", action="store_true", help="only the smoke study")
    args = ap.parse_args()
    repo = args.repo.resolve()
    if not args.smoke_only:
        paper_cases(repo, args.out / "paper_fast")
    smoke_study(repo, args.out)
    print(f"{args.out}: nine paper cases (fast) and the smoke study from {repo}")


if __name__ == "__main__":
    main()
