"""Sliding under a fixed normal force: full-sliding forces, uniform block, mirror symmetry."""

import numpy as np
import pytest

from capslide.config import apply_overrides, validate
from capslide.driver.case import run_case
from capslide.fem.mesh import rectangle_mesh
from capslide.laws import contact
from capslide.params import Parameters
from capslide.states import Phase, SlipState, Status

COARSE = ["preset=fast", "mesh.size=32", "loading.ubar_max=2.6", "loading.max_slide_step=0.2", "output.snapshot_ubar=[]"]


def params_with(paper_config, *overrides):
    return Parameters.from_config(validate(apply_overrides(paper_config, [*COARSE, *overrides])))


def surface_integral(p, mesh, x, fn):
    """Integral over the reference surface of fn(gap, J_s, Tn) at the state x, with the case's quadrature."""
    from capslide.fem.interface import SurfaceContact

    c = SurfaceContact(mesh, p.adhesion, p.mesh.surface_gauss_points, far_gap=p.contact.far_gap)
    u, h = x[:-1], x[-1]
    xs, t = c.quad.current(u)
    g = h - xs[..., 1]
    J = np.linalg.norm(t, axis=-1) / c.ref_len
    Tn, _ = contact.normal_traction(g, p.adhesion.T0, p.adhesion.r0, p.adhesion.g_reg)
    Tn = np.where(g < p.contact.far_gap, Tn, 0.0)
    return float(np.sum(fn(g, J, Tn) * c.quad.weight))


@pytest.fixture(scope="module")
def di_case(paper_config):
    p = params_with(paper_config, "friction.model=DI")
    return p, run_case(p)


def test_di_full_sliding_force(di_case):
    p, res = di_case
    assert res.status == Status.COMPLETED, res.reason
    last = res.records[-1]
    assert np.all(last.slip_state != SlipState.STICK)
    f = p.friction
    Ft_theory = surface_integral(p, res.mesh, res.final_x,
                                 lambda g, J, Tn: J * contact.di_threshold(g, f.tau_DI, f.k_DI, f.g_cut_DI)[0])
    assert last.Ft == pytest.approx(Ft_theory, rel=1e-6)
    # DI: Ft = tau_DI x contact area, up to the logistic edge
    ratio = last.Ft / (f.tau_DI * last.area)
    print("DI Ft / (tau A) =", ratio)
    assert abs(ratio - 1.0) < 0.02
    # after the onset, force and area stay constant
    onset = res.scalars["onset_ubar"]
    after = [r for r in res.records if r.phase == Phase.SLIDE and r.ubar >= onset]
    assert len(after) >= 2
    assert np.ptp([r.Ft for r in after]) <= 0.01 * abs(last.Ft)
    assert np.ptp([r.area for r in after]) <= 0.01 * last.area


def test_ea_coulomb_full_sliding_force(paper_config):
    p = params_with(paper_config, "friction.model=EA", "friction.s_cut=0")
    res = run_case(p)
    assert res.status == Status.COMPLETED, res.reason
    last = res.records[-1]
    assert np.isfinite(res.scalars["onset_ubar"])
    Ft_theory = surface_integral(p, res.mesh, res.final_x, lambda g, J, Tn: p.friction.mu_EA * np.maximum(Tn, 0.0))
    assert last.Ft == pytest.approx(Ft_theory, rel=1e-6)


def test_mirror_symmetry(paper_config, di_case):
    p, res = di_case
    pm = params_with(paper_config, "friction.model=DI", "loading.ubar_max=-2.6")
    resm = run_case(pm)
    slide = [r for r in res.records if r.phase == Phase.SLIDE]
    slidem = [r for r in resm.records if r.phase == Phase.SLIDE]
    assert len(slide) == len(slidem)
    np.testing.assert_allclose([r.ubar for r in slidem], [-r.ubar for r in slide], atol=1e-12)
    scale = max(abs(r.Ft) for r in slide)
    np.testing.assert_allclose([r.Ft for r in slidem], [-r.Ft for r in slide], atol=1e-7 * scale)
    np.testing.assert_allclose([r.x_left for r in slidem], [-r.x_right for r in slide], atol=1e-7)


@pytest.mark.parametrize("model_name, s_cut", [("DI", 1.0), ("EA", 0.0), ("EA", 0.5), ("EA", 1.0)])
def test_flat_block_uniform_sliding(paper_config, model_name, s_cut):
    """A flat-topped block pressed and slid: at full sliding T_t equals the threshold at the computed gap. The
    approach ends at 0.98 g_eq, with the whole face in contact: at 1.0 g_eq the apex gap (a corner node's) left the
    face in contact over one element, and on some machines the preload's Newton run then found the detached branch
    (round-off chose it) and ended diverged."""
    p = params_with(paper_config, f"friction.model={model_name}", f"friction.s_cut={s_cut}", "loading.preload=-0.5",
                    "loading.ubar_max=2.0", "loading.approach_end_gap_over_g_eq=0.98")
    mesh = rectangle_mesh(20, 4, 10.0, 2.0, "Q1")
    res = run_case(p, mesh=mesh)
    assert res.status == Status.COMPLETED, res.reason
    last = res.records[-1]
    # the middle half of the face, away from the free edges of the block: a nearly uniform state
    inside = (np.abs(last.x_surface) < 2.5) & (last.gap < p.adhesion.g_max)
    assert inside.sum() > 30 and np.all(last.slip_state[inside] == SlipState.SLIP)
    g = last.gap[inside]
    f, a = p.friction, p.adhesion
    if model_name == "DI":
        from capslide.fem.interface import SurfaceContact

        c = SurfaceContact(mesh, a, p.mesh.surface_gauss_points, far_gap=p.contact.far_gap)
        _, t = c.quad.current(res.final_x[:-1])
        J = (np.linalg.norm(t, axis=-1) / c.ref_len).ravel()[inside]
        expected = J * contact.di_threshold(g, f.tau_DI, f.k_DI, f.g_cut_DI)[0]
    else:
        expected = contact.ea_threshold(g, f.mu_EA, f.g_cut_EA, a.T0, a.r0, a.g_reg)[0]
    np.testing.assert_allclose(last.traction_t[inside], expected, rtol=0, atol=1e-8)


@pytest.mark.slow
@pytest.mark.parametrize("overrides", [["friction.model=DI"],
                                       ["friction.model=EA", "friction.s_cut=0", "loading.preload=-0.288"]])
def test_step_and_penalty_sensitivity_below_one_percent(paper_config, overrides):
    base = params_with(paper_config, *overrides)
    L, f = base.loading, base.friction
    ref = run_case(base).scalars
    halved = run_case(params_with(paper_config, *overrides, f"loading.slide_step={L.slide_step / 2}",
                                  f"loading.max_slide_step={L.max_slide_step / 2}",
                                  f"loading.min_slide_step={L.min_slide_step / 2}")).scalars
    stiffer = run_case(params_with(paper_config, *overrides, f"friction.eps_t={2 * f.eps_t}")).scalars
    for other in (halved, stiffer):
        assert other["peak_Ft"] == pytest.approx(ref["peak_Ft"], rel=0.01)
        assert other["onset_ubar"] == pytest.approx(ref["onset_ubar"], rel=0.01)


def test_stiff_penalty_first_slide_step_converges_with_inexact_newton(paper_config):
    """EA at Fn* = -0.288 with eps_t doubled: its first slide step, where friction switches on against a stiff
    penalty, ran to 30 Newton iterations and the case diverged when the first linear solve of a Newton solve was
    loose (eta = 1e-2, issue 19); with the first solve exact it completes, and the onset is found."""
    res = run_case(params_with(paper_config, "friction.model=EA", "friction.s_cut=0", "loading.preload=-0.288",
                               f"friction.eps_t={2 * paper_config['friction']['eps_t']}"))
    assert res.status.label == "completed", res.reason
    assert np.isfinite(res.scalars["onset_ubar"])


def test_the_first_slide_step_starts_from_the_stick_solution(paper_config):
    """EA0 at Fn* = 0: at the preloaded state every tangential trial traction is 0 and the first slide step's
    trial traction (eps_t x 0.001 = 0.1 E) exceeds EA0's threshold on most of the contact, so Newton from the
    preloaded state landed near full sliding and the step was cut back twice (30 + 30 + 22 iterations, issue 19).
    Started from the solution with every point in stick (Leg.stick_first), the step converges at its first size in
    a few iterations, the predictor's counted."""
    p = params_with(paper_config, "friction.model=EA", "friction.s_cut=0", "loading.ubar_max=0.01")
    res = run_case(p)
    assert res.status.label == "completed", res.reason
    first = next(r for r in res.records if r.phase == Phase.SLIDE and r.ubar > 0.0)
    assert first.ubar == pytest.approx(p.loading.slide_step, rel=1e-12)
    assert first.newton_iterations <= 10


def test_the_stick_model_holds_every_point_and_leaves_the_model_alone(paper_config):
    """CapModel.sticking(): the same cap with Tt = the trial traction at every point however far it is beyond the
    threshold, no slip weakening, and a linear solver of its own; the model it came from is unchanged."""
    from capslide.laws.friction import Sticking
    from capslide.model.build import build_model

    model = build_model(params_with(paper_config, "friction.model=EA", "friction.s_cut=0",
                                    "friction.static_over_kinetic=1.5"))
    law, weakening, solver = model.contact.law, model.contact.weakening, model.solver
    stuck = model.sticking()
    assert isinstance(stuck.contact.law, Sticking) and stuck.contact.weakening is None
    assert stuck.solver is not solver and type(stuck.solver) is type(solver)
    assert (model.contact.law, model.contact.weakening, model.solver) == (law, weakening, solver)
    x = np.zeros(model.n_dofs + 1)
    x[-1] = model.mesh.nodes[model.apex_node, 1] + 0.5 * model.contact.contact_gap  # the apex in contact
    history = model.start_friction(x)
    ubar = 5.0  # the flat moved 5 L0 from the anchors: trial traction eps_t ubar at every point
    Tt, state = stuck.contact.tangential_state(x[:-1], x[-1], ubar, history.anchors, history.slip)
    _, own = model.contact.tangential_state(x[:-1], x[-1], ubar, history.anchors, history.slip)
    touching = state != SlipState.FREE
    assert touching.sum() > 10 and np.all(state[touching] == SlipState.STICK) and np.all(own[touching] == SlipState.SLIP)
    assert Tt[touching] == pytest.approx(model.contact.eps_t * ubar, rel=1e-12)


def test_force_balance_at_every_step(di_case):
    """The contact force on the cap equals minus the internal force at the clamped base, at every converged step."""
    p, res = di_case
    assert len(res.records) > 20
    for rec in res.records:
        assert rec.Fn + rec.reaction[1] == pytest.approx(0.0, abs=1e-8), rec.phase
        assert rec.Ft + rec.reaction[0] == pytest.approx(0.0, abs=1e-8), rec.phase


def test_onset_is_located_to_its_bracket(di_case):
    """The first fully sliding step lies within 1e-3 ubar (or two smallest steps) of the last step with a stick
    zone: a step that closes the stick zone from farther away is cut back (loadpath.slide_rules.onset_check)."""
    p, res = di_case
    slide = [r for r in res.records if r.phase == Phase.SLIDE]
    first = next(i for i, r in enumerate(slide) if r.ubar == res.scalars["onset_ubar"])
    assert slide[first - 1].area_stick > 0.0
    bracket = slide[first].ubar - slide[first - 1].ubar
    assert 0.0 < bracket <= max(1e-3 * slide[first].ubar, 2.0 * p.loading.min_slide_step)


def test_onset_search_bisects_below_the_ceiling():
    """Once a step to the ceiling was cut back for closing the stick zone, the next step is half of what is left,
    then one bracket (the longest closing step accepted) once two brackets or less are left, then the rest; in
    either slide direction. With the stick zone closed, or without a ceiling, the ceiling plays no part."""
    from capslide.loadpath.slide_rules import Mark, onset_step_limit

    def marks(sign, area_stick=0.5):
        return [Mark(Phase.SLIDE, sign * 1.8, 0.0, 1.0), Mark(Phase.SLIDE, sign * 2.0, 0.0, area_stick)]

    for sign in (1.0, -1.0):
        limit = lambda ubar, ceiling, stick=0.5: onset_step_limit(  # noqa: E731
            marks(sign, stick), sign * ubar, sign * ceiling, 0.002, sign)
        assert limit(2.0, 2.1) == pytest.approx(0.05)
        assert limit(2.0, 2.003) == pytest.approx(0.002)
        assert limit(2.0, 2.0015) == pytest.approx(0.0015)
        assert limit(2.0, 1.9) == pytest.approx(0.1)  # a ceiling behind: the stick area's extrapolation to 2.2, halved
        assert limit(2.0, 2.1, stick=0.0) == np.inf
        assert onset_step_limit(marks(sign), sign * 2.0, np.nan, 0.002, sign) == pytest.approx(0.1)


def test_a_jump_of_the_contact_area_is_cut_back():
    """A slide step whose contact area changes by more than 20 % is cut back (either way); one that
    changes it by 5 %, a step of another phase, or the first step of a leg is not. The case it was written for: the
    stability suite's tensile_90, whose Newton solve at ubar 0.7249 converged on another equilibrium (area 4.59 to
    6.72 L0) instead of ending the peeling contact as detached."""
    from types import SimpleNamespace

    from capslide.loadpath.slide_rules import Mark, jump_check

    state = SimpleNamespace(marks=[Mark(Phase.SLIDE, 0.7248, 0.354, 3.72, 0.4497, 4.59)])
    step = lambda area, phase=Phase.SLIDE: jump_check(state)(SimpleNamespace(phase=phase, area=area))  # noqa: E731
    assert "jumped from 4.59 to 6.72" in step(6.72)
    assert step(0.7 * 4.59) is not None and step(4.59 * 1.05) is None and step(4.59 * 0.95) is None
    assert step(6.72, Phase.PRELOAD) is None
    state.marks = [Mark(Phase.PRELOAD, 0.0, 0.354, 0.0, 0.0, 7.1)]
    assert step(4.59) is None and step(6.72, Phase.PRELOAD) is None


def test_a_jump_found_at_two_step_lengths_repeats():
    """AreaJump.repeats: the last two steps the rule rejected from the path's last mark found the same area, within a
    quarter of the jump (the experiment's snap at 34.6 um: 31,430 then 32,291 um^2 from 41,430). Not a change that
    halves with the step, not jumps either way, not a single one, not once the path has a new mark, and not right
    after a smallest step it sent the slide to that found no jump."""
    from types import SimpleNamespace

    from capslide.loadpath.slide_rules import Mark, jump_check

    def rule_after(*areas, last=41430.0):
        state = SimpleNamespace(marks=[Mark(Phase.SLIDE, 34.6, -600.0, 2e4, 8e3, last)])
        rule = jump_check(state)
        assert all(rule(SimpleNamespace(phase=Phase.SLIDE, area=a)) is not None for a in areas)
        return rule, state

    assert rule_after(31430.0, 32291.0)[0].repeats()
    assert rule_after(60000.0, 20000.0, 31430.0, 32291.0)[0].repeats()  # the last two count
    assert not rule_after(31430.0)[0].repeats()
    assert not rule_after(20000.0, 30000.0)[0].repeats()  # 10,000 apart: more than a quarter of the jump of 21,430
    assert not rule_after(60000.0, 25000.0)[0].repeats()
    rule, state = rule_after(31430.0, 32291.0)
    assert rule.repeats()  # the slide goes on at its smallest step
    mark = lambda ubar: Mark(Phase.SLIDE, ubar, -600.0, 2e4, 8e3, 41000.0)  # noqa: E731
    jump = lambda *areas: [rule(SimpleNamespace(phase=Phase.SLIDE, area=a)) for a in areas]  # noqa: E731
    state.marks = [state.marks[-1], mark(34.61)]  # that step found no jump: the fold lies further on
    assert not rule.repeats()
    jump(31000.0)
    assert not rule.repeats()  # one rejection from the new mark
    jump(31500.0)
    assert not rule.repeats()  # two, but right after a smallest step that found no jump: the halvings bisect
    state.marks = [state.marks[-1], mark(34.62)]
    jump(31000.0, 31500.0)
    assert rule.repeats()


def test_steady_sliding_needs_three_fully_sliding_steps_with_nothing_changing():
    """Steady: the last two marks and the new step slide fully, Ft and the area change by at most 1e-8 (relative)
    in each step, and no gap by more than 1e-8 r0 in the last one; the gaps are read only when the rest holds."""
    from types import SimpleNamespace

    from capslide.loadpath.slide_rules import Mark, steady_sliding

    gap, r0 = np.array([0.02, 0.5, 3.0]), 0.1

    def rec(Ft=1.55, area=9.4, gap=gap, area_stick=0.0, phase=Phase.SLIDE, ubar=2.5):
        return SimpleNamespace(phase=phase, ubar=ubar, Ft=Ft, area=area, area_stick=area_stick, gap=gap)

    marks = [Mark(Phase.SLIDE, 2.2, 0.0, 0.0, 1.55, 9.4), Mark(Phase.SLIDE, 2.3, 0.0, 0.0, 1.55, 9.4)]
    steady = lambda marks, r, before=gap: steady_sliding(marks, r, lambda: before, r0)  # noqa: E731
    assert steady(marks, rec())
    assert steady(marks, rec(Ft=1.55 * (1 + 5e-9), area=9.4 * (1 - 5e-9)), gap + 0.5e-8 * r0)
    assert not steady(marks, rec(Ft=1.55 * (1 + 2e-8)))
    assert not steady(marks, rec(area=9.4 * (1 + 2e-8)))
    assert not steady(marks, rec(), gap + np.array([0.0, 2e-8 * r0, 0.0]))
    assert not steady(marks, rec(area_stick=0.01))
    assert steady(marks, rec(ubar=0.0))  # back at the start of a slide back: no exception for ubar = 0
    assert not steady(marks, rec(phase=Phase.PRELOAD))
    assert not steady(marks[1:], rec())  # two fully sliding steps only
    assert not steady([Mark(Phase.SLIDE, 2.2, 0.0, 0.01, 1.55, 9.4), marks[1]], rec())  # the first still sticks
    assert not steady([Mark(Phase.SLIDE, 2.2, 0.0, 0.0, 1.5, 9.4), marks[1]], rec())  # Ft changed a step earlier

    def unread():
        raise AssertionError("gaps read although Ft changed")
    assert not steady_sliding(marks, rec(Ft=1.6), unread, r0)


@pytest.mark.slow
def test_steady_sliding_goes_to_the_snapshots_and_the_end_in_one_step(paper_config, monkeypatch, tmp_path):
    """Once sliding is steady, each step goes to the next snapshot or the end: the same state there as step by
    step (QoIs, forces, gaps and tractions), in fewer steps, each a converged Newton solve, flagged in the file."""
    import xarray as xr

    import capslide.loadpath.cap as cap
    from capslide.io.results import case_dataset, write_netcdf

    p = params_with(paper_config, "friction.model=DI", "loading.ubar_max=4.0", "output.snapshot_ubar=[2.5, 3.0]")
    steady = run_case(p)
    monkeypatch.setattr(cap, "steady_sliding", lambda *args, **kw: False)
    plain = run_case(p)
    assert steady.status == plain.status == Status.COMPLETED
    long_steps = [r for r in steady.records if r.steady_step]
    assert [r.ubar for r in long_steps] == [2.5, 3.0, 4.0]
    assert all(r.newton_iterations <= 2 for r in long_steps)
    assert not any(r.steady_step for r in plain.records)
    assert len(steady.records) <= len(plain.records) - 5
    for key in ("peak_Ft", "onset_ubar", "onset_Ft", "onset_area"):
        assert steady.scalars[key] == pytest.approx(plain.scalars[key], rel=1e-9), key
    at = {r.ubar: r for r in plain.records if r.phase == Phase.SLIDE}
    for r in long_steps:
        q = at[r.ubar]
        assert r.Ft == pytest.approx(q.Ft, rel=1e-9) and r.Fn == pytest.approx(q.Fn, abs=1e-9)
        assert r.area == pytest.approx(q.area, rel=1e-9)
        np.testing.assert_allclose(r.gap, q.gap, rtol=0, atol=1e-9 * p.adhesion.r0)
        np.testing.assert_allclose(r.traction_t, q.traction_t, rtol=0, atol=1e-9 * np.max(np.abs(q.traction_t)))
    with xr.open_dataset(write_netcdf(case_dataset(steady), tmp_path / "case.nc")) as ds:
        assert ds["steady_step"].dtype == np.int8
        np.testing.assert_array_equal(ds["steady_step"].values, [int(r.steady_step) for r in steady.records])
    # a rule that holds only from the onset to ubar 2.3: every long step from there ends where the rule no
    # longer holds, and is cut back; the path goes on as step by step
    monkeypatch.setattr(cap, "steady_sliding", lambda marks, rec, *args, **kw: rec.area_stick == 0.0 and rec.ubar < 2.3)
    wrong = run_case(p)
    assert wrong.status == Status.COMPLETED and not any(r.steady_step for r in wrong.records)
    assert wrong.cutbacks > plain.cutbacks
    assert wrong.records[-1].Ft == pytest.approx(plain.records[-1].Ft, rel=1e-9)


def test_snapshot_landings_do_not_shorten_the_steps_after_them(paper_config, di_case):
    """Landing on a snapshot shortens that one step, not the ones after it: four snapshots up to ubar = 2, before
    the onset, add four slide steps there (measured 23 -> 27; the step rule before issue 19 went from 26 to 41) and
    leave the onset in place."""
    _, plain = di_case
    snaps = run_case(params_with(paper_config, "friction.model=DI", "output.snapshot_ubar=[0.5, 1.0, 1.5, 2.0]"))
    count = lambda res: sum(r.phase == Phase.SLIDE and r.ubar <= 2.0 for r in res.records)  # noqa: E731
    assert count(snaps) <= count(plain) + 4 + 1
    assert snaps.scalars["onset_ubar"] == pytest.approx(plain.scalars["onset_ubar"], rel=2e-3)
    assert snaps.scalars["peak_Ft"] == pytest.approx(plain.scalars["peak_Ft"], rel=1e-4)


def test_pull_off_ends_detached_with_a_file(tmp_path):
    """A tensile preload beyond pull-off: status detached, the file is written, the exit code is non-zero."""
    import subprocess
    import sys

    import xarray as xr

    from conftest import PAPER_CONFIG

    out = tmp_path / "detached.nc"
    res = subprocess.run([sys.executable, "-m", "capslide", "run", str(PAPER_CONFIG), "--set", "preset=fast",
                          "--set", "mesh.size=32",
                          "--set", "loading.preload=1.0", "--set", "output.snapshot_ubar=[]", "-q", "-o", str(out)],
                         capture_output=True, text=True, timeout=600)
    assert res.returncode == 3, res.stderr
    with xr.open_dataset(out) as ds:
        assert ds.attrs["status"] == "detached" and "pull-off" in ds.attrs["status_reason"]
        Fn = ds["Fn"].values
        assert 0.1 < Fn.max() < 1.0  # the largest tensile force that still had an equilibrium
        assert np.isnan(float(ds["peak_Ft"]))


def test_stop_at_onset_ends_on_the_onset_step(paper_config, di_case):
    """loading.stop_at_onset ends the slide at the first fully sliding step of the full run, same history."""
    p_full, full = di_case
    p = params_with(paper_config, "friction.model=DI", "loading.stop_at_onset=true")
    short = run_case(p)
    assert short.status == Status.COMPLETED and "onset of full sliding" in short.reason
    assert short.records[-1].ubar == full.scalars["onset_ubar"] < p_full.loading.ubar_max
    for key in ("onset_ubar", "onset_Ft", "onset_area"):
        assert short.scalars[key] == full.scalars[key]
    # the full run's peak may come a step after the onset (full sliding at a constant force, to round-off)
    assert short.scalars["peak_Ft"] == pytest.approx(full.scalars["peak_Ft"], rel=1e-12)
    n = len(short.records)
    np.testing.assert_array_equal([r.Ft for r in short.records], [r.Ft for r in full.records[:n]])


def test_hopeless_newton_ends_diverged_with_the_last_state(tmp_path):
    """Newton allowed too few iterations once contact forms: bounded cut-backs, status diverged, the converged
    history up to there is written, exit code 4."""
    import subprocess
    import sys

    import xarray as xr

    from conftest import PAPER_CONFIG

    out = tmp_path / "diverged.nc"
    res = subprocess.run([sys.executable, "-m", "capslide", "run", str(PAPER_CONFIG), *sum((["--set", s] for s in COARSE), []),
                          "--set", "loading.max_cutbacks=3", "--set", "solver.newton_max_iterations=3",
                          "-q", "-o", str(out)], capture_output=True, text=True, timeout=600)
    assert res.returncode == 4, res.stderr
    with xr.open_dataset(out) as ds:
        assert ds.attrs["status"] == "diverged" and "more than 3 cut-backs" in ds.attrs["status_reason"]
        assert ds.attrs["cutbacks"] == 4 and ds.sizes["step"] >= 1  # the converged steps before the failure
