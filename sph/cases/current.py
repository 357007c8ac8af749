r"""Current tank: a channel of uniform stream between an inflow and an outflow region
(:mod:`sph.engine.openbc`; the second source paper, Sec. 2.3), empty (``current_tank``) or
with a fixed submerged circular cylinder (``cylinder_in_current``).

Layout along x: the inflow region ``[-l_in, 0)``, the fluid ``[0, tank_length]``, the
outflow region ``(tank_length, tank_length + l_out]``; a flat bottom of wall particles at
z = 0 under all three, the still free surface at z = depth, a damping zone towards the
stream (:mod:`sph.engine.absorber`) optional ahead of the outflow. The fluid starts with
the stream velocity (around the cylinder: the potential flow past a cylinder in an
unbounded stream, :func:`cylinder_potential_flow`).

**Cylinder in a current** (Havelock 1926; Lamb 1932, Sec. 247; Wehausen & Laitone 1960,
Sec. 21). A circular cylinder of radius :math:`a`, its centre at depth :math:`f` under the
free surface of deep water, in a stream :math:`U`, leaves far downstream the steady wave

.. math:: \eta(x) = -4\pi a^2 K e^{-Kf}\,\sin K(x - x_c),\qquad K = g / U^2,

(its wave length is that of a free wave travelling upstream at :math:`U`); linear theory,
so the steepness :math:`KA = 4\pi (a/f)^2 (Kf)^2 e^{-Kf}` must stay small (below 0.16 for
:math:`a/f \le 0.15`). :func:`havelock_wave` gives :math:`K` and :math:`A`; the Froude
number is :math:`F = U / \sqrt{g f}`, :math:`Kf = 1/F^2`. The case adds wave gauges
``G000, G001, ...`` every ``gauge_spacing`` from the cylinder to the end of the fluid
(their positions in the output attributes ``gauge_x0`` and ``gauge_spacing``).
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field

import numpy as np

from sph.cases.base import (
    CaseSetup,
    check_absorber_fits,
    load_defaults,
    make_particles,
    require_resolved,
    scales,
    wall_layers,
)
from sph.cases.geometry import lattice
from sph.engine.absorber import AbsorberConfig, absorber_params
from sph.engine.config import CaseConfig
from sph.engine.openbc import (
    CurrentConfig,
    OpenBoundary,
    check_region_lengths,
    region_lengths,
    stream_velocity,
)
from sph.engine.particles import FLUID
from sph.engine.probes import surface_heights
from sph.schema import ConfigError, spec


def havelock_wave(radius: float, submergence: float, velocity: float,
                  gravity: float = 9.81) -> dict:
    """The steady wave far behind a submerged cylinder in deep water (linear theory,
    Havelock 1926; Lamb Sec. 247): wavenumber ``K = g / U^2``, wave length, amplitude
    ``4 pi a^2 K exp(-K f)``, steepness ``K A`` and the Froude number ``U / sqrt(g f)``."""
    k = gravity / velocity**2
    amp = 4.0 * math.pi * radius**2 * k * math.exp(-k * submergence)
    return dict(wavenumber=k, wavelength=2.0 * math.pi / k, amplitude=amp,
                steepness=k * amp, froude=velocity / math.sqrt(gravity * submergence))


def havelock_surface(x, radius: float, submergence: float, velocity: float,
                     gravity: float = 9.81) -> np.ndarray:
    r"""The whole linear free surface over a submerged cylinder in a stream, near field
    included (Havelock 1926; Wehausen & Laitone 1960, Sec. 21), at ``x`` measured from the
    cylinder's centre (m, the stream towards +x):

    .. math:: \eta(x) = -2a^2\left[\mathrm{PV}\!\int_0^\infty
              \frac{k\,e^{-kf}\cos kx}{K - k}\,dk + \pi K e^{-Kf}\sin Kx\right],

    the doublet :math:`U a^2` under a free surface (:math:`U^2\phi_{xx} + g\phi_z = 0`,
    :math:`\eta = -U\phi_x / g`) with the free wave that leaves no wave upstream; far
    downstream it tends to :func:`havelock_wave`'s :math:`-A\sin Kx`, far upstream to
    nothing. Deep water. Shows what a fit over a window behind the cylinder reads of
    linear theory itself (:func:`sph.study.current.havelock_comparison`)."""
    from scipy.integrate import quad

    k_wave = gravity / velocity**2
    f, a2 = submergence, radius * radius
    cut = 60.0 / f  # exp(-60): the integrand's tail beyond is below round-off
    out = []
    for xi in np.atleast_1d(np.asarray(x, dtype=float)):
        def g(k, xi=xi):
            return math.exp(-k * f) * k * math.cos(k * xi)
        pv = -quad(g, 0.0, cut, weight="cauchy", wvar=k_wave, limit=400)[0]
        out.append(-2.0 * a2 * (pv + math.pi * k_wave * math.exp(-k_wave * f)
                                * math.sin(k_wave * xi)))
    return np.array(out)


def tank_for_froude(froude: float, dx: float, gravity: float = 9.81) -> dict:
    """Case-file values (dotted keys) of a ``cylinder_in_current`` tank sized for the wave
    of Froude number ``froude`` with the built-in cylinder (``sph example
    cylinder_in_current``): depth ``f + 2.3 / K`` (the bottom's image adds at most 1 % to
    the wave), the damping zone from 2 wave lengths behind the cylinder over 0.75 of one
    (the gauges' window of :func:`sph.study.current.havelock_comparison` runs from half a
    wave length to its start), gauges every 1/16."""
    geo = load_defaults("cylinder_in_current")["geometry"]
    f, xc = float(geo["cylinder"]["submergence"]), float(geo["cylinder"]["x"])
    k = 1.0 / (f * froude**2)
    lam = 2.0 * math.pi / k
    depth = math.ceil((f + 2.3 / k) / dx - 1e-9) * dx
    length, start = round(xc + 2.75 * lam, 3), round(xc + 2.0 * lam, 3)
    return {"geometry.depth": round(depth, 9), "geometry.tank_height": round(1.5 * depth, 9),
            "geometry.tank_length": length, "geometry.absorber.start": start,
            "geometry.absorber.length": round(length - start, 3),
            "geometry.gauge_spacing": round(lam / 16.0, 4)}


def cylinder_potential_flow(x, z, xc, zc, radius, velocity):
    """Velocity of the potential flow of a stream ``velocity`` past a circular cylinder in
    an unbounded fluid, :math:`\\phi = U x (1 + a^2 / r^2)`."""
    rx, rz = x - xc, z - zc
    r2 = np.maximum(rx * rx + rz * rz, radius * radius)
    a2 = radius * radius
    u = velocity * (1.0 - a2 * (rx * rx - rz * rz) / (r2 * r2))
    w = -velocity * a2 * 2.0 * rx * rz / (r2 * r2)
    return u, w


@dataclass(frozen=True)
class Cylinder:
    """A fixed circular cylinder under the free surface."""

    radius: float = spec(lo=0.0, lo_open=True, hi=1.0e3, unit="m", doc="radius a")
    x: float = spec(lo=0.0, hi=1.0e5, unit="m", doc="x of the centre")
    submergence: float = spec(lo=0.0, lo_open=True, hi=1.0e4, unit="m",
                              doc="depth f of the centre under the still free surface")


def _check_channel(cfg: CaseConfig) -> tuple[float, float]:
    """Checks shared by both cases; returns the region lengths."""
    g, dx = cfg.geometry, cfg.numerics.dx
    sc = scales(cfg)
    require_resolved("geometry.depth", g.depth, dx)
    require_resolved("geometry.tank_length", g.tank_length, dx)
    if g.depth >= g.tank_height:
        raise ConfigError("geometry.depth", f"must be in (0, geometry.tank_height = "
                          f"{g.tank_height:g}) m; got {g.depth:g}")
    check_region_lengths(g.current, sc.support, dx)
    check_absorber_fits(g.absorber, g.tank_length)
    l_in, l_out = region_lengths(g.current, sc.support, dx)
    for k, pr in enumerate(cfg.probes.surface):
        if not 0.0 <= pr.x <= g.tank_length:
            raise ConfigError(f"probes.surface[{k}].x", f"must be in the fluid between the "
                              f"inflow and the outflow, [0, {g.tank_length:g}] m; got "
                              f"{pr.x:g}")
    if cfg.probes.pressure:
        raise ConfigError("probes.pressure", "a current tank has no pressure probes "
                          "(its walls are the bottom and the body); got "
                          f"{len(cfg.probes.pressure)}")
    if cfg.numerics.refinement:
        raise ConfigError("numerics.refinement", "a current tank runs at uniform "
                          "resolution (the inflow rows are of spacing numerics.dx); got "
                          f"{len(cfg.numerics.refinement)} box(es)")
    return l_in, l_out


def _channel(cfg: CaseConfig, body=None):
    """Lattice points of the channel: fluid and bottom walls, less the fluid inside
    ``body`` (its ``outside(x, z)`` marks the fluid it leaves, ``walls()`` gives its wall
    particles); returns fluid, walls, bounds, region lengths."""
    g, dx = cfg.geometry, cfg.numerics.dx
    t = wall_layers(cfg) * dx
    l_in, l_out = region_lengths(g.current, scales(cfg).support, dx)
    # the lattice starts at x = 0 so that the inflow rows continue the fluid's columns
    n_in = int(math.ceil(l_in / dx - 1e-9))
    n_out = int(math.ceil((g.tank_length + l_out) / dx - 1e-9))
    x0 = -n_in * dx
    pts = lattice(x0 - t, n_out * dx + t, -t, g.depth, dx)
    x, z = pts[:, 0], pts[:, 1]
    fluid = (z > 0.0) & (x > x0) & (x < n_out * dx)
    walls = pts[(z < 0.0) & (z > -t)]
    if body is not None:
        fluid &= body.outside(x, z)
        walls = np.concatenate([walls, body.walls()])
    bounds = (x0 - t - 2.0 * dx, n_out * dx + t + 4.0 * dx, -t, g.tank_height + g.depth)
    return pts[fluid], walls, bounds, (n_in * dx, g.tank_length + l_out)


@dataclass(frozen=True)
class RingCylinder:
    """A circular cylinder of wall particles on concentric rings (spacing ``dx`` along and
    across them), so that its surface is a circle and not the lattice's staircase; the
    fluid lattice points at ``r >= radius`` stay fluid."""

    xc: float
    zc: float
    radius: float
    dx: float
    layers: int

    def outside(self, x, z):
        return np.hypot(x - self.xc, z - self.zc) >= self.radius

    def walls(self) -> np.ndarray:
        out = []
        for k in range(self.layers):
            r = self.radius - (k + 0.5) * self.dx
            if r < 0.25 * self.dx:
                out.append([[self.xc, self.zc]])
                break
            n = max(1, round(2.0 * math.pi * r / self.dx))
            th = (np.arange(n) + 0.5) * 2.0 * math.pi / n
            out.append(np.column_stack([self.xc + r * np.cos(th), self.zc + r * np.sin(th)]))
        return np.concatenate(out)


def _open_boundary(cfg: CaseConfig, parts, x0: float, x_end: float) -> OpenBoundary:
    g, dx, fl = cfg.geometry, cfg.numerics.dx, cfg.fluid
    sc = scales(cfg, g.depth)
    inflow = (parts.kind == FLUID) & (parts.x < 0.0)
    rows_z = np.unique(parts.z[inflow])
    u = stream_velocity(g.current, rows_z)
    return OpenBoundary(x0, 0.0, g.tank_length, x_end, rows_z, u, g.depth, dx, fl.rho0, sc.b,
                        fl.gamma, fl.gravity, g.current.outflow)


def _mass_diagnostics(ob: OpenBoundary) -> dict:
    def fluid_mass(p, t):
        return float(np.sum(p.m[p.kind == FLUID]))

    return {"fluid_mass": fluid_mass, "mass_in": lambda p, t: ob.mass_in,
            "mass_out": lambda p, t: ob.mass_out}


def _attrs(cfg: CaseConfig, l_in: float, x_end: float) -> dict:
    g = cfg.geometry
    return dict(depth=g.depth, tank_length=g.tank_length, stream_velocity=g.current.velocity,
                stream_profile=g.current.profile or "", inflow_start=-l_in,
                outflow_end=x_end, absorber=int(g.absorber.enabled),
                absorber_start=g.absorber.start, absorber_length=g.absorber.length,
                absorber_form=g.absorber.form, absorber_strength=g.absorber.strength)


class CurrentTank:
    """An empty channel of uniform stream, case ``current_tank``."""

    @dataclass(frozen=True)
    class Geometry:
        depth: float = spec(lo=0.0, lo_open=True, hi=1.0e4, unit="m",
                            doc="water depth d, held at the inflow")
        tank_length: float = spec(lo=0.0, lo_open=True, hi=1.0e5, unit="m",
                                  doc="length of the fluid between the inflow and the "
                                  "outflow region")
        tank_height: float = spec(lo=0.0, lo_open=True, hi=1.0e4, unit="m",
                                  doc="height of the domain above the bottom")
        current: CurrentConfig = field(metadata=dict(doc="stream and buffer regions"))
        absorber: AbsorberConfig = field(metadata=dict(doc="damping zone towards the stream"))

    @staticmethod
    def defaults() -> dict:
        return load_defaults("current_tank")

    @staticmethod
    def check(cfg: CaseConfig) -> None:
        _check_channel(cfg)

    @staticmethod
    def setup(cfg: CaseConfig) -> CaseSetup:
        fluid, walls, bounds, (l_in, x_end) = _channel(cfg)
        return _finish(cfg, fluid, walls, bounds, l_in, x_end, None, {})


def _finish(cfg, fluid, walls, bounds, l_in, x_end, velocity, extra_attrs, extra_probes=None):
    g = cfg.geometry
    parts = make_particles(cfg, fluid, walls, g.depth, g.depth)
    nf = len(fluid)
    if velocity is None:
        parts.vx[:nf] = stream_velocity(g.current, parts.z[:nf])
    else:
        parts.vx[:nf], parts.vz[:nf] = velocity
    parts.vx_old[:nf] = parts.vx[:nf]
    parts.vz_old[:nf] = parts.vz[:nf]
    ob = _open_boundary(cfg, parts, -l_in, x_end)
    u = float(np.max(ob.rows_u))
    attrs = _attrs(cfg, l_in, x_end)
    attrs.update(extra_attrs)
    speed = math.sqrt(cfg.fluid.gravity * g.depth)
    return CaseSetup(parts, bounds, g.depth, diagnostics=_mass_diagnostics(ob), attrs=attrs,
                     absorber=absorber_params(g.absorber, speed, cfg.numerics.dx, stream=u),
                     still_level=g.depth, events=[ob], open_boundary=ob,
                     extra_probes=extra_probes or {})


class CylinderInCurrent:
    """A fixed submerged circular cylinder in a stream, case ``cylinder_in_current``."""

    @dataclass(frozen=True)
    class Geometry:
        depth: float = spec(lo=0.0, lo_open=True, hi=1.0e4, unit="m",
                            doc="water depth d, held at the inflow")
        tank_length: float = spec(lo=0.0, lo_open=True, hi=1.0e5, unit="m",
                                  doc="length of the fluid between the inflow and the "
                                  "outflow region")
        tank_height: float = spec(lo=0.0, lo_open=True, hi=1.0e4, unit="m",
                                  doc="height of the domain above the bottom")
        cylinder: Cylinder = field(metadata=dict(doc="the fixed cylinder"))
        gauge_spacing: float = spec(lo=0.0, lo_open=True, hi=1.0e4, unit="m",
                                    doc="spacing of the wave gauges G000, G001, ... from the "
                                    "cylinder's centre to the end of the fluid")
        current: CurrentConfig = field(metadata=dict(doc="stream and buffer regions"))
        absorber: AbsorberConfig = field(metadata=dict(doc="damping zone towards the stream"))
        froude: float | None = spec(None, lo=0.0, lo_open=True, hi=10.0,
                                    doc="F = U / sqrt(g f); when set, the stream velocity is "
                                    "F sqrt(g f) and current.velocity is not used")

    @staticmethod
    def defaults() -> dict:
        return load_defaults("cylinder_in_current")

    @staticmethod
    def velocity(cfg: CaseConfig) -> float:
        """The stream velocity U (m/s): from ``froude`` when set."""
        g = cfg.geometry
        if g.froude is None:
            return g.current.velocity
        return g.froude * math.sqrt(cfg.fluid.gravity * g.cylinder.submergence)

    @staticmethod
    def check(cfg: CaseConfig) -> None:
        g, dx = cfg.geometry, cfg.numerics.dx
        if g.froude is not None and g.current.profile is not None:
            raise ConfigError("geometry.froude", "must be null with a velocity profile "
                              "(geometry.current.profile), which gives the stream")
        _check_channel(cfg)
        c = g.cylinder
        t = wall_layers(cfg) * dx
        support = scales(cfg).support
        require_resolved("geometry.cylinder.radius", c.radius, dx, cells=2)
        top = c.submergence - c.radius
        if top < dx:
            raise ConfigError("geometry.cylinder.submergence", f"must be at least radius + "
                              f"dx = {c.radius + dx:g} m (the cylinder under the free "
                              f"surface); got {c.submergence:g}")
        if g.depth - c.submergence - c.radius < support:
            raise ConfigError("geometry.cylinder.submergence", f"must be at most depth - "
                              f"radius - kernel support = "
                              f"{g.depth - c.radius - support:g} m (the cylinder clear of "
                              f"the bottom); got {c.submergence:g}")
        lo, hi = c.radius + t + support, g.tank_length - c.radius - t - support
        if not lo <= c.x <= hi:
            raise ConfigError("geometry.cylinder.x", f"must be in [{lo:g}, {hi:g}] m, so "
                              "that the cylinder and its wall layers stay a kernel support "
                              "clear of the inflow and the outflow region; got "
                              f"{c.x:g}")
        ab = g.absorber
        if ab.enabled and ab.start < c.x + c.radius + t:
            raise ConfigError("geometry.absorber.start", f"must be at least "
                              f"{c.x + c.radius + t:g} m, downstream of the cylinder "
                              f"(and its wall layers); got {ab.start:g}")

    @staticmethod
    def setup(cfg: CaseConfig) -> CaseSetup:
        g, dx = cfg.geometry, cfg.numerics.dx
        c = g.cylinder
        zc = g.depth - c.submergence
        u = CylinderInCurrent.velocity(cfg)
        if g.froude is not None:
            cfg = dataclasses.replace(cfg, geometry=dataclasses.replace(
                g, current=dataclasses.replace(g.current, velocity=u)))
            g = cfg.geometry

        body = RingCylinder(c.x, zc, c.radius, dx, wall_layers(cfg))
        fluid, walls, bounds, (l_in, x_end) = _channel(cfg, body)
        vel = cylinder_potential_flow(fluid[:, 0], fluid[:, 1], c.x, zc, c.radius, u)
        th = havelock_wave(c.radius, c.submergence, u, cfg.fluid.gravity)
        xg = c.x + g.gauge_spacing * np.arange(int((g.tank_length - c.x) / g.gauge_spacing)
                                                + 1)
        kp = scales(cfg).kp
        extra = {f"G{k:03d}": (_gauge(xk, kp, dx), g.depth) for k, xk in enumerate(xg)}
        attrs = dict(cylinder_radius=c.radius, cylinder_x=c.x, cylinder_submergence=
                     c.submergence, froude=th["froude"], stream_velocity=u,
                     theory_wavenumber=th["wavenumber"], theory_wavelength=th["wavelength"],
                     theory_amplitude=th["amplitude"], gauge_x0=float(xg[0]),
                     gauge_spacing=g.gauge_spacing)
        setup = _finish(cfg, fluid, walls, bounds, l_in, x_end, vel, attrs, extra)
        return setup


def _gauge(xp: float, kp: np.ndarray, dx: float):
    """A kernel-sum wave gauge at ``xp`` (:func:`sph.engine.probes.surface_heights`)."""
    at = np.array([xp])

    def height(p):
        return float(surface_heights(p.x, p.z, p.m, p.rho, p.kind, p.comp, -1, at, kp, 0.0,
                                     0.1 * dx)[0])

    return height
