# snakemake --cores 2 convergence: speed against error (config/convergence.yaml; issue 7).
# Not part of the default reproduction; outputs under results/<config>/studies/convergence/.
CONVERGENCE_SPEC = "config/convergence.yaml"
CONVERGENCE = read_spec(CONVERGENCE_SPEC)
CONVERGENCE_RUNS = expand_study(
    CONVERGENCE, "convergence", CONVERGENCE_SPEC
)  # "{case}/{run}" -> overrides
CONVERGENCE_DIR = result("studies/convergence")
CONVERGENCE_FILES = sorted(
    f"{CONVERGENCE_DIR}/cases/{run}.nc" for run in CONVERGENCE_RUNS
)
# the long runs (the finest meshes) start first: they are the critical path on two cores
CONVERGENCE_LONG = [
    run for run in CONVERGENCE_RUNS if Path(run).name in ("size-0.5", "size-1")
]


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
        f"{CONVERGENCE_DIR}/cases/{{run}}.nc",
    log:
        logged(f"convergence/{{run}}.log"),
    benchmark:
        result(f"benchmarks/convergence/{{run}}.tsv")
    wildcard_constraints:
        run="|".join(re.escape(r) for r in sorted(CONVERGENCE_RUNS)),
    priority: lambda wildcards: 10 if wildcards.run in CONVERGENCE_LONG else 0
    conda:
        ENV
    threads: 1
    resources:
        mem_mb=6000,
        runtime=180,
    params:
        overrides=lambda wildcards: set_args(CONVERGENCE_RUNS[wildcards.run]),
    # exit 3 (detached) and 4 (diverged) still write the case file; the table reports the status
    shell:
        f"{THREADS_ENV} rc=0; {CAPSLIDE} run --resume {CONFIG_ARGS} {{params.overrides}} -o {{output}} > {{log}} 2>&1 || rc=$?; test $rc -eq 0 -o $rc -eq 3 -o $rc -eq 4"


rule convergence_table:
    input:
        CONVERGENCE_SPEC,
        CONVERGENCE_FILES,
    output:
        csv=f"{CONVERGENCE_DIR}/table.csv",
        md=report(
            f"{CONVERGENCE_DIR}/table.md",
            caption="../report/convergence_table.rst",
            category="Convergence",
        ),
        orders=f"{CONVERGENCE_DIR}/orders.csv",
        pdf=f"{CONVERGENCE_DIR}/error_vs_time.pdf",
        png=report(
            f"{CONVERGENCE_DIR}/error_vs_time.png",
            caption="../report/convergence_figure.rst",
            category="Convergence",
        ),
    log:
        logged("convergence/table.log"),
    conda:
        ENV
    threads: 1
    resources:
        mem_mb=2000,
        runtime=5,
    shell:
        f"{THREADS_ENV} {CAPSLIDE} convergence {CONVERGENCE_SPEC} --cases {CONVERGENCE_DIR}/cases --orders {{output.orders}} -o {{output.csv}} -o {{output.md}} -o {{output.pdf}} -o {{output.png}} > {{log}} 2>&1"
