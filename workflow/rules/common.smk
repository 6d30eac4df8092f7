# Helpers shared by every rule: validated config, study expansion, the CLI call, job settings.
import os
import re
import shlex
import sys
from pathlib import Path
from types import SimpleNamespace

import yaml

from capslide.config import (
    ConfigError,
    apply_settings,
    flatten,
    load_config,
    override_args,
    retyped,
    validate,
)
from capslide.loadpath.preload_targets import previous_target
from capslide.model.build import mesh_spec
from capslide.params import Parameters
from capslide.studies.expansion import (
    check_runs,
    results_name,
    runs,
    shares_normal_state,
)
from capslide.studies.experiment_3d import normal_states, study_cases
from capslide.version import source_digest
from snakemake.exceptions import WorkflowError

# --config NAME=VALUE of this run (Snakemake reads nested values as strings): typed again, applied here, and passed
# to every capslide call, so that Snakemake's view of the config and what runs are the same configuration
CONFIG_OVERRIDES = {
    key: retyped(value)
    for key, value in flatten(
        dict(workflow.config_settings.config), whole_below=("study.models", "presets")
    ).items()
}
try:
    config = validate(
        apply_settings(config, CONFIG_OVERRIDES)
    )  # the schema of workflow/schemas/config.schema.yaml
except ConfigError as err:
    raise WorkflowError(f"config error: {err}") from None

# Every run writes under results/NAME/ and logs/NAME/, NAME named for its configuration: the preset when the
# configuration is the packaged study at that preset (results/paper/ for `snakemake --cores 2`), else the preset and
# a digest of the validated configuration (results/fast-1a2b3c4d/ for config/smoke.yaml). Runs of different
# configurations never touch each other's files.
RESULTS_NAME = results_name(config)
RESULTS = f"results/{RESULTS_NAME}"


def result(path):
    """``path`` under this configuration's results folder."""
    return f"{RESULTS}/{path}"


def logged(path):
    """``path`` under this configuration's log folder."""
    return f"logs/{RESULTS_NAME}/{path}"


# Jobs call the capslide command of the Python that runs Snakemake (the project's .venv): its bin directory goes
# first on the PATH the jobs inherit, so rule commands (and the report) name no local path.
os.environ.update(
    PATH=os.pathsep.join([str(Path(sys.executable).parent), os.environ.get("PATH", "")])
)
CAPSLIDE = "capslide"
# The digest of the package's source: normal states carry it as a parameter, so that Snakemake reruns them (and the
# cases that start from them) when the code that computes them changes.
SOURCE_DIGEST = source_digest()
# With --sdm conda every rule runs in workflow/envs/capslide.yaml, capslide from this checkout's src/.
ENV = "../envs/capslide.yaml"
if "conda" in {str(m).lower() for m in workflow.deployment_settings.deployment_method}:
    CAPSLIDE = "PYTHONPATH=src python -m capslide"
# The config files of this run in merge order: the Snakefile's default, then --configfile files; relative to
# the working directory where they are inside it (Snakemake hands them over absolute), so that no log, result
# or report names a local path.
# Each file once, named by the path given (config/ links to the packaged scenes in src/capslide/scenes/).
_default = Path(DEFAULT_CONFIG).resolve()
CONFIG_FILES = [DEFAULT_CONFIG] + [
    str(p.relative_to(Path.cwd())) if p.is_relative_to(Path.cwd()) else str(p)
    for p in dict.fromkeys(Path(os.path.abspath(f)) for f in workflow.configfiles)
    if p.resolve() != _default
]
# (inlined into shell templates, which Snakemake formats: braces of JSON values doubled)
CONFIG_ARGS = (
    (
        " ".join(shlex.quote(p) for p in CONFIG_FILES)
        + "".join(f" --set {shlex.quote(s)}" for s in override_args(CONFIG_OVERRIDES))
    )
    .replace("{", "{{")
    .replace("}", "}}")
)
# One BLAS/OpenMP thread per declared thread of a job: parallel jobs do not oversubscribe the cores.
THREADS_ENV = "export OMP_NUM_THREADS={threads} OPENBLAS_NUM_THREADS={threads} MKL_NUM_THREADS={threads} MPLBACKEND=Agg;"


def read_spec(path):
    """A study spec file (YAML)."""
    with open(path) as fh:
        return yaml.safe_load(fh)


def expand_study(spec, kind, what, skip=()):
    """Run id -> config overrides of a study spec (capslide.studies.expansion.runs), each run's configuration
    validated now: a bad spec or run stops the workflow before any job, with one line naming it.
    """
    try:
        out = runs(spec, kind)
        check_runs(out, CONFIG_FILES, skip, CONFIG_OVERRIDES)
    except ConfigError as err:
        raise WorkflowError(f"{what}: {err}") from None
    return out


def set_args(overrides):
    """The --set options of a run's overrides (dotted key -> value)."""
    return " ".join(f"--set {shlex.quote(s)}" for s in override_args(overrides))


def shared_state(sets):
    """The preload (+0.000) of the reproduction's normal state that a run of a study with overrides ``sets``
    starts from, or None (its overrides change the approach or the preload, or no such state is computed).
    """
    preload = sets.get("loading.preload", config["loading"]["preload"])
    name = f"{preload:+.3f}"
    if shares_normal_state(config, sets) and STATE_PRELOADS.get(name) == preload:
        return name
    return None


def previous_state(preload, computed):
    """The preload (+0.000) of the normal state that the state at ``preload`` goes on from, among the
    preloads ``computed``, or None (capslide.loadpath.preload_targets)."""
    loading = SimpleNamespace(
        preload=preload,
        retract_from=config["loading"]["retract_from"],
        preload_via=tuple(config["loading"]["preload_via"]),
    )
    previous = previous_target(loading, computed)
    return None if previous is None else f"{previous:+.3f}"


def case_priority(sets):
    """Longest first, so that the two cores finish together: a slide's cost grows with the preload's compression
    (tensile cases are the quickest, docs/performance.md), and every case ranks below the normal states (10).
    """
    preload = sets.get("loading.preload", config["loading"]["preload"])
    return 5.0 - 10.0 * float(preload)


def expand_scene_study(scene_file, spec, what, settings=None):
    """Run id -> config overrides of a packaged scene's study section (``spec``), each after ``settings`` (dotted
    key -> value, shared by the study's runs), each run's configuration (the scene file, the settings, then the
    run's overrides) validated now, as :func:`expand_study` does for the workflow's study. A solver library this
    Python lacks is left to the jobs to refuse: the workflow reads these rules on every run.
    """
    settings = settings or {}
    try:
        out = runs(spec, "study")
        check_runs(out, [scene_file], settings=settings, libraries=False)
        out = {run: {**settings, **sets} for run, sets in out.items()}
    except ConfigError as err:
        raise WorkflowError(f"{what}: {err}") from None
    return out


def experiment3d_cases(scene_file):
    """Run id -> config overrides of the experiment scene's study (capslide.studies.experiment_3d), each run's
    configuration validated now."""
    try:
        out = study_cases(load_config([scene_file]))
        # its jobs refuse a missing MKL (make experiment3d installs it); the rule files parse without it
        check_runs(out, [scene_file], libraries=False)
    except ConfigError as err:
        raise WorkflowError(f"experiment3d: {err}") from None
    return out


def scene_previous_state(scene_config, preload, computed):
    """:func:`previous_state` for a scene's own loading (its retract_from and preload_via), None also when the
    two states' meshes differ (the 3D sphere's band radius grows with a compressive preload).
    """
    loading = SimpleNamespace(
        preload=preload,
        retract_from=scene_config["loading"]["retract_from"],
        preload_via=tuple(scene_config["loading"]["preload_via"]),
    )
    previous = previous_target(loading, computed)
    mesh = lambda value: mesh_spec(
        Parameters.from_config(
            validate(apply_settings(scene_config, {"loading.preload": value}))
        )
    )
    if previous is None or mesh(previous) != mesh(preload):
        return None
    return f"{previous:+.3f}"
