"""Bad inputs of every kind end with exit 2 and one line naming the key or file and the value: no traceback, no file
left behind, nothing computed. In this process (capslide.cli.main), well under a minute for the whole suite.

Families: every key of the configuration schema with NaN, +-inf, wrong types and values past its bounds; config
files; command lines; result files; study specs (the workflow's expansion, validated when Snakemake parses);
configurations beyond the cost limits or the contact band.
"""

from __future__ import annotations

import pytest

from capslide.cli import main
from capslide.config import ConfigError, schema
from capslide.studies.expansion import check_runs, runs

from conftest import PAPER_CONFIG

SKIP = {"presets", "study.models"}  # maps of user-chosen names: their values are checked where they are used
YAML_TOKEN = {".nan": "nan", ".inf": "inf", "-.inf": "-inf"}


def _keys(spec, prefix=""):
    for name, sub in spec.get("properties", {}).items():
        key = f"{prefix}{name}"
        if key in SKIP:
            continue
        if sub.get("type") == "object" and "properties" in sub:
            yield from _keys(sub, f"{key}.")
        else:
            yield key, sub


def _bad_values(spec) -> list[str]:
    """YAML texts that the schema (or the finiteness check) must refuse for a key of this spec."""
    kinds = spec.get("type") if isinstance(spec.get("type"), list) else [spec.get("type")]
    if "enum" in spec:
        return ["bogus", "1", ".nan"]
    if "array" in kinds:
        return ["1.0", "[.nan]", "[0.5, .inf]", "[-.inf]", "[abc]", "{a: 1}"]
    if "boolean" in kinds:
        return ["maybe", "2", ".nan"]
    if "string" in kinds:
        return ["[1, 2]", ".inf"]
    out = [".nan", ".inf", "-.inf", "abc", "[1]"]
    if "integer" in kinds:
        out.append("2.5")
    for bound, step in (("exclusiveMinimum", 0), ("minimum", -1), ("maximum", 1), ("exclusiveMaximum", 0)):
        if bound in spec:
            value = spec[bound] + step
            out.append(str(int(value)) if float(value).is_integer() and "integer" in kinds else repr(float(value)))
    return out


CONFIG_VALUES = [(key, text) for key, spec in _keys(schema()) for text in _bad_values(spec)]


def _one_line(capsys, code, words):
    out, err = capsys.readouterr()
    lines = err.strip().splitlines()
    assert code == 2, (code, err)
    assert len(lines) == 1 and lines[0].startswith("capslide: error: "), err
    for word in words:
        assert word in lines[0], (word, lines[0])


@pytest.mark.parametrize("key, text", CONFIG_VALUES, ids=[f"{k}={t}" for k, t in CONFIG_VALUES])
def test_every_config_key_refuses_bad_values(capsys, key, text):
    code = main(["constants", str(PAPER_CONFIG), "--set", f"{key}={text}"])
    last = text.strip("[]{}").split(",")[-1].split(":")[0].strip()  # the bad item of a list (the last)
    _one_line(capsys, code, [key, YAML_TOKEN.get(last, last)])


def test_the_config_family_is_large():
    assert len(CONFIG_VALUES) >= 200


CONFIG_FILES = [  # (file text or bytes, words of the message)
    (b"\x89PNG\r\n\x1a\n\x00\xff", ["not a text (UTF-8) file"]),
    ("material: [1, 2\n", ["line"]),
    ("- 1\n- 2\n", ["must hold a mapping"]),
    ("friction:\n  s_cut: 1\n  s_cut: 0\n", ["duplicate key 's_cut'", "line 3"]),
    ("material:\n  E: 2.0e+6\n  E: 3.0e+6\n  nu: 0.4\n", ["duplicate key 'E'"]),
    ("material: !!python/object/apply:os.system ['true']\n", ["line"]),
    ("nosuchsection: {a: 1}\n", ["unknown key 'nosuchsection'"]),
    ("friction: 3\n", ["friction", "must be a section"]),
    ("friction:\n  s_cut: .nan\n", ["friction.s_cut = nan"]),
    ("output:\n  snapshot_ubar: [0, 1, .inf]\n", ["output.snapshot_ubar[2] = inf"]),
    ("study:\n  preloads: [0, -.inf]\n", ["study.preloads[1] = -inf"]),
    ("verification:\n  loads: [.nan]\n", ["verification.loads[0] = nan"]),
]


@pytest.mark.parametrize("content, words", CONFIG_FILES, ids=[str(w[0]) for _, w in CONFIG_FILES])
def test_bad_config_files(capsys, tmp_path, content, words):
    path = tmp_path / "bad.yaml"
    path.write_bytes(content if isinstance(content, bytes) else content.encode())
    _one_line(capsys, main(["constants", str(PAPER_CONFIG), str(path)]), ["bad.yaml", *words] if "line" in words else words)


def _result_files(tmp_path):
    """A text file, an empty file, a directory, a truncated netCDF, a netCDF capslide did not write."""
    import numpy as np
    import xarray as xr

    (tmp_path / "text.nc").write_text("not netCDF\n")
    (tmp_path / "empty.nc").write_bytes(b"")
    (tmp_path / "dir.nc").mkdir()
    xr.Dataset({"T": ("t", np.arange(3.0))}).to_netcdf(tmp_path / "foreign.nc")
    data = (tmp_path / "foreign.nc").read_bytes()
    (tmp_path / "truncated.nc").write_bytes(data[: len(data) // 2])
    (tmp_path / "table.csv").write_text("a,b\n1,2\n")
    rng = np.random.default_rng(0)
    big = xr.Dataset({"T": (("t", "x"), rng.normal(size=(200, 500)))}, attrs={"status": "completed"})
    big.to_netcdf(tmp_path / "damaged.nc", encoding={"T": {"zlib": True, "chunksizes": (20, 500)}})
    data = bytearray((tmp_path / "damaged.nc").read_bytes())
    data[len(data) // 2: len(data) // 2 + 64] = bytes(64)  # a compressed chunk of T zeroed
    (tmp_path / "damaged.nc").write_bytes(bytes(data))


COMMAND_LINES = [  # (argv after "capslide", words of the one-line message); {t} is a scratch directory
    (["frobnicate"], ["invalid choice", "frobnicate"]),
    (["run"], ["run", "required"]),
    (["run", "{c}", "-o", "{t}/x.nc", "--bogus"], ["unrecognized arguments", "--bogus"]),
    (["run", "{c}", "-o", "{t}/x.txt"], ["x.txt", "unsupported file type"]),
    (["run", "{c}", "-o", "{t}/dir.nc"], ["dir.nc", "is a directory"]),
    (["run", "{c}", "-o", "{t}/text.nc/x.nc"], ["text.nc", "not a directory"]),
    (["run", "{c}", "-o", "/proc/capslide/x.nc"], ["/proc", "not writable"]),
    (["run", "{t}/absent.yaml", "-o", "{t}/x.nc"], ["absent.yaml"]),
    (["run", "{t}", "-o", "{t}/x.nc"], ["cannot read config file", "Is a directory"]),
    (["run", "{c}", "--set", "noequals", "-o", "{t}/x.nc"], ["override 'noequals'"]),
    (["run", "{c}", "--set", ".a=1", "-o", "{t}/x.nc"], ["override '.a=1'"]),
    (["run", "{c}", "-o", "{t}/x.nc", "--from-state", "{t}/absent.npz"], ["absent.npz", "does not exist"]),
    (["run", "{c}", "-o", "{t}/x.nc", "--from-state", "{t}/text.nc"], ["text.nc", "cannot read normal state"]),
    (["run", "{c}", "-o", "{t}/x.nc", "--from-state", "{t}/foreign.nc"], ["foreign.nc", "cannot read normal state"]),
    (["preload", "{c}", "-o", "{t}/x.nc"], ["x.nc", "unsupported file type"]),
    (["preload", "{c}", "-o", "{t}/s.npz", "--from-state", "{t}/dir.nc"], ["dir.nc", "is a directory"]),
    (["figure", "NoSuch", "-o", "{t}/f.png"], ["unknown figure 'NoSuch'"]),
    (["figure", "Tn", "-o", "{t}/f.png"], ["Tn", "needs a CONFIG"]),
    (["figure", "Tn", "{c}", "-o", "{t}/f.jpg2"], ["f.jpg2", "unsupported file type"]),
    (["figure", "cap_xn", "-o", "{t}/f.png"], ["cap_xn", "--input CASE.nc"]),
    (["figure", "cap_PxAndAc", "-o", "{t}/f.png"], ["cap_PxAndAc", "--input CASES.nc"]),
    (["figure", "cap_setup", "-o", "{t}/f.png"], ["cap_setup", "--input MESH.nc"]),
    (["figure", "verification", "-o", "{t}/f.png"], ["verification", "--table"]),
    (["figure", "verification", "--table", "{t}/nosuch.csv", "-o", "{t}/f.png"], ["nosuch.csv", "does not exist"]),
    (["figure", "verification", "--table", "{t}/table.csv", "-o", "{t}/f.png"], ["table.csv", "not a verification table"]),
    (["pull-off", "{t}/foreign.nc", "--fraction", "2", "-o", "{t}/p.yaml"], ["--fraction", "2"]),
    (["pull-off", "{t}/foreign.nc", "--fraction", "abc", "-o", "{t}/p.yaml"], ["--fraction", "abc"]),
    (["pull-off", "{t}/foreign.nc", "--fraction", "0.5", "-o", "{t}/p.txt"], ["p.txt", "unsupported file type"]),
    (["collect", "{t}/dir.nc", "-o", "{t}/cases.nc"], ["dir.nc", "is a directory"]),
    (["collect", "{t}/absent.nc", "-o", "{t}/cases.nc"], ["absent.nc", "does not exist"]),
    (["vtk", "{t}/text.nc", "-o", "{t}/text.nc"], ["text.nc"]),
    (["verify", "{c}", "-o", "{t}/v.csv"], ["verification.loads is empty"]),
    (["verify", "{c}", "--scene", "hertz", "-o", "{t}/v.csv"], ["--scene = 'hertz'", "repulsion_only = False", "jkr scene"]),
    (["verify", "{c}", "--scene", "dmt", "-o", "{t}/v.csv"],
     ["scene = 'dmt'", "packaged scenes (cap, experiment, hertz, jkr, sphere, sphere_dugdale3, sphere_hertz, sphere_md3, "
     "sphere_md5)"]),
    (["run", "--scene", "sphere", "--set", "material.nu=0.42", "-o", "{t}/x.nc"],
     ["material.nu = 0.42", "mesh.element = H1", "locks beyond nu = 0.4", "mesh.formulation = mixed (H1/P0"]),
    (["stability", "{t}/absent.yaml", "{c}", "--cases", "{t}", "-o", "{t}/s.md"], ["absent.yaml"]),
    (["convergence", "{c}", "--cases", "{t}", "-o", "{t}/c.md"], ["config.yaml", "unknown key 'adhesion'"]),
]
RESULT_FILES = [(cmd, name, words) for name, words in (
    ("text.nc", ["cannot read netCDF file", "text.nc"]), ("empty.nc", ["cannot read netCDF file", "empty.nc"]),
    ("dir.nc", ["dir.nc", "is a directory"]), ("truncated.nc", ["cannot read netCDF file", "truncated.nc"]),
    ("absent.nc", ["cannot read netCDF file", "absent.nc"]), ("foreign.nc", ["foreign.nc"]),
    ("damaged.nc", ["damaged.nc"]),
) for cmd in (["inspect", "{f}"], ["vtk", "{f}", "-o", "{t}/vtk"], ["figure", "cap_xn", "--input", "{f}", "-o", "{t}/f.png"],
              ["figure", "cap_PxAndAc", "--input", "{f}", "-o", "{t}/f.png"],
              ["figure", "cap_setup", "--input", "{f}", "-o", "{t}/f.png"], ["collect", "{f}", "-o", "{t}/c.nc"],
              ["pull-off", "{f}", "--fraction", "0.5", "-o", "{t}/p.yaml"])
    if not (cmd[0] == "collect" and name in ("dir.nc", "absent.nc"))]
LIMITS = [  # configurations that validate but must not be computed
    (["mesh.size=0.003"], ["mesh.size = 0.003", "limits.max_dofs"]),
    (["mesh.size=0.03", "limits.max_dofs=1e9"], ["limits.max_memory_gb"]),
    (["loading.max_slide_step=1e-7", "loading.min_slide_step=1e-9"], ["loading.max_slide_step = 1e-07", "limits.max_steps"]),
    (["loading.approach_step_over_r0=1e-9"], ["loading.approach_step_over_r0 = 1e-09", "limits.max_steps"]),
    (["loading.preload=-0.288", "loading.force_step=1e-9", "loading.min_force_step=1e-10"], ["loading.force_step = 1e-09"]),
    (["loading.ubar_max=1000"], ["loading.ubar_max = 1000"]),
    (["geometry.H=0.001"], ["geometry.H = 0.001"]),
    (["geometry.R=1e6"], ["geometry.R = 1000000.0"]),
    (["mesh.band_half_width=1000"], ["mesh.band_half_width = 1000"]),
    (["material.E=1e-310"], ["material.E = 1e-310", "not computable"]),
    (["adhesion.W_adh=1e-320"], ["adhesion.W_adh = 1e-320", "not computable"]),
    (["material.nu=0.4999"], ["material.nu = 0.4999", "mesh.element = Q2", "locks"]),
    (["material.nu=0.49", "preset=fast"], ["material.nu = 0.49", "mesh.element = Q1", "locks",
                                           "use mesh.formulation = mixed", "mesh.element = Q2"]),
    (["material.nu=0.46", "mesh.element=Q1"], ["material.nu = 0.46", "Q1"]),
]


@pytest.mark.parametrize("argv, words", COMMAND_LINES, ids=[" ".join(a[:2]) + "|" + w[0] for a, w in COMMAND_LINES])
def test_bad_command_lines(capsys, tmp_path, argv, words):
    _result_files(tmp_path)
    before = sorted(tmp_path.rglob("*"))
    _one_line(capsys, main([a.format(t=tmp_path, c=PAPER_CONFIG) for a in argv]), words)
    assert sorted(tmp_path.rglob("*")) == before  # nothing written, not even a directory


@pytest.mark.parametrize("argv, name, words", RESULT_FILES, ids=[f"{a[0]} {a[1] if a[0] == 'figure' else ''} {n}"
                                                                 for a, n, _ in RESULT_FILES])
def test_bad_result_files(capsys, tmp_path, argv, name, words):
    _result_files(tmp_path)
    before = sorted(tmp_path.rglob("*"))
    _one_line(capsys, main([a.format(t=tmp_path, f=tmp_path / name) for a in argv]), words)
    assert sorted(tmp_path.rglob("*")) == before


@pytest.mark.parametrize("sets, words", LIMITS, ids=[" ".join(s) for s, _ in LIMITS])
@pytest.mark.parametrize("command", ["run", "mesh"])
def test_beyond_the_limits_nothing_is_computed(capsys, tmp_path, command, sets, words):
    if command == "mesh" and any("step" in s for s in sets):
        pytest.skip("a mesh has no steps")
    out = tmp_path / "sub" / "x.nc"
    code = main([command, str(PAPER_CONFIG), *[a for s in sets for a in ("--set", s)], "-o", str(out)])
    _one_line(capsys, code, words)
    assert list(tmp_path.iterdir()) == []


SPECS = [  # (kind, spec, words of the ConfigError)
    ("study", {"models": {"DI": {}}, "preloads": [0.0, 0.0001]}, ["both name the case file DI_Fn+0.000.nc"]),
    ("study", {"models": {"DI": {}}, "preloads": [".nan"]}, ["study.preloads[0]", "'.nan'"]),
    ("study", {"models": {"DI": {}}, "preloads": [float("nan")]}, ["preloads[0] = nan", "finite"]),
    ("study", {"models": {"DI": {}}, "onset_preloads": [float("inf")]}, ["onset_preloads[0] = inf"]),
    ("study", {"models": [1, 2]}, ["models"]),
    ("study", {"bogus": 1}, ["unknown key 'study.bogus'"]),
    ("stability", {"cases": {}}, ["cases"]),
    ("stability", {"cases": {"x": {"expect": "exploded"}}}, ["cases.x.expect = 'exploded'"]),
    ("stability", {"cases": {"x": {"expect": "completed", "check": "magic"}}}, ["cases.x.check = 'magic'"]),
    ("stability", {"cases": {"x": {"expect": "completed", "pull_off_fraction": 0.5}}}, ["needs a case named 'pull_off'"]),
    ("stability", {"cases": {"x": {"expect": "completed", "pull_off_fraction": float("nan")}}}, ["pull_off_fraction = nan"]),
    ("stability", {"cases": {"x": {"expect": "completed"}}, "time_bound_s": float("inf")}, ["time_bound_s = inf"]),
    ("stability", {"cases": {"x": {"expect": "completed", "sett": {}}}}, ["unknown key 'cases.x.sett'"]),
    ("convergence", {"cases": {"A": {}}, "sweeps": {"m": {"key": "mesh.size", "values": []}},
                     "reference": {"sweep": "m", "value": 1}}, ["sweeps.m.values"]),
    ("convergence", {"cases": {"A": {}}, "base": {"mesh.size": 8}, "sweeps": {"m": {"key": "mesh.size", "values": [8]}},
                     "reference": {"sweep": "q", "value": 8}}, ["reference.sweep = 'q'"]),
    ("convergence", {"cases": {"A": {}}, "base": {"mesh.size": 8},
                     "sweeps": {"m": {"key": "mesh.size", "values": [8, float("nan")]}},
                     "reference": {"sweep": "m", "value": 8}}, ["sweeps.m.values[1] = nan"]),
]
RUNS = [  # runs whose configuration is bad: refused by the workflow's parse-time validation, naming the run
    ({"A": {"friction.modle": "DI"}}, ["run A", "unknown key 'friction.modle'"]),
    ({"A": {"friction.s_cut": float("nan")}}, ["run A", "friction.s_cut = nan"]),
    ({"A": {"mesh.size": -1}}, ["run A", "mesh.size = -1"]),
    ({"A": {"material": 3}}, ["run A", "material"]),
    ({"A": {"loading.preload": "tensile"}}, ["run A", "'tensile'"]),
]


@pytest.mark.parametrize("kind, spec, words", SPECS, ids=[f"{k}:{w[0]}" for k, _, w in SPECS])
def test_bad_study_specs(kind, spec, words):
    with pytest.raises(ConfigError) as err:
        runs(spec, kind)
    assert len(str(err.value).splitlines()) == 1
    for word in words:
        assert word in str(err.value), (word, str(err.value))


@pytest.mark.parametrize("sets, words", RUNS, ids=[w[1] for _, w in RUNS])
def test_bad_runs(sets, words):
    with pytest.raises(ConfigError) as err:
        check_runs(sets, [PAPER_CONFIG])
    for word in words:
        assert word in str(err.value), (word, str(err.value))
