"""Measures of a discrete run: interface slip, slip surface, run-out of a slope or a deposit.

Units: m. An interface is the edge two elements shared at the start; its two node pairs
coincided then, so their separation is the slip (sliding and opening together).
:class:`SlipSurface` gathers the slip-surface measures of a run; :class:`SlopeMarks` picks a
slope's crest and toe at the start of a run and measures how far they moved at its end;
:class:`FootingMarks` does the same for a footing (settlement) and the ground beside it (heave);
:func:`deposit` measures where a mass that spread over a floor came to rest;
:func:`mean_displacement` is the mean movement of a set of elements; :func:`moving_zone_back`
the inclination of the back of the zone that moved (an active wedge behind a wall);
:func:`failure_onset` where and how bonds began to fail.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any, NamedTuple

import numpy as np

from hybrid.discrete.ledger import EnergyLedger
from hybrid.discrete.solver import ExplicitSolver, Observer
from hybrid.discrete.state import DiscreteState
from hybrid.discrete.ties import mode_counts
from hybrid.io import Check

__all__ = ["interface_slip", "slip_surface", "slip_trace", "slipped_interfaces", "SlipSurface",
           "SlopeMarks", "SlopeMovement", "FootingMarks", "Deposit", "deposit",
           "mean_displacement", "moving_zone_back", "MOVING_FRACTION", "interface_opening",
           "Crack", "crack_from_top", "CrackWatch", "surface_opening", "FailureOnset",
           "failure_onset", "first_failures", "interfaces_of", "top_interfaces",
           "interfaces_between", "slip_along"]

#: The zone that moves with a wall (or a slope face): elements that have moved at least this
#: fraction of the face's own movement [-]. Small enough to reach the back of the slip, large
#: enough to leave out the elastic and diffuse plastic straining behind it.
MOVING_FRACTION = 0.05


def interface_slip(state: DiscreteState) -> np.ndarray:
    """Relative movement [m] of the two sides of every interface (n_interfaces,).

    The mean over the interface's two node pairs of their distance.
    """
    n = state.interface_nodes
    return 0.5 * (np.linalg.norm(state.x[n[:, 0]] - state.x[n[:, 2]], axis=1)
                  + np.linalg.norm(state.x[n[:, 1]] - state.x[n[:, 3]], axis=1))


def interface_opening(state: DiscreteState) -> np.ndarray:
    """Opening [m] of every interface (n_interfaces,): its sides' separation along the normal.

    The normal is the outward normal of element A's edge (a0 -> a1, counter-clockwise) in the
    current geometry; the mean over the two node pairs of (x_b - x_a) . n. Positive: the
    sides stand apart (an open crack); about zero: they slide in contact; negative: overlap.
    """
    n = state.interface_nodes
    edge = state.x[n[:, 1]] - state.x[n[:, 0]]
    normal = np.stack([edge[:, 1], -edge[:, 0]], axis=1)
    normal /= np.maximum(np.linalg.norm(normal, axis=1), 1e-300)[:, None]
    gap = 0.5 * ((state.x[n[:, 2]] - state.x[n[:, 0]]) + (state.x[n[:, 3]] - state.x[n[:, 1]]))
    return np.einsum("ij,ij->i", gap, normal)


def slip_surface(state: DiscreteState, min_slip: float) -> np.ndarray:
    """(n_interfaces,) True for the failed interfaces that slipped at least ``min_slip`` [m]."""
    return ~state.interface_intact & (interface_slip(state) >= min_slip)


def slip_trace(state: DiscreteState, on_surface: np.ndarray,
               width: float = 5.0) -> list[list[float]]:
    """The slip surface as (x, y) points [m] in the start geometry.

    In each ``width`` strip of x, the midpoint of the deepest interface of ``on_surface`` (a
    mask of interfaces).
    """
    mid = state.x_ref[state.interface_nodes[on_surface][:, :2]].mean(axis=1)
    trace = []
    for b in np.unique(np.floor(mid[:, 0] / width)):
        k = np.floor(mid[:, 0] / width) == b
        trace.append(mid[k][np.argmin(mid[k, 1])].tolist())
    return trace


def slipped_interfaces(state: DiscreteState, thresholds: Sequence[float],
                       element_sets: Mapping[str, np.ndarray]) -> dict[str, dict[str, int]]:
    """Count the failed interfaces that slipped at least each threshold t [m].

    For each t (key f"{t:g}"): the failed interfaces that slipped at least t ("interfaces")
    and, per named element set (an (n_elements,) mask), how many of them have an element of
    the set on either side.
    """
    slip = interface_slip(state)
    beside = {name: interfaces_of(state, mask) for name, mask in element_sets.items()}
    out = {}
    for t in thresholds:
        slipped = ~state.interface_intact & (slip >= t)
        out[f"{t:g}"] = {"interfaces": int(slipped.sum()),
                         **{name: int((slipped & b).sum()) for name, b in beside.items()}}
    return out


@dataclass(frozen=True)
class SlipSurface:
    """The slip surface of a run: the failed interfaces that slipped at least ``min_slip``.

    Attributes:
        min_slip: the slip that puts a failed interface on the surface [m].
        interfaces: (n_interfaces,) True for its interfaces (:func:`slip_surface`).
        by_threshold: :func:`slipped_interfaces` at ``min_slip`` and the further thresholds.
        trace: :func:`slip_trace` of the surface.
    """

    min_slip: float
    interfaces: np.ndarray
    by_threshold: dict[str, dict[str, int]]
    trace: list[list[float]]

    @classmethod
    def of(cls, state: DiscreteState, min_slip: float, element_sets: Mapping[str, np.ndarray],
           thresholds: Sequence[float] = (0.5, 1.0, 2.0)) -> SlipSurface:
        """Measure the slip surface of ``state``.

        Args:
            state: the state at the end of the run.
            min_slip: slip that puts a failed interface on the surface [m].
            element_sets: named (n_elements,) masks whose interfaces on the surface are
                counted (:func:`slipped_interfaces`).
            thresholds: further slips [m] at which the failed interfaces are counted.
        """
        on_surface = slip_surface(state, min_slip)
        by_threshold = slipped_interfaces(state, (min_slip, *thresholds), element_sets)
        return cls(min_slip, on_surface, by_threshold, slip_trace(state, on_surface))

    @property
    def through(self) -> dict[str, int]:
        """Counts at ``min_slip``: "interfaces" and the interfaces of each element set."""
        return self.by_threshold[f"{self.min_slip:g}"]

    def lines(self, state: DiscreteState) -> dict[str, np.ndarray]:
        """The surface's interfaces [m] as ``lines`` of :func:`plot_configuration`.

        One segment per interface, on its first element's side, in the current geometry;
        labelled with ``min_slip``.
        """
        segments = state.x[state.interface_nodes[self.interfaces][:, :2]]
        return {f"slip surface: slipped >= {self.min_slip:g} m": segments}

    def summary(self) -> dict[str, Any]:
        """Its measures for a case's summary.

        "slip_surface_interfaces", the interfaces of each element set ("slip_surface_<set>",
        :attr:`through`), "slip_surface_trace_m", "slipped_interfaces_by_threshold_m".
        """
        return {"slip_surface_interfaces": int(self.interfaces.sum()),
                **{f"slip_surface_{name}": n for name, n in self.through.items()
                   if name != "interfaces"},
                "slip_surface_trace_m": self.trace,
                "slipped_interfaces_by_threshold_m": self.by_threshold}

    def checks(self, sets: Mapping[str, str]) -> dict[str, Check]:
        """Checks "slip_surface_through_<set>": the surface runs through each set.

        That is, an interface on the surface has an element of the set on a side. ``sets``:
        the element sets measured by :meth:`of`, by name -> the set's element in words
        (e.g. "a clay element").
        """
        return {f"slip_surface_through_{name}": Check(
            float(self.through[name] > 0), 1.0, 0.0, "-",
            f"failed interfaces slipped >= {self.min_slip} m with {element}")
            for name, element in sets.items()}


class Crack(NamedTuple):
    """The failed interfaces that run down from a surface (:func:`crack_from_top`).

    Attributes:
        interfaces: (n_interfaces,) True for the crack's interfaces.
        top: the highest reference elevation in the column searched [m].
        depth: how far below ``top`` the crack reaches (its lowest interface end) [m]; 0
            when there is no crack.
        max_opening: the largest :func:`interface_opening` of its interfaces [m] (0: none).
        max_slip: the largest :func:`interface_slip` of its interfaces [m] (0: none).
    """

    interfaces: np.ndarray
    top: float
    depth: float
    max_opening: float
    max_slip: float


def _column_top(state: DiscreteState, column: tuple[float, float]
                ) -> tuple[np.ndarray, np.ndarray, float]:
    """The interfaces' reference ends, which of them lie in a column, and the column's top.

    Returns (ends (n_if, 2, 2), in ``column`` by midpoint (n_if,), highest reference
    elevation of a node in ``column`` [m]).
    """
    ends = state.x_ref[state.interface_nodes[:, :2]]
    mid = ends.mean(axis=1)
    in_column = (mid[:, 0] > column[0]) & (mid[:, 0] < column[1])
    nodes = np.unique(state.element_nodes)
    column_nodes = nodes[(state.x_ref[nodes, 0] > column[0]) & (state.x_ref[nodes, 0] < column[1])]
    if column_nodes.size == 0:
        raise ValueError(f"no node in the column {column} m (reference x): give the x-range "
                         "of the surface to search")
    return ends, in_column, float(state.x_ref[column_nodes, 1].max())


def surface_opening(state: DiscreteState, column: tuple[float, float], *,
                    top_depth: float) -> float:
    """A crack's width at the surface [m]: the largest opening of a failed interface.

    Of the failed interfaces in ``column`` with an end within ``top_depth`` [m] of its highest
    point (:func:`crack_from_top`'s top); 0 when none stands open (or none reaches the top).
    """
    return _surface_opening(state, _column_top(state, column), interface_opening(state),
                            top_depth)


def _at_top(where: tuple[np.ndarray, np.ndarray, float], top_depth: float) -> np.ndarray:
    """The interfaces in the column with an end within ``top_depth`` [m] of its top.

    ``where``: :func:`_column_top`'s.
    """
    ends, in_column, top = where
    return in_column & (ends[:, :, 1].max(axis=1) >= top - top_depth)


def _surface_opening(state: DiscreteState, where: tuple[np.ndarray, np.ndarray, float],
                     opening: np.ndarray, top_depth: float) -> float:
    """:func:`surface_opening` on :func:`_column_top`'s ``where`` and the openings."""
    at_top = ~state.interface_intact & _at_top(where, top_depth)
    return max(float(opening[at_top].max(initial=0.0)), 0.0)


def crack_from_top(state: DiscreteState, column: tuple[float, float], *, min_opening: float,
                   top_depth: float) -> Crack:
    """The open failed interfaces connected to the top of a column, e.g. a crack from a crest.

    Within the column ``column[0] < x < column[1]`` (reference midpoints) [m]: the failed
    interfaces whose sides stand apart by at least ``min_opening`` [m] along their normal
    (:func:`interface_opening`: a crack, not a slip surface sliding closed), those with an
    end within ``top_depth`` [m] of the column's highest point, and every such interface
    joined to them through shared vertices (reference geometry). Its depth is measured from
    that highest point.
    """
    return _crack(state, _column_top(state, column), interface_opening(state),
                  min_opening, top_depth)


def _crack(state: DiscreteState, where: tuple[np.ndarray, np.ndarray, float],
           opening: np.ndarray, min_opening: float, top_depth: float) -> Crack:
    """:func:`crack_from_top` on :func:`_column_top`'s ``where`` and the openings."""
    ends, in_column, top = where
    n = state.interface_nodes
    candidate = np.flatnonzero(~state.interface_intact & in_column & (opening >= min_opening))
    vertices = {int(i): [tuple(np.round(v, 9)) for v in ends[i]] for i in candidate}
    by_vertex: dict[tuple, list[int]] = {}
    for i, pair in vertices.items():
        for key in pair:
            by_vertex.setdefault(key, []).append(i)
    at_top = _at_top(where, top_depth)
    found = {i for i in vertices if at_top[i]}
    todo = list(found)
    while todo:  # grow through shared vertices
        for key in vertices[todo.pop()]:
            for j in by_vertex[key]:
                if j not in found:
                    found.add(j)
                    todo.append(j)
    mask = np.zeros(n.shape[0], dtype=bool)
    mask[sorted(found)] = True
    if not found:
        return Crack(mask, top, 0.0, 0.0, 0.0)
    return Crack(mask, top, top - float(ends[mask, :, 1].min()), float(opening[mask].max()),
                 float(interface_slip(state)[mask].max()))


class CrackWatch(Observer):
    """The deepest crack from the top of a column over a run (:func:`crack_from_top` at checks).

    A crack that opens during a slide may close again before rest, where
    :func:`crack_from_top` alone would not see it. At every check of the run (the solver's
    ``check_every`` steps) the crack is measured; the watch keeps when one was first open, the
    deepest (its time, depth, interfaces and largest opening) and the largest opening of any.
    It also keeps the widest opening at the surface, whatever ``min_opening``: the largest
    opening of a failed interface with an end within ``top_depth`` of the top (a crack's width
    at the crest, as surveyed on a dam). It only reads the state, and is part of the solver's
    checkpoints.

    Args:
        column, min_opening, top_depth: as :func:`crack_from_top`.
    """

    def __init__(self, column: tuple[float, float], *, min_opening: float,
                 top_depth: float) -> None:
        """An empty watch: no crack seen yet."""
        self.column, self.min_opening, self.top_depth = column, min_opening, top_depth
        self.first_time = math.nan  # first check with a crack [s] (nan: none yet)
        self.deepest_time = math.nan  # check with the deepest crack [s]
        self.depth = 0.0  # the deepest crack's depth [m]
        self.interfaces = 0  # its interfaces
        self.opening_at_deepest = 0.0  # its largest opening [m]
        self.max_opening = 0.0  # the largest opening of any crack seen [m]
        self.surface_opening = 0.0  # the widest failed interface at the top [m]
        self.checks = 0  # checks watched
        self._where: tuple[np.ndarray, np.ndarray, float] | None = None  # the column's top

    def checked(self, solver: ExplicitSolver, ledger: EnergyLedger) -> None:
        """Measure the crack now; keep it if it is the first or the deepest."""
        state = solver.state
        if self._where is None:  # reference geometry: the same at every check
            self._where = _column_top(state, self.column)
        opening = interface_opening(state)
        crack = _crack(state, self._where, opening, self.min_opening, self.top_depth)
        self.checks += 1
        self.surface_opening = max(self.surface_opening,
                                   _surface_opening(state, self._where, opening, self.top_depth))
        if not crack.interfaces.any():
            return
        if math.isnan(self.first_time):
            self.first_time = state.time
        self.max_opening = max(self.max_opening, crack.max_opening)
        if crack.depth > self.depth:
            self.depth, self.deepest_time = crack.depth, state.time
            self.interfaces = int(crack.interfaces.sum())
            self.opening_at_deepest = crack.max_opening

    @property
    def seen(self) -> bool:
        """A crack from the top was open at a check."""
        return not math.isnan(self.first_time)

    def summary(self, prefix: str) -> dict[str, Any]:
        """Its figures for a summary, keys ``{prefix}_...`` (times [s], lengths [m]).

        "_seen", "_first_time_s", "_deepest_m", "_deepest_time_s", "_deepest_interfaces",
        "_deepest_max_opening_m", "_max_opening_m", "_surface_opening_m", "_checks" (times
        None when none seen).
        """
        def time(t: float) -> float | None:
            return None if math.isnan(t) else t

        return {f"{prefix}_seen": self.seen, f"{prefix}_first_time_s": time(self.first_time),
                f"{prefix}_deepest_m": self.depth,
                f"{prefix}_deepest_time_s": time(self.deepest_time),
                f"{prefix}_deepest_interfaces": self.interfaces,
                f"{prefix}_deepest_max_opening_m": self.opening_at_deepest,
                f"{prefix}_max_opening_m": self.max_opening,
                f"{prefix}_surface_opening_m": self.surface_opening,
                f"{prefix}_checks": self.checks}

    _FIELDS = ("first_time", "deepest_time", "depth", "interfaces", "opening_at_deepest",
               "max_opening", "surface_opening", "checks")

    def state(self) -> dict[str, np.ndarray]:
        """What it has seen, for checkpoints."""
        return {"seen": np.array([float(getattr(self, f)) for f in self._FIELDS])}

    def restore(self, saved: dict[str, np.ndarray]) -> None:
        """Continue from :meth:`state`."""
        if "seen" not in saved or len(saved["seen"]) != len(self._FIELDS):
            raise ValueError("the checkpoint has no crack watch's state of this version "
                             "(written by another version of hybrid, or with other "
                             "observers): rerun without --resume")
        for f, v in zip(self._FIELDS, saved["seen"], strict=True):
            setattr(self, f, int(v) if f in ("interfaces", "checks") else float(v))


def interfaces_of(state: DiscreteState, elements: np.ndarray) -> np.ndarray:
    """(n_interfaces,) True for the interfaces with an element of ``elements`` on a side.

    ``elements``: an (n_elements,) mask.
    """
    return np.asarray(elements, dtype=bool)[state.interface_elements].any(axis=1)


def interfaces_between(state: DiscreteState, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """(n_interfaces,) True for the interfaces between two zones: the face between them.

    An element of ``a`` on one side and one of ``b`` on the other (``a``, ``b``:
    (n_elements,) masks).
    """
    a, b = np.asarray(a, dtype=bool), np.asarray(b, dtype=bool)
    i, j = state.interface_elements[:, 0], state.interface_elements[:, 1]
    return (a[i] & b[j]) | (a[j] & b[i])


def slip_along(state: DiscreteState, interfaces: np.ndarray, min_slip: float
               ) -> dict[str, float]:
    """How much of a line of interfaces (e.g. the face between two zones) has slipped.

    ``interfaces``: (n_interfaces,) mask; ``min_slip``: the slip that puts a failed interface
    on the slip surface [m] (:func:`slip_surface`). Returns {"interfaces": their number,
    "length_m": their length in the reference geometry [m], "slipped_interfaces" and
    "slipped_length_m": those on the slip surface, "max_slip_m": the largest slip of a failed
    one (0: none failed)}.
    """
    mask = np.asarray(interfaces, dtype=bool)
    ends = state.x_ref[state.interface_nodes[:, :2]]
    length = np.linalg.norm(ends[:, 1] - ends[:, 0], axis=1)
    on = mask & slip_surface(state, min_slip)
    failed = mask & ~state.interface_intact
    return {"interfaces": int(mask.sum()), "length_m": float(length[mask].sum()),
            "slipped_interfaces": int(on.sum()), "slipped_length_m": float(length[on].sum()),
            "max_slip_m": float(interface_slip(state)[failed].max(initial=0.0))}


def top_interfaces(state: DiscreteState, column: tuple[float, float], *,
                   top_depth: float) -> np.ndarray:
    """(n_interfaces,) True for the interfaces at the top of a column (e.g. a crest).

    Those in ``column[0] < x < column[1]`` (reference midpoints) [m] with an end within
    ``top_depth`` [m] of the column's highest node, as :func:`surface_opening` takes them.
    """
    return _at_top(_column_top(state, column), top_depth)


class FailureOnset(NamedTuple):
    """When and how the bonds of a set of interfaces began to fail (:func:`failure_onset`).

    Attributes:
        first_time: state time of the first splitting check that failed one of them [s]
            (``DiscreteState.interface_failure_time``; nan when none failed in a run).
        first_modes: {mode name (``ties.MODE_NAMES``): count} of those failed at that check.
        failed: failed interfaces of the set (recorded or not).
        modes: {mode name: count} of every failed interface of the set (none at 0 omitted).
    """

    first_time: float
    first_modes: dict[str, int]
    failed: int
    modes: dict[str, int]

    def summary(self) -> dict[str, Any]:
        """Its fields for a case's summary (nan first time as None)."""
        return {"first_failure_s": None if math.isnan(self.first_time) else self.first_time,
                "first_failure_modes": self.first_modes, "failed": self.failed,
                "failed_by_mode": self.modes}


def failure_onset(state: DiscreteState, where: Mapping[str, np.ndarray]
                  ) -> dict[str, FailureOnset]:
    """Where and how bonds began to fail: :class:`FailureOnset` of each named interface set.

    ``where``: name -> (n_interfaces,) mask (:func:`interfaces_of`, :func:`top_interfaces`).
    From the time and mode the solver recorded at the splitting check that failed each
    interface (``interface_failure_time``, ``interface_mode``): the failure is placed to
    within one splitting interval (``RunOptions.split_every`` steps). The first time is
    unknown (nan) when none failed in a run, and when one failed in a run without a time
    (a run resumed from a checkpoint written before times were recorded).
    """
    failed = ~state.interface_intact
    out = {}
    for name, mask in where.items():
        f = failed & np.asarray(mask, dtype=bool)
        times = state.interface_failure_time[f]
        modes = state.interface_mode[f]
        recorded = ~np.isnan(times)
        if not recorded.any() or (modes[~recorded] > 0).any():
            out[name] = FailureOnset(math.nan, {}, int(f.sum()), mode_counts(modes))
            continue
        first = float(times[recorded].min())
        out[name] = FailureOnset(first, mode_counts(modes[times == first]), int(f.sum()),
                                 mode_counts(modes))
    return out


def first_failures(state: DiscreteState, where: Mapping[str, np.ndarray]
                   ) -> tuple[float, dict[str, int]]:
    """The first splitting check that failed a bond: its time and where those bonds lie.

    Returns (time [s], nan when :func:`failure_onset` of all interfaces does not know it;
    {"interfaces": how many failed at it, each name of ``where`` (interface masks): how many
    of them lie in that set, "elsewhere": how many in none of the sets}).
    """
    everywhere = np.ones(state.interface_intact.shape[0], dtype=bool)
    first = failure_onset(state, {"": everywhere})[""].first_time
    at_first = ~state.interface_intact & (state.interface_failure_time == first)  # nan: none
    inside = np.zeros_like(everywhere, dtype=bool)
    counts = {"interfaces": int(at_first.sum())}
    for name, mask in where.items():
        counts[name] = int((at_first & mask).sum())
        inside |= np.asarray(mask, dtype=bool)
    counts["elsewhere"] = int((at_first & ~inside).sum())
    return first, counts


class SlopeMovement(NamedTuple):
    """How far a slope moved (:meth:`SlopeMarks.movement`) [m].

    Attributes:
        toe_dx: x-displacement of the toe node (negative towards -x).
        crest_drop: mean settlement of the crest nodes (positive down).
        run_out: largest movement of a node of the slope towards the side it faces.
    """

    toe_dx: float
    crest_drop: float
    run_out: float


@dataclass(frozen=True)
class SlopeMarks:
    """Nodes of a slope picked at the start of a run, to measure its movement at the end.

    Displacements count from the state's reference geometry (``x_ref``: the start of the
    discrete phase).

    Attributes:
        nodes: the slope's nodes.
        crest: the nodes near the top of the slope (see :meth:`pick`).
        toe: the node furthest towards the side the slope faces.
        facing: -1 when the slope faces -x (it runs out towards -x), +1 when it faces +x.
    """

    nodes: np.ndarray
    crest: np.ndarray
    toe: int
    facing: int = -1

    @classmethod
    def pick(cls, state: DiscreteState, elements: np.ndarray, *,
             crest_x: tuple[float, float], crest_depth: float = 0.5,
             facing: int = -1) -> SlopeMarks:
        """Pick the nodes of the slope made of ``elements`` in the current geometry.

        Args:
            state: the state at the start of the run.
            elements: (n_elements,) mask of the slope's elements.
            crest_x: the crest's x range [m] (open interval).
            crest_depth: the crest nodes lie less than this below the slope's highest node
                [m].
            facing: -1 (the toe is the node of smallest x) or +1 (largest x).
        """
        if facing not in (-1, 1):
            raise ValueError(f"facing = {facing!r}: -1 (the slope faces -x) or +1 (+x)")
        nodes = np.unique(state.element_nodes[elements])
        x, y = state.x[nodes, 0], state.x[nodes, 1]
        top = float(y.max())
        crest = nodes[(y > top - crest_depth) & (x > crest_x[0]) & (x < crest_x[1])]
        toe = int(nodes[np.argmax(facing * x)])
        return cls(nodes, crest, toe, facing)

    def movement(self, state: DiscreteState) -> SlopeMovement:
        """Toe, crest and largest movement of the slope in ``state``."""
        u = state.x - state.x_ref
        return SlopeMovement(toe_dx=float(u[self.toe, 0]),
                             crest_drop=-float(np.mean(u[self.crest, 1])),
                             run_out=float(np.max(self.facing * u[self.nodes, 0])))


@dataclass(frozen=True)
class FootingMarks:
    """A footing's nodes and the ground surface beside it, to measure settlement and heave.

    Both count from the state's reference geometry (``x_ref``: the start of the discrete
    phase); ``offset`` [m] is the settlement before it (the continuum's, at handover), so that
    :meth:`total_settlement` counts from the start of the analysis.

    Attributes:
        footing: the footing's nodes (their mean vertical movement is the settlement).
        surface: the ground-surface nodes beside the footing (their largest rise is the heave).
        offset: settlement before the start of the discrete phase [m].
    """

    footing: np.ndarray
    surface: np.ndarray
    offset: float = 0.0

    @classmethod
    def pick(cls, state: DiscreteState, footing: np.ndarray, surface: np.ndarray, *,
             beside: float, offset: float = 0.0) -> FootingMarks:
        """The footing nodes and the ``surface`` nodes whose x lies beyond ``beside`` [m]."""
        footing = np.asarray(footing, dtype=np.int64)
        surface = np.asarray(surface, dtype=np.int64)
        if footing.size == 0 or surface.size == 0:
            raise ValueError("FootingMarks.pick: the footing and the surface need nodes "
                             "(check the boundary names of the mesh)")
        beyond = surface[state.x_ref[surface, 0] > beside]
        if beyond.size == 0:
            raise ValueError(f"FootingMarks.pick: no surface node beyond x = {beside} m")
        return cls(footing, beyond, float(offset))

    def settlement(self, state: DiscreteState) -> float:
        """Mean downward movement of the footing nodes since the start of the phase [m]."""
        return -float(np.mean(state.x[self.footing, 1] - state.x_ref[self.footing, 1]))

    def total_settlement(self, state: DiscreteState) -> float:
        """:meth:`settlement` plus the settlement before the phase (``offset``) [m]."""
        return self.offset + self.settlement(state)

    def heave(self, state: DiscreteState) -> float:
        """Largest upward movement of the ground surface beside the footing [m]."""
        return float(np.max(state.x[self.surface, 1] - state.x_ref[self.surface, 1]))


class Deposit(NamedTuple):
    """Where a mass spread from a back wall came to rest (:func:`deposit`).

    Attributes:
        runout: distance [m] of the far end of the deposit from the back wall
            (``direction`` * (x - wall)).
        height: highest point [m] of the deposit above the floor.
        elements: (n,) indices of the elements in the deposit.
        detached: number of elements beyond the deposit's far end (not counted in it).
        profile: (m, 2) surface [m] of the deposit: bin centres (distance from the wall, as
            ``runout``) and the highest node in each bin of width ``bin_width`` (0 where no
            node lies in the bin).
    """

    runout: float
    height: float
    elements: np.ndarray
    detached: int
    profile: np.ndarray


def deposit(state: DiscreteState, elements: np.ndarray, *, wall_x: float = 0.0,
            floor_y: float = 0.0, bin_width: float, direction: int = 1) -> Deposit:
    """The deposit of ``elements`` (an (n_elements,) mask) spread from a wall at ``wall_x``.

    The deposit is the run of elements whose x-extents overlap or touch without a gap, from
    the wall outwards: the union of the elements' x-extents, followed from the element nearest
    the wall until the first stretch of bare floor. An element flung beyond such a stretch is
    not part of it (``detached``), however far it went: the run-out is the far end of the
    continuous mass. Elements wholly behind the wall (a dam's downstream half, seen from its
    axis spreading upstream) are neither: the walk starts at the wall's side of the mass, so
    a gap behind the wall does not cut it.
    Distances count from the wall, ``direction`` * (x - ``wall_x``) (``direction`` 1: the mass
    spread towards +x; -1: towards -x), and from the floor (y - ``floor_y``) [m].
    """
    if not bin_width > 0.0:
        raise ValueError(f"deposit: bin_width = {bin_width!r} must be > 0 m")
    if direction not in (1, -1):
        raise ValueError(f"deposit: direction = {direction!r} must be 1 (towards +x) or -1")
    idx = np.flatnonzero(np.asarray(elements, dtype=bool))
    xe = direction * (state.x[state.element_nodes[idx], 0] - wall_x)
    ahead = xe.max(axis=1) > 0.0  # some of the element on the side the mass spreads to
    idx, xe = idx[ahead], xe[ahead]
    if idx.size == 0:
        raise ValueError("deposit: no element of the mask lies on the side the mass spreads "
                         "to (check the element set, wall_x and direction)")
    lo, hi = xe.min(axis=1), xe.max(axis=1)
    order = np.argsort(lo, kind="stable")
    reach = float(lo[order[0]])  # the deposit starts at the element nearest the wall
    for k in order:
        if lo[k] > reach:
            break
        reach = max(reach, float(hi[k]))
    inside = idx[lo <= reach]
    nodes = np.unique(state.element_nodes[inside])
    x = direction * (state.x[nodes, 0] - wall_x)
    y = state.x[nodes, 1] - floor_y
    n_bins = max(int(np.ceil(reach / bin_width)), 1)
    b = np.clip((x / bin_width).astype(np.int64), 0, n_bins - 1)
    top = np.zeros(n_bins)
    np.maximum.at(top, b, np.maximum(y, 0.0))
    centres = (np.arange(n_bins) + 0.5) * bin_width
    return Deposit(reach, float(y.max()), inside, int(idx.size - inside.size),
                   np.column_stack([centres, top]))


def mean_displacement(state: DiscreteState, elements: np.ndarray) -> tuple[float, float]:
    """Mean displacement (x, y) [m] of the nodes of ``elements`` (an (n_elements,) mask).

    Counted from the state's reference geometry (``x_ref``: the start of the discrete phase).
    """
    u = (state.x - state.x_ref)[state.element_nodes[elements]]
    return float(np.mean(u[..., 0])), float(np.mean(u[..., 1]))


def moving_zone_back(state: DiscreteState, elements: np.ndarray, height: float, size: float,
                     moved: float) -> tuple[float, float]:
    """Inclination [deg] and base intercept a [m] of the back of the zone moved >= ``moved`` [m].

    The inclination is measured from the horizontal. The face is at x = 0 with the soil at
    x > 0 (the H3 wall). At each level 0 <= y < ``height`` (bins of ``size``, reference shape)
    the elements of ``elements`` (mask) are walked out from the face in order of their
    reference centroids; the back of the zone is the last one whose centroid has moved
    ``moved`` or more before the first that has not (so that a fragment flung beyond the
    scarp does not count). The least-squares line x = a + y cot(angle) through them;
    (nan, nan) with fewer than three levels.
    """
    en = state.element_nodes[elements]
    ref = state.x_ref[en].mean(axis=1)
    shift = state.x[en].mean(axis=1) - ref
    moving = np.hypot(shift[:, 0], shift[:, 1]) >= moved
    ys, xs = [], []
    for lo in np.arange(0.0, height, size):
        level = np.flatnonzero((ref[:, 1] >= lo) & (ref[:, 1] < lo + size) & (ref[:, 0] > 0.0))
        level = level[np.argsort(ref[level, 0], kind="stable")]
        if level.size == 0 or not moving[level[0]]:
            continue
        still = np.flatnonzero(~moving[level])
        back = level[still[0] - 1] if still.size else level[-1]
        ys.append(lo + 0.5 * size)
        xs.append(float(ref[back, 0]))
    if len(ys) < 3:
        return float("nan"), float("nan")
    cot, a = np.polyfit(ys, xs, 1)
    return float(np.degrees(np.arctan2(1.0, cot))), float(a)
