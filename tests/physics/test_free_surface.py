"""Free-surface detection (:func:`sph.engine.surface.free_surface`, Marrone et al. 2010)
against the geometry of lattices, and the wall-tension rules of the pair loop
(``numerics.wall_tension``; the second source paper's Eq. 6).

A scene is a square lattice of spacing ``dx`` whose sites are air, fluid or wall. The
detection is judged by the geometry alone: a fluid particle with an air site next to it
(one of its four lattice neighbours) lies on the free surface and must be flagged; one with
no air site within two spacings (the 5 x 5 block around it) is inside and must not be. The
sites in between (air only diagonally or two spacings away) may go either way: the
criterion marks a surface one particle layer thick, and which of the half-covered corner
particles it counts is a matter of the kernel.
"""

import numpy as np
import pytest

from sph.engine.eos import tait_density
from sph.engine.fluid import interact, interact_reference, pair_work
from sph.engine.kernels import KERNELS, KP_R2MAX, SUPPORT, f_r2, kernel_params
from sph.engine.neighbours import CellGrid
from sph.engine.opening import no_opening
from sph.engine.particles import FLUID, WALL
from sph.engine.surface import (
    CLAMP,
    FREE_SURFACE,
    LAMBDA_INTERIOR,
    NONE,
    free_surface,
    smallest_eigenvalue,
)
from sph.engine.walls import fixed_kinematics, wall_pressure
from tests.physics_helpers import sort_by_cells, verlet_lists

DX = 0.1
RHO0 = 1000.0
AIR, WATER, SOLID = 0, 1, 2
H_FACTOR = {"gaussian": 1.23, "wendland": 1.41}


def _layers(kernel):
    """Wall layers that cover the kernel support."""
    return int(np.ceil(SUPPORT[KERNELS[kernel]] * H_FACTOR[kernel]))


class Scene:
    """Particles on the sites of ``labels`` (rows from the bottom), sorted by cell, with
    their inner lists."""

    def __init__(self, labels, kernel, jitter=0.0):
        self.kp = kernel_params(kernel, H_FACTOR[kernel] * DX)
        iz, ix = np.nonzero(labels != AIR)
        x = (ix + 0.5) * DX
        z = (iz + 0.5) * DX
        if jitter:  # fluid particles moved off their sites by up to jitter * dx
            rng = np.random.default_rng(7)
            moved = labels[iz, ix] == WATER
            x[moved] += rng.uniform(-jitter, jitter, moved.sum()) * DX
            z[moved] += rng.uniform(-jitter, jitter, moved.sum()) * DX
        kind = np.where(labels[iz, ix] == WATER, FLUID, WALL).astype(np.int32)
        radius = np.sqrt(self.kp[KP_R2MAX])
        self.grid = CellGrid(x.min(), x.max(), z.min(), z.max(), radius)
        self.x, self.z, self.kind, self.ix, self.iz = sort_by_cells(
            self.grid, x, z, kind, ix, iz)
        self.n = len(self.x)
        self.m = np.full(self.n, RHO0 * DX * DX)
        self.rho = np.full(self.n, RHO0)
        self.body = np.where(self.kind == FLUID, -1, 0).astype(np.int32)
        self.comp = np.zeros(self.n, np.int32)
        self.lists = verlet_lists(self.x, self.z, self.kind, self.grid)
        self.labels = labels

    def detect(self):
        lam = np.zeros(self.n)
        surf = np.zeros(self.n, np.bool_)
        free_surface(self.x, self.z, self.m, self.rho, self.kind, self.body, self.comp, None,
                     self.kp, no_opening(), fixed_kinematics(1), *self.lists, lam, surf)
        return lam, surf

    def exposure(self):
        """Per particle: 1 with air among its four neighbours, 0 with no air in the 5 x 5
        block around it, -1 otherwise (either answer is right)."""
        pad = np.pad(self.labels, 2, constant_values=AIR)
        out = np.full(self.n, -1)
        for k in range(self.n):
            i, j = self.iz[k] + 2, self.ix[k] + 2
            if AIR in (pad[i + 1, j], pad[i - 1, j], pad[i, j + 1], pad[i, j - 1]):
                out[k] = 1
            elif AIR not in pad[i - 2:i + 3, j - 2:j + 3]:
                out[k] = 0
        return out


def tank(nx=30, depth=12, height=18, layers=4, floor_step=None):
    """Water ``depth`` sites deep in a tank ``nx`` sites wide, walls ``layers`` thick, the
    side walls ``height`` sites high; ``floor_step = (i0, i1, rise)`` raises the floor by
    ``rise`` sites between columns ``i0`` and ``i1``."""
    lab = np.full((layers + height, nx + 2 * layers), AIR)
    lab[:layers, :] = SOLID
    lab[:, :layers] = SOLID
    lab[:, layers + nx:] = SOLID
    lab[layers:layers + depth, layers:layers + nx] = WATER
    if floor_step is not None:
        i0, i1, rise = floor_step
        lab[layers:layers + rise, layers + i0:layers + i1] = SOLID
    return lab


def drop(radius=10):
    """A circular drop of ``radius`` spacings, no walls."""
    n = 2 * radius + 2
    c = (np.arange(n) + 0.5 - n / 2)
    r2 = c[None, :] ** 2 + c[:, None] ** 2
    return np.where(r2 <= radius * radius, WATER, AIR)


def dam(layers=4):
    """A tank whose water has a step in its surface: 16 sites deep over the left 8 columns,
    8 deep beyond, and a raised floor (4 sites) under the shallow part."""
    lab = tank(nx=30, depth=8, height=22, layers=layers, floor_step=(18, 24, 4))
    lab[layers + 8:layers + 16, layers:layers + 8] = WATER
    return lab


@pytest.mark.parametrize("kernel", ["gaussian", "wendland"])
@pytest.mark.parametrize("shape", ["tank", "step_floor", "drop", "dam"])
@pytest.mark.parametrize("jitter", [0.0, 0.2])
def test_detection_follows_the_geometry(kernel, shape, jitter):
    """Still tank, a floor with a step under the water, a circular drop, and water with a
    step in its surface over a raised floor; on the lattice and with the fluid particles
    moved off it by up to 0.2 dx."""
    layers = _layers(kernel)
    labels = {"tank": lambda: tank(layers=layers),
              "step_floor": lambda: tank(layers=layers, floor_step=(10, 18, 5)),
              "drop": drop, "dam": lambda: dam(layers)}[shape]()
    sc = Scene(labels, kernel, jitter)
    lam, surf = sc.detect()
    fluid = sc.kind == FLUID
    exp = sc.exposure()
    missed = fluid & (exp == 1) & ~surf
    false = fluid & (exp == 0) & surf
    assert not missed.any(), f"surface particles not flagged at {_sites(sc, missed)}"
    assert not false.any(), f"interior particles flagged at {_sites(sc, false)}"
    # inside, away from every boundary, the renormalisation matrix is the identity (on the
    # lattice; 0.2 dx of disorder takes its smallest eigenvalue down to about 0.8)
    assert np.all(np.abs(lam[fluid & (exp == 0)] - 1.0) < (0.05 if jitter == 0.0 else 0.25))


def _sites(sc, mask):
    return [(int(sc.ix[k]), int(sc.iz[k])) for k in np.nonzero(mask)[0][:10]]


@pytest.mark.parametrize("kernel", ["gaussian", "wendland"])
def test_still_tank_flags_the_top_layer_only(kernel):
    """In a still tank the flagged particles are the top row, wall corners included, and
    the fluid next to the side walls and the floor is inside. With 0.2 dx of disorder some
    particles of the second row have a smallest eigenvalue below 0.75 (the support is cut
    by the surface one spacing above them): the scan region, which finds the top row above
    them, keeps them inside."""
    layers = _layers(kernel)
    for jitter in (0.0, 0.2):
        sc = Scene(tank(layers=layers), kernel, jitter)
        lam, surf = sc.detect()
        fluid = sc.kind == FLUID
        top = fluid & (sc.iz == sc.iz[fluid].max())
        assert np.array_equal(surf[fluid], top[fluid])
    if kernel == "gaussian":
        assert np.any(fluid & ~top & (lam <= LAMBDA_INTERIOR))


def test_smallest_eigenvalue():
    rng = np.random.default_rng(1)
    for _ in range(20):
        a, b, c = rng.normal(size=3)
        want = np.linalg.eigvalsh(np.array([[a, b], [b, c]]))[0]
        assert abs(smallest_eigenvalue(a, b, c) - want) < 1e-12


# --------------------------------------------------------------------------- Eq. 6


TENSION = -2000.0  # Pa: the whole tank in uniform tension, no gravity


def _accelerations(sc, tension, surf, reference=False):
    """Accelerations of the fluid of ``sc`` with every fluid particle at ``TENSION`` and the
    wall pressures extrapolated from it (clamped at zero except under ``none``)."""
    n = sc.n
    b = 1000.0 * 30.0**2 / 7.0
    p = np.where(sc.kind == FLUID, TENSION, 0.0)
    rho = np.where(sc.kind == FLUID, tait_density(TENSION, RHO0, b, 7.0), RHO0)
    m = sc.m.copy()
    wall_pressure(sc.x, sc.z, rho, p, m, sc.kind, sc.body, sc.comp, None, sc.kp, 0.0, 0.0,
                  fixed_kinematics(1), RHO0, b, 7.0, DX * DX, no_opening(), *sc.lists,
                  tension != NONE, None)
    out = [np.zeros(n) for _ in range(5)]
    zero = np.zeros(n)
    g = sc.grid
    args = (sc.x, sc.z, zero, zero, rho, p, m, sc.kind, sc.body, sc.comp, np.ones(n),
            g.cell_of, g.cell_start, g.ncx, sc.kp, 0.0, 0.0, 0.0, 0.0, 0.0, zero, zero,
            *out[:3], no_opening(), fixed_kinematics(1), np.zeros(3), *out[3:])
    if reference:
        interact_reference(*args, tension, surf, None, None, None)
    else:
        interact(*args, pair_work(n), *sc.lists, False, tension, surf, None, None, None)
    return out[0], out[1], p


@pytest.mark.parametrize("kernel", ["gaussian", "wendland"])
def test_eq6_frees_the_surface_and_holds_the_interior(kernel):
    """Fluid in tension next to the side wall of a tank: the wall's pull on it (the
    acceleration towards the wall beyond the fluid's own, measured against ``none``, which
    keeps every pair) is zero for the free-surface particle at the waterline under
    ``free_surface`` and under ``clamp``, and is kept for the particle inside the fluid under
    ``free_surface`` (it is zero there only under ``clamp``)."""
    layers = _layers(kernel)
    sc = Scene(tank(layers=layers), kernel)
    _, surf = sc.detect()
    fluid = sc.kind == FLUID
    col = fluid & (sc.ix == layers)  # the column next to the left wall
    corner = np.nonzero(col & (sc.iz == sc.iz[fluid].max()))[0][0]
    inner = np.nonzero(col & (sc.iz == layers + 6))[0][0]
    assert surf[corner] and not surf[inner]

    ax_none, _, p = _accelerations(sc, NONE, None)
    ax_fs, _, p_fs = _accelerations(sc, FREE_SURFACE, surf)
    ax_clamp, _, p_clamp = _accelerations(sc, CLAMP, None)
    assert p[sc.kind == WALL].max() == 0.0 and p[sc.kind == WALL].min() < 0.0
    assert np.all(p_fs[sc.kind == WALL] == 0.0) and np.all(p_clamp[sc.kind == WALL] == 0.0)
    # the wall pull of each rule: what the walls add to the fluid-fluid part, which is the
    # same under every rule; under none the walls (at about the fluid's tension) pull
    # towards -x, under free_surface the fluid's own tension does
    pull_none = _wall_part(sc, (corner, inner), p, NONE, None)
    pull_fs = _wall_part(sc, (corner, inner), p_fs, FREE_SURFACE, surf)
    pull_clamp = _wall_part(sc, (corner, inner), p_clamp, CLAMP, None)
    for k in (corner, inner):
        assert pull_none[k] < -0.5 * abs(TENSION) / (RHO0 * DX)  # pulled, m/s^2
        assert pull_clamp[k] == 0.0
        # the pair loop agrees with the pair sums done here to round-off
        fluid_part = ax_none[k] - pull_none[k]
        assert abs(ax_fs[k] - (fluid_part + pull_fs[k])) < 1e-9 * abs(ax_none[k])
        assert abs(ax_clamp[k] - (fluid_part + pull_clamp[k])) < 1e-9 * abs(ax_none[k])
    assert pull_fs[corner] == 0.0  # Eq. 6: the surface particle feels no attraction
    assert pull_fs[inner] < -0.25 * abs(TENSION) / (RHO0 * DX)  # the interior one does
    # the general loop (variable resolution, damage opening) takes the same rule
    ax_ref, _, _ = _accelerations(sc, FREE_SURFACE, surf, reference=True)
    assert np.allclose(ax_ref[fluid], ax_fs[fluid], rtol=1e-10, atol=1e-9 * abs(ax_none).max())


def _wall_part(sc, index, p, tension, surf):
    """x-acceleration of the fluid particles ``index`` from its wall pairs alone, summed here:
    ``-sum_j V_j S_ij / rho_i * dW/dx`` with the pressure sum ``S_ij`` of the rule."""
    out = np.zeros(sc.n)
    walls = np.nonzero(sc.kind == WALL)[0]
    rho = tait_density(TENSION, RHO0, 1000.0 * 30.0**2 / 7.0, 7.0)
    for i in index:
        dx = sc.x[i] - sc.x[walls]
        dz = sc.z[i] - sc.z[walls]
        fw = np.array([f_r2(r2, sc.kp) for r2 in dx * dx + dz * dz])
        if tension == CLAMP:
            s = max(p[i], 0.0) + p[walls]
        elif tension == FREE_SURFACE and surf[i]:
            s = np.maximum(p[i] + p[walls], 0.0)
        else:
            s = p[i] + p[walls]
        out[i] = -np.sum(DX * DX * s * fw * dx) / rho
    return out
