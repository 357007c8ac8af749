"""Free sloshing: centre-of-mass oscillation and first-mode frequency against theory.

    python workflow/scripts/fig_sloshing.py OUT.png RUN1.nc [RUN2.nc ...]

Each run is a ``sloshing_rect`` or ``sloshing_u`` output; the title of each panel gives the
measured frequency, linear theory for a rectangular tank of the same width and depth, and
for the U-shaped cabin the paper's Table II value.
"""


import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import xarray as xr  # noqa: E402

from sph.study.validation import frequency  # noqa: E402

TABLE_II = {0.25: 0.87, 0.5: 1.12, 0.75: 1.26}  # Cao et al. (2019), U-shaped cabin, rad/s


def main(out: str, runs: list[str]) -> None:
    fig, axes = plt.subplots(len(runs), 1, figsize=(8, 2.2 * len(runs)), squeeze=False)
    for ax, path in zip(axes[:, 0], runs, strict=True):
        ds = xr.open_dataset(path)
        t, xc = ds.time.values, ds.centre_of_mass_x.values
        omega, _ = frequency(t, xc)
        theory = float(ds.attrs["linear_frequency_rect"])
        fill = float(ds.attrs["fill"])
        text = (f"{ds.attrs['case']}, fill {fill:.0%}, dx = {ds.attrs['dx']:g} m: "
                f"$\\omega$ = {omega:.4f} rad/s, rectangular theory {theory:.4f}")
        if ds.attrs["case"] == "sloshing_u" and fill in TABLE_II:
            text += f", Table II {TABLE_II[fill]:.2f}"
        ax.plot(t, xc - xc.mean(), lw=1)
        ax.set_title(text, fontsize=9)
        ax.set_ylabel("$x_c - \\bar{x}_c$ (m)")
        ds.close()
    axes[-1, 0].set_xlabel("t (s)")
    fig.tight_layout()
    fig.savefig(out, dpi=110)


if __name__ == "__main__":
    if "snakemake" in globals():
        sm = globals()["snakemake"]
        main(sm.output[0], list(sm.input))
    else:
        main(sys.argv[1], sys.argv[2:])
