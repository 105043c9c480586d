"""Broad phase: candidate contact pairs from element boxes, and their tangential history.

The history is carried from one pair list to the next.

Thesis (G. S. Bala 2008) section 4.8.2.  Elements are count-sorted into a uniform grid by
the centre of their box (grown by ``margin``), with the cell size at least the largest
grown box, so that a pair of overlapping boxes lies in 3x3 neighbouring cells (Munjiza's
NBS idea; cost linear in the number of elements).  A few oversized elements (box > 4x the
median, e.g. one large rigid ground block) are kept out of the grid and checked against all
elements.  The pair list comes out sorted lexicographically, so that the history of the
pairs that stay in contact is carried over by one merge of two sorted lists.
"""

from __future__ import annotations

import numpy as np
from numba import njit

import hybrid  # noqa: F401  (sets NUMBA_CACHE_DIR / OMP_WAIT_POLICY before numba compiles)
from hybrid.discrete.contact.polygon import check_mesh, polygon_box

_BIG_FACTOR = 4.0  # elements with a box > this x the median box bypass the grid
_MAX_BIG = 64  # at most this many oversized elements bypass the grid


@njit(cache=True)
def _element_boxes(x, element_nodes, margin, boxes):
    """Axis-aligned boxes [xmin, ymin, xmax, ymax] of the elements, grown by ``margin``."""
    nen = element_nodes.shape[1]
    for e in range(element_nodes.shape[0]):
        xmin, ymin, xmax, ymax = polygon_box(x, element_nodes, e, nen)
        boxes[e, 0] = xmin - margin
        boxes[e, 1] = ymin - margin
        boxes[e, 2] = xmax + margin
        boxes[e, 3] = ymax + margin


@njit(cache=True)
def _is_candidate(i, j, boxes, element_nodes, node_group, max_shared):
    """True when the boxes of i and j overlap (inclusive) and the elements share few ties.

    The elements may share at most ``max_shared`` distinct tie groups. Distinct: a group
    that holds several nodes of one element (a rigid platen, ``DiscreteState.tie_rigidly``)
    is one tie, so two elements that each touch the platen, at one vertex or along an edge,
    share one group and stay candidates; counted per node they would share two and could
    interpenetrate without contact force.
    """
    if boxes[i, 0] > boxes[j, 2] or boxes[j, 0] > boxes[i, 2]:
        return False
    if boxes[i, 1] > boxes[j, 3] or boxes[j, 1] > boxes[i, 3]:
        return False
    nen = element_nodes.shape[1]
    shared = 0
    for ka in range(nen):
        ga = node_group[element_nodes[i, ka]]
        seen = False  # ga already counted at an earlier node of i
        for kp in range(ka):
            if node_group[element_nodes[i, kp]] == ga:
                seen = True
                break
        if seen:
            continue
        for kb in range(nen):
            if node_group[element_nodes[j, kb]] == ga:
                shared += 1
                if shared > max_shared:
                    return False
                break
    return True


@njit(cache=True)
def _grid_pairs(boxes, element_nodes, node_group, big, h, max_shared):
    """Candidate pairs (i < j, sorted) by a uniform grid of cell size ``h``.

    Elements flagged ``big`` bypass the grid and are tested against all others.  ``h`` must
    be at least the largest box of the other elements.
    """
    n = boxes.shape[0]
    big_ids = np.nonzero(big)[0]
    n_small = n - big_ids.shape[0]
    cxmin = np.inf
    cymin = np.inf
    cxmax = -np.inf
    cymax = -np.inf
    for e in range(n):
        if big[e]:
            continue
        cx = 0.5 * (boxes[e, 0] + boxes[e, 2])
        cy = 0.5 * (boxes[e, 1] + boxes[e, 3])
        cxmin = min(cxmin, cx)
        cxmax = max(cxmax, cx)
        cymin = min(cymin, cy)
        cymax = max(cymax, cy)
    ncx = 1
    ncy = 1
    if n_small > 0:
        # keep the grid at most ~4 cells per element (a coarser grid stays correct)
        limit = 4.0 * n_small + 16.0
        span = ((cxmax - cxmin) / h + 1.0) * ((cymax - cymin) / h + 1.0)
        if span > limit:
            h *= np.sqrt(span / limit)
        ncx = int((cxmax - cxmin) / h) + 1
        ncy = int((cymax - cymin) / h) + 1
    n_cells = ncx * ncy
    cell = np.full(n, -1, dtype=np.int64)
    ix = np.zeros(n, dtype=np.int64)
    iy = np.zeros(n, dtype=np.int64)
    start = np.zeros(n_cells + 1, dtype=np.int64)
    for e in range(n):
        if big[e]:
            continue
        cx = 0.5 * (boxes[e, 0] + boxes[e, 2])
        cy = 0.5 * (boxes[e, 1] + boxes[e, 3])
        ix[e] = min(ncx - 1, int((cx - cxmin) / h))
        iy[e] = min(ncy - 1, int((cy - cymin) / h))
        cell[e] = iy[e] * ncx + ix[e]
        start[cell[e] + 1] += 1
    for c in range(n_cells):
        start[c + 1] += start[c]
    fill = start[:-1].copy()
    members = np.empty(max(n_small, 1), dtype=np.int64)
    for e in range(n):  # count sort: element ids ascending inside each cell
        if cell[e] >= 0:
            members[fill[cell[e]]] = e
            fill[cell[e]] += 1

    cap = 4 * n + 16
    out = np.empty((cap, 2), dtype=np.int64)
    n_out = 0
    cand = np.empty(n, dtype=np.int64)
    for i in range(n):
        k = 0
        if big[i]:
            for j in range(i + 1, n):
                if _is_candidate(i, j, boxes, element_nodes, node_group, max_shared):
                    cand[k] = j
                    k += 1
        else:
            for dyc in range(-1, 2):
                cy_ = iy[i] + dyc
                if cy_ < 0 or cy_ >= ncy:
                    continue
                for dxc in range(-1, 2):
                    cx_ = ix[i] + dxc
                    if cx_ < 0 or cx_ >= ncx:
                        continue
                    c = cy_ * ncx + cx_
                    for q in range(start[c], start[c + 1]):
                        j = members[q]
                        if j > i and _is_candidate(i, j, boxes, element_nodes, node_group,
                                                   max_shared):
                            cand[k] = j
                            k += 1
            for q in range(big_ids.shape[0]):
                j = big_ids[q]
                if j > i and _is_candidate(i, j, boxes, element_nodes, node_group, max_shared):
                    cand[k] = j
                    k += 1
            # insertion sort of the few candidates of i
            for u in range(1, k):
                val = cand[u]
                w = u - 1
                while w >= 0 and cand[w] > val:
                    cand[w + 1] = cand[w]
                    w -= 1
                cand[w + 1] = val
        if n_out + k > cap:
            cap = 2 * (n_out + k)
            grown = np.empty((cap, 2), dtype=np.int64)
            grown[:n_out] = out[:n_out]
            out = grown
        for u in range(k):
            out[n_out, 0] = i
            out[n_out, 1] = cand[u]
            n_out += 1
    return out[:n_out].copy()


def find_contact_pairs(
    x: np.ndarray,
    element_nodes: np.ndarray,
    node_group: np.ndarray,
    margin: float,
    bounds: tuple[float, float, float, float] | None = None,
    *,
    hinges: bool = False,
) -> np.ndarray:
    """Candidate contact pairs (i < j, sorted lexicographically), shape (n_pairs, 2) int64.

    Elements i, j are candidates when their boxes grown by ``margin`` [m] overlap and no node
    of i shares a tie group (``node_group``) with a node of j.  With ``hinges=True`` pairs
    that share exactly one tie group are candidates too (only pairs tied at two or more
    vertices, i.e. along an edge, are left out; the groups are counted distinct, so a rigid
    platen's group holding several nodes of an element is one tie): two elements whose
    common edge has failed but that are still tied at one end (the other interfaces around
    that vertex hold, or both touch a rigid platen) rotate about that vertex and would
    otherwise interpenetrate with no contact force, and enter contact with a deep overlap
    (a large energy kick) once the last tie goes.  Elements of a
    conforming patch that share one vertex (diagonal neighbours) cannot overlap while the
    patch is tied, so including them costs only a box test.  Uniform grid broad phase:
    elements are count-sorted into cells by their box centre, the cell size is the largest
    grown box, and each element is tested against the 3x3 neighbouring cells (cost linear in
    the number of elements).  ``bounds = (xmin, ymin, xmax, ymax)`` [m], if given, is the
    region the elements must stay in.

    Every box is grown by ``margin``, so elements closer than ``2 margin`` are candidates:
    ``margin = safety * v_max * refresh * dt`` covers two elements approaching each other at
    ``v_max`` during the ``refresh`` steps until the next call (section 4.8.2).
    """
    x = np.ascontiguousarray(x, dtype=np.float64)
    element_nodes = np.ascontiguousarray(element_nodes, dtype=np.int64)
    node_group = np.ascontiguousarray(node_group, dtype=np.int64)
    check_mesh(x, element_nodes)
    if node_group.shape != (x.shape[0],):
        raise ValueError(
            f"node_group must have shape (n_nodes,) = ({x.shape[0]},), got {node_group.shape}"
        )
    margin = float(margin)
    if not np.isfinite(margin) or margin < 0.0:
        raise ValueError(f"margin must be a finite length >= 0 [m], got {margin}")
    n_el = element_nodes.shape[0]
    if n_el < 2:
        return np.zeros((0, 2), dtype=np.int64)
    if bounds is not None:
        xmin, ymin, xmax, ymax = (float(b) for b in bounds)
        xe = x[element_nodes]
        out = (
            (xe[..., 0] < xmin) | (xe[..., 0] > xmax) | (xe[..., 1] < ymin) | (xe[..., 1] > ymax)
        ).any(axis=1)
        if out.any():
            e = int(np.argmax(out))
            raise ValueError(
                f"element {e} escaped the contact grid bounds {tuple(bounds)}: its nodes are at "
                f"{xe[e].tolist()}; enlarge the bounds or check the run for instability"
            )
    boxes = np.empty((n_el, 4))
    _element_boxes(x, element_nodes, margin, boxes)
    size = np.maximum(boxes[:, 2] - boxes[:, 0], boxes[:, 3] - boxes[:, 1])
    big = size > _BIG_FACTOR * np.median(size)
    if big.sum() > _MAX_BIG:
        big[:] = False
        big[np.argsort(size, kind="stable")[-_MAX_BIG:]] = True
    h = float(size[~big].max()) if (~big).any() else 1.0
    h = h * (1.0 + 1e-9) + 1e-300  # round-off guard: overlapping boxes stay in 3x3 cells
    return _grid_pairs(boxes, element_nodes, node_group, big, h, 1 if hinges else 0)


@njit(cache=True)
def _merge_history(old_pairs, old_shear, new_pairs, new_shear):
    """Copy the rows of ``old_shear`` whose pair is in ``new_pairs``, merging the pair lists.

    Returns False (and copies nothing) unless both are strictly sorted lexicographically.
    """
    for pairs in (old_pairs, new_pairs):
        for p in range(1, pairs.shape[0]):
            if pairs[p, 0] < pairs[p - 1, 0] or (
                pairs[p, 0] == pairs[p - 1, 0] and pairs[p, 1] <= pairs[p - 1, 1]
            ):
                return False
    i = 0
    n_old = old_pairs.shape[0]
    for j in range(new_pairs.shape[0]):
        a = new_pairs[j, 0]
        b = new_pairs[j, 1]
        while i < n_old and (
            old_pairs[i, 0] < a or (old_pairs[i, 0] == a and old_pairs[i, 1] < b)
        ):
            i += 1
        if i < n_old and old_pairs[i, 0] == a and old_pairs[i, 1] == b:
            new_shear[j, 0] = old_shear[i, 0]
            new_shear[j, 1] = old_shear[i, 1]
    return True


def carry_contact_history(
    old_pairs: np.ndarray, old_shear: np.ndarray, new_pairs: np.ndarray
) -> np.ndarray:
    """Tangential history for ``new_pairs``.

    A pair present in ``old_pairs`` keeps its ``old_shear`` row, a new pair starts at zero.
    Returns (n_new, 2) float64.
    """
    old_pairs = np.asarray(old_pairs, dtype=np.int64).reshape(-1, 2)
    new_pairs = np.asarray(new_pairs, dtype=np.int64).reshape(-1, 2)
    old_shear = np.asarray(old_shear, dtype=np.float64)
    if old_shear.shape != (old_pairs.shape[0], 2):
        raise ValueError(
            f"old_shear must have shape (n_old_pairs, 2) = ({old_pairs.shape[0]}, 2), "
            f"got {old_shear.shape}"
        )
    new_shear = np.zeros((new_pairs.shape[0], 2))
    if old_pairs.shape[0] == 0 or new_pairs.shape[0] == 0:
        return new_shear
    if _merge_history(old_pairs, old_shear, new_pairs, new_shear):
        return new_shear  # both lists sorted (as find_contact_pairs returns them): O(n) merge
    base = int(max(old_pairs.max(), new_pairs.max())) + 1
    k_old = old_pairs[:, 0] * base + old_pairs[:, 1]
    k_new = new_pairs[:, 0] * base + new_pairs[:, 1]
    order = np.argsort(k_old, kind="stable")
    k_sorted = k_old[order]
    idx = np.minimum(np.searchsorted(k_sorted, k_new), k_sorted.shape[0] - 1)
    hit = k_sorted[idx] == k_new
    new_shear[hit] = old_shear[order[idx[hit]]]
    return new_shear

