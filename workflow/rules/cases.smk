# The study's cases: one netCDF file per (model, preload), from config["study"].
STUDY = config["study"]


def case_name(model, preload):
    return f"{model}_Fn{float(preload):+.3f}"


# full slides to ubar_max (f:cap:PxAndAc), then slides only to the onset of full sliding (f:cap:PxOverAc)
CASES = {case_name(m, f): (m, float(f)) for m in STUDY["models"] for f in STUDY["preloads"]}
ONSET_CASES = {
    case_name(m, f): (m, float(f)) for m in STUDY["models"] for f in STUDY["onset_preloads"]
    if case_name(m, f) not in CASES
}
CASES.update(ONSET_CASES)
CASE_FILES = expand("results/cases/{case}.nc", case=sorted(CASES))


def case_overrides(wildcards):
    model, preload = CASES[wildcards.case]
    sets = [f"{k}={v}" for k, v in STUDY["models"][model].items()] + [f"loading.preload={preload}"]
    if wildcards.case in ONSET_CASES:
        sets.append("loading.stop_at_onset=true")
    return " ".join(f"--set {shlex.quote(s)}" for s in sets)


rule run_case:
    input:
        CONFIG_FILES,
    output:
        "results/cases/{case}.nc",
    wildcard_constraints:
        case="|".join(re.escape(c) for c in CASES) if CASES else "none",
    params:
        overrides=case_overrides,
    log:
        "logs/cases/{case}.log",
    benchmark:
        "results/benchmarks/cases/{case}.tsv"
    threads: 1
    resources:
        mem_mb=4000,
        runtime=120,
    shell:
        THREADS_ENV + " " + CAPSLIDE + " run --resume " + CONFIG_ARGS + " {params.overrides} -o {output} > {log} 2>&1"
