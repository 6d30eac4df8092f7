"""Passing a snap (solver.snap_through, loadpath/snap_through.py): pseudo-transient continuation reaches the
equilibrium Newton reaches, and a slide step that fails or jumps at the minimum step is passed instead of ending the
case. Coarse 2D cases at zero load (a few seconds each)."""

import numpy as np
import pytest

import capslide.loadpath.continuation as continuation
from capslide.config import apply_overrides, validate
from capslide.driver.case import run_case
from capslide.loadpath.snap_through import PseudoTransient, pseudo_transient
from capslide.model.build import build_model
from capslide.model.constraints import FixedForce
from capslide.model.system import History
from capslide.params import Parameters
from capslide.solvers.newton import NewtonResult
from capslide.states import Phase, Status

from conftest import FOLD

COARSE = ["mesh.size=32", "loading.ubar_max=1.0", "loading.max_slide_step=0.2", "output.snapshot_ubar=[]",
          "loading.preload=0.0"]


def _params(paper_config, *overrides) -> Parameters:
    return Parameters.from_config(validate(apply_overrides(paper_config, [*COARSE, *overrides])))


def _fold(paper_config, *overrides) -> Parameters:
    return Parameters.from_config(validate(apply_overrides(paper_config, [*FOLD, *overrides])))


def test_pseudo_transient_continuation_reaches_the_equilibrium(paper_config):
    """From the normal state at zero load with every displacement 20 % larger, the continuation returns to it within
    1e-6 L0, in more than one iteration; given two iterations only, it reports failure."""
    p = _params(paper_config, "loading.ubar_max=0")
    res = run_case(p)
    assert res.status == Status.COMPLETED
    model = build_model(p)
    x_star = res.final_x
    x0 = x_star.copy()
    x0[:-1] *= 1.2  # every displacement 20 % larger, the substrate where it was
    assert model.admissible(x0)
    constraint = FixedForce(res.records[-1].Fn)
    out = pseudo_transient(model, constraint, History(), x0, settings=PseudoTransient(handover=1e-10))
    print("iterations", out.iterations, "residuals", out.residual_norms[0], out.residual_norms[-1])
    assert out.converged and out.iterations > 1 and out.residual_norms[-1] <= 1e-10
    np.testing.assert_allclose(out.x, x_star, atol=1e-6)
    short = pseudo_transient(model, constraint, History(), x0, settings=PseudoTransient(max_iterations=2))
    assert not short.converged and "after 2 iterations" in short.reason


def test_a_fixed_height_step_snaps_through_on_its_energy(paper_config, monkeypatch):
    """At a fixed height the continuation runs on the step's energy in u (FixedHeight.potential, .project): from the
    normal state at zero load with every displacement 20 % larger and the substrate 1e-3 L0 off its height, it
    returns to the equilibrium within 1e-6 L0, on the energy, which is only ever taken at h = h*."""
    import capslide.loadpath.snap_through as snap
    from capslide.model.constraints import FixedHeight

    p = _params(paper_config, "loading.ubar_max=0")
    res = run_case(p)
    model, x_star = build_model(p), res.final_x
    x0 = x_star.copy()
    x0[:-1] *= 1.2
    x0[-1] += 1e-3
    on_the_energy, taken = snap._on_the_energy, []
    monkeypatch.setattr(snap, "_on_the_energy", lambda *a, **k: taken.append(on_the_energy(*a, **k)) or taken[-1])
    step_energy, heights = model.step_energy, []
    monkeypatch.setattr(model, "step_energy", lambda x, *a: heights.append(x[-1]) or step_energy(x, *a))
    out = pseudo_transient(model, FixedHeight(float(x_star[-1])), History(), x0, settings=PseudoTransient(handover=1e-10))
    assert taken and out.converged and out.iterations > 1
    assert len(heights) > 2 and set(heights[1:]) == {x_star[-1]}  # the first: whether the step has an energy
    np.testing.assert_allclose(out.x, x_star, atol=1e-6)


def _failing_across(monkeypatch, ubar, converged):
    """Slide steps across ``ubar`` come back failed (not converged), or converged but rejected as if the area had
    jumped (``converged``)."""
    solved_step = continuation._solved_step
    judged = continuation._judged

    def failing(model, loop, leg, history, target, opts, dt, constraint):
        res, solved = solved_step(model, loop, leg, history, target, opts, dt, constraint)
        if leg.phase == Phase.SLIDE and loop.value < ubar < target and not converged:
            res = NewtonResult(res.x, False, res.iterations, "forced failure", res.residual_norms)
        return res, solved

    def rejecting(model, loop, leg, res, solved, aim, constraint, wall, dt, snapped=False):
        if converged and leg.phase == Phase.SLIDE and loop.value < ubar < aim.target and not snapped:
            return None, "forced jump", False
        return judged(model, loop, leg, res, solved, aim, constraint, wall, dt, snapped)

    monkeypatch.setattr(continuation, "_solved_step", failing)
    monkeypatch.setattr(continuation, "_judged", rejecting)


@pytest.mark.parametrize("converged", [False, True], ids=["no_equilibrium", "jump"])
def test_a_slide_passes_a_step_that_fails_at_the_minimum_step(paper_config, monkeypatch, converged):
    """Every slide step across ubar = 0.5 L0 fails (or converges and is rejected as a jump): by default the case ends
    diverged there; with snap_through the step that failed at the minimum step is taken by pseudo-transient
    continuation (or the jump stands), the case completes, and its state there is an equilibrium as any other."""
    _failing_across(monkeypatch, 0.5, converged)
    plain = run_case(_params(paper_config))
    assert plain.status == Status.DIVERGED and "step below minimum" in plain.reason
    snapping = run_case(_params(paper_config, "solver.snap_through=true"))
    assert snapping.status == Status.COMPLETED, snapping.reason
    slide = [r for r in snapping.records if r.phase == Phase.SLIDE]
    assert any(0.5 < r.ubar < 0.5 + 1e-3 for r in slide) and slide[-1].ubar == pytest.approx(1.0)
    assert plain.records[-1].ubar < 0.5
    assert [r.ubar for r in snapping.records if r.snapped] == [min(r.ubar for r in slide if r.ubar > 0.5)]
    assert not any(r.snapped for r in plain.records)


def test_a_snaps_end_state_is_never_the_onset_of_full_sliding():
    """measures.sliding_onset: a snapped-through step with no sticking point (the experiment's re-adhering snaps,
    whose new points carry no threshold in the step) is not the onset; the first quasi-static step with none is."""
    from types import SimpleNamespace

    from capslide.loadpath.measures import sliding_onset
    from capslide.states import SlipState

    def rec(ubar, stick, snapped=False):
        states = [SlipState.STICK] * stick + [SlipState.SLIP] * 3
        return SimpleNamespace(phase=Phase.SLIDE, ubar=ubar, Ft=ubar, area=1.0, snapped=snapped,
                               slip_state=np.array(states))

    onset = sliding_onset([rec(0.5, 2), rec(0.6, 0, snapped=True), rec(0.7, 1), rec(0.8, 0), rec(0.9, 0)])
    assert onset["onset_ubar"] == 0.8


def test_a_snap_to_a_grown_contact_is_its_coming_off():
    """regrowth_check: a snapped-through step whose area grew by more than 20 % over the last mark's is the contact
    coming off (the numbers of the experiment's A0 = 0.10 mm^2), whether or not the area fell at the last step (the
    A0 = 0.19 mm^2 case: a 0.1 % rise, then a 34 % re-adhesion); one that shrank on, or grew by less, is not."""
    from types import SimpleNamespace

    from capslide.loadpath.slide_rules import REGROWTH, Mark, regrowth_check

    state = SimpleNamespace(marks=[Mark(Phase.SLIDE, 38.4755, 224.2, 7966.5, 6498.6, 21923.1),
                                   Mark(Phase.SLIDE, 38.4855, 161.9, 1562.8, 5260.6, 9997.0)])
    rule = regrowth_check(state)
    reason = rule(SimpleNamespace(phase=Phase.SLIDE, area=118219.9))
    assert "came off at ubar = 38.4855 (its area fell to 9997" in reason
    assert REGROWTH in reason  # what the experiment table reads as the outcome re-adhered
    assert rule(SimpleNamespace(phase=Phase.SLIDE, area=8000.0)) is None
    assert rule(SimpleNamespace(phase=Phase.SLIDE, area=1.1 * 9997.0)) is None
    state.marks = [Mark(Phase.SLIDE, 34.3141, 0.0, 0.0, 0.0, 120519.0), Mark(Phase.SLIDE, 34.3141, 0.0, 0.0, 0.0, 120664.0)]
    reason = rule(SimpleNamespace(phase=Phase.SLIDE, area=161285.0))  # growing before the snap: ends all the same
    assert reason is not None and "(its area was 120664;" in reason and REGROWTH in reason
    assert rule(SimpleNamespace(phase=Phase.SLIDE, area=1.19 * 120664.0)) is None


def test_a_snap_that_the_leg_calls_vanishing_ends_it_detached(paper_config, monkeypatch):
    """With snap_through, a snapped-through step for which the leg's ``vanishes`` gives a reason ends the case
    detached at the state before it, with that reason; with ``loading.readhesion_snap: follow`` the slide goes on
    past it to ubar_max."""
    import capslide.loadpath.slide_rules as rules

    _failing_across(monkeypatch, 0.5, converged=False)
    monkeypatch.setattr(rules, "regrowth_check", lambda state: (lambda rec: "the contact came off (forced)"))
    res = run_case(_params(paper_config, "solver.snap_through=true"))
    assert res.status == Status.DETACHED and "the contact came off (forced)" in res.reason
    assert res.records[-1].ubar < 0.5
    followed = run_case(_params(paper_config, "solver.snap_through=true", "loading.readhesion_snap=follow"))
    assert followed.status == Status.COMPLETED, followed.reason
    assert followed.records[-1].ubar == pytest.approx(1.0)


def test_a_jump_found_at_two_step_lengths_goes_on_at_the_smallest_step(paper_config, monkeypatch):
    """A fold at the first slide mark past ubar = 0.5 L0: every step from it finds the contact area 30 % smaller
    (another equilibrium). The area-jump rule rejects the step, its half finds the same area, and the next step is
    the smallest, where the jump stands (AreaJump.repeats): three solves from that mark instead of halvings down to
    the smallest step."""
    from dataclasses import replace

    measure, solved_step, steps = continuation.measure, continuation._solved_step, []

    def jumped(model, x, history, phase, ubar, *args):
        rec = measure(model, x, history, phase, ubar, *args)
        return replace(rec, area=0.7 * rec.area) if phase == Phase.SLIDE and steps[-1][0] >= 0.5 else rec

    def counted(model, loop, leg, history, target, *args):
        if leg.phase == Phase.SLIDE:
            steps.append((loop.value, target))
        return solved_step(model, loop, leg, history, target, *args)

    monkeypatch.setattr(continuation, "measure", jumped)
    monkeypatch.setattr(continuation, "_solved_step", counted)
    p = _params(paper_config, "solver.snap_through=true")
    res = run_case(p)
    assert res.status == Status.COMPLETED, res.reason
    fold = min(start for start, _ in steps if start >= 0.5)
    (_, first), (_, second), (_, last) = [step for step in steps if step[0] == fold]
    assert second - fold == pytest.approx(0.5 * (first - fold)) and last - fold == pytest.approx(p.loading.min_slide_step)
    assert first - fold > 4 * p.loading.min_slide_step  # without the rule: three more halvings
    assert [r.ubar for r in res.records if r.snapped] == [last]


def test_tangential_potential_is_the_return_maps_integral():
    """psi(d) of laws.contact.tangential_potential: its derivative in d is the return map's traction magnitude
    min(eps_t d, c), in stick, in slip and on both sides of the transition; psi is continuous there."""
    from capslide.laws import contact

    eps_t, rng = 50.0, np.random.default_rng(4)
    c = rng.uniform(0.1, 2.0, 300)
    d = np.concatenate([rng.uniform(0.0, 0.04, 100), rng.uniform(0.05, 1.0, 100),
                        c[200:] / eps_t * (1.0 + rng.choice([-1e-3, 1e-3], 100))])
    h = 1e-7
    dpsi = (contact.tangential_potential(d + h, c, eps_t) - contact.tangential_potential(d - h, c, eps_t)) / (2 * h)
    T, slipping, _, _ = contact.return_map(-eps_t * d, c)
    assert slipping.any() and (~slipping).any()
    np.testing.assert_allclose(dpsi, np.abs(T), rtol=1e-6, atol=1e-9)
    at = c / eps_t
    np.testing.assert_allclose(contact.tangential_potential(at, c, eps_t), 0.5 * c * c / eps_t, rtol=1e-14)


def _sheared_sphere(shift: float):
    """The coarse 3D sphere of tests/test_friction_3d.py with DI held at the step's start, pressed, anchored, then
    sheared by ``shift`` at the top (stick below about 0.0016 L0, slip above)."""
    from test_friction_3d import _model

    from fe_helpers import pressed_sphere_state

    model = _model(("mesh.element=H1", "friction.model=DI", "friction.threshold_at=step_start"))
    x0 = pressed_sphere_state(model)
    history = model.start_friction(x0)
    x = x0.copy()
    x[:-1:3] += shift * model.mesh.nodes[:, 2] / 10
    x[1:-1:3] += 0.5 * shift * model.mesh.nodes[:, 2] / 10 * (model.mesh.nodes[:, 1] > 0)
    x[model.bc.dofs] = 0.0
    return model, x, history


@pytest.mark.parametrize("shift", [0.0005, 0.01], ids=["stick", "slip"])
def test_the_step_energy_gradient_is_the_residual(shift):
    """CapModel.step_energy on the 3D half model with DI friction held at the step's start, under a spring and under
    a force, and at a fixed height along directions that keep h: its central differences along random directions
    equal energy_gradient(residual) . v (the u rows times 2, the constraint's row as it is). Without a potential
    (a threshold that follows the gap) it is None."""
    from capslide.model.constraints import FixedHeight, SlideAtForce, SlideOnSpring

    model, x, history = _sheared_sphere(shift)
    ubar = 1e-4
    _, state = model.contact.tangential_state(x[:-1], x[-1], ubar, *history.friction)
    assert (state == (1 if shift < 0.001 else 2)).sum() > 0
    rng = np.random.default_rng(8)
    for constraint in (SlideOnSpring(ubar, -0.1, x[-1] + 0.01, 3.0), SlideAtForce(ubar, 0.2), FixedHeight(x[-1], ubar)):
        grad = model.energy_gradient(model.residual(x, constraint, history))
        for _ in range(2):
            v = 1e-3 * rng.normal(size=x.shape)
            v[model.bc.dofs] = 0.0
            if isinstance(constraint, FixedHeight):
                v[-1] = 0.0
            h = 1e-4
            fd = (model.step_energy(x + h * v, constraint, history)
                  - model.step_energy(x - h * v, constraint, history)) / (2 * h)
            assert fd == pytest.approx(grad @ v, rel=1e-6)
    following = model.contact.threshold_at_step_start
    model.contact.threshold_at_step_start = False
    try:
        assert model.step_energy(x, SlideAtForce(ubar, 0.2), history) is None
    finally:
        model.contact.threshold_at_step_start = following


def test_the_snap_on_the_energy_passes_the_2d_caps_fold(paper_config, monkeypatch):
    """The 2D test cap with DI held at the step's start at zero load: past the onset of full sliding its area jumps
    (docs/options.md). With steps of at least 0.001 L0 Newton alone ends diverged before 2.2 L0 (at ubar = 2.074 L0
    on the machine of 2026-12-03); with snap_through the continuation on the step's energy passes (where the
    continuation by the residual ended at 2.2e-4 after 400 iterations), every snap in fewer than 40 iterations, and
    the case completes to 2.2 L0. With the default minimum step of 1e-4 L0 Newton's cut-backs passed the fold on
    that machine's AVX-512 CPU, where they had failed on earlier machines: the larger minimum makes the snap happen
    whatever the rounding."""
    import capslide.loadpath.snap_through as snap

    taken = []
    on_the_energy = snap._on_the_energy

    def counted(*args, **kwargs):
        res = on_the_energy(*args, **kwargs)
        taken.append(res)
        return res

    monkeypatch.setattr(snap, "_on_the_energy", counted)
    fold = ["friction.threshold_at=step_start", "loading.min_slide_step=0.001"]
    alone = run_case(_fold(paper_config, *fold, "solver.snap_through=false"))
    assert alone.status == Status.DIVERGED and alone.records[-1].ubar < 2.2
    assert not taken
    res = run_case(_fold(paper_config, *fold))
    assert res.status == Status.COMPLETED, res.reason
    assert taken and all(t.converged and t.iterations < 40 for t in taken)
    assert res.records[-1].ubar == pytest.approx(2.2)


@pytest.fixture(scope="module")
def predicted_fold(paper_config):
    """The 2D cap's fold with DI held at the gaps predicted for each step's end (``step_predicted``), run once for
    the tests below: its result, and the events of each step in order: ("advanced", whether the step snapped) when a
    step is taken, ("held", whether its thresholds are held with no state before it) when the next one starts. The
    recorders call through, so the run is the case's own."""
    from capslide.model.system import CapModel

    events = []
    step_history, advanced = CapModel.step_history, continuation._advanced

    def recorded_history(self, history, x, x_before, ratio):
        events.append(("held", x_before is None))
        return step_history(self, history, x, x_before, ratio)

    def recorded_advance(loop, aim, x, snapped=False):
        events.append(("advanced", snapped))
        return advanced(loop, aim, x, snapped)

    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(CapModel, "step_history", recorded_history)
        mp.setattr(continuation, "_advanced", recorded_advance)
        res = run_case(_fold(paper_config, "friction.threshold_at=step_predicted"))
    assert res.status == Status.COMPLETED, res.reason
    return res, events


def test_the_step_after_a_snap_holds_the_thresholds_at_its_start(predicted_fold):
    """With ``friction.threshold_at: step_predicted`` a step extrapolates the gaps along the last converged step;
    a snap's jump is no such rate, so the step after a snap holds the thresholds at its start state. The 2D cap's
    fold as above: every step after a snap is given no state before it, every other slide step after the first
    one is."""
    _, events = predicted_fold
    after = [(events[i][1], events[i + 1][1]) for i in range(len(events) - 1)
             if events[i][0] == "advanced" and events[i + 1][0] == "held"]
    snaps = [held_at_start for snapped, held_at_start in after if snapped]
    print(len(snaps), "snaps among", len(after), "steps")
    assert snaps and all(snaps)
    assert sum(not held_at_start for snapped, held_at_start in after if not snapped) > 10


def test_slide_steps_grow_back_after_harder_solves_when_asked(paper_config, predicted_fold):
    """``loading.slide_growth_iterations``: a converged slide step of at most that many Newton iterations lets the
    next one grow. On the 2D cap's fold (steps cut back by 25 halvings at the default of 4) a limit of 30 lets every
    converged step grow back: about half the slide steps (measured 60 against 113), Ft at the end within 1 %."""
    assert _fold(paper_config).loading.slide_growth_iterations == 4  # the shared run is the default's
    res = run_case(_fold(paper_config, "friction.threshold_at=step_predicted", "loading.slide_growth_iterations=30"))
    assert res.status == Status.COMPLETED, res.reason
    default, growing = ([r for r in case.records if r.phase == Phase.SLIDE] for case in (predicted_fold[0], res))
    print("slide steps", len(default), len(growing))
    assert len(growing) < 0.7 * len(default)
    assert growing[-1].Ft == pytest.approx(default[-1].Ft, rel=1e-2)
