# Workflow entry point: `snakemake --cores 2` from the repository root runs the default sweep
# (config/config.yaml: the paper's Table I and the validation ladder); another sweep runs with
# `snakemake --cores 2 --configfile config/sweeps/NAME.yaml`. The report:
# `snakemake --report report.html`.

from snakemake.utils import min_version

min_version("8.0")


configfile: "config/config.yaml"


report: "workflow/report/workflow.rst"


include: "workflow/rules/common.smk"
include: "workflow/rules/simulate.smk"
include: "workflow/rules/gather.smk"
include: "workflow/rules/validation.smk"
include: "workflow/rules/figures.smk"


rule all:
    input:
        all_targets(),
    default_target: True
