"""Outcome of a continuum stage and the figures that judge a load-displacement curve.

:class:`Analysis` is what every stage of a
:class:`~hybrid.continuum.plastic.PlasticSolver` returns (the target reached, or the last
converged factor) with the tests that decide whether a stage that stopped short found a
collapse or a limit load (``require*``); :func:`runaway_ratio` and :func:`plateau_rise` read
a curve, :func:`largest_nodal_norm` the largest nodal displacement over the MPI ranks;
:func:`at_rest_checks` compares the stress in level ground under its own weight with K0.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any, NamedTuple

import numpy as np
from mpi4py import MPI

from hybrid.errors import StageIncomplete
from hybrid.io import Check
from hybrid.references import oedometer_stress

__all__ = ["RUNAWAY_JUMP", "Analysis", "AtRest", "at_rest_checks", "largest_nodal_norm",
           "plateau_rise", "runaway_ratio"]

# a load path ran away (a collapse) when d u / d load of its last increment is at least this many
# times its first's
RUNAWAY_JUMP = 10.0


@dataclass
class Analysis:
    """Outcome of a stage: the target reached (``completed``) or the last converged factor.

    Attributes:
        completed: True when the stage reached its target.
        factor: the last factor with equilibrium (load factor, fraction of the self-weight or
            of the lift's weight).
        cuts: increments halved on the way.
        stage: what was applied, in words ("self-weight", "load", "lift 'fill_2'").
        target: the factor asked for.
        path: (factor, largest nodal displacement of the stage [m]) at the start and after
            every converged increment, where the stage records it (a lift placed: its
            weight's fraction); :meth:`runaway` reads it.
    """

    completed: bool
    factor: float
    cuts: int
    stage: str = "load"
    target: float = 1.0
    path: tuple[tuple[float, float], ...] = ()

    def message(self) -> str:
        """What happened, in a sentence a user can act on."""
        if self.completed:
            return f"{self.stage}: completed ({self.target:.6g})"
        if self.stage == "self-weight":
            return (f"self-weight carried up to {100 * self.factor:.0f} %: no equilibrium "
                    "under the full weight at these strengths (unstable under gravity, "
                    "F < 1, or Newton did not converge); run the strength search from a "
                    "stronger state (factor_of_safety(..., gravity_steps=...)) or check the "
                    "strengths and supports")
        if self.stage.startswith("lift"):
            return (f"{self.stage} placed with {100 * self.factor:.0f} % of its weight: no "
                    "equilibrium beyond (the structure collapses during this lift, or Newton "
                    "did not converge)")
        return (f"{self.stage} factor {self.factor:.6g} of the target {self.target:.6g}: no "
                "equilibrium beyond (collapse, or Newton did not converge)")

    def runaway(self) -> float | None:
        """:func:`runaway_ratio` of :attr:`path`; None with fewer than two increments."""
        if len(self.path) < 3:
            return None
        return runaway_ratio([f for f, _ in self.path], [u for _, u in self.path])

    def require(self) -> Analysis:
        """Return self when completed; otherwise raise :class:`StageIncomplete`."""
        if not self.completed:
            raise StageIncomplete(self.message())
        return self

    def require_limit(self, displacement: Sequence[float], force: Sequence[float], *,
                      jump: float = 10.0) -> Analysis:
        """A displacement-controlled push (a rigid footing, a wall moved).

        The push is complete, or stopped on the limit load.

        An incomplete push counts as having found the limit when the structure's stiffness
        has fallen: d(force)/d(displacement) of the last step below 1/``jump`` of the first
        (or negative: the force falls); otherwise Newton stopped before the limit and
        :class:`StageIncomplete` is raised.
        """
        if self.completed:
            return self
        ratio = runaway_ratio(force, displacement)
        if ratio >= jump or ratio < 0.0:
            return self
        raise StageIncomplete(
            f"{self.message()}; the force was still rising (stiffness of the last step "
            f"1/{ratio:.3g} of the first, not below 1/{jump:g}): no limit load was reached. "
            "Use more steps or a finer mesh")

    def require_collapse(self, load: Sequence[float], displacement: Sequence[float], *,
                         jump: float = RUNAWAY_JUMP) -> Analysis:
        """A load-controlled ramp stopped short of its target.

        It counts as a collapse only if the displacement ran away (:func:`runaway_ratio` of
        the last step >= ``jump``).
        """
        if self.completed:
            return self
        ratio = runaway_ratio(load, displacement)
        if ratio >= jump:
            return self
        raise StageIncomplete(
            f"{self.message()}; the displacement did not run away (d u / d load of the last "
            f"step {ratio:.3g} times that of the first, below {jump:g}): Newton did not "
            "converge before a collapse. Use more steps or a finer mesh")


def largest_nodal_norm(values: np.ndarray, comm: Any) -> float:
    """Largest |v| over the nodes of a 2-D vector field given by its dof values.

    Over all ranks (collective).
    """
    local = float(np.max(np.linalg.norm(np.reshape(values, (-1, 2)), axis=1), initial=0.0))
    return comm.allreduce(local, op=MPI.MAX)


def plateau_rise(x: Sequence[float], y: Sequence[float], tail: float = 0.2) -> float:
    """Rise of ``y`` over the last ``tail`` of the range of ``x``, relative to its end value.

    0 on a plateau; ``y`` at the start of the tail is the first point inside it.
    """
    xa, ya = np.asarray(x, float), np.asarray(y, float)
    if len(xa) < 2 or ya[-1] == 0.0:
        return math.inf
    inside = xa >= xa[-1] - tail * (xa[-1] - xa[0])
    return float((ya[-1] - ya[inside][0]) / abs(ya[-1]))


def runaway_ratio(factor: Sequence[float], displacement: Sequence[float]) -> float:
    """Ratio of d(displacement)/d(factor) in the last step to that in the first.

    At a collapse the displacement runs away. 1 with fewer than three points; inf when the
    first step did not move and the last did; negative when the factor fell in the last step.
    """
    f, u = np.asarray(factor, float), np.asarray(displacement, float)
    if len(f) < 3:
        return 1.0
    first = (u[1] - u[0]) / (f[1] - f[0])
    last = (u[-1] - u[-2]) / (f[-1] - f[-2])
    if first <= 0.0:
        return math.inf if last > 0.0 else 1.0
    return float(last / first)


class AtRest(NamedTuple):
    """What :func:`at_rest_checks` found.

    ``stress`` (4,) at the point [kPa]; ``checks`` "far_field_sigma_v" and
    "far_field_sigma_h".
    """

    stress: np.ndarray
    checks: dict[str, Check]


def at_rest_checks(state: Any, point: Sequence[float], *, ground_level: float,
                   unit_weight: float, nu: float, tolerance: float = 0.01,
                   where: str = "below level ground") -> AtRest:
    """The stress at ``point`` (x, y) [m] of level elastic ground under its own weight.

    Far from any load, the ground is laterally confined: sigma_v = -gamma z and
    sigma_h = K0 sigma_v, K0 = nu / (1 - nu), with z the depth below ``ground_level`` [m]
    (:func:`~hybrid.references.oedometer_stress`); each within ``tolerance`` (relative).
    ``state``: a :class:`~hybrid.continuum.state.ContinuumState`; ``where`` ends the
    description of sigma_v's check. Collective under MPI.
    """
    stress = state.stress_at(np.array([point], dtype=float))[0]
    sv, sh = oedometer_stress(unit_weight, nu, np.array(ground_level - float(point[1])))
    return AtRest(stress, {
        "far_field_sigma_v": Check(float(stress[1]), float(sv), tolerance, "kPa",
                                   f"gamma z {where}"),
        "far_field_sigma_h": Check(float(stress[0]), float(sh), tolerance, "kPa",
                                   "K0 gamma z, K0 = nu / (1 - nu)")})
