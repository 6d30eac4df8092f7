"""The catalog of output variables (capslide.io.catalog) is the one list: the case files and the collected cube
hold exactly its variables, each read from a step-record field that exists, and docs/data.md names every one."""

import re
from dataclasses import fields

import pytest

import capslide
from capslide.io.catalog import VARIABLES, cube_step_coordinates, cube_step_variables
from capslide.loadpath.measures import StepRecord

from conftest import PAPER_CONFIG, ROOT

SHORT = {"preset": "fast", "mesh": {"size": 32}, "loading": {"ubar_max": 0.4}, "output": {"checkpoint_every": 0}}


@pytest.fixture(scope="module")
def case():
    return capslide.run(capslide.load_config(PAPER_CONFIG, **SHORT))


def test_every_record_field_of_the_catalog_exists():
    names = {f.name for f in fields(StepRecord)}
    assert {v.record for v in VARIABLES if v.record} <= names
    assert all(len(v.long_name) <= 40 for v in VARIABLES)
    assert len({v.name for v in VARIABLES}) == len(VARIABLES)


def test_a_case_file_holds_exactly_the_catalog(case):
    on_steps = {n for n, var in case.variables.items() if var.dims and var.dims[0] == "step" and n != "step"}
    scalars = {n for n, var in case.data_vars.items() if var.ndim == 0}
    expected = {v.name for v in VARIABLES if v.dims and v.present not in ("velocity", "3d")}
    assert on_steps == expected
    assert scalars == {v.name for v in VARIABLES if not v.dims}
    for v in VARIABLES:
        if v.name in case:
            assert case[v.name].attrs["long_name"] == v.long_name, v.name


def test_the_cube_keeps_what_the_catalog_says(case, tmp_path):
    case.to_netcdf(tmp_path / "DI_Fn+0.000.nc")
    cube = capslide.collect([tmp_path / "DI_Fn+0.000.nc"])
    three_d = {v.name for v in VARIABLES if v.present == "3d"}  # a 2D study's cube: without them
    kept = (set(cube_step_variables()) - three_d) | (set(cube_step_coordinates()) - {"time"})  # quasi-static: no time
    assert {n for n, var in cube.variables.items() if var.dims == ("model", "preload", "step")} == kept
    assert {"base_force_x", "base_force_y"} <= set(cube.data_vars)  # once dropped by a list that missed them


def test_docs_data_names_every_variable():
    text = (ROOT / "docs" / "data.md").read_text()
    named = set(re.findall(r"`([A-Za-z_][A-Za-z0-9_]*)`", text))
    assert not [v.name for v in VARIABLES if v.name not in named]
