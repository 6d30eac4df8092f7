"""The Snakemake workflow, run in a scratch copy of the repository."""

import os
import re
import subprocess
import sys
import warnings

import pytest

from cf_checks import check_cf
from conftest import ROOT, SNAKEMAKE, default_sigint, snakemake, step_lines


def test_dry_run_is_clean(workdir):
    res = snakemake(workdir, "-n")
    assert res.returncode == 0, res.stderr
    assert "Warning" not in res.stdout + res.stderr


def test_the_workflow_parses_without_mkl(workdir):
    """The experiment scene solves with PARDISO (MKL, not part of make setup): the default reproduction's dry run
    still parses every rule file on a Python without MKL."""
    script = ("import sys; import capslide.model.cost as cost; cost.mkl_runtime = lambda: None; "
              "from snakemake.cli import main; sys.argv = ['snakemake', '-n', '--cores', '1']; main()")
    res = subprocess.run([sys.executable, "-c", script], cwd=workdir, capture_output=True, text=True,
                         env={**os.environ, "PYTHONPATH": str(workdir / "src")})
    assert res.returncode == 0, res.stderr[-2000:]


def test_preset_file_reaches_every_case_and_the_convergence_target_plans(workdir):
    """--configfile config/presets/fast.yaml is passed on to each case's capslide run; the convergence target
    plans one job per distinct run of config/convergence.yaml and the table."""
    res = snakemake(workdir, "results/fast/cases/DI_Fn+0.000.nc", "-n", "-p", "--configfile", "config/presets/fast.yaml")
    assert res.returncode == 0, res.stderr[-2000:]
    assert re.search(r"capslide run --resume config/config\.yaml \S*config/presets/fast\.yaml", res.stdout), res.stdout[-2000:]
    conv = snakemake(workdir, "-n", "convergence")
    assert conv.returncode == 0, conv.stderr[-2000:]
    jobs = dict(re.findall(r"^(convergence_\w+)\s+(\d+)$", conv.stdout, re.M))
    assert jobs["convergence_table"] == "1" and int(jobs["convergence_case"]) >= 40


def test_the_normal_states_form_one_chain(workdir):
    """With loading.preload_via listing the study's preloads, each normal state goes on from the one before it on
    its path: only the state at 0 approaches; without preload_via the tensile states go on from -0.288 (as
    before) and the others approach themselves."""
    def chain(*args):
        res = snakemake(workdir, "-n", "-p", *args)
        assert res.returncode == 0, res.stderr[-2000:]
        runs = re.findall(r"capslide preload .*?(?:--from-state results/[\w-]+/states/Fn(\S+)\.npz )?"
                          r"-o results/[\w-]+/states/Fn(\S+)\.npz", res.stdout)
        return {state: start or None for start, state in runs}
    assert chain() == {"+0.000": None, "-0.144": "+0.000", "-0.288": "-0.144", "+0.144": "-0.288",
                       "+0.288": "+0.144"}
    assert chain("--config", "loading={preload_via: []}") == {"+0.000": None, "-0.144": None, "-0.288": None,
                                                              "+0.144": "-0.288", "+0.288": "-0.288"}


def test_the_sphere_study_solves_every_job_with_pardisos_factors(workdir):
    """`snakemake sphere`: its 3 normal states and 9 slides all run with the study's solver (workflow/rules/
    sphere.smk), the states' and the cases' configurations alike, so that every case can start from its state."""
    res = snakemake(workdir, "-n", "-p", "sphere")
    assert res.returncode == 0, res.stdout[-2000:] + res.stderr[-2000:]
    jobs = re.findall(r"capslide (?:preload|run) --resume --scene sphere .*", res.stdout)
    assert len(jobs) == 12, jobs
    assert all("--set solver.linear=lu_krylov --set solver.factorization=pardiso" in job for job in jobs), jobs


def test_the_workflow_passes_its_linter(workdir):
    res = subprocess.run([str(SNAKEMAKE), "--lint"], cwd=workdir, capture_output=True, text=True)
    assert res.returncode == 0 and "Congratulations" in res.stdout + res.stderr, res.stdout[-3000:]


def test_slurm_profile_parses(workdir):
    """The cluster profile loads (executor plugin installed, resources valid) without a cluster: a dry run."""
    res = snakemake(workdir, "--profile", "profiles/slurm", "-n")
    assert res.returncode == 0, res.stdout[-2000:] + res.stderr[-2000:]
    assert "This was a dry-run" in res.stdout + res.stderr


def test_model_figures_render(workdir):
    res = snakemake(workdir, "results/paper/figures/Tn.png", "results/paper/figures/exp_FnJKR.pdf")
    assert res.returncode == 0, res.stdout + res.stderr
    for name in ("Tn.png", "Tn.pdf", "exp_FnJKR.pdf", "exp_FnJKR.png"):
        assert (workdir / "results" / "paper" / "figures" / name).stat().st_size > 5000
    assert (workdir / "logs" / "paper" / "figures" / "Tn.log").exists()
    assert (workdir / "results" / "paper" / "benchmarks" / "figures" / "Tn.tsv").exists()


@pytest.mark.parametrize("overlay, message", [
    ("friction:\n  s_cut: 2\n", "config error: friction.s_cut = 2 is not allowed: must be number >= 0 and <= 1"),
    ("study:\n  models:\n    DI: {friction.modle: DI}\n", "config: run DI_Fn-0.288: unknown key 'friction.modle'"),
], ids=["value", "study model"])
def test_a_bad_config_is_one_clear_line_when_the_workflow_is_parsed(workdir, overlay, message):
    (workdir / "bad.yaml").write_text(overlay)
    res = snakemake(workdir, "-n", "--configfile", "config/config.yaml", "bad.yaml")
    assert res.returncode != 0 and message in res.stdout + res.stderr


def test_a_bad_study_spec_is_refused_when_the_workflow_is_parsed(workdir):
    spec = workdir / "config" / "convergence.yaml"
    spec.write_text(spec.read_text().replace("eps_t: {key: friction.eps_t", "eps_t: {key: friction.eps_tt"))
    res = snakemake(workdir, "-n")
    assert res.returncode != 0
    assert "config/convergence.yaml: sweeps.eps_t.key = 'friction.eps_tt' must have a value in 'base'" in res.stdout + res.stderr


def test_config_values_reach_the_runs(workdir):
    """--config NAME=VALUE, nested values included, is passed on to capslide run; a non-finite one is refused."""
    res = snakemake(workdir, "-n", "-p", "cases", "--config", "preset=fast", "friction={s_cut: 0.5, eps_t: 200}")
    assert res.returncode == 0, res.stdout[-2000:] + res.stderr[-2000:]
    assert "--set preset=fast --set friction.s_cut=0.5 --set friction.eps_t=200" in res.stdout
    # a model given on the command line: its dotted keys reach its runs as keys, not as a section that replaces
    # the whole friction section of the config files
    res = snakemake(workdir, "-n", "-p", "cases", "--config", "study={models: {X: {friction.mu_DI: 0.5}}, preloads: [0.0]}")
    assert res.returncode == 0, res.stdout[-2000:] + res.stderr[-2000:]
    assert "--set friction.mu_DI=0.5 --set loading.preload=0.0" in res.stdout and "friction={" not in res.stdout
    res = snakemake(workdir, "-n", "--config", "friction={s_cut: .nan}")
    assert res.returncode != 0 and "config error: friction.s_cut = nan is not allowed" in res.stdout + res.stderr


def test_smoke_workflow_end_to_end(workdir):
    """The CI smoke study: coarse mesh, three cases, collected dataset and cap figures, through Snakemake. The fast
    preset's normal state is computed first: each configuration writes its own folder (results/fast/,
    results/fast-*/), the fast files stay untouched, and neither uses the other's normal state."""
    import xarray as xr

    fast = snakemake(workdir, "results/fast/states/Fn+0.000.npz", "--config", "preset=fast")
    assert fast.returncode == 0, fast.stdout[-2000:] + fast.stderr[-2000:]
    before = {p: (p.stat().st_mtime_ns, p.read_bytes()) for p in (workdir / "results" / "fast").rglob("*") if p.is_file()}
    assert "Fn+0.000.npz" in {p.name for p in before}
    res = snakemake(workdir, "--configfile", "config/smoke.yaml", "-p")
    assert res.returncode == 0, res.stdout[-3000:] + res.stderr[-3000:]
    (results,) = (workdir / "results").glob("fast-*")  # the smoke configuration's own folder
    assert "results/fast/" not in res.stdout and (results / "states" / "Fn+0.000.npz").exists()
    after = {p: (p.stat().st_mtime_ns, p.read_bytes()) for p in (workdir / "results" / "fast").rglob("*") if p.is_file()}
    assert after == before
    logs = workdir / "logs" / results.name
    cases = sorted((results / "cases").glob("*.nc"))
    assert [p.name for p in cases] == ["DI_Fn+0.000.nc", "EA0_Fn+0.000.nc", "EA1_Fn+0.000.nc"]
    with xr.open_dataset(results / "cases.nc") as ds:
        assert list(ds["model"].values) == ["DI", "EA1", "EA0"] and list(ds["preload"].values) == [0.0]
        assert (ds["status"].values == 0).all()
        ds.sel(model="DI", preload=0.0).Ft.plot(x="ubar")
    # every file the workflow writes: CF attributes, units that UDUNITS converts to the physical unit
    written = [*results.rglob("*.nc")]
    assert len(written) == 5  # three cases, the collected file, the mesh
    for path in written:
        with warnings.catch_warnings():
            warnings.simplefilter("error")  # opening must not warn
            with xr.open_dataset(path) as ds:
                assert "software_version" in ds.attrs and "config_yaml" in {*ds.attrs, *ds.variables}, path.name
                check_cf(ds, path.name)
    (workdir / "results" / "paper").symlink_to(results.name)  # the examples name the reproduction's folder
    run_documented_examples(workdir)
    (workdir / "results" / "paper").unlink()
    for name in ("Tn", "modelCA", "modelAM", "TnTt", "exp_FnJKR", "cap_setup", "cap_PxAndAc", "cap_PxOverAc",
                 "cap_FtOverA", "cap_Aczoom", "cap_xn"):
        for ext in ("pdf", "png"):
            assert (results / "figures" / f"{name}.{ext}").stat().st_size > 5000, name
    # nothing left to do: a second run is a no-op
    again = snakemake(workdir, "--configfile", "config/smoke.yaml", "-n")
    assert "Nothing to be done" in again.stdout + again.stderr

    # the report: one self-contained page with every figure
    rep = snakemake(workdir, "--configfile", "config/smoke.yaml", "--report", "report.html")
    assert rep.returncode == 0, rep.stdout[-2000:] + rep.stderr[-2000:]
    page = (workdir / "report.html").read_text()
    assert len(page) > 200_000 and all(f"Reproduces <strong>{f}</strong>" in page for f in ("Fig. 6", "Fig. 13", "Fig. 10b"))
    assert "config.yaml;base64," in page and "The configuration of this run" in page  # the validated config
    leaks = [s for s in (str(workdir), str(ROOT), ".venv", os.path.expanduser("~") + "/") if s in page]
    assert not leaks, leaks  # no local path: the report is shared

    # ParaView export of every case (optional target)
    pv = snakemake(workdir, "paraview", "--configfile", "config/smoke.yaml")
    assert pv.returncode == 0, pv.stdout[-2000:] + pv.stderr[-2000:]
    pvd = (results / "paraview" / "DI_Fn+0.000" / "DI_Fn+0.000.pvd").read_text()
    assert pvd.count("<DataSet ") == 6 and len(list((results / "paraview" / "DI_Fn+0.000").glob("*.vtu"))) == 6

    # deleting one case file reruns that case and what depends on it, nothing else
    uninterrupted = step_lines((logs / "cases" / "EA0_Fn+0.000.log").read_text(), untimed=True)
    (results / "cases" / "EA0_Fn+0.000.nc").unlink()
    dry = snakemake(workdir, "--configfile", "config/smoke.yaml", "-n")
    assert _job_counts(dry.stdout) == {"run_case": 1, "collect": 1, "cap_figure": 3, "all": 1}

    # an interrupted run (Ctrl-C during the case: the case sends SIGINT to the workflow's process group after its
    # 30th converged step, in the slide) leaves no partial file; the rerun resumes from the checkpoint and completes
    env = {**os.environ, "CAPSLIDE_INTERRUPT_AFTER_STEP": "30"}
    interrupted = subprocess.run([str(SNAKEMAKE), "--cores", "2", "--configfile", "config/smoke.yaml"], cwd=workdir,
                                 env=env, capture_output=True, text=True, start_new_session=True,
                                 preexec_fn=default_sigint, timeout=600)
    assert interrupted.returncode != 0
    assert "capslide: interrupted" in (logs / "cases" / "EA0_Fn+0.000.log").read_text()
    assert not (results / "cases" / "EA0_Fn+0.000.nc").exists()
    assert not list((results / "cases").glob(".*tmp*"))
    assert (results / "cases" / ".EA0_Fn+0.000.nc.checkpoint").is_dir()  # saved at step 20
    rerun = snakemake(workdir, "--configfile", "config/smoke.yaml")
    assert rerun.returncode == 0, rerun.stdout[-3000:] + rerun.stderr[-3000:]
    resumed = (logs / "cases" / "EA0_Fn+0.000.log").read_text()
    assert "resuming from" in resumed and len(uninterrupted) > 30
    assert step_lines(resumed, untimed=True) == uninterrupted  # Snakemake emptied the log: the checkpoint's steps shown again
    with xr.open_dataset(results / "cases" / "EA0_Fn+0.000.nc") as ds:
        assert ds.attrs["status"] == "completed"


def test_make_lifts_the_lock_a_stopped_run_left_unless_snakemake_runs_there(workdir, tmp_path):
    """A run stopped hard leaves Snakemake's lock, at which the next run stops. `make unlock`, which every workflow
    target runs first, lifts it, but not while a Snakemake process runs in the folder (here a stand-in whose command
    line is Snakemake's: python .../bin/snakemake)."""
    make = ["make", "-s", "-f", str(ROOT / "Makefile"), "-o", "setup", "unlock", f"BIN={SNAKEMAKE.parent}"]
    lock = workdir / ".snakemake" / "locks" / "0.input.lock"
    lock.parent.mkdir(parents=True)
    lock.write_text("stale")
    stand_in = tmp_path / "bin" / "snakemake"
    stand_in.parent.mkdir()
    stand_in.write_text("import time\ntime.sleep(60)\n")
    running = subprocess.Popen([sys.executable, str(stand_in), "--cores", "2"], cwd=workdir)
    try:
        busy = subprocess.run(make, cwd=workdir, capture_output=True, text=True)
    finally:
        running.kill()
        running.wait()
    assert busy.returncode == 0 and f"Snakemake (pid {running.pid}) runs in this folder" in busy.stdout
    assert lock.exists()
    idle = subprocess.run(make, cwd=workdir, capture_output=True, text=True)
    assert idle.returncode == 0 and "lifted the lock" in idle.stdout, idle.stdout + idle.stderr
    assert not lock.exists()


def run_documented_examples(workdir):
    """Every Python example of README.md, docs/data.md and docs/cli.md, run where the smoke study's results are; the examples
    of one document share a namespace, as they do for a reader going down the page."""
    import matplotlib

    matplotlib.use("Agg")
    docs = {doc: [block.split("```", 1)[0] for block in (ROOT / doc).read_text().split("```python\n")[1:]]
            for doc in ("README.md", "docs/data.md", "docs/cli.md")}
    assert sum(map(len, docs.values())) >= 4
    cwd = os.getcwd()
    os.chdir(workdir)
    try:
        for doc, blocks in docs.items():
            namespace = {}
            for block in blocks:
                exec(compile(block, doc, "exec"), namespace)  # noqa: S102 (the project's own documentation)
    finally:
        os.chdir(cwd)


def _job_counts(dry_run_output: str) -> dict[str, int]:
    """The 'Job stats' table of a Snakemake dry run as {rule: count} (without the total)."""
    table = dry_run_output.split("Job stats:")[1].split("\n\n")[0]
    rows = (re.match(r"^(\w+)\s+(\d+)$", line.strip()) for line in table.splitlines())
    return {m[1]: int(m[2]) for m in rows if m and m[1] != "total"}

