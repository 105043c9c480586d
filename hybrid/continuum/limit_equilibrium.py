"""Limit equilibrium of a model's section: the critical slip circle by Bishop's method.

The glue between a :class:`~hybrid.model.Model` (cells, material per cell, cells in place)
and :func:`hybrid.references.critical_circle`: the ground surface is the upper envelope of the
cells in place, the soil at a point is the material of the cell containing it (unit weight 0
outside them), the lowest level a circle may reach is the bottom of the mesh. Strengths are
the materials' own (F is the result); a slip may not pass through a material without
strength (elastic: the analysis never lets it yield).
"""

from __future__ import annotations

import numpy as np
from mpi4py import MPI

from hybrid.model import Model
from hybrid.references import SlipCircle, Soil, critical_circle

__all__ = ["section_of", "bishop_circle"]


def section_of(model: Model, active: np.ndarray | None = None
               ) -> tuple[np.ndarray, Soil, float]:
    """(ground surface (n, 2) [m], soil lookup, lowest level [m]) of the cells in place.

    ``active``: (n_owned_cells,) True for the cells in place (None: all). Collective under
    MPI: every rank gets the whole section.
    """
    from matplotlib.tri import Triangulation

    md = model.mesh
    x, cells = md.cell_vertices()
    ids = model.material_ids()
    keep = np.ones(len(cells), bool) if active is None else np.asarray(active, bool)
    parts = md.comm.allgather((x[cells[keep]], ids[keep]))
    polys = np.concatenate([p[0] for p in parts])  # (n, nv, 2)
    material = np.concatenate([p[1] for p in parts])
    floor = md.comm.allreduce(float(x[cells][..., 1].min()), op=MPI.MIN)
    # one point per mesh vertex (the cells of all ranks share them): a valid triangulation
    scale = float(np.abs(polys).max()) or 1.0
    points, vertex = np.unique(np.round(polys.reshape(-1, 2) / scale, 10), axis=0,
                               return_inverse=True)
    points = points * scale
    vertex = vertex.reshape(polys.shape[:2])
    if polys.shape[1] == 4:  # quadrilaterals split along a diagonal
        triangles = np.concatenate([vertex[:, [0, 1, 2]], vertex[:, [0, 2, 3]]])
        owner = np.concatenate([np.arange(len(polys))] * 2)
    else:
        triangles, owner = vertex, np.arange(len(polys))
    finder = Triangulation(points[:, 0], points[:, 1], triangles).get_trifinder()
    mats = [model.materials[n] for n in model.material_names]
    gamma = np.array([m.unit_weight for m in mats] + [0.0])
    cohesion = np.array([m.cohesion if m.is_plastic else np.inf for m in mats] + [0.0])
    phi = np.array([m.phi if m.is_plastic else 0.0 for m in mats] + [0.0])
    cell_material = np.append(material, len(mats))  # index -1 (outside) -> no soil

    def soil(xq: np.ndarray, yq: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        tri = finder(np.asarray(xq, float), np.asarray(yq, float))
        m = cell_material[np.where(tri >= 0, owner[tri], -1)]
        return gamma[m], cohesion[m], phi[m]

    return _upper_envelope(polys), soil, floor


def bishop_circle(model: Model, active: np.ndarray | None = None, *,
                  slices: int = 60) -> SlipCircle:
    """Bishop's simplified critical circle of the model's section (cells in place)."""
    surface, soil, floor = section_of(model, active)
    return critical_circle(surface, soil, floor=floor, slices=slices)


def _upper_envelope(polys: np.ndarray) -> np.ndarray:
    """Highest point of the cells above every vertex abscissa: the ground profile y(x)."""
    a = polys.reshape(-1, 2)
    b = np.roll(polys, -1, axis=1).reshape(-1, 2)
    xs = np.unique(np.round(a[:, 0], 9))
    x0, x1 = np.minimum(a[:, 0], b[:, 0]), np.maximum(a[:, 0], b[:, 0])
    top = np.full(len(xs), -np.inf)
    for lo in range(0, len(xs), 256):
        xq = xs[lo:lo + 256, None]
        spans = (x0[None, :] <= xq + 1e-12) & (xq - 1e-12 <= x1[None, :])
        dx = np.where(x1 > x0, x1 - x0, 1.0)
        t = np.clip((xq - np.minimum(a[:, 0], b[:, 0])[None, :]) / dx[None, :], 0.0, 1.0)
        ya = np.where(a[:, 0] <= b[:, 0], a[:, 1], b[:, 1])
        yb = np.where(a[:, 0] <= b[:, 0], b[:, 1], a[:, 1])
        y = np.where(x1 > x0, ya + t * (yb - ya), np.maximum(a[:, 1], b[:, 1]))
        top[lo:lo + 256] = np.max(np.where(spans, y, -np.inf), axis=1)
    return np.stack([xs, top], axis=1)

