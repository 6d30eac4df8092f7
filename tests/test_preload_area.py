"""A preload to a target contact area (loading.preload_area; issues 39 and 40: the experiment knows its areas, not
its loads): the secant on the force (capslide.loadpath.preload_targets.area_correction), and on the 2D cap, that the
area reached is the target's and the force the one a preload to that force gives, and that the slide holds it."""

from types import SimpleNamespace

import numpy as np
import pytest

from capslide.config import apply_overrides, validate
from capslide.driver.case import run_case
from capslide.loadpath.preload_targets import (
    AreaUnreachable,
    area_bracket,
    area_correction,
    area_targets,
    area_unreachable,
    bracketed_force,
)
from capslide.params import Parameters
from capslide.states import Phase, Status


def test_the_secant_lands_on_a_linear_area_law_in_one_step():
    area = lambda F: 10.0 - 4.0 * F  # noqa: E731 (compression, F < 0, grows the area)
    F_next = area_correction((0.0, -0.5), (area(0.0), area(-0.5)), 15.0, 1e-3, 1e-6)
    assert F_next == pytest.approx(-1.25, abs=1e-14)


def test_the_secant_stops_within_the_tolerance_and_below_the_smallest_force_step():
    assert area_correction((0.0, -0.5), (10.0, 12.0), 12.0 * (1 + 0.9e-3), 1e-3, 1e-6) is None
    assert area_correction((0.0, -0.5), (10.0, 12.0), 12.0 * (1 + 2e-3), 1e-3, 1e-6) is not None
    assert area_correction((0.0, -0.5), (10.0, 12.0), 12.0 * (1 + 2e-3), 1e-3, 1.0) is None  # step 0.006 < 1


def test_on_a_stair_of_the_area_the_secant_grows_its_step_at_most_twofold():
    """Two states on one stair (lambda = 3 on the experiment's annulus: 133,123 um^2 at 558.1 and 563.9 E L0^2,
    tensile) put the secant's target 29,000 E L0^2 away, five rings past the area; the step is held to twice the
    last one. A secant within that bound is taken whole (the linear law's 1.5 times)."""
    F_next = area_correction((558.087, 563.855), (133123.2185, 133122.6023), 130000.0, 2e-3, 1e-5)
    assert F_next == pytest.approx(563.855 + 2.0 * (563.855 - 558.087))
    assert area_correction((0.0, -0.5), (10.0, 12.0), 13.5, 1e-3, 1e-6) == pytest.approx(-0.875)


@pytest.mark.parametrize(("Fn", "area"), [((0.0, -0.5), (12.0, 10.0)), ((0.0, -0.5), (10.0, 10.0)), ((0.0, 0.0), (9.0, 10.0))])
def test_an_area_that_does_not_grow_under_compression_is_unreachable(Fn, area):
    with pytest.raises(AreaUnreachable):
        area_correction(Fn, area, 20.0, 1e-3, 1e-6)


def test_the_reason_names_the_key_and_its_value():
    loading = SimpleNamespace(preload_area=20.0, preload_area_rtol=1e-3, min_force_step=1e-6)
    marks = [SimpleNamespace(phase=Phase.PRELOAD, Fn=0.0, area=12.0), SimpleNamespace(phase=Phase.PRELOAD, Fn=-0.5, area=10.0)]
    with pytest.raises(AreaUnreachable):
        area_targets(loading, marks, [])
    message = area_unreachable(loading, marks, [])
    assert message.startswith("preload to loading.preload_area = 20:") and "\n" not in message


def _mark(Fn, area):
    return SimpleNamespace(phase=Phase.PRELOAD, Fn=Fn, area=area)


def test_the_bracket_keeps_the_latest_state_on_either_side_of_the_target():
    b = area_bracket([], [_mark(-1.0, 9.0), _mark(-2.0, 11.0)], 10.0)
    assert sorted(m.Fn for m in b) == [-2.0, -1.0]
    b = area_bracket(b, [_mark(-2.0, 11.0), _mark(-1.5, 10.5)], 10.0)  # -1.5 replaces -2 above the target
    assert sorted(m.Fn for m in b) == [-1.5, -1.0]
    assert area_bracket([], [SimpleNamespace(phase=Phase.APPROACH, Fn=0.0, area=3.0), _mark(-1.0, 9.0)], 10.0) == [
        _mark(-1.0, 9.0)]


def _jumping_area(F):  # a contact edge that snaps by a face at F = -1.3: 8 -> 12, over the target 10
    return 8.0 - F if F > -1.3 else 12.0 - F


def test_a_preload_to_an_area_that_jumps_over_the_target_ends_once_the_force_is_resolved():
    """Without the bracket the secant through the last two states bounces over the jump (the case that did not end
    in the experiment's sweep at A0 = 0.10 mm^2); with it the force closes in on the jump and stops within rtol."""
    loading = SimpleNamespace(preload_area=10.0, preload_area_rtol=1e-3, min_force_step=1e-6)
    marks, bracket = [_mark(0.0, _jumping_area(0.0)), _mark(-1.0, _jumping_area(-1.0))], []
    for _ in range(60):
        targets, bracket = area_targets(loading, marks, bracket)
        if not targets:
            break
        marks = [marks[-1], _mark(targets[0], _jumping_area(targets[0]))]
    assert not targets
    lo, hi = sorted(m.Fn for m in bracket)
    assert lo <= -1.3 < hi and hi - lo <= 1e-3 * 1.31


def test_inside_the_bracket_the_secant_is_kept_and_a_step_outside_it_is_halved():
    bracket = [_mark(-1.0, 9.0), _mark(-2.0, 11.0)]
    assert bracketed_force(bracket, (bracket[0], bracket[1]), 10.0, 1e-3, 1e-6) == pytest.approx(-1.5)
    far = (_mark(-1.9, 10.9), _mark(-2.0, 11.0))  # the branch's secant reaches past the bracket
    assert bracketed_force(bracket, far, 10.0, 1e-3, 1e-6) == pytest.approx(-1.5)
    near = (_mark(-1.0, 9.0), _mark(-1.2, 9.8))
    assert bracketed_force(bracket, near, 10.0, 1e-3, 1e-6) == pytest.approx(-1.25)
    assert bracketed_force([_mark(-1.0, 9.0), _mark(-1.0005, 11.0)], near, 10.0, 1e-3, 1e-6) is None


COARSE = ["preset=fast", "mesh.size=32", "loading.ubar_max=0", "output.snapshot_ubar=[]"]


def _run(paper_config, *overrides):
    p = Parameters.from_config(validate(apply_overrides(paper_config, [*COARSE, *overrides])))
    res = run_case(p)
    assert res.status == Status.COMPLETED, res.reason
    return p, res


@pytest.mark.parametrize("Fn_star", [-0.2, 0.1])  # compressive, and tensile (a smaller area than at zero load)
def test_a_preload_to_an_area_reaches_the_area_of_a_preload_to_a_force(paper_config, Fn_star):
    """The area of a preload to Fn* taken as the target, from a first guess of 0: the area is met to its tolerance,
    and the force is Fn* to within what that tolerance lets through (dFn = rtol A / |dA/dFn|)."""
    _, by_force = _run(paper_config, f"loading.preload={Fn_star}")
    target = by_force.records[-1].area
    p, by_area = _run(paper_config, "loading.preload=0.0", f"loading.preload_area={target}")
    last = by_area.records[-1]
    assert last.phase == Phase.PRELOAD
    assert abs(last.area - target) <= p.loading.preload_area_rtol * target
    pre = [r for r in by_force.records if r.phase == Phase.PRELOAD][-2:]
    slope = (pre[1].area - pre[0].area) / (pre[1].Fn - pre[0].Fn)
    assert abs(last.Fn - Fn_star) <= 2 * p.loading.preload_area_rtol * target / abs(slope)
    assert abs(last.Fn) > 0.0  # the guess was corrected


def test_the_slide_holds_the_force_the_preload_to_an_area_reached(paper_config):
    p, res = _run(paper_config, "loading.preload=0.0", "loading.preload_area=20.0", "loading.ubar_max=0.6",
                  "loading.max_slide_step=0.2")
    reached = [r for r in res.records if r.phase == Phase.PRELOAD][-1]
    assert abs(reached.area - 20.0) <= p.loading.preload_area_rtol * 20.0
    slide = [r for r in res.records if r.phase == Phase.SLIDE]
    assert slide and all(abs(r.Fn - reached.Fn) <= 1e-9 for r in slide)


@pytest.mark.slow
def test_a_preload_to_an_area_goes_on_from_the_zero_load_state(tmp_path, capsys):
    """The experiment's cases start from one normal state at zero load (workflow/rules/experiment3d.smk): the path
    goes on from it (no second approach) and lands on the same area as a fresh path."""
    from capslide.cli import main
    from capslide.io.reading import open_result

    base = ["--scene", "cap", *[a for s in [*COARSE, "loading.preload_via=[]"] for a in ("--set", s)]]
    state, chained, fresh = tmp_path / "Fn0.npz", tmp_path / "chained.nc", tmp_path / "fresh.nc"
    assert main(["preload", *base, "--set", "loading.preload=0.0", "-o", str(state)]) == 0
    area = ["--set", "loading.preload=-0.1", "--set", "loading.preload_area=20.0"]
    assert main(["run", *base, *area, "--from-state", str(state), "-o", str(chained)]) == 0
    assert "starting afresh" not in capsys.readouterr().err
    assert main(["run", *base, *area, "-o", str(fresh)]) == 0
    a, b = open_result(chained, "case"), open_result(fresh, "case")
    approach = [int(p) for p in (Phase.APPROACH, Phase.SPREAD)]
    assert np.isin(a.phase.values, approach).sum() == np.isin(b.phase.values, approach).sum()  # one approach each
    # the chained path passes the zero-load state (its preload's last step), the fresh one goes past it
    assert np.any(np.abs(a.Fn.values) < 1e-8) and not np.any(np.abs(b.Fn.values) < 1e-8)
    for ds in (a, b):  # both land on the area, at one force (the equilibrium at an area is the path's end)
        assert abs(float(ds.area[-1]) - 20.0) <= 1e-3 * 20.0
    assert float(a.Fn[-1]) == pytest.approx(float(b.Fn[-1]), rel=0.01)


def _params(scene: str, *overrides: str) -> Parameters:
    from capslide.config import load_config

    return Parameters.from_config(load_config([scene], list(overrides)))


def test_the_pull_off_area_bound_is_jkrs_at_a_large_maugis_parameter():
    """At lambda = 20 the Maugis-Dugdale sphere is JKR's: pull-off under load control at A^3 - sqrt(6 A^3) = -3/2,
    A = 1.5^(1/3) (Johnson and Greenwood's variables); lambda = 2 pulls off at a smaller contact."""
    from capslide.laws import analytic, sphere
    from capslide.model.reach import md_pull_off_area

    p = _params("experiment", "adhesion.maugis_lambda=20.0")
    E_star = analytic.effective_modulus(p.material.E, p.material.nu)
    jkr = np.pi * (1.5 ** (1.0 / 3.0) * sphere.md_scales(p.geometry.R, E_star, p.adhesion.W_adh)["radius"]) ** 2
    assert md_pull_off_area(p) == pytest.approx(jkr, rel=0.02)
    assert md_pull_off_area(_params("experiment")) < 0.9 * jkr


@pytest.mark.parametrize(("scene", "area", "words"), [
    ("experiment", "0.27", "below half of the Maugis-Dugdale sphere's pull-off area (67020.7 L0^2)"),  # mm^2 for um^2
    ("sphere", "270000.0", "beyond the cap's top surface 2 pi R H = 2959.38 L0^2"),  # the experiment's area
    ("cap", "200.0", "beyond the cap's top arc = 62.5255 L0"),
])
def test_an_area_no_preload_reaches_is_refused_before_anything_is_written(tmp_path, capsys, scene, area, words):
    from capslide.cli import main

    out = tmp_path / "case.nc"  # superlu: the experiment scene's PARDISO would be refused first without MKL
    assert main(["run", "--scene", scene, "--set", f"loading.preload_area={area}", "--set",
                 "solver.factorization=superlu", "-o", str(out)]) == 2
    err = capsys.readouterr().err
    assert f"loading.preload_area = {float(area)!r} is not allowed here: " in err and words in err
    assert err.count("\n") == 1 and "Traceback" not in err
    assert list(tmp_path.iterdir()) == []


def test_an_area_between_the_bounds_passes_the_preflight():
    from capslide.model.reach import check_preload_area, preload_area_bounds

    for scene, area in (("experiment", 100000.0), ("experiment", 460000.0), ("cap", 20.0), ("sphere", 150.0)):
        p = _params(scene, f"loading.preload_area={area}")
        lo, hi = preload_area_bounds(p)
        assert lo < area < hi
        check_preload_area(p)
    p = _params("sphere", "contact.repulsion_only=true", "loading.preload=-1.0")
    assert preload_area_bounds(p)[0] == 0.0  # no adhesion, no pull-off
