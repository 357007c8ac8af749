"""The scales of a run, derived once from its configuration: particle spacing ``dx``,
smoothing length ``h``, the packed kernel parameters, the kernel's support radius, the
speed of sound ``c0`` and the Tait coefficient ``B``.

``h = h_factor dx`` (:data:`sph.engine.kernels.DEFAULT_H_FACTOR` when not set);
``c0 = c_factor sqrt(g H)`` with ``H`` the case's reference depth; ``B = c0^2 rho0 / gamma``
(Tait equation of state, :mod:`sph.engine.eos`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from sph.engine.config import Fluid, Numerics
from sph.engine.kernels import kernel_params, support_radius


@dataclass(frozen=True)
class Scales:
    dx: float
    h: float
    #: packed kernel parameters for the numba kernels (:func:`sph.engine.kernels.kernel_params`)
    kp: np.ndarray
    #: radius beyond which the kernel vanishes (m)
    support: float
    c0: float
    b: float

    @classmethod
    def of(cls, numerics: Numerics, fluid: Fluid, depth: float | None = None) -> Scales:
        """The scales of ``numerics`` and ``fluid``; ``c0`` and ``b`` need the reference
        depth (NaN without it)."""
        h = numerics.h
        kp = kernel_params(numerics.kernel, h)
        c0 = (numerics.c_factor * math.sqrt(fluid.gravity * depth) if depth is not None
              else math.nan)
        return cls(dx=numerics.dx, h=h, kp=kp, support=support_radius(kp), c0=c0,
                   b=c0 * c0 * fluid.rho0 / fluid.gamma)
