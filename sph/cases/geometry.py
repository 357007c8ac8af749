"""Particle geometry: lattices, signed-distance shapes, tanks and their dummy-particle walls.

All particles of one case lie on one square lattice of spacing ``dx`` (cell-centred), so fluid
and wall particles never overlap and are never closer than ``dx``. A shape is described by a
signed distance ``sdf(x, z)`` (negative inside); lattice points inside are fluid candidates,
lattice points outside within ``n_layers * dx`` of the surface are wall particles.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from sph.engine.walls import tank_guard


def lattice(x0: float, x1: float, z0: float, z1: float, dx: float) -> np.ndarray:
    """Cell-centred lattice points of spacing ``dx`` filling ``[x0, x1] x [z0, z1]``."""
    nx = int(round((x1 - x0) / dx))
    nz = int(round((z1 - z0) / dx))
    xs = x0 + (np.arange(nx) + 0.5) * dx
    zs = z0 + (np.arange(nz) + 0.5) * dx
    xx, zz = np.meshgrid(xs, zs, indexing="ij")
    return np.column_stack([xx.ravel(), zz.ravel()])


def fit_cells(lo: float, hi: float, dx: float) -> tuple[np.ndarray, float]:
    """Centres and spacing of the cells of one lattice row filling ``[lo, hi]`` exactly (the
    spacing is stretched from ``dx`` by at most half a spacing over the row, so that the
    first and last centres sit half a spacing from the ends: free surfaces and walls are
    where the geometry puts them). No cell when the interval is under half a spacing."""
    n = int(round((hi - lo) / dx))
    if n < 1:
        return np.zeros(0), 0.0
    s = (hi - lo) / n
    return lo + (np.arange(n) + 0.5) * s, s


@dataclass(frozen=True)
class RoundedTank:
    """Open-topped tank ``[x0, x0 + width] x [z0, z0 + height]`` with rounded bottom corners.

    ``radius = 0`` gives a rectangular tank; ``radius > 0`` the U-shaped section of the
    ship's cabins (flat bottom, circular bilges, vertical sides)."""

    x0: float
    z0: float
    width: float
    height: float
    radius: float = 0.0

    def sdf(self, x: np.ndarray, z: np.ndarray) -> np.ndarray:
        """Signed distance to the tank's inner surface (negative inside), open at the top."""
        x = np.asarray(x, dtype=float)
        z = np.asarray(z, dtype=float)
        r = self.radius
        xl, xr = self.x0, self.x0 + self.width
        zb = self.z0
        # distance inside from each flat face (the top is open: no face there)
        d_in = np.minimum(np.minimum(x - xl, xr - x), z - zb)
        out = -d_in
        # rounded corners: points in the corner squares
        if r > 0.0:
            cz = zb + r
            for cx, side in ((xl + r, x < xl + r), (xr - r, x > xr - r)):
                corner = side & (z < cz)
                out = np.where(corner, np.hypot(x - cx, z - cz) - r, out)
        return out

    def guard(self, top: float, dx: float, n_layers: int) -> np.ndarray | None:
        """The tank's guard (:func:`sph.engine.walls.tank_guard`): its floor and both side
        walls up to ``top``; None for a rounded tank, whose bilges are not the guard's
        flat walls."""
        if self.radius > 0.0:
            return None
        return tank_guard(self.x0, self.x0 + self.width, self.z0, top, dx, n_layers)


def tank_particles(tank: RoundedTank, dx: float, n_layers: int, wall_top: float,
                   fluid_level: float | None):
    """Fluid and wall particles of an open tank.

    Parameters
    ----------
    tank : RoundedTank
    dx : float
        Lattice spacing.
    n_layers : int
        Wall thickness in particles.
    wall_top : float
        Height (absolute z) up to which the side walls extend.
    fluid_level : float or None
        Absolute height of the still free surface; ``None`` for an empty tank.

    Returns
    -------
    fluid_xz, wall_xz : (n, 2) arrays
    """
    t = n_layers * dx
    pts = lattice(tank.x0 - t, tank.x0 + tank.width + t, tank.z0 - t, wall_top, dx)
    d = tank.sdf(pts[:, 0], pts[:, 1])
    wall = pts[(d > 0.0) & (d <= t + 1e-9 * dx)]
    fluid = np.empty((0, 2))
    if fluid_level is not None:
        fluid = pts[(d < 0.0) & (pts[:, 1] < fluid_level)]
    return fluid, wall


def n_wall_layers(support_radius: float, dx: float, requested: int = 0) -> int:
    """Wall layers needed so that the walls cover the kernel support (or ``requested``)."""
    if requested:
        return requested
    return int(math.ceil(support_radius / dx - 1e-9))
