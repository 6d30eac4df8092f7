"""Result files: mesh round trip, CF attributes, atomic writes."""

import subprocess
import sys

import numpy as np
import xarray as xr

from capslide.mesh import CapMeshSpec, cap_mesh
from capslide.results import mesh_dataset, read_mesh, write_netcdf
from conftest import PAPER_CONFIG


def test_mesh_round_trip(tmp_path, paper_config):
    mesh = cap_mesh(CapMeshSpec(R=47.1, H=10.0, h0=0.2, band_half_width=8.0, element="Q2"))
    path = write_netcdf(mesh_dataset(mesh, paper_config), tmp_path / "m.nc")
    back = read_mesh(path)
    assert back.element == "Q2"
    np.testing.assert_array_equal(back.nodes, mesh.nodes)
    np.testing.assert_array_equal(back.cells, mesh.cells)
    np.testing.assert_array_equal(back.surface_segments, mesh.surface_segments)
    np.testing.assert_array_equal(back.base, mesh.base)
    with xr.open_dataset(path) as ds:
        for name, var in ds.variables.items():
            assert "units" in var.attrs and "long_name" in var.attrs, name
        assert ds.attrs["Conventions"].startswith("CF-")
        assert ds.attrs["material.E"] == 2e6 and ds.attrs["mesh.band_half_width"] == "null"
        assert "friction:" in ds.attrs["config_yaml"]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["m.nc"]  # no temporary left


def test_mesh_cli_and_figure(tmp_path):
    out = tmp_path / "mesh.nc"
    run = lambda *a: subprocess.run([sys.executable, "-m", "capslide", *map(str, a)], capture_output=True, text=True)  # noqa: E731
    res = run("mesh", PAPER_CONFIG, "--set", "mesh.size=8", "-o", out)
    assert res.returncode == 0, res.stderr
    assert "Q1 cells" in res.stdout
    res = run("figure", "cap_setup", "--input", out, "-o", tmp_path / "setup.png")
    assert res.returncode == 0, res.stderr
    assert (tmp_path / "setup.png").stat().st_size > 20000
    res = run("mesh", PAPER_CONFIG, "--set", "mesh.band_half_width=40", "-o", tmp_path / "bad.nc")
    assert res.returncode == 2 and "does not fit" in res.stderr
    assert not (tmp_path / "bad.nc").exists()
    res = run("figure", "cap_setup", "-o", tmp_path / "x.png")
    assert res.returncode == 2 and "--input" in res.stderr
