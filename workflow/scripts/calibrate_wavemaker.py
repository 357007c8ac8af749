"""Calibrate the flap angle of a ship case's wave at the ship's position.

Rule ``calibrate_wavemaker``: ``snakemake.params.document`` (a ship case file) ->
``snakemake.output[0]``, a JSON record of the calibrated angle and of every wave-tank run
(:func:`sph.study.calibration.calibrate`), on the rule's ``threads``.
"""


import json
import logging

from sph.study.calibration import calibrate


def main(document: dict, out: str, threads: int = 1) -> None:
    log = logging.getLogger("calibration")
    document = dict(document)
    document["numerics"] = dict(document.get("numerics") or {}, threads=int(threads))
    result = calibrate(document)
    for k, r in enumerate(result["runs"], start=1):
        log.info("run %d: theta0 = %.6g rad -> incident amplitude %.5g m at x = %g m "
                 "(target %.5g m)", k, r["theta0"], r["amplitude"], result["x"],
                 result["target"])
    with open(out, "w") as fh:
        json.dump(result, fh, indent=1)


if __name__ == "__main__":
    snakemake = globals()["snakemake"]
    logging.basicConfig(filename=snakemake.log[0], level=logging.INFO,
                        format="%(levelname)s %(message)s")
    main(dict(snakemake.params.document), snakemake.output[0], snakemake.threads)
