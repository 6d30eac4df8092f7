# The paper's study on the sphere (issue 40): the sphere scene's study section, models x preloads, slid from the
# scene's normal states, collected into results/<config>/sphere/cases.nc, and its figures. The scene's normal
# states form one chain (loading.preload_via: zero load, then the compressive preload by loading, then the tensile
# one by retraction from loading.retract_from), and every case slides from the state at its preload, as the
# cap's study does (workflow/rules/cases.smk). `snakemake --cores 2 sphere` runs it; a rerun resumes the cases.
SPHERE_SCENE = "config/scenes/sphere.yaml"
SPHERE_CONFIG = load_config([SPHERE_SCENE])
# The study's linear solver: PARDISO's LU factors, reused as GMRES's preconditioner (MKL: `make sphere` sets it up
# first; without it the jobs stop with one line naming solver.factorization). On the study's mesh (36,450 DOF) it
# ran the normal state 2.9 and DI's slide 3.7 times faster than pyamg, which `solver.linear: auto` takes in 3D, to
# the same results (docs/three_d.md, pyamg as the engine; benchmarks/sphere_solvers.py). Its factors fill in (3.9 GB
# at 138k DOF against pyamg's 2.1): pyamg is the solver of the million-DOF sphere.
SPHERE_SOLVER = {"solver.linear": "lu_krylov", "solver.factorization": "pardiso"}
SPHERE_CASES = expand_scene_study(
    SPHERE_SCENE, SPHERE_CONFIG["study"], "sphere study", SPHERE_SOLVER
)
SPHERE_PRELOADS = {
    f"{sets['loading.preload']:+.3f}": sets["loading.preload"]
    for sets in SPHERE_CASES.values()
}
SPHERE_STATE = result("sphere/states/Fn{preload}.npz")
SPHERE_PREVIOUS = {
    name: scene_previous_state(SPHERE_CONFIG, value, SPHERE_PRELOADS.values())
    for name, value in SPHERE_PRELOADS.items()
}
SPHERE_FIGURES = [
    "sphere_PxAndAc",
    "sphere_PxOverAc",
    "sphere_FtOverA",
    "sphere_Aczoom",
    "sphere_Tn",
    "sphere_Pa",
]


rule sphere:
    input:
        expand(result("sphere/{figure}.pdf"), figure=SPHERE_FIGURES),


rule sphere_state:
    input:
        SPHERE_SCENE,
        previous=lambda wildcards: (
            SPHERE_STATE.format(preload=SPHERE_PREVIOUS[wildcards.preload])
            if SPHERE_PREVIOUS[wildcards.preload]
            else []
        ),
    output:
        SPHERE_STATE,
    log:
        logged("sphere/states/Fn{preload}.log"),
    benchmark:
        result("benchmarks/sphere/states/Fn{preload}.tsv")
    wildcard_constraints:
        preload="|".join(re.escape(p) for p in SPHERE_PRELOADS),
    priority: 10
    conda:
        ENV
    threads: 1
    resources:
        mem_mb=4000,
        runtime=120,
    params:
        overrides=lambda wildcards: set_args(
            {**SPHERE_SOLVER, "loading.preload": SPHERE_PRELOADS[wildcards.preload]}
        ),
        code=SOURCE_DIGEST,
        start=lambda wildcards, input: (
            f"--from-state {input.previous}" if input.previous else ""
        ),
    shell:
        f"{THREADS_ENV} {CAPSLIDE} preload --resume --scene sphere {{params.overrides}} {{params.start}} -o {{output}} > {{log}} 2>&1"


rule sphere_study_case:
    input:
        SPHERE_SCENE,
        state=lambda wildcards: SPHERE_STATE.format(
            preload=f"{SPHERE_CASES[wildcards.case]['loading.preload']:+.3f}"
        ),
    output:
        result("sphere/cases/{case}.nc"),
    log:
        logged("sphere/cases/{case}.log"),
    benchmark:
        result("benchmarks/sphere/cases/{case}.tsv")
    wildcard_constraints:
        case="|".join(re.escape(c) for c in SPHERE_CASES),
    conda:
        ENV
    threads: 1
    resources:
        mem_mb=4000,
        runtime=240,
    params:
        overrides=lambda wildcards: set_args(SPHERE_CASES[wildcards.case]),
    shell:
        f"{THREADS_ENV} {CAPSLIDE} run --resume --scene sphere {{params.overrides}} --from-state {{input.state}} -o {{output}} > {{log}} 2>&1"


rule sphere_collect:
    input:
        expand(result("sphere/cases/{case}.nc"), case=list(SPHERE_CASES)),
    output:
        result("sphere/cases.nc"),
    log:
        logged("sphere/collect.log"),
    conda:
        ENV
    threads: 1
    resources:
        mem_mb=4000,
        runtime=10,
    shell:
        f"{THREADS_ENV} {CAPSLIDE} collect {{input}} -o {{output}} > {{log}} 2>&1"


rule sphere_study_figure:
    input:
        result("sphere/cases.nc"),
    output:
        pdf=result("sphere/{figure}.pdf"),
        png=result("sphere/{figure}.png"),
    log:
        logged("sphere/{figure}.log"),
    wildcard_constraints:
        figure="sphere_PxAndAc|sphere_PxOverAc|sphere_FtOverA",
    conda:
        ENV
    threads: 1
    resources:
        mem_mb=1000,
        runtime=5,
    shell:
        f"{THREADS_ENV} {CAPSLIDE} figure {{wildcards.figure}} --input {{input}} -o {{output.pdf}} -o {{output.png}} > {{log}} 2>&1"


# the normal traction at zero load, the load against the radius on the way there, and the outlines during the slide:
# from the DI case at zero load (its file holds the approach and the preload too)
rule sphere_case_figure:
    input:
        result("sphere/cases/DI_Fn+0.000.nc"),
    output:
        pdf=result("sphere/{figure}.pdf"),
        png=result("sphere/{figure}.png"),
    log:
        logged("sphere/{figure}.log"),
    wildcard_constraints:
        figure="sphere_Aczoom|sphere_Tn|sphere_Pa",
    conda:
        ENV
    threads: 1
    resources:
        mem_mb=1000,
        runtime=5,
    shell:
        f"{THREADS_ENV} {CAPSLIDE} figure {{wildcards.figure}} --input {{input}} -o {{output.pdf}} -o {{output.png}} > {{log}} 2>&1"
