# snakemake --cores 2 experiment: does a viscous bulk give the experiment's features (issue 18, docs/experiment.md)?
# DI and EA1 at zero load, elastic against viscoelastic at Deborah numbers 0.1, 1 and 10, at fixed force and on
# the experiment-scaled spring (config/experiment.yaml). Not part of the default reproduction; outputs under
# results/<config>/studies/experiment/. Every run preloads itself: a viscous bulk's approach and preload take time.
EXPERIMENT_SPEC = "config/experiment.yaml"
EXPERIMENT = read_spec(EXPERIMENT_SPEC)
EXPERIMENT_RUNS = expand_study(EXPERIMENT, "experiment", EXPERIMENT_SPEC)
EXPERIMENT_DIR = result("studies/experiment")
EXPERIMENT_CONTROLS = sorted({o.split("_")[0] for o in EXPERIMENT["options"]})
EXPERIMENT_FIGURES = [
    f"{EXPERIMENT_DIR}/{name}.{ext}"
    for name in [f"panels_{c}" for c in EXPERIMENT_CONTROLS]
    + [f"edges_{c}" for c in EXPERIMENT_CONTROLS]
    + [f"interface_{run}" for run in EXPERIMENT.get("snapshots", [])]
    for ext in ("pdf", "png")
]


rule experiment:
    input:
        f"{EXPERIMENT_DIR}/table.csv",
        f"{EXPERIMENT_DIR}/table.md",
        f"{EXPERIMENT_DIR}/findings.md",
        EXPERIMENT_FIGURES,


rule experiment_case:
    input:
        CONFIG_FILES,
    output:
        f"{EXPERIMENT_DIR}/cases/{{run}}.nc",
    log:
        logged(f"experiment/{{run}}.log"),
    benchmark:
        result(f"benchmarks/experiment/{{run}}.tsv")
    wildcard_constraints:
        run="|".join(re.escape(r) for r in sorted(EXPERIMENT_RUNS)),
    conda:
        ENV
    threads: 1
    resources:
        mem_mb=4000,
        runtime=120,
    params:
        overrides=lambda wildcards: set_args(EXPERIMENT_RUNS[wildcards.run]),
    shell:
        f"{THREADS_ENV} {CAPSLIDE} run --resume {CONFIG_ARGS} {{params.overrides}} -o {{output}} > {{log}} 2>&1"


rule experiment_table:
    input:
        EXPERIMENT_SPEC,
        expand(f"{EXPERIMENT_DIR}/cases/{{run}}.nc", run=list(EXPERIMENT_RUNS)),
    output:
        csv=f"{EXPERIMENT_DIR}/table.csv",
        md=report(
            f"{EXPERIMENT_DIR}/table.md",
            caption="../report/experiment_table.rst",
            category="The experiment study",
        ),
        findings=report(
            f"{EXPERIMENT_DIR}/findings.md",
            caption="../report/experiment_findings.rst",
            category="The experiment study",
        ),
        figures=[
            (
                report(
                    f,
                    caption=f"../report/experiment_{Path(f).stem.split('_')[0]}.rst",
                    category="The experiment study",
                )
                if f.endswith(".png")
                else f
            )
            for f in EXPERIMENT_FIGURES
        ],
    log:
        logged("experiment/table.log"),
    conda:
        ENV
    threads: 1
    resources:
        mem_mb=2000,
        runtime=5,
    shell:
        f"{THREADS_ENV} {CAPSLIDE} experiment {EXPERIMENT_SPEC} --cases {EXPERIMENT_DIR}/cases -o {{output.csv}} -o {{output.md}} --findings {{output.findings}} --figures {EXPERIMENT_DIR} > {{log}} 2>&1"
