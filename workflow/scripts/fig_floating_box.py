"""Floating box in the Hadzic et al. (2005) wave group: wave probes and motions against the
experiment (analogue of Cao et al. 2019, Figs. 3 and 5).

    python workflow/scripts/fig_floating_box.py OUT.png RUN.nc [RUN2.nc ...]

Each run is a ``floating_box`` output driven by the experiment's flap signal; the
experimental series come from ``data/validation/hadzic2005`` (or
``$SPH_VALIDATION_DATA``).
"""


import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from sph.io.output import read_dataset  # noqa: E402
from sph.study.validation import (  # noqa: E402
    HADZIC_MAP,
    floating_box_errors,
    hadzic_series,
    simulated,
)

UNITS = {"m": "m", "degree": "deg"}


def main(out: str, runs: list[str], data_dir: str | None = None) -> None:
    path = (Path(data_dir) / "hadzic2005" / "EXP_FloatingWavesVal_Hadzic_et_al_2005.txt"
            if data_dir else None)
    exp = hadzic_series(path)
    sets = [read_dataset(p) for p in runs]
    errors = [floating_box_errors(ds, exp) for ds in sets]
    fig, axes = plt.subplots(len(HADZIC_MAP), 1, figsize=(9, 2.0 * len(HADZIC_MAP)),
                             sharex=True)
    for ax, (name, (variable, probe, unit)) in zip(axes, HADZIC_MAP.items(), strict=True):
        data = exp.get(name)
        if data is not None and len(data):
            ax.plot(data[:, 0], data[:, 1], "k.", ms=2.5, label="Hadzic et al. (2005)")
        for ds, err in zip(sets, errors, strict=True):
            y = simulated(ds, variable, probe)
            if y is not None:
                label = f"SPH dx = {float(ds.attrs['dx']):g} m"
                e = err.get(name)
                if e is not None:
                    label += (f": amplitude x{e['amplitude_ratio']:.2f}, lag "
                              f"{e['lag']:+.3f} s, r = {e['correlation']:.2f}")
                ax.plot(ds["time"].values, y, lw=1, label=label)
        ax.set_ylabel(f"{name}\n({UNITS[unit]})", fontsize=8)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7, loc="upper left")
    axes[-1].set_xlabel("t (s)")
    axes[-1].set_xlim(left=2.5)
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    plt.close(fig)


if __name__ == "__main__":
    if "snakemake" in globals():
        sm = globals()["snakemake"]
        main(sm.output[0], list(sm.input), sm.params.data_dir)
    else:
        main(sys.argv[1], sys.argv[2:])
