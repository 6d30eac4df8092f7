"""One study expansion: the study, stability and convergence specs -> run ids and overrides, validated."""

import pytest
import yaml

from capslide.config import ConfigError, apply_overrides, apply_settings, load_config, override_args
from capslide.studies.expansion import check_runs, runs

from conftest import PAPER_CONFIG, ROOT


def test_the_paper_study_expands_to_fifteen_named_cases():
    study = load_config([PAPER_CONFIG])["study"]
    cases = runs(study, "study")
    assert len(cases) == 15 and list(cases)[:3] == ["DI_Fn-0.288", "DI_Fn+0.000", "DI_Fn+0.288"]
    assert cases["DI_Fn+0.000"] == {"friction.model": "DI", "friction.g_cut_DI_over_g_max": 1.0, "loading.preload": 0.0}
    assert cases["EA0_Fn-0.144"] == {"friction.model": "EA", "friction.s_cut": 0.0, "loading.preload": -0.144,
                                     "loading.stop_at_onset": True}
    check_runs(cases, [PAPER_CONFIG])


def test_preloads_that_share_a_file_name_are_refused():
    study = {"models": {"DI": {"friction.model": "DI"}}, "preloads": [0.0, 0.0001]}
    with pytest.raises(ConfigError, match=r"study.preloads: preloads 0.0 and 0.0001 both name the case file DI_Fn\+0.000.nc"):
        runs(study, "study")
    # an onset preload equal to a full one is the same case, not a collision
    assert list(runs({**study, "preloads": [0.0], "onset_preloads": [0.0]}, "study")) == ["DI_Fn+0.000"]


def test_a_bad_key_in_a_run_is_refused_with_the_run_named():
    cases = runs({"models": {"DI": {"friction.modle": "DI"}}, "preloads": [0.0]}, "study")
    with pytest.raises(ConfigError, match=r"run DI_Fn\+0.000: unknown key 'friction.modle'"):
        check_runs(cases, [PAPER_CONFIG])
    with pytest.raises(ConfigError, match=r"run DI_Fn\+0.000: friction.s_cut = 3 is not allowed"):
        check_runs({"DI_Fn+0.000": {"friction.s_cut": 3}}, [PAPER_CONFIG])
    check_runs({"bad": {"friction.s_cut": 3}}, [PAPER_CONFIG], skip=["bad"])  # a case meant to be rejected


def test_the_studies_of_the_repository_expand_and_validate():
    stability = yaml.safe_load((ROOT / "config" / "stability.yaml").read_text())
    hard = runs(stability, "stability")
    check_runs(hard, [PAPER_CONFIG], skip=[n for n, c in stability["cases"].items() if c["expect"] == "rejected"])
    with pytest.raises(ConfigError, match="run g_reg_1.5: adhesion.g_reg_over_g_eq"):
        check_runs(hard, [PAPER_CONFIG])
    conv = runs(yaml.safe_load((ROOT / "config" / "convergence.yaml").read_text()), "convergence")
    assert len(conv) == 52 and conv["DI_Fn+0.000/default"]["mesh.size"] == 8
    assert conv["EA0_Fn-0.288/size-0.5"]["loading.preload"] == -0.288
    check_runs(conv, [PAPER_CONFIG])


def test_override_strings_read_back_as_the_values():
    settings = {"friction.model": "EA", "friction.s_cut": 0.0, "loading.preload": -0.144, "loading.stop_at_onset": True,
                "output.snapshot_ubar": [0.0, 1.5], "mesh.band_half_width": None, "preset": "fast", "mesh.size": 8}
    base = load_config([PAPER_CONFIG])
    assert apply_overrides(base, override_args(settings)) == apply_settings(base, settings)
    assert override_args({"friction.model": "EA", "preset": "null"})[1] == 'preset="null"'  # quoted where YAML would not


def test_unknown_kind_and_non_mapping_specs():
    with pytest.raises(ValueError, match="unknown kind"):
        runs({}, "sweep")
    with pytest.raises(ConfigError, match="must be a mapping"):
        runs([1, 2], "stability")


def test_a_run_needing_a_missing_library_is_refused_unless_its_jobs_refuse_it(monkeypatch):
    import capslide.model.cost as cost

    monkeypatch.setattr(cost, "mkl_runtime", lambda: None)
    pardiso = {"r": {"solver.linear": "lu_krylov", "solver.factorization": "pardiso"}}
    with pytest.raises(ConfigError, match="run r: solver.factorization = 'pardiso' needs Intel MKL"):
        check_runs(pardiso, [PAPER_CONFIG])
    check_runs(pardiso, [PAPER_CONFIG], libraries=False)  # the experiment3d rules: parsed by every run of the workflow
