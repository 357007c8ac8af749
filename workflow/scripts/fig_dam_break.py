"""Dam-break front against Koshizuka & Oka (1996) and the Ritter bound.

Usable by a Snakemake rule (``snakemake.input``/``snakemake.output``) or from the shell:

    python workflow/scripts/fig_dam_break.py OUT.png RUN1.nc [RUN2.nc ...]
"""


import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import xarray as xr  # noqa: E402

from sph.study.analysis import koshizuka_front, ritter_front  # noqa: E402


def main(out: str, runs: list[str]) -> None:
    exp = koshizuka_front()
    fig, (ax, ax2) = plt.subplots(1, 2, figsize=(11, 4.2))
    tt = np.linspace(0, 0.8, 50)
    ax.plot(tt, ritter_front(tt, 1.0, 2.0), "k:", label="shallow water (Ritter) bound")
    ax.plot(exp[:, 0], exp[:, 1], "ko", mfc="none", label="Koshizuka & Oka (1996)")
    sel = exp[:, 0] <= 0.6
    for path in runs:
        ds = xr.open_dataset(path)
        label = f"SPH dx = {ds.attrs['dx']:g} m, {ds.attrs['kernel']}, {ds.attrs['density_filter']}"
        ax.plot(ds.time, ds.front_position, label=label)
        rel = np.interp(exp[sel, 0], ds.time.values, ds.front_position.values) / exp[sel, 1] - 1
        ax2.plot(exp[sel, 0], 100 * rel, "o-", label=label)
        ds.close()
    ax.set(xlabel="t (s)", ylabel="front position x (m)", xlim=(0, 0.8), ylim=(1, 4.2),
           title="Dam break, 1 m x 2 m column")
    ax.legend(fontsize=8)
    ax2.axhline(15, color="r", ls="--", lw=0.8)
    ax2.axhline(16, color="grey", ls=":", lw=0.8)
    ax2.axhline(0, color="k", lw=0.5)
    ax2.set(xlabel="t (s)", ylabel="lead over experiment (%)", title="SPH lead (free-slip floor)")
    ax2.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out, dpi=120)


if __name__ == "__main__":
    if "snakemake" in globals():
        sm = globals()["snakemake"]
        main(sm.output[0], list(sm.input))
    else:
        main(sys.argv[1], sys.argv[2:])
