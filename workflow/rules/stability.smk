# snakemake --cores 2 stability: the hard cases of config/stability.yaml and their table
# (not part of the default reproduction; outputs under results/studies/stability/).
import yaml

STABILITY_SPEC = "config/stability.yaml"
STABILITY = yaml.safe_load(open(STABILITY_SPEC))
STABILITY_DIR = "results/studies/stability"
STABILITY_RUNS = [n for n, c in STABILITY["cases"].items() if c["expect"] != "rejected"]


rule stability:
    input:
        f"{STABILITY_DIR}/table.csv",
        f"{STABILITY_DIR}/table.md",


rule stability_case:
    input:
        CONFIG_FILES,
        STABILITY_SPEC,
        pull_off=lambda wc: (
            [f"{STABILITY_DIR}/pull_off.nc"] if "pull_off_fraction" in STABILITY["cases"][wc.name] else []
        ),
    output:
        f"{STABILITY_DIR}/{{name}}.nc",
    wildcard_constraints:
        name="|".join(re.escape(n) for n in STABILITY_RUNS),
    params:
        pull_off=lambda wc, input: f"--pull-off {input.pull_off[0]}" if input.pull_off else "",
    log:
        f"logs/stability/{{name}}.log",
    benchmark:
        f"results/benchmarks/stability/{{name}}.tsv"
    threads: 1
    resources:
        mem_mb=2000,
        runtime=30,
    # exit 3 (detached) and 4 (diverged) still write the case file; the table judges the status
    shell:
        THREADS_ENV + " sets=$(" + CAPSLIDE + " stability-overrides " + STABILITY_SPEC
        + " {wildcards.name} {params.pull_off}); rc=0; " + CAPSLIDE + " run " + CONFIG_ARGS
        + " $sets -o {output} > {log} 2>&1 || rc=$?; test $rc -eq 0 -o $rc -eq 3 -o $rc -eq 4"


rule stability_table:
    input:
        STABILITY_SPEC,
        expand(f"{STABILITY_DIR}/{{name}}.nc", name=STABILITY_RUNS),
    output:
        csv=f"{STABILITY_DIR}/table.csv",
        md=report(f"{STABILITY_DIR}/table.md", caption="../report/stability.rst", category="Stability"),
    log:
        "logs/stability/table.log",
    threads: 1
    resources:
        mem_mb=2000,
        runtime=5,
    shell:
        THREADS_ENV + " " + CAPSLIDE + " stability " + STABILITY_SPEC + " " + CONFIG_ARGS
        + " --cases " + STABILITY_DIR + " -o {output.csv} -o {output.md} > {log} 2>&1"
