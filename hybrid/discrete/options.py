"""The settings and the result record of a discrete run, and the settings as checkpoints save them.

:class:`RunOptions` (physics and numerics: time step, damping, splitting, contact, element
formulation) is fixed for an :class:`~hybrid.discrete.solver.ExplicitSolver`'s lifetime;
:class:`RunResult` is what one run returns, with its energy history under ``HISTORY_KEYS``.
:func:`settings_text` writes settings as sorted JSON into a checkpoint and
:func:`require_same_settings` refuses to resume a checkpoint with other settings, naming the
fields that differ. ``RESULT_NUMBERS`` are the numbers of a :class:`RunResult` a checkpoint
saves, in order.
"""

from __future__ import annotations

import bisect
import math
from collections.abc import Sequence
from dataclasses import dataclass, field, fields
from pathlib import Path
from typing import Any

import numpy as np

from hybrid.discrete.ledger import EnergyLedger
from hybrid.io import Check

__all__ = ["HISTORY_KEYS", "REST_DRIFT", "REST_WINDOW", "RESULT_NUMBERS", "RunOptions",
           "RunResult", "drift_ratio", "require_same_settings", "settings_text"]

#: keys of ``RunResult.history`` (the ledger's terms between time/step and residual)
HISTORY_KEYS = ("time", "step", *(f.name for f in fields(EnergyLedger)), "residual")

#: the last fraction of a run over which :func:`drift_ratio` measures the rate of work [-]
REST_WINDOW = 0.1
#: default largest :func:`drift_ratio` at rest: at its last rate, running as long again would
#: add at most 1 % to the work the loads and supports did in the run [-]
REST_DRIFT = 0.01


def drift_ratio(time: Sequence[float] | np.ndarray, loads: Sequence[float] | np.ndarray,
                supports: Sequence[float] | np.ndarray, floor: float) -> float:
    """How far a run is from having stopped moving, by the work of its loads [-].

    The work of the loads and supports over the last ``REST_WINDOW`` of the run's checks,
    extrapolated at that rate to the run's whole duration, over the work done in the run
    (at least ``floor``). A mass creeping under mass damping has little kinetic energy but
    gravity still works on it, so this ratio stays large where the kinetic-energy ratio
    already reads rest. A vibration about the rest position counts too, by the work its
    amplitude exchanges with gravity: up to about 20 times that amplitude over the run's
    work (1 % for an amplitude of 5e-4 of it), so a lightly damped run also waits for its
    vibration to die down. A steady driver (a support pushed at a constant speed, a load
    that keeps rising) keeps the ratio near 1: such a run never reads rest. Time and work are
    a run's history at its checks (the first check is the start of the measure).

    Args:
        time: the checks' times, increasing [s].
        loads: W_loads at the checks [kJ/m].
        supports: W_supports at the checks [kJ/m].
        floor: smallest denominator [kJ/m] (the run's peak kinetic energy: a run in which
            nothing is driven).
    """
    n = len(time)
    if n < 2:
        return math.inf
    t_end, t_start = time[-1], time[0]
    duration = t_end - t_start
    if not duration > 0.0:
        return math.inf
    i = min(bisect.bisect_right(time, t_end - REST_WINDOW * duration), n - 2)
    window = t_end - time[i]
    end = loads[-1] + supports[-1]
    done = abs(end - loads[0] - supports[0])
    return (abs(end - loads[i] - supports[i]) * (duration / window)
            / max(done, floor, 1e-300))


@dataclass(frozen=True, kw_only=True)
class RunOptions:
    """Physics and numerics of an :class:`ExplicitSolver`, fixed for its lifetime.

    Attributes:
        dt: time step [s]; None reuses ``state.dt`` (a continued state) or takes
            ``integrate.default_dt``: ``safety`` times the time-step scale
            (``integrate.stable_time_step``), at most 0.9 times the critical step
            (``integrate.critical_time_step``), and with contact at most 0.95 times the
            damped contacts' limit (``integrate.damped_contact_step``). A dt above the
            critical step, or one given here or continued above the damped contacts' limit,
            is refused.
        safety: fraction of the time-step scale when dt is None, in (0, 1] [-] (the critical
            step and the damped contacts' limit may take the step lower).
        mass_damping: alpha of the mass-proportional damping C = alpha M [1/s] (thesis eq
            3.12), >= 0.
        local_damping: Cundall's local non-viscous damping d in [0, 1) [-] (quasi-static
            phases).
        bbar: Q4 with the mean-dilatation B-bar (True, no volumetric locking) or full 2x2
            integration (False, as dolfinx Q1).
        plastic_strain_cap: expert option for materials without softening: a Gauss point
            whose accumulated plastic strain reaches it responds elastically from then on [-]
            (None: no cap), so that a perfectly plastic element flowing without end does not
            turn inside out. No shipped case needs it: an element distorted as far as an
            element can follow parts from its neighbours (``ties.DISTORTION_LIMIT``).
        split_every: check the interfaces for failure and split every N steps (0: never).
        split_plastic_strain: expert option for materials without softening: interfaces
            also fail where the adjacent Gauss points' mean plastic strain exceeds it [-]
            (None: the strength criteria and softening only, see ``ties``).
        contact: contact detection and forces; None: on when ``hybrid.discrete.contact``
            exists and there are several bodies or splitting.
        contact_refresh: steps between contact-pair searches (also after each splitting
            check).
        margin_factor: search margin of the pair search, this times the largest speed times
            ``contact_refresh`` dt [-].
        contact_bounds: (xmin, ymin, xmax, ymax) [m] of the contact grid; an element leaving
            them stops the run with a ValueError (None: the bounds of the elements).
        contact_hinges: also take as contact candidates the element pairs still tied at a
            single vertex (``find_contact_pairs(..., hinges=True)``): after a partial split
            two elements whose common edge failed rotate about that vertex and otherwise
            interpenetrate without any contact force, then repel with a deep overlap when the
            last tie fails (the retaining-wall collapse gained ~1 600 kJ/m through the normal
            contact forces by t = 0.2 s without it, 0.006 kJ/m with it).
    """

    dt: float | None = None
    safety: float = 0.5
    mass_damping: float = 0.0
    local_damping: float = 0.0
    bbar: bool = True
    plastic_strain_cap: float | None = None
    split_every: int = 0
    split_plastic_strain: float | None = None
    contact: bool | None = None
    contact_refresh: int = 10
    margin_factor: float = 2.0
    contact_bounds: tuple[float, float, float, float] | None = None
    contact_hinges: bool = True

    def __post_init__(self) -> None:
        """Refuse bad values with the option's name and the fix."""
        if self.dt is not None and not (math.isfinite(self.dt) and self.dt > 0.0):
            raise ValueError(f"dt = {self.dt!r}: must be a finite positive number [s] (None: "
                             "safety x the time-step scale)")
        if not 0.0 < self.safety <= 1.0:
            raise ValueError(f"safety = {self.safety!r}: must be in (0, 1] (a fraction of the "
                             "time-step scale)")
        if not (math.isfinite(self.mass_damping) and self.mass_damping >= 0.0):
            raise ValueError(f"mass_damping = {self.mass_damping!r}: alpha must be >= 0 [1/s]")
        if not 0.0 <= self.local_damping < 1.0:
            raise ValueError(f"local_damping = {self.local_damping!r}: must be in [0, 1)")
        if self.plastic_strain_cap is not None and not self.plastic_strain_cap > 0.0:
            raise ValueError(f"plastic_strain_cap = {self.plastic_strain_cap!r}: must be > 0 "
                             "(None: no cap)")
        if self.split_plastic_strain is not None and not self.split_plastic_strain > 0.0:
            raise ValueError(f"split_plastic_strain = {self.split_plastic_strain!r}: must be "
                             "> 0 (None: strength criteria only)")
        for name in ("split_every", "contact_refresh"):
            val = getattr(self, name)
            if int(val) != val or val < 0:
                raise ValueError(f"{name} = {val!r}: must be an integer >= 0")
        if not (math.isfinite(self.margin_factor) and self.margin_factor >= 0.0):
            raise ValueError(f"margin_factor = {self.margin_factor!r}: must be >= 0")
        b = self.contact_bounds
        if b is not None and not (len(b) == 4 and b[0] < b[2] and b[1] < b[3]):
            raise ValueError(f"contact_bounds = {b!r}: must be (xmin, ymin, xmax, ymax) with "
                             "xmin < xmax and ymin < ymax [m]")


@dataclass
class RunResult:
    """What :meth:`ExplicitSolver.run` returns: why it stopped, counts and the energy history.

    ``history`` holds one entry per check (and one at the end) under the keys
    ``HISTORY_KEYS``: time [s], step, the :class:`EnergyLedger` terms [kJ/m] and the residual
    since the start of this run [kJ/m]; ``start`` is the ledger when the run began (its works
    are totals since the state was made: a continued run's supply counts from it,
    :mod:`hybrid.discrete.energy`).
    """

    stop_reason: str  # "time", "steps", "rest" or "callback"
    steps: int  # steps taken by this run
    time: float  # state time at the end [s]
    dt: float  # time step [s]
    wall_time: float  # [s]
    element_steps_per_s: float
    n_split: int  # interfaces broken during this run
    history: dict[str, np.ndarray] = field(default_factory=dict)  # energy ledger per check
    phase: str = ""  # the run's name in the outputs
    peak_kinetic: float = 0.0  # largest kinetic energy at the start and the checks [kJ/m]
    start: dict[str, float] = field(default_factory=dict)  # EnergyLedger at the start [kJ/m]

    @property
    def rest_ratio(self) -> float:
        """E_kin / max(peak E_kin, E_strain) at the end [-]: the measure of ``until_rest``.

        A run stopped at rest has it at most ``until_rest``; the same number is the rest
        check of a case, so that the check and the stop never disagree.
        """
        h = self.history
        if not len(h.get("kinetic", ())):
            raise ValueError("rest_ratio: the run has no energy history")
        kin, strain = float(h["kinetic"][-1]), float(h["strain"][-1])
        return kin / max(self.peak_kinetic, kin, strain, 1e-300)

    @property
    def drift_ratio(self) -> float:
        """:func:`drift_ratio` of the run's history: the other measure of ``until_rest``.

        A run stopped at rest has it at most its ``rest_drift``.
        """
        h = self.history
        if len(h.get("time", ())) < 2:
            raise ValueError("drift_ratio: the run has fewer than two checks")
        return drift_ratio(h["time"], h["work_loads"], h["work_supports"], self.peak_kinetic)

    def rest_checks(self, rest: float, rest_drift: float = REST_DRIFT) -> dict[str, Check]:
        """The two measures of rest as checks, on the bars the run stopped on.

        ``rest_kinetic_ratio`` (:attr:`rest_ratio` at most ``rest``) and ``rest_drift_ratio``
        (:attr:`drift_ratio` at most ``rest_drift``): a run stopped at rest passes both, a
        run cut by its time or step limit while creeping fails the second.
        """
        return {"rest_kinetic_ratio": Check(self.rest_ratio, 0.0, rest, "-",
                                            "at rest: E_kin / max(peak E_kin, E_strain)"),
                "rest_drift_ratio": Check(self.drift_ratio, 0.0, rest_drift, "-",
                                          "at rest: work of the loads over the last tenth "
                                          "of the run, at that rate over the whole run, / "
                                          "their work in the run")}

    @property
    def ending(self) -> str:
        """How the run ended, for figure titles.

        "At rest (t = 1.1 s)" only when it stopped at rest, else "Not at rest: stopped by
        <reason> (t = ... s)".
        """
        at = f"t = {self.time:.3g} s"
        if self.stop_reason == "rest":
            return f"At rest ({at})"
        reason = {"time": "the time limit", "steps": "the step limit"}.get(self.stop_reason,
                                                                          self.stop_reason)
        return f"Not at rest: stopped by {reason} ({at})"


RESULT_NUMBERS = ("steps", "time", "dt", "wall_time", "element_steps_per_s", "n_split",
                  "peak_kinetic")


def settings_text(settings: Any) -> str:
    """A dataclass's fields as sorted JSON (what a checkpoint records of its settings)."""
    import dataclasses
    import json

    values = settings if isinstance(settings, dict) else dataclasses.asdict(settings)
    return json.dumps(values, sort_keys=True, default=repr)


def require_same_settings(path: str | Path, what: str, saved: Any, now: Any) -> None:
    """Refuse to resume checkpoint ``path`` with other ``what`` than it was written with.

    The message names the fields that differ. ``saved``: the checkpoint's
    :func:`settings_text` (None: not recorded, nothing to compare).
    """
    import json

    if saved is None:
        return
    old, new = json.loads(str(saved)), json.loads(settings_text(now))
    changed = sorted(k for k in old.keys() | new.keys() if old.get(k) != new.get(k))
    if changed:
        raise ValueError(
            f"checkpoint {path} was written with other {what}: "
            + ", ".join(f"{k} = {old.get(k)!r} then, {new.get(k)!r} now" for k in changed)
            + "; resume with the same values, or start again with --overwrite")
