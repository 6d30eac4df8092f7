"""Command-line interface: constants as JSON, one-line errors for bad input (in this process: capslide.cli.main)."""

import json
import subprocess
import sys
from dataclasses import dataclass

import pytest

from capslide.cli import main
from capslide.studies.verification import read_tables

from conftest import PAPER_CONFIG


@dataclass
class Completed:
    returncode: int
    stdout: str
    stderr: str


@pytest.fixture()
def run(capsys):
    """``capslide ARGS`` in this process: exit code and what it printed."""

    def call(*args):
        capsys.readouterr()
        code = main([str(a) for a in args])
        out, err = capsys.readouterr()
        return Completed(code, out, err)

    return call


def test_the_entry_point_runs_as_a_program():
    res = subprocess.run([sys.executable, "-m", "capslide", "constants", str(PAPER_CONFIG), "--set", "material.nu=0.6"],
                         capture_output=True, text=True)
    assert res.returncode == 2 and res.stderr.startswith("capslide: error: material.nu = 0.6") and not res.stdout


def test_constants_json(run):
    res = run("constants", PAPER_CONFIG, "--set", "friction.model=EA", "--set", "friction.s_cut=0")
    assert res.returncode == 0, res.stderr
    data = json.loads(res.stdout)
    assert data["internal"]["r0"] == pytest.approx(0.13188, rel=5e-5)
    assert data["SI"]["r0"] == pytest.approx(0.13188e-6, rel=5e-5)
    assert data["internal"]["g_cut_EA"] == pytest.approx(data["internal"]["g_eq"])  # s_cut = 0
    assert data["internal_units"]["T0"] == "E" and data["SI_units"]["T0"] == "Pa"


# (overrides or file text, words the one-line message must contain)
BAD_INPUT = [
    (["--set", "friction.foo=1"], ["unknown key", "friction.foo"]),
    (["--set", "bogus.key=1"], ["unknown key", "bogus"]),
    (["--set", "material.E=abc"], ["material.E", "'abc'", "number"]),
    (["--set", "material.nu=0.5"], ["material.nu = 0.5", "mesh.formulation = mixed"]),
    (["--set", "material.nu=0.51"], ["material.nu", "0.51", "<= 0.5"]),
    (["--set", "mesh.formulation=mixed", "--set", "mesh.element=Q1"], ["mesh.formulation = mixed", "mesh.element = Q2"]),
    (["--set", "mesh.formulation=hybrid"], ["mesh.formulation", "'hybrid'", "displacement, mixed"]),
    (["--set", "material.nu=0.7"], ["material.nu", "0.7"]),
    (["--set", "friction.s_cut=1.5"], ["friction.s_cut", "1.5", "<= 1"]),
    (["--set", "friction.s_cut=-0.1"], ["friction.s_cut", "-0.1", ">= 0"]),
    (["--set", "material.E=-2e6"], ["material.E", "-2000000.0", "> 0"]),
    (["--set", "friction.model=XY"], ["friction.model", "'XY'", "DI, EA, none"]),
    (["--set", "mesh.surface_gauss_points=2.5"], ["mesh.surface_gauss_points", "integer"]),
    (["--set", "geometry.H=60"], ["geometry.H", "geometry.R"]),
    (["--set", "adhesion.g_reg_over_g_eq=1.5"], ["adhesion.g_reg_over_g_eq", "1.5"]),
    (["--set", "noequals"], ["override", "noequals"]),
    (["--set", "material.E.x=1"], ["material.E", "value, not a section"]),
    (["--set", "material=3"], ["material", "section"]),
    (["--set", "friction.g_cut_DI_over_g_max=0.8"], ["friction.g_cut_DI_over_g_max", "0.8", "regularization gap"]),
    (["--set", "loading.preload=20"], ["loading.preload", "20", "beyond pull-off"]),
    (["--set", "contact.repulsion_only=true", "--set", "loading.preload=0.1"], ["loading.preload", "repulsion_only"]),
    (["--set", "loading.normal_control=spring"], ["loading.spring_stiffness = None", "normal_control = spring"]),
    (["--set", "solver.linear=cholmod"], ["solver.linear", "'cholmod'", "auto, amg, lu_krylov, direct"]),
    (["--set", "output.snapshot_ubar=1.0"], ["output.snapshot_ubar", "array"]),
    (["--set", "preset=slow"], ["preset", "'slow'", "fast, paper, reference"]),
    (["--set", "presets.paper.mesh.size=2"], ["presets.paper.mesh", "dotted"]),
]


@pytest.mark.parametrize("extra, words", BAD_INPUT, ids=[" ".join(b[0]) for b in BAD_INPUT])
def test_bad_overrides(run, extra, words):
    res = run("constants", PAPER_CONFIG, *extra)
    assert res.returncode == 2
    assert res.stdout == ""
    lines = res.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("capslide: error: "), res.stderr
    assert "Traceback" not in res.stderr
    for word in words:
        assert word in lines[0], (word, lines[0])


def test_missing_section_and_bad_files(run, tmp_path):
    text = PAPER_CONFIG.read_text()
    no_friction = tmp_path / "nofriction.yaml"
    no_friction.write_text(text.replace("friction:", "friction_gone:"))
    res = run("constants", no_friction)
    assert res.returncode == 2 and "unknown key 'friction_gone'" in res.stderr
    cut = text.split("friction:")[0] + "geometry:" + text.split("geometry:")[1]
    missing = tmp_path / "missing.yaml"
    missing.write_text(cut)
    res = run("constants", missing)
    assert res.returncode == 2 and "missing section 'friction'" in res.stderr
    broken = tmp_path / "broken.yaml"
    broken.write_text("material: [1, 2\n")
    res = run("constants", broken)
    assert res.returncode == 2 and "broken.yaml" in res.stderr and len(res.stderr.strip().splitlines()) == 1
    res = run("constants", tmp_path / "absent.yaml")
    assert res.returncode == 2 and "absent.yaml" in res.stderr
    nokey = tmp_path / "nokey.yaml"
    nokey.write_text(text.replace("  E: 2.0e+6          # Pa\n", ""))
    res = run("constants", nokey)
    assert res.returncode == 2 and "missing key 'material.E'" in res.stderr


def test_figure_bad_output_leaves_nothing(run, tmp_path):
    res = run("figure", "Tn", PAPER_CONFIG, "-o", tmp_path / "fig.jpg2")
    assert res.returncode == 2 and "unsupported file type" in res.stderr
    res = run("figure", "NoSuchFigure", PAPER_CONFIG, "-o", tmp_path / "fig.png")
    assert res.returncode == 2 and "unknown figure 'NoSuchFigure'" in res.stderr
    res = run("figure", "Tn", PAPER_CONFIG, "--set", "material.nu=0.5", "-o", tmp_path / "fig.png")
    assert res.returncode == 2
    assert list(tmp_path.iterdir()) == []


# (command line after "capslide", words of the one-line message); {tmp} is a scratch directory
BAD_RUNS = [
    (["run", PAPER_CONFIG, "-o", "{tmp}/case.txt"], ["case.txt", "unsupported file type"]),
    (["run", PAPER_CONFIG, "-o", "{tmp}/adir.nc"], ["adir.nc", "is a directory"]),
    (["run", PAPER_CONFIG, "-o", "{tmp}/afile/case.nc"], ["afile", "not a directory"]),
    (["run", PAPER_CONFIG, "-o", "/proc/capslide/case.nc"], ["/proc", "not writable"]),
    (["run", "{tmp}/absent.yaml", "-o", "{tmp}/case.nc"], ["absent.yaml"]),
    (["inspect", "{tmp}/absent.nc"], ["cannot read netCDF file", "absent.nc"]),
    (["inspect", "{tmp}/afile"], ["cannot read netCDF file", "afile"]),
    (["vtk", "{tmp}/afile", "-o", "{tmp}/vtk"], ["cannot read netCDF file", "afile"]),
    (["collect", "{tmp}/absent.nc", "-o", "{tmp}/cases.nc"], ["absent.nc"]),
    (["figure", "cap_xn", "-o", "{tmp}/xn.png"], ["cap_xn", "--input CASE.nc"]),
    (["figure", "cap_PxAndAc", "--input", "{tmp}/afile", "-o", "{tmp}/f.png"], ["cannot read netCDF file", "afile"]),
]


@pytest.mark.parametrize("argv, words", BAD_RUNS, ids=[" ".join(map(str, b[0][:1] + b[0][-1:])) for b in BAD_RUNS])
def test_bad_command_lines(run, tmp_path, argv, words):
    (tmp_path / "afile").write_text("not netCDF\n")
    (tmp_path / "adir.nc").mkdir()
    before = sorted(tmp_path.rglob("*"))
    res = run(*[str(a).format(tmp=tmp_path) for a in argv])
    assert res.returncode == 2, res.stderr
    lines = res.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("capslide: error: ") and "Traceback" not in res.stderr, res.stderr
    for word in words:
        assert word in lines[0], (word, lines[0])
    assert sorted(tmp_path.rglob("*")) == before  # nothing written, not even a directory


def test_experiment3d_of_a_2d_case_stops_with_one_line(run, tmp_path):
    """The experiment's table reads 3D sphere cases: a 2D case file is named in one line, exit 2, nothing written."""
    case = tmp_path / "cap.nc"
    res = run("run", "--scene", "cap", "--set", "preset=fast", "--set", "loading.ubar_max=0.3", "-q", "-o", case)
    assert res.returncode == 0, res.stderr
    res = run("experiment3d", case, "-o", tmp_path / "t.md", "--panels", tmp_path / "p.png")
    lines = res.stderr.strip().splitlines()
    assert res.returncode == 2 and len(lines) == 1 and "cap.nc" in lines[0] and "not a 3D sphere case" in lines[0]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["cap.nc"]


def test_aczoom_of_a_case_without_its_snapshots_stops_with_one_line(run, tmp_path):
    """f:cap:Aczoom shows the snapshots at ubar = 0.5 to 4 L0: a case with others is named in one line, exit 2."""
    case = tmp_path / "cap.nc"
    res = run("run", "--scene", "cap", "--set", "preset=fast", "--set", "loading.ubar_max=0.3", "--set",
              "output.snapshot_ubar=[0.3]", "-q", "-o", case)
    assert res.returncode == 0, res.stderr
    res = run("figure", "cap_Aczoom", "--input", case, "-o", tmp_path / "f.png")
    lines = res.stderr.strip().splitlines()
    assert res.returncode == 2 and len(lines) == 1 and "no snapshot at ubar = 0.5, 1," in lines[0], res.stderr
    assert sorted(p.name for p in tmp_path.iterdir()) == ["cap.nc"]
    assert run("figure", "cap_xn", "--input", case, "-o", tmp_path / "f.png").returncode == 0  # any snapshot


def test_verify_that_finds_no_equilibrium_stops_with_one_line(run, tmp_path):
    """A verification sweep whose solver gives up: exit 4 (diverged), one line on stderr, no table, no traceback."""
    scene = PAPER_CONFIG.parent / "scenes" / "hertz.yaml"
    out = tmp_path / "hertz.csv"
    res = run("verify", scene, "--scene", "hertz", "-q", "-o", out, "--set", "mesh.size=100",
              "--set", "solver.newton_max_iterations=1", "--set", "loading.max_cutbacks=3")
    assert res.returncode == 4, res.stderr
    assert "Traceback" not in res.stderr
    lines = [ln for ln in res.stderr.splitlines() if ln.strip()]
    assert len(lines) == 1 and "verification of scene hertz stopped: approach: more than 3 cut-backs" in lines[0]
    assert list(tmp_path.iterdir()) == []


@pytest.mark.slow
def test_verify_of_the_paper_cap_says_the_jkr_reference_is_not_valid(run, tmp_path):
    """The paper's cap (fast preset) has Maugis parameter 4.83 < 5: the table says so on every row, the terminal
    says it once and marks the rows; the scene comes from the config; the pull-off row has no load. About 12 s."""
    out = tmp_path / "v.csv"
    res = run("verify", PAPER_CONFIG, "-q", "-o", out, "--set", "preset=fast", "--set", "verification.loads=[0.0]")
    assert res.returncode == 0, res.stderr
    assert "lambda = 4.829" in res.stdout and "NOT a valid reference" in res.stdout
    rows = {r["quantity"]: r for r in read_tables([out])}
    assert set(rows) == {"half_width", "half_width_reference", "load_at_half_width", "pull_off"}
    assert all(r["scene"] == "jkr" and "jkr_valid=no" in r["extra"] for r in rows.values())
    assert all(ln.startswith("*jkr") for ln in res.stdout.splitlines()[1:])
    assert rows["pull_off"]["load_P"] == "nan" and float(rows["pull_off"]["fe"]) < 0
    # the reference-coordinate half-width: the material points in contact, not their current (stretched) span
    a_cur, a_ref = float(rows["half_width"]["fe"]), float(rows["half_width_reference"]["fe"])
    assert a_ref != a_cur and abs(a_ref / a_cur - 1) < 0.02


def test_a_closed_pipe_ends_quietly():
    """capslide constants | head -c 0: the reader is gone before capslide writes; no traceback, exit 141."""
    res = subprocess.run(f"{sys.executable} -m capslide constants {PAPER_CONFIG} | head -c 0; echo ${{PIPESTATUS[0]}} >&2",
                         shell=True, executable="/bin/bash", capture_output=True, text=True)
    assert res.stderr.strip() == "141", res.stderr


def test_a_run_checks_its_cost_once(tmp_path, monkeypatch):
    """capslide run estimates the mesh's cost once (its preflight), not again in the case driver."""
    from capslide.model import cost

    calls = []
    real = cost.estimate
    monkeypatch.setattr(cost, "estimate", lambda *a, **k: (calls.append(1), real(*a, **k))[1])
    args = ["run", str(PAPER_CONFIG), "--set", "preset=fast", "--set", "loading.ubar_max=0", "-q",
            "-o", str(tmp_path / "c.nc")]
    assert main(args) == 0 and len(calls) == 1
