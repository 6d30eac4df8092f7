# Model and experiment figures of the paper, drawn from the contact laws.
MODEL_FIGURES = ["Tn", "modelCA", "modelAM", "TnTt", "exp_FnJKR"]
MODEL_FIGURE_FILES = expand(
    result("figures/{name}.{ext}"), name=MODEL_FIGURES, ext=["pdf", "png"]
)


rule model_figure:
    input:
        CONFIG_FILES,
    output:
        pdf=result("figures/{name}.pdf"),
        png=report(
            result("figures/{name}.png"),
            caption="../report/model_figure.rst",
            category="Contact models",
        ),
    log:
        logged("figures/{name}.log"),
    benchmark:
        result("benchmarks/figures/{name}.tsv")
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
