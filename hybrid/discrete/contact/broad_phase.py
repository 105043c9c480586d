"""Broad phase: candidate contact pairs from element boxes, and their tangential history.

The history is carried from one pair list to the next.

Thesis (G. S. Bala 2008) section 4.8.2.  Each element's box (grown by ``margin``) is entered
in every cell of a uniform grid that it covers, the cell size about the median box, and a
pair is tested in the one cell that holds the lower-left corner of the overlap of its two
boxes (both boxes cover that cell, and no other cell tests the pair): a cell list in the
spirit of Munjiza's NBS, cost linear in the number of elements however graded the mesh.  A
few oversized elements (box > 4x the median, e.g. one large rigid ground block) are kept
out of the grid and checked against all elements.  The pair list comes out sorted
lexicographically, so that the history of the pairs that stay in contact is carried over by
one merge of two sorted lists.
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
def _element_groups(element_nodes, node_group, groups, first):
    """Each element's tie groups into ``groups`` (n_el, nen), gathered once per call.

    ``first`` marks a vertex whose group is the first of its kind in the element (a rigid
    platen's group can hold several nodes of one element).
    """
    nen = element_nodes.shape[1]
    for e in range(element_nodes.shape[0]):
        for k in range(nen):
            g = node_group[element_nodes[e, k]]
            groups[e, k] = g
            first[e, k] = True
            for kp in range(k):
                if groups[e, kp] == g:
                    first[e, k] = False
                    break


@njit(cache=True)
def _is_candidate(i, j, boxes, groups, first, max_shared):
    """True when the boxes of i and j overlap (inclusive) and the elements share few ties.

    The elements may share at most ``max_shared`` distinct tie groups (``groups``, ``first``
    from ``_element_groups``). Distinct: a group that holds several nodes of one element (a
    rigid platen, ``DiscreteState.tie_rigidly``) is one tie, so two elements that each touch
    the platen, at one vertex or along an edge, share one group and stay candidates; counted
    per node they would share two and could interpenetrate without contact force.
    """
    if boxes[i, 0] > boxes[j, 2] or boxes[j, 0] > boxes[i, 2]:
        return False
    if boxes[i, 1] > boxes[j, 3] or boxes[j, 1] > boxes[i, 3]:
        return False
    nen = groups.shape[1]
    shared = 0
    for ka in range(nen):
        if not first[i, ka]:
            continue
        ga = groups[i, ka]
        for kb in range(nen):
            if groups[j, kb] == ga:
                shared += 1
                if shared > max_shared:
                    return False
                break
    return True


@njit(cache=True)
def _cell_of(coord, origin, h, n_cells):
    """Cell of ``coord`` >= ``origin`` on one axis (clamped to ``n_cells - 1``)."""
    return min(n_cells - 1, int((coord - origin) / h))


@njit(cache=True)
def _cell_range(lo, hi, origin, h, n_cells):
    """First and last cell of the interval [lo, hi] on one axis."""
    return _cell_of(lo, origin, h, n_cells), _cell_of(hi, origin, h, n_cells)


@njit(cache=True)
def _append(out, n_out, key):
    """``out`` with ``key`` written at ``n_out`` (a copy twice as long when it is full)."""
    if n_out == out.shape[0]:
        grown = np.empty(2 * out.shape[0], dtype=np.int64)
        grown[:n_out] = out[:n_out]
        out = grown
    out[n_out] = key
    return out


@njit(cache=True)
def _cell_list_pairs(boxes, element_nodes, node_group, big, h, max_shared):
    """Candidate pairs (i < j, sorted lexicographically) by a cell list of cell size ``h``.

    Every element not flagged ``big`` is entered in each cell its box covers; a pair is
    tested only in the cell of the lower-left corner of its boxes' overlap (both boxes cover
    it: the cell index is monotone in the coordinate), so each pair is found once. Elements
    flagged ``big`` bypass the grid and are tested against all others. ``h`` is enlarged
    when the grid would have more than about four cells per element or the boxes would
    enter more than sixteen cells per element (any ``h`` > 0 gives the same pairs).
    """
    n = boxes.shape[0]
    groups = np.empty(element_nodes.shape, dtype=np.int64)
    first = np.empty(element_nodes.shape, dtype=np.bool_)
    _element_groups(element_nodes, node_group, groups, first)
    x0 = np.inf
    y0 = np.inf
    x1 = -np.inf
    y1 = -np.inf
    n_small = 0
    for e in range(n):
        if big[e]:
            continue
        n_small += 1
        x0 = min(x0, boxes[e, 0])
        y0 = min(y0, boxes[e, 1])
        x1 = max(x1, boxes[e, 2])
        y1 = max(y1, boxes[e, 3])
    ncx = 1
    ncy = 1
    n_entries = n_small
    if n_small > 0:
        limit = 4.0 * n_small + 16.0
        span = ((x1 - x0) / h + 1.0) * ((y1 - y0) / h + 1.0)
        if span > limit:
            h *= np.sqrt(span / limit)
        for _ in range(64):
            ncx = int((x1 - x0) / h) + 1
            ncy = int((y1 - y0) / h) + 1
            n_entries = 0
            for e in range(n):
                if not big[e]:
                    ia, ib = _cell_range(boxes[e, 0], boxes[e, 2], x0, h, ncx)
                    ja, jb = _cell_range(boxes[e, 1], boxes[e, 3], y0, h, ncy)
                    n_entries += (ib - ia + 1) * (jb - ja + 1)
            if n_entries <= 16 * n_small:
                break
            h *= 2.0
    n_cells = ncx * ncy
    start = np.zeros(n_cells + 1, dtype=np.int64)
    for e in range(n):
        if not big[e]:
            ia, ib = _cell_range(boxes[e, 0], boxes[e, 2], x0, h, ncx)
            ja, jb = _cell_range(boxes[e, 1], boxes[e, 3], y0, h, ncy)
            for jy in range(ja, jb + 1):
                for ix in range(ia, ib + 1):
                    start[jy * ncx + ix + 1] += 1
    for c in range(n_cells):
        start[c + 1] += start[c]
    fill = start[:-1].copy()
    members = np.empty(max(start[n_cells], 1), dtype=np.int64)
    for e in range(n):  # element ids ascending inside each cell
        if not big[e]:
            ia, ib = _cell_range(boxes[e, 0], boxes[e, 2], x0, h, ncx)
            ja, jb = _cell_range(boxes[e, 1], boxes[e, 3], y0, h, ncy)
            for jy in range(ja, jb + 1):
                for ix in range(ia, ib + 1):
                    c = jy * ncx + ix
                    members[fill[c]] = e
                    fill[c] += 1

    out = np.empty(4 * n + 16, dtype=np.int64)  # keys i * n + j
    n_out = 0
    for c in range(n_cells):
        cx = c % ncx
        cy = c // ncx
        for qa in range(start[c], start[c + 1]):
            i = members[qa]
            for qb in range(qa + 1, start[c + 1]):
                j = members[qb]
                if boxes[i, 0] > boxes[j, 2] or boxes[j, 0] > boxes[i, 2]:
                    continue
                if boxes[i, 1] > boxes[j, 3] or boxes[j, 1] > boxes[i, 3]:
                    continue
                # the overlap's lower-left corner decides the one cell that tests the pair
                if _cell_of(max(boxes[i, 0], boxes[j, 0]), x0, h, ncx) != cx:
                    continue
                if _cell_of(max(boxes[i, 1], boxes[j, 1]), y0, h, ncy) != cy:
                    continue
                if _is_candidate(i, j, boxes, groups, first, max_shared):
                    out = _append(out, n_out, i * n + j)
                    n_out += 1
    for i in range(n):
        if not big[i]:
            continue
        for j in range(n):
            if j == i or (big[j] and j < i):
                continue
            if _is_candidate(i, j, boxes, groups, first, max_shared):
                out = _append(out, n_out, min(i, j) * n + max(i, j))
                n_out += 1
    keys = np.sort(out[:n_out])
    pairs = np.empty((n_out, 2), dtype=np.int64)
    for p in range(n_out):
        pairs[p, 0] = keys[p] // n
        pairs[p, 1] = keys[p] % n
    return pairs


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
    patch is tied, so including them costs only a box test.  Cell-list broad phase (module
    docstring): each box is entered in every cell of a uniform grid that it covers, the cell
    about the median box, and a pair is tested in the one cell holding the lower-left corner
    of the two boxes' overlap (cost linear in the number of elements).  ``bounds = (xmin,
    ymin, xmax, ymax)`` [m], if given, is the region the elements must stay in.

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
    median = float(np.median(size))
    big = size > _BIG_FACTOR * median
    if big.sum() > _MAX_BIG:
        big[:] = False
        big[np.argsort(size, kind="stable")[-_MAX_BIG:]] = True
    h = median + 1e-300
    return _cell_list_pairs(boxes, element_nodes, node_group, big, h, 1 if hinges else 0)


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

