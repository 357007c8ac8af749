# Workflow entry point: `snakemake --cores 2` from the repository root.
# The rules live in workflow/rules/*.smk and are included here as they are written.

configfile: "config/config.yaml"


rule all:
    input:
        [],
