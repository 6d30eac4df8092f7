# snakemake --cores 2 verification: Hertz and JKR scenes against the closed forms.
VERIFICATION_SCENES = ["hertz", "jkr"]


rule verification:
    input:
        "results/verification/verification.pdf",
        "results/verification/verification.png",
        expand("results/verification/{scene}.csv", scene=VERIFICATION_SCENES),


rule verify_scene:
    input:
        "config/scenes/{scene}.yaml",
    output:
        "results/verification/{scene}.csv",
    log:
        "logs/verification/{scene}.log",
    benchmark:
        "results/benchmarks/verification/{scene}.tsv"
    wildcard_constraints:
        scene="|".join(VERIFICATION_SCENES),
    conda:
        ENV
    threads: 1
    resources:
        mem_mb=4000,
        runtime=60,
    shell:
        f"{THREADS_ENV} {CAPSLIDE} verify {{input}} --scene {{wildcards.scene}} -q -o {{output}} > {{log}} 2>&1"


rule verification_figure:
    input:
        expand("results/verification/{scene}.csv", scene=VERIFICATION_SCENES),
    output:
        pdf="results/verification/verification.pdf",
        png=report(
            "results/verification/verification.png",
            caption="../report/verification.rst",
            category="Verification",
        ),
    log:
        "logs/verification/figure.log",
    benchmark:
        "results/benchmarks/verification/figure.tsv"
    conda:
        ENV
    threads: 1
    resources:
        mem_mb=1000,
        runtime=5,
    params:
        tables=lambda wildcards, input: " ".join(f"--table {t}" for t in input),
    shell:
        f"{THREADS_ENV} {CAPSLIDE} figure verification {{params.tables}} -o {{output.pdf}} -o {{output.png}} > {{log}} 2>&1"
