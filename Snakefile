# capslide: reproduce the numerical study of Mergel, Sahli, Scheibert, Sauer (2019).
#   snakemake --cores 2                      full reproduction (results/)
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
include: "workflow/rules/collect.smk"
include: "workflow/rules/cap_figures.smk"
include: "workflow/rules/stability.smk"
include: "workflow/rules/convergence.smk"


rule all:
    input:
        model_figures=MODEL_FIGURE_FILES,
        cap_setup=["results/figures/cap_setup.pdf", "results/figures/cap_setup.png"],
        cases=CASE_FILES,
        collected="results/cases.nc",
        cap_figures=CAP_FIGURE_FILES,
    default_target: True
