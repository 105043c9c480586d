"""The checks of a discrete run: refused inputs, instability, distortion, the energy history.

:func:`input_fault` finds inputs that make a run meaningless (non-finite loads or masses, a
contact damping ratio outside [0, 1], free tie groups without mass). :class:`Monitor` stops a
run whose mechanical energy exceeds ``RUNAWAY_MARGIN`` times its sources or turns non-finite
(:func:`raise_non_finite`), :func:`check_distortion` one whose elements have distorted below
its time step (their Courant scale); each message names the likeliest cause.
:func:`record_check` appends a check's energy ledger to a run's history.
"""

from __future__ import annotations

import math

import numpy as np

from hybrid.discrete import integrate
from hybrid.discrete.ledger import EnergyLedger
from hybrid.discrete.state import DiscreteState
from hybrid.errors import RunUnstable

__all__ = ["RUNAWAY_MARGIN", "Monitor", "check_distortion", "input_fault", "wall_fault",
           "raise_non_finite", "record_check"]


def record_check(hist: dict[str, list[float]], state: DiscreteState, led: EnergyLedger,
                 led0: EnergyLedger) -> None:
    """Append a check to a run's history: time, step, the ledger ``led``, the residual."""
    hist["time"].append(state.time)
    hist["step"].append(float(state.step))
    for key, val in led.as_dict().items():
        hist[key].append(val)
    # relative to the start of this run (the works and dissipations are totals since the
    # state was made; a continued run starts with them non-zero)
    hist["residual"].append(led.residual(led0))


def input_fault(state: DiscreteState) -> str | None:
    """What in the state's inputs makes a run meaningless (None: nothing found).

    Non-finite gravity, external forces, prescribed velocities or masses, a contact damping
    ratio outside [0, 1], a negative or non-finite contact cohesion or boundary dashpot,
    malformed smooth walls (non-finite, a normal that is not a unit vector, s_min > s_max,
    wall nodes out of range), and tie groups with no mass that are free to move (their
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
    coh = state.contact_table[:, 4]
    bad_c = ~((coh >= 0.0) & np.isfinite(coh))
    if bad_c.any():
        m = int(np.argmax(bad_c))
        return (f"contact cohesion {coh[m]!r} of material {m} is not a finite number >= 0 "
                "kPa")
    bad_d = ~((state.dashpot >= 0.0) & np.isfinite(state.dashpot))
    if bad_d.any():
        node = int(np.argwhere(bad_d)[0][0])
        return (f"dashpot at node {node} is {state.dashpot[node].tolist()}: a transmitting "
                "boundary's dashpots are finite numbers >= 0 kN s/m2 "
                "(DiscreteState.set_transmitting)")
    fault = wall_fault(state)
    if fault is not None:
        return fault
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


def wall_fault(state: DiscreteState) -> str | None:
    """What is wrong with the state's smooth walls (``contact.walls``; None: nothing).

    Each row [n_x, n_y, c, s_min, s_max] needs finite entries, a unit normal and
    s_min <= s_max; each ``wall_nodes`` row [wall, node] a wall and a node that exist.
    """
    walls = np.asarray(state.walls)
    if walls.ndim != 2 or walls.shape[1] != 5:
        return (f"walls has shape {walls.shape}: give (n_walls, 5) rows [n_x, n_y, c, s_min, "
                "s_max] (contact.walls.make_wall)")
    for k, (nx, ny, c, lo, hi) in enumerate(walls):
        if not np.isfinite([nx, ny, c]).all() or np.isnan([lo, hi]).any():
            return f"wall {k} holds non-finite values {walls[k].tolist()}: give finite numbers"
        if abs(math.hypot(nx, ny) - 1.0) > 1e-9:
            return (f"wall {k}: its normal ({nx!r}, {ny!r}) is not a unit vector: divide it by "
                    "its length (and c with it)")
        if lo > hi:
            return f"wall {k}: s_min = {lo!r} > s_max = {hi!r}: swap them"
    nodes = np.asarray(state.wall_nodes)
    if nodes.ndim != 2 or nodes.shape[1] != 2:
        return f"wall_nodes has shape {nodes.shape}: give (n, 2) rows [wall, node]"
    if nodes.size and not ((nodes[:, 0] >= 0).all() and (nodes[:, 0] < walls.shape[0]).all()
                           and (nodes[:, 1] >= 0).all()
                           and (nodes[:, 1] < state.x.shape[0]).all()):
        return (f"wall_nodes names a wall outside 0..{walls.shape[0] - 1} or a node outside "
                f"0..{state.x.shape[0] - 1}: give existing walls and nodes")
    return None


def _cause(state: DiscreteState, dt: float, contact: bool | None) -> str:
    """The likeliest cause of an unstable run, checked in order: inputs, distortion, dt."""
    fault = input_fault(state)
    if fault is not None:
        return f"Cause: {fault}."
    if np.isfinite(state.x).all():
        crit = integrate.stable_time_step(state, contact=contact)
        if dt > crit:
            return (f"Cause: the elements have distorted so much that the time-step scale "
                    f"L_min / c_p fell to {crit:.4g} s, below dt = {dt:.4g} s (an element "
                    "that cannot part "
                    "from its neighbours: let the flowing region split, RunOptions(split_every"
                    "=10) and its interfaces splittable; or reduce dt).")
    return (f"Likely cause: dt = {dt:.4g} s too large for the current mesh or contact "
            "stiffness (reduce dt or the safety factor), or an element inverted under a "
            "too large deformation.")


def raise_non_finite(state: DiscreteState, dt: float, contact: bool | None = None) -> None:
    """Raise RunUnstable for non-finite numbers at the state's step, with the likeliest cause."""
    raise RunUnstable(
        f"discrete run unstable at step {state.step} (t = {state.time:.6g} s): non-finite "
        f"coordinates/velocities/energy. {_cause(state, dt, contact)}")


#: a run stops when its mechanical energy exceeds this times its sources (energy at the
#: start of the run and the work of loads and supports)
RUNAWAY_MARGIN = 2.0


class Monitor:
    """Stops an unstable run: non-finite numbers, or mechanical energy without a source.

    Runaway: the mechanical energy (kinetic + strain + contact) above ``RUNAWAY_MARGIN``
    times its sources (its energy at the start of the run plus the magnitudes of the work of
    the loads and of the supports since), however fast it grew. A stable run never holds
    more than its sources plus the small energy the contact forces create (a few % of the
    work of gravity).
    """

    def __init__(self, state: DiscreteState, led0: EnergyLedger, dt: float,
                 contact: bool | None = None) -> None:
        """Sources and tolerance of the run starting with ``led0``."""
        self.e_start = led0.mechanical
        # the ledger's works are totals since the state was made: the run's count from these
        self.loads0, self.supports0 = led0.work_loads, led0.work_supports
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
        return np.array([self.e_start, self.loads0, self.supports0, self.tol_e, self.e_prev])

    def restore(self, saved: np.ndarray) -> None:
        """Continue from :meth:`state`."""
        if len(saved) != 5:
            raise ValueError(f"the run monitor's checkpoint has {len(saved)} numbers, this "
                             "version 5: written by another version of hybrid; rerun without "
                             "--resume")
        self.e_start, self.loads0, self.supports0, self.tol_e, self.e_prev = (
            float(v) for v in saved)

    def check(self, state: DiscreteState, led: EnergyLedger) -> None:
        """Raise RuntimeError if the state with ledger ``led`` is unstable."""
        e_now = led.mechanical
        if not (np.isfinite(e_now) and np.isfinite(state.x).all()
                and np.isfinite(state.v).all()):
            raise_non_finite(state, self.dt, self.contact)
        supply = (self.e_start + abs(led.work_loads - self.loads0)
                  + abs(led.work_supports - self.supports0))
        if e_now > RUNAWAY_MARGIN * supply + self.tol_e:
            raise RunUnstable(
                f"discrete run unstable at step {state.step} (t = {state.time:.6g} s): "
                f"mechanical energy {e_now:.4g} kJ/m ({e_now / max(supply, 1e-300):.3g} x its "
                f"sources {supply:.4g} kJ/m, above the margin of {RUNAWAY_MARGIN:g} x; "
                f"{self.e_prev:.4g} kJ/m at the last check). "
                f"{_cause(state, self.dt, self.contact)}")


def check_distortion(state: DiscreteState, dt: float, contact: bool) -> None:
    """Stop when the elements have distorted so far that their time-step scale fell below dt.

    The scale (``integrate.stable_time_step``, L_min / c_p) lies above the critical step
    (``integrate.critical_time_step``) on undistorted elements, so this catches gross
    distortion only; the run would otherwise end in NaN a few steps later. The message names
    the remedies. Also the check of a continued or resumed run's step (``ExplicitSolver``).
    """
    crit = integrate.stable_time_step(state, contact=contact)
    if dt > crit:
        raise RunUnstable(
            f"discrete run stopped at step {state.step} (t = {state.time:.6g} s): the elements "
            f"have distorted so much that the time-step scale L_min / c_p fell to {crit:.4g} s, "
            f"below the run's dt = {dt:.4g} s (large plastic flow pancakes an element). A "
            "distorted element parts from its neighbours at a splitting check "
            "(hybrid.discrete.ties.DISTORTION_LIMIT) only where splitting is on and its "
            "interfaces are splittable: "
            "check RunOptions(split_every=...) (10 is typical; 0 turns splitting off) and the "
            "region allowed to split (ties.limit_splitting), keep the time step at most half "
            "the scale (RunOptions(safety=0.5) or a dt that small), or continue with a "
            "smaller dt.")
