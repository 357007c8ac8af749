r"""Fluid equations: continuity, momentum with gravity and artificial viscosity.

Discrete forms of Cao et al. (2019):

.. math::
    \frac{D\rho_i}{Dt} = \rho_i \sum_j \frac{m_j}{\rho_j}
    (\mathbf{v}_i - \mathbf{v}_j)\cdot\nabla_i W_{ij}
    \quad\text{(Eq. 2)}

.. math::
    \frac{D\mathbf{v}_i}{Dt} = -\sum_j m_j \frac{P_i + P_j}{\rho_i\rho_j}\nabla_i W_{ij}
    + \mathbf{g} + \mathbf{F}_v \quad\text{(Eq. 3)}

.. math::
    \mathbf{F}_v = \alpha h \sum_j m_j \frac{c_i + c_j}{\rho_i + \rho_j}
    \frac{\mathbf{v}_{ij}\cdot\mathbf{r}_{ij}}{r_{ij}^2 + (0.01h)^2}\nabla_i W_{ij}
    \quad\text{(Eq. 5, fluid--fluid pairs only: free slip at walls)}

with :math:`c_i = c_j = c_0`. Against a wall particle the fluid pressure enters as
:math:`\max(P_i, 0)` (and the wall's own extrapolated pressure is clamped at zero,
:func:`sph.engine.walls.wall_pressure`): a wall pushes and never pulls, so fluid in tension
(a vortex core reaching the tank floor under a rolling hull) cannot be drawn through the wall
layers. The optional delta-SPH diffusive term (second source paper,
Eq. 2; Antuono et al. 2010) is added to the continuity equation between fluid particles:

.. math::
    D_i = \delta h c_0 \sum_j \psi_{ij}\cdot\nabla_i W_{ij} V_j,\qquad
    \psi_{ij} = 2(\rho_j - \rho_i)\frac{\mathbf{r}_j - \mathbf{r}_i}{r_{ij}^2}
    - \left(\langle\nabla\rho\rangle^L_i + \langle\nabla\rho\rangle^L_j\right)

with the renormalised density gradient of :func:`sph.engine.filters.renormalised_density_gradient`.
The ``ddt`` variant (Fourtakas et al. 2019) needs no gradient pass: it
subtracts the hydrostatic density difference of the pair instead,

.. math::
    \psi_{ij} = 2\left(\rho_j - \rho_i - \rho^H_{ji}\right)
    \frac{\mathbf{r}_j - \mathbf{r}_i}{r_{ij}^2},\qquad
    \rho^H_{ji} = -\frac{\rho_0}{c_0^2}\,\mathbf{g}\cdot(\mathbf{r}_i - \mathbf{r}_j)

(the Tait law linearised over a kernel support: the relative error is
:math:`\rho_0 g\,3h / B`, below 1e-3 for every case here), so that a fluid at rest in
hydrostatic balance is left exactly as it is, while noise and the density jumps of a
violent flow are diffused. Like the renormalised form, and unlike a re-initialisation, it
does not reset the density of particles packed closer than their volumes allow.

The loop is a gather over fluid particles (no writes to neighbours, no races); pairs
interact only when their compartment ids match (thin walls), or, for two fluid particles,
when the segment between them passes through an open damage opening (:mod:`sph.bodies.damage`).
"""

from __future__ import annotations

from numba import prange

from sph.engine.jit import JIT_PARALLEL, njit
from sph.engine.kernels import KP_H, KP_R2MAX, f_r2, w_given_f, w_r2
from sph.engine.opening import passable, wall_hidden
from sph.engine.particles import FLUID
from sph.engine.shifting import SH_COEF, shift_vector


@njit(**JIT_PARALLEL)
def interact(x, z, vx, vz, rho, p, m, kind, body, comp, cell_of, cell_start, ncx, kp,
             visc_coef, gx, gz, delta_coef, ddt_rho, grx, grz, ax, az, drho, op, kin, shift,
             sx, sz):
    """Accelerations ``ax, az``, density rates ``drho`` and, when shifting is on, the
    particle shifts ``sx, sz`` (:mod:`sph.engine.shifting`) of all fluid particles.

    Parameters
    ----------
    visc_coef : float
        :math:`2 \\alpha h c_0` (zero disables viscosity).
    delta_coef : float
        :math:`\\delta h c_0` (zero disables the diffusive term; then ``grx, grz`` are unused).
    ddt_rho : float
        :math:`\\rho_0 / c_0^2` for the hydrostatic (``ddt``) form of the diffusive term;
        zero selects the renormalised form (``grx, grz``).
    grx, grz : arrays
        Renormalised density gradient of each particle (delta-SPH only).
    op, kin : arrays
        Damage opening (:mod:`sph.bodies.damage`) and body kinematics (:mod:`sph.engine.walls`).
    shift : array
        ``[coef, W(dx), cap]`` of :func:`sph.engine.shifting.shift_params`; ``coef = 0`` disables
        shifting and leaves ``sx, sz`` untouched. The kernel sum that decides whether a
        particle is packed is taken in this pair loop; only packed particles search their
        neighbours again for the shift (:func:`sph.engine.shifting.shift_vector`).
    """
    n = x.shape[0]
    r2max = kp[KP_R2MAX]
    eps2 = 1.0e-4 * kp[KP_H] * kp[KP_H]
    use_delta = delta_coef != 0.0
    use_ddt = ddt_rho != 0.0
    use_shift = shift[SH_COEF] != 0.0
    for i in prange(n):
        if kind[i] != FLUID:
            continue
        xi = x[i]
        zi = z[i]
        vxi = vx[i]
        vzi = vz[i]
        rhoi = rho[i]
        pi = p[i]
        ci = comp[i]
        gxi = grx[i] if use_delta else 0.0
        gzi = grz[i] if use_delta else 0.0
        accx = 0.0
        accz = 0.0
        div = 0.0
        diff = 0.0
        shep = m[i] / rhoi * w_r2(0.0, kp) if use_shift else 0.0
        c = cell_of[i]
        for row in (c - ncx, c, c + ncx):
            for j in range(cell_start[row - 1], cell_start[row + 2]):
                dx = xi - x[j]
                dz = zi - z[j]
                r2 = dx * dx + dz * dz
                if r2 >= r2max or j == i:
                    continue
                if kind[j] == FLUID:
                    if comp[j] != ci and not passable(xi, zi, x[j], z[j], ci, comp[j], op,
                                                      kin):
                        continue
                elif comp[j] != ci or wall_hidden(xi, zi, x[j], z[j], body[j], op, kin):
                    continue
                fw = f_r2(r2, kp)
                rhoj = rho[j]
                vj = m[j] / rhoj
                dvx = vxi - vx[j]
                dvz = vzi - vz[j]
                vr = dvx * dx + dvz * dz
                div += vj * vr * fw
                if kind[j] == FLUID:
                    coef = -m[j] * (pi + p[j]) / (rhoi * rhoj)
                else:  # a wall pushes and never pulls: fluid tension does not count
                    coef = -m[j] * (max(pi, 0.0) + p[j]) / (rhoi * rhoj)
                if kind[j] == FLUID:
                    coef += visc_coef * m[j] / (rhoi + rhoj) * vr / (r2 + eps2)
                    if use_ddt:
                        rho_h = -ddt_rho * (gx * dx + gz * dz)
                        diff -= 2.0 * vj * fw * (rhoj - rhoi - rho_h)
                    elif use_delta:
                        diff += vj * fw * (-2.0 * (rhoj - rhoi)
                                           - ((gxi + grx[j]) * dx + (gzi + grz[j]) * dz))
                accx += coef * fw * dx
                accz += coef * fw * dz
                if use_shift:
                    shep += vj * w_given_f(r2, fw, kp)
        ax[i] = accx + gx
        az[i] = accz + gz
        drho[i] = rhoi * div + delta_coef * diff
        if use_shift:
            sx[i], sz[i] = shift_vector(i, shep, x, z, rho, m, kind, body, comp, cell_of,
                                        cell_start, ncx, kp, op, kin, shift)
