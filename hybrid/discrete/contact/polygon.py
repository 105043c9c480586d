"""Overlap geometry of two elements: clipping, area, centroid, contact normal and length.

Thesis (G. S. Bala 2008) section 4.3 and appendices A-C.  One element pair A-B, both
polygons counter-clockwise:

* overlap polygon by Sutherland-Hodgman clipping of convex polygons; a deformed non-convex
  quad is split into two triangles along the diagonal through its reflex vertex, and the
  overlap of two split elements is the sum over the convex sub-pairs;
* overlap area ``A`` and centroid ``c`` by the shoelace formula;
* contact normal: the gradient of the overlap area under a translation of B relative to A,
  ``G = sum over A's edges of n_edge * (length of the edge inside B)`` (outward unit normals
  of A), summed over the outline edges of the clipped polygon that lie on A's boundary (the
  clipping labels them).  ``|G|`` is the contact (chord) length ``L_c`` and ``n = G / |G|``
  points from A to B.  With two boundary intersection points ``G`` is exactly the normal of
  the chord joining them times its length (the thesis's appendix C case analysis reduces to
  this vector geometry).  When ``G`` vanishes (one element wholly inside the other) the
  normal falls back to the direction from A's centroid to B's centroid (then (0, 1)) and
  ``L_c = sqrt(A)``.

A polygon is read through an index table: its vertex k is ``pts[ids[row, k]]``.  For the
mesh that is ``x[element_nodes[e, k]]``, so the box and reflex vertex of an element come
from the node coordinates without a copy; a lone polygon uses a one-row identity table.
The kernels take scratch arrays from the caller (no allocation per pair); scratch of shape
(MAXV, 3) holds a clipped polygon, column 2 labelling its outline edges.
"""

from __future__ import annotations

import numpy as np
from numba import njit

import hybrid  # noqa: F401  (sets NUMBA_CACHE_DIR / OMP_WAIT_POLICY before numba compiles)

MAXV = 16  # vertex capacity of the clipping buffers (two convex <=4-gons clip to <= 8)
_OWN_VERTICES = np.arange(4, dtype=np.int64).reshape(1, 4)  # index table of a lone polygon


# --------------------------------------------------------------------------------------
# Element boxes and reflex vertices
# --------------------------------------------------------------------------------------
@njit(cache=True)
def polygon_box(pts, ids, row, n):
    """Box ``(xmin, ymin, xmax, ymax)`` of a polygon given by vertex indices.

    Vertex k (``k < n``) of the polygon is ``pts[ids[row, k]]``.
    """
    i0 = ids[row, 0]
    xmin = pts[i0, 0]
    xmax = xmin
    ymin = pts[i0, 1]
    ymax = ymin
    for k in range(1, n):
        ik = ids[row, k]
        xmin = min(xmin, pts[ik, 0])
        xmax = max(xmax, pts[ik, 0])
        ymin = min(ymin, pts[ik, 1])
        ymax = max(ymax, pts[ik, 1])
    return xmin, ymin, xmax, ymax


@njit(cache=True)
def reflex_vertex(pts, ids, row, n):
    """Index of the reflex vertex of a counter-clockwise quad, -1 if convex (or n != 4).

    Vertex k of the quad is ``pts[ids[row, k]]``.

    Vertex i is reflex when the cross product of its incoming and outgoing edges is negative
    (a simple quad has at most one).
    """
    if n != 4:
        return -1
    for i in range(4):
        p = ids[row, (i + 3) % 4]
        c = ids[row, i]
        q = ids[row, (i + 1) % 4]
        ax = pts[c, 0] - pts[p, 0]
        ay = pts[c, 1] - pts[p, 1]
        bx = pts[q, 0] - pts[c, 0]
        by = pts[q, 1] - pts[c, 1]
        cr = ax * by - ay * bx
        scale = (abs(ax) + abs(ay)) * (abs(bx) + abs(by))
        if cr < -1e-14 * scale:
            return i
    return -1


@njit(cache=True)
def element_box_reflex(x, element_nodes, e, boxes, reflex):
    """Box [xmin, ymin, xmax, ymax] (not grown) and reflex vertex of element ``e``.

    Computed from the node coordinates, written into ``boxes[e]`` and ``reflex[e]``.
    """
    nen = element_nodes.shape[1]
    xmin, ymin, xmax, ymax = polygon_box(x, element_nodes, e, nen)
    boxes[e, 0] = xmin
    boxes[e, 1] = ymin
    boxes[e, 2] = xmax
    boxes[e, 3] = ymax
    reflex[e] = reflex_vertex(x, element_nodes, e, nen)


@njit(cache=True)
def boxes_apart(boxes, a, b):
    """The (ungrown) boxes of elements a and b do not overlap (the narrow phase's reject)."""
    return (
        boxes[a, 0] >= boxes[b, 2]
        or boxes[b, 0] >= boxes[a, 2]
        or boxes[a, 1] >= boxes[b, 3]
        or boxes[b, 1] >= boxes[a, 3]
    )


# --------------------------------------------------------------------------------------
# Clipping
# --------------------------------------------------------------------------------------
@njit(cache=True)
def _load_piece(poly, n, reflex, piece, out):
    """Copy convex piece ``piece`` of a polygon into ``out``; return its vertex count.

    Convex polygon (``reflex < 0``): the polygon itself.  Non-convex quad with reflex vertex
    r: triangles (r, r+1, r+2) and (r+2, r+3, r), split along the diagonal through r.
    """
    if reflex < 0:
        for i in range(n):
            out[i, 0] = poly[i, 0]
            out[i, 1] = poly[i, 1]
        return n
    start = reflex if piece == 0 else (reflex + 2) % 4
    for k in range(3):
        j = (start + k) % 4
        out[k, 0] = poly[j, 0]
        out[k, 1] = poly[j, 1]
    return 3


@njit(cache=True)
def _clip_pass(src, n, first, dst, ax, ay, ex, ey, j):
    """One Sutherland-Hodgman pass: clip ``src[:n]`` by one edge into ``dst``.

    Keeps the part of ``src[:n]`` left of the edge through (ax, ay) with direction (ex, ey),
    writes it to ``dst`` and returns its vertex count.

    Column 2 labels the edge leaving each vertex: -1 on the subject polygon's boundary, k on
    the clip polygon's edge k (``first``: ``src`` is the subject itself, every label -1); an
    edge keeps its label when clipped, and the stretch along the clip line gets ``j``.
    """
    m = 0
    px = src[n - 1, 0]
    py = src[n - 1, 1]
    pl = -1.0 if first else src[n - 1, 2]
    dp = ex * (py - ay) - ey * (px - ax)  # >= 0: left of the clip edge (inside)
    for i in range(n):
        qx = src[i, 0]
        qy = src[i, 1]
        ql = -1.0 if first else src[i, 2]
        dq = ex * (qy - ay) - ey * (qx - ax)
        if dp >= 0.0:
            if dq < 0.0:  # leaving: the outline runs on along the clip line
                t = dp / (dp - dq)
                dst[m, 0] = px + t * (qx - px)
                dst[m, 1] = py + t * (qy - py)
                dst[m, 2] = j
                m += 1
            else:
                dst[m, 0] = qx
                dst[m, 1] = qy
                dst[m, 2] = ql
                m += 1
        elif dq >= 0.0:  # entering: the rest of the edge p -> q
            t = dp / (dp - dq)
            dst[m, 0] = px + t * (qx - px)
            dst[m, 1] = py + t * (qy - py)
            dst[m, 2] = pl
            dst[m + 1, 0] = qx
            dst[m + 1, 1] = qy
            dst[m + 1, 2] = ql
            m += 2
        px = qx
        py = qy
        pl = ql
        dp = dq
    return m


@njit(cache=True, inline="always")
def _edge(poly, n, j):
    """Edge ``j`` of polygon ``poly[:n]``: its start (ax, ay) and direction (ex, ey)."""
    ax = poly[j, 0]
    ay = poly[j, 1]
    j1 = j + 1 if j + 1 < n else 0
    return ax, ay, poly[j1, 0] - ax, poly[j1, 1] - ay


@njit(cache=True)
def _clip_convex(sub, ns, clip, nc, out, tmp):
    """Sutherland-Hodgman clipping of convex ``sub[:ns]`` by convex ``clip[:nc]`` (both ccw).

    The result goes to ``out`` (``tmp`` is scratch, both of shape (MAXV, 3); the two are
    used in turn as source and destination, so that the last pass ends in ``out``; explicit
    branches rather than array variables: no reference counting in the hot loop); returns
    the number of vertices of the overlap polygon (0 when they do not overlap). Column 2 of
    ``out`` labels each outline edge (see ``_clip_pass``).
    """
    n = ns
    for j in range(nc):
        ax, ay, ex, ey = _edge(clip, nc, j)
        if j == 0:
            if (nc - 1) % 2 == 0:
                n = _clip_pass(sub, n, True, out, ax, ay, ex, ey, j)
            else:
                n = _clip_pass(sub, n, True, tmp, ax, ay, ex, ey, j)
        elif (nc - j) % 2 == 0:
            n = _clip_pass(out, n, False, tmp, ax, ay, ex, ey, j)
        else:
            n = _clip_pass(tmp, n, False, out, ax, ay, ex, ey, j)
        if n == 0:
            return 0
    return n


# --------------------------------------------------------------------------------------
# Area, centroid, normal
# --------------------------------------------------------------------------------------
@njit(cache=True)
def _subject_normal(poly, n):
    """Sum of (outward normal x length) over the subject's edges in the clipped polygon.

    The edges are those of the outline of ``poly[:n]`` that lie on the subject's boundary
    (label -1): the subject's edge lengths inside the clip polygon along their outward
    normals, i.e. minus the gradient of the overlap area under a translation of the clip
    polygon.
    """
    gx = 0.0
    gy = 0.0
    for i in range(n):
        if poly[i, 2] < 0.0:
            i1 = i + 1 if i + 1 < n else 0
            gx += poly[i1, 1] - poly[i, 1]  # outward normal of a ccw edge (dy, -dx)
            gy -= poly[i1, 0] - poly[i, 0]
    return gx, gy


@njit(cache=True)
def area_centroid(poly, n):
    """Signed area and centroid of polygon ``poly[:n]`` (shoelace formula)."""
    a2 = 0.0
    sx = 0.0
    sy = 0.0
    x0 = poly[0, 0]
    y0 = poly[0, 1]
    xi = poly[n - 1, 0] - x0  # relative to the first vertex for round-off
    yi = poly[n - 1, 1] - y0
    for j in range(n):
        xj = poly[j, 0] - x0
        yj = poly[j, 1] - y0
        cr = xi * yj - xj * yi
        a2 += cr
        sx += (xi + xj) * cr
        sy += (yi + yj) * cr
        xi = xj
        yi = yj
    if a2 == 0.0:
        return 0.0, x0, y0
    return 0.5 * a2, x0 + sx / (3.0 * a2), y0 + sy / (3.0 * a2)


@njit(cache=True)
def overlap_pieces(pa, na, ra, pb, nb, rb, piece_a, piece_b, out, tmp):
    """Overlap of polygons A = ``pa[:na]`` and B = ``pb[:nb]`` (ccw, 3 or 4 vertices).

    ``ra``/``rb`` are their reflex vertices (-1: convex); their boxes are known to overlap.

    Four scratch arrays (MAXV, 3) passed separately (no array views in the hot loop: each
    view costs numba an atomic reference count).  Returns ``(area, cx, cy, gx, gy)``:
    overlap area, its centroid and the unnormalised normal ``G`` (A's outward edge normals
    weighted by their lengths inside B; points from A to B, ``|G|`` = contact length).
    Non-convex quads are split into two triangles and the sub-pair results summed (internal
    diagonals cancel in ``G``).
    """
    if ra < 0 and rb < 0:  # both convex (the common case): no copies into the pieces
        m = _clip_convex(pa, na, pb, nb, out, tmp)
        if m < 3:
            return 0.0, 0.0, 0.0, 0.0, 0.0
        a, cx, cy = area_centroid(out, m)
        if a <= 0.0:
            return 0.0, 0.0, 0.0, 0.0, 0.0
        gx, gy = _subject_normal(out, m)
        return a, (a * cx) / a, (a * cy) / a, gx, gy  # the general path's sums, same rounding
    npa = 1 if ra < 0 else 2
    npb = 1 if rb < 0 else 2
    area = 0.0
    sx = 0.0
    sy = 0.0
    gx = 0.0
    gy = 0.0
    for ia in range(npa):
        ka = _load_piece(pa, na, ra, ia, piece_a)
        for ib in range(npb):
            kb = _load_piece(pb, nb, rb, ib, piece_b)
            m = _clip_convex(piece_a, ka, piece_b, kb, out, tmp)
            if m < 3:
                continue
            a, cx, cy = area_centroid(out, m)
            if a <= 0.0:
                continue
            area += a
            sx += a * cx
            sy += a * cy
            g1, g2 = _subject_normal(out, m)
            gx += g1
            gy += g2
    if area <= 0.0:
        return 0.0, 0.0, 0.0, 0.0, 0.0
    return area, sx / area, sy / area, gx, gy


@njit(cache=True)
def overlap_geometry(pa, na, pb, nb, work):
    """``overlap_pieces`` of two lone polygons ``pa[:na]``, ``pb[:nb]``.

    The polygons are ccw with 3 or 4 vertices; the box test is made and the reflex vertices
    found here.  ``work`` is scratch of shape (4, MAXV, 3).  Returns
    ``(area, cx, cy, gx, gy)``.
    """
    axmin, aymin, axmax, aymax = polygon_box(pa, _OWN_VERTICES, 0, na)
    bxmin, bymin, bxmax, bymax = polygon_box(pb, _OWN_VERTICES, 0, nb)
    if axmin >= bxmax or bxmin >= axmax or aymin >= bymax or bymin >= aymax:
        return 0.0, 0.0, 0.0, 0.0, 0.0
    return overlap_pieces(pa, na, reflex_vertex(pa, _OWN_VERTICES, 0, na), pb, nb,
                          reflex_vertex(pb, _OWN_VERTICES, 0, nb),
                          work[0], work[1], work[2], work[3])


@njit(cache=True)
def normal_length(pa, pb, nen, area, gx, gy):
    """Unit normal (A -> B) and contact length ``L_c`` from the area gradient ``G``.

    When ``G`` vanishes (one element inside the other): centroid to centroid,
    ``L_c = sqrt(A)``.
    """
    lc = np.sqrt(gx * gx + gy * gy)
    if lc > 1e-12 * np.sqrt(area):
        return gx / lc, gy / lc, lc
    ca, cax, cay = area_centroid(pa, nen)
    cb, cbx, cby = area_centroid(pb, nen)
    dx = cbx - cax
    dy = cby - cay
    d = np.sqrt(dx * dx + dy * dy)
    if d > 0.0:
        return dx / d, dy / d, np.sqrt(area)
    return 0.0, 1.0, np.sqrt(area)


@njit(cache=True)
def _edge_separates(pc, nc, ps, ns):
    """Some edge of convex ``pc[:nc]`` (ccw) has every vertex of ``ps[:ns]`` on or outside it.

    The side test is the clipping's own (``_clip_pass``: inside when ``d >= 0``).
    """
    for j in range(nc):
        ax, ay, ex, ey = _edge(pc, nc, j)
        outside = True
        for k in range(ns):
            if ex * (ps[k, 1] - ay) - ey * (ps[k, 0] - ax) > 0.0:
                outside = False
                break
        if outside:
            return True
    return False


@njit(cache=True)
def convex_apart(pa, na, pb, nb):
    """Convex polygons ``pa[:na]`` and ``pb[:nb]`` (ccw) overlap in no area.

    Separating-axis theorem: two convex polygons have disjoint interiors exactly when an
    edge line of one of them leaves the other wholly on its outer side (touching counts as
    apart). Elements of a conforming patch that touch along an edge or at a vertex (the
    contact candidates still tied at one vertex, and edge neighbours whose bond has failed)
    are told apart here at the cost of a few cross products. The clipping alone can return
    a sliver of round-off area for two elements that share an edge (an intersection point
    one unit of round-off off the edge), with a contact length of the whole edge on which
    the contact damping and the tangential spring then act: touching is not contact.
    """
    return _edge_separates(pb, nb, pa, na) or _edge_separates(pa, na, pb, nb)


@njit(cache=True, inline="always")
def pair_overlap(a, b, ra, rb, x, element_nodes, pa, pb, piece_a, piece_b, out, tmp):
    """Overlap of elements a (A) and b (B) of the mesh.

    Their boxes are known to overlap and ``ra``/``rb`` are their reflex vertices: copies
    their vertices into ``pa``/``pb`` (4, 2) and returns ``(area, cx, cy, nx, ny, L_c)``,
    all zero when they do not overlap. Two convex elements that only touch (most candidate
    pairs of an intact patch whose boxes overlap: diagonal neighbours, and edge neighbours
    whose bond has failed) are rejected by :func:`convex_apart` before the clipping.

    Inlined into its callers (numba IR): it runs once per candidate pair whose boxes
    overlap, and as a call passing eight arrays field by field it would cost the contact
    kernel ~9 % (1e3-element collapse).
    """
    nen = element_nodes.shape[1]
    for k in range(nen):
        na_ = element_nodes[a, k]
        nb_ = element_nodes[b, k]
        pa[k, 0] = x[na_, 0]
        pa[k, 1] = x[na_, 1]
        pb[k, 0] = x[nb_, 0]
        pb[k, 1] = x[nb_, 1]
    if ra < 0 and rb < 0 and convex_apart(pa, nen, pb, nen):  # touching, not overlapping
        return 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    area, cx, cy, gx, gy = overlap_pieces(pa, nen, ra, pb, nen, rb, piece_a, piece_b, out, tmp)
    if area <= 0.0:
        return 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    nx, ny, lc = normal_length(pa, pb, nen, area, gx, gy)
    return area, cx, cy, nx, ny, lc


# --------------------------------------------------------------------------------------
# Python level
# --------------------------------------------------------------------------------------
def check_mesh(x: np.ndarray, element_nodes: np.ndarray) -> None:
    """Raise a ValueError unless the mesh arrays are valid.

    ``x`` must be finite (n_nodes, 2) and ``element_nodes`` (n_elements, 3 or 4) must index
    its rows.
    """
    if x.ndim != 2 or x.shape[1] != 2:
        raise ValueError(f"x must have shape (n_nodes, 2), got {x.shape}")
    if not np.isfinite(x).all():
        bad = int(np.argmax(~np.isfinite(x).all(axis=1)))
        raise ValueError(
            f"x (node coordinates) contains NaN or inf, first at node {bad}: {x[bad].tolist()}; "
            "the run is probably unstable (reduce dt or check stiffnesses)"
        )
    if element_nodes.ndim != 2 or element_nodes.shape[1] not in (3, 4):
        raise ValueError(
            f"element_nodes must have shape (n_elements, 3 or 4), got {element_nodes.shape}"
        )
    if element_nodes.size and (element_nodes.min() < 0 or element_nodes.max() >= x.shape[0]):
        raise ValueError(f"element_nodes must index nodes 0..{x.shape[0] - 1}")


def overlap(poly_a: np.ndarray, poly_b: np.ndarray) -> tuple[float, np.ndarray, np.ndarray]:
    """Overlap of two polygons (3 or 4 vertices each, either orientation).

    Returns ``(area, centroid (2,), normal (2,))``: overlap area [m2], its centroid and the
    unit contact normal pointing from A to B (gradient of the overlap area under a
    translation of B, negated); zeros when they do not overlap.
    """
    pa = np.array(poly_a, dtype=np.float64)
    pb = np.array(poly_b, dtype=np.float64)
    for name, p in (("poly_a", pa), ("poly_b", pb)):
        if p.ndim != 2 or p.shape[1] != 2 or p.shape[0] not in (3, 4):
            raise ValueError(f"{name} must have shape (3 or 4, 2), got {p.shape}")
        if not np.isfinite(p).all():
            raise ValueError(f"{name} contains NaN or inf: {p.tolist()}")
    for p in (pa, pb):
        if area_centroid(p, p.shape[0])[0] < 0.0:
            p[:] = p[::-1].copy()  # make it counter-clockwise
    work = np.empty((4, MAXV, 3))
    area, cx, cy, gx, gy = overlap_geometry(pa, pa.shape[0], pb, pb.shape[0], work)
    g = np.hypot(gx, gy)
    normal = np.array([gx / g, gy / g]) if g > 0.0 else np.zeros(2)
    return float(area), np.array([cx, cy]), normal
