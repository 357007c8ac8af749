"""The dam break with a refinement box at the impact wall against uniform runs.

The built-in ``dam_break`` (Koshizuka & Oka 1996) to t = 1 s at a uniform dx = 0.04 m
(``coarse``), 0.02 m (``fine``) and 0.04 m with a level-1 box at x in [3.3, 4.5] m,
z in [-0.5, 1.2] m around the right wall and the run-up (``refined``: 0.02 m there).

    python benchmarks/refinement_dam_break.py run --mode refined --out DIR [--threads 1]
    python benchmarks/refinement_dam_break.py report DIR

``report`` prints, per run, the surge front's lead over the experiment up to 0.6 s (RMS and
largest, :func:`sph.study.validation.dam_break`) and the mean pressure at the wall probe
over windows that start at the impact (0.69-0.79, 0.69-0.89, 0.70-1.00 s), each against
the fine run, and writes ``DIR/refinement_dam_break.json``.
"""

from __future__ import annotations

import json
import time
from pathlib import Path

import numpy as np
import xarray as xr
from compare import run_report_main

from sph.cases import builtin
from sph.driver import Simulation
from sph.study.validation import dam_break

MODES = {"coarse": (0.04, False), "fine": (0.02, False), "refined": (0.04, True)}
BOX = {"x": [3.3, 4.5], "z": [-0.5, 1.2], "level": 1}
#: windows of the mean wall pressure (s): the first impact and longer
WINDOWS = ((0.69, 0.79), (0.69, 0.89), (0.70, 1.00))


def run(args) -> None:
    dx, refined = MODES[args.mode]
    over = [("numerics.dx", dx), ("run.t_end", 1.0), ("run.output_interval", 0.0025),
            ("numerics.threads", args.threads)]
    if refined:
        over.append(("numerics.refinement", [BOX]))
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    sim = Simulation(builtin("dam_break", over))
    t0 = time.perf_counter()
    sim.run(out / f"dam_{args.mode}.nc")
    print(f"{args.mode}: {sim.step} steps, {time.perf_counter() - t0:.0f} s")


def _wall_pressure(ds) -> list[float]:
    t = ds["time"].values
    p = ds["probe_pressure"].isel(pressure_probe=0).values
    return [float(np.mean(p[(t >= a) & (t <= b)])) for a, b in WINDOWS]


def report(args) -> None:
    d = Path(args.dir)
    runs = {m: xr.open_dataset(d / f"dam_{m}.nc") for m in MODES
            if (d / f"dam_{m}.nc").exists()}
    front = {r["run"].split(" ")[0]: r["measured"] for r in dam_break(runs)
             if r["quantity"] == "front lead, RMS"}
    lead = {r["run"].split(" ")[0]: r["measured"] for r in dam_break(runs)
            if r["quantity"].startswith("front lead, largest")}
    fine = _wall_pressure(runs["fine"]) if "fine" in runs else None
    result = {}
    for mode, ds in runs.items():
        p = _wall_pressure(ds)
        result[mode] = dict(front_rms=front.get(mode), front_largest=lead.get(mode),
                            wall_pressure=p, windows=WINDOWS,
                            relative_to_fine=None if fine is None else
                            [a / b - 1.0 for a, b in zip(p, fine, strict=True)],
                            wall_seconds=float(ds.attrs.get("wall_clock_seconds", 0.0)))
        r = result[mode]
        rel = ("" if r["relative_to_fine"] is None else
               " (" + ", ".join(f"{100 * v:+.1f} %" for v in r["relative_to_fine"]) + ")")
        print(f"{mode}: front RMS {100 * r['front_rms']:.1f} %, largest "
              f"{100 * r['front_largest']:.1f} %; mean wall pressure "
              + ", ".join(f"{v / 1e3:.1f}" for v in p) + f" kPa{rel}; "
              f"{r['wall_seconds']:.0f} s")
    (d / "refinement_dam_break.json").write_text(json.dumps(result, indent=1))


def _run_args(parser) -> None:
    parser.add_argument("--mode", choices=sorted(MODES), required=True)
    parser.add_argument("--threads", type=int, default=1)


def main() -> None:
    run_report_main(__doc__, run, report, _run_args)


if __name__ == "__main__":
    main()
