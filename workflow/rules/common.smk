# Helpers shared by every rule: validated config, study expansion, the CLI call, job settings.
import re
import shlex
import sys
from pathlib import Path

import yaml

from capslide.config import ConfigError, apply_settings, flatten, override_args, retyped, validate
from capslide.studies.expansion import check_runs, runs
from snakemake.exceptions import WorkflowError

# --config NAME=VALUE of this run (Snakemake reads nested values as strings): typed again, applied here, and passed
# to every capslide call, so that Snakemake's view of the config and what runs are the same configuration
CONFIG_OVERRIDES = {key: retyped(value) for key, value in flatten(dict(workflow.config_settings.config)).items()}
try:
    config = validate(apply_settings(config, CONFIG_OVERRIDES))  # the schema of workflow/schemas/config.schema.yaml
except ConfigError as err:
    raise WorkflowError(f"config error: {err}") from None

# The package CLI from the Python that runs Snakemake (the project's .venv).
CAPSLIDE = f"{shlex.quote(sys.executable)} -m capslide"
# The config files of this run in merge order: the Snakefile's default, then --configfile files.
_default = Path(DEFAULT_CONFIG).resolve()
CONFIG_FILES = [DEFAULT_CONFIG] + [
    str(p) for p in dict.fromkeys(Path(f).resolve() for f in workflow.configfiles) if p != _default
]
CONFIG_ARGS = " ".join(shlex.quote(p) for p in CONFIG_FILES) + "".join(
    f" --set {shlex.quote(s)}" for s in override_args(CONFIG_OVERRIDES)
)
# One BLAS/OpenMP thread per declared rule thread: parallel jobs do not oversubscribe.
THREADS_ENV = "export OMP_NUM_THREADS={threads} OPENBLAS_NUM_THREADS={threads} MKL_NUM_THREADS={threads} MPLBACKEND=Agg;"


def read_spec(path):
    """A study spec file (YAML)."""
    with open(path) as fh:
        return yaml.safe_load(fh)


def expand_study(spec, kind, what, skip=()):
    """Run id -> config overrides of a study spec (capslide.studies.expansion.runs), each run's configuration
    validated now: a bad spec or run stops the workflow before any job, with one line naming it."""
    try:
        out = runs(spec, kind)
        check_runs(out, CONFIG_FILES, skip, CONFIG_OVERRIDES)
    except ConfigError as err:
        raise WorkflowError(f"{what}: {err}") from None
    return out


def set_args(overrides):
    """The --set options of a run's overrides (dotted key -> value)."""
    return " ".join(f"--set {shlex.quote(s)}" for s in override_args(overrides))
