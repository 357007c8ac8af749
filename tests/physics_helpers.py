"""Small helpers shared by the tests."""

from __future__ import annotations

import os

import numpy as np
import pytest
import xarray as xr

from sph.cases import builtin
from sph.driver import Simulation
from sph.engine.fluid import interact, pair_work
from sph.engine.neighbours import NeighbourList
from sph.engine.opening import no_opening
from sph.engine.surface import CLAMP
from sph.engine.walls import fixed_kinematics
from sph.study.analysis import validation_data_dir

#: The last five arguments of :func:`sph.engine.fluid.interact` and ``interact_reference``
#: (``tension, surf, gw, wnx, wnz``) as the stepper passes them for a run with the default
#: wall tension and neither free surface, ghosts nor wall damping. They have no defaults, so
#: that a test compiles the stepper's signature, not one of its own (each signature of the
#: pair loop takes tens of seconds to compile).
NO_EXTRAS = (CLAMP, None, None, None, None)


def run_builtin(case: str, overrides) -> Simulation:
    """Build and run a built-in case with ``overrides`` (list of "key=value")."""
    cfg = builtin(case, list(overrides))
    return Simulation(cfg).run()


def set_options(overrides) -> list[str]:
    """``--set`` options of ``sph run`` for each ``key=value`` override."""
    out = []
    for item in overrides:
        out += ["--set", item]
    return out


def require_validation_data():
    """The experimental series live outside the project; CI must have them."""
    d = validation_data_dir()
    if not d.is_dir():
        if os.environ.get("CI"):
            pytest.fail(f"validation data not found at {d} (set SPH_VALIDATION_DATA)")
        pytest.skip(f"validation data not found at {d} (set SPH_VALIDATION_DATA)")
    return d


def assert_same_series(a: xr.Dataset, b: xr.Dataset) -> None:
    """Every variable and coordinate equal bit for bit (NaN where NaN), same dtypes."""
    assert sorted(a.variables) == sorted(b.variables)
    for name in a.variables:
        x, y = a[name].values, b[name].values
        assert x.shape == y.shape, name
        if x.dtype.kind in "OUS":  # labels: str in memory, object when read from a file
            assert [str(v) for v in x.ravel()] == [str(v) for v in y.ravel()], name
            continue
        assert x.dtype == y.dtype, name
        if x.dtype.kind == "f":
            assert np.array_equal(x, y, equal_nan=True), name
        else:
            assert np.array_equal(x, y), name


def sort_by_cells(grid, x, z, *arrays):
    """``x, z`` and ``arrays`` reordered by the cells of ``grid`` (every particle inside)."""
    assert grid.sort(x, z) == 0
    return [a[grid.order].copy() for a in (x, z, *arrays)]


def fluid_pair_loop(x, z, vx, vz, rho, m, grid, kp, *, visc_coef=0.0, gz=0.0,
                    delta_coef=0.0, ddt_rho=0.0, shift=None):
    """One call of :func:`sph.engine.fluid.interact` on fluid particles alone, already sorted by
    ``grid``: no walls, no body, no opening, no pressure, density gradients zero.

    Returns ``ax, az, drho, sx, sz`` (the shifts stay zero unless ``shift`` is given).
    """
    n = len(x)
    zero = np.zeros(n)
    ax, az, drho, sx, sz = (np.zeros(n) for _ in range(5))
    interact(x, z, vx, vz, rho, zero, m, np.zeros(n, np.int32), np.full(n, -1, np.int32),
             np.zeros(n, np.int32), np.ones(n), grid.cell_of, grid.cell_start, grid.ncx, kp,
             visc_coef, 0.0, gz, delta_coef, ddt_rho, zero, zero, ax, az, drho, no_opening(),
             fixed_kinematics(1), np.zeros(3) if shift is None else shift, sx, sz,
             pair_work(n), *verlet_lists(x, z, np.zeros(n, np.int32), grid), False,
             *NO_EXTRAS)
    return ax, az, drho, sx, sz


def verlet_lists(x, z, kind, grid):
    """``start, inner, inner_end`` of the inner lists (what the fluid pair loop reads) of
    particles sorted by ``grid``, of the grid's cell size (the kernel support: no skin)."""
    nlist = NeighbourList()
    nlist.build(x, z, kind, grid, grid.cell, np.ones(len(x)))
    nlist.refresh(x, z, grid.cell, np.ones(len(x)))
    return nlist.start, nlist.inner, nlist.inner_end
