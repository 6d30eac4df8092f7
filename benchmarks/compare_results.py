"""Compare two trees of capslide result files (netCDF), as a refactor must leave them.

Every variable (step variables, surface profiles, snapshots, case scalars) is compared except wall times; the
report gives, per file, the largest difference of any variable relative to that variable's largest magnitude,
and checks step counts, statuses, status reasons, cut-backs and the smallest step.

    .venv/bin/python benchmarks/compare_results.py /tmp/before /tmp/after [--rtol 1e-12]

Exit 0 when every file agrees to ``rtol``, 1 otherwise.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np
import xarray as xr

SKIP = {"wall_time"}
ATTRS = ("status", "status_reason", "cutbacks", "min_step")


def _values(ds: xr.Dataset, name: str) -> np.ndarray:
    return np.asarray(ds[name].values)


def compare_files(a: Path, b: Path) -> tuple[float, list[str]]:
    """Largest relative difference over the variables of two files, and the mismatches that are not numbers."""
    problems: list[str] = []
    worst = 0.0
    with xr.open_dataset(a) as da, xr.open_dataset(b) as db:
        if dict(da.sizes) != dict(db.sizes):
            problems.append(f"sizes {dict(da.sizes)} != {dict(db.sizes)}")
            return np.inf, problems
        for key in ATTRS:
            if key in da.attrs and str(da.attrs[key]) != str(db.attrs.get(key)):
                problems.append(f"attribute {key}: {da.attrs[key]!r} != {db.attrs.get(key)!r}")
        names = [n for n in da.variables if n not in SKIP]
        for name in names:
            if name not in db.variables:
                problems.append(f"variable {name} missing")
                continue
            x, y = _values(da, name), _values(db, name)
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
            worst = max(worst, float(np.max(np.abs(x[ok] - y[ok]))) / scale)
    return worst, problems


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("before", type=Path)
    ap.add_argument("after", type=Path)
    ap.add_argument("--rtol", type=float, default=1e-12)
    args = ap.parse_args()
    files = sorted(p.relative_to(args.before) for p in args.before.rglob("*.nc"))
    if not files:
        print(f"no .nc files under {args.before}")
        return 1
    failed = 0
    print("| file | steps | status | largest relative difference | verdict |")
    print("|---|---|---|---|---|")
    for rel in files:
        other = args.after / rel
        if not other.is_file():
            print(f"| {rel} | | | missing in {args.after} | **no** |")
            failed += 1
            continue
        worst, problems = compare_files(args.before / rel, other)
        with xr.open_dataset(args.before / rel) as ds:
            steps = ds.sizes.get("step", "")
            status = ds.attrs.get("status", "")
        ok = worst <= args.rtol and not problems
        failed += not ok
        note = "; ".join(problems)
        print(f"| {rel} | {steps} | {status} | {worst:.3g}{' (' + note + ')' if note else ''} | {'yes' if ok else '**no**'} |")
    print(f"\n{len(files) - failed} of {len(files)} files agree to {args.rtol:g}")
    return 0 if failed == 0 else 1


if __name__ == "__main__":
    sys.exit(main())
