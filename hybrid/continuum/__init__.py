"""Continuum phase on dolfinx: plane-strain elasticity (and, later, Mohr-Coulomb plasticity)."""

from hybrid.continuum.elastic import solve_elastic
from hybrid.continuum.state import ContinuumState

__all__ = ["ContinuumState", "solve_elastic"]
