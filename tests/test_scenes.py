"""Packaged scenes: the paper's configuration, the presets and the verification scenes ship with the package, so
they work from any folder; config/ in the repository links to them (issue 41, item 1)."""

import os
import shutil
import subprocess
import sys
import zipfile

import pytest

import capslide
from capslide.config import ConfigError, load_config, scene_path, scenes

from conftest import ROOT, default_sigint


def test_the_paper_study_is_a_packaged_scene_from_any_folder(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    assert scenes() == ["cap", "experiment", "hertz", "jkr", "sphere", "sphere_dugdale3", "sphere_hertz", "sphere_md3",
                        "sphere_md5"]
    config = capslide.load_config("cap", preset="fast")
    assert config == load_config([ROOT / "config" / "config.yaml"], ["preset=fast"])
    assert config["mesh"]["size"] == 32.0 and config["study"]["preloads"] == [-0.288, 0.0, 0.288]


def test_config_links_to_the_package_and_holds_no_copy():
    for name, target in (("config.yaml", "cap.yaml"), ("scenes", ""), ("presets", "presets")):
        link = ROOT / "config" / name
        assert link.is_symlink(), name
        assert link.resolve() == (ROOT / "src" / "capslide" / "scenes" / target).resolve()


def test_a_scene_case_runs_from_outside_the_clone(tmp_path):
    res = subprocess.run([sys.executable, "-m", "capslide", "run", "--scene", "cap", "--set", "preset=fast", "--set",
                          "loading.ubar_max=0.2", "-q", "-o", "c.nc"], cwd=tmp_path, capture_output=True, text=True,
                         preexec_fn=default_sigint, env={**os.environ, "PYTHONPATH": ""})
    assert res.returncode == 0 and (tmp_path / "c.nc").exists(), res.stderr


@pytest.mark.parametrize("args, words", [
    (["--scene", "capp"], "packaged scenes (cap, experiment, hertz, jkr, sphere, sphere_dugdale3, sphere_hertz, "
                          "sphere_md3, sphere_md5); did you mean 'cap'?"),
    ([], "no configuration: give a config file or a packaged scene"),
    (["--scene", "cap", "--set", "friction.s_cutt=1"], "did you mean 'friction.s_cut'?"),
])
def test_a_bad_scene_or_key_is_one_line_with_a_hint(tmp_path, args, words):
    res = subprocess.run([sys.executable, "-m", "capslide", "run", *args, "-o", "x.nc"], cwd=tmp_path,
                         capture_output=True, text=True)
    err = res.stderr.strip()
    assert res.returncode == 2 and "\n" not in err and words in err, err
    assert not list(tmp_path.iterdir())


def test_an_unknown_scene_name_in_python_names_the_scenes():
    with pytest.raises(ConfigError, match="did you mean 'hertz'"):
        scene_path("herz")


def test_the_wheel_ships_the_scenes(tmp_path):
    """The wheel built from the checkout holds every scene and preset; the paper's study loads from it alone."""
    source = tmp_path / "source"  # a copy: an in-tree build would leave build/ in the checkout
    shutil.copytree(ROOT / "src", source / "src", ignore=shutil.ignore_patterns("__pycache__", "*.egg-info"))
    for name in ("pyproject.toml", "README.md", "LICENSE"):
        shutil.copy(ROOT / name, source / name)
    res = subprocess.run([sys.executable, "-m", "pip", "wheel", str(source), "--no-deps", "-q", "-w", str(tmp_path)],
                         capture_output=True, text=True)
    assert res.returncode == 0, res.stderr[-2000:]
    (wheel,) = tmp_path.glob("capslide-*.whl")
    names = set(zipfile.ZipFile(wheel).namelist())
    for name in ("cap", "hertz", "jkr", "sphere", "sphere_hertz", "experiment", "presets/fast", "presets/paper",
                 "presets/reference"):
        assert f"capslide/scenes/{name}.yaml" in names, name
    zipfile.ZipFile(wheel).extractall(tmp_path / "site")
    check = ("import capslide; assert capslide.__file__.startswith(%r); "
             "print(capslide.load_config('cap', preset='fast')['preset'])")
    res = subprocess.run([sys.executable, "-c", check % str(tmp_path / "site")], cwd=tmp_path, capture_output=True,
                         text=True, env={**os.environ, "PYTHONPATH": str(tmp_path / "site")})
    assert res.returncode == 0 and res.stdout.strip() == "fast", res.stderr


def test_the_3d_verification_sweeps_save_inside_their_legs():
    """`snakemake verification3d` sweeps these scenes for hours, a leg of edge-controlled steps taking longer than a
    session may last: every adhesive one saves inside its legs (verification.checkpoint_every), so a rerun goes on
    from its last save, not from its last load."""
    import re

    from capslide.params import Parameters

    rules = (ROOT / "workflow" / "rules" / "verification.smk").read_text()
    names = re.findall(r'"(\w+)"', re.search(r"VERIFICATION_3D_SCENES = \[(.*)\]", rules)[1])
    adhesive = [Parameters.from_config(load_config([scene_path(n)])) for n in names]
    adhesive = {n: p for n, p in zip(names, adhesive) if not p.contact.repulsion_only}
    assert sorted(adhesive) == ["sphere_dugdale3", "sphere_md3", "sphere_md5"]
    assert [n for n, p in adhesive.items() if not p.verification.checkpoint_every > 0] == []
