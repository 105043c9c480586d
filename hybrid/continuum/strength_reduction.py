"""Factor of safety by strength reduction (Zienkiewicz et al. 1975; Griffiths & Lane 1999).

c and tan(phi) (and tan(psi)) of every plastic material are divided by F. Starting from the
converged state at the current strength, F is raised in steps of ``step`` and then bisected:
each trial restores the last converged state, sets the reduced strengths and seeks equilibrium
under the same loads. **Failure criterion:** no equilibrium, i.e. neither full Newton
(``max_iterations``) nor the elastic-stiffness iterations (``elastic_iterations``) bring the
residual under the tolerance. F is reported as the last converged value once the bracket is
narrower than ``tolerance``.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from hybrid.continuum.plastic import PlasticSolver
from hybrid.continuum.state import ContinuumState

__all__ = ["SafetyResult", "factor_of_safety"]


@dataclass
class SafetyResult:
    """F (last factor with equilibrium), the bracket, the trials and the two states.

    ``mechanism`` is the displacement increment [m] between the last two converged factors
    (the failure mechanism: what moves when strength is lost), as nodal values of ``state.u``'s
    space.
    """

    factor: float
    bracket: tuple[float, float]
    trials: list[tuple[float, bool, int]] = field(default_factory=list)
    state: ContinuumState | None = None
    mechanism: np.ndarray | None = None


def factor_of_safety(solver: PlasticSolver, *, start: float = 1.0, step: float = 0.2,
                     tolerance: float = 0.005, max_factor: float = 10.0) -> SafetyResult:
    """Strength-reduction factor of safety of the solver's current (converged) state."""
    if step <= 0 or tolerance <= 0:
        raise ValueError("strength reduction: step and tolerance must be > 0")
    lo, hi = start, None
    solver.set_strength_factor(lo)
    if solver.step() is None:
        raise RuntimeError(f"no equilibrium at the starting strength factor {start}: "
                           "the structure is already unstable")
    good = solver.snapshot()
    previous_u = good[3].copy()
    trials: list[tuple[float, bool, int]] = []
    while hi is None or hi - lo > tolerance:
        trial = lo + step if hi is None else 0.5 * (lo + hi)
        if trial > max_factor:
            raise RuntimeError(f"no failure up to F = {max_factor}: check the loads")
        solver.restore(good)
        solver.set_strength_factor(trial)
        record = solver.step()
        trials.append((trial, record is not None, 0 if record is None else record.iterations))
        if record is not None:
            lo = trial
            previous_u = good[3].copy()
            good = solver.snapshot()
        else:
            hi = trial
    solver.restore(good)
    solver.set_strength_factor(lo)
    state = solver.state()
    return SafetyResult(lo, (lo, hi), trials, state, good[3] - previous_u)
