# Two entry points for a fresh machine (Python 3.11, no venv yet):
#   make reproduce   set up .venv and run the full Snakemake reproduction
#   make test        set up .venv and run the default test suite
#   make convergence set up .venv and run the speed-against-error study (results/paper/studies/convergence/)
#   make sphere      set up .venv with MKL and run the paper's study on the sphere (results/paper/sphere/)
#   make experiment3d set up .venv with MKL and run the experiment in numbers (results/paper/experiment3d/)
#   make verification3d set up .venv with MKL and run the 3D sphere against Hertz and Maugis-Dugdale (hours)
#   make test-slurm  the smoke workflow through a local single-node SLURM (root)
PYTHON ?= python3
VENV   := .venv
BIN    := $(VENV)/bin
CORES  ?= 2
# One BLAS thread per process: Snakemake runs jobs in parallel on the cores.
export OMP_NUM_THREADS ?= 1
export OPENBLAS_NUM_THREADS ?= 1
export MKL_NUM_THREADS ?= 1
export MPLBACKEND ?= Agg

.PHONY: setup setup-pardiso unlock reproduce convergence sphere experiment3d verification3d test test-all test-slurm lock clean

setup: $(VENV)/.installed

$(VENV)/.installed: pyproject.toml requirements.lock
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip
	$(BIN)/python -m pip install --quiet -c requirements.lock -e '.[workflow,slurm,test]'
	touch $@

# Intel MKL for solver.factorization: pardiso (x86-64 only; about 1 GB in the venv). Not part of setup.
setup-pardiso: setup
	$(BIN)/python -m pip install --quiet -c requirements.lock -e '.[workflow,slurm,test,pardiso]'

# A run stopped hard (a session's end, a power loss) leaves Snakemake's lock in .snakemake/locks, and the next run
# stops at it. The workflow targets lift it first, unless a Snakemake process is running in this folder.
unlock: setup
	@if [ -n "$$(ls -A .snakemake/locks 2>/dev/null)" ]; then \
	  busy=; for p in $$(pgrep -f '^[^ ]*python[^ ]* ([^ ]*bin/snakemake|-m snakemake)( |$$)'); do \
	    if [ "$$(readlink /proc/$$p/cwd)" = "$(CURDIR)" ]; then busy=$$p; fi; done; \
	  if [ -n "$$busy" ]; then echo "make: Snakemake (pid $$busy) runs in this folder; its lock stays"; \
	  else $(BIN)/snakemake --unlock > /dev/null 2>&1 && echo "make: lifted the lock a stopped run left in .snakemake/locks"; fi; fi

reproduce: setup unlock
	$(BIN)/snakemake --cores $(CORES)

convergence: setup unlock
	$(BIN)/snakemake --cores $(CORES) convergence

# The sphere study solves with PARDISO's factors (workflow/rules/sphere.smk), so this target sets MKL up first.
sphere: setup-pardiso unlock
	$(BIN)/snakemake --cores $(CORES) sphere

# The experiment scene solves with PARDISO's factors (docs/experiment3d.md), so this target sets MKL up first.
experiment3d: setup-pardiso unlock
	$(BIN)/snakemake --cores $(CORES) experiment3d

# sphere_md3 solves with PARDISO's factors too (docs/three_d.md).
verification3d: setup-pardiso unlock
	$(BIN)/snakemake --cores $(CORES) verification3d

test: setup
	$(BIN)/ruff check src tests benchmarks
	$(BIN)/snakefmt --check Snakefile workflow/rules
	$(BIN)/python -m pytest -m "not slow" -n $(CORES) --dist loadscope

test-all: setup
	$(BIN)/ruff check src tests benchmarks
	$(BIN)/snakefmt --check Snakefile workflow/rules
	$(BIN)/python -m pytest

# The smoke workflow through profiles/slurm on a single-node SLURM of this machine (root: installs and starts
# slurmctld, slurmd, slurmdbd, munge, MariaDB; stops them at the end). Not part of make test.
test-slurm: setup
	bash tests/slurm/run.sh

lock: setup-pardiso
	( echo '# Exact versions of every dependency, used as pip constraints by the Makefile.'; \
	  echo '# Regenerate: make lock'; \
	  $(BIN)/python -m pip freeze --exclude-editable | grep -v -iE '^(pip|setuptools|wheel)==' ) > requirements.lock

clean:
	rm -rf $(VENV) .snakemake results logs
