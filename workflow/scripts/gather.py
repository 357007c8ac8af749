"""Gather the runs of a sweep into one netCDF dataset with a ``case`` dimension.

Rule ``gather``: ``snakemake.input.nc`` (one file per case, in the order of
``snakemake.params.cases``) -> ``snakemake.output.nc``.
"""


import logging

from sph.io.output import write_netcdf_atomic
from sph.study.sweeps import gather


def main(paths, cases, attrs, out) -> None:
    ds = gather(paths, cases, attrs)
    write_netcdf_atomic(ds, out)
    log = logging.getLogger("gather")
    log.info("wrote %s: %d cases, %d times", out, ds.sizes["case"], ds.sizes["time"])
    for case, status in zip(ds["case"].values, ds["case_status"].values, strict=True):
        if status != "completed":
            log.warning("case %s stopped before its end (NaN after it): %s", case, status)


if __name__ == "__main__":
    snakemake = globals()["snakemake"]
    logging.basicConfig(filename=snakemake.log[0], level=logging.INFO,
                        format="%(levelname)s %(message)s")
    main(list(snakemake.input.nc), list(snakemake.params.cases), dict(snakemake.params.attrs),
         snakemake.output.nc)
