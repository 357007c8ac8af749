"""Write the case file of one run (the rule's ``params.document``) as YAML; a ship run with a
wavemaker calibration (``input.calibration``, :mod:`sph.study.calibration`) takes its flap
angle."""


import json
import sys

import yaml


def main(document: dict, out: str, calibration: str | None = None) -> None:
    header = f"# case file written by the workflow; run: sph run {out} -o OUT.nc\n"
    if calibration:
        from sph.study.calibration import calibrated_document

        with open(calibration) as fh:
            result = json.load(fh)
        document = calibrated_document(document, result)
        header += (f"# flap angle from the wavemaker calibration {calibration}: incident "
                   f"amplitude {result['runs'][-1]['amplitude']:.4g} m at x = "
                   f"{result['x']:g} m for a target of {result['target']:.4g} m\n")
    text = yaml.safe_dump(document, sort_keys=False, default_flow_style=False)
    with open(out, "w") as fh:
        fh.write(header)
        fh.write(text)


if __name__ == "__main__":
    snakemake = globals()["snakemake"]
    with open(snakemake.log[0], "w") as log:
        sys.stderr = log
        cal = snakemake.input.get("calibration", None)
        if cal is not None and not isinstance(cal, str):  # a list of one or none
            cal = cal[0] if len(cal) else None
        main(dict(snakemake.params.document), snakemake.output[0], cal)
