# Meshes of the study (results/<config>/meshes/*.nc) and the setup figure f:cap:setup.
STUDY_MESH = result("meshes/cap_{element}_size{size}.nc").format(
    element=config["mesh"]["element"], size=config["mesh"]["size"]
)


rule mesh:
    input:
        CONFIG_FILES,
    output:
        result("meshes/cap_{element}_size{size}.nc"),
    log:
        logged("meshes/cap_{element}_size{size}.log"),
    benchmark:
        result("benchmarks/meshes/cap_{element}_size{size}.tsv")
    wildcard_constraints:
        element="Q1|Q2",
        size=r"[0-9.]+",
    conda:
        ENV
    threads: 1
    resources:
        mem_mb=2000,
        runtime=10,
    shell:
        f"{THREADS_ENV} {CAPSLIDE} mesh {CONFIG_ARGS} --set mesh.element={{wildcards.element}} --set mesh.size={{wildcards.size}} -o {{output}} > {{log}} 2>&1"


rule cap_setup_figure:
    input:
        STUDY_MESH,
    output:
        pdf=result("figures/cap_setup.pdf"),
        png=report(
            result("figures/cap_setup.png"),
            caption="../report/cap_setup.rst",
            category="Cap: sliding",
        ),
    log:
        logged("figures/cap_setup.log"),
    benchmark:
        result("benchmarks/figures/cap_setup.tsv")
    conda:
        ENV
    threads: 1
    resources:
        mem_mb=2000,
        runtime=10,
    shell:
        f"{THREADS_ENV} {CAPSLIDE} figure cap_setup --input {{input}} -o {{output.pdf}} -o {{output.png}} > {{log}} 2>&1"
