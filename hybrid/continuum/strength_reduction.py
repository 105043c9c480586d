"""Factor of safety by strength reduction (Zienkiewicz et al. 1975; Griffiths & Lane 1999).

c, tan(phi), tan(psi) and the tensile strength of every plastic material are divided by F
(:meth:`PlasticSolver.set_strength_factor`). The search is a **continuation**: from the
newest converged state, F is raised by a relative increment ``r`` (F <- F (1 + r)) and the
equilibrium under the same loads is sought from that state (:meth:`PlasticSolver.step`, the
previous increment of the displacement as the first iterate). After a converged step ``r``
grows by ``growth`` (up to ``max_increment``); after a failed one it is halved and the step is
tried again from the same newest converged state, so a factor that failed from far away is
tried again from closer before it is called a failure.

**Failure criterion:** no equilibrium for an increase smaller than ``tolerance`` (relative)
from the newest converged state, and none for the confirmation increases tried next from that
state: smaller ones (``tolerance`` / 4 and / 8) and larger ones (2, 4, ... x ``tolerance`` up
to ``initial_increment``). Non-smooth Newton (points changing return region, as with
non-associated flow) sometimes fails for one increase and converges for another: any of them
converging shows that the failure was numerical, and the search goes on from there. F is the
last converged factor; the failed factor above it is within ``tolerance`` F.
**Cross-check:** the monitored displacement (the largest nodal displacement since the start
of the search, or the displacement of a given point) against F is the curve PLAXIS users know
from Msf; at failure it turns flat. ``displacement_jump`` is the rate d(u)/dF of the last
converged increment over that of the first; a mechanism is confirmed when it is at least
``jump_ratio`` (10). A factor found without it is reported as such (``mechanism_confirmed``).

**F < 1.** With ``gravity_steps`` the search first switches the self-weight on itself. If the
weight cannot be carried at the starting strengths, the strengths are multiplied up (F
multiplied by ``strengthen``, 0.5) and the weight switched on again from the unloaded state,
until it is carried (or F falls below ``lowest_factor``: an error); the continuation then
raises F from there, and the F found may be below 1 (``SafetyResult.below_one``). These
switch-ons resolve the fraction of the weight carried to 1/64 of a gravity step: only whether
it is carried decides.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from hybrid.continuum.analysis import largest_nodal_norm, runaway_ratio
from hybrid.continuum.plastic import IncrementControl, PlasticSolver
from hybrid.continuum.probe import evaluate
from hybrid.continuum.state import ContinuumState
from hybrid.errors import StageIncomplete
from hybrid.progress import progress

__all__ = ["SafetyResult", "StrengthSearch", "factor_of_safety"]

log = logging.getLogger(__name__)


@dataclass(frozen=True)
class StrengthSearch:
    """Options of the strength-reduction search (increments are fractions of F).

    Attributes:
        initial_increment: first relative increase of F [-].
        max_increment: largest relative increase of F [-].
        tolerance: F is bracketed to this relative width: the search ends when an increase
            smaller than this finds no equilibrium [-].
        growth: factor on the increment after a converged step [-].
        strengthen: F multiplied by this while the self-weight cannot be carried [-].
        lowest_factor: give up strengthening below this F [-].
        highest_factor: give up raising F above this (no failure: check the loads) [-].
        jump_ratio: d(u)/dF of the last step over that of the first that confirms a
            mechanism [-].
    """

    initial_increment: float = 0.05
    max_increment: float = 0.25
    tolerance: float = 0.005
    growth: float = 1.5
    strengthen: float = 0.5
    lowest_factor: float = 0.05
    highest_factor: float = 10.0
    jump_ratio: float = 10.0

    def __post_init__(self) -> None:
        for name in ("initial_increment", "max_increment", "tolerance", "lowest_factor",
                     "highest_factor", "jump_ratio"):
            value = getattr(self, name)
            if not (isinstance(value, int | float) and np.isfinite(value) and value > 0):
                raise ValueError(f"StrengthSearch.{name} = {value!r} must be a number > 0")
        if not self.tolerance <= self.initial_increment <= self.max_increment:
            raise ValueError("StrengthSearch: need tolerance <= initial_increment <= "
                             f"max_increment, got {self.tolerance}, {self.initial_increment}, "
                             f"{self.max_increment}")
        if not 1.0 <= self.growth <= 4.0:
            raise ValueError(f"StrengthSearch.growth = {self.growth} must be in [1, 4]")
        if not 0.0 < self.strengthen < 1.0:
            raise ValueError(f"StrengthSearch.strengthen = {self.strengthen} must be in (0, 1)")
        if self.lowest_factor >= 1.0 or self.highest_factor <= 1.0:
            raise ValueError("StrengthSearch: need lowest_factor < 1 < highest_factor")


@dataclass
class SafetyResult:
    """The factor of safety, how it was found and the state at it.

    Attributes:
        factor: F, the last strength factor with equilibrium [-].
        bracket: (F, the failed factor just above it).
        start: the strength factor the continuation started from (below 1 when the
            self-weight needed stronger materials).
        gravity_attempts: (strength factor, fraction of the self-weight carried) of each
            switch-on (empty when the search started from the caller's state).
        trials: (factor, equilibrium found, Newton iterations) of every step tried.
        curve: (factor, monitored displacement [m]) of the converged steps, from the start
            (one point only when no increase of F converged: F is then a lower bound).
        displacement_jump: d(u)/dF of the last converged step over that of the first.
        mechanism_confirmed: ``displacement_jump`` reached the search's ``jump_ratio``.
        monitor: what the displacement of ``curve`` is, in words.
        state: the converged state at F (reduced strengths in force).
        mechanism: displacement increment of the last converged step (what moves when
            strength is lost), dof values of ``state.u``'s space [m].
    """

    factor: float
    bracket: tuple[float, float]
    start: float
    gravity_attempts: list[tuple[float, float]] = field(default_factory=list)
    trials: list[tuple[float, bool, int]] = field(default_factory=list)
    curve: list[tuple[float, float]] = field(default_factory=list)
    displacement_jump: float = 1.0
    mechanism_confirmed: bool = False
    monitor: str = ""
    state: ContinuumState | None = None
    mechanism: np.ndarray | None = None

    @property
    def below_one(self) -> bool:
        """True when the structure cannot stand at the strengths given (F < 1)."""
        return self.factor < 1.0

    def as_dict(self) -> dict[str, Any]:
        """The figures for a summary (no arrays, no state)."""
        return {"F": self.factor, "bracket": list(self.bracket), "below_one": self.below_one,
                "start_factor": self.start, "converged_steps": len(self.curve) - 1,
                "gravity_attempts": [{"strength_factor": f, "weight_carried": w}
                                     for f, w in self.gravity_attempts],
                "trials": [{"F": f, "equilibrium": ok, "iterations": it}
                           for f, ok, it in self.trials],
                "curve": {"F": [c[0] for c in self.curve],
                          "displacement_m": [c[1] for c in self.curve]},
                "monitor": self.monitor, "displacement_jump": self.displacement_jump,
                "mechanism_confirmed": self.mechanism_confirmed,
                "criterion": "no equilibrium for an increase of F below the tolerance from "
                             "the newest converged state; cross-checked by the jump of the "
                             "monitored displacement"}


def factor_of_safety(solver: PlasticSolver, *, search: StrengthSearch | None = None,
                     gravity_steps: int | None = None,
                     monitor_point: tuple[float, float] | None = None) -> SafetyResult:
    """Strength-reduction factor of safety (continuation; module docstring).

    Without ``gravity_steps`` the search starts from the solver's converged state at its
    strength factor (e.g. after a completed stage); with it, the solver must be unloaded and
    the search switches the self-weight on itself (F < 1 found by strengthening). The solver
    is left at the converged state at F. ``monitor_point``: the displacement of this point
    is the monitored one (default: the largest nodal displacement).

    Raises :class:`~hybrid.errors.StageIncomplete` when the start has no equilibrium, the
    weight cannot be carried even at ``lowest_factor``, or no failure is found below
    ``highest_factor``.
    """
    search = search or StrengthSearch()
    attempts: list[tuple[float, float]] = []
    if gravity_steps is not None:
        attempts = _carry_self_weight(solver, gravity_steps, search)
    elif solver.step() is None:
        raise StageIncomplete(
            f"strength search: no equilibrium at the starting strength factor "
            f"{solver.strength_factor:g}; start it from a converged stage (or give "
            "gravity_steps to let it switch the self-weight on)")
    start = solver.strength_factor
    monitor, described = _monitor(solver, monitor_point)
    curve = [(start, 0.0)]
    trials: list[tuple[float, bool, int]] = []
    control = IncrementControl(search.initial_increment, search.max_increment,
                               0.5 * search.tolerance, search.growth)
    # before a failure is accepted: smaller increases, then larger ones, from the same state
    confirmations = ([search.tolerance / 4.0, search.tolerance / 8.0]
                     + [search.tolerance * 2.0**k for k in range(1, 8)
                        if search.tolerance * 2.0**k <= search.initial_increment])
    before = solver.u.x.array.copy()
    failed = np.inf
    pending: list[float] = []
    bar = progress("strength search", unit="trial")
    while True:
        confirming = bool(pending)
        size = pending.pop(0) if confirming else control.size
        trial = solver.strength_factor * (1.0 + size)
        if trial > search.highest_factor:
            bar.close()
            raise StageIncomplete(
                f"strength search: equilibrium up to F = {solver.strength_factor:.4g}, no "
                f"failure below F = {search.highest_factor:g}: check the loads and supports "
                "(or raise StrengthSearch.highest_factor)")
        u_before = solver.u.x.array.copy()
        iterations = solver.iterations_total
        record = solver.step(strength_factor=trial)
        trials.append((trial, record is not None, solver.iterations_total - iterations))
        bar.update(len(trials), F=solver.strength_factor)
        if record is None:
            if not confirming:
                failed = trial
                if not control.cut():
                    # confirmations beyond the range searched are not tried
                    pending = [c for c in confirmations if solver.strength_factor * (1.0 + c)
                               <= search.highest_factor]
                    if not pending:
                        break
            elif not pending:
                break  # every confirmation failed: the failure stands
            continue
        if confirming:  # a confirmation converged: the failure was numerical
            control.size = size
            failed = np.inf
        pending = []
        before = u_before
        curve.append((trial, monitor()))
        control.grow()
    bar.close()
    F = solver.strength_factor
    jump = _jump(curve)
    log.info("factor of safety %.4g (bracket %.4g, %d trials)", F, failed, len(trials))
    return SafetyResult(F, (F, failed), start, attempts, trials, curve, jump,
                        jump >= search.jump_ratio, described, solver.state(),
                        solver.u.x.array - before)


def _carry_self_weight(solver: PlasticSolver, steps: int,
                       search: StrengthSearch) -> list[tuple[float, float]]:
    """Switch the self-weight on, strengthening until it is carried; the attempts made."""
    if solver.gravity_factor != 0.0:
        raise ValueError("factor_of_safety(gravity_steps=...) needs a solver without "
                         f"self-weight yet (gravity factor {solver.gravity_factor:g})")
    unloaded = solver.snapshot()
    attempts = []
    while True:
        # whether the weight is carried matters, not the fraction: 1/64 of a step at least
        analysis = solver.apply_gravity(steps, min_increment=1.0 / 64.0)
        attempts.append((solver.strength_factor, analysis.factor))
        if analysis.completed:
            return attempts
        weaker = solver.strength_factor
        if weaker * search.strengthen < search.lowest_factor:
            raise StageIncomplete(
                f"self-weight carried up to {100 * analysis.factor:.0f} % even with the "
                f"strengths divided by F = {weaker:.3g}: F < {weaker:.3g} (below the lowest "
                f"factor searched, {search.lowest_factor:g}); check the strengths, the "
                "geometry and the supports")
        log.info("self-weight carried up to %.0f %% at F = %.3g: strengths multiplied up",
                 100 * analysis.factor, weaker)
        solver.restore(unloaded)
        solver.set_strength_factor(weaker * search.strengthen)


def _jump(curve: list[tuple[float, float]]) -> float:
    """d(u)/dF of the last converged step over that of the first."""
    return runaway_ratio([c[0] for c in curve], [c[1] for c in curve])


def _monitor(solver: PlasticSolver, point: tuple[float, float] | None) -> tuple[Any, str]:
    """A function returning the monitored displacement [m] since now, and its description."""
    u0 = solver.u.x.array.copy()
    if point is not None:
        p = np.array([point], dtype=float)
        start = evaluate(solver.u, p)[0]

        def at_point() -> float:
            return float(np.linalg.norm(evaluate(solver.u, p)[0] - start))

        return at_point, f"|u| at ({point[0]:g}, {point[1]:g}) since the search started"
    comm = solver.u.function_space.mesh.comm

    def largest() -> float:
        return largest_nodal_norm(solver.u.x.array - u0, comm)

    return largest, "largest nodal |u| since the search started"
