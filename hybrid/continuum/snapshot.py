"""Export a converged continuum state as a :class:`~hybrid.snapshot.CellSnapshot`.

The cells of every MPI rank are gathered on rank 0 in the gmsh cell and vertex order, so
serial and parallel runs give the same snapshot; only the cells in place (staged
construction, ``ContinuumState.active``) are kept, with their boundary edges.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import ufl

from hybrid.continuum.quadrature import evaluate_at_points
from hybrid.io import displacement_at_geometry_nodes
from hybrid.materials import GRAVITY
from hybrid.model import Displacement, Fixed, Pressure, Roller, Traction
from hybrid.snapshot import CellSnapshot

__all__ = ["cell_snapshot"]


def cell_snapshot(state: Any, *, strength_factor: float | None = None,
                  gravity: bool | None = None) -> CellSnapshot | None:
    """The snapshot of ``state`` (a :class:`~hybrid.continuum.ContinuumState`) on rank 0.

    None on the other ranks.

    ``strength_factor``: the strengths the snapshot's materials carry (default: those in
    force in ``state``, e.g. the reduced ones of a strength-reduction state). ``gravity``:
    whether the self-weight acts (default: when the state had it switched on).
    """
    data = _gather(state)
    if data is None:
        return None
    model = state.model
    factor = state.strength_factor if strength_factor is None else strength_factor
    if gravity is None:
        gravity = state.info.get("gravity_factor", 0.0) > 0
    cell_of_original = {int(o): e for e, o in enumerate(data["original"])}
    name_of_tag = {tag: name for name, tag in model.mesh.facet_groups.items()}
    rows: dict[str, list[tuple[int, int, int]]] = {}
    for tag, va, vb, orig in data["facets"]:  # sorted by tag: the names in tag order
        rows.setdefault(name_of_tag[tag], []).append((va, vb, cell_of_original[orig]))
    edges = {name: np.array(r, dtype=np.int64).reshape(-1, 3) for name, r in rows.items()}
    return CellSnapshot(
        x_undeformed=data["x0"], x=data["x"], cells=data["cells"], material=data["material"],
        materials=tuple(state.materials_at(factor)), material_names=tuple(model.material_names),
        strength_factor=float(factor), degree=int(state.disc.degree), points=data["qp"],
        point_areas=data["area"], stress=data["stress"], plastic_strain=data["plastic"],
        yielded=data["yielded"],
        boundary_edges=edges, supports=tuple(_held(s) for s in model.supports),
        smooth=tuple(s.boundary for s in model.supports if isinstance(s, Roller)),
        transmitting=tuple(s.boundary for s in model.supports
                           if isinstance(s, Roller) and s.transmitting),
        loads={load.boundary: _load_row(load) for load in model.loads},
        load_factor=float(state.info.get("load_factor", 1.0)),
        gravity=(0.0, -GRAVITY) if gravity else (0.0, 0.0))


def _held(support: Any) -> tuple[str, bool, bool]:
    """(boundary, x held, y held) of a support."""
    if isinstance(support, Fixed):
        return support.boundary, True, True
    if isinstance(support, Roller):
        return support.boundary, support.direction == "x", support.direction == "y"
    if isinstance(support, Displacement):
        return support.boundary, support.ux is not None, support.uy is not None
    raise TypeError(f"unknown support {support!r}")


def _load_row(load: Any) -> tuple[float, float, float]:
    """(pressure, traction x, traction y) [kPa] of a surface load."""
    if isinstance(load, Pressure):
        return float(load.value), 0.0, 0.0
    if isinstance(load, Traction):
        return 0.0, float(load.tx), float(load.ty)
    raise TypeError(f"unknown load {load!r}")


def _gather(state: Any) -> dict[str, Any] | None:
    """Cells, vertices, point values and boundary facets of all ranks on rank 0."""
    md = state.model.mesh
    msh = md.mesh
    x, cells = md.cell_vertices()
    gid = np.asarray(msh.geometry.input_global_indices, dtype=np.int64)
    xu = x + displacement_at_geometry_nodes(msh, state.u)
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
        "qp": qp, "area": state.point_areas(), "cells": gid[cells], "original": original,
        "x": xu, "x0": x.copy(), "gid": gid,
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
                     "area", "active")}
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
