r"""Earth-fixed probes: free-surface elevation and wall pressure.

Free-surface elevation at :math:`x_p` (second source paper, Eq. 7, kernel-sum wave gauge):
the fluid fraction :math:`\phi(\mathbf{r}) = \sum_f V_f W(\mathbf{r} - \mathbf{r}_f)` is 1
inside the fluid and falls through 1/2 at the free surface. The probe scans down from above
the highest fluid particle near :math:`x_p` in steps of ``dz`` and returns the height where
:math:`\phi` first reaches 1/2 (linear interpolation between samples); NaN where dry.

Wall pressure at a point on a wall: the fluid pressure extrapolated to the point exactly as
for the dummy particles (Cao et al. 2019, Eq. 11), so a probe reads what the wall feels.
"""

from __future__ import annotations

import numpy as np

from sph.engine.jit import JIT, njit
from sph.engine.kernels import KP_R2MAX, w_r2
from sph.engine.particles import FLUID


@njit(**JIT)
def surface_heights(x, z, m, rho, kind, comp, cfilter, xp, kp, zfloor, dz, wall_fill=False):
    r"""Free-surface height (absolute z, m) at each probe abscissa ``xp``.

    Only fluid of compartment ``cfilter`` counts (all fluid if ``cfilter < 0``). With
    ``wall_fill`` the wall particles passed in (of compartment ``cfilter``) complete the
    kernel next to a wall: :math:`\phi = \sum_f V_f W / (1 - \sum_w V_w W)`, so that a
    probe closer to a wall than the kernel support still reads the level (a point on the
    free surface against a vertical wall has a quarter of its kernel in fluid and half in
    the wall: phi = 1/2 again); points inside the wall layers are skipped."""
    radius = np.sqrt(kp[KP_R2MAX])
    out = np.full(xp.shape[0], np.nan)
    n = x.shape[0]
    cand = np.empty(n, dtype=np.int64)
    wcand = np.empty(n, dtype=np.int64)
    for k in range(xp.shape[0]):
        nc = 0
        ztop = -1.0e300
        for j in range(n):
            if (kind[j] == FLUID and (cfilter < 0 or comp[j] == cfilter)
                    and abs(x[j] - xp[k]) < radius):
                cand[nc] = j
                nc += 1
                if z[j] > ztop:
                    ztop = z[j]
        if nc == 0:
            continue
        zs = ztop + radius
        phi_prev = 0.0
        nw = 0
        if wall_fill:
            for j in range(n):
                if (kind[j] != FLUID and (cfilter < 0 or comp[j] == cfilter)
                        and abs(x[j] - xp[k]) < radius):
                    wcand[nw] = j
                    nw += 1
        while zs > zfloor:
            phi = 0.0
            for c in range(nc):
                j = cand[c]
                dx = xp[k] - x[j]
                dzz = zs - z[j]
                phi += w_r2(dx * dx + dzz * dzz, kp) * m[j] / rho[j]
            if nw > 0:
                sw = 0.0
                for c in range(nw):
                    j = wcand[c]
                    dx = xp[k] - x[j]
                    dzz = zs - z[j]
                    sw += w_r2(dx * dx + dzz * dzz, kp) * m[j] / rho[j]
                if sw > 0.8:  # inside the wall layers
                    phi_prev = 0.0
                    zs -= dz
                    continue
                phi /= 1.0 - sw
            if phi >= 0.5:
                out[k] = zs + dz * (phi - 0.5) / (phi - phi_prev)
                break
            phi_prev = phi
            zs -= dz
    return out


@njit(**JIT)
def point_pressures(x, z, m, rho, p, kind, xp, zp, kp, gx, gz):
    """Pressure (Pa) extrapolated from the fluid to each point ``(xp, zp)``; NaN if dry."""
    out = np.full(xp.shape[0], np.nan)
    for k in range(xp.shape[0]):
        sw = 0.0
        sp = 0.0
        for j in range(x.shape[0]):
            if kind[j] != FLUID:
                continue
            dx = xp[k] - x[j]
            dz = zp[k] - z[j]
            w = w_r2(dx * dx + dz * dz, kp)
            if w > 0.0:
                w *= m[j] / rho[j]
                sw += w
                sp += w * (p[j] + rho[j] * (gx * dx + gz * dz))
        if sw > 1.0e-6:
            out[k] = sp / sw
    return out
