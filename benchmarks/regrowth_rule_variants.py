"""Where variants of the slide's regrowth rule would have ended the experiment's cases, read from the case files.

The regrowth rule (``slide_rules.regrowth_check``, ``loading.readhesion_snap: end``) ends a slide at a snap-through
whose state re-adheres: the snap's area exceeds the last step's by more than 20 % (up to 477cd4a also only where
the last step's area fell). It judges snapped steps only and changes nothing before the end, so a variant that ends
a slide no later than the rule did ends it at a snapped step of the file (or at the file's last event) with the
same path before it: its peak is read off the file exactly. A variant that lets the file's last event pass would
go on past the file (not known here).

    .venv/bin/python benchmarks/regrowth_rule_variants.py results/paper/experiment3d/cases/*.nc

prints, per case and variant, where the slide ends, its peak Ft (mN) and stage travel (um) before the end, and the
share of A0 in contact at the last step kept.
"""

from __future__ import annotations

import argparse
import re
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "src"))

from capslide.io.reading import open_result  # noqa: E402
from capslide.states import Phase  # noqa: E402
from capslide.studies.experiment_3d import features  # noqa: E402

# name -> rule(growth, last_change, area_before / A0): growth = A_snap / A_last - 1; last_change = A_last / A_before - 1
VARIANTS = {
    "up to 477cd4a: last step fell, > 20 %": lambda g, d, share: d < 0.0 and g > 0.20,
    "the scene's: any snap > 20 %": lambda g, d, share: g > 0.20,
    "any snap > 10 %": lambda g, d, share: g > 0.10,
    "any snap > 5 %": lambda g, d, share: g > 0.05,
    "last step fell, > 20 %, from below half of A0": lambda g, d, share: d < 0.0 and g > 0.20 and share < 0.5,
}
LAST_EVENT = re.compile(r"its area (fell to|was) ([0-9.e+]+); .* at ([0-9.e+]+)\)")


def snap_events(path: Path) -> tuple[list[dict], dict | None, float]:
    """The snapped slide steps of a case file (index within the slide, growth and last step's change of the area),
    the event that ended it when the regrowth rule did (its snap's state is not in the file), and the area the
    slide started from (L0^2)."""
    ds = open_result(path, "case")
    phase = ds["phase"].values
    slide, pre = np.flatnonzero(phase == Phase.SLIDE), np.flatnonzero(phase == Phase.PRELOAD)
    A0 = float(ds["area"].values[int(pre[-1]) if len(pre) else 0])
    area, snapped = ds["area"].values[slide], ds["snapped"].values[slide].astype(bool)
    reason = str(ds.attrs.get("status_reason", ""))
    ds.close()
    events = [{"index": int(i), "growth": area[i] / area[i - 1] - 1.0, "last_change": area[i - 1] / area[i - 2] - 1.0,
               "before": float(area[i - 1])} for i in np.flatnonzero(snapped) if i >= 2]
    match = LAST_EVENT.search(reason)
    last = None
    if match:
        fell, before, readhered = match.group(1) == "fell to", float(match.group(2)), float(match.group(3))
        last = {"index": len(slide), "growth": readhered / before - 1.0, "last_change": -1.0 if fell else 0.0,
                "before": before}
    return events, last, A0


def variant_end(events: list[dict], last: dict | None, rule, A0_model: float) -> tuple[int | None, str]:
    """The slide index a variant ends at (the steps before it are kept), and how: a snap in the file, the file's
    own end, or past it (None)."""
    for e in events:
        if rule(e["growth"], e["last_change"], e["before"] / A0_model):
            return e["index"], f"snap +{100 * e['growth']:.1f} %"
    if last is None:
        return -1, "the file's end (no regrowth)"
    if rule(last["growth"], last["last_change"], last["before"] / A0_model):
        return last["index"], f"the file's end (+{100 * last['growth']:.1f} %)"
    return None, "past the file"


def rows(path: Path) -> list[list[str]]:
    c = features(path)
    events, last, A0_model = snap_events(path)
    out = []
    for name, rule in VARIANTS.items():
        end, how = variant_end(events, last, rule, A0_model)
        if end is None:
            out.append([c["case"], name, how, "", "", ""])
            continue
        kept = slice(0, len(c["Ft"]) if end == -1 else end)
        Ft, ubar, area = c["Ft"][kept], c["ubar"][kept], c["area"][kept]
        k = int(np.argmax(np.abs(Ft)))
        out.append([c["case"], name, f"{ubar[-1]:.2f} um, {how}", f"{abs(Ft[k]):.2f} at {ubar[k]:.2f}",
                    f"{100 * area[k] / c['A0']:.0f} %", f"{100 * area[-1] / c['A0']:.0f} %"])
    return out


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("cases", nargs="+", type=Path)
    args = parser.parse_args(argv)
    print("| case | variant | ends at | peak Ft (mN) at ubar (um) | A / A0 at the peak | A / A0 at the end |")
    print("|---|---|---|---|---|---|")
    for path in args.cases:
        for row in rows(path):
            print("| " + " | ".join(row) + " |")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
