"""Result files: mesh round trip, CF attributes, atomic writes."""

import subprocess
import sys

import numpy as np
import xarray as xr

from capslide.fem.mesh import CapMeshSpec, cap_mesh
from capslide.io.reading import read_mesh
from capslide.io.results import mesh_dataset, write_netcdf

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
    assert "Q2 cells" in res.stdout  # the paper preset
    res = run("figure", "cap_setup", "--input", out, "-o", tmp_path / "setup.png")
    assert res.returncode == 0, res.stderr
    assert (tmp_path / "setup.png").stat().st_size > 20000
    res = run("mesh", PAPER_CONFIG, "--set", "mesh.band_half_width=40", "-o", tmp_path / "bad.nc")
    assert res.returncode == 2 and "mesh.band_half_width = 40 is not allowed here" in res.stderr
    assert not (tmp_path / "bad.nc").exists()
    res = run("figure", "cap_setup", "-o", tmp_path / "x.png")
    assert res.returncode == 2 and "--input" in res.stderr


def test_case_files_and_collect(tmp_path, paper_config, capsys):
    import warnings

    from capslide.config import apply_overrides, validate
    from capslide.driver.case import run_case
    from capslide.io.results import case_dataset, collect
    from capslide.params import Parameters

    paths = []
    for sets in (["friction.model=DI", "loading.ubar_max=0.3"], ["friction.model=EA", "friction.s_cut=0", "loading.ubar_max=0.6",
                                                                   "loading.preload=-0.1"]):
        cfg = validate(apply_overrides(paper_config, ["mesh.size=32", "output.snapshot_ubar=[0, 0.3]", *sets]))
        res = run_case(Parameters.from_config(cfg))
        paths.append(write_netcdf(case_dataset(res), tmp_path / f"{len(paths)}.nc"))
    out = write_netcdf(collect(paths), tmp_path / "cases.nc")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        for path in [*paths, out]:
            with xr.open_dataset(path) as ds:
                for name, var in ds.variables.items():
                    assert "units" in var.attrs and "long_name" in var.attrs, (path, name)
                for name in ("phase", "slip_state", "status"):
                    if name in ds:
                        assert "flag_values" in ds[name].attrs and "flag_meanings" in ds[name].attrs
                assert ds.attrs["Conventions"].startswith("CF-") and "software_version" in ds.attrs
                assert "config_yaml" in ds.attrs
    with xr.open_dataset(paths[0]) as c0, xr.open_dataset(out) as ds:
        assert c0.attrs["status"] == "completed"
        np.testing.assert_allclose(c0["snapshot_ubar"], [0.0, 0.3])
        assert c0["u_node"].shape == (2, c0.sizes["node"]) and c0["I1_sigma"].shape == (2, c0.sizes["cell"])
        assert ds.sizes["case"] == 2
        assert list(ds["model"].values) == ["DI", "EA"] and np.isnan(ds["s_cut"][0]) and ds["s_cut"][1] == 0
        np.testing.assert_allclose(ds["preload"], [0.0, -0.1])
        n0 = int(ds["n_steps"][0])
        np.testing.assert_allclose(ds["Ft"][0, :n0], c0["Ft"])
        if n0 < ds.sizes["step"]:
            assert np.isnan(ds["Ft"][0, n0:]).all()  # padded
        assert list(ds["status"].values) == [0, 0]
    # inspect reads all three kinds of files capslide writes
    from capslide.cli import main

    for path, first_words in ((out, "case "), (paths[0], "status ")):
        capsys.readouterr()
        assert main(["inspect", str(path)]) == 0
        assert capsys.readouterr().out.startswith(first_words)
