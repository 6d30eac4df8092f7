# snakemake --cores 2 stability: the hard cases of config/stability.yaml and their table
# (not part of the default reproduction; outputs under results/<config>/studies/stability/).
STABILITY_SPEC = "config/stability.yaml"
STABILITY = read_spec(STABILITY_SPEC)
STABILITY_REJECTED = [
    n
    for n, c in (STABILITY or {}).get("cases", {}).items()
    if isinstance(c, dict) and c.get("expect") == "rejected"
]
# case name -> overrides; the cases expected to be rejected are not validated (the table checks their refusal)
STABILITY_RUNS = expand_study(
    STABILITY, "stability", STABILITY_SPEC, skip=STABILITY_REJECTED
)
STABILITY_DIR = result("studies/stability")
STABILITY_CASES = [n for n in STABILITY_RUNS if n not in STABILITY_REJECTED]
# cases whose preload is a fraction of the pull-off force of the case 'pull_off'
STABILITY_FRACTIONS = {
    n: c["pull_off_fraction"]
    for n, c in STABILITY["cases"].items()
    if "pull_off_fraction" in c
}


rule stability:
    input:
        f"{STABILITY_DIR}/table.csv",
        f"{STABILITY_DIR}/table.md",


rule stability_preload:
    input:
        f"{STABILITY_DIR}/pull_off.nc",
    output:
        f"{STABILITY_DIR}/{{name}}.preload.yaml",
    log:
        logged(f"stability/{{name}}.preload.log"),
    wildcard_constraints:
        name=(
            "|".join(re.escape(n) for n in STABILITY_FRACTIONS)
            if STABILITY_FRACTIONS
            else "none"
        ),
    conda:
        ENV
    threads: 1
    resources:
        mem_mb=1000,
        runtime=5,
    params:
        fraction=lambda wildcards: STABILITY_FRACTIONS[wildcards.name],
    shell:
        f"{THREADS_ENV} {CAPSLIDE} pull-off {{input}} --fraction {{params.fraction}} -o {{output}} > {{log}} 2>&1"


rule stability_case:
    input:
        CONFIG_FILES,
        STABILITY_SPEC,
        overlay=lambda wildcards: (
            [f"{STABILITY_DIR}/{wildcards.name}.preload.yaml"]
            if wildcards.name in STABILITY_FRACTIONS
            else []
        ),
    output:
        f"{STABILITY_DIR}/{{name}}.nc",
    log:
        logged(f"stability/{{name}}.log"),
    benchmark:
        result(f"benchmarks/stability/{{name}}.tsv")
    wildcard_constraints:
        name="|".join(re.escape(n) for n in STABILITY_CASES),
    conda:
        ENV
    threads: lambda wildcards: STABILITY["cases"][wildcards.name].get("writers", 1)
    resources:
        mem_mb=2000,
        runtime=30,
    params:
        overrides=lambda wildcards: set_args(STABILITY_RUNS[wildcards.name]),
        writers=lambda wildcards: STABILITY["cases"][wildcards.name].get("writers", 1),
    # `writers` runs at once write the same file (the last rename wins); each must end with exit 0, 3 (detached) or
    # 4 (diverged), which still write the case file; the table judges the status. Logs: {log}, {log}.2, ...
    shell:
        f'{THREADS_ENV} pids=; for i in $(seq {{params.writers}}); do out={{log}}; [ $i -gt 1 ] && out={{log}}.$i; {CAPSLIDE} run {CONFIG_ARGS} {{input.overlay}} {{params.overrides}} -o {{output}} > $out 2>&1 & pids="$pids $!"; done; rc=0; for p in $pids; do wait $p || {{{{ c=$?; [ $c -eq 3 -o $c -eq 4 ] || rc=$c; }}}}; done; exit $rc'


rule stability_table:
    input:
        STABILITY_SPEC,
        expand(f"{STABILITY_DIR}/{{name}}.nc", name=STABILITY_CASES),
    output:
        csv=f"{STABILITY_DIR}/table.csv",
        md=report(
            f"{STABILITY_DIR}/table.md",
            caption="../report/stability.rst",
            category="Stability",
        ),
    log:
        logged("stability/table.log"),
    conda:
        ENV
    threads: 1
    resources:
        mem_mb=2000,
        runtime=5,
    shell:
        f"{THREADS_ENV} {CAPSLIDE} stability {STABILITY_SPEC} {CONFIG_ARGS} --cases {STABILITY_DIR} -o {{output.csv}} -o {{output.md}} > {{log}} 2>&1"
