"""The paper's findings measured on a sweep dataset: a CSV table, an HTML page and the
same page in Markdown.

Rule ``findings``: ``snakemake.input.nc`` -> ``snakemake.output.csv``, ``.html``, ``.md``
and ``.spectra`` (where each case's records sit after t2: :func:`sph.study.findings.spectra_table`).
"""


import csv
import logging

from sph.io.output import read_dataset
from sph.study.findings import (
    SPECTRA_COLUMNS,
    compute_findings,
    departures,
    fast_runs,
    finding_cases,
    findings_html,
    findings_markdown,
    findings_table,
    particle_losses,
    spectra_table,
    stopped_runs,
    zone_entries,
)
from sph.study.sweeps import one_wave


def write_csv(path, rows, columns) -> None:
    """``rows`` (dicts) as a CSV table with the header ``columns``."""
    with open(path, "w", newline="") as fh:
        writer = csv.DictWriter(fh, fieldnames=list(columns))
        writer.writeheader()
        writer.writerows(rows)


def main(nc, groups, t2_periods, title, out_csv, out_html, out_md, out_spectra) -> None:
    ds = read_dataset(nc)
    found = compute_findings(ds, groups, t2_periods)
    rows = findings_table(found)
    write_csv(out_csv, rows, rows[0])
    write_csv(out_spectra, spectra_table(ds, groups, t2_periods), SPECTRA_COLUMNS)
    # the findings' cases, at one wave (a sweep over wave frequency has several)
    ds = one_wave(ds, finding_cases(groups))
    period = float(ds.attrs["wave_period"])
    note = (f"Sweep '{ds.attrs.get('sweep', '')}' at preset '{ds.attrs.get('preset', '')}' "
            f"(dx = {ds.attrs.get('dx', float('nan')):g} m), runs to t/T = "
            f"{float(ds['time'][-1]) / period:.2f}; damage at t1/T = "
            f"{float(ds.attrs['damage_time']) / period:.2f}; dynamic equilibrium taken from "
            f"t2/T = {t2_periods:g}. Measures: see sph/study/findings.py.")
    differ = departures(ds)
    note += (" Runs that differ from the paper: " + "; ".join(differ) + "." if differ
             else " No run differs from the paper in its cargo.")
    stopped = stopped_runs(ds, period)
    if stopped:
        note += (" Runs that stopped before their end (their findings after that are not "
                 "determinable): " + "; ".join(stopped) + ".")
    fast = fast_runs(ds, period)
    if fast:
        note += (" Runs in which some particle outran a tenth of the speed of sound after "
                 "the damage (spray beyond weak compressibility; read their findings with "
                 "care): " + "; ".join(fast) + ".")
    losses = particle_losses(ds)
    if losses:
        note += (" Runs whose fluid went through the walls (particles that left the domain "
                 "are removed; those found just through a fixed tank wall are put back): "
                 + "; ".join(losses) + ".")
    elif losses is not None:
        note += " No run lost a fluid particle or had one put back through a wall."
    drifted = zone_entries(ds, period)
    if drifted:
        note += (" Runs whose hull drifted into the absorbing zone (the findings that read "
                 "them after t2 end there): " + "; ".join(drifted) + ".")
    heading = f"Findings of Cao et al. (2019) on: {title}"
    with open(out_html, "w") as fh:
        fh.write(findings_html(found, heading, note))
    with open(out_md, "w") as fh:
        fh.write(findings_markdown(found, heading, note))
    for f in found:
        logging.getLogger("findings").info("%s %s: %s", f.id, f.verdict, f.measured)
    for line in differ:
        logging.getLogger("findings").info("differs from the paper: %s", line)
    for line in stopped:
        logging.getLogger("findings").warning("stopped early: %s", line)
    for line in fast:
        logging.getLogger("findings").warning("fast particles: %s", line)
    for line in losses or []:
        logging.getLogger("findings").warning("particles through the walls: %s", line)
    for line in drifted:
        logging.getLogger("findings").info("hull in the absorbing zone: %s", line)


if __name__ == "__main__":
    snakemake = globals()["snakemake"]
    logging.basicConfig(filename=snakemake.log[0], level=logging.INFO,
                        format="%(levelname)s %(message)s")
    main(snakemake.input.nc, dict(snakemake.params.groups), float(snakemake.params.t2_periods),
         snakemake.params.title, snakemake.output.csv, snakemake.output.html,
         snakemake.output.md, snakemake.output.spectra)
