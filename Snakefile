# capslide: reproduce the numerical study of Mergel, Sahli, Scheibert, Sauer (2019).
#   snakemake --cores 2                      full reproduction (results/paper/: a folder per configuration)
#   snakemake --cores 2 --configfile X.yaml  the same with X.yaml merged on top
from snakemake.utils import min_version

min_version("9.0")


DEFAULT_CONFIG = "config/config.yaml"


configfile: DEFAULT_CONFIG


report: "workflow/report/workflow.rst"


include: "workflow/rules/common.smk"
include: "workflow/rules/model_figures.smk"
include: "workflow/rules/meshes.smk"
include: "workflow/rules/cases.smk"
include: "workflow/rules/verification.smk"
include: "workflow/rules/sphere.smk"
include: "workflow/rules/collect.smk"
include: "workflow/rules/cap_figures.smk"
include: "workflow/rules/stability.smk"
include: "workflow/rules/convergence.smk"
include: "workflow/rules/options.smk"
include: "workflow/rules/experiment.smk"
include: "workflow/rules/experiment3d.smk"
include: "workflow/rules/report_config.smk"


# Jobs of seconds run where Snakemake runs, not as cluster jobs.
localrules:
    all,
    cases,
    model_figure,
    mesh,
    cap_setup_figure,
    collect,
    cap_figure,
    case_figure,
    vtk_export,
    paraview,
    verification_figure,
    stability_preload,
    stability_table,
    convergence_table,
    options_table,
    experiment_table,
    experiment3d_table,
    effective_config,
    stability,
    verification,
    verification3d,
    sphere,
    convergence,
    options,
    experiment,
    experiment3d,


rule all:
    default_target: True
    input:
        model_figures=MODEL_FIGURE_FILES,
        cap_setup=[result("figures/cap_setup.pdf"), result("figures/cap_setup.png")],
        cases=CASE_FILES,
        collected=result("cases.nc"),
        cap_figures=CAP_FIGURE_FILES,
        config=result("config.yaml"),


# The study's cases and their cube, without figures: snakemake --cores 2 cases (under results/NAME/, NAME as above)
rule cases:
    input:
        result("cases.nc"),


onstart:
    print(f"capslide: this configuration writes to {RESULTS}/ and logs/{RESULTS_NAME}/")
