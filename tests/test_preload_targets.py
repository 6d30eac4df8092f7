"""Where the preload's path lands: loading for compressive and zero preloads, retraction from retract_from for
tensile ones, and the forces of loading.preload_via on the way (capslide.loadpath.preload_targets)."""

from types import SimpleNamespace

import pytest

from capslide.loadpath.preload_targets import preload_targets, previous_target

STUDY = (-0.288, -0.144, 0.0, 0.144, 0.288)


def loading(preload, via=STUDY, retract_from=-0.288):
    return SimpleNamespace(preload=preload, retract_from=retract_from, preload_via=tuple(via))


@pytest.mark.parametrize(("preload", "targets"), [
    (0.0, [0.0]),
    (-0.144, [0.0, -0.144]),
    (-0.288, [0.0, -0.144, -0.288]),
    (0.144, [0.0, -0.144, -0.288, 0.144]),  # loading to retract_from, then retraction
    (0.288, [0.0, -0.144, -0.288, 0.144, 0.288]),
    (-0.5, [0.0, -0.144, -0.288, -0.5]),
    (0.2, [0.0, -0.144, -0.288, 0.144, 0.2]),
])
def test_the_path_lands_on_the_study_preloads_it_passes(preload, targets):
    assert preload_targets(loading(preload), 0.322) == targets  # the paper cap's approach ends at Fn* = +0.322


def test_without_via_the_path_goes_straight_to_the_preload():
    for preload, targets in ((0.0, [0.0]), (-0.288, [-0.288]), (0.144, [-0.288, 0.144]), (0.288, [-0.288, 0.288])):
        assert preload_targets(loading(preload, via=()), 0.322) == targets


def test_a_tensile_force_on_the_loading_is_not_landed_on():
    """+0.144 is a preload reached by retraction: the loading from +0.322 passes it on another branch."""
    assert 0.144 not in preload_targets(loading(-0.288), 0.322)[:-1]


def test_forces_beyond_the_approach_end_are_not_passed():
    """An approach that ends compressive (at -0.2) loads on to -0.288 without passing 0 or -0.144; the way up to 0
    passes -0.144, as the path to -0.144 itself goes."""
    assert preload_targets(loading(-0.288), -0.2) == [-0.288]
    assert preload_targets(loading(0.0), -0.2) == [-0.144, 0.0]
    assert preload_targets(loading(-0.144), -0.2) == [-0.144]


def test_an_approach_that_ends_below_retract_from_goes_up_without_retracting_from_it():
    assert preload_targets(loading(0.144), -0.4) == [-0.288, -0.144, 0.0, 0.144]
    assert preload_targets(loading(0.144), -0.2) == [-0.288, 0.144]


def test_the_path_to_a_preload_begins_with_the_path_to_every_target_before_it():
    for approached in (0.322, -0.2, -0.4):
        for p in (-0.5, *STUDY, 0.2):
            targets = preload_targets(loading(p), approached)
            for i, t in enumerate(targets[:-1]):
                assert preload_targets(loading(t), approached) == targets[:i + 1], (approached, p, t)


def test_the_study_states_form_one_chain():
    chain = {p: previous_target(loading(p), STUDY) for p in STUDY}
    assert chain == {0.0: None, -0.144: 0.0, -0.288: -0.144, 0.144: -0.288, 0.288: 0.144}
    # without via only the tensile states go on, from retract_from, as before
    assert {p: previous_target(loading(p, via=()), STUDY) for p in STUDY} == \
           {0.0: None, -0.144: None, -0.288: None, 0.144: -0.288, 0.288: -0.288}
    assert previous_target(loading(-0.288), [0.0, 0.288]) == 0.0  # the last computed state on the way
