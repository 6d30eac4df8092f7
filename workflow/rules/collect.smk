# Stack every case of the study into results/<config>/cases.nc (coordinates model, s_cut, preload).


rule collect:
    input:
        CASE_FILES,
    output:
        result("cases.nc"),
    log:
        logged("collect.log"),
    benchmark:
        result("benchmarks/collect.tsv")
    conda:
        ENV
    threads: 1
    resources:
        mem_mb=4000,
        runtime=10,
    shell:
        f"{THREADS_ENV} {CAPSLIDE} collect {{input}} -o {{output}} > {{log}} 2>&1"
