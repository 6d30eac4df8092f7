"""Result files: mesh round trip, the layout of case files and of the collected cube (docs/data.md), CF attributes
and units, atomic writes."""

import subprocess
import sys

import numpy as np
import pytest
import xarray as xr

from capslide.fem.mesh import CapMeshSpec, cap_mesh
from capslide.io.reading import ResultFileError, read_mesh
from capslide.io.results import mesh_dataset, write_netcdf

from cf_checks import check_cf
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
        check_cf(ds, "mesh")
        assert ds.attrs["material_E"] == 2e6 and "mesh_band_half_width" not in ds.attrs  # key parameters only
        assert not [k for k, v in ds.attrs.items() if v in ("null", "[]")] and len(ds.attrs) < 40
        assert "friction:" in ds.attrs["config_yaml"] and ds["X_node"].attrs["units"] == "1e-06 m"
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


def test_case_files_and_the_collected_cube(tmp_path, paper_config, capsys):
    """Case files with coordinates where a user plots against them; the collected file a model x preload x step cube
    that selects by name; both CF-valid with units UDUNITS converts."""
    from capslide.cli import main
    from capslide.config import apply_overrides, validate
    from capslide.driver.case import run_case
    from capslide.io.cube import collect
    from capslide.io.results import case_dataset
    from capslide.params import Parameters

    paths = []
    for name, sets in (("DI_Fn+0.000", ["friction.model=DI", "loading.ubar_max=0.3"]),
                       ("EA0_Fn-0.100", ["friction.model=EA", "friction.s_cut=0", "loading.ubar_max=0.6",
                                         "loading.preload=-0.1"])):
        cfg = validate(apply_overrides(paper_config, ["mesh.size=32", "output.snapshot_ubar=[0, 0.3]", *sets]))
        res = run_case(Parameters.from_config(cfg))
        paths.append(write_netcdf(case_dataset(res), tmp_path / f"{name}.nc"))
    out = write_netcdf(collect(paths), tmp_path / "cases.nc")
    with xr.open_dataset(paths[0]) as case, xr.open_dataset(out) as cube:
        check_cf(case, "case")
        check_cf(cube, "cube")
        assert case.attrs["status"] == "completed" and case.attrs["friction_model"] == "DI"
        assert {"ubar", "h", "phase", "X_reference", "X_node", "Y_node", "snapshot_ubar"} <= set(case.coords)
        case.Ft.plot(x="ubar")  # the README's first example
        np.testing.assert_allclose(case["snapshot_ubar"], [0.0, 0.3])
        assert case.u_node.sel(snapshot_ubar=0.3).shape == (case.sizes["node"],)
        assert case["I1_sigma"].dims == ("snapshot_ubar", "cell")
        assert case["Ft"].attrs["units"] == "2 N/m" and case["gap"].attrs["units"] == "1e-06 m"
        assert cube.sizes == {"model": 2, "preload": 2, "step": max(xr.open_dataset(p).sizes["step"] for p in paths)}
        assert list(cube["model"].values) == ["DI", "EA0"] and list(cube["preload"].values) == [-0.1, 0.0]
        assert list(cube["friction_model"].values) == ["DI", "EA"]
        assert np.isnan(float(cube["s_cut"].sel(model="DI"))) and float(cube["s_cut"].sel(model="EA0")) == 0.0
        di = cube.sel(model="DI", preload=0.0)
        n = int(di["n_steps"])
        np.testing.assert_array_equal(di["Ft"].values[:n], case["Ft"].values)
        np.testing.assert_array_equal(di["ubar"].values[:n], case["ubar"].values)
        assert np.isnan(di["Ft"].values[n:]).all()  # padded
        assert np.isnan(float(cube["peak_Ft"].sel(model="DI", preload=-0.1)))  # no such case
        assert int(cube["status"].sel(model="DI", preload=-0.1)) == -1 and int(cube["status"].sel(model="DI", preload=0.0)) == 0
        assert cube.peak_Ft.to_pandas().shape == (2, 2)
    # a case in other units (E = 3 MPa: forces in 3 N/m) does not join the cube, which keeps the first case's units
    cfg = validate(apply_overrides(paper_config, ["mesh.size=32", "loading.ubar_max=0.3", "material.E=3e6"]))
    other = write_netcdf(case_dataset(run_case(Parameters.from_config(cfg))), tmp_path / "EA1_Fn+0.000.nc")
    with pytest.raises(ResultFileError, match=r"EA1_Fn\+0.000.nc' has Fn in '3 N/m', '.*DI_Fn\+0.000.nc' in '2 N/m'"):
        collect([paths[0], other])
    # inspect reads all three kinds of files capslide writes
    for path, first_words in ((out, "model "), (paths[0], "status ")):
        capsys.readouterr()
        assert main(["inspect", str(path)]) == 0
        printed = capsys.readouterr().out
        assert printed.startswith(first_words)
    with xr.open_dataset(paths[0]) as case:  # the case's scalars also in SI: Ft in E L0 = 2 N/m
        line = next(row for row in printed.splitlines() if row.startswith("peak_Ft "))
        assert line.endswith(f"(peak Ft)  = {float(case.peak_Ft) * 2.0:.6g} N/m"), line
