# The configuration this run used, as validated (presets applied, defaults filled): results/<config>/config.yaml, in the report.


rule effective_config:
    input:
        CONFIG_FILES,
    output:
        report(
            result("config.yaml"),
            caption="../report/config.rst",
            category="Configuration",
        ),
    log:
        logged("config.log"),
    conda:
        ENV
    threads: 1
    resources:
        mem_mb=500,
        runtime=5,
    shell:
        f"{THREADS_ENV} {CAPSLIDE} config {CONFIG_ARGS} -o {{output}} > {{log}} 2>&1"
