# snakemake --cores 2 convergence: speed against error (config/convergence.yaml; issue 7).
# Not part of the default reproduction; outputs under results/studies/convergence/.
import yaml

from capslide.convergence import run_overrides, study_runs, validate_spec

CONVERGENCE_SPEC = "config/convergence.yaml"
CONVERGENCE = yaml.safe_load(open(CONVERGENCE_SPEC))
try:
    validate_spec(CONVERGENCE)
except ValueError as err:
    raise WorkflowError(f"{CONVERGENCE_SPEC}: {err}") from None
CONVERGENCE_DIR = "results/studies/convergence"
CONVERGENCE_SETS = {
    (r.case, r.run_id): run_overrides(CONVERGENCE, r.case, r.sweep, r.value)
    for r in study_runs(CONVERGENCE)
}
CONVERGENCE_FILES = sorted(f"{CONVERGENCE_DIR}/cases/{c}/{i}.nc" for c, i in CONVERGENCE_SETS)
# the long runs (the finest meshes) start first: they are the critical path on two cores
CONVERGENCE_LONG = [i for _, i in CONVERGENCE_SETS if i in ("size-0.5", "size-1")]


def convergence_overrides(wildcards):
    sets = CONVERGENCE_SETS[(wildcards.case, wildcards.run)]
    return " ".join(f"--set {shlex.quote(f'{k}={v}')}" for k, v in sets.items())


rule convergence:
    input:
        f"{CONVERGENCE_DIR}/table.csv",
        f"{CONVERGENCE_DIR}/table.md",
        f"{CONVERGENCE_DIR}/orders.csv",
        f"{CONVERGENCE_DIR}/error_vs_time.pdf",
        f"{CONVERGENCE_DIR}/error_vs_time.png",


rule convergence_case:
    input:
        CONFIG_FILES,  # the run's own overrides are params (Snakemake reruns a run when they change)
    output:
        f"{CONVERGENCE_DIR}/cases/{{case}}/{{run}}.nc",
    wildcard_constraints:
        case="|".join(re.escape(c) for c in CONVERGENCE["cases"]),
        run="|".join(re.escape(i) for i in sorted({i for _, i in CONVERGENCE_SETS})),
    params:
        overrides=convergence_overrides,
    priority: lambda wildcards: 10 if wildcards.run in CONVERGENCE_LONG else 0
    log:
        f"logs/convergence/{{case}}/{{run}}.log",
    benchmark:
        f"results/benchmarks/convergence/{{case}}/{{run}}.tsv"
    threads: 1
    resources:
        mem_mb=6000,
        runtime=180,
    # exit 3 (detached) and 4 (diverged) still write the case file; the table reports the status
    shell:
        THREADS_ENV + " rc=0; " + CAPSLIDE + " run --resume " + CONFIG_ARGS
        + " {params.overrides} -o {output} > {log} 2>&1 || rc=$?; test $rc -eq 0 -o $rc -eq 3 -o $rc -eq 4"


rule convergence_table:
    input:
        CONVERGENCE_SPEC,
        CONVERGENCE_FILES,
    output:
        csv=f"{CONVERGENCE_DIR}/table.csv",
        md=report(f"{CONVERGENCE_DIR}/table.md", caption="../report/convergence_table.rst", category="Convergence"),
        orders=f"{CONVERGENCE_DIR}/orders.csv",
        pdf=f"{CONVERGENCE_DIR}/error_vs_time.pdf",
        png=report(f"{CONVERGENCE_DIR}/error_vs_time.png", caption="../report/convergence_figure.rst", category="Convergence"),
    log:
        "logs/convergence/table.log",
    threads: 1
    resources:
        mem_mb=2000,
        runtime=5,
    shell:
        THREADS_ENV + " " + CAPSLIDE + " convergence " + CONVERGENCE_SPEC + " --cases " + CONVERGENCE_DIR + "/cases --orders {output.orders} -o {output.csv} -o {output.md} -o {output.pdf} -o {output.png} > {log} 2>&1"
