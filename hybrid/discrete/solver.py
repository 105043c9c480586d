"""The explicit solver of the discrete engine: one step, and runs to a time, a step count or rest.

Orchestration only (no math here). :meth:`ExplicitSolver.step` calls the kernels in order:
contact refresh (``contact.find_contact_pairs`` every ``contact_refresh`` steps and after each
splitting check), contact forces (``contact.forces.add_contact_forces``, and
``contact.walls`` for the smooth walls of the roller supports), the explicit update
(``integrate.step``: tie groups, central differences, element stresses and internal forces),
the contact terms of the energy ledger (``contact.energy.contact_step_works``, see
``hybrid.discrete.ledger``) and, every ``split_every`` steps, interface failure and splitting
(``ties``). :meth:`ExplicitSolver.run` only loops and checks: every ``check_every`` steps it
measures the ledger, stops an unstable run, records the history, detects rest and calls the
observers and ``on_check``; the checks themselves are in ``hybrid.discrete.monitor``.

The settings are split in two. :class:`RunOptions` (physics and numerics: time step,
damping, splitting, contact, element formulation; defined with :class:`RunResult` in
``hybrid.discrete.options``) is fixed for the solver's lifetime, so one solver is one
consistent model. The arguments of :meth:`ExplicitSolver.run` say when one run
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

import numba
import numpy as np

from hybrid.constitutive.softening import warn_snap_back
from hybrid.constitutive.table import SOFTENING_DISPLACEMENT
from hybrid.discrete import integrate, ties
from hybrid.discrete.elements import StrengthMemo
from hybrid.discrete.ledger import EnergyLedger
from hybrid.discrete.monitor import (
    Monitor,
    check_distortion,
    input_fault,
    raise_non_finite,
    record_check,
    wall_fault,
)
from hybrid.discrete.options import (
    HISTORY_KEYS,
    REST_DRIFT,
    RESULT_NUMBERS,
    RunOptions,
    RunResult,
    drift_ratio,
    require_same_settings,
    settings_text,
)
from hybrid.discrete.state import (
    LEDGER_CONTACT_DAMPING,
    LEDGER_CONTACT_NORMAL,
    LEDGER_FRICTION,
    DiscreteState,
    read_checkpoint,
)

__all__ = ["RunOptions", "ExplicitSolver", "Observer", "RunResult", "run",
           "has_contact_module"]

log = logging.getLogger(__name__)

#: Runs of fewer elements step on one numba thread: a small step is shorter than the cost of
#: its parallel regions on a second thread (``hybrid bench``, tied and collapse problems: at
#: 1e3 elements 1 thread is 1.3-1.7x faster than 2, at 2.5e3 2 threads are 1.2-1.3x faster;
#: the threshold lies between the two; docs/performance.md). Results are the same bit for bit
#: on any number of threads.
SERIAL_BELOW_ELEMENTS = 1500


def has_contact_module() -> bool:
    """True when ``hybrid.discrete.contact`` can be imported."""
    try:
        import hybrid.discrete.contact  # noqa: F401
    except ImportError:
        return False
    return True


@dataclass
class _Progress:
    """A run in progress: everything that decides its future, saved in checkpoints."""

    call: str  # the run's arguments (a resumed solver must be called the same way)
    phase: str  # name of the run in the outputs
    n_total: int | None  # steps of the run when bounded
    external: bool  # loads were non-zero when the run started or an on_check put them on
    led0: EnergyLedger  # ledger at the start of the run
    monitor: Monitor
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
        monitor = Monitor(state, led0, dt, contact)
        monitor.restore(a[f"{prefix}monitor"])
        return cls(call=str(a[f"{prefix}call"]), phase=str(a[f"{prefix}phase"]),
                   n_total=None if n_total < 0 else n_total, external=bool(external),
                   led0=led0, monitor=monitor, split0=split0, k=k,
                   peak_ke=float(a[f"{prefix}peak_ke"]),
                   hist={key: [float(v) for v in a[f"{prefix}hist.{key}"]]
                         for key in HISTORY_KEYS},
                   callback=_prefixed(a, f"{prefix}on_check."))



#: the :class:`EnergyLedger` terms in field order (a run's ``start`` in checkpoints)
_LEDGER_KEYS = tuple(f.name for f in fields(EnergyLedger))


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
        self._memo = StrengthMemo()  # the Gauss points' strengths, kept from step to step
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
            from hybrid.discrete.contact.energy import contact_step_works
            from hybrid.discrete.contact.walls import WallBuffers, add_wall_forces, near_walls

            self._cmod = cmod
            self._contact_step_works = contact_step_works
            self._add_contact_forces = add_contact_forces
            self._add_wall_forces = add_wall_forces
            self._near_walls = near_walls
            self._wbuf = WallBuffers()
        dt = o.dt
        chosen = dt is None and not state.dt > 0.0  # else given, or a continued state's
        crit = integrate.critical_time_step(state, contact=self.contact, bbar=o.bbar)
        if chosen:  # within the critical step and the damped contacts' limit
            dt = integrate.default_dt(state, o.safety, contact=self.contact, critical=crit)
        elif dt is None:
            dt = state.dt
        integrate.check_dt(state, float(dt), contact=self.contact, critical=crit)
        if self.contact and not chosen:  # the damped contacts stable at a step not chosen here?
            fault = integrate.damped_contact_fault(state, float(dt))
            if fault is not None:
                raise ValueError(fault)
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
        self._split_damping = self._split[0]  # the walls' damping part goes here (a view)
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
        self._point_cap = ties.plastic_cap(st, self._cap)
        mass_tot = float(np.sum(st.mass))
        # floor of the contact search margin [m]
        self._margin_floor = 1e-6 * math.sqrt(mass_tot / float(st.density.max()))
        self._cmass: np.ndarray = (
            self._cmod.rigid_contact_mass(st.mass, st.fixed, st.element_nodes) if self.contact
            else np.zeros(0))
        fault = wall_fault(st)
        if fault is not None:  # before held_walls reads them
            raise ValueError(f"discrete run refused: {fault}")
        if st.walls.shape[0]:  # a released roller takes its wall with it
            from hybrid.discrete.contact.walls import held_walls

            st.walls, st.wall_nodes = held_walls(st.walls, st.wall_nodes, st.fixed)
        if self.contact:  # every element, until the next refresh of the contact search
            self._wbuf.elements = np.arange(st.n_elements)

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
                    raise_non_finite(st, dt, self.contact)
                vmax = float(np.max(np.abs(st.v))) if st.n_nodes else 0.0
                margin = o.margin_factor * vmax * self._refresh * dt
                margin = max(margin, self._margin_floor)
                pairs = cmod.find_contact_pairs(st.x, st.element_nodes, st.node_group, margin,
                                                o.contact_bounds, hinges=o.contact_hinges)
                st.contact_shear = cmod.carry_contact_history(st.contact_pairs,
                                                              st.contact_shear, pairs)
                st.contact_pairs = pairs
                if st.walls.shape[0]:  # the elements that can meet a wall before the next
                    self._wbuf.elements = self._near_walls(st.x, st.element_nodes, st.walls,
                                                           margin)
            self._cforce[:] = 0.0
            n_pairs = st.contact_pairs.shape[0] + st.walls.shape[0]  # forces to account for
            if n_pairs:
                self._split[:] = 0.0
                self._v_start[:] = st.v
            if st.contact_pairs.shape[0]:
                self.active_contacts = self._add_contact_forces(  # unchecked: state, dt and
                    st.x, st.v, self._cmass, st.element_nodes,  # pairs checked already
                    st.element_material, st.contact_table, st.contact_pairs, st.contact_shear,
                    dt, self._cforce, self._split, self._cbuf)[0]
            if st.walls.shape[0]:  # the smooth walls: normal force, its damping part
                self._add_wall_forces(st.x, st.v, st.mass, st.element_nodes,
                                      st.element_material, st.contact_table, st.fixed,
                                      st.walls, dt, self._cforce, self._split_damping,
                                      self._wbuf)
        integrate.step(st, dt, mass_damping=o.mass_damping, local_damping=o.local_damping,
                       contact_force=self._cforce if self.contact else None, bbar=o.bbar,
                       external=self._external,
                       plastic_strain_cap=self._point_cap, memo=self._memo)
        if n_pairs:
            # minus the work of the tangential / damping / elastic normal forces on the
            # mid-step velocity
            w_d, w_t, w_all = self._contact_step_works(self._split, self._cforce,
                                                       self._v_start, st.v, dt)
            st.ledger[LEDGER_FRICTION] -= w_t
            st.ledger[LEDGER_CONTACT_DAMPING] -= w_d
            st.ledger[LEDGER_CONTACT_NORMAL] -= w_all - w_t - w_d
        if self._split_every and st.step % self._split_every == 0:
            new_fragments = ties.mark_fragments(st)
            modes = ties.check_interfaces(st, self._split_limit)
            if modes.any():
                failed = modes > 0  # intact ones only: check_interfaces skips the others
                st.interface_mode[failed] = modes[failed]
                st.interface_failure_time[failed] = st.time
                self.n_split += ties.split_interfaces(st, failed)
            if new_fragments:
                self._point_cap = ties.plastic_cap(st, self._cap)
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
            rest_min_steps: int = 200, rest_drift: float = REST_DRIFT,
            on_check: Callable[[DiscreteState], bool | None] | None = None,
            phase: str | None = None) -> RunResult:
        """Advance the state until a time, a step count or rest, whichever comes first.

        Args:
            until_time: absolute state time to reach [s].
            max_steps: steps of this run at most.
            until_rest: stop when E_kin <= until_rest * max(peak E_kin of this run, E_strain)
                and the loads have stopped working, ``drift_ratio`` <= ``rest_drift``
                (checked every ``check_every`` steps after ``rest_min_steps``) [-]. The
                second condition keeps a mass creeping under mass damping (slow, so little
                kinetic energy) from being taken as at rest; a run with a steady driver (a
                support pushed at a constant speed, a rising load) never reads rest.
            check_every: steps between checks: energy ledger, instability monitor, history,
                rest, observers' ``checked`` and ``on_check``.
            rest_min_steps: steps of this run before rest may stop it.
            rest_drift: largest :func:`~hybrid.discrete.options.drift_ratio` at rest [-] (inf:
                the kinetic energy alone).
            on_check: called with the state at every check; it may change loads
                (``external_force``, load histories) and returns True to stop the run (stop
                reason "callback"). Loads it puts on act from the next step.
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
                time-step scale); the message names the likeliest cause.
        """
        if until_time is None and max_steps is None and until_rest is None:
            raise ValueError("give at least one of until_time, max_steps, until_rest")
        if max_steps is not None and (int(max_steps) != max_steps or max_steps < 0):
            raise ValueError(f"max_steps = {max_steps!r}: must be an integer >= 0")
        if until_rest is not None and not until_rest > 0.0:
            raise ValueError(f"until_rest = {until_rest!r}: must be a positive energy ratio")
        if not rest_drift > 0.0:
            raise ValueError(f"rest_drift = {rest_drift!r}: must be a positive ratio of works "
                             f"(default {REST_DRIFT}; inf: the kinetic energy alone)")
        if until_time is not None and not math.isfinite(until_time):
            raise ValueError(f"until_time = {until_time!r}: must be a finite time [s]")
        for name, val in (("check_every", check_every), ("rest_min_steps", rest_min_steps)):
            if int(val) != val or val < 0:
                raise ValueError(f"{name} = {val!r}: must be an integer >= 0")
        if self._closed:
            raise RuntimeError("this solver is closed: make a new ExplicitSolver")
        check_every = max(int(check_every), 1)
        phase = phase if phase is not None else f"run {len(self._done) + 1}"
        call = repr((until_time, max_steps, until_rest, check_every, rest_min_steps, phase)
                    + ((rest_drift,) if rest_drift != REST_DRIFT else ()))
        if self._replay:  # a run that had ended before the checkpoint
            saved_call, result = self._replay.pop(0)
            self._check_call(saved_call, call)
            saved = self._replay_callbacks.pop(0)
            _restore_callback(on_check, saved)
            self._done.append((saved_call, result))
            self._done_callbacks.append(saved)
            return result
        st, dt = self.state, self.dt
        fault = input_fault(st)
        if fault is not None:
            raise ValueError(f"discrete run refused: {fault}")
        # the run continues the solver's step (checked when it started) under the in-run rule
        check_distortion(st, dt, self.contact)
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
                          led0=led0, monitor=Monitor(st, led0, dt, self.contact),
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
        threads = numba.get_num_threads()
        if st.n_elements < SERIAL_BELOW_ELEMENTS:
            numba.set_num_threads(1)
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
                        raise_non_finite(st, dt, self.contact)  # before the ledger reads x
                    led = EnergyLedger.measure(st)
                    monitor.check(st, led)
                    check_distortion(st, dt, self.contact)
                    monitor.e_prev = led.mechanical
                    r.peak_ke = max(r.peak_ke, led.kinetic)
                    record_check(hist, st, led, led0)
                    for obs in observers:
                        obs.checked(self, led)
                    if (until_rest is not None and k >= rest_min_steps
                            and led.kinetic <= until_rest * max(r.peak_ke, led.strain)
                            and drift_ratio(hist["time"], hist["work_loads"],
                                            hist["work_supports"], r.peak_ke) <= rest_drift):
                        stop = "rest"
                        break
                    if on_check is not None:
                        done = on_check(st)
                        if not r.external and np.any(st.external_force):  # loads put on
                            r.external = self._external = True
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
        finally:
            numba.set_num_threads(threads)
        wall = _time.perf_counter() - t0
        if not hist["step"] or hist["step"][-1] != st.step:
            led = EnergyLedger.measure(st)
            monitor.check(st, led)
            r.peak_ke = max(r.peak_ke, led.kinetic)
            record_check(hist, st, led, led0)
        k = r.k
        log.info("discrete run: %d steps, stop=%s, %.3g s wall", k, stop, wall)
        result = RunResult(stop_reason=stop, steps=k, time=st.time, dt=dt, wall_time=wall,
                           element_steps_per_s=(k - k0) * st.n_elements / wall if wall > 0
                           else 0.0,
                           n_split=self.n_split - r.split0,
                           history={kk: np.asarray(v) for kk, v in hist.items()}, phase=r.phase,
                           peak_kinetic=r.peak_ke, start=r.led0.as_dict())
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
            out[p + "numbers"] = np.array([float(getattr(res, n)) for n in RESULT_NUMBERS])
            out[p + "start"] = np.array([res.start[k] for k in _LEDGER_KEYS])
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
        if "fragment_cap" not in fields_:
            raise ValueError(f"checkpoint {path} was written by an older version of hybrid "
                             "(its elements carry no fragment flags): rerun without --resume")
        if "dashpot" not in fields_:
            raise ValueError(f"checkpoint {path} was written by an older version of hybrid "
                             "(its nodes carry no boundary dashpots): rerun without --resume")
        if "solver.numbers" not in extra:
            raise ValueError(f"checkpoint {path} holds a state only (DiscreteState.save): "
                             "load it with DiscreteState.load and start a new solver on it")
        require_same_settings(path, "run options", extra.get("solver.options"), self.options)
        if self.options.dt is not None and fields_["dt"] != self.options.dt:
            raise ValueError(f"checkpoint {path} ran with dt = {fields_['dt']:.6g} s, the "
                             f"options give dt = {self.options.dt:.6g} s: resume with the same "
                             "options")
        full = DiscreteState(**fields_)  # a field the checkpoint lacks made as on creation
        for f in fields(DiscreteState):
            setattr(st, f.name, getattr(full, f.name))
        self.dt = st.dt
        check_distortion(st, self.dt, self.contact)  # as the run it resumes did
        self.steps, self.n_split, self.active_contacts, n_done = (
            int(v) for v in extra["solver.numbers"])
        done = []
        for i in range(n_done):
            p = f"solver.done{i}."
            if len(extra[p + "numbers"]) != len(RESULT_NUMBERS):
                raise ValueError(f"checkpoint {path}: its run results have "
                                 f"{len(extra[p + 'numbers'])} numbers, this version "
                                 f"{len(RESULT_NUMBERS)}: written by another version of "
                                 "hybrid; rerun without --resume")
            if p + "start" not in extra:
                raise ValueError(f"checkpoint {path}: its run results lack the energy ledger "
                                 "at their start: written by another version of hybrid; "
                                 "rerun without --resume")
            nums = dict(zip(RESULT_NUMBERS, extra[p + "numbers"], strict=True))
            res = RunResult(stop_reason=str(extra[p + "stop_reason"]),
                            steps=int(nums["steps"]), time=float(nums["time"]),
                            dt=float(nums["dt"]), wall_time=float(nums["wall_time"]),
                            element_steps_per_s=float(nums["element_steps_per_s"]),
                            n_split=int(nums["n_split"]),
                            history={k: extra[f"{p}hist.{k}"] for k in HISTORY_KEYS},
                            phase=str(extra[p + "phase"]),
                            peak_kinetic=float(nums["peak_kinetic"]),
                            start={k: float(v) for k, v in zip(_LEDGER_KEYS, extra[p + "start"],
                                                               strict=True)})
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
