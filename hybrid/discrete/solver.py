"""The explicit solver of the discrete engine: one step, and runs to a time, a step count or rest.

Orchestration only (no math here). :meth:`ExplicitSolver.step` calls the kernels in order:
contact refresh (``contact.find_contact_pairs`` every ``contact_refresh`` steps and after each
splitting check), contact forces (``contact.forces.add_contact_forces``), the explicit update
(``integrate.step``: tie groups, central differences, element stresses and internal forces),
the contact terms of the energy ledger (``contact.mid_step_work``, see
``hybrid.discrete.ledger``) and, every ``split_every`` steps, interface failure and splitting
(``ties``). :meth:`ExplicitSolver.run` only loops and checks: every ``check_every`` steps it
measures the ledger, stops an unstable run, records the history, detects rest and calls the
observers and ``on_check``.

The settings are split in two. :class:`RunOptions` (physics and numerics: time step,
damping, splitting, contact, element formulation) is fixed for the solver's lifetime, so one
solver is one consistent model. The arguments of :meth:`ExplicitSolver.run` say when one run
stops and how it is watched (``until_time``, ``max_steps``, ``until_rest`` with
``rest_min_steps``, ``check_every``, ``on_check``); several runs of one solver continue each
other (a loading phase, then a rest phase). Outputs (time series, frames, checkpoints,
progress bars) are :class:`Observer` objects of the output layer
(``hybrid.discrete.outputs``) attached to the solver for its lifetime; closing the solver
(:meth:`ExplicitSolver.close` or a ``with`` block) closes them.
"""

from __future__ import annotations

import logging
import math
import time as _time
import warnings
from collections.abc import Callable, Iterable
from dataclasses import dataclass, field, fields
from pathlib import Path
from typing import Any

import numpy as np

from hybrid.constitutive.softening import warn_snap_back
from hybrid.constitutive.table import SOFTENING_DISPLACEMENT
from hybrid.discrete import integrate, ties
from hybrid.discrete.ledger import EnergyLedger
from hybrid.discrete.state import (
    LEDGER_CONTACT_DAMPING,
    LEDGER_CONTACT_NORMAL,
    LEDGER_FRICTION,
    DiscreteState,
    read_checkpoint,
)
from hybrid.errors import RunUnstable

__all__ = ["RunOptions", "ExplicitSolver", "Observer", "RunResult", "run",
           "has_contact_module"]

log = logging.getLogger(__name__)

#: keys of ``RunResult.history`` (the ledger's terms between time/step and residual)
HISTORY_KEYS = ("time", "step", *(f.name for f in fields(EnergyLedger)), "residual")


def has_contact_module() -> bool:
    """True when ``hybrid.discrete.contact`` can be imported."""
    try:
        import hybrid.discrete.contact  # noqa: F401
    except ImportError:
        return False
    return True


@dataclass(frozen=True, kw_only=True)
class RunOptions:
    """Physics and numerics of an :class:`ExplicitSolver`, fixed for its lifetime.

    Attributes:
        dt: time step [s]; None reuses ``state.dt`` (a continued state) or takes ``safety``
            times the stable step. A dt above the stable step is refused.
        safety: fraction of the stable time step when dt is None, in (0, 1] [-].
        mass_damping: alpha of the mass-proportional damping C = alpha M [1/s] (thesis eq
            3.12), >= 0.
        local_damping: Cundall's local non-viscous damping d in [0, 1) [-] (quasi-static
            phases).
        bbar: Q4 with the mean-dilatation B-bar (True, no volumetric locking) or full 2x2
            integration (False, as dolfinx Q1).
        plastic_strain_cap: expert option for materials without softening: a Gauss point
            whose accumulated plastic strain reaches it responds elastically from then on [-]
            (None: no cap), so that a perfectly plastic element flowing without end does not
            turn inside out. With softening materials none is needed: an element beside a
            failed bond stops yielding at its residual (``ties.band_plastic_cap``).
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
                             "safety x the stable time step)")
        if not 0.0 < self.safety <= 1.0:
            raise ValueError(f"safety = {self.safety!r}: must be in (0, 1] (a fraction of the "
                             "stable time step)")
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
    since the start of this run [kJ/m].
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


_RESULT_NUMBERS = ("steps", "time", "dt", "wall_time", "element_steps_per_s", "n_split",
                   "peak_kinetic")


@dataclass
class _Progress:
    """A run in progress: everything that decides its future, saved in checkpoints."""

    call: str  # the run's arguments (a resumed solver must be called the same way)
    phase: str  # name of the run in the outputs
    n_total: int | None  # steps of the run when bounded
    external: bool  # loads were non-zero when the run started
    led0: EnergyLedger  # ledger at the start of the run
    monitor: _Monitor
    split0: int  # ``ExplicitSolver.n_split`` at the start
    k: int = 0  # steps done
    peak_ke: float = 0.0  # peak kinetic energy of the run (rest detection) [kJ/m]
    hist: dict[str, list[float]] = field(
        default_factory=lambda: {k: [] for k in HISTORY_KEYS})
    callback: dict[str, np.ndarray] = field(default_factory=dict)  # on_check's, when resumed

    def arrays(self, prefix: str) -> dict[str, np.ndarray]:
        """The progress as named arrays (no pickle)."""
        out = {f"{prefix}call": np.array(self.call), f"{prefix}phase": np.array(self.phase),
               f"{prefix}numbers": np.array([
                   -1 if self.n_total is None else self.n_total, int(self.external),
                   self.split0, self.k], dtype=np.int64),
               f"{prefix}peak_ke": np.array(self.peak_ke),
               f"{prefix}led0": np.array(list(self.led0.as_dict().values())),
               f"{prefix}monitor": self.monitor.state()}
        out.update({f"{prefix}hist.{k}": np.array(v, dtype=float) for k, v in self.hist.items()})
        return out

    @classmethod
    def from_arrays(cls, a: dict[str, np.ndarray], prefix: str, state: DiscreteState,
                    dt: float, contact: bool | None = None) -> _Progress:
        """The progress saved by :meth:`arrays`."""
        n_total, external, split0, k = (int(v) for v in a[f"{prefix}numbers"])
        led0 = EnergyLedger(*(float(v) for v in a[f"{prefix}led0"]))
        monitor = _Monitor(state, led0, dt, contact)
        monitor.restore(a[f"{prefix}monitor"])
        return cls(call=str(a[f"{prefix}call"]), phase=str(a[f"{prefix}phase"]),
                   n_total=None if n_total < 0 else n_total, external=bool(external),
                   led0=led0, monitor=monitor, split0=split0, k=k,
                   peak_ke=float(a[f"{prefix}peak_ke"]),
                   hist={key: [float(v) for v in a[f"{prefix}hist.{key}"]]
                         for key in HISTORY_KEYS},
                   callback=_prefixed(a, f"{prefix}on_check."))


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


def _prefixed(arrays: dict[str, np.ndarray], prefix: str) -> dict[str, np.ndarray]:
    """The entries of ``arrays`` under ``prefix``, the prefix removed."""
    return {k[len(prefix):]: v for k, v in arrays.items() if k.startswith(prefix)}


def _callback_state(on_check: Any) -> dict[str, np.ndarray]:
    """The state of a stateful ``on_check`` (one with ``state()``/``restore()``), else {}."""
    state = getattr(on_check, "state", None)
    return {k: np.asarray(v) for k, v in state().items()} if callable(state) else {}


def _restore_callback(on_check: Any, saved: dict[str, np.ndarray]) -> None:
    """Give a resumed run's ``on_check`` the state it had in the checkpoint."""
    if not saved:
        return
    restore = getattr(on_check, "restore", None)
    if not callable(restore):
        raise ValueError("the checkpoint holds the state of this run's on_check: pass an "
                         "on_check with state()/restore() (as the interrupted script did)")
    restore(saved)


class Observer:
    """Something that watches a solver for its lifetime (outputs, progress): no-op hooks.

    Observers only read the state; they must not change it. ``files`` lists what the observer
    has written.
    """

    files: tuple[Path, ...] | list[Path] = ()

    def run_started(self, solver: ExplicitSolver, total_steps: int | None) -> None:
        """A run begins (``total_steps``: its step count when known)."""

    def stepped(self, solver: ExplicitSolver) -> None:
        """A step is done (not called for the step at which a run stopped at its check)."""

    def checked(self, solver: ExplicitSolver, ledger: EnergyLedger) -> None:
        """A check of the run (every ``check_every`` steps and at the last step)."""

    def run_ended(self, solver: ExplicitSolver, result: RunResult | None) -> None:
        """A run ended (``result`` None when it raised)."""

    def close(self, solver: ExplicitSolver, final: bool) -> None:
        """The solver is closed (``final``: normally, not after an error)."""

    def attached(self, solver: ExplicitSolver) -> None:
        """The solver is made (an output that resumes restores the solver here)."""

    def state(self) -> dict[str, np.ndarray]:
        """What decides the observer's future outputs, for the solver's checkpoints."""
        return {}

    def restore(self, saved: dict[str, np.ndarray]) -> None:
        """Continue from what :meth:`state` returned (the solver resumes a checkpoint)."""



def _warn_cap_before_residual(state: DiscreteState, cap: float) -> None:
    """Warn when ``plastic_strain_cap`` stops softening elements before their residual.

    A capped Gauss point responds elastically, so a softening element whose residual plastic
    strain u_r / (sqrt(3) h) lies above the cap never reaches residual, and the interfaces
    beside it never fail as softened.
    """
    u_r = state.material_table[state.element_material, SOFTENING_DISPLACEMENT]
    soft = u_r > 0.0
    if not math.isfinite(cap) or not soft.any():
        return
    kappa_r = u_r[soft] / (math.sqrt(3.0) * state.element_length[soft])
    if float(kappa_r.max()) > cap:
        warnings.warn(f"plastic_strain_cap = {cap:g} is below the residual plastic strain of "
                      f"{int((kappa_r > cap).sum())} softening elements (up to "
                      f"{float(kappa_r.max()):.3g}): they stop yielding before residual and "
                      "never split as softened; leave the cap unset (None) with softening",
                      UserWarning, stacklevel=3)


class ExplicitSolver:
    """Explicit dynamics of a :class:`DiscreteState` (advanced in place) with fixed options.

    Construction resolves and checks dt, decides on contact and owns the step's work arrays
    (no allocation per step). :meth:`step` advances one step; :meth:`run` loops. Observers
    (``hybrid.discrete.outputs``) are attached for the solver's lifetime, so that one time
    series covers all its runs; use the solver in a ``with`` block or call :meth:`close`.
    """

    def __init__(self, state: DiscreteState, options: RunOptions | None = None, *,
                 observers: Iterable[Observer] = ()) -> None:
        """Set up the solver of ``state`` (see the class docstring)."""
        self.state = state
        self.options = o = options if options is not None else RunOptions()
        self.observers: list[Observer] = list(observers)
        contact = o.contact
        if contact is None:
            contact = has_contact_module() and (o.split_every > 0 or _n_bodies(state) > 1)
        self.contact = bool(contact)
        if self.contact:
            try:
                from hybrid.discrete import contact as cmod
                from hybrid.discrete.contact.forces import ContactBuffers, add_contact_forces
            except ImportError as err:
                raise ValueError("contact=True but hybrid.discrete.contact is not available"
                                 ) from err
            self._cmod = cmod
            self._add_contact_forces = add_contact_forces
        dt = o.dt
        if dt is None:
            dt = state.dt if state.dt > 0.0 else o.safety * integrate.stable_time_step(
                state, contact=self.contact)
        integrate.check_dt(state, float(dt), contact=self.contact)
        self.dt = float(dt)
        state.dt = self.dt
        if not state.primed:
            integrate.prime(state)
        self.steps = 0  # steps over the solver's lifetime
        self.n_split = 0  # interfaces broken over the solver's lifetime
        self.active_contacts = 0  # contact pairs in contact at the last step with pairs
        self._cap = math.inf if o.plastic_strain_cap is None else float(o.plastic_strain_cap)
        _warn_cap_before_residual(state, self._cap)
        warn_snap_back(state.element_length, state.element_material, state.material_table)
        self._split_limit = (math.inf if o.split_plastic_strain is None
                             else o.split_plastic_strain)
        self._split_every = int(o.split_every)
        self._refresh = max(int(o.contact_refresh), 1)
        self._closed = False
        self._done: list[tuple[str, RunResult]] = []  # runs that ended: (call, result)
        self._replay: list[tuple[str, RunResult]] = []  # of a checkpoint, not yet called again
        # the state of each ended run's on_check at its end (stateful callbacks only), the
        # same of the checkpoint's runs not yet called again, and the running one's on_check
        self._done_callbacks: list[dict[str, np.ndarray]] = []
        self._replay_callbacks: list[dict[str, np.ndarray]] = []
        self._on_check: Any = None
        self._run: _Progress | None = None  # the run in progress
        self._resumed: _Progress | None = None  # of a checkpoint, to continue
        # work arrays of the step, reused: contact force, its damping and tangential parts and
        # the start-of-step velocity (for the ledger), the contact loop's buffers
        # (empty without contact)
        n_work = state.x.shape[0] if self.contact else 0
        self._cforce: np.ndarray = np.zeros((n_work, 2))
        self._split: np.ndarray = np.zeros((2, n_work, 2))
        self._v_start: np.ndarray = np.zeros((n_work, 2))
        self._cbuf: Any = ContactBuffers() if self.contact else None
        self._begin()
        for obs in self.observers:
            obs.attached(self)

    # -- one step ----------------------------------------------------------------------------
    def _begin(self) -> None:
        """Read what may have changed since the last run: loads, supports, masses, splits."""
        st = self.state
        self._external = bool(np.any(st.external_force))
        self._point_cap = ties.band_plastic_cap(st, self._cap)
        self._n_failed = int(np.count_nonzero(~st.interface_intact))  # that the cap is of
        mass_tot = float(np.sum(st.mass))
        # floor of the contact search margin [m]
        self._margin_floor = 1e-6 * math.sqrt(mass_tot / float(st.density.max()))
        self._cmass: np.ndarray = (
            self._cmod.rigid_contact_mass(st.mass, st.fixed, st.element_nodes) if self.contact
            else np.zeros(0))

    def step(self) -> None:
        """Advance the state by one step: contacts, forces, update, ledger, splitting."""
        st, o, dt = self.state, self.options, self.dt
        n_pairs = 0
        if self.contact:
            cmod = self._cmod
            # refresh on schedule, and after each splitting check (new free edges)
            if st.step % self._refresh == 0 or (self._split_every
                                                and st.step % self._split_every == 0):
                if not (np.isfinite(st.x).all() and np.isfinite(st.v).all()):
                    _raise_non_finite(st, dt, self.contact)
                vmax = float(np.max(np.abs(st.v))) if st.n_nodes else 0.0
                margin = o.margin_factor * vmax * self._refresh * dt
                margin = max(margin, self._margin_floor)
                pairs = cmod.find_contact_pairs(st.x, st.element_nodes, st.node_group, margin,
                                                o.contact_bounds, hinges=o.contact_hinges)
                st.contact_shear = cmod.carry_contact_history(st.contact_pairs,
                                                              st.contact_shear, pairs)
                st.contact_pairs = pairs
            self._cforce[:] = 0.0
            n_pairs = st.contact_pairs.shape[0]
            if n_pairs:
                self._split[:] = 0.0
                self._v_start[:] = st.v
                self.active_contacts = self._add_contact_forces(  # unchecked: state, dt and
                    st.x, st.v, self._cmass, st.element_nodes,  # pairs checked already
                    st.element_material, st.contact_table, st.contact_pairs, st.contact_shear,
                    dt, self._cforce, self._split, self._cbuf)[0]
        integrate.step(st, dt, mass_damping=o.mass_damping, local_damping=o.local_damping,
                       contact_force=self._cforce if self.contact else None, bbar=o.bbar,
                       external=self._external,
                       plastic_strain_cap=self._point_cap)
        if n_pairs:
            # minus the work of the tangential / damping / elastic normal forces on the
            # mid-step velocity
            cmod = self._cmod
            w_t = cmod.mid_step_work(self._split[1], self._v_start, st.v, dt)
            w_d = cmod.mid_step_work(self._split[0], self._v_start, st.v, dt)
            w_all = cmod.mid_step_work(self._cforce, self._v_start, st.v, dt)
            st.ledger[LEDGER_FRICTION] -= w_t
            st.ledger[LEDGER_CONTACT_DAMPING] -= w_d
            st.ledger[LEDGER_CONTACT_NORMAL] -= w_all - w_t - w_d
        if self._split_every and st.step % self._split_every == 0:
            modes = ties.check_interfaces(st, self._split_limit)
            if modes.any():
                self.n_split += ties.split_interfaces(st, modes > 0)
                self._point_cap = ties.band_plastic_cap(st, self._cap)
                self._n_failed = int(np.count_nonzero(~st.interface_intact))
        self.steps += 1

    @property
    def contact_force(self) -> np.ndarray:
        """(n_nodes, 2) contact force of the last step [kN/m] (zero without contact)."""
        return self._cforce if self.contact else np.zeros_like(self.state.x)

    def ledger(self) -> EnergyLedger:
        """The energy ledger of the state now."""
        return EnergyLedger.measure(self.state)

    # -- runs --------------------------------------------------------------------------------
    def run(self, *, until_time: float | None = None, max_steps: int | None = None,
            until_rest: float | None = None, check_every: int = 100,
            rest_min_steps: int = 200,
            on_check: Callable[[DiscreteState], bool | None] | None = None,
            phase: str | None = None) -> RunResult:
        """Advance the state until a time, a step count or rest, whichever comes first.

        Args:
            until_time: absolute state time to reach [s].
            max_steps: steps of this run at most.
            until_rest: stop when E_kin <= until_rest * max(peak E_kin of this run, E_strain)
                (checked every ``check_every`` steps after ``rest_min_steps``) [-].
            check_every: steps between checks: energy ledger, instability monitor, history,
                rest, observers' ``checked`` and ``on_check``.
            rest_min_steps: steps of this run before rest may stop it.
            on_check: called with the state at every check; it may change loads
                (``external_force``, load histories) and returns True to stop the run (stop
                reason "callback"). Loads are read as non-zero when the run starts.
            phase: the run's name in the outputs (animation titles; default "run N").

        A solver that resumed a checkpoint (:meth:`restore`) returns the saved results of
        the runs that had ended before it and continues the run it was in, so that calling
        the same runs again ends bit for bit as the uninterrupted solver.

        Returns:
            Why and where the run stopped, with the ledger history of its checks.

        Raises:
            ValueError: no stopping criterion, or a bad one; non-finite gravity, loads,
                prescribed velocities or masses; a tie group free to move without mass.
            RuntimeError: the run turned unstable (non-finite numbers, mechanical energy
                above ``RUNAWAY_MARGIN`` times its sources, elements distorted below the
                stable step); the message names the likeliest cause.
        """
        if until_time is None and max_steps is None and until_rest is None:
            raise ValueError("give at least one of until_time, max_steps, until_rest")
        if max_steps is not None and (int(max_steps) != max_steps or max_steps < 0):
            raise ValueError(f"max_steps = {max_steps!r}: must be an integer >= 0")
        if until_rest is not None and not until_rest > 0.0:
            raise ValueError(f"until_rest = {until_rest!r}: must be a positive energy ratio")
        if until_time is not None and not math.isfinite(until_time):
            raise ValueError(f"until_time = {until_time!r}: must be a finite time [s]")
        for name, val in (("check_every", check_every), ("rest_min_steps", rest_min_steps)):
            if int(val) != val or val < 0:
                raise ValueError(f"{name} = {val!r}: must be an integer >= 0")
        if self._closed:
            raise RuntimeError("this solver is closed: make a new ExplicitSolver")
        check_every = max(int(check_every), 1)
        phase = phase if phase is not None else f"run {len(self._done) + 1}"
        call = repr((until_time, max_steps, until_rest, check_every, rest_min_steps, phase))
        if self._replay:  # a run that had ended before the checkpoint
            saved_call, result = self._replay.pop(0)
            self._check_call(saved_call, call)
            saved = self._replay_callbacks.pop(0)
            _restore_callback(on_check, saved)
            self._done.append((saved_call, result))
            self._done_callbacks.append(saved)
            return result
        st, dt = self.state, self.dt
        fault = _input_fault(st)
        if fault is not None:
            raise ValueError(f"discrete run refused: {fault}")
        integrate.check_dt(st, dt, contact=self.contact)
        if not st.primed:
            integrate.prime(st)
        self._begin()
        r = self._resumed
        if r is not None:  # the run the checkpoint was taken in
            self._resumed = None
            self._check_call(r.call, call)
            _restore_callback(on_check, r.callback)
            self._external = r.external
        else:
            n_total = max_steps if max_steps is not None else None
            if until_time is not None:
                n_time = max(int(math.ceil((until_time - st.time) / dt - 1e-9)), 0)
                n_total = n_time if n_total is None else min(n_total, n_time)
            led0 = EnergyLedger.measure(st)
            r = _Progress(call=call, phase=phase, n_total=n_total, external=self._external,
                          led0=led0, monitor=_Monitor(st, led0, dt, self.contact),
                          split0=self.n_split,
                          peak_ke=led0.kinetic)
        self._run = r
        self._on_check = on_check
        n_total, monitor, hist, led0 = r.n_total, r.monitor, r.hist, r.led0
        stop = "steps"
        observers = self.observers
        for obs in observers:
            obs.run_started(self, None if n_total is None else n_total - r.k)
        k0 = r.k
        t0 = _time.perf_counter()
        try:
            while True:
                if n_total is not None and r.k >= n_total:
                    stop = "time" if (until_time is not None
                                      and st.time >= until_time - 0.5 * dt) else "steps"
                    break
                self.step()
                r.k += 1
                k = r.k
                if k % check_every == 0 or (n_total is not None and k == n_total):
                    if not (np.isfinite(st.x).all() and np.isfinite(st.v).all()):
                        _raise_non_finite(st, dt, self.contact)  # before the ledger reads x
                    led = EnergyLedger.measure(st)
                    monitor.check(st, led)
                    _check_distortion(st, dt, self.contact)
                    monitor.e_prev = led.mechanical
                    r.peak_ke = max(r.peak_ke, led.kinetic)
                    _record(hist, st, led, led0)
                    for obs in observers:
                        obs.checked(self, led)
                    if (until_rest is not None and k >= rest_min_steps
                            and led.kinetic <= until_rest * max(r.peak_ke, led.strain)):
                        stop = "rest"
                        break
                    if on_check is not None:
                        n_failed = self._n_failed
                        done = on_check(st)
                        if int(np.count_nonzero(~st.interface_intact)) != n_failed:
                            self._point_cap = ties.band_plastic_cap(st, self._cap)  # it split
                        if done:
                            stop = "callback"
                            break
                for obs in observers:
                    obs.stepped(self)
        except BaseException:
            self._run = None
            self._on_check = None
            for obs in observers:
                obs.run_ended(self, None)
            raise
        wall = _time.perf_counter() - t0
        if not hist["step"] or hist["step"][-1] != st.step:
            led = EnergyLedger.measure(st)
            monitor.check(st, led)
            r.peak_ke = max(r.peak_ke, led.kinetic)
            _record(hist, st, led, led0)
        k = r.k
        log.info("discrete run: %d steps, stop=%s, %.3g s wall", k, stop, wall)
        result = RunResult(stop_reason=stop, steps=k, time=st.time, dt=dt, wall_time=wall,
                           element_steps_per_s=(k - k0) * st.n_elements / wall if wall > 0
                           else 0.0,
                           n_split=self.n_split - r.split0,
                           history={kk: np.asarray(v) for kk, v in hist.items()}, phase=r.phase,
                           peak_kinetic=r.peak_ke)
        self._run = None
        self._done.append((call, result))
        self._done_callbacks.append(_callback_state(on_check))
        self._on_check = None
        for obs in observers:
            obs.run_ended(self, result)
        return result

    @property
    def results(self) -> list[RunResult]:
        """The results of the runs that ended, in order (their histories: the phase's)."""
        return [result for _, result in self._done]

    @property
    def phase(self) -> str:
        """Name of the run in progress, or of the last run ("" before the first)."""
        if self._run is not None:
            return self._run.phase
        return self._done[-1][1].phase if self._done else ""

    # -- checkpoints -------------------------------------------------------------------------
    def checkpoint_arrays(self) -> dict[str, np.ndarray]:
        """The state's fields and everything else that decides the solver's future, by name.

        Beside the state: the solver's step and split counters, the results of the runs
        that ended, the run in progress (its step, peak kinetic energy for rest detection,
        ledger at its start, monitor, history) and the observers' counters.
        :meth:`restore` continues from them bit for bit.
        """
        out = self.state.arrays()
        out["solver.options"] = np.array(settings_text(self.options))
        out["solver.numbers"] = np.array([self.steps, self.n_split, self.active_contacts,
                                          len(self._done)], dtype=np.int64)
        for i, (call, res) in enumerate(self._done):
            p = f"solver.done{i}."
            out[p + "call"] = np.array(call)
            out[p + "stop_reason"] = np.array(res.stop_reason)
            out[p + "phase"] = np.array(res.phase)
            out[p + "numbers"] = np.array([float(getattr(res, n)) for n in _RESULT_NUMBERS])
            out.update({f"{p}hist.{k}": np.asarray(v, dtype=float)
                        for k, v in res.history.items()})
            out.update({f"{p}on_check.{k}": v for k, v in self._done_callbacks[i].items()})
        if self._run is not None:
            out.update(self._run.arrays("solver.run."))
            out.update({f"solver.run.on_check.{k}": v
                        for k, v in _callback_state(self._on_check).items()})
        for i, obs in enumerate(self.observers):
            out.update({f"solver.obs{i}.{k}": np.asarray(v) for k, v in obs.state().items()})
        return out

    def restore(self, path: str | Path) -> None:
        """Continue from a checkpoint written from :meth:`checkpoint_arrays`.

        The state's fields are set to the checkpoint's arrays (``solver.state`` stays the same
        object; references held to its old arrays, e.g. ``state.x``, do not follow), then the
        counters, the runs and the observers. Call the same runs as the
        interrupted solver: those that had ended return their saved results and the one in
        progress continues.
        """
        fields_, extra = read_checkpoint(path)
        st = self.state
        if (fields_["x"].shape != st.x.shape
                or fields_["element_nodes"].shape != st.element_nodes.shape):
            raise ValueError(f"checkpoint {path} holds {fields_['x'].shape[0]} nodes and "
                             f"{fields_['element_nodes'].shape[0]} elements, the solver's state "
                             f"{st.n_nodes} and {st.n_elements}: a checkpoint of another model")
        if "solver.numbers" not in extra:
            raise ValueError(f"checkpoint {path} holds a state only (DiscreteState.save): "
                             "load it with DiscreteState.load and start a new solver on it")
        require_same_settings(path, "run options", extra.get("solver.options"), self.options)
        if self.options.dt is not None and fields_["dt"] != self.options.dt:
            raise ValueError(f"checkpoint {path} ran with dt = {fields_['dt']:.6g} s, the "
                             f"options give dt = {self.options.dt:.6g} s: resume with the same "
                             "options")
        for name, value in fields_.items():
            setattr(st, name, value)
        self.dt = st.dt
        integrate.check_dt(st, self.dt, contact=self.contact)
        self.steps, self.n_split, self.active_contacts, n_done = (
            int(v) for v in extra["solver.numbers"])
        done = []
        for i in range(n_done):
            p = f"solver.done{i}."
            if len(extra[p + "numbers"]) != len(_RESULT_NUMBERS):
                raise ValueError(f"checkpoint {path}: its run results have "
                                 f"{len(extra[p + 'numbers'])} numbers, this version "
                                 f"{len(_RESULT_NUMBERS)}: written by another version of "
                                 "hybrid; rerun without --resume")
            nums = dict(zip(_RESULT_NUMBERS, extra[p + "numbers"], strict=True))
            res = RunResult(stop_reason=str(extra[p + "stop_reason"]),
                            steps=int(nums["steps"]), time=float(nums["time"]),
                            dt=float(nums["dt"]), wall_time=float(nums["wall_time"]),
                            element_steps_per_s=float(nums["element_steps_per_s"]),
                            n_split=int(nums["n_split"]),
                            history={k: extra[f"{p}hist.{k}"] for k in HISTORY_KEYS},
                            phase=str(extra[p + "phase"]),
                            peak_kinetic=float(nums["peak_kinetic"]))
            done.append((str(extra[p + "call"]), res))
        self._replay = done
        self._replay_callbacks = [_prefixed(extra, f"solver.done{i}.on_check.")
                                  for i in range(n_done)]
        self._done = []
        self._done_callbacks = []
        self._resumed = (_Progress.from_arrays(extra, "solver.run.", st, self.dt,
                                                 self.contact)
                         if "solver.run.numbers" in extra else None)
        for i, obs in enumerate(self.observers):
            p = f"solver.obs{i}."
            obs.restore({k[len(p):]: v for k, v in extra.items() if k.startswith(p)})
        self._begin()

    @staticmethod
    def _check_call(saved: str, call: str) -> None:
        if saved != call:
            raise ValueError(f"the resumed solver's run was called with (until_time, max_steps, "
                             f"until_rest, check_every, rest_min_steps, phase) = {call}, the "
                             f"checkpoint's with {saved}: call the runs as the interrupted "
                             "script did")

    # -- lifetime ----------------------------------------------------------------------------
    @property
    def files(self) -> list[Path]:
        """Files the observers have written, in the order they were attached."""
        return [f for obs in self.observers for f in obs.files]

    def close(self) -> list[Path]:
        """Close the observers (final frames, GIF, ...); returns :attr:`files`."""
        self._close(final=True)
        return self.files

    def _close(self, final: bool) -> None:
        if not self._closed:
            self._closed = True
            for obs in self.observers:
                obs.close(self, final)

    def __enter__(self) -> ExplicitSolver:
        """The solver itself."""
        return self

    def __exit__(self, exc_type, exc, tb) -> None:
        """Close; after an error without writing a final state."""
        self._close(final=exc_type is None)


def run(state: DiscreteState, *, until_time: float | None = None,
        max_steps: int | None = None, until_rest: float | None = None,
        check_every: int = 100, rest_min_steps: int = 200,
        on_check: Callable[[DiscreteState], bool | None] | None = None,
        observers: Iterable[Observer] = (), **options) -> RunResult:
    """One run of a fresh :class:`ExplicitSolver` (``options``: :class:`RunOptions` fields).

    A convenience for single runs: the solver is closed at the end.
    """
    with ExplicitSolver(state, RunOptions(**options), observers=observers) as solver:
        return solver.run(until_time=until_time, max_steps=max_steps, until_rest=until_rest,
                          check_every=check_every, rest_min_steps=rest_min_steps,
                          on_check=on_check)


def _n_bodies(state: DiscreteState) -> int:
    """Connected components of the graph "element - intact interface - element"."""
    ie = state.interface_elements[state.interface_intact]
    label = np.arange(state.n_elements)
    if ie.shape[0] == 0:
        return int(label.size)
    a, b = ie[:, 0], ie[:, 1]
    while True:  # min-label propagation with pointer jumping
        new = label.copy()
        m = np.minimum(label[a], label[b])
        np.minimum.at(new, a, m)
        np.minimum.at(new, b, m)
        new = new[new]
        if np.array_equal(new, label):
            break
        label = new
    return int(np.unique(label).size)


def _record(hist: dict[str, list[float]], state: DiscreteState, led: EnergyLedger,
            led0: EnergyLedger) -> None:
    hist["time"].append(state.time)
    hist["step"].append(float(state.step))
    for key, val in led.as_dict().items():
        hist[key].append(val)
    # relative to the start of this run (the works and dissipations are totals since the
    # state was made; a continued run starts with them non-zero)
    hist["residual"].append(led.residual(led0))


def _input_fault(state: DiscreteState) -> str | None:
    """What in the state's inputs makes a run meaningless (None: nothing found).

    Non-finite gravity, external forces, prescribed velocities or masses, a contact damping
    ratio outside [0, 1], and tie groups with no mass that are free to move (their
    acceleration would be a force over zero).
    """
    for name in ("gravity", "external_force", "prescribed_velocity", "mass"):
        values = np.asarray(getattr(state, name))
        bad = ~np.isfinite(values)
        if bad.any():
            where = "" if values.ndim == 1 and values.size == 2 else \
                f" at node {int(np.argwhere(bad)[0][0])}"
            return (f"{name} holds non-finite values{where} ({int(bad.sum())} entries): give "
                    "finite numbers")
    zeta = state.contact_table[:, 3]
    bad_zeta = ~((zeta >= 0.0) & (zeta <= 1.0))
    if bad_zeta.any():
        m = int(np.argmax(bad_zeta))
        return (f"contact damping ratio {zeta[m]!r} of material {m} is outside [0, 1] (above "
                "1 the contact damping forces push the bodies apart and create energy)")
    free = ~state.fixed.all(axis=1)
    group_free = np.zeros(state.n_groups, dtype=bool)
    np.logical_or.at(group_free, state.node_group, free)
    massless = group_free & ~(state.group_mass > 0.0)
    if massless.any():
        g = int(np.argmax(massless))
        return (f"{int(massless.sum())} tie group(s) free to move have no mass (group {g}, "
                f"nodes {state.group_nodes[state.group_ptr[g]:state.group_ptr[g + 1]].tolist()[:6]}"
                "): give their material a density > 0 or hold them")
    return None


def _cause(state: DiscreteState, dt: float, contact: bool | None) -> str:
    """The likeliest cause of an unstable run, checked in order: inputs, distortion, dt."""
    fault = _input_fault(state)
    if fault is not None:
        return f"Cause: {fault}."
    if np.isfinite(state.x).all():
        crit = integrate.stable_time_step(state, contact=contact)
        if dt > crit:
            return (f"Cause: the elements have distorted so much that the stable time step fell "
                    f"to {crit:.4g} s, below dt = {dt:.4g} s (give the flowing material a "
                    "residual strength and a softening displacement so that its bonds fail "
                    "where it flows; without softening, the expert options plastic_strain_cap "
                    "and split_plastic_strain; or reduce dt).")
    return (f"Likely cause: dt = {dt:.4g} s too large for the current mesh or contact "
            "stiffness (reduce dt or the safety factor), or an element inverted under a "
            "too large deformation.")


def _raise_non_finite(state: DiscreteState, dt: float, contact: bool | None = None) -> None:
    raise RunUnstable(
        f"discrete run unstable at step {state.step} (t = {state.time:.6g} s): non-finite "
        f"coordinates/velocities/energy. {_cause(state, dt, contact)}")


#: a run stops when its mechanical energy exceeds this times its sources (energy at the
#: start of the run and the work of loads and supports)
RUNAWAY_MARGIN = 2.0


class _Monitor:
    """Stops an unstable run: non-finite numbers, or mechanical energy without a source.

    Runaway: the mechanical energy (kinetic + strain + contact) above ``RUNAWAY_MARGIN``
    times its sources, however fast it grew. A stable run never holds more than its sources
    plus the small energy the contact forces create (a few % of the work of gravity).
    """

    def __init__(self, state: DiscreteState, led0: EnergyLedger, dt: float,
                 contact: bool | None = None) -> None:
        """Sources and tolerance of the run starting with ``led0``."""
        self.e_start = led0.mechanical
        self.src0 = led0.work_loads + led0.work_supports
        mass_tot = float(np.sum(state.mass))
        cmax = float(np.max(np.sqrt((state.material_table[:, 0]
                                     + 4.0 * state.material_table[:, 1] / 3.0)
                                    / state.density)))
        self.tol_e = 1e-12 * mass_tot * cmax**2 + 1e-6 * abs(self.e_start)
        self.e_prev = self.e_start
        self.dt = dt
        self.contact = contact

    def state(self) -> np.ndarray:
        """What the monitor's future checks depend on, for checkpoints."""
        return np.array([self.e_start, self.src0, self.tol_e, self.e_prev])

    def restore(self, saved: np.ndarray) -> None:
        """Continue from :meth:`state`."""
        self.e_start, self.src0, self.tol_e, self.e_prev = (float(v) for v in saved)

    def check(self, state: DiscreteState, led: EnergyLedger) -> None:
        """Raise RuntimeError if the state with ledger ``led`` is unstable."""
        e_now = led.mechanical
        if not (np.isfinite(e_now) and np.isfinite(state.x).all()
                and np.isfinite(state.v).all()):
            _raise_non_finite(state, self.dt, self.contact)
        supply = (self.e_start + abs(led.work_loads - self.src0) + abs(led.work_supports)
                  + abs(self.src0))
        if e_now > RUNAWAY_MARGIN * supply + self.tol_e:
            raise RunUnstable(
                f"discrete run unstable at step {state.step} (t = {state.time:.6g} s): "
                f"mechanical energy {e_now:.4g} kJ/m ({e_now / max(supply, 1e-300):.3g} x its "
                f"sources {supply:.4g} kJ/m, above the margin of {RUNAWAY_MARGIN:g} x; "
                f"{self.e_prev:.4g} kJ/m at the last check). "
                f"{_cause(state, self.dt, self.contact)}")


def _check_distortion(state: DiscreteState, dt: float, contact: bool) -> None:
    """Stop when the elements have distorted below the run's stable time step.

    The run would otherwise end in NaN a few steps later; the message names the remedies.
    """
    crit = integrate.stable_time_step(state, contact=contact)
    if dt > crit:
        raise RunUnstable(
            f"discrete run stopped at step {state.step} (t = {state.time:.6g} s): the elements "
            f"have distorted so much that the stable time step fell to {crit:.4g} s, below the "
            f"run's dt = {dt:.4g} s (large plastic flow pancakes an element). Give the "
            "flowing material a residual strength and a softening displacement (its bonds "
            "then fail where it softens, and the elements beside them stop yielding), use "
            "larger elements if its residual plastic strain u_r / (sqrt(3) h) is more than an "
            "element can take, continue with a smaller dt (RunOptions(dt=...)), or, without "
            "softening, use the expert options split_plastic_strain and plastic_strain_cap.")
