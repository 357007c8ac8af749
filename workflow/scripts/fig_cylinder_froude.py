"""The steady wave behind a submerged cylinder in a current against Havelock's linear
theory, over the Froude number.

Usable by a Snakemake rule (``snakemake.input``/``snakemake.output``) or from the shell:

    python workflow/scripts/fig_cylinder_froude.py OUT.png RUN1.nc [RUN2.nc ...]

Left: the fitted amplitude of the steady wave (over the gauges from 0.5 to 1.5 theoretical
wave lengths behind the cylinder, time mean over the run's second half) against
F = U / sqrt(g f), beside 4 pi a^2 K exp(-K f) with K = g / U^2 (both over a). Middle: the
amplitude at each output (theory's wavenumber held) over its theory's, with the averaged
stretch marked. Right: each run's time-mean surface profile behind the cylinder in units of
a, with its theoretical wave.
"""


import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import xarray as xr  # noqa: E402

from sph.cases.current import havelock_wave  # noqa: E402
from sph.study.current import (  # noqa: E402
    amplitude_history,
    averaged,
    gauge_positions,
    havelock_comparison,
)


def main(out: str, runs: list[str]) -> None:
    fig, (ax, ax3, ax2) = plt.subplots(1, 3, figsize=(17, 4.4))
    froude, amp, dx = [], [], []
    a = f = None
    for path in runs:
        ds = xr.open_dataset(path)
        fit = havelock_comparison(ds)
        a, f = float(ds.attrs["cylinder_radius"]), float(ds.attrs["cylinder_submergence"])
        froude.append(fit["froude"])
        amp.append(fit["amplitude"])
        dx.append(float(ds.attrs["dx"]))
        names, x = gauge_positions(ds)
        t = ds["time"].values
        late = averaged(t)
        eta = ds["probe_elevation"].sel(probe=list(names)).values[:, late]
        xc = float(ds.attrs["cylinder_x"])
        hist = amplitude_history(ds)
        (h,) = ax3.plot(t, hist["amplitude_ratio"], lw=1.0, label=f"F = {fit['froude']:.3f}")
        ax3.plot(t[late], np.full(late.sum(), fit["amplitude_ratio"]), "--",
                 color=h.get_color(), lw=1.0)
        (line,) = ax2.plot((x - xc) / a, eta.mean(axis=1) / a,
                           label=f"F = {fit['froude']:.3f}: A = {fit['amplitude'] / a:.3f} a, "
                                 f"{100 * (fit['amplitude_ratio'] - 1):+.0f} %")
        k, amp_th = float(ds.attrs["theory_wavenumber"]), float(ds.attrs["theory_amplitude"])
        ax2.plot((x - xc) / a, -amp_th * np.sin(k * (x - xc)) / a, "--", lw=0.8,
                 color=line.get_color())
        ds.close()
    ff = np.linspace(0.9 * min(froude), 1.1 * max(froude), 200)
    th = [havelock_wave(a, f, F * np.sqrt(9.81 * f))["amplitude"] / a for F in ff]
    ax.plot(ff, th, "k-", label="linear theory (Havelock 1926)")
    froude, amp, dx = np.array(froude), np.array(amp), np.array(dx)
    for d in sorted(set(dx), reverse=True):  # one line per resolution
        sel = dx == d
        order = np.argsort(froude[sel])
        ax.plot(froude[sel][order], amp[sel][order] / a, "o-",
                label=f"SPH, dx = {d:g} m (a / dx = {a / d:.0f})")
    ax.set(xlabel="$F = U / \\sqrt{g f}$", ylabel="wave amplitude A / a",
           title=f"Submerged cylinder, a / f = {a / f:.2f}")
    ax.legend(fontsize=8)
    ax3.axhline(1.0, color="k", lw=0.5)
    ax3.axhspan(0.85, 1.15, color="0.9", zorder=0)
    ax3.set(xlabel="t (s)", ylabel="A / A$_{theory}$",
            title="amplitude at each output (dashed: the time mean's fit)")
    ax3.legend(fontsize=8)
    ax2.set(xlabel="$(x - x_c) / a$", ylabel="$\\bar\\eta / a$",
            title="time-mean surface behind the cylinder (dashed: theory)")
    ax2.axhline(0, color="k", lw=0.5)
    ax2.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(out, dpi=110)


if __name__ == "__main__":
    if "snakemake" in globals():
        sm = globals()["snakemake"]
        main(sm.output[0], list(sm.input))
    else:
        main(sys.argv[1], sys.argv[2:])
