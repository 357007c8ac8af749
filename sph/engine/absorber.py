r"""Absorbing (damping) zone at the far end of the tank (Cao et al. 2019, Eq. 16).

A sink term :math:`\mathbf{D}_i = -\sigma(x_i)(\mathbf{v}_i - \mathbf{v}_0)`, with
:math:`\mathbf{v}_0 = 0`, is added to the momentum equation, with the hyperbolic profile of
Modave et al. (2010):

.. math:: \sigma(x) = \frac{c}{l}\,\frac{x - x_0}{x_0 + l - x + dx},\qquad x_0 < x,

where :math:`x_0` is the start of the zone, :math:`l` its length and :math:`c` a speed (the
paper's :math:`c_0`; by default the linear phase speed of the generated wave, the choice of
Modave et al.). The term is applied implicitly in the velocity update,
:math:`\mathbf{v}^{n+1} = \tilde{\mathbf{v}}^{n+1} / (1 + \Delta t_{eff}\,\sigma)`, which stays
stable however large :math:`\sigma\Delta t` becomes near the end wall.

Two forms are offered (``form``):

``two_sided`` (default)
    the damping acts on every particle in the zone;
``one_sided``
    Eq. 16 as printed: only particles with :math:`v_x < 0` (flowing back towards the
    wavemaker) are damped.

The two-sided form is the default: by construction the one-sided form leaves the forward half
of each orbital cycle undamped, so a wave reaches the end wall less attenuated. Measured in
the paper's tank at dx = 1 A over 40-60 s with a probe array, the one-sided form reflects
2.5 % against the two-sided 1.9 % at ``strength`` 1, and 1.6 % against 0.8 % at 2.

``strength`` multiplies :math:`c`. The reflection of the paper's tank (a one-wavelength zone,
kh = 3.1) measured at dx = 1 A over 40-60 s with a probe array
(:func:`sph.study.validation.wave_separation`), against c in units of the phase speed:
0.25 -> 11.6 %, 0.5 -> 4.0 %, 1 -> 1.9 %, 2 -> 0.8 %, 4 -> 1.0 %. A weak zone lets the wave
reach the end wall and come back; a strong one starts to reflect on its own gradient. The
built-in ``wave_tank`` case uses ``strength: 2``; the library default stays 1 (Modave et
al.'s choice, which the ship and floating-box cases were validated with).

In a current tank (:mod:`sph.engine.openbc`) the zone damps towards the stream,
:math:`\mathbf{v}_0 = (U, 0)`: it takes the waves out of the flow and leaves the stream;
the one-sided form then damps the particles with :math:`v_x < U`.

``mirrored`` adds the zone's mirror image about the middle of the tank: a zone at each end,
for a body released in the middle of a still tank (a free decay), whose radiated waves would
otherwise come back from the end walls and beat with its motion. Only a case that knows its
tank's middle and has no wavemaker running offers it (:mod:`sph.cases.ship`).

The zone travels to numba as a float array ``[mode, x0, l, c, dx, pitch, U, x_m]`` (mode 0 =
no zone, 1 = one-sided, 2 = two-sided; x_m > 0: the zone is mirrored about x = x_m).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from sph.engine.jit import JIT, njit
from sph.schema import ConfigError, spec

FORMS = {"one_sided": 1, "two_sided": 2}

# slots of the packed zone ``ab`` (:func:`absorber_params`; all zeros: no zone)
AB_FORM = 0  #: 0 none, 1 one-sided, 2 two-sided
AB_START = 1  #: x where the zone starts (m)
AB_LENGTH = 2  #: zone length (m)
AB_SPEED = 3  #: c of the profile times the strength (m/s)
AB_DX = 4  #: particle spacing (m)
AB_PITCH = 5  #: the zone repeats every pitch metres along x (0: once)
AB_STREAM = 6  #: reference velocity along x the zone damps towards (m/s; 0: still water)
AB_MIRROR = 7  #: x about which the zone is mirrored (m; 0: no mirror image)
AB_SIZE = 8


@dataclass(frozen=True)
class AbsorberConfig:
    """Damping zone ``[start, start + length]`` (each case gives where it lies)."""

    enabled: bool = spec(True, doc="switch the zone on or off")
    start: float | None = spec(None, lo=0.0, hi=1.0e6, unit="m",
                               doc="x where the zone starts (required when enabled)")
    length: float | None = spec(None, lo=0.0, lo_open=True, hi=1.0e6, unit="m",
                                doc="zone length (required when enabled)")
    speed: float | None = spec(None, lo=0.0, lo_open=True, hi=1.0e4, unit="m/s",
                               doc="c of the profile; default: linear phase speed of the wave")
    form: str = spec("two_sided", choices=tuple(FORMS), doc="damp all particles, or only "
                     "those with vx < 0")
    strength: float = spec(1.0, lo=0.0, lo_open=True, hi=100.0,
                           doc="multiplies c (speed, or the default phase speed)")
    mirrored: bool = spec(False, doc="also damp the zone's mirror image about the tank's "
                          "middle (a zone at each end: free decay in a still tank; ship "
                          "cases without a wave only)")

    def check(self, key):
        if self.enabled:
            for name, unit in (("start", "[0, 1e+06] m"), ("length", "(0, 1e+06] m")):
                if getattr(self, name) is None:
                    raise ConfigError(f"{key}.{name}", f"required when {key}.enabled is true "
                                      f"(expected a number in {unit})")


def absorber_params(cfg: AbsorberConfig | None, speed: float, dx: float,
                    pitch: float = 0.0, stream: float = 0.0,
                    middle: float | None = None) -> np.ndarray:
    """Pack the zone for the numba update (``speed`` used when ``cfg.speed`` is None).

    ``pitch`` > 0 repeats the zone every ``pitch`` metres along x: the tanks of the strip
    segments of a ship lie side by side at that spacing (:mod:`sph.cases.ship`).
    ``stream``: the velocity along x the zone damps towards (a current tank's U).
    ``middle``: the x of the tank's middle, about which a ``mirrored`` zone is mirrored (the
    case checks that the zone starts beyond it); a case that passes none does not offer
    ``mirrored``."""
    if cfg is None or not cfg.enabled:
        return np.zeros(AB_SIZE)
    if cfg.mirrored and middle is None:
        raise ConfigError("geometry.absorber.mirrored", "must be false in this case (a zone "
                          "at each end is offered for a ship in a still tank only)")
    c = (cfg.speed if cfg.speed is not None else speed) * cfg.strength
    ab = np.zeros(AB_SIZE)
    ab[AB_FORM] = FORMS[cfg.form]
    ab[AB_START] = cfg.start
    ab[AB_LENGTH] = cfg.length
    ab[AB_SPEED] = c
    ab[AB_DX] = dx
    ab[AB_PITCH] = pitch
    ab[AB_STREAM] = stream
    ab[AB_MIRROR] = middle if cfg.mirrored else 0.0
    return ab


def absorber_active(ab: np.ndarray) -> bool:
    return ab[AB_FORM] != 0.0


def absorber_speed(ab: np.ndarray) -> float:
    """The zone's effective c (speed times strength), m/s."""
    return float(ab[AB_SPEED])


@njit(inline="always", **JIT)
def sigma(x, vx, ab):
    """Damping rate (1/s) at ``x`` for a particle moving with ``vx`` relative to the
    stream (:data:`AB_STREAM`); 0 outside the zone."""
    if ab[AB_FORM] != 0.0 and ab[AB_PITCH] > 0.0:
        x -= ab[AB_PITCH] * np.floor(x / ab[AB_PITCH])
    if ab[AB_MIRROR] > 0.0 and x < ab[AB_MIRROR]:
        x, vx = 2.0 * ab[AB_MIRROR] - x, -vx  # position and velocity mirrored
    if ab[AB_FORM] == 0.0 or x <= ab[AB_START]:
        return 0.0
    if ab[AB_FORM] == 1.0 and vx >= 0.0:
        return 0.0
    return ab[AB_SPEED] / ab[AB_LENGTH] * (x - ab[AB_START]) / max(
        ab[AB_START] + ab[AB_LENGTH] - x + ab[AB_DX], ab[AB_DX])


def damping_depth(rate: float, speed: float, length: float, dx: float) -> float:
    """How far into a two-sided zone (its effective speed ``speed``, ``length`` and ``dx``,
    as packed by :func:`absorber_params`) :func:`sigma` reaches ``rate`` (1/s): the
    inverse of the profile, (c / l) d / (l - d + dx) = rate."""
    r = rate * length
    return r * (length + dx) / (speed + r)
