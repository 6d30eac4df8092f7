# Model and experiment figures of the paper, drawn from the contact laws.
MODEL_FIGURES = ["Tn", "modelCA", "modelAM", "TnTt", "exp_FnJKR"]
MODEL_FIGURE_FILES = expand(
    "results/figures/{name}.{ext}", name=MODEL_FIGURES, ext=["pdf", "png"]
)


rule model_figure:
    input:
        CONFIG_FILES,
    output:
        pdf="results/figures/{name}.pdf",
        png=report(
            "results/figures/{name}.png",
            caption="../report/model_figure.rst",
            category="Contact models",
        ),
    log:
        "logs/figures/{name}.log",
    benchmark:
        "results/benchmarks/figures/{name}.tsv"
    wildcard_constraints:
        name="|".join(MODEL_FIGURES),
    conda:
        ENV
    threads: 1
    resources:
        mem_mb=500,
        runtime=5,
    shell:
        f"{THREADS_ENV} {CAPSLIDE} figure {{wildcards.name}} {CONFIG_ARGS} -o {{output.pdf}} -o {{output.png}} > {{log}} 2>&1"
