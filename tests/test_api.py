"""The Python interface (capslide.load_config / run / open_case / open_cases): typed overrides, the same refusals
and the same numbers as the command line."""

import math

import numpy as np
import pytest
import xarray as xr

import capslide
from capslide.cli import main
from capslide.config import ConfigError

from conftest import PAPER_CONFIG

# no checkpoints: a save renews the linear solver's factorization (so that a resumed run repeats the arithmetic),
# which moves the history by round-off (1e-13) against a run that never saves
SHORT = {"preset": "fast", "mesh": {"size": 32}, "loading": {"ubar_max": 0.6}, "output": {"checkpoint_every": 0}}


def test_overrides_are_typed_values_merged_into_their_section():
    cfg = capslide.load_config(PAPER_CONFIG, preset="fast", friction={"model": "EA", "s_cut": 0.0},
                               settings={"loading.preload": -0.1})
    assert cfg["friction"]["model"] == "EA" and cfg["friction"]["s_cut"] == 0.0
    assert cfg["friction"]["g_cut_DI_over_g_max"] == 1.0  # the rest of the section stays
    assert cfg["loading"]["preload"] == -0.1 and cfg["mesh"]["element"] == "Q1"  # the fast preset


@pytest.mark.parametrize("overrides, words", [
    ({"friction": {"s_cut": math.nan}}, ["friction.s_cut = nan"]),
    ({"friction": {"s_cutt": 1.0}}, ["unknown key 'friction.s_cutt'"]),
    ({"settings": {"material.nu": 0.4999}}, ["material.nu = 0.4999", "locks"]),
    ({"loading": "fast"}, ["loading"]),
])
def test_bad_overrides_raise_one_line(overrides, words):
    with pytest.raises(ConfigError) as err:
        capslide.load_config(PAPER_CONFIG, **overrides)
    assert len(str(err.value).splitlines()) == 1
    for word in words:
        assert word in str(err.value)


def test_run_refuses_a_case_beyond_the_limits_before_computing():
    cfg = capslide.load_config(PAPER_CONFIG, mesh={"size": 0.003})
    with pytest.raises(ConfigError, match="limits.max_dofs"):
        capslide.run(cfg)


def test_run_gives_the_case_file_of_the_command_line(tmp_path):
    """The same configuration through the API and through ``capslide run``: the same steps, bit for bit."""
    case = capslide.run(capslide.load_config(PAPER_CONFIG, **SHORT))
    out = tmp_path / "case.nc"
    assert main(["run", str(PAPER_CONFIG), "--set", "preset=fast", "--set", "mesh.size=32",
                 "--set", "loading.ubar_max=0.6", "--set", "output.checkpoint_every=0", "-q", "-o", str(out)]) == 0
    opened = capslide.open_case(out)
    assert case.attrs["status"] == opened.attrs["status"] == "completed"
    assert case.sizes["step"] == opened.sizes["step"] > 10
    for name in ("Ft", "Fn", "area", "ubar", "traction_n"):
        np.testing.assert_array_equal(case[name].values, opened[name].values, err_msg=name)
    assert capslide.config_of(case) == capslide.config_of(opened)
    assert capslide.config_of(case)["loading"]["ubar_max"] == 0.6
    # what a notebook does next: plot against the sliding distance, save, open again
    case.Ft.plot(x="ubar")
    case.to_netcdf(tmp_path / "again.nc")
    with xr.open_dataset(tmp_path / "again.nc") as again:
        np.testing.assert_array_equal(again.Ft.values, case.Ft.values)


def test_config_of_a_collected_dataset_names_the_case():
    cube = xr.Dataset({"config_yaml": (("model", "preload"), np.array([["friction: {model: DI}\n", ""]], dtype=object))},
                      coords={"model": ["DI"], "preload": [0.0, 0.288]})
    assert capslide.config_of(cube, model="DI", preload=0.0) == {"friction": {"model": "DI"}}
    with pytest.raises(KeyError, match="no case of model 'DI' at preload 0.288"):
        capslide.config_of(cube, model="DI", preload=0.288)  # absent from the study
    with pytest.raises(KeyError, match="'EA'"):
        capslide.config_of(cube, model="EA", preload=0.0)
    with pytest.raises(ValueError, match="name one by model and preload"):
        capslide.config_of(cube)


def test_the_slide_helper_indexes_the_forward_slide_by_ubar():
    """slide(): the slide steps up to the largest ubar, ubar as the dimension; a slide back is left out."""
    case = capslide.run(capslide.load_config(PAPER_CONFIG, **{**SHORT, "loading": {"ubar_max": 0.6, "slide_back": True}}))
    s = capslide.slide(case)
    assert s["Ft"].dims == ("ubar",) and np.all(np.diff(s.ubar.values) > 0) and float(s.ubar.max()) == 0.6
    back = case.isel(step=(case.phase == 2).values)
    assert back.sizes["step"] > s.sizes["ubar"]  # the slide back's steps exist, and are left out
    assert float(s.Ft.sel(ubar=0.6)) == float(case.Ft.where(case.ubar == 0.6).max())
    with pytest.raises(ValueError, match="one case"):
        capslide.slide(case.assign_coords(phase=(("model", "step"), np.stack([case.phase.values] * 2))))


def test_to_si_gives_units_that_pint_reads():
    """to_si multiplies each normalized variable by the scale of its units; pint-xarray then quantifies them."""
    import pint_xarray  # noqa: F401

    case = capslide.run(capslide.load_config(PAPER_CONFIG, **SHORT))
    assert case.Ft.attrs["units"] == "2 N/m" and case.area.attrs["units"] == "1e-06 m"
    assert len(case.attrs) < 40 and "friction_model" in case.attrs and "config_yaml" in case.attrs  # pruned, not lost
    assert case.Ft.attrs["long_name"] == "friction force Ft" and "sliding direction" in case.Ft.attrs["description"]
    si = capslide.to_si(case[["Ft", "area", "newton_iterations"]])
    np.testing.assert_array_equal(si.Ft.values, 2.0 * case.Ft.values)
    assert si.Ft.attrs["units"] == "N/m" and si.newton_iterations.attrs["units"] == case.newton_iterations.attrs["units"]
    q = si.pint.quantify()
    assert float(q.Ft.pint.to("mN/m").max().pint.magnitude) == pytest.approx(2000.0 * float(case.Ft.max()))
    assert str(q.area.pint.units) == "meter"
