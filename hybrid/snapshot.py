"""The continuum state as plain arrays: what the discrete phase starts from.

A :class:`CellSnapshot` is written by the continuum side
(:func:`hybrid.continuum.snapshot.cell_snapshot`, dolfinx) and read by the discrete side
(:func:`hybrid.discrete.start.start_from_snapshot`, numpy only): neither needs the other's
objects. Cells are in gmsh order (serial and MPI runs give the same snapshot); only the cells
in place are included (staged construction).

Units: m, kPa, kN/m3, m/s2; stress rows are (sigma_xx, sigma_yy, sigma_zz, sigma_xy).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from hybrid.materials import Material

__all__ = ["CellSnapshot", "STRESS_NAMES"]

#: names of the stress components (Voigt order, kPa, tension +) in both phases' outputs
STRESS_NAMES = ("sigma_xx", "sigma_yy", "sigma_zz", "sigma_xy")


@dataclass(frozen=True)
class CellSnapshot:
    """Cells, fields, boundaries and loads of a converged continuum state.

    Attributes:
        x_undeformed: (n_points, 2) mesh vertices before any displacement [m].
        x: (n_points, 2) the same vertices at the current geometry x + u [m].
        cells: (n_cells, 3 or 4) vertex indices, counter-clockwise.
        material: (n_cells,) index into ``materials``.
        materials: the materials at the strengths in force (one per cell group, in order).
        material_names: the cell-group name of each material.
        strength_factor: F the strengths of ``materials`` are divided by [-].
        degree: polynomial degree of the continuum displacement (1: the point values map
            one to one onto the discrete Gauss points when the rules match).
        points: (n_cells, n_points_per_cell, 2) continuum quadrature points [m].
        point_areas: (n_cells, n_points_per_cell) the area each point carries, its rule's
            weight times the Jacobian determinant of the undeformed cell there [m2]
            (a cell's mean of a point field is the sum of area x value over the cell's area).
        stress: (n_cells, n_points_per_cell, 4) stress at those points [kPa].
        plastic_strain: (n_cells, n_points_per_cell) equivalent plastic strain [-].
        yielded: (n_cells, n_points_per_cell) 1 where the point yielded in the last step.
        boundary_edges: boundary name -> (m, 3) rows (vertex a, vertex b, cell).
        supports: (boundary name, x held, y held) of every support, in the model's order.
        smooth: names of the boundaries with a roller support (a symmetry plane or a smooth
            wall: the discrete start makes the straight ones smooth rigid walls for every
            element, ``DiscreteState.walls``).
        transmitting: names of the roller boundaries that truncate a larger ground (the
            discrete start gives their free component viscous dashpots,
            ``DiscreteState.set_transmitting``).
        loads: boundary name -> (pressure [kPa], traction x [kPa], traction y [kPa]) of the
            surface load on it (pressure acts against the outward normal).
        load_factor: the factor the surface loads stand at [-].
        gravity: (2,) acceleration of gravity in force [m/s2] ((0, 0): no self-weight).
    """

    x_undeformed: np.ndarray
    x: np.ndarray
    cells: np.ndarray
    material: np.ndarray
    materials: tuple[Material, ...]
    material_names: tuple[str, ...]
    strength_factor: float
    degree: int
    points: np.ndarray
    point_areas: np.ndarray
    stress: np.ndarray
    plastic_strain: np.ndarray
    yielded: np.ndarray
    boundary_edges: dict[str, np.ndarray] = field(default_factory=dict)
    supports: tuple[tuple[str, bool, bool], ...] = ()
    smooth: tuple[str, ...] = ()
    transmitting: tuple[str, ...] = ()
    loads: dict[str, tuple[float, float, float]] = field(default_factory=dict)
    load_factor: float = 1.0
    gravity: tuple[float, float] = (0.0, 0.0)

    def __post_init__(self) -> None:
        n = len(self.cells)
        if self.cells.ndim != 2 or self.cells.shape[1] not in (3, 4):
            raise ValueError(f"CellSnapshot.cells must be (n_cells, 3 or 4), got "
                             f"{self.cells.shape}")
        if self.x.shape != self.x_undeformed.shape or self.x.ndim != 2 or self.x.shape[1] != 2:
            raise ValueError("CellSnapshot.x and x_undeformed must both be (n_points, 2), got "
                             f"{self.x.shape} and {self.x_undeformed.shape}")
        for name in ("material", "points", "point_areas", "stress", "plastic_strain",
                     "yielded"):
            if len(getattr(self, name)) != n:
                raise ValueError(f"CellSnapshot.{name} must have one row per cell ({n}), got "
                                 f"{len(getattr(self, name))}")
        if self.point_areas.shape != self.points.shape[:2]:
            raise ValueError("CellSnapshot.point_areas must have one area per quadrature point "
                             f"{self.points.shape[:2]}, got {self.point_areas.shape}")
        if n and not np.all(self.point_areas > 0.0):
            raise ValueError("CellSnapshot.point_areas must be positive (a point's weight x "
                             "|det J|): an inverted or degenerate cell, or areas not filled in")
        if len(self.material_names) != len(self.materials):
            raise ValueError("CellSnapshot: one material name per material")
        unsupported = set(self.transmitting) - {name for name, _, _ in self.supports}
        if unsupported:
            raise ValueError(f"CellSnapshot.transmitting names {sorted(unsupported)} without a "
                             "support: a transmitting boundary is a roller support's")
        if n and not 0 <= self.material.min() <= self.material.max() < len(self.materials):
            raise ValueError(f"CellSnapshot.material must index the {len(self.materials)} "
                             "materials")

    @property
    def n_cells(self) -> int:
        """Number of cells."""
        return len(self.cells)
