r"""Inflow and outflow regions: a numerical tank of uniform current.

After the second source paper (Sec. 2.3, its Fig. 2) and Sun, Colagrossi, Le Touzé & Zhang
(2019, J. Fluids Struct. 90, 19-42), who take the buffer regions of Marrone et al. (2013)
into the delta-SPH model. The tank is split along x into three regions:

.. code-block:: text

    inflow [x0, x_in) | fluid [x_in, x_out] | outflow (x_out, x_end]  (particles beyond: removed)

**Inflow region.** Its particles lie on the rows :math:`z_k` of the initial lattice below
the prescribed depth :math:`d` and move with the prescribed velocity
:math:`\mathbf{u} = (U(z_k), 0)` (a uniform :math:`U`, or a profile read from a file).
Their pressure is hydrostatic and their density follows from it by the Tait law,

.. math:: p_k = \rho_0 g (d - z_k),\qquad
          \rho_k = \rho_0\left(\frac{p_k}{B} + 1\right)^{1/\gamma},

and their density rate and acceleration are frozen,
:math:`D\rho/Dt = 0,\ D\mathbf{u}/Dt = 0`: they are not updated by the SPH equations but
give the fluid beside them a complete kernel support with the state of the incoming
stream. When the upstream-most particle of a row has moved one spacing :math:`\Delta x`
from the upstream end :math:`x_0`, a new particle of mass :math:`\rho_k \Delta x^2` is
placed one spacing upstream of it (the paper's "candidate set"); so every row stays a
row of spacing :math:`\Delta x` and the mass flux into the tank is
:math:`\sum_k \rho_k U(z_k) \Delta x` per unit width, the depth at the inflow held at
:math:`d`. A particle that passes :math:`x_{in}` is an ordinary fluid particle from then
on.

**Outflow region.** Its particles are advected with the stream velocity
:math:`(U(z), 0)` of the inflow, or with the velocity they had when they entered
(:math:`D\mathbf{u}/Dt = 0` either way); their density is frozen as well. A particle
beyond :math:`x_{end}` is removed. The first choice (the default) is the one condition
that a subcritical stream (:math:`U < \sqrt{g d}`) needs at its downstream end: the
outflow flux :math:`U d_{out}` then brings the depth at the outflow back to the inflow's
:math:`d`. With the second, nothing downstream fixes the depth of a subcritical stream:
measured in the empty channel of ``current_tank`` (d = 0.2 m, U = 0.8 m/s, dx = d/8), the
depth rose by 15 % over 30 flow-throughs; it suits a supercritical stream only. A
damping zone ahead of the outflow
(:mod:`sph.engine.absorber` with the stream velocity as its reference) takes the waves
out of the flow before they meet it, so that they leave without reflection.

Particles are created and removed when the neighbour lists are rebuilt (as the
splitting and merging of :mod:`sph.engine.refinement`): no particle of a row is then more
than the lists' half skin beyond one spacing from :math:`x_0`, so the inflow region must
be at least the kernel support plus one spacing long for the fluid to see a complete
support, and a run restarted from a checkpoint creates and removes particles exactly as
the uninterrupted one. Buffer particles are fluid particles (``kind`` FLUID) told apart by
their position only; a fluid particle that drifts back across :math:`x_{in}` or
:math:`x_{out}` is a buffer particle again.

The mass created and the mass removed are counted (:attr:`OpenBoundary.mass_in`,
:attr:`OpenBoundary.mass_out`): the fluid mass of the run changes by their difference.

The regions travel to numba as a float array ``ob`` (slots ``OB_*``) and the rows as
arrays of height, velocity and density.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numba import prange

from sph.engine.eos import hydrostatic_density
from sph.engine.jit import JIT_PARALLEL, njit
from sph.engine.particles import _FI, _II, FLOAT_FIELDS, FLUID, INT_FIELDS, Particles
from sph.schema import ConfigError, spec

# slots of the packed regions ``ob``
OB_X0 = 0  #: upstream end of the inflow region (m)
OB_X_IN = 1  #: the inflow region's downstream end: the fluid starts here (m)
OB_X_OUT = 2  #: the outflow region starts here (m)
OB_X_END = 3  #: particles beyond are removed (m)
OB_STREAM_OUT = 4  #: 1: outflow particles move with the stream; 0: with their own velocity
OB_DX = 5  #: particle spacing (m)
OB_SIZE = 6
#: the outflow region's velocity (:class:`CurrentConfig` ``outflow``)
OUTFLOW_MODES = ("stream", "own")


@dataclass(frozen=True)
class CurrentConfig:
    """The stream of a current tank: inflow velocity and the lengths of the two regions."""

    velocity: float = spec(lo=-1.0e3, hi=1.0e3, unit="m/s",
                           doc="stream velocity U at the inflow (along +x); must be > 0")
    profile: str | None = spec(None, doc="file of two columns, height above the bottom "
                               "(m) and velocity (m/s): a profile u(z) that replaces the "
                               "uniform velocity")
    inflow_length: float | None = spec(None, lo=0.0, lo_open=True, hi=1.0e4, unit="m",
                                       doc="length of the inflow region; null: the kernel "
                                       "support plus two spacings")
    outflow_length: float | None = spec(None, lo=0.0, lo_open=True, hi=1.0e4, unit="m",
                                        doc="length of the outflow region; null: the "
                                        "kernel support plus two spacings")
    outflow: str = spec("stream", choices=OUTFLOW_MODES,
                        doc="outflow particles move with the stream velocity of the inflow "
                        "(stream), or keep the velocity they enter with (own: for a "
                        "supercritical stream only, U > sqrt(g d))")

    def check(self, key):
        if self.profile is None and not self.velocity > 0.0:
            raise ConfigError(f"{key}.velocity", f"must be in (0, 1000] m/s (the stream "
                              f"flows along +x); got {self.velocity:g}")
        if self.profile is not None:
            load_profile(self.profile, f"{key}.profile")


def load_profile(path: str, key: str = "profile") -> np.ndarray:
    """Read a velocity profile (height above the bottom m, velocity m/s) and check it;
    returns an (n, 2) array with heights increasing."""
    p = Path(path)
    if not p.is_file():
        raise ConfigError(key, f"profile file {path!r} does not exist")
    try:
        data = np.loadtxt(p, dtype=np.float64, ndmin=2)
    except ValueError as exc:
        raise ConfigError(key, f"profile file {path!r} must hold two numeric columns "
                          f"(height m, velocity m/s): {exc}") from None
    if data.shape[1] < 2 or data.shape[0] < 2:
        raise ConfigError(key, f"profile file {path!r} must hold at least 2 rows of two "
                          "columns (height m, velocity m/s)")
    data = data[:, :2]
    if not np.all(np.isfinite(data)):
        raise ConfigError(key, f"profile file {path!r} contains non-finite values")
    if np.any(np.diff(data[:, 0]) <= 0.0):
        raise ConfigError(key, f"profile file {path!r}: heights must increase strictly")
    if np.any(data[:, 1] <= 0.0) or np.any(data[:, 1] > 1.0e3):
        raise ConfigError(key, f"profile file {path!r}: velocities must be in (0, 1000] "
                          "m/s (the stream flows along +x)")
    return data


def stream_velocity(cfg: CurrentConfig, z: np.ndarray) -> np.ndarray:
    """The inflow velocity at heights ``z`` above the bottom: the profile (interpolated,
    constant beyond its ends) or the uniform ``velocity``."""
    z = np.asarray(z, dtype=np.float64)
    if cfg.profile is None:
        return np.full(z.shape, float(cfg.velocity))
    data = load_profile(cfg.profile)
    return np.interp(z, data[:, 0], data[:, 1])


def region_lengths(cfg: CurrentConfig, support: float, dx: float) -> tuple[float, float]:
    """Lengths of the inflow and outflow regions (the defaults: support plus two spacings)."""
    default = support + 2.0 * dx
    return (cfg.inflow_length if cfg.inflow_length is not None else default,
            cfg.outflow_length if cfg.outflow_length is not None else default)


def check_region_lengths(cfg: CurrentConfig, support: float, dx: float,
                         key: str = "geometry.current") -> None:
    """Each region must cover the kernel support plus one spacing (plus the lists' skin,
    :mod:`sph.engine.neighbours`, in practice: the default adds two spacings)."""
    lo = support + dx
    for name in ("inflow_length", "outflow_length"):
        value = getattr(cfg, name)
        if value is not None and value < lo - 1e-9 * dx:
            raise ConfigError(f"{key}.{name}", f"must be at least the kernel support plus "
                              f"one spacing, {lo:g} m, so that the fluid beside it sees a "
                              f"complete support; got {value:g}")


class OpenBoundary:
    """The inflow and outflow regions of one run (see the module docstring).

    Parameters
    ----------
    x0, x_in, x_out, x_end : float
        Region ends (m), ``x0 < x_in < x_out < x_end``.
    rows_z, rows_u : arrays
        Heights (m, absolute) of the inflow rows and their prescribed velocities (m/s).
    depth : float
        Absolute height of the free surface at the inflow (m).
    dx : float
        Particle spacing (m).
    rho0, b_coef, gamma, gravity : float
        Fluid and Tait law (:mod:`sph.engine.eos`).
    outflow : str
        ``stream``: outflow particles move with the inflow's velocity at their height;
        ``own``: with the velocity they enter with.
    """

    def __init__(self, x0, x_in, x_out, x_end, rows_z, rows_u, depth, dx, rho0, b_coef,
                 gamma, gravity, outflow="stream"):
        if not x0 < x_in < x_out < x_end:
            raise ValueError(f"regions out of order: {x0}, {x_in}, {x_out}, {x_end}")
        self.ob = np.zeros(OB_SIZE)
        self.ob[OB_X0], self.ob[OB_X_IN] = x0, x_in
        self.ob[OB_X_OUT], self.ob[OB_X_END] = x_out, x_end
        self.ob[OB_STREAM_OUT] = 1.0 if outflow == "stream" else 0.0
        self.ob[OB_DX] = dx
        self.rows_z = np.ascontiguousarray(rows_z, dtype=np.float64)
        self.rows_u = np.ascontiguousarray(rows_u, dtype=np.float64)
        self.rows_rho = hydrostatic_density(depth - self.rows_z, rho0, b_coef, gamma, gravity)
        self.rows_p = rho0 * gravity * (depth - self.rows_z)
        self.dx = dx
        #: mass (kg per metre of width) created in the inflow and removed at the outflow
        self.mass_in = 0.0
        self.mass_out = 0.0
        self.n_in = 0
        self.n_out = 0
        self.next_pid = -1  # set from the particles at the first rebuild

    # ---------------------------------------------------------------- the stepper's hooks
    def apply(self, sim) -> None:
        """Before every evaluation: put the prescribed velocity and hydrostatic density on
        the inflow particles, freeze the outflow particles' velocity and density."""
        p = sim.parts
        prescribe(p.x, p.z, p.vx, p.vz, p.vx_old, p.vz_old, p.rho, p.rho_old, p.kind,
                  self.ob, self.rows_z, self.rows_u, self.rows_rho)

    def freeze(self, parts: Particles) -> None:
        """After the derivatives: zero the accelerations, density rates and shifts of the
        buffer particles."""
        p = parts
        freeze(p.x, p.ax, p.az, p.drho, p.sx, p.sz, p.kind, self.ob)

    def rebuild(self, parts: Particles) -> Particles:
        """At a rebuild of the neighbour lists: the set with the new inflow particles and
        without those beyond ``x_end`` (``parts`` itself when nothing changes)."""
        ob, dx = self.ob, self.dx
        fluid = parts.kind == FLUID
        if self.next_pid < 0:
            self.next_pid = int(parts.pid.max()) + 1
        gone = fluid & (parts.x > ob[OB_X_END])
        # the upstream-most particle of every row
        inflow = np.nonzero(fluid & (parts.x < ob[OB_X_IN]))[0]
        nrow = len(self.rows_z)
        row = np.rint((parts.z[inflow] - self.rows_z[0]) / dx).astype(np.int64)
        ok = (row >= 0) & (row < nrow)
        first = np.full(nrow, ob[OB_X_IN])
        np.minimum.at(first, row[ok], parts.x[inflow][ok])
        count = np.floor((first - ob[OB_X0]) / dx + 1e-9).astype(np.int64)
        count[first < ob[OB_X0] + dx] = 0
        n_new = int(count.sum())
        if n_new == 0 and not gone.any():
            return parts
        keep = ~gone
        self.mass_out += float(parts.m[gone].sum())
        self.n_out += int(gone.sum())
        f = np.zeros((len(FLOAT_FIELDS), n_new))
        i = np.zeros((len(INT_FIELDS), n_new), dtype=np.int32)
        if n_new:
            k = np.repeat(np.arange(nrow), count)
            # j = 1 .. count[k] spacings upstream of the row's first particle
            j = np.arange(n_new) - np.repeat(np.cumsum(count) - count, count) + 1
            x = first[k] - j * dx
            for name, value in (("x", x), ("z", self.rows_z[k]), ("vx", self.rows_u[k]),
                                ("vx_old", self.rows_u[k]), ("rho", self.rows_rho[k]),
                                ("rho_old", self.rows_rho[k]), ("p", self.rows_p[k]),
                                ("m", self.rows_rho[k] * dx * dx), ("x_sort", x),
                                ("z_sort", self.rows_z[k]), ("x_inner", x),
                                ("z_inner", self.rows_z[k]), ("hs", 1.0)):
                f[_FI[name]] = value
            i[_II["kind"]] = FLUID
            i[_II["body"]] = -1
            i[_II["pid"]] = self.next_pid + np.arange(n_new)
            self.next_pid += n_new
            self.mass_in += float(f[_FI["m"]].sum())
            self.n_in += n_new
        return Particles.of_columns(np.concatenate([parts.f[:, keep], f], axis=1),
                                    np.concatenate([parts.i[:, keep], i], axis=1))

    # ---------------------------------------------------------------- checkpoints
    def get_state(self) -> dict:
        return {"mass_in": np.array(self.mass_in), "mass_out": np.array(self.mass_out),
                "n_in": np.array(self.n_in), "n_out": np.array(self.n_out),
                "next_pid": np.array(self.next_pid)}

    def set_state(self, state: dict) -> None:
        self.mass_in = float(state["mass_in"])
        self.mass_out = float(state["mass_out"])
        self.n_in = int(state["n_in"])
        self.n_out = int(state["n_out"])
        self.next_pid = int(state["next_pid"])


@njit(**JIT_PARALLEL)
def prescribe(x, z, vx, vz, vx_old, vz_old, rho, rho_old, kind, ob, rows_z, rows_u,
              rows_rho):
    """Inflow particles: the row's velocity and hydrostatic density on both levels of the
    Verlet scheme; outflow particles: the stream's velocity at their height (or their own)
    and their density, on both levels (so that the leapfrog step moves them uniformly)."""
    stream_out = ob[OB_STREAM_OUT] != 0.0
    for i in prange(x.shape[0]):
        if kind[i] != FLUID:
            continue
        if x[i] < ob[OB_X_IN]:
            u = np.interp(z[i], rows_z, rows_u)
            r = np.interp(z[i], rows_z, rows_rho)
            vx[i] = u
            vx_old[i] = u
            vz[i] = 0.0
            vz_old[i] = 0.0
            rho[i] = r
            rho_old[i] = r
        elif x[i] > ob[OB_X_OUT]:
            if stream_out:
                vx[i] = np.interp(z[i], rows_z, rows_u)
                vz[i] = 0.0
            vx_old[i] = vx[i]
            vz_old[i] = vz[i]
            rho_old[i] = rho[i]


@njit(**JIT_PARALLEL)
def freeze(x, ax, az, drho, sx, sz, kind, ob):
    """Zero the time derivatives and shifts of the particles in the two regions."""
    for i in prange(x.shape[0]):
        if kind[i] == FLUID and (x[i] < ob[OB_X_IN] or x[i] > ob[OB_X_OUT]):
            ax[i] = 0.0
            az[i] = 0.0
            drho[i] = 0.0
            sx[i] = 0.0
            sz[i] = 0.0
