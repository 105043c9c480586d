"""A discrete run to rest with the standard outputs and figures (e.g. after a handover).

:func:`run_to_rest` runs a state with an :class:`~hybrid.discrete.solver.ExplicitSolver`
until it comes to rest or to a time limit, with the observers of
:func:`~hybrid.discrete.outputs.standard_outputs` (XDMF series, PNG frames and GIF, progress
bar) and figures of the configuration (:func:`~hybrid.discrete.figures.plot_configuration`)
at the start and at chosen times; the :class:`RestRun` it returns reports the run's standard
numbers and checks (elements, mass and energy). What else the run measures is left to the
caller (:mod:`hybrid.discrete.measures`).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from hybrid.discrete.energy import conservation_checks, energy_peak_ratio
from hybrid.discrete.figures import Snapshots, plot_configuration
from hybrid.discrete.ledger import support_work
from hybrid.discrete.outputs import frame_interval, standard_outputs
from hybrid.discrete.solver import ExplicitSolver, Observer, RunOptions, RunResult
from hybrid.discrete.state import DiscreteState
from hybrid.discrete.ties import failure_modes
from hybrid.io import Check

__all__ = ["LoadProgram", "PunchProgram", "RestRun", "require_serial", "run_to_rest"]

_LOADING, _UNLOADING, _REMOVED = 0, 1, 2  # the phases of a LoadProgram


class _Unloading:
    """What a load program and a punch share: the removal of a load over ``ramp_time``."""

    phase: int
    ramp_time: float  # [s]

    @property
    def removed(self) -> bool:
        """True once the load has been removed."""
        return self.phase == _REMOVED

    def _ramp_down(self, peak: float, t: float, t_unload: float) -> float:
        """The load ``peak`` falling linearly to 0 over ``ramp_time`` from ``t_unload`` [s].

        The program is removed once it is 0.
        """
        value = peak * max(1.0 - (t - t_unload) / self.ramp_time, 0.0)
        if value == 0.0:
            self.phase = _REMOVED
        return value


@dataclass
class LoadProgram(_Unloading):
    """A load raised, held until a displacement is reached, then removed: a run's ``on_check``.

    From ``t_start`` [s] the load value goes linearly from ``start`` to ``peak`` over
    ``ramp_time`` [s] and is held; when ``measure()`` reaches ``target`` (or after
    ``max_time`` [s] of loading) it falls linearly to 0 over ``ramp_time`` from the value it
    had reached. ``apply(value)`` sets the load (e.g. a handover's ``set_load_factor`` scaled
    to a pressure). Called at every check, it returns True once the load is removed (the run
    stops there). Its progress is saved in checkpoints (``state``/``restore``), so a resumed
    run continues it.

    ``curve`` holds (measure, load) at every check; ``t_unload`` the time of the unloading
    (from ``t_start``) and ``at_unloading`` the measure then (None before).
    """

    apply: Callable[[float], None]
    measure: Callable[[], float]
    start: float
    peak: float
    target: float
    ramp_time: float  # [s]
    max_time: float  # [s]
    t_start: float  # [s]
    phase: int = _LOADING
    t_unload: float | None = None
    at_unloading: float | None = None
    curve: list[tuple[float, float]] = field(default_factory=list)

    def raised(self, t: float) -> float:
        """The load ``t`` [s] after ``t_start`` while it is raised and held."""
        if t >= self.ramp_time:
            return self.peak
        return self.start + (self.peak - self.start) * (t / self.ramp_time)

    def __call__(self, state: DiscreteState) -> bool:
        """Set the load for the state's time; True once it is removed."""
        t = state.time - self.t_start
        if self.phase == _LOADING:
            value = self.raised(t)
            if self.measure() >= self.target or t >= self.max_time:
                self.phase, self.t_unload, self.at_unloading = _UNLOADING, t, self.measure()
        if self.phase == _UNLOADING:
            assert self.t_unload is not None
            # removed from the load it had reached (the peak unless the target came first)
            value = self._ramp_down(self.raised(self.t_unload), t, self.t_unload)
        if self.phase == _REMOVED:
            value = 0.0
        self.apply(value)
        self.curve.append((self.measure(), value))
        return self.phase == _REMOVED

    def state(self) -> dict[str, np.ndarray]:
        """The program's progress as arrays (for checkpoints)."""
        nan = float("nan")
        return {"phase": np.array(self.phase),
                "unload": np.array([nan if self.t_unload is None else self.t_unload,
                                    nan if self.at_unloading is None else self.at_unloading]),
                "curve": np.array(self.curve, dtype=float).reshape(-1, 2)}

    def restore(self, saved: dict[str, np.ndarray]) -> None:
        """Continue from :meth:`state`."""
        self.phase = int(saved["phase"])
        t_unload, at = (float(v) for v in saved["unload"])
        self.t_unload = None if np.isnan(t_unload) else t_unload
        self.at_unloading = None if np.isnan(at) else at
        self.curve = [(float(a), float(b)) for a, b in saved["curve"]]


@dataclass
class PunchProgram(_Unloading):
    """A rigid platen pushed down at a set speed to a settlement, then unloaded: an ``on_check``.

    Displacement control, as in a load test on a rigid footing (the thesis, section 3.4:
    "for smooth rigid or rough rigid footings a certain amount of displacement is normally
    specified"). From ``t_start`` [s] the platen's ``nodes`` move down at a speed raised
    linearly from 0 to ``speed`` [m/s] over ``ramp_time`` [s] and held until ``measure()``
    (the settlement [m]) reaches ``target`` [m] (or after ``max_time`` [s]). Then the platen
    is let go under the pressure it carried (force control, ``apply(pressure)`` in kPa) and
    that pressure falls linearly to 0 over ``ramp_time``, as the thesis unloads its footing
    (section 5.4.1). Called at every check, it returns True once the load is removed.

    The bearing pressure is measured, not applied: the work of the platen's reaction
    (:func:`~hybrid.discrete.ledger.support_work`) over the last ``window`` [m] of
    settlement, divided by that settlement and the platen's ``width`` [m] (a mean reaction,
    free of the step-to-step ringing of a stiff contact); ``measure()`` must be the
    platen's own settlement (the mean downward movement of its nodes). Every other support
    must be at rest (checked by :meth:`start`), so that the supports' work is the platen's.
    ``curve`` holds (settlement, pressure [kPa]) at every check (measured while pushed,
    applied while unloaded); ``t_unload`` the time of the unloading (from ``t_start``),
    ``at_unloading`` the settlement then and ``pressure_at_unloading`` the pressure let go
    (None before, and when ``max_time`` came before half a window of settlement: the platen
    is then let go under no load).
    """

    nodes: np.ndarray
    apply: Callable[[float], None]
    measure: Callable[[], float]
    width: float  # [m]
    speed: float  # [m/s]
    target: float  # [m]
    ramp_time: float  # [s]
    max_time: float  # [s]
    t_start: float  # [s]
    window: float = 0.01  # [m]
    phase: int = _LOADING
    t_unload: float | None = None
    at_unloading: float | None = None
    pressure_at_unloading: float | None = None
    curve: list[tuple[float, float]] = field(default_factory=list)
    _work: list[tuple[float, float]] = field(default_factory=list)  # (settlement, work)

    def __post_init__(self) -> None:
        for name in ("width", "speed", "target", "ramp_time", "max_time", "window"):
            if not getattr(self, name) > 0.0:
                raise ValueError(f"PunchProgram: {name} = {getattr(self, name)!r} must be > 0")
        if self.window > self.target:
            raise ValueError(f"PunchProgram: window = {self.window} m must not exceed the "
                             f"target settlement {self.target} m")
        nodes = np.asarray(self.nodes)
        self.nodes = np.flatnonzero(nodes) if nodes.dtype == bool else nodes.astype(np.int64)

    def pressure(self) -> float | None:
        """Mean bearing pressure over the last ``window`` of settlement [kPa].

        None until the push has covered half a window.
        """
        s1, w1 = self._work[-1]
        k = int(np.searchsorted([s for s, _ in self._work], s1 - self.window, side="right"))
        s0, w0 = self._work[max(k - 1, 0)]
        if s1 - s0 < 0.5 * self.window:
            return None
        return (w1 - w0) / ((s1 - s0) * self.width)

    def start(self, state: DiscreteState) -> None:
        """Take the platen over: its load removed and its vertical velocity held (at rest).

        Called by the first check if not before; call it before the solver is made (a
        resumed solver restores the program's progress afterwards), so that the platen is
        held from the first step. The platen's nodes must be free vertically before.
        """
        if self._work:
            return
        if state.fixed[self.nodes, 1].any():
            raise ValueError("PunchProgram: platen nodes are already held vertically; the "
                             "program holds and lets go of them itself")
        others = np.ones(state.n_nodes, dtype=bool)
        others[self.nodes] = False
        if (state.fixed[others] & (state.prescribed_velocity[others] != 0.0)).any():
            raise ValueError("PunchProgram: other supports move (prescribed velocity not 0), "
                             "so the supports' work is not the platen's; hold them at rest")
        self.apply(0.0)
        state.fix(self.nodes, x=False, y=True)
        self._work.append((self.measure(), support_work(state)))

    def mean_pressure(self, lower: float, upper: float) -> float:
        """Mean bearing pressure [kPa] while the settlement went from ``lower`` to ``upper`` [m].

        The work of the push over that settlement (interpolated between checks) divided by
        it and by the ``width``.
        """
        if not (self._work and self._work[0][0] <= lower < upper <= self._work[-1][0]):
            raise ValueError(f"PunchProgram.mean_pressure: {lower} to {upper} m lies outside "
                             "the settlement pushed so far")
        s, w = np.array(self._work).T
        w0, w1 = np.interp([lower, upper], s, w)
        return float((w1 - w0) / ((upper - lower) * self.width))

    def __call__(self, state: DiscreteState) -> bool:
        """Push, then unload, for the state's time; True once the load is removed."""
        t = state.time - self.t_start
        settlement = self.measure()
        if self.phase == _LOADING:
            self.start(state)
            # the settlement only grows under the push: the window is taken along it
            self._work.append((max(settlement, self._work[-1][0]), support_work(state)))
            q = self.pressure()
            if (settlement >= self.target and q is not None) or t >= self.max_time:
                # let go under the pressure it carried (none measured yet: under none)
                self.phase, self.t_unload = _UNLOADING, t
                self.at_unloading, self.pressure_at_unloading = settlement, q
                state.fixed[self.nodes, 1] = False
                state.prescribed_velocity[self.nodes, 1] = 0.0
                state.primed = False
            else:
                state.prescribed_velocity[self.nodes, 1] = (
                    -self.speed * min(max(t, 0.0) / self.ramp_time, 1.0))
                self.curve.append((settlement, float("nan") if q is None else q))
        if self.phase == _UNLOADING:
            assert self.t_unload is not None
            value = self._ramp_down(self.pressure_at_unloading or 0.0, t, self.t_unload)
            self.apply(value)
            self.curve.append((settlement, value))
        return self.phase == _REMOVED

    def state(self) -> dict[str, np.ndarray]:
        """The program's progress as arrays (for checkpoints)."""
        nan = float("nan")
        return {"phase": np.array(self.phase),
                "unload": np.array([nan if v is None else v for v in
                                    (self.t_unload, self.at_unloading,
                                     self.pressure_at_unloading)]),
                "curve": np.array(self.curve, dtype=float).reshape(-1, 2),
                "work": np.array(self._work, dtype=float).reshape(-1, 2)}

    def restore(self, saved: dict[str, np.ndarray]) -> None:
        """Continue from :meth:`state`."""
        self.phase = int(saved["phase"])
        t, at, q = (None if np.isnan(v) else float(v) for v in saved["unload"])
        self.t_unload, self.at_unloading, self.pressure_at_unloading = t, at, q
        self.curve = [(float(a), float(b)) for a, b in saved["curve"]]
        self._work = [(float(a), float(b)) for a, b in saved["work"]]


@dataclass
class RestRun:
    """What :func:`run_to_rest` did.

    Attributes:
        result: the solver's :class:`~hybrid.discrete.solver.RunResult`.
        figures: the configuration PNGs written: the start, then the snapshots in time order.
        outputs: the files of the observers other than PNG frames (XDMF, HDF5, GIF).
        state: the state run (advanced in place: the end of the run).
        n_elements: its elements at the start.
        mass: its mass at the start [t/m].
        window: the figures' (xmin, ymin, xmax, ymax) [m] (None: all elements).
        rest: the kinetic / strain energy ratio taken as rest [-].
    """

    result: RunResult
    figures: list[Path]
    outputs: list[Path]
    state: DiscreteState
    n_elements: int
    mass: float
    window: tuple[float, float, float, float] | None = None
    rest: float = 1e-4

    @property
    def at_rest(self) -> bool:
        """The run stopped at rest (not by its time or step limit)."""
        return self.result.stop_reason == "rest"

    def checks(self) -> dict[str, Check]:
        """The standard checks of the run: at rest, energy bounded, elements and mass kept.

        At rest: E_kin / max(peak E_kin, E_strain) at most ``rest`` and the loads no longer
        working (:func:`~hybrid.discrete.options.drift_ratio` at most ``REST_DRIFT``); the
        others are :func:`~hybrid.discrete.energy.conservation_checks`.
        """
        return {**conservation_checks(self.result.history, self.result.start, self.state,
                                      self.n_elements, self.mass),
                **self.result.rest_checks(self.rest)}

    def final_figure(self, path: str | Path,
                     lines: dict[str, np.ndarray] | None = None) -> Path:
        """The configuration at the end, titled with the time and why the run stopped.

        :func:`~hybrid.discrete.figures.plot_configuration` in ``window``, the outline at the
        start dashed, ``lines`` on top (e.g. a slip surface's).
        """
        res = self.result
        return plot_configuration(path, self.state, window=self.window, lines=lines,
                                  outline=True, title=f"t = {res.time:.3g} s ({res.stop_reason})")

    def report(self) -> dict[str, Any]:
        """The run in numbers for a summary.

        "elements" (at the end), "dt_s", "steps", "time_s", "stop" (the reason),
        "wall_time_s", "interfaces_failed" and "interfaces_failed_by_mode" (how they failed:
        ``failure_modes``), "energy_peak_over_supply"
        (:func:`~hybrid.discrete.energy.energy_peak_ratio`) and the "outputs" (paths).
        """
        res, state = self.result, self.state
        return {"elements": state.n_elements, "dt_s": res.dt, "steps": res.steps,
                "time_s": res.time, "stop": res.stop_reason, "wall_time_s": res.wall_time,
                "interfaces_failed": int((~state.interface_intact).sum()),
                "interfaces_failed_by_mode": failure_modes(state),
                "energy_peak_over_supply": energy_peak_ratio(res.history, res.start),
                "outputs": [str(f) for f in self.outputs]}


def run_to_rest(state: DiscreteState, out: str | Path, options: RunOptions, *,
                until_time: float, rest: float, rest_min_steps: int = 2000,
                frames: int = 0, snapshot_times: Sequence[float] = (),
                window: tuple[float, float, float, float] | None = None,
                progress: bool = True, prefix: str = "discrete_",
                check_every: int = 50, material_names: Sequence[str] = (),
                watch: Sequence[Observer] = ()) -> RestRun:
    """Run ``state`` (advanced in place) to rest, or to ``until_time``, with outputs.

    Writes in ``out``: ``{prefix}t0.png`` (the start: plastic strain, bonds intact),
    ``{prefix}t{t:g}.png`` when the time first reaches each of ``snapshot_times`` (failed
    interfaces in red) and, in ``out/discrete``, the XDMF series and the PNG frames of
    :func:`~hybrid.discrete.outputs.standard_outputs`.

    Args:
        state: the discrete state (supports set).
        out: the output folder.
        options: the solver's options; ``options.dt`` is needed when ``frames`` > 0.
        until_time: the run stops at this time [s] at the latest.
        rest: kinetic / strain energy ratio taken as rest (``ExplicitSolver.run``'s
            ``until_rest``).
        rest_min_steps: steps before rest may stop the run.
        frames: about this many XDMF / PNG frames over ``until_time`` (0: none).
        snapshot_times: times [s] of the configuration snapshots.
        window: (xmin, ymin, xmax, ymax) [m] of the figures (None: all elements).
        progress: a progress bar.
        prefix: start of the figures' file names.
        check_every: steps between the run's checks (rest, snapshots, energy history).
        material_names: the materials' names by index, written in the series' index.
        watch: more observers of the run (e.g. :class:`~hybrid.discrete.measures.CrackWatch`),
            attached after the standard outputs.
    """
    out = Path(out)
    if frames and options.dt is None:
        raise ValueError("run_to_rest: frames > 0 needs options.dt (the frames are spaced in "
                         "steps)")
    figures = [plot_configuration(out / f"{prefix}t0.png", state, window=window,
                                  title="Discrete start: plastic strain, bonds intact")]
    snapshots = Snapshots(out, snapshot_times, prefix=f"{prefix}t", window=window,
                          title="t = {time:.3g} s: failed interfaces (red), plastic strain")
    every = frame_interval(until_time, options.dt, frames) if options.dt is not None else 0
    n_elements, mass = state.n_elements, float(state.mass.sum())
    observers = standard_outputs(out / "discrete", progress=progress, output_every=every,
                                 material_names=material_names) + list(watch)
    with ExplicitSolver(state, options, observers=observers) as solver:
        result = solver.run(until_time=until_time, until_rest=rest,
                            rest_min_steps=rest_min_steps, on_check=snapshots,
                            check_every=check_every)
    return RestRun(result, figures + snapshots.paths,
                   [f for f in solver.files if f.suffix != ".png"], state, n_elements, mass,
                   window, rest)


def require_serial(case: str) -> None:
    """Refuse to run a discrete-only case under MPI (the discrete engine runs on one process).

    Called on every rank before anything is built or written, so all ranks stop together.
    """
    from mpi4py import MPI

    size = MPI.COMM_WORLD.size
    if size > 1:
        raise ValueError(f"{case} is a discrete-only case: the discrete engine runs in one "
                         f"process (threads: NUMBA_NUM_THREADS), not on {size} MPI ranks; "
                         "run it without mpirun")
