"""Smooth rigid walls: the planes of the roller supports as frictionless contact for every element.

A roller support (a symmetry plane, or a smooth rigid wall) holds the whole body on its
side of the plane, not only the nodes that lay on it at the start: a fragment that parts
from the boundary and moves toward the plane must meet it (its mirror image across a
symmetry plane, or the wall). Without this a fragment crosses the plane and moves on
beside the model with nothing in its way (H2: a fragment squeezed over the footing slid
across the symmetry plane and fell for ever).

A wall belongs to its support (``DiscreteState.wall_nodes``): it stands while one of the
support's nodes is held along its normal, and goes when the support is released (a gate or
a retaining wall removed for the discrete phase by freeing its nodes: ``held_walls``,
applied by the solver at the start of each run).

A wall is a row ``[n_x, n_y, c, s_min, s_max]`` of ``DiscreteState.walls``: the body lies
on the side ``n . x >= c`` (``n`` the unit normal into the body) and the wall spans the
tangential coordinate ``s = t . x`` in ``[s_min, s_max]`` (``t = (-n_y, n_x)``; the extent
of the boundary at the start). An element takes part when it is not held, its centroid
lies on the body's side with ``s`` in the span (an element that is already beyond the plane
is not pulled back through it) and some of its nodes lie beyond the plane. The force is the
pair law (``contact.law``) with the wall rigid and frictionless, from the element's own
contact properties: ``F_n = k_n A - c_n v_n`` along ``n``, never adhesive, with ``A`` the
area of the element beyond the plane, ``c_n = 2 zeta sqrt(k_n L_c m_e)`` (``L_c`` the
chord of the element along the plane, ``m_e`` its lumped mass, the wall's infinite),
``v_n = n . v`` at the centroid of ``A``, distributed to the element's nodes by its shape
functions there. The stored energy is ``k_n A^2 / (2 L_c)`` as for a pair
(``contact.energy``).

The walls act in runs with contact (``RunOptions.contact``), their forces added to the
contact forces and booked in the same ledger terms. The loop is serial over the elements
(the force of one element goes to its own nodes: no race, a fixed order, the same sums for
any thread count) and runs over the elements near a wall only (``near_walls``, chosen with
the contact search's margin at each of its refreshes). The work arrays belong to the caller
(``WallBuffers``): a step allocates nothing.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

import hybrid  # noqa: F401  (sets NUMBA_CACHE_DIR / OMP_WAIT_POLICY before numba compiles)
from hybrid.discrete.contact.law import _shape_weights, point_law

__all__ = ["WALL_WIDTH", "WallBuffers", "add_wall_forces", "wall_energy", "make_wall",
           "held_walls", "near_walls"]

WALL_WIDTH = 5  # [n_x, n_y, c, s_min, s_max]


class WallBuffers:
    """Scratch of ``add_wall_forces``: one element's vertices and shape-function weights.

    ``elements``: the elements near a wall (``near_walls``), the only ones the forces are
    computed for; None until the caller has chosen them.
    """

    def __init__(self) -> None:
        self.poly = np.empty((4, 2))
        self.w = np.empty((1, 4))
        self.elements: np.ndarray | None = None


@njit(cache=True)
def _near_walls(x, element_nodes, walls, margin, out):
    """Write the elements near a wall into ``out``, ascending; return how many.

    Near: a node closer than ``margin`` (|n_x| + |n_y|) to a wall's plane, or beyond it.
    """
    n = 0
    for e in range(element_nodes.shape[0]):
        near = False
        for k in range(walls.shape[0]):
            reach = margin * (abs(walls[k, 0]) + abs(walls[k, 1]))
            for a in range(element_nodes.shape[1]):
                i = element_nodes[e, a]
                if walls[k, 0] * x[i, 0] + walls[k, 1] * x[i, 1] - walls[k, 2] < reach:
                    near = True
                    break
            if near:
                break
        if near:
            out[n] = e
            n += 1
    return n


def near_walls(x: np.ndarray, element_nodes: np.ndarray, walls: np.ndarray,
               margin: float) -> np.ndarray:
    """The elements (ascending) with a node near a wall's plane or beyond it.

    Near: within ``margin`` (|n_x| + |n_y|) [m], the farthest a node moving by at most
    ``margin`` along each axis (as the contact search's boxes are grown) can come toward
    an inclined plane. The only elements that can meet a wall before they have moved that
    far: the caller chooses them with the margin of the contact search and again at each of
    its refreshes (``find_contact_pairs``), and ``add_wall_forces`` looks at them alone.
    """
    out = np.empty(element_nodes.shape[0], dtype=np.int64)
    return out[:_near_walls(x, element_nodes, walls, float(margin), out)].copy()


@njit(cache=True)
def _beyond(x, element_nodes, e, nx, ny, c):
    """Area, centroid and chord length of the part of element ``e`` with ``n . x < c``.

    The element's outline clipped by the plane, accumulated edge by edge (shoelace); the
    chord is the extent along the plane of the points where the outline crosses it.
    """
    nen = element_nodes.shape[1]
    a2 = 0.0
    cx6 = 0.0
    cy6 = 0.0
    tx = -ny
    ty = nx
    s_lo = math.inf
    s_hi = -math.inf
    # walk the clipped outline: vertices beyond the plane and the crossing points, in order
    first = True
    px0 = 0.0
    py0 = 0.0
    qx = 0.0
    qy = 0.0
    for k in range(nen):
        i = element_nodes[e, k]
        j = element_nodes[e, (k + 1) % nen]
        xi = x[i, 0]
        yi = x[i, 1]
        xj = x[j, 0]
        yj = x[j, 1]
        di = nx * xi + ny * yi - c
        dj = nx * xj + ny * yj - c
        for m in range(2):  # up to two outline points per edge: vertex i, crossing i-j
            if m == 0:
                if di >= 0.0:
                    continue
                ux = xi
                uy = yi
            else:
                if (di < 0.0) == (dj < 0.0):
                    continue
                f = di / (di - dj)
                ux = xi + f * (xj - xi)
                uy = yi + f * (yj - yi)
                s = tx * ux + ty * uy
                s_lo = min(s_lo, s)
                s_hi = max(s_hi, s)
            if first:
                px0 = ux
                py0 = uy
                first = False
            else:
                cr = qx * uy - ux * qy
                a2 += cr
                cx6 += (qx + ux) * cr
                cy6 += (qy + uy) * cr
            qx = ux
            qy = uy
    if first:
        return 0.0, 0.0, 0.0, 0.0
    cr = qx * py0 - px0 * qy  # close the outline
    a2 += cr
    cx6 += (qx + px0) * cr
    cy6 += (qy + py0) * cr
    if a2 <= 0.0:
        return 0.0, 0.0, 0.0, 0.0
    lc = s_hi - s_lo if s_hi > s_lo else 0.0
    return 0.5 * a2, cx6 / (3.0 * a2), cy6 / (3.0 * a2), lc


@njit(cache=True, inline="always")
def _engaged(x, element_nodes, fixed, e, nx, ny, c, s_min, s_max):
    """Whether element e meets the wall: free, centroid inside and in the span, a node beyond."""
    nen = element_nodes.shape[1]
    held = True
    beyond = False
    cx = 0.0
    cy = 0.0
    for k in range(nen):
        i = element_nodes[e, k]
        held = held and fixed[i, 0] and fixed[i, 1]
        beyond = beyond or nx * x[i, 0] + ny * x[i, 1] < c
        cx += x[i, 0]
        cy += x[i, 1]
    if held or not beyond:
        return False
    cx /= nen
    cy /= nen
    s = -ny * cx + nx * cy
    return nx * cx + ny * cy > c and s_min <= s <= s_max


@njit(cache=True)
def _wall_kernel(x, v, mass, element_nodes, element_material, contact_table, fixed, walls, dt,
                 force, damping_force, poly, w, elements):
    """Add the wall forces on ``elements`` to ``force``, their damping part to ``damping_force``.

    Returns (elements in contact, stored energy k_n A^2 / (2 L_c) summed).
    """
    nen = element_nodes.shape[1]
    n_active = 0
    energy = 0.0
    for q in range(elements.shape[0]):
        e = elements[q]
        for k in range(walls.shape[0]):
            nx = walls[k, 0]
            ny = walls[k, 1]
            c = walls[k, 2]
            if not _engaged(x, element_nodes, fixed, e, nx, ny, c, walls[k, 3], walls[k, 4]):
                continue
            area, gx, gy, lc = _beyond(x, element_nodes, e, nx, ny, c)
            if area <= 0.0 or lc <= 0.0:
                continue
            m = element_material[e]
            kn = contact_table[m, 0]
            zeta = contact_table[m, 3]
            me = 0.0
            for a in range(nen):
                i = element_nodes[e, a]
                poly[a, 0] = x[i, 0]
                poly[a, 1] = x[i, 1]
                me += mass[i]
            _shape_weights(poly, nen, gx, gy, w, 0)
            vx = 0.0
            vy = 0.0
            for a in range(nen):
                i = element_nodes[e, a]
                vx += w[0, a] * v[i, 0]
                vy += w[0, a] * v[i, 1]
            # the pair law with the wall as the rigid side A: frictionless, no history
            f_n, f_el = point_law(area, lc, nx, ny, vx, vy, me, kn, 0.0, 0.0, 0.0, 0.0, 0.0,
                                  zeta, 0.0, 0.0, dt)[:2]
            n_active += 1
            energy += kn * area * area / (2.0 * lc)
            if dt > 0.0:  # dt = 0: the energy only
                for a in range(nen):
                    i = element_nodes[e, a]
                    force[i, 0] += w[0, a] * f_n * nx
                    force[i, 1] += w[0, a] * f_n * ny
                    damping_force[i, 0] += w[0, a] * (f_n - f_el) * nx
                    damping_force[i, 1] += w[0, a] * (f_n - f_el) * ny
    return n_active, energy


def add_wall_forces(x: np.ndarray, v: np.ndarray, mass: np.ndarray, element_nodes: np.ndarray,
                    element_material: np.ndarray, contact_table: np.ndarray,
                    fixed: np.ndarray, walls: np.ndarray, dt: float, force: np.ndarray,
                    damping_force: np.ndarray, buffers: WallBuffers) -> int:
    """Add the forces of the smooth walls on the elements to ``force`` (n_nodes, 2).

    Only the elements of ``buffers.elements`` (``near_walls``) are looked at (all of them
    while it is None). ``damping_force`` receives (added) their damping part as applied, for
    the energy ledger (``mid_step_work``). Returns the number of element-wall contacts.
    Unchecked (the hot path of ``ExplicitSolver.step``; the state's arrays are checked when
    it is made or loaded).
    """
    elements = (np.arange(element_nodes.shape[0]) if buffers.elements is None
                else buffers.elements)
    return int(_wall_kernel(x, v, mass, element_nodes, element_material, contact_table, fixed,
                            walls, float(dt), force, damping_force, buffers.poly,
                            buffers.w, elements)[0])


def wall_energy(x: np.ndarray, element_nodes: np.ndarray, element_material: np.ndarray,
                contact_table: np.ndarray, fixed: np.ndarray, walls: np.ndarray) -> float:
    """Elastic energy stored in the element-wall contacts, k_n A^2 / (2 L_c) each [kJ/m]."""
    walls = np.ascontiguousarray(walls, dtype=np.float64).reshape(-1, WALL_WIDTH)
    if walls.shape[0] == 0:
        return 0.0
    b = WallBuffers()
    dummy = np.zeros((1, 2))
    return float(_wall_kernel(x, np.zeros_like(x), np.ones(x.shape[0]), element_nodes,
                              element_material, contact_table, fixed, walls, 0.0, dummy,
                              dummy, b.poly, b.w, np.arange(element_nodes.shape[0]))[1])


def make_wall(points: np.ndarray, inside: np.ndarray, axis: int,
              tol: float = 1e-9) -> np.ndarray | None:
    """The wall row of a roller boundary held along ``axis`` (0: x, 1: y), or None.

    ``points`` (k, 2): the boundary's nodes; ``inside`` (2,): a point of the body (the mean
    of the elements along the boundary). The boundary is a wall when its nodes lie on one
    line ``x[axis] = const`` (within ``tol`` times the boundary's extent; a curved or
    inclined roller boundary gives None). The plane is placed at the nodes' extreme
    coordinate on the outer side, so that every node of the boundary lies on the body's
    side of it.
    """
    points = np.asarray(points, dtype=float).reshape(-1, 2)
    if points.shape[0] < 2:
        return None
    along = points[:, 1 - axis]
    across = points[:, axis]
    extent = float(np.ptp(along))
    if extent <= 0.0 or float(np.ptp(across)) > tol * extent:
        return None
    normal = np.zeros(2)
    sign = 1.0 if float(inside[axis]) > float(across.mean()) else -1.0
    normal[axis] = sign
    c = float((sign * across).min())
    s = -normal[1] * points[:, 0] + normal[0] * points[:, 1]
    return np.array([normal[0], normal[1], c, float(s.min()), float(s.max())])


def held_walls(walls: np.ndarray, wall_nodes: np.ndarray,
               fixed: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The walls whose support stands, and their nodes renumbered.

    A wall stands while one of its support nodes (``wall_nodes`` rows [wall, node]) is held
    along its normal; a wall with no nodes listed stands for good. A roller released for the
    discrete phase (its nodes freed along the normal: a gate opened, a retaining wall
    removed) takes its wall with it.
    """
    walls = np.asarray(walls, dtype=float).reshape(-1, WALL_WIDTH)
    wall_nodes = np.asarray(wall_nodes, dtype=np.int64).reshape(-1, 2)
    keep = np.ones(walls.shape[0], dtype=bool)
    for k, (nx, ny, _, _, _) in enumerate(walls):
        nodes = wall_nodes[wall_nodes[:, 0] == k, 1]
        if nodes.size:
            keep[k] = bool(fixed[nodes, 0 if abs(nx) >= abs(ny) else 1].any())
    renumber = np.cumsum(keep) - 1
    rows = keep[wall_nodes[:, 0]]
    nodes = np.column_stack([renumber[wall_nodes[rows, 0]], wall_nodes[rows, 1]])
    return walls[keep], nodes.astype(np.int64).reshape(-1, 2)
