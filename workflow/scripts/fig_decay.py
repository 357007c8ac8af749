"""Free roll and heave decay of the intact ship against Table II (1.06 and 1.28 rad/s).

    python workflow/scripts/fig_decay.py OUT.png ROLL.nc HEAVE.nc

Each run is a ``ship_decay`` output; a run with a non-zero initial heel is drawn as roll,
the others as heave. Panel titles give the fitted frequency and damping ratio.
"""


import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from sph.io.output import read_dataset  # noqa: E402
from sph.study.validation import TABLE_II_HEAVE, TABLE_II_ROLL, frequency  # noqa: E402


def main(out: str, runs: list[str]) -> None:
    fig, axes = plt.subplots(len(runs), 1, figsize=(8, 2.6 * len(runs)), squeeze=False)
    for ax, path in zip(axes[:, 0], runs, strict=True):
        ds = read_dataset(path)
        roll = float(ds.attrs.get("heel", 0.0)) != 0.0
        name, ref, unit = ("roll", TABLE_II_ROLL, "deg") if roll else ("heave", TABLE_II_HEAVE,
                                                                       "m")
        t, y = ds["time"].values, ds[name].values
        omega, zeta = frequency(t, y)
        ax.plot(t, y, lw=1)
        ax.set_ylabel(f"{name} ({unit})")
        ax.set_title(f"{name} decay, dx = {float(ds.attrs['dx']):g} m: omega = {omega:.3f} "
                     f"rad/s (Table II {ref:.2f}, {100 * (omega / ref - 1):+.1f} %), "
                     f"damping ratio {zeta:.3f}", fontsize=9)
        ax.grid(alpha=0.3)
    axes[-1, 0].set_xlabel("t (s)")
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    plt.close(fig)


if __name__ == "__main__":
    if "snakemake" in globals():
        sm = globals()["snakemake"]
        main(sm.output[0], list(sm.input))
    else:
        main(sys.argv[1], sys.argv[2:])
