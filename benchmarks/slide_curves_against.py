"""Ft and the contact area of experiment cases along their slides, against the first file's, at given stage
travels (a mesh or lambda check of one case): each curve interpolated linearly between its slide steps, in mN, mm^2
and um (capslide.studies.experiment_3d.features). A travel past a file's last step is left blank. Then each file's
peak and how its slide ended. With ``--halvings`` the files are one case at successively halved steps (the
coarsest first), and a second table gives, per travel, each halving's change in Ft and A, the ratio of successive
changes, and the order it implies (log2 of the ratio: 1 for a first-order error, which halves with the step).

    .venv/bin/python benchmarks/slide_curves_against.py a019_ann4.nc a019_ann8.nc --ubar 5 10 20 30 34
    .venv/bin/python benchmarks/slide_curves_against.py --halvings --ubar 15 20 25 30 -- s1.nc s05.nc s025.nc
    .venv/bin/python benchmarks/slide_curves_against.py a010.nc --log a010_k8.log --ubar 5 10 15

``--log LOG`` adds a case still running (or stopped), read from its progress lines (``capslide run``'s ``slide``
lines, in E L0^2 and L0^2, converted with the first file's scales: the same scene); a step cut back and redone
keeps its last line.
"""

from __future__ import annotations

import argparse
import re
from pathlib import Path

import numpy as np

from capslide.io.reading import config_of
from capslide.studies.experiment_3d import features

PROGRESS = re.compile(r"^slide\s+ubar=\s*(\S+).*?\sFt=\s*(\S+)\s+area=\s*(\S+)")


def at(c: dict, key: str, ubar: float) -> float:
    """``c[key]`` at the travel ``ubar`` (um), linearly between steps; NaN past the last step."""
    u = c["ubar"]
    return float(np.interp(ubar, u, c[key])) if len(u) and ubar <= u[-1] + 1e-9 else float("nan")


def progress_case(log: Path, like: str) -> dict:
    """The slide steps of a case from its progress lines, in the units of :func:`features` (um, mN, mm^2), with the
    scales of the case file ``like``; a travel met again (a resumed run redoing steps) keeps its last line."""
    config = config_of(like)
    L0, E = config["geometry"]["L0"], config["material"]["E"]
    steps = {}
    for line in Path(log).read_text(errors="replace").splitlines():
        match = PROGRESS.match(line)
        if match:
            ubar, Ft, area = map(float, match.groups())
            steps[ubar] = (Ft, area)
    ubar = np.array(sorted(steps))
    Ft, area = (np.array([steps[u][j] for u in ubar]) for j in (0, 1))
    return {"case": Path(log).stem, "ubar": ubar * L0 * 1e6, "Ft": Ft * E * L0**2 * 1e3, "area": area * L0**2 * 1e6}


def cell(value: float, fmt: str) -> str:
    return "" if np.isnan(value) else fmt.format(value)


def table(cases: list[dict], travels) -> list[str]:
    """Markdown rows: ubar, then per file Ft and A, and for the others their difference from the first (%)."""
    head, rule = ["ubar (um)"], ["---"]
    for i, c in enumerate(cases):
        head += [f"Ft {c['case']}", f"A {c['case']}"] + ([] if i == 0 else ["Ft against first", "A against first"])
    rows = ["| " + " | ".join(head) + " |", "|" + "|".join(rule * len(head)) + "|"]
    for u in travels:
        ref = (at(cases[0], "Ft", u), at(cases[0], "area", u))
        cells = [f"{u:g}"]
        for i, c in enumerate(cases):
            Ft, A = at(c, "Ft", u), at(c, "area", u)
            cells += [cell(Ft, "{:.2f}"), cell(A, "{:.4f}")]
            if i:
                cells += [cell(100 * (Ft / ref[0] - 1), "{:+.1f} %"), cell(100 * (A / ref[1] - 1), "{:+.1f} %")]
        rows.append("| " + " | ".join(cells) + " |")
    return rows


def halving_orders(values) -> tuple[list[float], list[float], list[float]]:
    """The changes between successive values (a case at halved steps, the coarsest first), the ratios of successive
    changes, and the orders they imply (log2 of the ratio; NaN where the changes differ in sign or vanish)."""
    v = np.asarray(values, dtype=float)
    changes = np.diff(v)
    with np.errstate(divide="ignore", invalid="ignore"):
        ratios = changes[:-1] / changes[1:]
        orders = np.where(ratios > 0, np.log2(np.where(ratios > 0, ratios, 1.0)), np.nan)
    return changes.tolist(), ratios.tolist(), orders.tolist()


def halving_table(cases: list[dict], travels) -> list[str]:
    """Markdown rows: per travel and quantity, each halving's change, their ratios and orders."""
    rows = ["| ubar (um) | quantity | values | changes per halving | ratios of successive changes | orders |",
            "|---|---|---|---|---|---|"]
    for u in travels:
        for key, fmt in (("Ft", "{:.2f}"), ("area", "{:.4f}")):
            values = [at(c, key, u) for c in cases]
            changes, ratios, orders = halving_orders(values)
            join = lambda xs, f: ", ".join(cell(x, f) or "-" for x in xs)  # noqa: E731
            rows.append(f"| {u:g} | {key} | {join(values, fmt)} | {join(changes, '{:+.4f}')} | "
                        f"{join(ratios, '{:.2f}')} | {join(orders, '{:.2f}')} |")
    return rows


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("files", nargs="+", help="case files (.nc) of one case; the first is the reference")
    ap.add_argument("--ubar", type=float, nargs="+", default=[5, 10, 15, 20, 25, 30], help="stage travels (um)")
    ap.add_argument("--halvings", action="store_true", help="the files are one case at halved steps, coarsest first")
    ap.add_argument("--log", type=Path, nargs="*", default=[], help="progress logs of running cases (capslide run)")
    args = ap.parse_args(argv)
    cases = [features(f) for f in args.files]
    running = [progress_case(log, args.files[0]) for log in args.log]
    cases += running
    print("\n".join(table(cases, args.ubar)))
    print()
    if args.halvings:
        print("\n".join(halving_table(cases, args.ubar)))
        print()
    for c in running:
        k = int(np.argmax(np.abs(c["Ft"])))
        print(f"{c['case']} (progress lines): largest Ft so far {abs(c['Ft'][k]):.2f} mN at {c['ubar'][k]:.2f} um, "
              f"last step at {c['ubar'][-1]:.2f} um")
    for c in cases[:len(cases) - len(running)]:
        print(f"{c['case']}: A0 {c['A0']:.4f} mm2, Fn0 {c['Fn0']:+.4f} mN, peak Ft {c['peak_Ft']:.2f} mN at "
              f"{c['travel_to_peak']:.2f} um (area lost {c['area_loss_pct']:.0f} %), {c['outcome']} at "
              f"{c['ubar_end']:.2f} um with {c['area_end_pct']:.0f} % of A0")


if __name__ == "__main__":
    main()
