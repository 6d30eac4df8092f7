"""The paper's study on the sphere in numbers (issue 40, docs/sphere.md): one row per case of the collected file of
`snakemake --cores 2 sphere` (results/<config>/sphere/cases.nc), from the slide's records: the contact area at the
preload A0, the peak Ft, the onset of full sliding (ubar, Ft, area), the area lost up to the onset, Ft / A and
Ft / (tau_DI A) at the slide's end, the extents' ratio x / y at the onset, how far the trailing (x_left) and the
leading (x_right) contact edges moved up to the onset, and Ft and the area at the slide's end over their onset
values. Forces in E L0^2, areas in L0^2, lengths in L0.

    .venv/bin/python benchmarks/sphere_study_table.py results/paper/sphere/cases.nc
"""

from __future__ import annotations

import argparse
import math

import numpy as np
import xarray as xr

from capslide.states import Phase


def rows(cases: xr.Dataset):
    tau = float(cases.attrs["friction_mu_DI"]) * float(cases.attrs["adhesion_T_max"]) / float(cases.attrs["material_E"])
    for model in cases.model.values:
        for preload in cases.preload.values:
            c = cases.sel(model=model, preload=preload)
            slide = np.flatnonzero(c.phase.values == Phase.SLIDE)
            if not len(slide):
                continue
            start = int(slide[0]) - 1
            ubar, Ft, area = (c[k].values for k in ("ubar", "Ft", "area"))
            onset = float(c.onset_ubar)
            k = int(slide[np.argmin(np.abs(ubar[slide] - onset))]) if math.isfinite(onset) else int(slide[-1])
            end = int(slide[-1])
            ratio = float((c.x_right[k] - c.x_left[k]) / c.width_y[k]) if "width_y" in c else math.nan
            yield {
                "model": str(model), "Fn": float(preload), "A0": area[start], "peak Ft": float(c.peak_Ft),
                "onset ubar": onset, "onset Ft": float(c.onset_Ft), "onset A": float(c.onset_area),
                "A lost": 1.0 - area[k] / area[start], "Ft/A end": Ft[end] / area[end],
                "Ft/(tau A) end": Ft[end] / (tau * area[end]), "x/y at onset": ratio,
                "trailing edge moved": float(c.x_left[k] - c.x_left[start]),
                "leading edge moved": float(c.x_right[k] - c.x_right[start]),
                "Ft end / onset Ft": Ft[end] / float(c.onset_Ft) if math.isfinite(onset) else math.nan,
                "A end / onset A": area[end] / float(c.onset_area) if math.isfinite(onset) else math.nan,
                "ubar end": ubar[end],
            }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("cases", help="the collected file (capslide collect)")
    args = parser.parse_args()
    with xr.open_dataset(args.cases) as cases:
        table = list(rows(cases))
    keys = list(table[0])
    print("| " + " | ".join(keys) + " |")
    print("|---" * len(keys) + "|")
    for r in table:
        print("| " + " | ".join(v if isinstance(v, str) else f"{v:.4g}" for v in r.values()) + " |")


if __name__ == "__main__":
    main()
