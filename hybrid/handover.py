"""Continuum -> discrete handover: every cell becomes a discrete element.

What is carried (``to_discrete``):
  * geometry: each cell's vertices at their current (deformed) coordinates x + u; every
    element owns its nodes; all coincident nodes are tied (one velocity), every shared edge is
    an intact interface;
  * stress, plastic strain, yield flags: when the continuum rule is the discrete element's own
    (P1 triangle, 1 point; Q1, 2x2 Gauss) point by point; otherwise (P2 / Q2) the **cell mean**
    (the local L2 projection onto constants) at every discrete Gauss point, and the maximum
    plastic strain / any yielded point of the cell;
  * materials (density from the unit weight, strengths, interface and contact parameters)
    at the strengths in force in the continuum state (a strength-reduction state hands over
    its reduced strengths; ``strength_factor`` chooses others),
    supports (Fixed, Roller: the nodes on the boundary are held; Displacement: held, at the
    velocity the caller sets), surface loads (consistent nodal forces on each boundary edge of
    its element, at the current geometry, kept in ``load_forces`` so that a load history can
    scale them), gravity (when the continuum had it switched on);
  * velocities start at zero.
What is approximated: the quadratic (P2 / Q2) continuum field becomes linear elements with a
constant stress: the discrete start is close to, not exactly in, its own equilibrium; a tied
settle (:func:`settle`) brings it there and reports how far it moved.

The **splittable region** (``Region``): cells with plastic strain above a threshold (or any
yielded point), optionally grown by N layers of neighbours, or a named cell group, or
everything. Interfaces with both elements in the region may split; all others stay tied.
Cells further than ``freeze_layers`` layers from the region can be frozen (all nodes held:
a rigid contact body).

Under MPI the continuum state is gathered and the discrete state is built on rank 0 (None on
the other ranks), in the gmsh cell and node order: serial and parallel runs give the same
discrete start.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np
import ufl

from hybrid.continuum.quadrature import evaluate_at_points
from hybrid.model import Displacement, Fixed, Pressure, Roller, Traction

__all__ = ["Region", "Handover", "to_discrete", "settle", "SettleReport", "residual_force"]


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
        if self.plastic_strain < 0 or self.layers < 0:
            raise ValueError("Region: plastic_strain and layers must be >= 0")


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
    """

    discrete: Any
    splittable: np.ndarray
    frozen: np.ndarray
    load_forces: np.ndarray
    boundary_nodes: dict[str, np.ndarray] = field(default_factory=dict)
    report: dict[str, Any] = field(default_factory=dict)

    def set_load_factor(self, factor: float) -> None:
        """Scale the surface loads carried over (1 = as at handover, 0 = removed)."""
        self.discrete.external_force[:] = factor * self.load_forces
        self.discrete.primed = False


def _gather(state: Any) -> dict[str, Any] | None:
    """Cells, vertices, stresses and boundary facets of all ranks on rank 0, in gmsh order."""
    md = state.model.mesh
    msh = md.mesh
    x, cells = md.cell_vertices()
    gid = np.asarray(msh.geometry.input_global_indices, dtype=np.int64)
    from hybrid.io import _displacement_at_geometry_nodes

    xu = x + _displacement_at_geometry_nodes(msh, state.u)
    n = md.num_owned_cells
    original = np.asarray(msh.topology.original_cell_index, dtype=np.int64)[:n]
    # boundary facets of the named groups: (group tag, vertex ids, owning cell's original id)
    msh.topology.create_connectivity(1, 0)
    msh.topology.create_connectivity(1, 2)
    f2v, f2c = msh.topology.connectivity(1, 0), msh.topology.connectivity(1, 2)
    geo_of_vertex = _vertex_to_geometry(msh)
    facets = []
    for tag in md.facet_groups.values():
        for f in md.facet_tags.find(tag):
            c = f2c.links(f)[0]
            if c >= n:
                continue  # counted by the owning rank
            verts = geo_of_vertex[f2v.links(f)]
            facets.append((tag, int(gid[verts[0]]), int(gid[verts[1]]), int(original[c])))
    qp = evaluate_at_points(state.disc, ufl.SpatialCoordinate(msh))  # (n, nqp, 2) [m]
    local = {
        "qp": qp, "cells": gid[cells], "original": original, "x": xu, "x0": x.copy(), "gid": gid,
        "material": state.model.material_ids(), "stress": state.stress,
        "plastic": state.plastic_strain, "yielded": state.yielded, "facets": facets,
        "active": np.ones(n, dtype=bool) if state.active is None else state.active,
    }
    parts = state.comm.gather(local, root=0)
    if state.comm.rank != 0:
        return None
    order = np.argsort(np.concatenate([p["original"] for p in parts]), kind="stable")
    n_vertices = 1 + max(int(p["gid"].max()) for p in parts)
    coords, coords0 = np.zeros((n_vertices, 2)), np.zeros((n_vertices, 2))
    for p in parts:
        coords[p["gid"]] = p["x"]
        coords0[p["gid"]] = p["x0"]
    cat = {k: np.concatenate([p[k] for p in parts])[order]
           for k in ("cells", "original", "material", "stress", "plastic", "yielded", "qp",
                     "active")}
    cat["x"], cat["x0"] = coords, coords0
    cat["facets"] = sorted(f for p in parts for f in p["facets"])
    return _placed_only(cat)


def _placed_only(data: dict[str, Any]) -> dict[str, Any]:
    """Drop the cells that staged construction has not placed yet (and their facets)."""
    keep = data["active"]
    if keep.all():
        return data
    out = {k: v[keep] for k, v in data.items() if k not in ("x", "x0", "facets")}
    placed = set(data["original"][keep].tolist())
    out.update(x=data["x"], x0=data["x0"],
               facets=[f for f in data["facets"] if f[3] in placed])
    return out


def _vertex_to_geometry(msh: Any) -> np.ndarray:
    """Geometry node index of each topological vertex (first-order meshes)."""
    tdim = msh.topology.dim
    msh.topology.create_connectivity(tdim, 0)
    c2v = msh.topology.connectivity(tdim, 0)
    n_cells = msh.topology.index_map(tdim).size_local + msh.topology.index_map(tdim).num_ghosts
    geo = msh.geometry.dofmap.array.reshape(n_cells, -1)
    out = np.zeros(msh.topology.index_map(0).size_local + msh.topology.index_map(0).num_ghosts,
                   dtype=np.int64)
    for c in range(n_cells):
        out[c2v.links(c)] = geo[c]
    return out


def _region_cells(data: dict[str, Any], state: Any, region: Region) -> np.ndarray:
    cells = data["cells"]
    if region.everywhere:
        return np.ones(len(cells), dtype=bool)
    if region.group is not None:
        state.model.mesh.cell_tag(region.group)  # a clear error for an unknown group
        # material ids are the cell groups' indices (one material per group)
        inside = data["material"] == state.model.material_names.index(region.group)
    else:
        pmax = data["plastic"].max(axis=1)
        inside = pmax > region.plastic_strain
        if region.plastic_strain == 0:
            inside |= np.any(data["yielded"] > 0, axis=1)
    return _grow(cells, inside, region.layers)


def _grow(cells: np.ndarray, inside: np.ndarray, layers: int) -> np.ndarray:
    """Add ``layers`` layers of cells sharing a vertex with the set."""
    inside = inside.copy()
    for _ in range(layers):
        touched = np.zeros(cells.max() + 1, dtype=bool)
        touched[cells[inside].ravel()] = True
        inside |= touched[cells].any(axis=1)
    return inside


def _carry_points(values: np.ndarray, n_discrete: int, exact: bool,
                  match: np.ndarray | None) -> np.ndarray:
    """Map (n, nqp, ...) continuum point values onto the discrete Gauss points.

    ``exact``: the same rule; ``match[e, k]`` is the continuum point at discrete point k.
    Otherwise the cell mean goes to every discrete point.
    """
    if exact:
        return np.take_along_axis(values, match.reshape(match.shape + (1,) * (values.ndim - 2)),
                                  axis=1).copy()
    mean = values.mean(axis=1, keepdims=True)
    return np.repeat(mean, n_discrete, axis=1)


def _match_points(disc: Any, qp: np.ndarray) -> np.ndarray:
    """For each element and discrete Gauss point, the nearest continuum quadrature point."""
    xe = disc.x[disc.element_nodes]  # (n, nen, 2), current = continuum geometry + u
    if disc.nen == 4:
        from hybrid.discrete.state import Q4_GAUSS

        xi, eta = Q4_GAUSS[:, 0], Q4_GAUSS[:, 1]
        shape = 0.25 * np.stack([(1 - xi) * (1 - eta), (1 + xi) * (1 - eta),
                                 (1 + xi) * (1 + eta), (1 - xi) * (1 + eta)], axis=1)
        gp = np.einsum("ka,nad->nkd", shape, xe)
    else:
        gp = xe.mean(axis=1, keepdims=True)
    dist = np.sum((gp[:, :, None, :] - qp[:, None, :, :]) ** 2, axis=-1)
    return np.argmin(dist, axis=2)


def to_discrete(state: Any, *, region: Region | None = None,
                freeze_layers: int | None = None, gravity: bool | None = None,
                strength_factor: float | None = None) -> Handover:
    """Build the discrete start from a converged :class:`~hybrid.continuum.ContinuumState`.

    Only the cells in place are handed over (staged construction: ``state.active``); a lift
    the continuum placed with part of its weight gets all of it in the discrete phase.
    The discrete materials have the strengths in force in ``state`` (its
    ``strength_factor``: the reduced strengths of a strength-reduction state) unless
    ``strength_factor`` is given (1: the materials as defined); the report records them."""
    from hybrid.discrete.state import check_elements, from_mesh

    region = region or Region()
    data = _gather(state)
    md = state.model.mesh
    if data is None:
        return Handover(None, np.zeros(0, bool), np.zeros(0, bool), np.zeros((0, 2)))
    factor = state.strength_factor if strength_factor is None else strength_factor
    materials = state.materials_at(factor)
    if gravity is None:
        gravity = state.info.get("gravity_factor", 1.0 if state.info.get("solver") == "elastic"
                                 else 0.0) > 0
    g = (0.0, -9.81) if gravity else (0.0, 0.0)
    # masses from the undeformed cells (mass is conserved: rho_0 V_0), then the nodes moved to
    # the current geometry, which must still be valid elements
    disc = from_mesh(data["x0"], data["cells"], data["material"], materials, gravity=g)
    disc.x[:] = data["x"][data["cells"]].reshape(-1, 2)
    disc.x_ref[:] = disc.x
    check_elements(disc.x, disc.element_nodes)
    nen = data["cells"].shape[1]
    ngp = disc.stress.shape[1]
    exact = state.disc.degree == 1 and state.disc.num_points == ngp
    # continuum points sit on the undeformed cells: match them on the undeformed geometry
    match = None
    if exact:
        moved = disc.x.copy()
        disc.x[:] = data["x0"][data["cells"]].reshape(-1, 2)
        match = _match_points(disc, data["qp"])
        disc.x[:] = moved
    disc.stress[:] = _carry_points(data["stress"], ngp, exact, match)
    if exact:
        disc.plastic_strain[:] = _carry_points(data["plastic"], ngp, True, match)
        disc.yielded[:] = _carry_points(data["yielded"], ngp, True, match)
    else:
        disc.plastic_strain[:] = data["plastic"].max(axis=1, keepdims=True)
        disc.yielded[:] = np.any(data["yielded"] > 0, axis=1, keepdims=True).astype(np.int8)

    splittable = _region_cells(data, state, region)
    ie = disc.interface_elements
    disc.interface_splittable[:] = splittable[ie[:, 0]] & splittable[ie[:, 1]]
    frozen = np.zeros(len(splittable), dtype=bool)
    if freeze_layers is not None:
        frozen = ~_grow(data["cells"], splittable, freeze_layers)
        disc.fix(disc.element_nodes[frozen].ravel())

    # nodes of each named boundary, supports and surface loads
    point_of_node = data["cells"].reshape(-1)  # discrete node k sits at mesh vertex point[k]
    elem_of_original = {int(o): e for e, o in enumerate(data["original"])}
    name_of_tag = {tag: name for name, tag in md.facet_groups.items()}
    boundary: dict[str, list[int]] = {}
    load_forces = np.zeros_like(disc.x)
    loads = {load.boundary: load for load in state.model.loads}
    load_factor = float(state.info.get("load_factor", 1.0))
    for tag, va, vb, orig in data["facets"]:
        name = name_of_tag[tag]
        e = elem_of_original[orig]
        nodes = disc.element_nodes[e]
        a = int(nodes[np.flatnonzero(point_of_node[nodes] == va)[0]])
        b = int(nodes[np.flatnonzero(point_of_node[nodes] == vb)[0]])
        boundary.setdefault(name, []).extend([a, b])
        if name in loads:
            load_forces[[a, b]] += 0.5 * load_factor * _edge_force(
                loads[name], disc.x[a], disc.x[b], disc.element_centroids()[e])
    boundary_nodes = {k: np.unique(v) for k, v in boundary.items()}
    for support in state.model.supports:
        nodes = boundary_nodes.get(support.boundary, np.zeros(0, dtype=np.int64))
        if isinstance(support, Fixed):
            disc.fix(nodes)
        elif isinstance(support, Roller):
            disc.fix(nodes, x=support.direction == "x", y=support.direction == "y")
        elif isinstance(support, Displacement):
            disc.fix(nodes, x=support.ux is not None, y=support.uy is not None)
    disc.external_force[:] = load_forces
    disc.primed = False
    report = {"elements": int(disc.n_elements), "nodes": int(disc.n_nodes),
              "tie_groups": int(disc.n_groups), "interfaces": int(len(ie)),
              "splittable_elements": int(splittable.sum()),
              "splittable_interfaces": int(disc.interface_splittable.sum()),
              "frozen_elements": int(frozen.sum()), "total_mass_t_per_m": float(disc.mass.sum()),
              "stress_mapping": "point by point" if exact else "cell mean (L2 onto constants)",
              "element": "Q4" if nen == 4 else "T3", "strength_factor": float(factor),
              "strengths": {m.name: {"cohesion_kPa": m.cohesion, "phi_deg": m.phi,
                                     "psi_deg": m.psi} for m in materials if m.is_plastic}}
    return Handover(disc, splittable, frozen, load_forces, boundary_nodes, report)


def _edge_force(load: Any, xa: np.ndarray, xb: np.ndarray, inside: np.ndarray) -> np.ndarray:
    """Resultant [kN/m] of a surface load on the edge a-b (outward normal away from ``inside``)."""
    t = xb - xa
    length = float(np.hypot(*t))
    normal = np.array([t[1], -t[0]]) / length
    if np.dot(normal, 0.5 * (xa + xb) - inside) < 0:
        normal = -normal
    if isinstance(load, Pressure):
        return -load.value * length * normal
    if isinstance(load, Traction):
        return np.array([load.tx, load.ty]) * length
    raise TypeError(f"unknown load {load!r}")


def residual_force(disc: Any) -> np.ndarray:
    """Out-of-balance force of every tie group's free components (n_groups, 2) [kN/m]:
    gravity + external - internal, summed over the group (zero in equilibrium)."""
    from hybrid.discrete.integrate import prime

    prime(disc)
    f = disc.external_force - disc.internal_force + disc.mass[:, None] * disc.gravity[None, :]
    per_group = np.zeros((disc.n_groups, 2))
    np.add.at(per_group, disc.node_group, f)
    held = np.zeros((disc.n_groups, 2), dtype=bool)
    np.logical_or.at(held, disc.node_group, disc.fixed)
    per_group[held] = 0.0
    return per_group


@dataclass
class SettleReport:
    """How far a tied settle moved the discrete start (H1)."""

    steps: int
    initial_residual: float  # norm of the out-of-balance forces at handover [kN/m]
    final_residual: float  # the same after the settle [kN/m]
    reference_force: float  # norm of the weight + loads, for scale [kN/m]
    max_velocity: float  # largest node speed at the end [m/s]
    max_displacement: float  # largest node movement during the settle [m]
    stress_change: float  # max |stress change| / max |stress| over the Gauss points [-]

    def as_dict(self) -> dict[str, float]:
        return dict(self.__dict__)


def settle(handover: Handover, *, steps: int = 2000, damping: float | None = None,
           local_damping: float = 0.7) -> SettleReport:
    """Tied settle of the discrete start, no splitting, no contact (H1)."""
    from hybrid.discrete.run import run

    disc = handover.discrete
    x0, s0 = disc.x.copy(), disc.stress.copy()
    r0 = float(np.linalg.norm(residual_force(disc)))
    weight = disc.mass[:, None] * disc.gravity[None, :] + disc.external_force
    ref = float(np.linalg.norm(weight))
    saved = disc.interface_splittable.copy()
    run(disc, max_steps=steps, damping=damping or 0.0, local_damping=local_damping,
        split_every=0, contact=False, progress=False)
    disc.interface_splittable[:] = saved
    r1 = float(np.linalg.norm(residual_force(disc)))
    scale = float(np.max(np.abs(s0))) or 1.0
    return SettleReport(steps, r0, r1, ref, float(np.max(np.hypot(*disc.v.T))),
                        float(np.max(np.hypot(*(disc.x - x0).T))),
                        float(np.max(np.abs(disc.stress - s0))) / scale)
