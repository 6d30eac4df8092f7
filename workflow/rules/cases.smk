# The study's cases: one netCDF file per (model, preload), from config["study"] (capslide.studies.expansion).
STUDY = config["study"]
CASES = expand_study(STUDY, "study", "config")  # case name -> overrides
CASE_FILES = expand(
    "results/cases/{case}.nc", case=list(CASES)
)  # study order: the cube's model order


rule run_case:
    input:
        CONFIG_FILES,
    output:
        "results/cases/{case}.nc",
    log:
        "logs/cases/{case}.log",
    benchmark:
        "results/benchmarks/cases/{case}.tsv"
    wildcard_constraints:
        case="|".join(re.escape(c) for c in CASES) if CASES else "none",
    conda:
        ENV
    threads: 1
    resources:
        mem_mb=4000,
        runtime=120,
    params:
        overrides=lambda wildcards: set_args(CASES[wildcards.case]),
    shell:
        f"{THREADS_ENV} {CAPSLIDE} run --resume {CONFIG_ARGS} {{params.overrides}} -o {{output}} > {{log}} 2>&1"
