"""Discrete finite element engine (numba): deformable elements with ties, splitting, contact.

Public API: ``DiscreteState`` / ``from_mesh`` (state; its materials are
``hybrid.materials.Material``), ``rectangle`` (builders), ``step`` / ``stable_time_step`` /
``critical_time_step`` (integrate), ``check_interfaces`` / ``split_interfaces`` (ties),
``ExplicitSolver`` / ``RunOptions`` / ``RunResult`` (solver), ``EnergyLedger`` (ledger); the
outputs of runs are observers in ``outputs``. Import the submodules directly for more.
"""

from hybrid.discrete.builders import rectangle
from hybrid.discrete.ledger import EnergyLedger
from hybrid.discrete.solver import ExplicitSolver, RunOptions, RunResult
from hybrid.discrete.state import DiscreteState, from_mesh

__all__ = ["DiscreteState", "EnergyLedger", "ExplicitSolver", "RunOptions", "RunResult",
           "from_mesh", "rectangle"]
