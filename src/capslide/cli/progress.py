"""Progress of a running case: a one-line bar on a terminal (tqdm), a widget in a notebook (tqdm.auto), one log
line per step elsewhere.

The bar fits 80 columns and shows the phase, the load (ubar, or Fn in the preload), the percent of the planned path,
the steps, the last step's Newton iterations, the elapsed time and an estimate of the time left. The planned path is
the path's own (:func:`capslide.loadpath.cap.plan`): its legs weighted by their usual share of the steps. Notices
(building the mesh, cut-backs) show in the bar's last field, or as log lines.
"""

from __future__ import annotations

import shutil
import sys

from ..driver.observers import Observer
from ..loadpath.legs import LegName, plan

__all__ = ["ProgressDisplay", "path_fraction", "in_notebook", "log_line"]

WIDTH = 80


def path_fraction(step, loading, leg_start: float | None) -> float:
    """Fraction of the planned path (0 to 1) reached at a path step, on the spans of the path's own plan
    (:func:`capslide.loadpath.cap.plan`); ``leg_start`` is the load parameter where the running preload target's leg
    started."""
    state, rec = step.state, step.record
    spans = plan(loading)
    lo, hi = spans.get(state.leg, (1.0, 1.0))
    if state.loop is None:  # the step finished a leg: the path stands at the start of the next one
        return lo
    value = state.loop.value
    if state.leg == LegName.APPROACH:
        inner = (loading.approach_start_gap - value) / (loading.approach_start_gap - loading.approach_end_gap)
    elif state.leg == LegName.PRELOAD and state.targets:
        span = abs(state.targets[0] - (leg_start if leg_start is not None else value)) or 1.0
        done = 1.0 - abs(state.targets[0] - value) / span
        inner = done / len(state.targets) if len(state.targets) > 1 else done
    elif state.leg in (LegName.SLIDE, LegName.SLIDE_BACK) and loading.ubar_max:
        inner = rec.ubar / loading.ubar_max if state.leg == LegName.SLIDE else 1.0 - rec.ubar / loading.ubar_max
    elif state.leg == LegName.DWELL and loading.dwell:
        inner = value / loading.dwell
    else:
        inner = 0.5
    return lo + (hi - lo) * min(max(inner, 0.0), 1.0)


def log_line(rec) -> str:
    """One step record as a log line (the step's own wall time at its end)."""
    return (f"{rec.phase.label:8s} ubar={rec.ubar:7.4f} h={rec.h:9.5f} Fn={rec.Fn:+.5f} Ft={rec.Ft:+.5f} "
            f"area={rec.area:8.4f} stick={rec.area_stick:8.4f} newton={rec.newton_iterations:2d} "
            f"krylov={rec.krylov_iterations:4d} t={rec.wall_time:6.2f}s\n")


def in_notebook() -> bool:
    """Whether this runs in a Jupyter kernel (an IPython shell that talks over ZMQ)."""
    shell = sys.modules.get("IPython")
    try:
        return shell is not None and type(shell.get_ipython()).__name__ == "ZMQInteractiveShell"
    except AttributeError:
        return False


class ProgressDisplay(Observer):
    """Shows a running case: a bar on a terminal, log lines elsewhere (``stream``: standard error by default).

    ``loading`` (:class:`capslide.params.Loading`) lets the bar show the percent of the planned path.
    """

    def __init__(self, loading=None, stream=None):
        self.loading, self.stream = loading, stream or sys.stderr
        self.steps, self._leg, self._leg_start, self._last_Fn = 0, None, None, None
        self.bar = None
        if in_notebook() and stream is None:  # a widget in Jupyter (tqdm.auto), not one text line per step
            from tqdm.auto import tqdm

            self.bar = tqdm(total=100, leave=True, mininterval=0.2)
        elif self.stream.isatty():
            from tqdm import tqdm

            width = min(shutil.get_terminal_size((WIDTH, 24)).columns, WIDTH)
            self.bar = tqdm(total=100, file=self.stream, ncols=width, leave=True, mininterval=0.2,
                            bar_format="{desc} {percentage:3.0f}%|{bar}| {elapsed}<{remaining}")

    def __call__(self, rec, percent: float | None = None) -> None:
        """Show one step record."""
        self.steps += 1
        if self.bar is None:
            self.stream.write(log_line(rec))
            self.stream.flush()
            return
        load = {"slide": f"ubar {rec.ubar:5.3f}", "dwell": f"t {rec.time:.3g} s"}.get(rec.phase.label, f"Fn {rec.Fn:+.3f}")
        self.bar.set_description_str(f"{rec.phase.label:<8} {load:<11} step {self.steps:<4} N{rec.newton_iterations:<2}",
                                     refresh=False)
        if percent is not None:
            self.bar.n = percent
        self.bar.refresh()

    def replay(self, records) -> None:
        """Show the steps a resumed run takes over from its checkpoint: their log lines once more, as the
        interrupted run wrote them (Snakemake empties a job's log before a rerun), or their count on a bar."""
        if self.bar is None:
            self.stream.write("".join(log_line(rec) for rec in records))
            self.stream.flush()
        self.steps += len(records)

    def step(self, step):
        state = step.state
        leg = (state.leg, len(state.targets))
        if leg != self._leg:  # a leg (or preload target) starts: remember the force it starts from
            self._leg, self._leg_start = leg, self._last_Fn
        self._last_Fn = step.record.Fn
        percent = None if self.loading is None else round(100 * path_fraction(step, self.loading, self._leg_start), 1)
        self(step.record, percent)

    def notice(self, notice):
        if self.bar is None:
            self.stream.write(f"capslide: {notice.text}\n")
            self.stream.flush()
        else:
            self.bar.set_description_str(f"{notice.text[:40]:<40}", refresh=True)

    def close(self) -> None:
        if self.bar is not None:
            self.bar.close()
