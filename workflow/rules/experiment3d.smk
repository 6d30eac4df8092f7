# The experiment in numbers (issue 40, docs/experiment3d.md): the `experiment` scene's study section, one case per
# initial contact area A0 (each preloaded to its area, then slid on the 410 N/m cantilever) and the lambda checks at
# one area; the table and the figures. The cases of one lambda start from its normal state at zero load (the
# approach and the spread, computed once). A case whose contact came off (exit 3) or whose slide found no equilibrium
# (exit 4) keeps its file: the table says how it ended. `snakemake --cores 2 experiment3d` runs it; a rerun resumes
# the states and cases from their checkpoints. Not part of the default reproduction; outputs under
# results/<config>/experiment3d/.
EXPERIMENT3D_SCENE = "config/scenes/experiment.yaml"
EXPERIMENT3D_CASES = experiment3d_cases(EXPERIMENT3D_SCENE)
EXPERIMENT3D_STATES = normal_states(EXPERIMENT3D_CASES)
EXPERIMENT3D_DIR = result("experiment3d")


rule experiment3d_state:
    input:
        EXPERIMENT3D_SCENE,
    output:
        f"{EXPERIMENT3D_DIR}/states/{{state}}.npz",
    log:
        logged("experiment3d/states/{state}.log"),
    benchmark:
        result("benchmarks/experiment3d/states/{state}.tsv")
    wildcard_constraints:
        state="|".join(re.escape(c) for c in EXPERIMENT3D_STATES),
    priority: 10
    conda:
        ENV
    threads: 1
    resources:
        mem_mb=4000,
        runtime=180,
    params:
        overrides=lambda wildcards: set_args(EXPERIMENT3D_STATES[wildcards.state]),
        code=SOURCE_DIGEST,
    shell:
        f"{THREADS_ENV} {CAPSLIDE} preload --resume --scene experiment {{params.overrides}} -o {{output}} > {{log}} 2>&1"


rule experiment3d:
    input:
        f"{EXPERIMENT3D_DIR}/table.md",


rule experiment3d_case:
    input:
        EXPERIMENT3D_SCENE,
        state=lambda wildcards: f"{EXPERIMENT3D_DIR}/states/lambda{EXPERIMENT3D_CASES[wildcards.case]['adhesion.maugis_lambda']:g}.npz",
    output:
        f"{EXPERIMENT3D_DIR}/cases/{{case}}.nc",
    log:
        logged("experiment3d/{case}.log"),
    benchmark:
        result("benchmarks/experiment3d/{case}.tsv")
    wildcard_constraints:
        case="|".join(re.escape(c) for c in EXPERIMENT3D_CASES),
    # the larger contacts slide longer (A0 = 0.46 mm^2 takes the most time): started first, two jobs end sooner
    priority: lambda wildcards: EXPERIMENT3D_CASES[wildcards.case]["loading.preload_area"] / 1.0e6
    conda:
        ENV
    threads: 1
    resources:
        mem_mb=4000,
        runtime=180,
    params:
        overrides=lambda wildcards: set_args(EXPERIMENT3D_CASES[wildcards.case]),
    shell:
        f"{THREADS_ENV} rc=0; {CAPSLIDE} run --resume --scene experiment {{params.overrides}} --from-state {{input.state}} -o {{output}} > {{log}} 2>&1 || rc=$?; test $rc -eq 0 -o $rc -eq 3 -o $rc -eq 4"


rule experiment3d_table:
    input:
        expand(f"{EXPERIMENT3D_DIR}/cases/{{case}}.nc", case=list(EXPERIMENT3D_CASES)),
    output:
        csv=f"{EXPERIMENT3D_DIR}/table.csv",
        md=f"{EXPERIMENT3D_DIR}/table.md",
        panels=f"{EXPERIMENT3D_DIR}/panels.pdf",
        outlines=f"{EXPERIMENT3D_DIR}/outlines.pdf",
    log:
        logged("experiment3d/table.log"),
    conda:
        ENV
    threads: 1
    resources:
        mem_mb=2000,
        runtime=10,
    shell:
        f"{THREADS_ENV} {CAPSLIDE} experiment3d {{input}} -o {{output.csv}} -o {{output.md}} --panels {{output.panels}} --outlines {{output.outlines}} > {{log}} 2>&1"
