# snakemake --cores 2 options: each option beyond the paper switched on alone (config/options.yaml,
# docs/options.md). Not part of the default reproduction; outputs under results/<config>/studies/options/.
# Runs whose overrides act only from the slide on start from the reproduction's normal state at their preload.
OPTIONS_SPEC = "config/options.yaml"
OPTIONS = read_spec(OPTIONS_SPEC)
OPTIONS_RUNS = expand_study(
    OPTIONS, "options", OPTIONS_SPEC
)  # "{model}_{option}" -> overrides
OPTIONS_DIR = result("studies/options")


OPTIONS_SHARED = {  # run -> the preload of the normal state it starts from
    run: shared_state(sets)
    for run, sets in OPTIONS_RUNS.items()
    if shared_state(sets) is not None
}


rule options:
    input:
        f"{OPTIONS_DIR}/table.csv",
        f"{OPTIONS_DIR}/table.md",
        expand(
            f"{OPTIONS_DIR}/{{name}}.{{ext}}",
            name=["forces", "edges"],
            ext=["pdf", "png"],
        ),
        expand(result("figures/cap_FtOverA.{ext}"), ext=["pdf", "png"]),


rule options_case:
    input:
        CONFIG_FILES,
        state=lambda wildcards: (
            STATE_FILE.format(preload=OPTIONS_SHARED[wildcards.run])
            if wildcards.run in OPTIONS_SHARED
            else []
        ),
    output:
        f"{OPTIONS_DIR}/cases/{{run}}.nc",
    log:
        logged(f"options/{{run}}.log"),
    benchmark:
        result(f"benchmarks/options/{{run}}.tsv")
    wildcard_constraints:
        run="|".join(re.escape(r) for r in sorted(OPTIONS_RUNS)),
    conda:
        ENV
    threads: 1
    resources:
        mem_mb=4000,
        runtime=120,
    params:
        overrides=lambda wildcards: set_args(OPTIONS_RUNS[wildcards.run]),
        start=lambda wildcards, input: (
            f"--from-state {input.state}" if input.state else ""
        ),
    # exit 5 (snapped: a slide with slip weakening that loses its quasi-static path) still writes the case file
    shell:
        f"{THREADS_ENV} rc=0; {CAPSLIDE} run --resume {CONFIG_ARGS} {{params.overrides}} {{params.start}} -o {{output}} > {{log}} 2>&1 || rc=$?; test $rc -eq 0 -o $rc -eq 5"


rule options_table:
    input:
        OPTIONS_SPEC,
        expand(f"{OPTIONS_DIR}/cases/{{run}}.nc", run=list(OPTIONS_RUNS)),
    output:
        csv=f"{OPTIONS_DIR}/table.csv",
        md=report(
            f"{OPTIONS_DIR}/table.md",
            caption="../report/options_table.rst",
            category="Options beyond the paper",
        ),
        forces_pdf=f"{OPTIONS_DIR}/forces.pdf",
        forces_png=report(
            f"{OPTIONS_DIR}/forces.png",
            caption="../report/options_forces.rst",
            category="Options beyond the paper",
        ),
        edges_pdf=f"{OPTIONS_DIR}/edges.pdf",
        edges_png=report(
            f"{OPTIONS_DIR}/edges.png",
            caption="../report/options_edges.rst",
            category="Options beyond the paper",
        ),
    log:
        logged("options/table.log"),
    conda:
        ENV
    threads: 1
    resources:
        mem_mb=2000,
        runtime=5,
    shell:
        f"{THREADS_ENV} {CAPSLIDE} options {OPTIONS_SPEC} --cases {OPTIONS_DIR}/cases -o {{output.csv}} -o {{output.md}} --forces {{output.forces_pdf}} --forces {{output.forces_png}} --edges {{output.edges_pdf}} --edges {{output.edges_png}} > {{log}} 2>&1"
