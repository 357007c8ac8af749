"""A flap that pulls back from the water faster than gravity lets the water follow: the three
rules of ``numerics.wall_tension`` (:mod:`sph.engine.surface`) side by side.

The built-in ``wave_tank`` case, made small and violent: water 1 m deep, the flap hinged at
the bottom and driven by theta(t) = 0.15 sin(10 t) from rest (no ramp), so that at the
still-water level it swings 0.15 m each way and pulls back with up to 1.5 g; a 3 m tank
with the damping zone over its last 1.5 m (the radiated wave is 0.62 m long). Each rule
runs the same case; every 0.01 s the script records the contact height of the water on the
flap (the highest fluid particle within 1.5 dx of the flap's face, in the flap's frame) and
the lowest fluid pressure within that distance, and keeps a snapshot of the particles near
the flap at ``--snapshot`` s. A run may lose up to 1 % of its fluid particles through the
walls (``run.max_lost_fraction``); the number lost is printed.

Linear wavemaker theory (Havelock 1929; Dean & Dalrymple 1991, Sec. 6.2, with the
evanescent modes) gives the pressure on the flap in the periodic state,
p(z, t) = rho g (H - z) - rho Re{i omega Phi(0, z) e^{i omega t}}: the figure marks the
height above which it is negative (tension: a wall that does not pull loses the water
there), to compare with the contact heights.

    python benchmarks/wall_tension_flap.py [--dx 0.02] [--t-end 1.4] [--data /tmp/flap.npz]
        [--plot-only] [--figure docs/validation/wall_tension.png]

Prints one JSON line with the numbers quoted in docs/validation/wall_tension.md.
"""

from __future__ import annotations

import argparse
import json
import math
import time
from pathlib import Path

import numpy as np

from sph.bodies.wavemaker import wavenumber
from sph.cases import builtin
from sph.driver import Simulation
from sph.engine.particles import FLUID

RULES = ("clamp", "free_surface", "none")
DEPTH, LENGTH, HEIGHT = 1.0, 3.0, 1.6
THETA0, OMEGA = 0.15, 10.0
G, RHO0 = 9.81, 1000.0
ROOT = Path(__file__).resolve().parent.parent


def config(rule: str, dx: float, t_end: float):
    return builtin("wave_tank", [
        ("numerics.dx", dx), ("numerics.wall_tension", rule), ("numerics.threads", 1),
        ("geometry.depth", DEPTH), ("geometry.tank_length", LENGTH),
        ("geometry.tank_height", HEIGHT), ("geometry.wavemaker.theta0", THETA0),
        ("geometry.wavemaker.omega", OMEGA), ("geometry.wavemaker.ramp_time", 0.0),
        ("geometry.absorber.start", 1.5), ("geometry.absorber.length", 1.5),
        ("probes.surface", [{"name": "P1", "x": 1.0}]), ("run.t_end", t_end),
        ("run.max_lost_fraction", 0.01)])


def flap_frame(p, theta):
    """Fluid positions in the flap's frame: ``u`` from its face into the water, ``w``
    along it from the hinge."""
    c, s = math.cos(theta), math.sin(theta)
    f = p.kind == FLUID
    x, z = p.x[f], p.z[f]
    return c * x - s * z, s * x + c * z, p.p[f], x, z


def run(rule: str, dx: float, t_end: float, snapshot: float) -> dict:
    sim = Simulation(config(rule, dx, t_end))
    motion = sim.setup.motions[0]
    sim.evaluate()
    rec = {k: [] for k in ("t", "theta", "contact", "pmin")}
    snap = None
    next_sample = 0.0
    t0 = time.perf_counter()
    while sim.t < t_end:
        if sim.t >= next_sample:
            theta = motion.angle(sim.t)[0]
            u, w, pres, x, z = flap_frame(sim.parts, theta)
            near = u < 1.5 * dx
            rec["t"].append(sim.t)
            rec["theta"].append(theta)
            rec["contact"].append(float(w[near].max()))
            rec["pmin"].append(float(pres[near].min()))
            if snap is None and sim.t >= snapshot:
                keep = x < 0.8
                snap = dict(x=x[keep], z=z[keep], p=pres[keep], t=sim.t, theta=theta)
            next_sample += 0.01
            sim.check()
        sim.advance()
    out = {k: np.array(v) for k, v in rec.items()}
    out.update({f"snap_{k}": np.asarray(v) for k, v in snap.items()})
    out["seconds"] = time.perf_counter() - t0
    out["steps"] = sim.step
    out["lost"] = sim.n_lost
    out["particles"] = sim.parts.n
    return out


def flap_pressure(z: np.ndarray, t: np.ndarray) -> np.ndarray:
    """Linear pressure on the flap (rows: times, columns: heights ``z`` from the bottom) in
    the periodic state of theta = THETA0 sin(OMEGA t): progressive and 60 evanescent
    modes, each coefficient the projection of the flap velocity on its mode."""
    h, nu = DEPTH, OMEGA * OMEGA / G
    zz = np.linspace(0.0, h, 4001)
    k0 = wavenumber(OMEGA, h, G)
    modes = [(np.cosh(k0 * zz), np.cosh(k0 * z), 1j * k0)]  # d/dx of e^{-i k0 x}: -i k0
    for n in range(1, 61):
        lo, hi = (n - 0.5) * math.pi / h + 1e-12, n * math.pi / h - 1e-12
        for _ in range(200):  # k tan(k h) = -nu on ((n - 1/2) pi / h, n pi / h)
            mid = 0.5 * (lo + hi)
            if mid * math.tan(mid * h) + nu > 0.0:
                hi = mid
            else:
                lo = mid
        kn = 0.5 * (lo + hi)
        modes.append((np.cos(kn * zz), np.cos(kn * z), kn))
    phi0 = np.zeros(len(z), dtype=complex)  # Phi(0, z)
    for fz, fzo, kx in modes:
        # -kx a f(z) summed = THETA0 OMEGA z: project on f (the modes are orthogonal)
        a = -THETA0 * OMEGA * np.trapezoid(zz * fz, zz) / (kx * np.trapezoid(fz * fz, zz))
        phi0 += a * fzo
    dyn = -RHO0 * np.real(1j * OMEGA * phi0[None, :] * np.exp(1j * OMEGA * t[:, None]))
    return RHO0 * G * (h - z)[None, :] + dyn


def tension_height(t: np.ndarray) -> np.ndarray:
    """Height on the flap above which the linear pressure is negative (the depth if none)."""
    z = np.linspace(0.0, DEPTH, 401)
    p = flap_pressure(z, t)
    out = np.full(len(t), DEPTH)
    for k in range(len(t)):
        neg = np.nonzero(p[k] < 0.0)[0]
        if len(neg):
            out[k] = z[neg[0]]
    return out


def figure(data: dict, dx: float, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig = plt.figure(figsize=(11, 7.5))
    ax = fig.add_subplot(2, 1, 1)
    period = 2 * math.pi / OMEGA
    colours = {"clamp": "C0", "free_surface": "C3", "none": "C2"}
    for rule in RULES:
        d = data[rule]
        ax.plot(d["t"] / period, d["contact"] / DEPTH, color=colours[rule],
                label=f"SPH, wall_tension: {rule}")
    t = data["clamp"]["t"]
    ax.plot(t / period, tension_height(t) / DEPTH, "k--", lw=1,
            label="linear theory: pressure on the flap < 0 above")
    ax.axhline(1.0, color="0.6", lw=0.6)
    ax2 = ax.twinx()
    ax2.plot(t / period, -THETA0 * OMEGA**2 * np.sin(OMEGA * t) * DEPTH / G, color="0.6",
             lw=0.8)
    ax2.set_ylabel("flap acceleration at z = H, towards the water (g)", color="0.5")
    ax.set_xlabel("t / T")
    ax.set_ylabel("contact height on the flap / H")
    ax.set_ylim(0.0, 1.35)
    ax.legend(loc="lower left", fontsize=8)
    ax.set_title(f"Flap pulled back at up to 1.5 g, H = {DEPTH:g} m, dx = {dx:g} m")
    ts = data["clamp"]["snap_t"]
    for k, rule in enumerate(RULES):
        d = data[rule]
        a = fig.add_subplot(2, 3, 4 + k)
        sc = a.scatter(d["snap_x"], d["snap_z"], c=d["snap_p"] / (RHO0 * G * DEPTH), s=2,
                       cmap="coolwarm", vmin=-0.5, vmax=1.0)
        th = float(d["snap_theta"])
        a.plot([0.0, 1.5 * math.sin(th)], [0.0, 1.5 * math.cos(th)], "k", lw=2)
        a.set_xlim(-0.25, 0.8)
        a.set_ylim(0.0, 1.4)
        a.set_aspect("equal")
        a.set_title(f"{rule}, t = {float(ts):.2f} s", fontsize=9)
        a.set_xlabel("x (m)")
        if k == 0:
            a.set_ylabel("z (m)")
    fig.colorbar(sc, ax=fig.axes[-3:], label="p / (rho g H)", shrink=0.8)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=110, bbox_inches="tight")


def summary(data: dict) -> dict:
    """Contact heights and pressures over the second period, when the flap pulls back."""
    period = 2 * math.pi / OMEGA
    out = {}
    for rule in RULES:
        d = data[rule]
        pull = (d["t"] > period) & (d["t"] < 2 * period)
        out[rule] = dict(contact_min=round(float(d["contact"][pull].min()), 3),
                         pmin_pa=round(float(d["pmin"][pull].min()), 1),
                         seconds=round(float(d["seconds"]), 1), steps=int(d["steps"]),
                         lost=int(d["lost"]))
    t = data["clamp"]["t"]
    pull = (t > period) & (t < 2 * period)
    out["theory_tension_height_min"] = round(float(tension_height(t[pull]).min()), 3)
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--dx", type=float, default=0.02)
    ap.add_argument("--t-end", type=float, default=1.4)
    ap.add_argument("--snapshot", type=float, default=1.05,
                    help="time of the particle snapshots (s)")
    ap.add_argument("--data", type=Path, default=Path("/tmp/wall_tension_flap.npz"))
    ap.add_argument("--plot-only", action="store_true", help="redraw from --data")
    ap.add_argument("--figure", type=Path,
                    default=ROOT / "docs" / "validation" / "wall_tension.png")
    args = ap.parse_args()
    if args.plot_only:
        raw = np.load(args.data)
        data = {r: {k.split("/", 1)[1]: raw[k] for k in raw.files if k.startswith(r + "/")}
                for r in RULES}
    else:
        data = {r: run(r, args.dx, args.t_end, args.snapshot) for r in RULES}
        np.savez(args.data, **{f"{r}/{k}": v for r in RULES for k, v in data[r].items()})
    figure(data, args.dx, args.figure)
    print(json.dumps(summary(data)))


if __name__ == "__main__":
    main()
