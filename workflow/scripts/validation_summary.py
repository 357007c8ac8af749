"""Validation metrics of every target at one preset: a CSV table and an HTML page.

Rule ``validation_summary``: ``snakemake.input.<target>`` (the runs of each target, in the
order of ``snakemake.params.runs[target]``) -> ``snakemake.output.csv``, ``.html``. Each
target is measured by the metric of its record in ``sph.study.validation.TARGETS``; the page
lists the targets' references and the tolerances the project's tests ask of them.
"""


import csv
import html
import logging

from sph.io.output import read_dataset
from sph.study import validation


def main(inputs: dict, runs: dict, window, data_dir: str, out_csv: str, out_html: str) -> None:
    rows = []
    for target, paths in inputs.items():
        sets = {run: read_dataset(p) for run, p in zip(runs[target], paths, strict=True)}
        rows += validation.TARGETS[target].metric(sets, window, data_dir)
    fields = ["target", "run", "quantity", "measured", "reference", "unit", "error", "source"]
    with open(out_csv, "w", newline="") as fh:
        writer = csv.DictWriter(fh, fieldnames=fields)
        writer.writeheader()
        writer.writerows(rows)

    def cell(v):
        if isinstance(v, float):
            return "" if v != v else f"{v:.4g}"
        return html.escape(str(v))

    body = "\n".join("<tr>" + "".join(f"<td>{cell(r[f])}</td>" for f in fields) + "</tr>"
                     for r in rows)
    about = "\n".join(
        "<tr>" + "".join(f"<td>{cell(v)}</td>" for v in (t.id, t.compares, t.reference,
                                                          t.tolerance)) + "</tr>"
        for t in (validation.TARGETS[name] for name in inputs))
    with open(out_html, "w") as fh:
        fh.write("<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>Validation"
                 "</title><style>body{font-family:sans-serif;font-size:14px}table{border-"
                 "collapse:collapse}td,th{border:1px solid #999;padding:3px 6px}th{background:"
                 "#ddd}</style></head><body><h2>Validation ladder</h2><p>error: measured / "
                 "reference - 1, or for a series against an experiment the RMS difference "
                 "over the experiment's half range.</p><table><tr>"
                 + "".join(f"<th>{f}</th>" for f in fields) + "</tr>\n" + body
                 + "</table><h3>Targets</h3><p>tolerance: what the project's validation tests "
                 "ask of each comparison at the resolution of docs/validation/; the metrics "
                 "above are not judged against it.</p><table><tr><th>target</th><th>compares"
                 "</th><th>reference</th><th>tolerance</th></tr>\n" + about
                 + "</table></body></html>\n")
    logging.getLogger("validation").info("%d metrics", len(rows))


if __name__ == "__main__":
    sm = globals()["snakemake"]
    logging.basicConfig(filename=sm.log[0], level=logging.INFO)
    targets = list(sm.params.runs)
    main({t: list(sm.input[t]) for t in targets}, dict(sm.params.runs), list(sm.params.window),
         sm.params.data_dir, sm.output.csv, sm.output.html)
