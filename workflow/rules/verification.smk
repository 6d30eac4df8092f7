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
        f"{THREADS_ENV} {CAPSLIDE} verify {{input}} --scene {{wildcards.scene}} -q -o {{output}} > {{log}} 2>&1"


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


# snakemake --cores 2 verification3d: the 3D sphere against the Hertz and Maugis-Dugdale spheres (docs/three_d.md).
VERIFICATION_3D_SCENES = ["sphere_hertz", "sphere_md3", "sphere_md5"]


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
        mem_mb=6000,
        runtime=180,
    shell:
        f"{THREADS_ENV} {CAPSLIDE} verify {{input}} -q -o {{output}} > {{log}} 2>&1"


# snakemake --cores 2 sphere: the sphere scene (3D, normal contact) at its fast preset, checkpointed (--resume
# continues an interrupted run), and its figures: the normal traction over the contact, the load against the radius.
rule sphere:
    input:
        result("sphere/sphere_Tn.pdf"),
        result("sphere/sphere_Pa.pdf"),


rule sphere_case:
    input:
        "config/scenes/sphere.yaml",
    output:
        result("sphere/sphere.nc"),
    log:
        logged("sphere/sphere.log"),
    benchmark:
        result("benchmarks/sphere/sphere.tsv")
    conda:
        ENV
    threads: 1
    resources:
        mem_mb=4000,
        runtime=120,
    shell:
        f"{THREADS_ENV} {CAPSLIDE} run --resume {{input}} -q -o {{output}} > {{log}} 2>&1"


rule sphere_figure:
    input:
        result("sphere/sphere.nc"),
    output:
        pdf=result("sphere/{figure}.pdf"),
        png=result("sphere/{figure}.png"),
    log:
        logged("sphere/{figure}.log"),
    wildcard_constraints:
        figure="sphere_Tn|sphere_Pa",
    conda:
        ENV
    threads: 1
    resources:
        mem_mb=1000,
        runtime=5,
    shell:
        f"{THREADS_ENV} {CAPSLIDE} figure {{wildcards.figure}} --input {{input}} -o {{output.pdf}} -o {{output.png}} > {{log}} 2>&1"
