"""Compare two trees of capslide result files (netCDF), as a refactor must leave them.

Every variable (step variables, surface profiles, snapshots, case scalars) is compared except wall times; the
report gives, per file, the largest difference of any variable relative to that variable's largest magnitude,
and checks step counts, statuses, status reasons, cut-backs and the smallest step. Files of the layout before
docs/data.md (names X_surface, x_surface, y_surface; a flat ``case`` dimension in the collected file) are read into
the same per-case arrays as files of the current layout, so a change of layout can be checked too.

    .venv/bin/python benchmarks/compare_results.py /tmp/before /tmp/after [--rtol 1e-12] [--ignore krylov_iterations]

``--ignore NAME`` leaves a variable out (repeatable): the Krylov counts, for a change of the linear solver's
arithmetic that leaves the solutions equal to round-off.

Exit 0 when every file agrees to ``rtol``, 1 otherwise.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np
import xarray as xr

SKIP = {"wall_time", "step", "case_file", "config_yaml", "model", "preload", "friction_model", "s_cut", "case",
        "slide_end", "n_steps"}
ATTRS = ("status", "status_reason", "cutbacks", "min_step")
RENAMED = {"X_surface": "X_reference", "x_surface": "x_current", "y_surface": "y_current"}


def _arrays(ds: xr.Dataset) -> dict:
    """Every compared variable as {key: array}: by name in a case file, by (model, preload, name) in a collected
    file, its steps trimmed to the case's own."""
    if "case" in ds.dims:  # the collected file before docs/data.md
        out = {}
        for i in range(ds.sizes["case"]):
            model, n = Path(str(ds["case_file"].values[i])).stem.split("_Fn")[0], int(ds["n_steps"].values[i])
            for name, var in ds.variables.items():
                if name not in SKIP and "case" in var.dims:
                    out[(model, float(ds["preload"].values[i]), name)] = var.values[i, :n] if var.ndim > 1 else var.values[i]
        return out
    if "model" in ds.dims:
        out = {}
        for m in ds["model"].values:
            for f in ds["preload"].values:
                case = ds.sel(model=m, preload=f)
                if int(case["status"]) < 0:
                    continue
                n = int(case["n_steps"])
                for name, var in case.variables.items():
                    if name not in SKIP and var.dims in ((), ("step",)):
                        out[(str(m), float(f), name)] = var.values[:n] if var.ndim else var.values
        return out
    return {RENAMED.get(name, name): np.asarray(var.values) for name, var in ds.variables.items() if name not in SKIP}


def compare_files(a: Path, b: Path, ignore=()) -> tuple[float, str, list[str]]:
    """Largest relative difference over the variables of two files, the variable where it is, and the mismatches
    that are not numbers."""
    problems: list[str] = []
    worst, where = 0.0, ""
    with xr.open_dataset(a) as da, xr.open_dataset(b) as db:
        if da.sizes.get("step") != db.sizes.get("step"):
            problems.append(f"steps {da.sizes.get('step')} != {db.sizes.get('step')}")
            return np.inf, "", problems
        for key in ATTRS:
            if key in da.attrs and str(da.attrs[key]) != str(db.attrs.get(key)):
                problems.append(f"attribute {key}: {da.attrs[key]!r} != {db.attrs.get(key)!r}")
        va, vb = _arrays(da), _arrays(db)
        for name in va:
            if (name[-1] if isinstance(name, tuple) else name) in ignore:
                continue
            if name not in vb:
                problems.append(f"variable {name} missing")
                continue
            x, y = va[name], vb[name]
            if x.dtype.kind in "OUS":
                if not np.array_equal(x, y):
                    problems.append(f"{name} differs")
                continue
            x, y = x.astype(float), y.astype(float)
            if not np.array_equal(np.isnan(x), np.isnan(y)):
                problems.append(f"{name}: NaN at different places")
                continue
            ok = ~np.isnan(x)
            if not ok.any():
                continue
            scale = float(np.max(np.abs(x[ok]))) or 1.0
            diff = float(np.max(np.abs(x[ok] - y[ok]))) / scale
            if diff > worst:
                worst, where = diff, name if isinstance(name, str) else "/".join(map(str, name))
    return worst, where, problems


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("before", type=Path)
    ap.add_argument("after", type=Path)
    ap.add_argument("--rtol", type=float, default=1e-12)
    ap.add_argument("--ignore", action="append", default=[], metavar="NAME", help="leave this variable out")
    args = ap.parse_args()
    files = sorted(p.relative_to(args.before) for p in args.before.rglob("*.nc"))
    if not files:
        print(f"no .nc files under {args.before}")
        return 1
    failed = 0
    print("| file | steps | status | largest relative difference | in | verdict |")
    print("|---|---|---|---|---|---|")
    for rel in files:
        other = args.after / rel
        if not other.is_file():
            print(f"| {rel} | | | missing in {args.after} | | **no** |")
            failed += 1
            continue
        worst, where, problems = compare_files(args.before / rel, other, set(args.ignore))
        with xr.open_dataset(args.before / rel) as ds:
            steps = ds.sizes.get("step", "")
            status = ds.attrs.get("status", "")
        ok = worst <= args.rtol and not problems
        failed += not ok
        note = "; ".join(problems)
        verdict = "yes" if ok else "**no**"
        print(f"| {rel} | {steps} | {status} | {worst:.3g}{' (' + note + ')' if note else ''} | {where} | {verdict} |")
    print(f"\n{len(files) - failed} of {len(files)} files agree to {args.rtol:g}")
    return 0 if failed == 0 else 1


if __name__ == "__main__":
    sys.exit(main())
