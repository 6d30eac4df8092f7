"""The progress of a running case: one 80-column line on a terminal, one log line per step elsewhere."""

import fcntl
import os
import re
import select
import struct
import subprocess
import sys
import termios

import pytest

from conftest import PAPER_CONFIG

RUN = [sys.executable, "-m", "capslide", "run", str(PAPER_CONFIG), "--set", "preset=fast", "--set", "mesh.size=32",
       "--set", "loading.ubar_max=0.6", "--set", "output.checkpoint_every=0", "--set", "output.snapshot_ubar=[]"]


def _in_a_terminal(cmd, columns=80):
    """Run ``cmd`` with a pseudo-terminal of ``columns`` columns as its terminal; (exit code, what it showed)."""
    master, slave = os.openpty()
    fcntl.ioctl(slave, termios.TIOCSWINSZ, struct.pack("HHHH", 24, columns, 0, 0))
    proc = subprocess.Popen(cmd, stdin=slave, stdout=slave, stderr=slave)
    os.close(slave)
    out = b""
    while True:
        ready, _, _ = select.select([master], [], [], 0.5)
        if ready:
            try:
                chunk = os.read(master, 65536)
            except OSError:  # the terminal closed with the process
                break
            if not chunk:
                break
            out += chunk
        elif proc.poll() is not None:
            break
    os.close(master)
    return proc.wait(), out.decode(errors="replace")


def test_the_bar_fits_80_columns_and_stays_on_one_line(tmp_path):
    code, shown = _in_a_terminal([*RUN, "-o", str(tmp_path / "case.nc")])
    assert code == 0, shown
    bar, summary = shown.rsplit("\n", 2)[0], shown.rsplit("\n", 2)[1]
    assert "\n" not in bar.strip("\n") and summary.startswith(str(tmp_path / "case.nc"))  # redrawn in place
    frames = [re.sub(r"\x1b\[[0-9;]*[A-Za-z]", "", f) for f in re.split(r"\r", bar) if f.strip()]
    assert len(frames) > 10 and max(map(len, frames)) <= 80
    assert any(f.startswith("building the mesh") for f in frames)
    assert any(f.startswith("approach") for f in frames) and any(f.startswith("preload") for f in frames)
    last = frames[-1]
    assert last.startswith("slide    ubar 0.600") and "100%|" in last and re.search(r"\d\d:\d\d<\d\d:\d\d$", last)


def test_without_a_terminal_one_line_per_step_and_the_cut_backs(tmp_path):
    res = subprocess.run([*RUN, "--set", "loading.slide_step=0.2", "--set", "loading.max_slide_step=1.0",
                          "--set", "loading.ubar_max=2.5", "-o", str(tmp_path / "case.nc")], capture_output=True, text=True)
    assert res.returncode == 0, res.stderr
    lines = res.stderr.splitlines()
    steps = [ln for ln in lines if ln.split()[0] in ("approach", "preload", "slide")]
    notices = [ln for ln in lines if ln.startswith("capslide: ")]
    assert "\r" not in res.stderr and len(steps) > 20
    assert re.match(r"capslide: building the mesh: [0-9,]+ Q1 cells, [0-9,]+ DOF$", notices[0]), notices[0]
    assert any(": cut-back 1 at " in n for n in notices), notices  # the onset check cuts back the step that
    # would close the stick zone (slide_rules.onset_check), at ubar = 2, and the notice says so
    assert any(re.search(r": cut-back 1 at .*\(the stick zone closed within a step of [0-9.e-]+\)$", n) for n in notices), notices


def test_the_plan_is_the_paths_own_legs():
    """The progress display's plan comes from the path: the legs a loading runs, spans that tile [0, 1]."""
    from types import SimpleNamespace

    from capslide.loadpath.legs import LegName, plan

    def loading(**kw):
        return SimpleNamespace(**{"approach_edge_step": 0.0, "dwell": 0.0, "ubar_max": 5.0, "slide_back": False, **kw})

    spans = plan(loading())
    assert list(spans) == [LegName.APPROACH, LegName.PRELOAD, LegName.SLIDE, LegName.DONE]
    assert spans[LegName.APPROACH][0] == 0.0 and spans[LegName.SLIDE][1] == 1.0
    back = plan(loading(dwell=2.0, slide_back=True, approach_edge_step=0.4))
    assert list(back) == [LegName.APPROACH, LegName.SPREAD, LegName.PRELOAD, LegName.DWELL, LegName.SLIDE,
                          LegName.SLIDE_BACK, LegName.DONE]
    ends = [hi for lo, hi in back.values()]
    assert all(a == pytest.approx(b[0]) for a, b in zip(ends[:-2], list(back.values())[1:-1]))  # contiguous
    assert back[LegName.SLIDE][1] - back[LegName.SLIDE][0] == pytest.approx(back[LegName.SLIDE_BACK][1]
                                                                           - back[LegName.SLIDE_BACK][0])
    assert list(plan(loading(ubar_max=0.0))) == [LegName.APPROACH, LegName.PRELOAD, LegName.DONE]
    assert LegName.SLIDE == "slide"  # saved states keep the text
