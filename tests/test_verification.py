"""Verification: how errors are scaled, the figure drawn from the CSV tables, the edge-controlled JKR sweep."""

import csv
import math
from types import SimpleNamespace

import pytest

from capslide import figures
from capslide.config import load_config
from capslide.laws import analytic
from capslide.loadpath.cap import load_path
from capslide.loadpath.continuation import drain
from capslide.model.build import build_model
from capslide.params import Parameters
from capslide.states import Phase, Status
from capslide.studies import verification
from capslide.studies.verification import VerificationRow, edge_controlled_sweep, read_tables, sweep

from conftest import ROOT

R, E_STAR, W = 200.0, 1.0 / 0.84, 0.013478


def test_half_width_error_is_relative_to_the_closed_form():
    row = VerificationRow("jkr", "half_width", 0.0, 16.0, 16.5)
    assert row.rel_error == pytest.approx(-0.5 / 16.5)


def test_load_error_near_zero_load_is_relative_to_the_pull_off_load():
    """At P = 0 the JKR load at the FE half-width is small; the error is scaled by |P_c| instead."""
    P_c = analytic.jkr_cylinder_pull_off(R, E_STAR, W)
    a0 = analytic.jkr_cylinder_half_width(0.0, R, E_STAR, W)
    P_a = float(analytic.jkr_cylinder_load(0.97 * a0, R, E_STAR, W))
    row = VerificationRow("jkr", "load_at_half_width", 0.0, 0.0, P_a, {"relative_to": max(abs(P_a), abs(P_c))})
    assert abs(P_a) < abs(P_c)
    assert row.rel_error == pytest.approx(-P_a / abs(P_c))
    # P = c1 a^2 - c2 sqrt(a) with c1 a0^2 = c2 sqrt(a0) and a_c = 4^(-2/3) a0: 3 % short of a0 is 9.3 % of |P_c|
    expected = (0.97**0.5 - 0.97**2) / (4 ** (-1 / 3) - 4 ** (-4 / 3))
    assert row.rel_error == pytest.approx(expected, rel=1e-9)
    assert 0.09 < expected < 0.095


def test_pressure_row_without_scale_is_nan():
    assert math.isnan(VerificationRow("hertz", "pressure_L2", 0.3, 0.02, 0.0).rel_error)


def test_verification_figure_from_tables(tmp_path):
    P_c = analytic.jkr_cylinder_pull_off(R, E_STAR, W)
    rows = []
    for P in (0.3, 0.0, -0.3):
        a = analytic.jkr_cylinder_half_width(P, R, E_STAR, W)
        rows.append(["jkr", "half_width", P, 0.98 * a, a, -0.02, f"R={R};E_star={E_STAR};w={W}"])
        rows.append(["jkr", "load_at_half_width", P, P, float(analytic.jkr_cylinder_load(0.98 * a, R, E_STAR, W)), 0.05, ""])
        h = float(analytic.hertz_line_half_width(P + 0.5, R, E_STAR))
        rows.append(["hertz", "half_width", P + 0.5, 0.99 * h, h, -0.01, ""])
        rows.append(["hertz", "pressure_L2", P + 0.5, 0.02 + 0.01 * P, 0.0, "nan", ""])
    rows.append(["jkr", "pull_off", P_c, P_c * 1.003, P_c, -0.003, "status=diverged"])
    table = tmp_path / "v.csv"
    with open(table, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["scene", "quantity", "load_P", "fe", "theory", "rel_error", "extra"])
        w.writerows(rows)
    with figures.journal_style():
        fig = figures.TABLE_FIGURES["verification"](read_tables([table]))
    titles = [ax.get_title() for ax in fig.axes]
    assert "a 1.00%" in titles[0] and "p(x) 2.30%" in titles[0] and "P(a)" not in titles[0]
    assert "a 2.00%" in titles[1] and "P(a) 5.00%" in titles[1]
    out = [tmp_path / "v.pdf", tmp_path / "v.png"]
    figures.save(fig, out)
    assert all(p.stat().st_size > 5000 for p in out)


# A small, stiff JKR scene: T_max 4x the paper's (interaction range r0 = 0.033 L0), R = 20 L0, Maugis parameter 14;
# Q1, not the scene file's Q2: these tests are about the load path, and Q1 is the cheaper element.
STIFF_SCENE = ["geometry.R=20", "geometry.H=15", "mesh.band_half_width=6", "mesh.element=Q1", "mesh.size=4",
               "adhesion.T_max=1.32e6", "loading.approach_end_gap_over_g_eq=1.2", "loading.approach_edge_step=0.15"]


def _stiff_scene(loads, overrides=()):
    cfg = load_config([ROOT / "config" / "config.yaml", ROOT / "config" / "scenes" / "jkr.yaml"],
                      [*STIFF_SCENE, f"verification.loads={list(loads)}", *overrides])
    return Parameters.from_config(cfg)


@pytest.mark.slow
def test_stiff_law_apex_control_alone_stops_at_the_snap_in():
    """The case for edge control: with the apex gap as the only load parameter the approach of the stiff scene
    stops where the contact snaps in, within 2 % of g_eq (the apex gap turns there; g_max = 1.2 g_eq). About 50 s."""
    p = _stiff_scene([0.0], ["loading.approach_edge_step=0", "loading.approach_end_gap_over_g_eq=1.0"])
    end = drain(load_path(build_model(p), stop_before="preload"))
    assert end.status == Status.DIVERGED and end.reason.startswith("approach: step below minimum")
    stopped_at = float(end.reason.split(" at ")[1].split()[0])
    assert p.adhesion.g_eq < stopped_at < 1.02 * p.adhesion.g_eq


def test_edge_controlled_sweep_of_a_stiff_law():
    """Through the snap-in and the pull-off point to the loads: exact equilibria at the loads, force balance at
    every step, and the issue's JKR criteria (zero-load half-width within 3 %, pull-off within 5 %)."""
    loads = [0.0, -0.2]
    p = _stiff_scene(loads)
    model = build_model(p)
    records = []
    states, F_max, _ = edge_controlled_sweep(model, loads, records, None)
    E_star = analytic.effective_modulus(p.material.E, p.material.nu)
    w = p.adhesion.W_adh
    for P in loads:
        assert states[P].phase == Phase.PRELOAD and states[P].Fn == pytest.approx(-P, abs=1e-9)
    edge_path = [r for r in records if r.phase == Phase.SPREAD]
    i_peak = max(range(len(edge_path)), key=lambda i: edge_path[i].Fn)
    assert edge_path[i_peak].Fn == F_max and 0 < i_peak < len(edge_path) - 3  # through the pull-off point
    assert states[-0.2].area > edge_path[i_peak].area  # the tensile load on the stable branch
    assert states[0.0].area > states[-0.2].area
    for rec in records:
        assert rec.Fn + rec.reaction[1] == pytest.approx(0.0, abs=1e-8), rec.phase
    a0 = analytic.jkr_cylinder_half_width(0.0, p.geometry.R, E_star, w)
    assert 0.5 * states[0.0].area == pytest.approx(a0, rel=0.03)
    P_c = analytic.jkr_cylinder_pull_off(p.geometry.R, E_star, w)
    assert -F_max == pytest.approx(P_c, rel=0.05)


def _stop_index(path_P: list[float], P: float) -> int | None:
    """Where a load leg's ends(rec) stops a path of loads P = -Fn, called as a leg calls it: before the record is
    appended."""
    forces: list[float] = []
    ends = verification._stop_past_load(lambda: list(forces), P)
    for i, p in enumerate(path_P):
        rec = SimpleNamespace(Fn=-p)
        if ends(rec) is not None:
            return i
        forces.append(rec.Fn)
    return None


def test_a_load_leg_stops_where_the_path_crosses_the_load_even_on_a_jagged_path():
    """The R = 1000 L0 Dugdale sweep's path after its load 0 (P = -Fn per step, E L0^2): the load +20 is crossed
    between the states at 18.10 and 27.08, three steps after one where the load fell (8.92 to 8.64). The leg stops
    there, so that those two states bracket it, and as early after a fall (a shortened path); it does not stop on a
    jag of the unstable branch, before the path has been past its peak (the load rising at three steps in a row)."""
    pull_off = [-30.0, -45.0, -42.0, -55.0, -64.0, -63.0, -60.0, -50.0, -20.0]  # a jag at -45 to -42
    after_zero = [4.33, 5.31, 5.67, 8.92, 8.64, 12.94, 18.10, 27.08, 39.02]
    path = pull_off + after_zero
    assert _stop_index(path, 20.0) == path.index(27.08)  # the state after 18.10
    shortened = pull_off + [4.33, 8.92, 8.64, 12.94, 27.08, 39.02]
    assert _stop_index(shortened, 20.0) == shortened.index(27.08)  # the state after 12.94
    assert _stop_index(path, -44.0) == path.index(-20.0)  # not the jag -45 to -42, before the peak
    assert _stop_index(path, -55.0) == path.index(-50.0)  # -60 to -50, on the stable branch
    assert _stop_index(path, 50.0) is None


@pytest.mark.slow
def test_an_edge_controlled_sweep_resumes_from_its_checkpoint_bit_for_bit(tmp_path):
    """capslide verify --resume: a sweep saves after its approach, after each load and every
    verification.checkpoint_every converged steps inside a leg. Stopped at a save inside the second load's leg (the
    first load done), it continues from the file to the uninterrupted table exactly; a checkpoint of another
    configuration is refused."""
    from capslide.io.checkpoint import CheckpointError, config_text
    from capslide.io.sweep_checkpoint import load_sweep, save_sweep

    p = _stiff_scene([0.0, -0.2], ["verification.checkpoint_every=2"])
    text, path = config_text(p.config), tmp_path / ".t.csv.checkpoint.npz"
    whole = sweep(p, "jkr")

    class Stop(Exception):
        pass

    saves = []

    def save_then_stop(saved):
        save_sweep(path, text, saved)
        saves.append((saved.loop is not None, list(saved.done)))
        if saved.loop is not None and saved.done:
            raise Stop

    with pytest.raises(Stop):
        sweep(p, "jkr", save=save_then_stop)
    assert saves[0] == (False, []) and (True, []) in saves and (False, [-0.2]) in saves  # approach, leg, load
    saved = load_sweep(path, text)
    assert list(saved.done) == [-0.2] and saved.loop.value == saved.X and saved.loop.x_prev is not None
    assert len(saved.records) > saved.done[-0.2] + 1
    resumed = sweep(p, "jkr", saved=saved)
    assert [(r.quantity, r.load, r.fe, r.theory) for r in resumed] == [(r.quantity, r.load, r.fe, r.theory) for r in whole]
    with pytest.raises(CheckpointError, match="another configuration"):
        load_sweep(path, config_text(_stiff_scene([0.0]).config))


def test_hertz_scene_on_a_coarse_mesh():
    """The Hertz scene (Q2) at one load on a mesh 2x coarser than the scene's, against sqrt(4 P R / (pi E*)) and
    the Hertz ellipse. The issue asks for 2 % (half-width) and 5 % (pressure, L2 of p0); this mesh gives 0.04 % and
    0.4 %, so 0.5 % and 1 % are asserted: Q1 on the same mesh (-1.3 %, 1.7 %) fails them. About 8 s."""
    cfg = load_config([ROOT / "config" / "scenes" / "hertz.yaml"], ["mesh.size=40", "verification.loads=[0.3]"])
    rows = {r.quantity: r for r in sweep(Parameters.from_config(cfg), "hertz")}
    assert rows["half_width"].theory == pytest.approx(8.0107, rel=1e-4)  # a/R = 0.04
    assert abs(rows["half_width"].rel_error) < 0.005
    # the surface points in contact moved towards the axis (the Hertz tangential displacement): their reference
    # span is longer, +0.52 % against the closed form here (issue's 2 %); 1 % asserted
    assert rows["half_width_reference"].fe > rows["half_width"].fe
    assert abs(rows["half_width_reference"].rel_error) < 0.01
    assert 0.0 < rows["pressure_L2"].fe < 0.01
