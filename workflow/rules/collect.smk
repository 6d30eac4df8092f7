# Stack every case of the study into results/cases.nc (coordinates model, s_cut, preload).


rule collect:
    input:
        CASE_FILES,
    output:
        "results/cases.nc",
    log:
        "logs/collect.log",
    benchmark:
        "results/benchmarks/collect.tsv"
    conda:
        ENV
    threads: 1
    resources:
        mem_mb=4000,
        runtime=10,
    shell:
        f"{THREADS_ENV} {CAPSLIDE} collect {{input}} -o {{output}} > {{log}} 2>&1"
