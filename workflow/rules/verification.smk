# snakemake --cores 2 verification: Hertz and JKR scenes against the closed forms.
VERIFICATION_SCENES = ["hertz", "jkr"]


rule verification:
    input:
        result("verification/verification.pdf"),
        result("verification/verification.png"),
        expand(result("verification/{scene}.csv"), scene=VERIFICATION_SCENES),


rule verify_scene:
    input:
        "config/scenes/{scene}.yaml",
    output:
        result("verification/{scene}.csv"),
    log:
        logged("verification/{scene}.log"),
    benchmark:
        result("benchmarks/verification/{scene}.tsv")
    wildcard_constraints:
        scene="|".join(VERIFICATION_SCENES),
    conda:
        ENV
    threads: 1
    resources:
        mem_mb=4000,
        runtime=60,
    shell:
        f"{THREADS_ENV} {CAPSLIDE} verify {{input}} --scene {{wildcards.scene}} -o {{output}} > {{log}} 2>&1"


rule verification_figure:
    input:
        expand(result("verification/{scene}.csv"), scene=VERIFICATION_SCENES),
    output:
        pdf=result("verification/verification.pdf"),
        png=report(
            result("verification/verification.png"),
            caption="../report/verification.rst",
            category="Verification",
        ),
    log:
        logged("verification/figure.log"),
    benchmark:
        result("benchmarks/verification/figure.tsv")
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


# snakemake --cores 2 verification3d: the 3D sphere against the Hertz and Maugis-Dugdale spheres, the latter under
# its own law (sphere_md3, sphere_md5) and under the Dugdale law (sphere_dugdale3) (docs/three_d.md).
VERIFICATION_3D_SCENES = ["sphere_hertz", "sphere_md3", "sphere_md5", "sphere_dugdale3"]


rule verification3d:
    input:
        expand(result("verification3d/{scene}.csv"), scene=VERIFICATION_3D_SCENES),


rule verify_scene_3d:
    input:
        "config/scenes/{scene}.yaml",
    output:
        result("verification3d/{scene}.csv"),
    log:
        logged("verification3d/{scene}.log"),
    benchmark:
        result("benchmarks/verification3d/{scene}.tsv")
    wildcard_constraints:
        scene="|".join(VERIFICATION_3D_SCENES),
    conda:
        ENV
    threads: 1
    resources:
        mem_mb=9000,  # sphere_md3: 7.8 GB peak (docs/three_d.md)
        runtime=480,  # sphere_md5: hours a load on one core beside other jobs (docs/three_d.md)
    shell:
        f"{THREADS_ENV} {CAPSLIDE} verify {{input}} --resume -o {{output}} > {{log}} 2>&1"
