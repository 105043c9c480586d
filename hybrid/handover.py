"""Continuum -> discrete handover: every cell in place becomes a discrete element.

The continuum state is exported as plain arrays (:class:`~hybrid.snapshot.CellSnapshot`:
cells at the current geometry, stresses, plastic strains, the materials at the strengths in
force, boundaries, supports, loads, gravity); :func:`hybrid.discrete.start.start_from_snapshot`
builds the discrete start from it (docs/hybrid.md says what is carried and how). This module
chooses where interfaces may split and glues the two together.

The **splittable region** (``Region``): cells with plastic strain above a threshold (or any
yielded point), optionally grown by N layers of neighbours, or a named cell group, or
everything. Interfaces with both elements in the region may split; all others stay tied.
Cells further than ``freeze_layers`` layers from the region can be frozen (all nodes held:
a rigid contact body).

After a staged construction (:func:`~hybrid.continuum.staging.build_in_lifts`),
:func:`from_construction` hands over the last complete lift with the collapsing one in place,
and :func:`element_groups` names each element's cell group with the lifts merged.

Under MPI the snapshot and the discrete state exist on rank 0 only (None on the other
ranks); serial and parallel runs give the same discrete start.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING, Any

import numpy as np

from hybrid.discrete.settle import SettleReport, residual_force, settle
from hybrid.discrete.start import Handover, start_from_snapshot
from hybrid.materials import Material
from hybrid.snapshot import CellSnapshot

if TYPE_CHECKING:
    from hybrid.continuum.plastic import PlasticSolver
    from hybrid.continuum.staging import Construction

__all__ = ["Region", "Handover", "to_discrete", "start_from", "region_cells", "settle",
           "SettleReport", "residual_force", "from_construction", "element_groups",
           "discrete_materials"]


@dataclass(frozen=True)
class Region:
    """Where interfaces may split.

    Attributes:
        plastic_strain: cells whose largest plastic strain exceeds this are in the region
            (a cell with a yielded point counts when this is 0).
        layers: grow the region by this many layers of neighbouring cells (sharing a vertex).
        group: a named cell group instead of the plastic criterion.
        everywhere: every interface may split.
    """

    plastic_strain: float = 0.0
    layers: int = 0
    group: str | None = None
    everywhere: bool = False

    def __post_init__(self) -> None:
        if not self.plastic_strain >= 0 or self.layers < 0:
            raise ValueError("Region: plastic_strain and layers must be >= 0")


def region_cells(snapshot: CellSnapshot, region: Region) -> np.ndarray:
    """(n_cells,) True for the cells in ``region``."""
    cells = snapshot.cells
    if region.everywhere:
        return np.ones(len(cells), dtype=bool)
    if region.group is not None:
        if region.group not in snapshot.material_names:
            raise ValueError(f"Region(group={region.group!r}): no such cell group; the groups "
                             f"are {list(snapshot.material_names)}")
        # material ids are the cell groups' indices (one material per group)
        inside = snapshot.material == snapshot.material_names.index(region.group)
    else:
        pmax = snapshot.plastic_strain.max(axis=1)
        inside = pmax > region.plastic_strain
        if region.plastic_strain == 0:
            inside |= np.any(snapshot.yielded > 0, axis=1)
    return _grow(cells, inside, region.layers)


def _grow(cells: np.ndarray, inside: np.ndarray, layers: int) -> np.ndarray:
    """Add ``layers`` layers of cells sharing a vertex with the set."""
    inside = inside.copy()
    for _ in range(layers):
        touched = np.zeros(cells.max() + 1, dtype=bool)
        touched[cells[inside].ravel()] = True
        inside |= touched[cells].any(axis=1)
    return inside


def start_from(snapshot: CellSnapshot, *, region: Region | None = None,
               freeze_layers: int | None = None) -> Handover:
    """The discrete start of a snapshot, with its splittable region.

    ``region`` defaults to the yielded cells; with ``freeze_layers``, the cells beyond that
    many layers of it are frozen (refused when the region is empty: every cell would be).
    """
    splittable = region_cells(snapshot, region or Region())
    frozen = np.zeros(len(splittable), dtype=bool)
    if freeze_layers is not None:
        if int(freeze_layers) != freeze_layers or freeze_layers < 0:
            raise ValueError(f"freeze_layers = {freeze_layers!r}: must be a whole number >= 0 "
                             "(None: nothing frozen)")
        if not splittable.any():
            raise ValueError(f"freeze_layers = {freeze_layers}: the splittable region is empty "
                             f"({region or Region()} selects no cell), so every element would "
                             "be held; choose a region that selects cells (a lower "
                             "plastic_strain, a group) or freeze_layers=None")
        frozen = ~_grow(snapshot.cells, splittable, freeze_layers)
    return start_from_snapshot(snapshot, splittable=splittable, frozen=frozen)


def to_discrete(state: Any, *, region: Region | None = None,
                freeze_layers: int | None = None, gravity: bool | None = None,
                strength_factor: float | None = None,
                materials: Mapping[str, Material] | None = None) -> Handover:
    """Build the discrete start from a converged :class:`~hybrid.continuum.ContinuumState`.

    Only the cells in place are handed over (staged construction: ``state.active``); a lift
    the continuum placed with part of its weight gets all of it in the discrete phase.
    The discrete materials have the strengths in force in ``state`` (its
    ``strength_factor``: the reduced strengths of a strength-reduction state) unless
    ``strength_factor`` is given (1: the materials as defined); the report records them.
    ``gravity``: whether the self-weight acts (default: when the state had it on).
    ``materials``: the discrete phase's materials by cell-group name, in place of the
    continuum's (:func:`discrete_materials`).
    """
    from hybrid.continuum.snapshot import cell_snapshot

    snapshot = cell_snapshot(state, strength_factor=strength_factor, gravity=gravity)
    if snapshot is None:
        return Handover(None, np.zeros(0, bool), np.zeros(0, bool), np.zeros((0, 2)))
    if materials is not None:
        snapshot = discrete_materials(snapshot, materials)
    return start_from(snapshot, region=region, freeze_layers=freeze_layers)


def discrete_materials(snapshot: CellSnapshot,
                       materials: Mapping[str, Material]) -> CellSnapshot:
    """``snapshot`` with the discrete phase's own materials.

    E.g. strengths that soften once the failed mass moves, after a construction at peak
    strength. ``materials`` maps a cell-group name to its material; a lift ("core:2") takes its
    group's ("core"), a group not named keeps the continuum's, a name that is no group is
    refused (ValueError). The stresses are handed over
    as they are, so a replacement keeps E, nu and the density of the material it replaces
    (a ValueError names the first that differs); its strengths are divided by the snapshot's
    ``strength_factor`` as the continuum's were. The continuum's plastic strain counts
    towards a softening law from the start.
    """
    groups = {name.split(":")[0] for name in snapshot.material_names}
    unknown = sorted(set(materials) - groups)
    if unknown:
        raise ValueError(f"discrete materials for {unknown}: no such cell group (the groups: "
                         f"{sorted(groups)}; a lift takes its group's material)")
    out = []
    for old, name in zip(snapshot.materials, snapshot.material_names):
        new = materials.get(name.split(":")[0])
        if new is None:
            out.append(old)
            continue
        for field in ("E", "nu", "density"):
            if getattr(new, field) != getattr(old, field):
                raise ValueError(
                    f"discrete material for '{name}': {field} = {getattr(new, field)!r} "
                    f"differs from the continuum's {getattr(old, field)!r}; the stresses are "
                    f"handed over as they are, so give the same {field} (only strengths and "
                    "the discrete properties may change)")
        factor = snapshot.strength_factor
        out.append(new.weakened(factor) if new.is_plastic and factor != 1.0 else new)
    return replace(snapshot, materials=tuple(out))


def from_construction(solver: PlasticSolver, construction: Construction, *,
                      region: Region | None = None,
                      materials: Mapping[str, Material] | None = None) -> Handover:
    """The discrete start after a staged construction (``solver`` as it ended it).

    When a lift collapsed (``construction.before_collapse``), the solver is restored to the
    last complete lift first: the collapsing lift is handed over in place, stress-free, and
    gets all its weight in the discrete phase (:func:`to_discrete`); otherwise the end of
    construction is handed over. ``region``: where interfaces may split (default: the
    yielded cells); ``materials``: the discrete phase's own, by cell group
    (:func:`discrete_materials`).
    """
    if construction.before_collapse is not None:
        solver.restore(construction.before_collapse)
    return to_discrete(solver.state(), region=region, materials=materials)


def element_groups(hand: Handover) -> np.ndarray:
    """(n_elements,) the cell-group name of each element of ``hand.discrete``.

    The lifts of a group (:func:`~hybrid.continuum.staging.split_into_lifts`: "core:1",
    "core:2", ...) count as the group ("core").
    """
    if not hand.material_names:
        raise ValueError("element_groups: the handover has no material names (a Handover of "
                         "start_from_snapshot has them)")
    names = np.array([name.split(":")[0] for name in hand.material_names])
    return names[hand.discrete.element_material]
