"""Tied settle of a discrete start: how far it is from its own equilibrium (H1)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from hybrid.discrete.integrate import prime
from hybrid.discrete.solver import ExplicitSolver, RunOptions
from hybrid.discrete.start import Handover
from hybrid.discrete.state import DiscreteState

__all__ = ["SettleReport", "residual_force", "settle"]


def residual_force(disc: DiscreteState) -> np.ndarray:
    """Out-of-balance force of every tie group's free components (n_groups, 2) [kN/m].

    Gravity + external - internal, summed over the group (zero in equilibrium).
    """
    prime(disc)
    f = disc.external_force - disc.internal_force + disc.mass[:, None] * disc.gravity[None, :]
    per_group = np.zeros((disc.n_groups, 2))
    np.add.at(per_group, disc.node_group, f)
    held = np.zeros((disc.n_groups, 2), dtype=bool)
    np.logical_or.at(held, disc.node_group, disc.fixed)
    per_group[held] = 0.0
    return per_group


@dataclass
class SettleReport:
    """How far a tied settle moved the discrete start (H1)."""

    steps: int
    initial_residual: float  # norm of the out-of-balance forces at handover [kN/m]
    final_residual: float  # the same after the settle [kN/m]
    reference_force: float  # norm of the weight + loads, for scale [kN/m]
    max_velocity: float  # largest node speed at the end [m/s]
    max_displacement: float  # largest node movement during the settle [m]
    stress_change: float  # max |stress change| / max |stress| over the Gauss points [-]

    def as_dict(self) -> dict[str, float]:
        """The figures for a summary."""
        return dict(self.__dict__)


def settle(handover: Handover, *, steps: int = 2000, mass_damping: float = 0.0,
           local_damping: float = 0.7) -> SettleReport:
    """Tied settle of the discrete start.

    ``steps`` explicit steps with mass damping ``mass_damping`` [1/s] and local damping
    ``local_damping`` [-], no splitting, no contact.
    """
    disc = handover.discrete
    x0, s0 = disc.x.copy(), disc.stress.copy()
    r0 = float(np.linalg.norm(residual_force(disc)))
    weight = disc.mass[:, None] * disc.gravity[None, :] + disc.external_force
    ref = float(np.linalg.norm(weight))
    saved = disc.interface_splittable.copy()
    opts = RunOptions(mass_damping=mass_damping, local_damping=local_damping, split_every=0,
                      contact=False)
    with ExplicitSolver(disc, opts) as solver:
        solver.run(max_steps=steps)
    disc.interface_splittable[:] = saved
    r1 = float(np.linalg.norm(residual_force(disc)))
    scale = float(np.max(np.abs(s0))) or 1.0
    return SettleReport(steps, r0, r1, ref, float(np.max(np.hypot(*disc.v.T))),
                        float(np.max(np.hypot(*(disc.x - x0).T))),
                        float(np.max(np.abs(disc.stress - s0))) / scale)
