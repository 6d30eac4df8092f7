# The study's cases: one netCDF file per (model, preload), from config["study"] (capslide.studies.expansion).
# The approach and the preload do not depend on the friction model: they are computed once per preload into a
# normal state (capslide preload), and every case whose overrides act only from the slide on starts from it
# (capslide run --from-state, bitwise the same case file). A state goes on from the state at the last preload its
# own path passes (capslide.loadpath.preload_targets): with loading.preload_via listing the study's preloads,
# the five states form one chain (0, -0.144, -0.288 by loading, +0.144, +0.288 by retraction), and only the
# first approaches. Other cases approach and preload themselves.
STUDY = config["study"]
CASES = expand_study(STUDY, "study", "config")  # case name -> overrides
CASE_FILES = expand(
    result("cases/{case}.nc"), case=list(CASES)
)  # study order: the cube's model order
SHARED_PRELOADS = {
    case: f"{sets['loading.preload']:+.3f}"
    for case, sets in CASES.items()
    if shares_normal_state(config, sets)
}
RETRACT_FROM = f"{config['loading']['retract_from']:+.3f}"
STATE_FILE = result(
    "states/Fn{preload}.npz"
)  # the normal state at a preload (formatted +0.000)
STATE_PRELOADS = {  # file name -> the exact preload of its cases
    SHARED_PRELOADS[case]: CASES[case]["loading.preload"] for case in SHARED_PRELOADS
}
if any(value > 0 for value in STATE_PRELOADS.values()):
    STATE_PRELOADS.setdefault(RETRACT_FROM, config["loading"]["retract_from"])


PREVIOUS_STATE = {
    name: previous_state(value, STATE_PRELOADS.values())
    for name, value in STATE_PRELOADS.items()
}


rule normal_state:
    input:
        CONFIG_FILES,
        previous=lambda wildcards: (
            STATE_FILE.format(preload=PREVIOUS_STATE[wildcards.preload])
            if PREVIOUS_STATE[wildcards.preload]
            else []
        ),
    output:
        STATE_FILE,
    log:
        logged("states/Fn{preload}.log"),
    benchmark:
        result("benchmarks/states/Fn{preload}.tsv")
    wildcard_constraints:
        preload=(
            "|".join(re.escape(p) for p in STATE_PRELOADS)
            if STATE_PRELOADS
            else "none"
        ),
    priority: 10  # the cases wait for it
    conda:
        ENV
    threads: 1
    resources:
        mem_mb=4000,
        runtime=60,
    params:
        overrides=lambda wildcards: set_args(
            {"loading.preload": STATE_PRELOADS[wildcards.preload]}
        ),
        code=SOURCE_DIGEST,  # a change of the code reruns the states (Snakemake's params trigger)
        start=lambda wildcards, input: (
            f"--from-state {input.previous}" if input.previous else ""
        ),
    shell:
        f"{THREADS_ENV} {CAPSLIDE} preload --resume {CONFIG_ARGS} {{params.overrides}} {{params.start}} -o {{output}} > {{log}} 2>&1"


rule run_case:
    input:
        CONFIG_FILES,
        state=lambda wildcards: (
            STATE_FILE.format(preload=SHARED_PRELOADS[wildcards.case])
            if wildcards.case in SHARED_PRELOADS
            else []
        ),
    output:
        result("cases/{case}.nc"),
    log:
        logged("cases/{case}.log"),
    benchmark:
        result("benchmarks/cases/{case}.tsv")
    wildcard_constraints:
        case="|".join(re.escape(c) for c in CASES) if CASES else "none",
    priority: lambda wildcards: case_priority(CASES[wildcards.case])
    conda:
        ENV
    threads: 1
    resources:
        mem_mb=4000,
        runtime=120,
    params:
        overrides=lambda wildcards: set_args(CASES[wildcards.case]),
        start=lambda wildcards, input: (
            f"--from-state {input.state}" if input.state else ""
        ),
    shell:
        f"{THREADS_ENV} {CAPSLIDE} run --resume {CONFIG_ARGS} {{params.overrides}} {{params.start}} -o {{output}} > {{log}} 2>&1"
