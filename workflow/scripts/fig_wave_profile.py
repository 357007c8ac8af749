"""First-harmonic wave amplitude along the tank against linear theory with viscous decay.

    python workflow/scripts/fig_wave_profile.py OUT.png RUN.nc [RUN2.nc ...] [--window T0 T1]

The workflow draws it from the wave-tank validation runs (rule ``validation_figure``,
``results/validation/<preset>/figures/fig_wave_profile.png``, window of the preset).

Each run is a ``wave_tank`` output with several surface probes. For every probe the
first-harmonic amplitude over the window (40-60 s unless ``--window`` gives another) is
plotted against x, with two references: linear flap theory decayed at the rate that the
run's artificial viscosity gives a progressive wave, and the incident-plus-reflected fit
of :func:`sph.study.validation.wave_separation` (the partial standing wave that the absorbing
zone's reflection adds). Probes nearer the flap than 0.6 depths sit in the flap's near
field and are drawn hollow.
"""

import argparse

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import xarray as xr  # noqa: E402

from sph.study.analysis import harmonic_fit  # noqa: E402
from sph.study.validation import (  # noqa: E402
    NEAR_FIELD_DEPTHS,
    _run_config,
    probe_positions,
    run_viscosity,
    run_wave_decay,
    wave_separation,
)

WINDOW = (40.0, 60.0)


def main(out: str, runs: list[str], window: tuple[float, float] = WINDOW) -> None:
    fig, ax = plt.subplots(figsize=(10, 4.2))
    for path, colour in zip(runs, plt.rcParams["axes.prop_cycle"].by_key()["color"],
                            strict=False):
        ds = xr.open_dataset(path)
        t = ds.time.values
        a = float(ds.attrs["theory_amplitude"])
        omega = float(ds.attrs["omega"])
        k = float(ds.attrs["theory_wavenumber"])
        depth = float(ds.attrs["depth"])
        sel = (t >= window[0]) & (t <= window[1])
        positions = probe_positions(ds)
        xs, amps = [], []
        for probe in ds.probe.values:
            z, _ = harmonic_fit(t[sel], ds.probe_elevation.sel(probe=probe).values[sel], omega)
            xs.append(positions[str(probe)])
            amps.append(abs(z) / a)
        xs, amps = np.array(xs), np.array(amps)
        order = np.argsort(xs)
        xs, amps = xs[order], amps[order]
        near = xs < NEAR_FIELD_DEPTHS * depth
        dx = float(ds.attrs["dx"])
        c_phase = omega / k
        c_zone = float(ds.attrs.get("absorber_speed", 0.0))
        if not c_zone:  # runs written before the attribute existed: from their configuration
            zone = (_run_config(ds).get("geometry") or {}).get("absorber") or {}
            c_zone = (zone.get("speed") or c_phase) * zone.get("strength", 1.0)
        label = f"SPH dx = {dx:g} m = {dx / a:.2f} A, zone c = {c_zone / c_phase:.2g} x phase speed"
        ax.plot(xs[~near], amps[~near], "o", color=colour, ms=5, label=label)
        ax.plot(xs[near], amps[near], "o", color=colour, ms=5, mfc="none")
        nu = run_viscosity(ds)
        beta = run_wave_decay(ds)
        xf = np.linspace(0.0, float(ds.attrs["absorber_start"]) if int(ds.attrs["absorber"])
                         else float(ds.attrs["tank_length"]), 300)
        ax.plot(xf, np.exp(-beta * xf), "--", color=colour, lw=1,
                label=f"linear theory, decay of nu = {nu:.2f} m2/s")
        sep = wave_separation(ds, window)
        if sep is not None:
            ai, ar = sep["a_incident"], sep["a_reflected"]
            model = np.abs(ai * np.exp(-1j * k * xf - beta * xf)
                           + ar * np.exp(1j * k * xf + beta * xf))
            ax.plot(xf, model / a, ":", color=colour, lw=1.3,
                    label=f"incident {sep['incident'] / a:.3f} A at the flap + reflected "
                          f"{100 * sep['coefficient']:.1f} %")
        ds.close()
    ax.axhline(1.0, color="k", lw=0.6)
    ax.set(xlabel="x from the flap hinge (m)", ylabel="first-harmonic amplitude / A theory",
           title=f"Wave amplitude along the tank, {window[0]:g}-{window[1]:g} s")
    ax.legend(fontsize=8, loc="lower left")
    fig.tight_layout()
    fig.savefig(out, dpi=110)


if __name__ == "__main__":
    if "snakemake" in globals():
        sm = globals()["snakemake"]
        main(sm.output[0], list(sm.input), tuple(sm.params.window))
    else:
        ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
        ap.add_argument("out")
        ap.add_argument("runs", nargs="+")
        ap.add_argument("--window", nargs=2, type=float, default=WINDOW, metavar=("T0", "T1"))
        args = ap.parse_args()
        main(args.out, args.runs, tuple(args.window))
