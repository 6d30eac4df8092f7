# Cap figures of the paper: force and area curves from the collected dataset,
# interface and stress snapshots from the case file of DI at zero load.
CAP_FIGURES = ["cap_PxAndAc", "cap_PxOverAc", "cap_FtOverA"]
CASE_FIGURES = ["cap_Aczoom", "cap_xn"]
# the case the paper's snapshot figures show: model DI, zero normal load
SNAPSHOT_CASE = next(
    (
        c
        for c, sets in sorted(CASES.items())
        if sets.get("friction.model") == "DI" and sets["loading.preload"] == 0.0
    ),
    None,
)
CAP_FIGURE_FILES = expand(
    result("figures/{name}.{ext}"), name=CAP_FIGURES, ext=["pdf", "png"]
)
if SNAPSHOT_CASE is not None:
    CAP_FIGURE_FILES += expand(
        result("figures/{name}.{ext}"), name=CASE_FIGURES, ext=["pdf", "png"]
    )


rule cap_figure:
    input:
        result("cases.nc"),
    output:
        pdf=result("figures/{name}.pdf"),
        png=report(
            result("figures/{name}.png"),
            caption="../report/cap_figure.rst",
            category="Cap: sliding",
        ),
    log:
        logged("figures/{name}.log"),
    benchmark:
        result("benchmarks/figures/{name}.tsv")
    wildcard_constraints:
        name="|".join(CAP_FIGURES),
    conda:
        ENV
    threads: 1
    resources:
        mem_mb=2000,
        runtime=5,
    shell:
        f"{THREADS_ENV} {CAPSLIDE} figure {{wildcards.name}} --input {{input}} -o {{output.pdf}} -o {{output.png}} > {{log}} 2>&1"


rule case_figure:
    input:
        result(f"cases/{SNAPSHOT_CASE}.nc"),
    output:
        pdf=result("figures/{name}.pdf"),
        png=report(
            result("figures/{name}.png"),
            caption="../report/case_figure.rst",
            category="Cap: sliding",
        ),
    log:
        logged("figures/{name}.log"),
    benchmark:
        result("benchmarks/figures/{name}.tsv")
    wildcard_constraints:
        name="|".join(CASE_FIGURES),
    conda:
        ENV
    threads: 1
    resources:
        mem_mb=4000,
        runtime=10,
    shell:
        f"{THREADS_ENV} {CAPSLIDE} figure {{wildcards.name}} --input {{input}} -o {{output.pdf}} -o {{output.png}} > {{log}} 2>&1"


# snakemake --cores 2 paraview: every case's field snapshots as .vtu series with a .pvd index (optional target).
rule paraview:
    input:
        expand(result("paraview/{case}/{case}.pvd"), case=sorted(CASES)),


rule vtk_export:
    input:
        result("cases/{case}.nc"),
    output:
        result("paraview/{case}/{case}.pvd"),
    log:
        logged("paraview/{case}.log"),
    wildcard_constraints:
        case="|".join(re.escape(c) for c in CASES) if CASES else "none",
    conda:
        ENV
    threads: 1
    resources:
        mem_mb=2000,
        runtime=10,
    shell:
        f"{THREADS_ENV} {CAPSLIDE} vtk {{input}} -o {RESULTS}/paraview/{{wildcards.case}} > {{log}} 2>&1"
