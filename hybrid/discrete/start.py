"""The discrete start built from a :class:`~hybrid.snapshot.CellSnapshot` (numpy only).

What is carried:
  * geometry: each cell's vertices at their current (deformed) coordinates; every element
    owns its nodes; coincident nodes are tied (one velocity), every shared edge is an intact
    interface; masses from the undeformed cells (mass is conserved: rho_0 V_0);
  * stress, plastic strain, yield flags: when the continuum rule is the discrete element's own
    (P1 triangle, 1 point; Q1, 2x2 Gauss) point by point; otherwise (P2 / Q2) the **cell mean**
    (the local L2 projection onto constants) at every discrete Gauss point, and the maximum
    plastic strain / any yielded point of the cell;
  * the snapshot's materials (the strengths in force), supports (the nodes on the boundary
    are held in the directions given; a straight roller boundary also becomes a smooth
    rigid wall for every element, ``hybrid.discrete.contact.walls``, and a transmitting one
    gets viscous dashpots on its free component, ``DiscreteState.set_transmitting``),
    surface loads (consistent nodal forces on each boundary edge of its element, at the
    current geometry, kept in ``load_forces`` so that a load history can scale them),
    gravity;
  * velocities start at zero.
The quadratic continuum field becomes linear elements with a constant stress: the start is
close to, not exactly in, its own equilibrium (:func:`hybrid.discrete.settle.settle` brings it
there and reports how far it moved).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from hybrid.discrete.state import Q4_GAUSS, DiscreteState, check_elements, from_mesh
from hybrid.snapshot import CellSnapshot

__all__ = ["Handover", "start_from_snapshot"]


@dataclass
class Handover:
    """The discrete start and what is needed to continue the loading.

    Attributes:
        discrete: the DiscreteState (None on MPI ranks other than 0).
        splittable: (n_elements,) True for elements in the splittable region.
        frozen: (n_elements,) True for frozen (held) elements.
        load_forces: (n_nodes, 2) nodal forces [kN/m] of the model's surface loads as they
            stood at handover; ``discrete.external_force`` starts equal to it.
        boundary_nodes: boundary name -> discrete node indices on it.
        report: counts (elements, nodes, mass, region size) for the summary.
        material_names: the cell-group name of each material (``element_material`` indexes
            it).
    """

    discrete: Any
    splittable: np.ndarray
    frozen: np.ndarray
    load_forces: np.ndarray
    boundary_nodes: dict[str, np.ndarray] = field(default_factory=dict)
    report: dict[str, Any] = field(default_factory=dict)
    material_names: tuple[str, ...] = ()

    def set_load_factor(self, factor: float) -> None:
        """Scale the surface loads carried over (1 = as at handover, 0 = removed)."""
        self.discrete.external_force[:] = factor * self.load_forces
        self.discrete.primed = False


def start_from_snapshot(snapshot: CellSnapshot, *, splittable: np.ndarray,
                        frozen: np.ndarray) -> Handover:
    """The discrete start of a snapshot: one discrete element per snapshot cell.

    Interfaces between two ``splittable`` cells may split; the nodes of ``frozen`` cells are
    held (a rigid contact body).
    """
    s = snapshot
    splittable = np.asarray(splittable, dtype=bool)
    frozen = np.asarray(frozen, dtype=bool)
    if splittable.shape != (s.n_cells,) or frozen.shape != (s.n_cells,):
        raise ValueError(f"splittable and frozen need one flag per cell ({s.n_cells}), got "
                         f"{splittable.shape} and {frozen.shape}")
    # masses from the undeformed cells, then the nodes moved to the current geometry, which
    # must still be valid elements
    disc = from_mesh(s.x_undeformed, s.cells, s.material, list(s.materials),
                     gravity=s.gravity)
    disc.x[:] = s.x[s.cells].reshape(-1, 2)
    disc.x_ref[:] = disc.x
    check_elements(disc.x, disc.element_nodes)
    ngp = disc.stress.shape[1]
    exact = s.degree == 1 and s.points.shape[1] == ngp
    # continuum points sit on the undeformed cells: match them on the undeformed geometry
    match = None
    if exact:
        match = _match_points(disc, s.x_undeformed[s.cells].reshape(-1, 2), s.points)
    disc.stress[:] = _carry_points(s.stress, ngp, match, s.point_areas)
    if exact:
        disc.plastic_strain[:] = _carry_points(s.plastic_strain, ngp, match, s.point_areas)
        disc.yielded[:] = _carry_points(s.yielded, ngp, match, s.point_areas)
    else:
        disc.plastic_strain[:] = s.plastic_strain.max(axis=1, keepdims=True)
        disc.yielded[:] = np.any(s.yielded > 0, axis=1, keepdims=True).astype(np.int8)

    ie = disc.interface_elements
    disc.interface_splittable[:] = splittable[ie[:, 0]] & splittable[ie[:, 1]]
    if frozen.any():
        disc.fix(disc.element_nodes[frozen].ravel())
    boundary_nodes, load_forces = _boundaries(s, disc)
    for name, held_x, held_y in s.supports:
        nodes = boundary_nodes.get(name, np.zeros(0, dtype=np.int64))
        disc.fix(nodes, x=held_x, y=held_y)
    disc.walls, disc.wall_nodes = _walls(s, disc, boundary_nodes)
    _transmitting(s, disc)
    disc.external_force[:] = load_forces
    disc.primed = False
    report = {"elements": int(disc.n_elements), "nodes": int(disc.n_nodes),
              "tie_groups": int(disc.n_groups), "interfaces": int(len(ie)),
              "splittable_elements": int(splittable.sum()),
              "splittable_interfaces": int(disc.interface_splittable.sum()),
              "frozen_elements": int(frozen.sum()), "total_mass_t_per_m": float(disc.mass.sum()),
              "stress_mapping": "point by point" if exact else "cell mean (L2 onto constants)",
              "element": "Q4" if s.cells.shape[1] == 4 else "T3",
              "strength_factor": float(s.strength_factor),
              "strengths": {m.name: {"cohesion_kPa": m.cohesion, "phi_deg": m.phi,
                                     "psi_deg": m.psi} for m in s.materials if m.is_plastic},
              "crack_strengths": {m.name: {"cohesion_kPa": float(row[4]),
                                           "phi_deg": round(math.degrees(math.atan(row[2])), 9)}
                                  for m, row in zip(s.materials, disc.contact_table)}}
    return Handover(disc, splittable, frozen, load_forces, boundary_nodes, report,
                    tuple(s.material_names))


def _walls(s: CellSnapshot, disc: DiscreteState,
           boundary_nodes: dict[str, np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
    """The smooth walls of the straight roller boundaries and their support nodes.

    ``contact.walls.make_wall``; the body's side is that of the centroids of the elements
    along the boundary, the support nodes the boundary's.
    """
    from hybrid.discrete.contact.walls import WALL_WIDTH, make_wall

    rows: list[np.ndarray] = []
    nodes_of: list[np.ndarray] = []
    held = _held_directions(s)
    centroids = disc.element_centroids()
    for name in s.smooth:
        nodes = boundary_nodes.get(name)
        if nodes is None or not nodes.size or name not in held:
            continue
        axis = 0 if held[name][0] else 1
        elements = np.unique([int(e) for _, _, e in s.boundary_edges[name]])
        wall = make_wall(disc.x[nodes], centroids[elements].mean(axis=0), axis)
        if wall is not None:
            nodes_of.append(np.column_stack([np.full(nodes.size, len(rows)), nodes]))
            rows.append(wall)
    wall_nodes = (np.concatenate(nodes_of) if nodes_of else np.zeros((0, 2))).astype(np.int64)
    return np.array(rows, dtype=float).reshape(-1, WALL_WIDTH), wall_nodes


#: the largest slope [-] of a transmitting boundary's edges from its axis (0.01: 0.6 deg)
SLOPE = 0.01


def _transmitting(s: CellSnapshot, disc: DiscreteState) -> None:
    """Dashpots on the free component of the transmitting roller boundaries.

    A straight boundary along an axis: the shear wave's impedance when the roller holds its
    normal (the free component its tangent), the pressure wave's when it holds its tangent;
    any other boundary is refused.
    """
    point_of_node = s.cells.reshape(-1)  # discrete node k sits at snapshot point [k]
    held = _held_directions(s)
    for name in s.transmitting:
        hx, hy = held.get(name, (False, False))
        if hx == hy:
            raise ValueError(f"transmitting boundary {name!r} is held in "
                             f"{'both directions' if hx else 'neither direction'}: a "
                             "transmitting boundary is a roller, held in one direction only")
        edges = np.array([(*_edge_ends(point_of_node, disc, va, vb, e), int(e))
                          for va, vb, e in s.boundary_edges.get(name, ())],
                         dtype=np.int64).reshape(-1, 3)
        free = 1 if hx else 0
        t = np.abs(disc.x[edges[:, 1]] - disc.x[edges[:, 0]])
        # every edge within 0.01 rad of an axis: the free component the tangent or the normal
        tangent = bool(np.all(t[:, 1 - free] <= SLOPE * t[:, free]))
        if not (tangent or np.all(t[:, free] <= SLOPE * t[:, 1 - free])):
            raise ValueError(f"transmitting boundary {name!r} does not run along x or y: its "
                             "dashpots would mix the shear and the pressure wave (make it a "
                             "straight axis-parallel roller boundary)")
        disc.set_transmitting(edges, axis=free, normal=not tangent)


def _held_directions(s: CellSnapshot) -> dict[str, tuple[bool, bool]]:
    """(x held, y held) of each supported boundary, every support on it counted."""
    held: dict[str, tuple[bool, bool]] = {}
    for name, hx, hy in s.supports:
        was = held.get(name, (False, False))
        held[name] = (was[0] or hx, was[1] or hy)
    return held


def _edge_ends(point_of_node: np.ndarray, disc: DiscreteState, va: int, vb: int,
               e: int) -> tuple[int, int]:
    """The discrete nodes of element ``e`` at the snapshot points ``va`` and ``vb``."""
    nodes = disc.element_nodes[e]
    return (int(nodes[np.flatnonzero(point_of_node[nodes] == va)[0]]),
            int(nodes[np.flatnonzero(point_of_node[nodes] == vb)[0]]))


def _boundaries(s: CellSnapshot, disc: DiscreteState) -> tuple[dict[str, np.ndarray],
                                                                 np.ndarray]:
    """Discrete nodes of each named boundary and the nodal forces of the surface loads."""
    point_of_node = s.cells.reshape(-1)  # discrete node k sits at snapshot point [k]
    centroids = disc.element_centroids()
    load_forces = np.zeros_like(disc.x)
    boundary_nodes = {}
    for name, edges in s.boundary_edges.items():
        nodes_on = []
        load = s.loads.get(name)
        for va, vb, e in edges:
            a, b = _edge_ends(point_of_node, disc, va, vb, e)
            nodes_on.extend([a, b])
            if load is not None:
                load_forces[[a, b]] += 0.5 * s.load_factor * _edge_force(
                    load, disc.x[a], disc.x[b], centroids[e])
        boundary_nodes[name] = np.unique(np.array(nodes_on, dtype=np.int64))
    return boundary_nodes, load_forces


def _edge_force(load: tuple[float, float, float], xa: np.ndarray, xb: np.ndarray,
                inside: np.ndarray) -> np.ndarray:
    """Resultant [kN/m] of a surface load (pressure, tx, ty) on the edge a-b.

    The edge's outward normal points away from ``inside``.
    """
    pressure, tx, ty = load
    t = xb - xa
    length = float(np.hypot(*t))
    if pressure == 0.0:
        return np.array([tx, ty]) * length
    normal = np.array([t[1], -t[0]]) / length
    if np.dot(normal, 0.5 * (xa + xb) - inside) < 0:
        normal = -normal
    force = -pressure * length * normal
    return force if tx == 0.0 and ty == 0.0 else force + np.array([tx, ty]) * length


def _carry_points(values: np.ndarray, n_discrete: int, match: np.ndarray | None,
                  areas: np.ndarray) -> np.ndarray:
    """Map (n, nqp, ...) continuum point values onto the discrete Gauss points.

    ``match`` (the same rule): ``match[e, k]`` is the continuum point at discrete point k.
    Otherwise (None) the cell mean, the local L2 projection onto constants
    sum_q A_q v_q / sum_q A_q with the points' areas ``areas`` (n, nqp) [m2], goes to every
    discrete point.
    """
    if match is not None:
        return np.take_along_axis(values, match.reshape(match.shape + (1,) * (values.ndim - 2)),
                                  axis=1).copy()
    weights = (areas / areas.sum(axis=1, keepdims=True)).reshape(areas.shape
                                                                 + (1,) * (values.ndim - 2))
    mean = np.sum(weights * values, axis=1, keepdims=True)
    return np.repeat(mean, n_discrete, axis=1)


def _match_points(disc: DiscreteState, x_nodes: np.ndarray, qp: np.ndarray) -> np.ndarray:
    """The nearest continuum quadrature point to each discrete Gauss point of each element.

    The discrete Gauss points are placed on the node positions ``x_nodes``.
    """
    xe = x_nodes[disc.element_nodes]  # (n, nen, 2)
    if disc.nen == 4:
        xi, eta = Q4_GAUSS[:, 0], Q4_GAUSS[:, 1]
        shape = 0.25 * np.stack([(1 - xi) * (1 - eta), (1 + xi) * (1 - eta),
                                 (1 + xi) * (1 + eta), (1 - xi) * (1 + eta)], axis=1)
        gp = np.einsum("ka,nad->nkd", shape, xe)
    else:
        gp = xe.mean(axis=1, keepdims=True)
    dist = np.sum((gp[:, :, None, :] - qp[:, None, :, :]) ** 2, axis=-1)
    return np.argmin(dist, axis=2)
