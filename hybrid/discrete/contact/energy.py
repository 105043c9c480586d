"""Contact energy for the run's ledger.

The elastic energy stored in the contacts and the work of a force term over one step.

The stored elastic energy is ``k_n A^2 / (2 L_c)`` (exact for a flat penetration at constant
``L_c``; 3/4 of the true integral for a corner wedge) plus ``|F_t|^2 / (2 k_t L_c)``.  The
dissipations are measured as the work of the damping and tangential parts of the applied
forces (the ``split_force`` of ``contact_forces``) on the mid-step velocity, which is exactly
what the central-difference update takes from the kinetic energy; the force kernel's own
returns use the start-of-step velocity (``c_n v_n^2 dt``, ``cap x slip``), which
overestimates the damping when a contact vibrates at a few time steps per period.
"""

from __future__ import annotations

import numpy as np
from numba import njit

import hybrid  # noqa: F401  (sets NUMBA_CACHE_DIR / OMP_WAIT_POLICY before numba compiles)
from hybrid.discrete.contact.law import pair_properties
from hybrid.discrete.contact.polygon import (
    MAXV,
    boxes_apart,
    check_mesh,
    element_box_reflex,
    pair_overlap,
)


@njit(cache=True)
def _mid_step_work(force, v_start, v_end, dt):
    s = 0.0
    for i in range(force.shape[0]):
        s += force[i, 0] * (v_start[i, 0] + v_end[i, 0])
        s += force[i, 1] * (v_start[i, 1] + v_end[i, 1])
    return 0.5 * dt * s


@njit(cache=True)
def contact_step_works(split, force, v_start, v_end, dt):
    """(damping, tangential, all) mid-step works [kJ/m] of a step's contact forces, unchecked.

    ``split[0]`` and ``split[1]`` are the damping and tangential parts of ``force``; each
    work is :func:`mid_step_work`'s sum, in the same order (the same bits), in one pass.
    """
    w_d = 0.0
    w_t = 0.0
    w_a = 0.0
    for i in range(force.shape[0]):
        sx = v_start[i, 0] + v_end[i, 0]
        sy = v_start[i, 1] + v_end[i, 1]
        w_d += split[0, i, 0] * sx
        w_d += split[0, i, 1] * sy
        w_t += split[1, i, 0] * sx
        w_t += split[1, i, 1] * sy
        w_a += force[i, 0] * sx
        w_a += force[i, 1] * sy
    return 0.5 * dt * w_d, 0.5 * dt * w_t, 0.5 * dt * w_a


def mid_step_work(force: np.ndarray, v_start: np.ndarray, v_end: np.ndarray, dt: float) -> float:
    """Work [kJ/m] of nodal forces ``F(t)`` over one step with the mid-step velocity.

    The mid-step velocity is ``(v(t - dt/2) + v(t + dt/2)) / 2``: the central-difference
    update changes the kinetic energy by exactly ``sum F(t) . v_mid dt``, so this is the
    energy a force term gave the bodies in the step.  For the contact damping forces
    ``-mid_step_work`` is the dissipation that closes the ledger (``c_n v_n(t - dt/2)^2 dt``
    overestimates it when a contact vibrates at a few time steps per period: D5 with
    zeta = 0.2 ran at -18 %).
    """
    if not (force.shape == v_start.shape == v_end.shape) or force.ndim != 2:
        raise ValueError(
            f"force, v_start, v_end must have the same shape (n_nodes, 2), got "
            f"{force.shape}, {v_start.shape}, {v_end.shape}"
        )
    return float(_mid_step_work(force, v_start, v_end, float(dt)))


@njit(cache=True)
def _contact_energy(x, element_nodes, element_material, contact_table, pairs, shear):
    n_el = element_nodes.shape[0]
    boxes = np.empty((n_el, 4))
    reflex = np.empty(n_el, dtype=np.int64)
    for e in range(n_el):
        element_box_reflex(x, element_nodes, e, boxes, reflex)
    pa = np.empty((4, 2))
    pb = np.empty((4, 2))
    piece_a = np.empty((MAXV, 3))
    piece_b = np.empty((MAXV, 3))
    out = np.empty((MAXV, 3))
    tmp = np.empty((MAXV, 3))
    u_n = 0.0
    u_t = 0.0
    for p in range(pairs.shape[0]):
        a = pairs[p, 0]
        b = pairs[p, 1]
        if boxes_apart(boxes, a, b):
            continue
        area, cx, cy, nx, ny, lc = pair_overlap(a, b, reflex[a], reflex[b], x, element_nodes,
                                                pa, pb, piece_a, piece_b, out, tmp)
        if area <= 0.0:
            continue
        kn, kt = pair_properties(element_material, contact_table, a, b)[:2]
        u_n += 0.5 * kn * area * area / lc
        if kt > 0.0:
            u_t += 0.5 * (shear[p, 0] ** 2 + shear[p, 1] ** 2) / (kt * lc)
    return u_n, u_t


def contact_energy(
    x: np.ndarray,
    element_nodes: np.ndarray,
    element_material: np.ndarray,
    contact_table: np.ndarray,
    pairs: np.ndarray,
    shear: np.ndarray,
) -> tuple[float, float]:
    """Elastic energy stored in the contacts [kJ/m]: ``(normal, tangential)``.

    Normal: ``F_n = k_n A`` and ``dA/d(penetration) = |G| = L_c``, so the stored energy is
    ``int k_n A dA / L_c``; with ``L_c`` constant during the penetration (flat edge-to-edge
    contact, ``A = L_c d``) it is exactly ``k_n A^2 / (2 L_c) = k_n L_c d^2 / 2``, which is
    what is summed here.  Approximation: for a penetration ``A ~ d^p`` it is ``(p + 1) / (2 p)``
    of the true integral (a corner wedge, p = 2: 3/4 of it; its energy is small, ~d^3).
    Tangential: the spring ``|F_t|^2 / (2 k_t L_c)`` with the stored history ``shear``
    (exact while sticking at constant ``L_c``).  Evaluated on the current ``x``.
    """
    x = np.ascontiguousarray(x, dtype=np.float64)
    element_nodes = np.ascontiguousarray(element_nodes, dtype=np.int64)
    check_mesh(x, element_nodes)
    pairs = np.asarray(pairs, dtype=np.int64).reshape(-1, 2)
    shear = np.asarray(shear, dtype=np.float64)
    if shear.shape != pairs.shape:
        raise ValueError(f"shear must have shape (n_pairs, 2) = {pairs.shape}, got {shear.shape}")
    if pairs.size and (pairs.min() < 0 or pairs.max() >= element_nodes.shape[0]):
        raise ValueError(f"pairs must index elements 0..{element_nodes.shape[0] - 1}")
    if pairs.shape[0] == 0:
        return 0.0, 0.0
    u_n, u_t = _contact_energy(x, element_nodes, np.asarray(element_material),
                               np.asarray(contact_table, dtype=np.float64), pairs, shear)
    return float(u_n), float(u_t)
