"""Point evaluation of dolfinx functions that works the same in serial and under MPI."""

from __future__ import annotations

from typing import Any

import numpy as np
from dolfinx import geometry
from mpi4py import MPI

__all__ = ["evaluate"]


def evaluate(f: Any, points: np.ndarray) -> np.ndarray:
    """Values of ``f`` at ``points`` (n, 2) [m], identical on every rank: (n, value_size).

    Each point is evaluated on the lowest rank that owns a cell containing it; a point outside
    the mesh raises ValueError.
    """
    mesh = f.function_space.mesh
    comm = mesh.comm
    pts = np.zeros((len(points), 3))
    pts[:, :2] = np.asarray(points, dtype=float)[:, :2]
    tree = geometry.BoundingBoxTree(mesh, mesh.topology.dim)
    candidates = geometry.compute_collisions(tree, pts)
    colliding = geometry.compute_colliding_cells(mesh, candidates, pts)
    n_owned = mesh.topology.index_map(mesh.topology.dim).size_local
    size = f.function_space.element.value_size if hasattr(
        f.function_space.element, "value_size") else int(np.prod(f.ufl_shape) or 1)
    values = np.zeros((len(pts), size))
    found = np.zeros(len(pts), dtype=np.int32)
    for i in range(len(pts)):
        cells = [c for c in colliding.links(i) if c < n_owned]
        if cells:
            values[i] = f.eval(pts[i], np.int32(cells[0]))
            found[i] = 1
    # lowest owning rank wins: mask the others out, then sum
    owner = np.where(found == 1, comm.rank, comm.size).astype(np.int32)
    first = np.empty_like(owner)
    comm.Allreduce(owner, first, op=MPI.MIN)
    if np.any(first == comm.size):
        missing = pts[first == comm.size][0, :2]
        raise ValueError(f"point ({missing[0]:.4g}, {missing[1]:.4g}) m is outside the mesh")
    values[first != comm.rank] = 0.0
    total = np.empty_like(values)
    comm.Allreduce(values, total, op=MPI.SUM)
    return total
