"""Write the case file of one run (the rule's ``params.document``) as YAML."""


import sys

import yaml


def main(document: dict, out: str) -> None:
    text = yaml.safe_dump(document, sort_keys=False, default_flow_style=False)
    with open(out, "w") as fh:
        fh.write(f"# case file written by the workflow; run: sph run {out} -o OUT.nc\n")
        fh.write(text)


if __name__ == "__main__":
    snakemake = globals()["snakemake"]
    with open(snakemake.log[0], "w") as log:
        sys.stderr = log
        main(dict(snakemake.params.document), snakemake.output[0])
