"""A preload to a target contact area (loading.preload_area; issues 39 and 40: the experiment knows its areas, not
its loads): the secant on the force (capslide.loadpath.preload_targets.area_correction), and on the 2D cap, that the
area reached is the target's and the force the one a preload to that force gives, and that the slide holds it."""

from types import SimpleNamespace

import numpy as np
import pytest

from capslide.config import apply_overrides, validate
from capslide.driver.case import run_case
from capslide.loadpath.preload_targets import AreaUnreachable, area_correction, area_targets, area_unreachable
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


@pytest.mark.parametrize(("Fn", "area"), [((0.0, -0.5), (12.0, 10.0)), ((0.0, -0.5), (10.0, 10.0)), ((0.0, 0.0), (9.0, 10.0))])
def test_an_area_that_does_not_grow_under_compression_is_unreachable(Fn, area):
    with pytest.raises(AreaUnreachable):
        area_correction(Fn, area, 20.0, 1e-3, 1e-6)


def test_the_reason_names_the_key_and_its_value():
    loading = SimpleNamespace(preload_area=20.0, preload_area_rtol=1e-3, min_force_step=1e-6)
    marks = [SimpleNamespace(Fn=0.0, area=12.0), SimpleNamespace(Fn=-0.5, area=10.0)]
    with pytest.raises(AreaUnreachable):
        area_targets(loading, marks)
    message = area_unreachable(loading, marks)
    assert message.startswith("preload to loading.preload_area = 20:") and "\n" not in message


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
