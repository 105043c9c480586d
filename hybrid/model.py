"""The problem description: mesh with named groups, materials, supports and loads.

No solver code lives here. Units: m, kN, kPa. Sign convention: tension positive; a
``Pressure`` is positive when it pushes on the body (compression).
"""

from __future__ import annotations

import math
import numbers
from dataclasses import dataclass, field
from typing import Literal

import numpy as np

from hybrid.geometry import GeometryError, MeshData
from hybrid.materials import Material

__all__ = ["Fixed", "Roller", "Displacement", "Pressure", "Traction", "Model", "ModelError"]


class ModelError(ValueError):
    """The model is inconsistent (names, materials, boundary conditions)."""


def _check_finite(item: object, **values: float | None) -> None:
    """Refuse a load or prescribed value that is not a finite number (None passes)."""
    for key, value in values.items():
        if value is not None and (isinstance(value, bool) or not isinstance(value, numbers.Real)
                                  or not math.isfinite(value)):
            raise ModelError(f"{type(item).__name__} on '{getattr(item, 'boundary', '?')}': "
                             f"{key} = {value!r} must be a finite number")


@dataclass(frozen=True)
class Fixed:
    """Both displacement components held at zero on a boundary (rough rigid support)."""

    boundary: str


@dataclass(frozen=True)
class Roller:
    """The displacement component along ``direction`` held at zero (smooth support).

    ``transmitting``: the boundary truncates a larger ground (not a symmetry plane, not a
    wall that is there): in the discrete phase its free component gets viscous dashpots
    (``DiscreteState.set_transmitting``; the boundary must run along x or y). On a roller
    that holds the boundary's normal (the usual one) they absorb the shear waves that meet
    it, which would leave through the ground beyond instead of ringing in the model; the
    held normal still reflects pressure waves. The continuum (static) phase is the same
    either way.
    """

    boundary: str
    direction: Literal["x", "y"]
    transmitting: bool = False

    def __post_init__(self) -> None:
        if self.direction not in ("x", "y"):
            raise ModelError(f"Roller on '{self.boundary}': direction must be 'x' or 'y', "
                             f"not {self.direction!r}")
        if not isinstance(self.transmitting, bool):
            raise ModelError(f"Roller on '{self.boundary}': transmitting must be True or "
                             f"False, not {self.transmitting!r}")


@dataclass(frozen=True)
class Displacement:
    """Prescribed displacement [m] on a boundary; a component left None is free."""

    boundary: str
    ux: float | None = None
    uy: float | None = None

    def __post_init__(self) -> None:
        if self.ux is None and self.uy is None:
            raise ModelError(f"Displacement on '{self.boundary}': give ux, uy or both")
        _check_finite(self, ux=self.ux, uy=self.uy)


@dataclass(frozen=True)
class Pressure:
    """Normal pressure [kPa] on a boundary, positive pushing into the body."""

    boundary: str
    value: float

    def __post_init__(self) -> None:
        _check_finite(self, value=self.value)


@dataclass(frozen=True)
class Traction:
    """Surface traction (tx, ty) [kPa] on a boundary, in global axes."""

    boundary: str
    tx: float = 0.0
    ty: float = 0.0

    def __post_init__(self) -> None:
        _check_finite(self, tx=self.tx, ty=self.ty)


Support = Fixed | Roller | Displacement
Load = Pressure | Traction


@dataclass
class Model:
    """A plane-strain problem: mesh, a material per named cell group, supports and loads.

    Attributes:
        mesh: the mesh with named groups (see :mod:`hybrid.geometry`).
        materials: cell-group name -> material; every cell group needs one.
        supports: displacement boundary conditions by boundary name.
        loads: surface loads by boundary name.
    """

    mesh: MeshData
    materials: dict[str, Material]
    supports: list[Support] = field(default_factory=list)
    loads: list[Load] = field(default_factory=list)

    def __post_init__(self) -> None:
        groups = self.mesh.cell_groups
        for name, material in self.materials.items():
            if name not in groups:
                raise ModelError(
                    f"material '{material.name}' is assigned to unknown cell group '{name}'; "
                    f"the mesh's cell groups are: {', '.join(sorted(groups))}"
                )
        unassigned = sorted(set(groups) - set(self.materials))
        if unassigned:
            raise ModelError(
                f"cell group(s) {', '.join(unassigned)} have no material; give every "
                "cell group a Material in Model(materials={...})"
            )
        for item in [*self.supports, *self.loads]:
            try:
                self.mesh.facet_tag(item.boundary)
            except GeometryError as err:
                raise ModelError(f"{type(item).__name__}: {err}") from None

    @property
    def material_names(self) -> list[str]:
        """Cell-group names in a fixed order: the index of a name is its material id."""
        return sorted(self.materials)

    def material_ids(self) -> np.ndarray:
        """Material id of every owned cell (index into :attr:`material_names`)."""
        ids = np.full(self.mesh.num_owned_cells, -1, dtype=np.int32)
        for i, name in enumerate(self.material_names):
            ids[self.mesh.cells(name)] = i
        return ids

    def cell_property(self, attribute: str) -> np.ndarray:
        """A material attribute (e.g. "E", "unit_weight", "lame_lambda") per owned cell."""
        table = np.array([getattr(self.materials[n], attribute) for n in self.material_names],
                         dtype=float)
        return table[self.material_ids()]
