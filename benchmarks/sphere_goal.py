"""The 10-minute goal of issue 39: the `sphere` scene's approach and preload to Fn = 0, per preset, against the
converged zero-load area.

Runs ``capslide run --scene sphere --set preset=P --set loading.ubar_max=0`` for each preset (a fresh process each,
under ``/usr/bin/time`` for the peak memory), reads the file and prints one Markdown row per preset: DOF, steps,
Newton and Krylov iterations, the wall time (median of ``--repeats``), peak RSS, the zero-load area and its error
against the two estimates of the converged area in docs/three_d.md (cost of the sphere scene): H2/P1's rings
extrapolated, about 148.0 L0^2, and H1/P0's, 146.3 to 146.8 (the middle, 146.55, here). Nothing is asserted.

    OMP_NUM_THREADS=2 MKL_NUM_THREADS=2 .venv/bin/python benchmarks/sphere_goal.py --presets coarse fast annulus_h2

``--variants`` runs each preset once per variant, a comma-separated list of ``--set`` assignments ("" the preset
alone), in the order given, and adds the wall time's ratio to the first row (measured in the same run):

    ... sphere_goal.py --presets annulus_h2 --variants "" solver.factor_precision=double
"""

from __future__ import annotations

import argparse
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from capslide.io.reading import open_result

CONVERGED = {"H2/P1": 148.0, "H1/P0": 146.55}  # L0^2, docs/three_d.md


def run_once(preset: str, folder: Path, sets: tuple[str, ...] = ()) -> dict:
    out = folder / f"{preset}.nc"
    cmd = [sys.executable, "-m", "capslide", "run", "--scene", "sphere", "--set", f"preset={preset}", "--set",
           "loading.ubar_max=0", *(a for s in sets for a in ("--set", s)), "-o", str(out)]
    timer = shutil.which("time") or ("/usr/bin/time" if Path("/usr/bin/time").exists() else None)
    if timer:
        cmd = [timer, "-f", "%M", *cmd]
    start = time.perf_counter()
    res = subprocess.run(cmd, capture_output=True, text=True, env=os.environ)
    wall = time.perf_counter() - start
    if res.returncode != 0:
        raise SystemExit(f"preset {preset}: exit {res.returncode}: {res.stderr.strip().splitlines()[-1]}")
    rss = float(res.stderr.strip().splitlines()[-1]) / 1e6 if timer else float("nan")  # kB -> GB
    ds = open_result(out, "case")
    row = {"dofs": int(ds.attrs["n_dofs"]),
           "steps": int(ds.sizes["step"]), "newton": int(ds["newton_iterations"].sum()),
           "krylov": int(ds["krylov_iterations"].sum()), "area": float(ds["area"].values[-1]),
           "element": str(ds.attrs.get("mesh_element", "")), "wall": wall, "rss": rss}
    ds.close()
    out.unlink()
    return row


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--presets", nargs="+", default=["coarse", "fast", "annulus_h2"])
    parser.add_argument("--repeats", type=int, default=1)
    parser.add_argument("--variants", nargs="+", default=[""], help="comma-separated --set assignments per row")
    args = parser.parse_args(argv)
    print(f"threads: OMP {os.environ.get('OMP_NUM_THREADS', 'unset')}, MKL {os.environ.get('MKL_NUM_THREADS', 'unset')}")
    print("| preset | variant | DOF | steps | Newton | Krylov | wall (median) | x first row | peak RSS (GB) | "
          "zero-load area (L0^2) | " + " | ".join(f"against {k} {v:g}" for k, v in CONVERGED.items()) + " |")
    print("|---|---|---|---|---|---|---|---|---|---|" + "---|" * len(CONVERGED))
    first = None
    with tempfile.TemporaryDirectory() as tmp:
        for preset in args.presets:
            for variant in args.variants:
                sets = tuple(s for s in variant.split(",") if s)
                rows = [run_once(preset, Path(tmp), sets) for _ in range(args.repeats)]
                r, wall = rows[-1], statistics.median(x["wall"] for x in rows)
                first = first or wall
                errors = " | ".join(f"{100 * (r['area'] / v - 1):+.1f} %" for v in CONVERGED.values())
                print(f"| {preset} | {variant or '-'} | {r['dofs']:,} | {r['steps']} | {r['newton']} | "
                      f"{r['krylov']:,} | {int(wall // 60)} min {wall % 60:.0f} s | {wall / first:.2f} | "
                      f"{max(x['rss'] for x in rows):.1f} | {r['area']:.4f} | {errors} |", flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
