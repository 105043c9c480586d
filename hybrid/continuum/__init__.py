"""Continuum phase on dolfinx: plane-strain elasticity and Mohr-Coulomb elasto-plasticity."""

import logging as _logging

import dolfinx as _dolfinx  # noqa: F401  (imported first: it configures the root logger)


def _quiet_jit(record: _logging.LogRecord) -> bool:
    """Drop the gcc lines that setuptools logs at INFO on the root logger during FFCx JIT."""
    return record.name != "root" or record.levelno >= _logging.WARNING


# FFCx installs a root handler (logging.basicConfig) and its JIT build raises the root level
# to INFO; UFL warns about DQ elements on quadrilaterals: keep the library quiet.
for _handler in _logging.getLogger().handlers:
    _handler.addFilter(_quiet_jit)
_logging.getLogger("UFL").setLevel(_logging.ERROR)

from hybrid.continuum.analysis import Analysis  # noqa: E402
from hybrid.continuum.control import DisplacementControl, DissipationControl  # noqa: E402
from hybrid.continuum.elastic import solve_elastic  # noqa: E402
from hybrid.continuum.plastic import NewtonOptions, PlasticSolver  # noqa: E402
from hybrid.continuum.state import ContinuumState  # noqa: E402
from hybrid.continuum.strength_reduction import factor_of_safety  # noqa: E402

__all__ = ["Analysis", "ContinuumState", "DisplacementControl", "DissipationControl",
           "NewtonOptions", "PlasticSolver", "factor_of_safety", "solve_elastic"]
