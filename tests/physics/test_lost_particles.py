"""Fluid particles that escape through a wall: removed and counted within the budget
``run.max_lost_fraction``, the run stopped beyond it; NaN positions always stop the run."""

import logging

import numpy as np
import pytest

from sph.cases import builtin
from sph.driver import Simulation
from sph.engine.stepper import SimulationError

SMALL = ["numerics.dx=0.1", "geometry.tank_length=1.0", "geometry.depth=0.5",
         "geometry.tank_height=0.8", "run.t_end=0.05", "run.output_interval=0.01"]


def _sim(extra=()):
    sim = Simulation(builtin("still_water", SMALL + list(extra)))
    sim.evaluate()
    return sim


def _throw_out(sim, k=1):
    """Put ``k`` fluid particles below the tank's wall layers (outside the domain)."""
    p = sim.parts
    idx = np.nonzero(p.kind == 0)[0][:k]
    p.z[idx] = sim.grid.bounds[2] - 1.0
    return p.pid[idx].copy()


def test_escaped_particle_is_removed_counted_and_reported(caplog):
    sim = _sim(["run.max_lost_fraction=0.05"])  # 50 fluid particles: 2 may go
    n0 = int(np.sum(sim.parts.kind == 0))
    gone = _throw_out(sim)
    with caplog.at_level(logging.WARNING, logger="sph.engine.stepper"):
        sim.evaluate()
    assert sim.n_lost == 1 and int(np.sum(sim.parts.kind == 0)) == n0 - 1
    assert not np.isin(gone, sim.parts.pid).any()
    assert "left the domain" in caplog.text and "removed (1 of 2 allowed)" in caplog.text
    sim.run()  # runs on, and says so in its output
    assert sim.dataset().attrs["lost_particles"] == 1


def test_run_stops_when_the_budget_is_spent():
    sim = _sim()  # default budget: 0.1 % of 50 particles = none
    _throw_out(sim)
    with pytest.raises(SimulationError, match="run.max_lost_fraction allows"):
        sim.evaluate()


def test_nan_position_always_stops_the_run():
    sim = _sim(["run.max_lost_fraction=0.1"])
    sim.parts.x[0] = np.nan
    with pytest.raises(SimulationError, match="or are NaN"):
        sim.evaluate()
