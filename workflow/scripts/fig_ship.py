"""Ship-motion figures of a sweep against t/T (analogues of Cao et al. 2019, Figs. 10-23).

Rule ``ship_figure`` / ``overview_figure``: the sweep dataset ``snakemake.input.nc``, the
cases ``snakemake.params.cases`` and the series ``snakemake.params.series`` (dataset
variables, or the body-fixed probes ``W1``, cargo cabin, and ``W2``, damaged cabin) ->
``snakemake.output.png``. One panel per series, one line per case; with the group ``fill``
and probe series (Fig. 22), one panel per case with both probes, as the paper draws it.
Vertical lines: the damage time t1 and the start of the dynamic equilibrium t2. Each case
is drawn against its own t/T (in a sweep over wave frequency the cases' periods differ).

    python workflow/scripts/fig_ship.py OUT.png SWEEP.nc roll,heave [CASE ...]
"""


import logging
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from sph.io.output import read_dataset  # noqa: E402
from sph.study.findings import (  # noqa: E402
    case_label,
    case_zone_entry,
    fraction_text,
    last_sample,
)

LABELS = {
    "roll": "roll (deg)",
    "heave": "heave (m)",
    "sway": "sway (m)",
    "flood_ratio": "Q/V",
    "flood_volume": "Q (m$^2$)",
    "W1": "W1 elevation (m)",
    "W2": "W2 elevation (m)",
    "WP1": "WP1 elevation (m)",
    "WP2": "WP2 elevation (m)",
}


def _series(ds, case, name):
    if name in ds.data_vars:
        return ds[name].sel(case=case).values
    return ds["probe_elevation"].sel(case=case, probe=name).values


def _case(ds, case):
    c = ds.sel(case=case)
    out = dict(case=case, opening=float(c["opening"]), side=str(c["side"].values),
               fill=float(c["fill"]), amplitude=float(c["amplitude"]))
    if "omega" in c.coords:
        out["omega"] = float(c["omega"])
    return out


def _stopped(ds, case) -> str:
    """Empty, or where the run of ``case`` stopped before its end (a run that blew up,
    gathered NaN after its last sample: ``case_status``), for its label."""
    if "case_status" not in ds.data_vars or \
            str(ds["case_status"].sel(case=case).values) == "completed":
        return ""
    end = last_sample(ds["time"].values, ds["roll"].sel(case=case).values)
    return f" (stopped at t/T = {end / _wave(ds, case)[0]:.3g})"


#: the figure's note where a line carries a dot (sph.study.findings.case_zone_entry)
ZONE_NOTE = ("dot: where the ship's hull reached the absorbing zone, drifting with the "
             "waves; the findings read each run up to there")


def _in_zone(ds, case) -> str:
    """Empty, or from when the hull of ``case`` lies in the absorbing zone, for its panel's
    title (the findings read it up to then)."""
    t = case_zone_entry(ds, case)[0]
    return f" (in the absorbing zone from t/T = {t / _wave(ds, case)[0]:.3g})" \
        if np.isfinite(t) else ""


def _wave(ds, case):
    """The wave period (s) of a case and its damage time t1 / T (each case its own in a
    sweep over wave frequency)."""
    if "wave_period" in ds.data_vars:
        period = float(ds["wave_period"].sel(case=case))
        return period, float(ds["damage_time"].sel(case=case)) / period
    period = float(ds.attrs["wave_period"])
    return period, float(ds.attrs["damage_time"]) / period


def main(out, nc, series, cases=None, group="", t2_periods=None, title="") -> None:
    ds = read_dataset(nc)
    cases = list(cases or ds["case"].values)
    t1 = _wave(ds, cases[0])[1]
    probes_per_case = group == "fill" and all(s in ("W1", "W2") for s in series)
    if probes_per_case:
        panels = [(c, list(series)) for c in cases]
    else:
        panels = [(s, cases) for s in series]
    fig, axes = plt.subplots(len(panels), 1, figsize=(9, 2.4 * len(panels) + 0.6),
                             sharex=True, squeeze=False)
    zoned = False
    for ax, (key, lines) in zip(axes[:, 0], panels, strict=True):
        for line in lines:
            case, name = (key, line) if probes_per_case else (line, key)
            label = name if probes_per_case else case_label(_case(ds, case))
            if group == "amplitude" and not probes_per_case:
                amp = float(ds["amplitude"].sel(case=case))
                label = f"A/d = {fraction_text(amp)}" if amp > 0 else "still water"
            if not probes_per_case:
                label += _stopped(ds, case)
            ax.plot(ds["time"].values / _wave(ds, case)[0], _series(ds, case, name), lw=1.0,
                    label=label)
            entry = case_zone_entry(ds, case)[0]
            if np.isfinite(entry):  # where the findings stop reading it
                k = int(np.searchsorted(ds["time"].values, entry))
                ax.plot(entry / _wave(ds, case)[0], _series(ds, case, name)[k], "o",
                        color=ax.get_lines()[-1].get_color(), ms=4)
                zoned = True
        ax.axvline(t1, color="k", ls="--", lw=0.8)
        if t2_periods is not None:
            ax.axvline(t2_periods, color="0.5", ls=":", lw=0.8)
        if probes_per_case:
            ax.set_ylabel("elevation (m)")
            ax.set_title(case_label(_case(ds, key)) + _stopped(ds, key) + _in_zone(ds, key),
                         fontsize=9)
        else:
            ax.set_ylabel(LABELS.get(key, key))
        ax.legend(fontsize=7, ncol=min(4, len(lines)), loc="upper left")
        ax.grid(alpha=0.3)
    axes[-1, 0].set_xlabel("t / T")
    axes[0, 0].annotate("t1", (t1, 1.0), xycoords=("data", "axes fraction"), fontsize=8,
                        ha="left", va="bottom")
    if t2_periods is not None:
        axes[0, 0].annotate("t2", (t2_periods, 1.0), xycoords=("data", "axes fraction"),
                            fontsize=8, ha="left", va="bottom")
    fig.suptitle(title or f"sweep {ds.attrs.get('sweep', '')}, preset "
                 f"{ds.attrs.get('preset', '')} (dx = {ds.attrs.get('dx', float('nan')):g} m)",
                 fontsize=10)
    if zoned:
        fig.text(0.01, 0.005, ZONE_NOTE, fontsize=7, ha="left", va="bottom")
    fig.tight_layout(rect=(0.0, 0.02 if zoned else 0.0, 1.0, 1.0))
    fig.savefig(out, dpi=110)
    plt.close(fig)


if __name__ == "__main__":
    if "snakemake" in globals():
        sm = globals()["snakemake"]
        logging.basicConfig(filename=sm.log[0], level=logging.INFO)
        main(sm.output.png, sm.input.nc, list(sm.params.series), list(sm.params.cases),
             sm.params.group, float(sm.params.t2_periods))
        logging.info("wrote %s", sm.output.png)
    else:
        main(sys.argv[1], sys.argv[2], sys.argv[3].split(","), sys.argv[4:] or None)
