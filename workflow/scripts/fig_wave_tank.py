"""Wave elevation at WP1 and WP2 against linear theory (analogue of Cao et al. 2019, Fig. 7).

    python workflow/scripts/fig_wave_tank.py OUT.png RUN1.nc [RUN2.nc ...] [--window T0 T1]

Each run is a ``wave_tank`` output (e.g. at dx = 0.4 A, 0.2 A, 0.1 A). The theory curve has
the linear-theory amplitude and period; its phase is matched to the finest run over the
steady window (the flap's start-up transient is outside linear theory; 40-60 s unless
``--window`` gives another). Panel titles give the steady amplitude of every run.
"""


import argparse

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import xarray as xr  # noqa: E402

from sph.analysis import harmonic_fit  # noqa: E402
from sph.validation import steady_wave  # noqa: E402

WINDOW = (40.0, 60.0)


def main(out: str, runs: list[str], window: tuple[float, float] = WINDOW) -> None:
    sets = [xr.open_dataset(p) for p in runs]
    sets.sort(key=lambda d: -float(d.attrs["dx"]))
    probes = [p for p in ("WP1", "WP2") if p in sets[0].probe.values]
    fig, axes = plt.subplots(len(probes), 1, figsize=(10, 3.2 * len(probes)), squeeze=False)
    for ax, probe in zip(axes[:, 0], probes, strict=True):
        notes = []
        for ds in sets:
            t = ds.time.values
            eta = ds.probe_elevation.sel(probe=probe).values
            omega = float(ds.attrs["omega"])
            a = float(ds.attrs["theory_amplitude"])
            s = steady_wave(t, eta, omega, window)
            dx = float(ds.attrs["dx"])
            ax.plot(t, eta, lw=1, label=f"SPH dx = {dx:g} m = {dx / a:.2f} A")
            notes.append(f"{dx / a:.1f}A: {s['amplitude']:.3f} m")
        finest = sets[-1]
        t = finest.time.values
        z, _ = harmonic_fit(t[t >= window[0]], finest.probe_elevation.sel(probe=probe).values[
            t >= window[0]], omega)
        ax.plot(t, a * np.cos(omega * t + np.angle(z)), "k--", lw=1,
                label=f"linear theory, A = {a:.3f} m")
        ax.axvspan(*window, color="0.92", zorder=-1)
        ax.set(ylabel=f"$\\eta$ at {probe} (m)",
               title=f"{probe}: steady amplitude " + ", ".join(notes))
        ax.legend(fontsize=8, loc="lower left", ncol=2)
    axes[-1, 0].set_xlabel("t (s)")
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    for ds in sets:
        ds.close()


if __name__ == "__main__":
    if "snakemake" in globals():
        sm = globals()["snakemake"]
        main(sm.output[0], list(sm.input), tuple(sm.params.window))
    else:
        ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
        ap.add_argument("out")
        ap.add_argument("runs", nargs="+")
        ap.add_argument("--window", nargs=2, type=float, default=WINDOW, metavar=("T0", "T1"))
        a = ap.parse_args()
        main(a.out, a.runs, tuple(a.window))
