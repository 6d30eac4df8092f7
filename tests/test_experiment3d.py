"""The experiment in numbers (issue 40): the experiment scene's study cases, the preload's first guess against the
JKR numbers of ../shared/reference/sphere-facts.md, DI's tau held while lambda changes, and the path state that
carries the force a preload to an area reached through a checkpoint."""

import json

import numpy as np
import pytest

from capslide.config import apply_settings, load_config, scene_path
from capslide.io.checkpoint import path_state, state_arrays
from capslide.io.state_check import check_header
from capslide.loadpath.cap import Mark, PathState
from capslide.model.build import mesh_spec
from capslide.model.system import History
from capslide.params import Parameters
from capslide.states import Phase
from capslide.studies.experiment_3d import normal_states, preload_guess, study_cases


@pytest.fixture(scope="module")
def scene() -> dict:
    return load_config([scene_path("experiment")])


def test_the_cases_are_the_experiments_areas_and_the_lambda_checks(scene):
    assert list(study_cases(scene)) == ["A0.100", "A0.130", "A0.160", "A0.190", "A0.270", "A0.460"]
    cases = study_cases(apply_settings(scene, {"study.lambda_checks": [3.0, 4.0]}))
    assert list(cases)[6:] == ["A0.270_lambda3", "A0.270_lambda4"]
    for name, sets in cases.items():
        A0 = float(name[1:6])
        assert sets["loading.preload_area"] == pytest.approx(A0 * 1e6)  # mm^2 -> um^2 = L0^2
    assert cases["A0.270_lambda3"]["adhesion.maugis_lambda"] == 3.0 and cases["A0.270"]["adhesion.maugis_lambda"] == 2.0
    assert list(normal_states(cases)) == ["lambda2", "lambda3", "lambda4"]
    assert cases["A0.100"]["loading.preload"] > 0 > cases["A0.460"]["loading.preload"]  # tensile, compressive


@pytest.mark.parametrize(("A0", "Fn_mN"), [(0.10, -1.15), (0.19, -0.15), (0.27, 1.57), (0.46, 7.91)])
def test_the_first_guess_tends_to_the_jkr_loads_of_the_sphere_facts(scene, A0, Fn_mN):
    """At a large lambda and nu = 0.5 the Maugis-Dugdale guess is JKR's load (sphere-facts.md, compressive > 0, to
    its two decimals)."""
    config = apply_settings(scene, {"material.nu": 0.5})
    guess_mN = -preload_guess(config, A0, 1e4) * config["material"]["E"] * config["geometry"]["L0"] ** 2 * 1e3
    assert guess_mN == pytest.approx(Fn_mN, abs=0.006)


def test_the_annulus_preset_is_the_coarse_bulk_with_rings_of_10_um_on_the_contact_line():
    """The peaks' mesh check (docs/experiment3d.md) runs the cases at preset=annulus: the mesh of the coarse preset
    plus the contact-line annulus, the same mesh as the explicit keys it stands for."""
    def spec(*settings):
        return mesh_spec(Parameters.from_config(load_config([scene_path("experiment")], list(settings))))

    annulus, coarse = spec("preset=annulus"), spec("preset=coarse")
    assert annulus == spec("mesh.line_band=[120,330]", "mesh.line_refinement=4")
    assert annulus.line_band == (120.0, 330.0) and annulus.line_size == pytest.approx(annulus.h0 / 4)
    assert annulus.h0 == coarse.h0 and coarse.line_band is None


def test_tau_stays_fixed_when_lambda_changes():
    T_max = set()
    for lam in (2.0, 3.0, 4.0):
        c = load_config([scene_path("experiment")], [f"adhesion.maugis_lambda={lam}"])
        T_max.add(c["adhesion"]["T_max"])
        assert c["friction"]["mu_DI"] * c["adhesion"]["T_max"] == pytest.approx(0.43e6, rel=1e-12)
    assert len(T_max) == 3


def test_a_checkpoint_keeps_the_force_the_preload_to_an_area_reached():
    arrays, header = state_arrays(PathState("slide", np.zeros(5), History(), preload_Fn=-1234.5))
    assert path_state(arrays, header).preload_Fn == -1234.5
    arrays, header = state_arrays(PathState("slide", np.zeros(5), History()))
    assert path_state(arrays, header).preload_Fn is None


def test_a_checkpoint_keeps_the_bracket_of_a_preload_to_an_area():
    bracket = [Mark(Phase.PRELOAD, 0.0, 688.4, 0.0, 0.0, 111834.4), Mark(Phase.PRELOAD, 0.0, 720.4, 0.0, 0.0, 89974.6)]
    arrays, header = state_arrays(PathState("preload", np.zeros(5), History(), area_bracket=bracket))
    json.loads(json.dumps(header))  # the header is JSON
    check_header({**header, "elapsed": 0.0, "chunks": []}, "checkpoint")
    assert path_state(arrays, header).area_bracket == bracket
    assert path_state(arrays, {k: v for k, v in header.items() if k != "area_bracket"}).area_bracket == []


def test_the_outlines_show_the_snapshot_times_and_name_those_past_the_slides_end():
    """A0 = 0.27 mm^2 whose slide ended at 0.369 s: only 0 s is drawn, the later times are named as past the end; a
    time before the end without a snapshot is named as missing."""
    from capslide.figures.experiment_3d import snapshot_panels

    times = (0.0, 0.45, 0.62, 0.73)
    shown, note = snapshot_panels([0.0], times, 0.369)
    assert shown == [(0.0, 0)]
    assert note == "0.45, 0.62 and 0.73 s: after the slide's end at 0.369 s"
    shown, note = snapshot_panels([0.0, 0.62], times, 0.7)
    assert shown == [(0.0, 0), (0.62, 1)]
    assert note == "0.73 s: after the slide's end at 0.7 s; 0.45 s: no snapshot in the file"
    shown, note = snapshot_panels([0.0, 0.4505, 0.62, 0.725], times, 2.0)  # within 1 ms, and 5 ms off
    assert shown == [(0.0, 0), (0.45, 1), (0.62, 2)] and note == "0.73 s: no snapshot in the file"
