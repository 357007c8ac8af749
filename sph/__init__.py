"""sph-flood: a numba weakly-compressible SPH engine for damaged-ship flooding studies.

The engine follows Cao, Tao, Zhang & Ming, "Smoothed particle hydrodynamics (SPH) model for
coupled analysis of a damaged ship with internal sloshing in beam seas", Phys. Fluids 31,
032103 (2019), with the delta-SPH density diffusion and Wendland C2 kernel as options.
"""

__version__ = "0.1.0"
