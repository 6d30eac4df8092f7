"""Where an experiment case's time goes (issue 40, docs/experiment3d.md): from each case file, its run time
(`case_wall_time`, s, the normal state it started from included), the time of its converged preload and slide
steps (each step's `wall_time`), and the rest: the attempts that failed and were cut back, and the run's overhead.
Then the converged slide steps that Newton reached (not a snap-through's continuation) in at least --hard
iterations, and their time: what a Newton that gave up at fewer iterations than its 30 would turn into failed
attempts.

    .venv/bin/python benchmarks/case_time_split.py results/paper/experiment3d/cases/*.nc --hard 25
"""

from __future__ import annotations

import argparse

import numpy as np

from capslide.io.reading import open_result
from capslide.states import Phase

HEAD = ["case", "run time (s)", "converged preload (s)", "converged slide (s)", "rest (s)", "slide steps",
        "snapped", "Newton's steps at >= HARD iterations", "their time (s)", "their share of converged slide",
        "most iterations"]


def split(path: str, hard: int) -> list[str]:
    """One table row of the case file at ``path``."""
    with open_result(path, "case") as ds:
        phase, its, wall = ds["phase"].values, ds["newton_iterations"].values, ds["wall_time"].values
        snapped, total = ds["snapped"].values.astype(bool), float(ds.attrs["case_wall_time"])
    slide, pre = phase == Phase.SLIDE, phase == Phase.PRELOAD
    slow = slide & ~snapped & (its >= hard)
    share = wall[slow].sum() / wall[slide].sum() if slide.any() else float("nan")
    return [path.rsplit("/", 1)[-1], f"{total:,.0f}", f"{wall[pre].sum():,.0f}", f"{wall[slide].sum():,.0f}",
            f"{total - wall.sum():,.0f}", str(int(slide.sum())), str(int((slide & snapped).sum())),
            str(int(slow.sum())), f"{wall[slow].sum():,.0f}",
            f"{100 * share:.0f} %", str(int(its[slide].max())) if slide.any() else ""]


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("files", nargs="+", metavar="CASE.nc")
    ap.add_argument("--hard", type=int, default=25, help="Newton iterations that count a converged step as hard")
    args = ap.parse_args(argv)
    head = [h.replace("HARD", str(args.hard)) for h in HEAD]
    print("| " + " | ".join(head) + " |")
    print("|" + "---|" * len(head))
    for path in args.files:
        print("| " + " | ".join(split(path, args.hard)) + " |")
    its = np.concatenate([_slide_iterations(p) for p in args.files])
    edges = [1, 10, 20, args.hard, its.max(initial=0) + 1]
    counts = [f"{lo} to {hi - 1}: {int(((its >= lo) & (its < hi)).sum())}"
              for lo, hi in zip(edges, edges[1:]) if hi > lo]
    print(f"\nNewton's converged slide steps of all files by their iterations: {'; '.join(counts)}")


def _slide_iterations(path: str) -> np.ndarray:
    with open_result(path, "case") as ds:
        newton = (ds["phase"].values == Phase.SLIDE) & ~ds["snapped"].values.astype(bool)
        return ds["newton_iterations"].values[newton].astype(int)


if __name__ == "__main__":
    main()
