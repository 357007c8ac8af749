"""Roll and heave response over wave frequency of a sweep (the ship's RAOs).

Rule ``rao_figure``: the sweep dataset ``snakemake.input.nc`` and ``snakemake.params.t2_periods``
-> ``snakemake.output.png`` (roll amplitude over the wave slope k A and heave amplitude over
the wave amplitude A against omega, one line per ship, solid with every harmonic and dotted
with the first harmonic alone, the intact roll natural frequency marked; a note names the
runs read only up to where their hull drifted into the absorbing zone) and
``snakemake.output.csv`` (the table of :func:`sph.study.response.response_table`).

    python workflow/scripts/fig_rao.py OUT.png OUT.csv SWEEP.nc [T2_PERIODS]
"""


import logging
import math
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from sph.io.output import read_dataset  # noqa: E402
from sph.study.response import (  # noqa: E402
    INTACT_ROLL_FREQUENCY,
    curves,
    response_table,
    write_csv,
)

PANELS = (("roll_rao", "roll amplitude / wave slope kA (deg/deg)"),
          ("heave_rao", "heave amplitude / wave amplitude A"))


def zone_note(rows) -> str:
    """The runs whose hull drifted into the absorbing zone: read up to there, or no
    amplitudes where that came before t2 + T; empty where none did."""
    cut = [f"{r['case']} {r['read_to']:.3g} T" for r in rows
           if math.isfinite(r["zone_entry"]) and math.isfinite(r["roll_rao"])]
    lost = [r["case"] for r in rows if not math.isfinite(r["roll_rao"])]
    parts = []
    if cut:
        parts.append("read to where the hull reached the absorbing zone: " + ", ".join(cut))
    if lost:
        parts.append("hull in the absorbing zone before t2 + T, no amplitude: "
                     + ", ".join(lost))
    return "; ".join(parts)


def main(out_png, out_csv, nc, t2_periods=7.0, title="") -> dict:
    """Draw the figure and write the table; returns the response curves."""
    ds = read_dataset(nc)
    rows = response_table(ds, t2_periods)
    write_csv(rows, out_csv)
    lines = curves(rows)
    fig, axes = plt.subplots(len(PANELS), 1, figsize=(7.5, 6.4), sharex=True)
    for ax, (name, label) in zip(axes, PANELS, strict=True):
        for ship, curve in lines.items():
            w = [r["omega"] for r in curve]
            (line,) = ax.plot(w, [r[name] for r in curve], "o-", lw=1.2, ms=4, label=ship)
            ax.plot(w, [r[f"{name}_first"] for r in curve], "o:", lw=0.9, ms=3, mfc="none",
                    color=line.get_color(), label=f"{ship}, first harmonic")
        ax.axvline(INTACT_ROLL_FREQUENCY, color="k", ls="--", lw=0.8,
                   label=f"intact roll natural frequency {INTACT_ROLL_FREQUENCY:g} rad/s")
        ax.axhline(1.0, color="0.6", ls=":", lw=0.8)
        ax.set_ylabel(label)
        ax.set_ylim(bottom=0.0)
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=8, loc="best")
    axes[-1].set_xlabel("wave frequency ω (rad/s)")
    steep = sorted({round(r["steepness"], 3) for r in rows})
    fig.suptitle(title or (
        f"sweep {ds.attrs.get('sweep', '')}, preset {ds.attrs.get('preset', '')} (dx = "
        f"{ds.attrs.get('dx', float('nan')):g} m): kA = {', '.join(f'{s:g}' for s in steep)}, "
        f"amplitudes after t2 = {t2_periods:g} T"), fontsize=9)
    note = zone_note(rows)
    fig.tight_layout(rect=(0, 0.03 if note else 0, 1, 1))
    if note:
        fig.text(0.01, 0.005, note, fontsize=7, ha="left", va="bottom", wrap=True)
    fig.savefig(out_png, dpi=110)
    plt.close(fig)
    return lines


if __name__ == "__main__":
    if "snakemake" in globals():
        sm = globals()["snakemake"]
        logging.basicConfig(filename=sm.log[0], level=logging.INFO)
        drawn = main(sm.output.png, sm.output.csv, sm.input.nc, float(sm.params.t2_periods))
        for ship, curve in drawn.items():
            logging.info("%s: %s", ship, "; ".join(
                f"omega {r['omega']:g}: roll/kA {r['roll_rao']:.3g}, heave/A "
                f"{r['heave_rao']:.3g}" for r in curve))
    else:
        main(sys.argv[1], sys.argv[2], sys.argv[3],
             float(sys.argv[4]) if len(sys.argv) > 4 else 7.0)
