"""Staged construction: cell groups split into lifts, placed one by one, strain from placement.

:func:`split_into_lifts` cuts named cell groups into lifts by the elevation of each cell's
centroid ("core" -> "core:1", "core:2", ...); :func:`build_in_lifts` places the lifts one
after another on a :class:`~hybrid.continuum.plastic.PlasticSolver` (each stress-free, its
weight ramped in), with an optional strength-reduction factor of safety after each, and stops
at the first lift whose full weight finds no equilibrium (the collapse); :func:`lift_materials`
gives each lift its group's material. :class:`PlacementStrain`
counts the strain of the fill from its placement, which the total displacement cannot give (a
lift's nodes start at zero while the nodes at its base have already moved).
"""

from __future__ import annotations

import time
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any, TypeVar

import numpy as np
from dolfinx import fem
from mpi4py import MPI

from hybrid.continuum.analysis import RUNAWAY_JUMP, AtRest, at_rest_checks, largest_nodal_norm
from hybrid.continuum.fields import strain
from hybrid.continuum.plastic import PlasticSolver
from hybrid.continuum.state import ContinuumState
from hybrid.continuum.strength_reduction import SafetyResult, StrengthSearch, factor_of_safety
from hybrid.geometry import GeometryError, MeshData
from hybrid.io import Check
from hybrid.references import SlipCircle

__all__ = ["split_into_lifts", "lift_groups", "lift_materials", "PlacementStrain",
           "Construction", "ground_stage", "build_in_lifts"]

_STRIDE = 100  # tag of lift k of a group tagged t: _STRIDE * t + k
T = TypeVar("T")


def split_into_lifts(mesh: MeshData, groups: Sequence[str], tops: Sequence[float]) -> MeshData:
    """The mesh with each of ``groups`` split into lifts "name:1" ... "name:n".

    ``tops``: rising top elevations of the n lifts [m]. A cell is in the first lift whose top
    is above its centroid (above the last top: the last lift); cut the geometry at the tops so
    that no cell straddles two lifts. The other groups keep their names; a lift without cells
    has no group. Same dolfinx mesh, new cell tags; collective under MPI.
    """
    from dolfinx.mesh import compute_midpoints, meshtags

    levels = np.asarray(tops, dtype=float)
    if not 0 < len(levels) < _STRIDE or np.any(np.diff(levels) <= 0.0):
        raise ValueError(f"lift tops {levels.tolist()}: 1 to {_STRIDE - 1} rising elevations")
    msh, tags = mesh.mesh, mesh.cell_tags
    mid = compute_midpoints(msh, 2, tags.indices)
    lift = (np.minimum(np.searchsorted(levels, mid[:, 1], side="right"), len(levels) - 1)
            + 1).astype(np.int32)
    names = {tag: name for name, tag in mesh.cell_groups.items()}
    split = [mesh.cell_tag(g) for g in groups]
    kept = set(names) - set(split)
    if any(_STRIDE * t + k in kept for t in split for k in range(1, len(levels) + 1)):
        raise GeometryError(f"cell tags {sorted(kept)} clash with the tags of the lifts")
    values = np.where(np.isin(tags.values, split), _STRIDE * tags.values + lift,
                      tags.values).astype(np.int32)
    present = np.unique(np.concatenate(mesh.comm.allgather(np.unique(values)))).tolist()
    new = {(names[v] if v in kept else f"{names[v // _STRIDE]}:{v % _STRIDE}"): v
           for v in present}
    return MeshData(msh, meshtags(msh, 2, tags.indices, values), mesh.facet_tags, new,
                    mesh.facet_groups, mesh.cell_type)


def lift_groups(mesh: MeshData, lift: int) -> list[str]:
    """Cell groups of one lift (1-based) of a :func:`split_into_lifts` mesh, sorted."""
    return sorted(g for g in mesh.cell_groups if g.endswith(f":{lift}"))


def lift_materials(mesh: MeshData, table: Mapping[str, T]) -> dict[str, T]:
    """The material of every cell group of a :func:`split_into_lifts` mesh, for a ``Model``.

    A lift ("core:3") takes its group's ("core") from ``table``; a group not split, its own.
    """
    return {name: table[name.split(":")[0]] for name in mesh.cell_groups}


class PlacementStrain:
    """Strain counted from placement.

    ``total`` (n_owned_cells, nqp, 4) [-] (Voigt, as the stress) is the sum over stages of
    eps(du) at the quadrature points of the cells active in each stage.
    """

    def __init__(self, solver: PlasticSolver) -> None:
        self.solver = solver
        self.du = fem.Function(solver.disc.V)
        self.expr = fem.Expression(strain(self.du), solver.disc.points)
        self.total = np.zeros((solver.sspace.num_cells, solver.disc.num_points, 4))

    def add(self, du: np.ndarray) -> None:
        """Add the strain of a displacement increment (dof values) in the active cells."""
        self.du.x.array[:] = du
        self.du.x.scatter_forward()
        values = self.expr.eval(np.arange(self.total.shape[0], dtype=np.int32))
        active = self.solver.active
        self.total[active] += values.reshape(self.total.shape)[active]

    def cell_mean(self, state: ContinuumState) -> np.ndarray:
        """Area-weighted cell means (n_owned_cells, 4) [-]."""
        return state.cell_mean(self.total)


@dataclass
class Construction:
    """What :func:`build_in_lifts` did.

    Attributes:
        stages: one record per lift tried (see :func:`build_in_lifts`).
        completed: every lift carried its full weight.
        max_unplaced_stress: largest |stress| in lifts not yet placed, after any lift [kPa]
            (zero when staging works).
        strain: the strain from placement at the end.
        safety: the last factor of safety (None when none was asked for).
        safety_active: the cells in place when it was found.
        safety_wall_time: seconds spent in the strength reduction.
        before_collapse: when a lift collapsed, the solver's snapshot of the last complete
            lift (``PlasticSolver.restore`` it); None when every lift was placed.
        base_level: the level below the first lift [m].
        unit: the elevations' unit in the stage records' keys ("top_<unit>").
    """

    stages: list[dict[str, Any]]
    completed: bool
    max_unplaced_stress: float
    strain: PlacementStrain
    safety: SafetyResult | None
    safety_active: np.ndarray
    safety_wall_time: float
    before_collapse: tuple | None
    base_level: float = 0.0
    unit: str = "m"

    @property
    def complete(self) -> list[dict[str, Any]]:
        """The records of the lifts that carried their full weight."""
        return [st for st in self.stages if st["completed"]]

    @property
    def level_carried(self) -> float:
        """Top of the last complete lift (``base_level`` when none was) [m]."""
        done = self.complete
        return done[-1][f"top_{self.unit}"] if done else self.base_level

    @property
    def collapse(self) -> dict[str, Any] | None:
        """The collapsing lift (None when every lift was placed).

        "lift", "top_<unit>", "weight_carried" (the fraction of its weight in equilibrium),
        "runaway_ratio" (d u / d weight of its last converged increment over its first's;
        None with fewer than two increments), "runaway" (that ratio at least
        :data:`RUNAWAY_JUMP`: the displacement ran away, a collapse; None when unknown) and
        "softening" (a material of the model softens). Without a run-away the stop is a sharp
        limit (the last part of a mechanism yielding at once), a softening peak, a stop inside
        a flowing section (the ratio compares the lift's own increments), or Newton stalling:
        the lift's record's "path" and a run with a smaller least increment tell them apart.
        """
        if self.completed:
            return None
        last = self.stages[-1]
        return {"lift": last["lift"], f"top_{self.unit}": last[f"top_{self.unit}"],
                "weight_carried": last["weight_placed"], "runaway_ratio": last["runaway_ratio"],
                "runaway": (None if last["runaway_ratio"] is None
                            else last["runaway_ratio"] >= RUNAWAY_JUMP),
                "softening": last["softening"]}

    def history(self, key: str, item: str | None = None) -> list[tuple[float, Any]]:
        """(top of the lift, its record's ``key``) of every complete lift.

        E.g. a value recorded by the ``monitor`` of :func:`build_in_lifts`; with ``item``,
        the entry ``item`` of a mapping recorded under ``key`` (one of several points).
        """
        return [(st[f"top_{self.unit}"], st[key] if item is None else st[key][item])
                for st in self.complete]

    def at_levels(self, key: str, levels: Sequence[float]) -> dict[str, Any]:
        """The record's ``key`` of the complete lift topped at each of ``levels``.

        Keyed by the level written with ``:g`` (e.g. "198"), None where no complete lift has
        that top (e.g. above a collapse): the values a publication gives at fixed levels.
        """
        history = self.history(key)
        return {f"{z:g}": next((value for top, value in history if top == z), None)
                for z in levels}

    def checks(self) -> dict[str, Check]:
        """The construction's own check: no stress in the fill not yet placed.

        "max_stress_in_unplaced_lifts": exactly zero, after every lift.
        """
        return {"max_stress_in_unplaced_lifts": Check(self.max_unplaced_stress, 0.0, 0.0, "kPa",
                                                      "exactly zero")}

    def safety_report(self, *, measures: Mapping[str, Any] | None = None,
                      groups: Mapping[str, np.ndarray] | None = None,
                      circle: SlipCircle | None = None) -> dict[str, Any]:
        """The last factor of safety for a summary (empty when none was asked for).

        ``SafetyResult.as_dict``, then the lift it was found after ("after_lift"), that
        lift's top ("fill_level_<unit>"), the seconds spent in strength reduction
        ("wall_time_s"), the caller's own ``measures``, the yielded fraction of each of
        ``groups`` at F (``ContinuumState.yielded_fractions`` of the safety state) and, with a
        limit-equilibrium ``circle`` of the same section, its figures ("bishop").
        """
        if self.safety is None:
            return {}
        last = [st for st in self.stages if "factor_of_safety" in st][-1]
        fractions = {} if self.safety.state is None or groups is None else (
            self.safety.state.yielded_fractions(groups))
        return {**self.safety.as_dict(), "after_lift": last["lift"],
                f"fill_level_{self.unit}": last[f"top_{self.unit}"],
                "wall_time_s": self.safety_wall_time, **(measures or {}), **fractions,
                **({} if circle is None else {"bishop": circle.as_dict()})}

    def safety_checks(self, circle: SlipCircle | None) -> dict[str, Check]:
        """The last F against a limit-equilibrium ``circle`` ("fos_vs_bishop", no bar).

        ``circle``: a search over circles of the same section and lift. Empty without either.
        """
        if self.safety is None or circle is None:
            return {}
        return {"fos_vs_bishop": Check(
            self.safety.factor, circle.factor, None, "-",
            "this project's Bishop simplified search over circles, same section and lift")}

    def report(self, solver: PlasticSolver, state: ContinuumState, wall_time: float, *,
               measures: Mapping[str, Any] | None = None,
               groups: Mapping[str, np.ndarray] | None = None) -> dict[str, Any]:
        """The construction in numbers for a summary.

        "completed", the "stages" records, "fill_level_<unit>" (:attr:`level_carried`; the
        unit in lower case, e.g. "fill_level_m_od"), "collapsing_lift" (:attr:`collapse`),
        then the caller's own ``measures`` of the state (e.g. its extreme displacements),
        "yielded_cells" of ``state`` (all ranks), the yielded fraction of each of ``groups``
        (``ContinuumState.yielded_fractions``), the solver's "newton_iterations" in all and
        ``wall_time`` ("wall_time_s"). ``state``: the state the numbers come from
        (:meth:`last_equilibrium`). Collective.
        """
        return {"completed": self.completed, "stages": self.stages,
                f"fill_level_{self.unit.lower()}": self.level_carried,
                "collapsing_lift": self.collapse, **(measures or {}),
                "yielded_cells": state.comm.allreduce(len(state.yielded_cells())),
                **state.yielded_fractions(groups or {}),
                "newton_iterations": solver.iterations_total, "wall_time_s": wall_time}

    def last_equilibrium(self, solver: PlasticSolver, mesh: MeshData) -> ContinuumState:
        """The state the figures and numbers of a construction come from.

        The end of construction, or after a collapse the last complete lift: ``solver`` is
        restored to it and the collapsing lift's cells are left out of the state (the
        solver keeps them active, as :func:`~hybrid.handover.from_construction` hands them
        over in place).
        """
        if self.before_collapse is None:
            return solver.state()
        solver.restore(self.before_collapse)
        state = solver.state()
        collapsing = np.isin(np.arange(mesh.num_owned_cells), np.concatenate(
            [mesh.cells(name) for name in lift_groups(mesh, self.stages[-1]["lift"])]))
        state.active = ~collapsing if state.active is None else state.active & ~collapsing
        return state


def ground_stage(solver: PlasticSolver, groups: Sequence[str], point: Sequence[float], *,
                 ground_level: float, unit_weight: float, nu: float, steps: int = 1,
                 where: str = "below level ground") -> tuple[int, AtRest]:
    """The first stage of a staged construction: the ground in place under its own weight.

    Only ``groups`` active, gravity applied in ``steps`` increments (an error when Newton
    finds no equilibrium), the far-field stress at ``point`` checked against level ground at
    rest (:func:`~hybrid.continuum.analysis.at_rest_checks` with ``ground_level``,
    ``unit_weight``, ``nu``, ``where``), then the displacements zeroed so that those of the
    lifts count from the initial stress state (the stresses are kept). Returns the solver's
    Newton iterations so far and the at-rest checks.
    """
    solver.set_active(list(groups))
    solver.apply_gravity(steps=steps).require()
    iterations = solver.iterations_total
    far = at_rest_checks(solver.state(), point, ground_level=ground_level,
                         unit_weight=unit_weight, nu=nu, where=where)
    solver.reset_displacement()
    return iterations, far


def build_in_lifts(solver: PlasticSolver, mesh: MeshData, tops: Sequence[float],
                   base_level: float, *, steps: int = 1, safety: StrengthSearch | None = None,
                   safety_every_lift: bool = True, unit: str = "m",
                   monitor: Callable[[PlasticSolver], dict[str, Any]] | None = None
                   ) -> Construction:
    """Place the lifts of a :func:`split_into_lifts` ``mesh`` one by one.

    Each lift is placed with ``activate`` (its weight in ``steps`` increments), up to the last
    or to the first that collapses.

    ``safety``: after every complete lift (or the last only, ``safety_every_lift=False``) a
    strength-reduction factor of safety with this search, from that lift's state, which is
    restored afterwards. Each stage record holds: "lift", "top_<unit>", "completed",
    "weight_placed" (fraction with equilibrium), "fill_level_<unit>" (the level that
    fraction of the lift reaches, from ``base_level`` below the first lift),
    "newton_iterations", "step_cuts", "wall_time_s", "yielded_cells", "max_displacement_m"
    (all ranks), for a lift that stopped short "runaway_ratio" (``Analysis.runaway``: whether
    it collapsed, :attr:`Construction.collapse`), "softening" (a material of the model
    softens) and "path" (``Analysis.path``: weight fraction, largest displacement since its
    placement [m]) and, with ``safety``, "factor_of_safety", "fos_wall_time_s"; ``unit``
    names the elevations' unit in the keys (e.g. "m_OD"). ``monitor``: called after every complete
    lift (before the factor of safety); its items are added to that lift's record (nothing
    is recorded from a lift that did not carry its full weight).
    """
    comm, lifts = mesh.comm, len(tops)
    if lifts == 0:
        raise ValueError("build_in_lifts: no lift tops given")
    placement = PlacementStrain(solver)
    stages: list[dict[str, Any]] = []
    result: SafetyResult | None = None
    safety_active = solver.active.copy()
    leak, fos_time, before = 0.0, 0.0, None
    for k in range(1, lifts + 1):
        t0, it0 = time.perf_counter(), solver.iterations_total
        u0 = solver.u.x.array.copy()
        before = solver.snapshot()
        analysis = solver.activate(lift_groups(mesh, k), steps=steps)
        bottom = base_level if k == 1 else tops[k - 2]
        stage: dict[str, Any] = {
            "lift": k, f"top_{unit}": tops[k - 1], "completed": analysis.completed,
            "weight_placed": analysis.factor,
            f"fill_level_{unit}": bottom + analysis.factor * (tops[k - 1] - bottom),
            "newton_iterations": solver.iterations_total - it0, "step_cuts": analysis.cuts,
            "wall_time_s": time.perf_counter() - t0}
        stages.append(stage)
        later = [mesh.cells(g) for j in range(k + 1, lifts + 1) for g in lift_groups(mesh, j)]
        s = solver.stress.reshape(solver.sspace.num_cells, -1, 4)
        s_later = s[np.concatenate(later)] if later else s[:0]
        leak = max(leak, comm.allreduce(float(np.max(np.abs(s_later), initial=0.0)),
                                        op=MPI.MAX))
        stage["yielded_cells"] = comm.allreduce(int(np.sum(np.any(
            solver.yielded.reshape(solver.sspace.num_cells, -1) > 0, axis=1))))
        stage["max_displacement_m"] = largest_nodal_norm(solver.u.x.array, comm)
        if not analysis.completed:
            stage["runaway_ratio"] = analysis.runaway()
            stage["softening"] = any(m.softens for m in solver.materials)
            stage["path"] = [list(point) for point in analysis.path]
            break  # its strain is no part of the last equilibrium the figures show
        placement.add(solver.u.x.array - u0)
        if monitor is not None:
            stage.update(monitor(solver))
        if safety is not None and (safety_every_lift or k == lifts):
            t0 = time.perf_counter()
            snap = solver.snapshot()
            result = factor_of_safety(solver, search=safety)
            solver.restore(snap)
            safety_active = solver.active.copy()
            fos_time += time.perf_counter() - t0
            stage["factor_of_safety"] = result.factor
            stage["fos_wall_time_s"] = time.perf_counter() - t0
    completed = stages[-1]["completed"] and len(stages) == lifts
    return Construction(stages, completed, leak, placement, result, safety_active, fos_time,
                        None if completed else before, base_level, unit)
