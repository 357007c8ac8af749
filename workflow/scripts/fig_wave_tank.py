"""Wave elevation at WP1 and WP2 against linear theory (analogue of Cao et al. 2019, Fig. 7).

    python workflow/scripts/fig_wave_tank.py OUT.png RUN1.nc [RUN2.nc ...] [--window T0 T1]

Each run is a ``wave_tank`` output (e.g. at dx = 0.4 A, 0.2 A, 0.1 A). The theory curves are
the linear signalling solution driven by the flap angle the finest run recorded
(:func:`sph.study.validation.linear_wave_record`: start-up front, amplitude and phase, nothing
fitted), without and with the viscous decay that the finest run's artificial viscosity
amounts to. Panel titles give the steady amplitude of every run over the grey window
(40-60 s unless ``--window`` gives another).
"""


import argparse

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import xarray as xr  # noqa: E402

from sph.study.validation import linear_wave_record, run_viscosity, steady_wave  # noqa: E402

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
            notes.append(f"{dx / a:.1f}A: {s['amplitude']:.3f} m "
                         f"({100 * (s['amplitude'] / a - 1):+.1f} %)")
        finest = sets[-1]
        t, eta = linear_wave_record(finest, probe)
        ax.plot(t, eta, "k--", lw=1, label=f"linear theory, A = {a:.3f} m")
        nu = run_viscosity(finest)
        t, eta = linear_wave_record(finest, probe, nu=nu)
        ax.plot(t, eta, ":", color="0.35", lw=1.2,
                label=f"linear theory with the viscous decay of nu = {nu:.2f} m2/s")
        ax.axvspan(*window, color="0.92", zorder=-1)
        ax.set(ylabel=f"$\\eta$ at {probe} (m)",
               title=f"{probe}: steady amplitude " + ", ".join(notes))
        ax.set_ylim(-1.8 * a, 1.35 * a)  # room for the legend below the troughs
        ax.legend(fontsize=8, loc="lower left", ncol=3)
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
