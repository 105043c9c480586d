"""Structured-mesh builders: a rectangle of Q4 or T3 elements -> DiscreteState."""

from __future__ import annotations

import numpy as np

from hybrid.discrete.state import DiscreteState, from_mesh
from hybrid.materials import GRAVITY, Material

__all__ = ["rectangle", "rectangle_mesh", "blocks"]


def rectangle_mesh(width: float, height: float, nx: int, ny: int, element: str = "Q4",
                   origin=(0.0, 0.0)) -> tuple[np.ndarray, np.ndarray]:
    """Points (n, 2) and counter-clockwise cells of a structured nx x ny rectangle [m].

    T3: every cell is cut along its diagonal from lower-left to upper-right (2 nx ny cells).
    Cells are numbered row by row from the lower-left corner.
    """
    for name, val in (("width", width), ("height", height)):
        if not (np.isfinite(val) and val > 0.0):
            raise ValueError(f"{name} = {val!r}: must be a finite positive length [m]")
    for name, val in (("nx", nx), ("ny", ny)):
        if int(val) != val or val < 1:
            raise ValueError(f"{name} = {val!r}: must be an integer >= 1")
    if element not in ("Q4", "T3"):
        raise ValueError(f"element = {element!r}: expected 'Q4' or 'T3'")
    nx, ny = int(nx), int(ny)
    xs = origin[0] + np.linspace(0.0, width, nx + 1)
    ys = origin[1] + np.linspace(0.0, height, ny + 1)
    X, Y = np.meshgrid(xs, ys)  # (ny+1, nx+1)
    points = np.stack([X.ravel(), Y.ravel()], axis=1)
    i, j = np.meshgrid(np.arange(nx), np.arange(ny))  # j rows
    i, j = i.ravel(), j.ravel()
    p00 = j * (nx + 1) + i
    p10 = p00 + 1
    p11 = p10 + nx + 1
    p01 = p00 + nx + 1
    if element == "Q4":
        cells = np.stack([p00, p10, p11, p01], axis=1)
    else:
        lower = np.stack([p00, p10, p11], axis=1)
        upper = np.stack([p00, p11, p01], axis=1)
        cells = np.stack([lower, upper], axis=1).reshape(-1, 3)
    return points, cells.astype(np.int64)


def rectangle(width: float, height: float, nx: int, ny: int, element: str = "Q4", *,
              material: Material, origin=(0.0, 0.0),
              gravity=(0.0, -GRAVITY)) -> DiscreteState:
    """A tied rectangle of nx x ny cells of one material, lower-left corner at ``origin`` [m].

    Q4, or T3 with two triangles per cell; all coincident nodes tied, every inner edge an
    intact splittable interface, nothing fixed.
    """
    points, cells = rectangle_mesh(width, height, nx, ny, element, origin)
    return from_mesh(points, cells, np.zeros(cells.shape[0], dtype=np.int32), [material],
                     gravity=gravity)


def blocks(specs, materials, element: str = "Q4", *, gravity=(0.0, -GRAVITY),
           rigid=()) -> DiscreteState:
    """Several separate rectangular bodies in one state (not tied to each other).

    specs: sequence of (width, height, nx, ny, origin, material_index); materials: sequence of
    Material; rigid: indices of specs whose nodes are all fixed (ground, walls), which
    makes them rigid contact bodies. Each body is tied inside; bodies meet only by contact.
    """
    pts, cells, mats, owner = [], [], [], []
    off = 0
    for b, (w, h, nx, ny, origin, mi) in enumerate(specs):
        p, c = rectangle_mesh(w, h, nx, ny, element, origin)
        pts.append(p)
        cells.append(c + off)
        mats.append(np.full(c.shape[0], mi, dtype=np.int32))
        owner.append(np.full(c.shape[0], b))
        off += p.shape[0]
    st = from_mesh(np.concatenate(pts), np.concatenate(cells), np.concatenate(mats),
                   materials, gravity=gravity)
    owner = np.concatenate(owner)
    for b in rigid:
        st.fix(st.element_nodes[owner == b].ravel())
    return st
