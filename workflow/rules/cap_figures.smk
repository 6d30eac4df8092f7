# Cap figures of the paper, drawn from the collected dataset only.
CAP_FIGURES = ["cap_PxAndAc", "cap_PxOverAc"]
CAP_FIGURE_FILES = expand("results/figures/{name}.{ext}", name=CAP_FIGURES, ext=["pdf", "png"])


rule cap_figure:
    input:
        "results/cases.nc",
    output:
        pdf="results/figures/{name}.pdf",
        png="results/figures/{name}.png",
    wildcard_constraints:
        name="|".join(CAP_FIGURES),
    log:
        "logs/figures/{name}.log",
    benchmark:
        "results/benchmarks/figures/{name}.tsv"
    threads: 1
    resources:
        mem_mb=2000,
        runtime=5,
    shell:
        THREADS_ENV + " " + CAPSLIDE + " figure {wildcards.name} --input {input} -o {output.pdf} -o {output.png} > {log} 2>&1"
