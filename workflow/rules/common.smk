# Helpers shared by every rule: validated config, the CLI call, job settings.
import shlex
import sys

from capslide.config import ConfigError, validate
from snakemake.exceptions import WorkflowError

try:
    config = validate(config)  # same schema file as workflow/schemas/config.schema.yaml
except ConfigError as err:
    raise WorkflowError(f"config error: {err}") from None

# The package CLI from the Python that runs Snakemake (the project's .venv).
CAPSLIDE = f"{shlex.quote(sys.executable)} -m capslide"
# The config files this run was started with, in merge order.
CONFIG_FILES = [str(p) for p in workflow.configfiles]
CONFIG_ARGS = " ".join(shlex.quote(p) for p in CONFIG_FILES)
# One BLAS/OpenMP thread per declared rule thread: parallel jobs do not oversubscribe.
THREADS_ENV = "export OMP_NUM_THREADS={threads} OPENBLAS_NUM_THREADS={threads} MKL_NUM_THREADS={threads} MPLBACKEND=Agg;"
