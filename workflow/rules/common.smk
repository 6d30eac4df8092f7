# Helpers shared by every rule: validated config, the CLI call, job settings.
import re
import shlex
import sys
from pathlib import Path

from capslide.config import ConfigError, validate
from snakemake.exceptions import WorkflowError

try:
    config = validate(config)  # same schema file as workflow/schemas/config.schema.yaml
except ConfigError as err:
    raise WorkflowError(f"config error: {err}") from None

# The package CLI from the Python that runs Snakemake (the project's .venv).
CAPSLIDE = f"{shlex.quote(sys.executable)} -m capslide"
# The config files of this run in merge order: the Snakefile's default, then --configfile files.
_default = Path(DEFAULT_CONFIG).resolve()
CONFIG_FILES = [DEFAULT_CONFIG] + [
    str(p) for p in dict.fromkeys(Path(f).resolve() for f in workflow.configfiles) if p != _default
]
CONFIG_ARGS = " ".join(shlex.quote(p) for p in CONFIG_FILES)
# One BLAS/OpenMP thread per declared rule thread: parallel jobs do not oversubscribe.
THREADS_ENV = "export OMP_NUM_THREADS={threads} OPENBLAS_NUM_THREADS={threads} MKL_NUM_THREADS={threads} MPLBACKEND=Agg;"
