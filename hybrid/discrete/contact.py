"""Contact between discrete elements: grid broad phase and overlap-area narrow phase.

Thesis (G. S. Bala 2008) sections 4.2-4.3 and appendices A-C; design.md section "Contact".

Units: m, kN, kPa, s, t; forces are per unit thickness (kN/m), areas in m2 (per unit
thickness m3/m), energies in kJ/m.

Narrow phase (one element pair A-B, both polygons counter-clockwise):

* overlap polygon by Sutherland-Hodgman clipping of convex polygons; a deformed non-convex
  quad is split into two triangles along the diagonal through its reflex vertex, and the
  overlap of two split elements is the sum over the convex sub-pairs;
* overlap area ``A`` and centroid ``c`` by the shoelace formula;
* contact normal: the gradient of the overlap area under a translation of B relative to A,
  ``G = sum over A's edges of n_edge * (length of the edge inside B)`` (outward unit normals
  of A), summed over the outline edges of the clipped polygon that lie on A's boundary (the
  clipping labels them).  ``|G|`` is the contact (chord) length ``L_c`` and ``n = G / |G|``
  points from A to B.
  With two boundary intersection points ``G`` is exactly the normal of the chord joining them
  times its length (the thesis's appendix C case analysis reduces to this vector geometry).
  When ``G`` vanishes (one element wholly inside the other) the normal falls back to the
  direction from A's centroid to B's centroid (then (0, 1)) and ``L_c = sqrt(A)``;
* normal force on B: ``F_n = k_n A - c_n v_n`` (eq 4.6 plus viscous contact damping), clamped
  at zero (never adhesive), with ``v_n = v_rel . n`` (``v_rel = v_B - v_A`` at ``c``),
  ``c_n = 2 zeta sqrt(k_eff m_eff)``, ``k_eff = k_n L_c = dF_n/d(penetration)`` and
  ``m_eff = m_A m_B / (m_A + m_B)`` from the elements' lumped nodal masses (sum over their
  nodes); an element with a non-finite mass is rigid and ``m_eff`` is the other's mass;
* tangential force on B: incremental spring ``dF_t = -k_t L_c v_t dt`` (eq 4.9), history kept
  per pair (``shear``), rotated onto the current tangent each step (projected, magnitude
  kept), capped at ``mu F_n`` (eq 4.10).  Slip work ``mu F_n * slip`` is the friction
  dissipation (``slip = (|F_trial| - mu F_n) / (k_t L_c)``);
* ``k_n`` and ``k_t`` are interface stiffnesses in kPa/m (traction per unit displacement):
  a penetration ``d`` over a contact length ``L_c`` gives ``F_n = k_n A ~ k_n d L_c``, and the
  tangential spring stiffness of the pair is ``k_t L_c`` (kN/m per m);
* the pair force acts at the overlap centroid ``c``; it goes to each element's nodes through
  the element's shape functions at ``c`` (Q4: bilinear, the isoparametric map inverted by
  Newton, clamped to [-1, 1]; T3: barycentric).  The shape functions sum to one and
  reproduce ``c`` (``sum N_i x_i = c``), so each element receives the full force and no
  moment about ``c``: the moment of the contact force about an element's centre comes out
  of the distribution itself.  The two elements get equal and opposite nodal sums.  (If
  ``c`` lies outside a non-convex element the Q4 clamp breaks the moment balance: documented
  limitation.)  Between two elements with different materials every entry of
  ``contact_table`` is the smaller of the two.

Broad phase: elements are count-sorted into a uniform grid by the centre of their box
(grown by ``margin``), with the cell size at least the largest grown box, so that a pair of
overlapping boxes lies in 3x3 neighbouring cells (Munjiza's NBS idea; cost linear in the
number of elements).  A few oversized elements (box > 4x the median, e.g. one large rigid
ground block) are kept out of the grid and checked against all elements.

Energy (``contact_energy``, ``mid_step_work``; used by ``hybrid.discrete.run``'s ledger):
the stored elastic energy is ``k_n A^2 / (2 L_c)`` (exact for a flat penetration at constant
``L_c``; 3/4 of the true integral for a corner wedge) plus ``|F_t|^2 / (2 k_t L_c)``.  The
dissipations are measured as the work of the damping and tangential parts of the applied
forces (``split_force``) on the mid-step velocity, which is exactly what the central-difference
update takes from the kinetic energy; the kernel's own returns use the start-of-step velocity
(``c_n v_n^2 dt``, ``mu F_n x slip``), which overestimates the damping when a contact vibrates
at a few time steps per period.

Determinism: ``contact_forces`` computes every pair into a per-pair buffer (``prange`` over
interleaved blocks of pairs, no reductions) and scatters to the nodes serially in pair order,
so results are bit-identical for any number of threads.

Speed (issue 4): element boxes and reflex vertices are computed once per call (not per pair)
and a pair whose boxes do not overlap returns before its coordinates are gathered; scratch
and per-pair outputs are passed as whole arrays with an index (an array view such as
``shear[p]`` costs numba an atomic reference count per pair, and the threads contend for it);
two convex elements are clipped without copying them into pieces; the work items take
interleaved blocks of pairs (numba's static schedule otherwise gives one thread most of the
active pairs).  Same results to the bit as before these changes.
"""

from __future__ import annotations

import numpy as np
from numba import njit, prange

import hybrid  # noqa: F401  (sets NUMBA_CACHE_DIR / OMP_WAIT_POLICY before numba compiles)

__all__ = [
    "carry_contact_history",
    "compute_contact_forces",
    "contact_energy",
    "contact_forces",
    "mid_step_work",
    "find_contact_pairs",
    "overlap",
    "rigid_contact_mass",
]

_MAXV = 16  # vertex capacity of the clipping buffers (two convex <=4-gons clip to <= 8)
_CHUNK = 64  # pairs per block of consecutive pairs
_N_ITEMS = 64  # parallel work items; item i takes blocks i, i + 64, ... (load balance)
_BIG_FACTOR = 4.0  # elements with a box > this x the median box bypass the grid
_MAX_BIG = 64  # at most this many oversized elements bypass the grid


# --------------------------------------------------------------------------------------
# Narrow phase: polygon kernels
# --------------------------------------------------------------------------------------
@njit(cache=True)
def _reflex_vertex(poly, n):
    """Index of the reflex vertex of a counter-clockwise quad, -1 if convex (or n != 4).

    Vertex i is reflex when the cross product of its incoming and outgoing edges is negative
    (a simple quad has at most one).
    """
    if n != 4:
        return -1
    for i in range(4):
        ip = (i + 3) % 4
        inx = (i + 1) % 4
        ax = poly[i, 0] - poly[ip, 0]
        ay = poly[i, 1] - poly[ip, 1]
        bx = poly[inx, 0] - poly[i, 0]
        by = poly[inx, 1] - poly[i, 1]
        cr = ax * by - ay * bx
        scale = (abs(ax) + abs(ay)) * (abs(bx) + abs(by))
        if cr < -1e-14 * scale:
            return i
    return -1


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
    """One Sutherland-Hodgman pass: keep the part of ``src[:n]`` left of the edge through
    (ax, ay) with direction (ex, ey); write it to ``dst``, return its vertex count.

    Column 2 labels the edge leaving each vertex: -1 on the subject polygon's boundary, k on
    the clip polygon's edge k (``first``: ``src`` is the subject itself, every label -1); an
    edge keeps its label when clipped, and the stretch along the clip line gets ``j``."""
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


@njit(cache=True)
def _clip_convex(sub, ns, clip, nc, out, tmp):
    """Sutherland-Hodgman clipping of convex ``sub[:ns]`` by convex ``clip[:nc]`` (both ccw).

    The result goes to ``out`` (``tmp`` is scratch, both of shape (_MAXV, 3); the two are
    used in turn as source and destination, so that the last pass ends in ``out``; explicit
    branches rather than array variables: no reference counting in the hot loop); returns
    the number of vertices of the overlap polygon (0 when they do not overlap). Column 2 of
    ``out`` labels each outline edge (see ``_clip_pass``).
    """
    n = ns
    for j in range(nc):
        ax = clip[j, 0]
        ay = clip[j, 1]
        j1 = j + 1 if j + 1 < nc else 0
        ex = clip[j1, 0] - ax
        ey = clip[j1, 1] - ay
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


@njit(cache=True)
def _subject_normal(poly, n):
    """Sum of (outward normal x length) over the outline edges of the clipped polygon
    ``poly[:n]`` that lie on the subject's boundary (label -1): the subject's edge lengths
    inside the clip polygon along their outward normals, i.e. minus the gradient of the
    overlap area under a translation of the clip polygon."""
    gx = 0.0
    gy = 0.0
    for i in range(n):
        if poly[i, 2] < 0.0:
            i1 = i + 1 if i + 1 < n else 0
            gx += poly[i1, 1] - poly[i, 1]  # outward normal of a ccw edge (dy, -dx)
            gy -= poly[i1, 0] - poly[i, 0]
    return gx, gy


@njit(cache=True)
def _area_centroid(poly, n):
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
def _overlap_geometry(pa, na, pb, nb, work):
    """Overlap of polygons A = ``pa[:na]`` and B = ``pb[:nb]`` (ccw, 3 or 4 vertices).

    ``work`` is scratch of shape (4, _MAXV, 3).  Returns ``(area, cx, cy, gx, gy)``: overlap
    area, its centroid and the unnormalised normal ``G`` (A's outward edge normals weighted
    by their lengths inside B; points from A to B, ``|G|`` = contact length).  Non-convex
    quads are split into two triangles and the sub-pair results summed (internal diagonals
    cancel in ``G``).
    """
    # quick reject on the bounding boxes
    axmin = pa[0, 0]
    axmax = pa[0, 0]
    aymin = pa[0, 1]
    aymax = pa[0, 1]
    for i in range(1, na):
        axmin = min(axmin, pa[i, 0])
        axmax = max(axmax, pa[i, 0])
        aymin = min(aymin, pa[i, 1])
        aymax = max(aymax, pa[i, 1])
    bxmin = pb[0, 0]
    bxmax = pb[0, 0]
    bymin = pb[0, 1]
    bymax = pb[0, 1]
    for i in range(1, nb):
        bxmin = min(bxmin, pb[i, 0])
        bxmax = max(bxmax, pb[i, 0])
        bymin = min(bymin, pb[i, 1])
        bymax = max(bymax, pb[i, 1])
    if axmin >= bxmax or bxmin >= axmax or aymin >= bymax or bymin >= aymax:
        return 0.0, 0.0, 0.0, 0.0, 0.0
    return _overlap_pieces(pa, na, _reflex_vertex(pa, na), pb, nb, _reflex_vertex(pb, nb),
                           work[0], work[1], work[2], work[3])


@njit(cache=True)
def _overlap_pieces(pa, na, ra, pb, nb, rb, piece_a, piece_b, out, tmp):
    """``_overlap_geometry`` without the box test, the reflex vertices ``ra``/``rb`` given;
    four scratch arrays (_MAXV, 3) passed separately (no array views in the hot loop: each
    view costs numba an atomic reference count)."""
    if ra < 0 and rb < 0:  # both convex (the common case): no copies into the pieces
        m = _clip_convex(pa, na, pb, nb, out, tmp)
        if m < 3:
            return 0.0, 0.0, 0.0, 0.0, 0.0
        a, cx, cy = _area_centroid(out, m)
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
            a, cx, cy = _area_centroid(out, m)
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
def _element_box_reflex(x, element_nodes, e, boxes, reflex):
    """Box [xmin, ymin, xmax, ymax] (not grown) and reflex vertex (as ``_reflex_vertex``,
    same arithmetic) of element ``e`` from the node coordinates, into ``boxes[e]``,
    ``reflex[e]``."""
    nen = element_nodes.shape[1]
    n0 = element_nodes[e, 0]
    xmin = x[n0, 0]
    xmax = xmin
    ymin = x[n0, 1]
    ymax = ymin
    for k in range(1, nen):
        nk = element_nodes[e, k]
        xmin = min(xmin, x[nk, 0])
        xmax = max(xmax, x[nk, 0])
        ymin = min(ymin, x[nk, 1])
        ymax = max(ymax, x[nk, 1])
    boxes[e, 0] = xmin
    boxes[e, 1] = ymin
    boxes[e, 2] = xmax
    boxes[e, 3] = ymax
    r = -1
    if nen == 4:
        for i in range(4):
            p = element_nodes[e, (i + 3) % 4]
            c = element_nodes[e, i]
            q = element_nodes[e, (i + 1) % 4]
            ax = x[c, 0] - x[p, 0]
            ay = x[c, 1] - x[p, 1]
            bx = x[q, 0] - x[c, 0]
            by = x[q, 1] - x[c, 1]
            cr = ax * by - ay * bx
            scale = (abs(ax) + abs(ay)) * (abs(bx) + abs(by))
            if cr < -1e-14 * scale:
                r = i
                break
    reflex[e] = r


@njit(cache=True)
def _shape_weights(poly, n, px, py, w, row):
    """Shape-function values of element ``poly[:n]`` at point (px, py) into ``w[row, :n]``.

    Q4: bilinear ``N_i = (1 + xi xi_i)(1 + eta eta_i) / 4``, the isoparametric map inverted
    by Newton iterations from the centre, (xi, eta) clamped to [-1, 1].  T3: barycentric
    coordinates (signed sub-triangle areas / area).  In both ``sum N_i = 1``.
    """
    if n == 3:
        x0 = poly[0, 0]
        y0 = poly[0, 1]
        x1 = poly[1, 0]
        y1 = poly[1, 1]
        x2 = poly[2, 0]
        y2 = poly[2, 1]
        det = (x1 - x0) * (y2 - y0) - (x2 - x0) * (y1 - y0)
        if det == 0.0:
            w[row, 0] = w[row, 1] = w[row, 2] = 1.0 / 3.0
            return
        w1 = ((px - x0) * (y2 - y0) - (x2 - x0) * (py - y0)) / det
        w2 = ((x1 - x0) * (py - y0) - (px - x0) * (y1 - y0)) / det
        w[row, 1] = w1
        w[row, 2] = w2
        w[row, 0] = 1.0 - w1 - w2
        return
    x0 = poly[0, 0]
    x1 = poly[1, 0]
    x2 = poly[2, 0]
    x3 = poly[3, 0]
    y0 = poly[0, 1]
    y1 = poly[1, 1]
    y2 = poly[2, 1]
    y3 = poly[3, 1]
    # x(xi, eta) = a0 + a1 xi + a2 eta + a3 xi eta (same for y with b)
    a0 = 0.25 * (x0 + x1 + x2 + x3)
    a1 = 0.25 * (-x0 + x1 + x2 - x3)
    a2 = 0.25 * (-x0 - x1 + x2 + x3)
    a3 = 0.25 * (x0 - x1 + x2 - x3)
    b0 = 0.25 * (y0 + y1 + y2 + y3)
    b1 = 0.25 * (-y0 + y1 + y2 - y3)
    b2 = 0.25 * (-y0 - y1 + y2 + y3)
    b3 = 0.25 * (y0 - y1 + y2 - y3)
    xi = 0.0
    eta = 0.0
    for _ in range(12):
        rx = a0 + a1 * xi + a2 * eta + a3 * xi * eta - px
        ry = b0 + b1 * xi + b2 * eta + b3 * xi * eta - py
        j11 = a1 + a3 * eta
        j12 = a2 + a3 * xi
        j21 = b1 + b3 * eta
        j22 = b2 + b3 * xi
        det = j11 * j22 - j12 * j21
        if det == 0.0:
            break
        dxi = (j22 * rx - j12 * ry) / det
        deta = (-j21 * rx + j11 * ry) / det
        xi = min(1.0, max(-1.0, xi - dxi))
        eta = min(1.0, max(-1.0, eta - deta))
        if abs(dxi) + abs(deta) < 1e-10:  # quadratic convergence: next error ~1e-20
            break
    w[row, 0] = 0.25 * (1.0 - xi) * (1.0 - eta)
    w[row, 1] = 0.25 * (1.0 + xi) * (1.0 - eta)
    w[row, 2] = 0.25 * (1.0 + xi) * (1.0 + eta)
    w[row, 3] = 0.25 * (1.0 - xi) * (1.0 + eta)


@njit(cache=True)
def _pair_contact(
    a,
    b,
    ra,
    rb,
    x,
    v,
    mass,
    element_nodes,
    element_material,
    contact_table,
    shear,
    p,
    dt,
    pa,
    pb,
    piece_a,
    piece_b,
    out,
    tmp,
    wa,
    wb,
):
    """Contact force on element B from element A (A gets the opposite).

    The caller has checked that the boxes of A and B overlap; ``ra``/``rb`` are their reflex
    vertices (-1: convex).  Fills row ``p`` of ``wa``/``wb`` with the shape-function weights
    at the overlap centroid, updates the pair's tangential history ``shear[p]`` in place and
    returns ``(active, fx, fy, diss_friction, diss_damping, f_damp, nx, ny)`` (``f_damp``:
    the damping part of the normal force as applied, after the clamp, along ``(nx, ny)``;
    the tangential part of the force is ``(fx, fy) - f_n (nx, ny)``); formulas in the module
    docstring.
    """
    nen = element_nodes.shape[1]
    for k in range(nen):
        na_ = element_nodes[a, k]
        nb_ = element_nodes[b, k]
        pa[k, 0] = x[na_, 0]
        pa[k, 1] = x[na_, 1]
        pb[k, 0] = x[nb_, 0]
        pb[k, 1] = x[nb_, 1]
    area, cx, cy, gx, gy = _overlap_pieces(pa, nen, ra, pb, nen, rb, piece_a, piece_b, out, tmp)
    if area <= 0.0:
        shear[p, 0] = 0.0
        shear[p, 1] = 0.0
        return 0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0

    # contact normal (A -> B) and contact length
    nx, ny, lc = _normal_length(pa, pb, nen, area, gx, gy)

    # pair properties: the smaller of the two materials' entries
    ma_ = element_material[a]
    mb_ = element_material[b]
    kn = min(contact_table[ma_, 0], contact_table[mb_, 0])
    kt = min(contact_table[ma_, 1], contact_table[mb_, 1])
    mu = min(contact_table[ma_, 2], contact_table[mb_, 2])
    zeta = min(contact_table[ma_, 3], contact_table[mb_, 3])

    # shape functions at the contact point, relative velocity of B w.r.t. A, masses
    _shape_weights(pa, nen, cx, cy, wa, p)
    _shape_weights(pb, nen, cx, cy, wb, p)
    vx = 0.0
    vy = 0.0
    m_a = 0.0
    m_b = 0.0
    for k in range(nen):
        na_ = element_nodes[a, k]
        nb_ = element_nodes[b, k]
        vx += wb[p, k] * v[nb_, 0] - wa[p, k] * v[na_, 0]
        vy += wb[p, k] * v[nb_, 1] - wa[p, k] * v[na_, 1]
        m_a += mass[na_]
        m_b += mass[nb_]
    if np.isfinite(m_a) and np.isfinite(m_b):
        m_eff = m_a * m_b / (m_a + m_b) if m_a + m_b > 0.0 else 0.0
    elif np.isfinite(m_a):
        m_eff = m_a
    elif np.isfinite(m_b):
        m_eff = m_b
    else:
        m_eff = 0.0

    # normal force (eq 4.6) + damping, never adhesive
    vn = vx * nx + vy * ny
    f_el = kn * area
    c_n = 2.0 * zeta * np.sqrt(kn * lc * m_eff)
    f_n = f_el - c_n * vn
    if f_n < 0.0:
        f_n = 0.0
    diss_d = -(f_n - f_el) * vn * dt

    # tangential spring (eq 4.9): rotate history onto the current tangent, increment, cap
    sx = shear[p, 0]
    sy = shear[p, 1]
    s_old = np.sqrt(sx * sx + sy * sy)
    sn = sx * nx + sy * ny
    sx -= sn * nx
    sy -= sn * ny
    s_proj = np.sqrt(sx * sx + sy * sy)
    if s_proj > 0.0:
        sx *= s_old / s_proj
        sy *= s_old / s_proj
    vtx = vx - vn * nx
    vty = vy - vn * ny
    k_t = kt * lc
    sx -= k_t * vtx * dt
    sy -= k_t * vty * dt
    s_tr = np.sqrt(sx * sx + sy * sy)
    cap = mu * f_n  # eq 4.10
    diss_f = 0.0
    if s_tr > cap:
        if k_t > 0.0:
            diss_f = cap * (s_tr - cap) / k_t  # force x slip
        scale = cap / s_tr
        sx *= scale
        sy *= scale
    shear[p, 0] = sx
    shear[p, 1] = sy
    return 1, f_n * nx + sx, f_n * ny + sy, diss_f, diss_d, f_n - f_el, nx, ny


@njit(cache=True)
def _normal_length(pa, pb, nen, area, gx, gy):
    """Unit normal (A -> B) and contact length ``L_c`` from the area gradient ``G``; when
    ``G`` vanishes (one element inside the other): centroid to centroid, ``L_c = sqrt(A)``."""
    lc = np.sqrt(gx * gx + gy * gy)
    if lc > 1e-12 * np.sqrt(area):
        return gx / lc, gy / lc, lc
    ca, cax, cay = _area_centroid(pa, nen)
    cb, cbx, cby = _area_centroid(pb, nen)
    dx = cbx - cax
    dy = cby - cay
    d = np.sqrt(dx * dx + dy * dy)
    if d > 0.0:
        return dx / d, dy / d, np.sqrt(area)
    return 0.0, 1.0, np.sqrt(area)


@njit(cache=True)
def _boxes_apart(boxes, a, b):
    """The (ungrown) boxes of elements a and b do not overlap (the narrow phase's reject)."""
    return (
        boxes[a, 0] >= boxes[b, 2]
        or boxes[b, 0] >= boxes[a, 2]
        or boxes[a, 1] >= boxes[b, 3]
        or boxes[b, 1] >= boxes[a, 3]
    )


@njit(parallel=True, cache=True)
def _contact_kernel(
    x,
    v,
    mass,
    element_nodes,
    element_material,
    contact_table,
    pairs,
    shear,
    dt,
    force,
    split_force,
    with_split,
):
    """``contact_forces`` (see there); with ``with_split`` the damping part of the normal
    forces (as applied, after the clamp) is also added to ``split_force[0]`` and the
    tangential part to ``split_force[1]``."""
    n_pairs = pairs.shape[0]
    n_el = element_nodes.shape[0]
    nen = element_nodes.shape[1]
    # per element, once per call: box and reflex vertex (not once per pair)
    boxes = np.empty((n_el, 4))
    reflex = np.empty(n_el, dtype=np.int64)
    for e in prange(n_el):
        _element_box_reflex(x, element_nodes, e, boxes, reflex)
    f_pair = np.empty((n_pairs, 2))  # every entry is written for the active pairs
    w_a = np.empty((n_pairs, nen))
    w_b = np.empty((n_pairs, nen))
    diss = np.empty((n_pairs, 2))
    f_split = np.empty((n_pairs if with_split else 1, 4))
    active = np.empty(n_pairs, dtype=np.int8)
    # numba schedules prange statically (one contiguous range of items per thread) and the
    # active pairs cluster (pairs are sorted by element): each item takes interleaved blocks
    n_blocks = (n_pairs + _CHUNK - 1) // _CHUNK
    n_items = min(_N_ITEMS, n_blocks)
    for item in prange(n_items):
        pa = np.empty((4, 2))
        pb = np.empty((4, 2))
        piece_a = np.empty((_MAXV, 3))
        piece_b = np.empty((_MAXV, 3))
        out = np.empty((_MAXV, 3))
        tmp = np.empty((_MAXV, 3))
        for blk in range(item, n_blocks, n_items):
            start = blk * _CHUNK
            stop = min(n_pairs, start + _CHUNK)
            for p in range(start, stop):
                a = pairs[p, 0]
                b = pairs[p, 1]
                if _boxes_apart(boxes, a, b):  # most candidate pairs: no overlap, no force
                    active[p] = 0
                    shear[p, 0] = 0.0
                    shear[p, 1] = 0.0
                    continue
                act, fx, fy, d_f, d_d, fd, nx, ny = _pair_contact(
                    a,
                    b,
                    reflex[a],
                    reflex[b],
                    x,
                    v,
                    mass,
                    element_nodes,
                    element_material,
                    contact_table,
                    shear,
                    p,
                    dt,
                    pa,
                    pb,
                    piece_a,
                    piece_b,
                    out,
                    tmp,
                    w_a,
                    w_b,
                )
                active[p] = act
                f_pair[p, 0] = fx
                f_pair[p, 1] = fy
                diss[p, 0] = d_f
                diss[p, 1] = d_d
                if with_split and act:
                    f_split[p, 0] = fd * nx
                    f_split[p, 1] = fd * ny
                    f_split[p, 2] = shear[p, 0]
                    f_split[p, 3] = shear[p, 1]
    n_active = 0
    diss_f = 0.0
    diss_d = 0.0
    for p in range(n_pairs):
        if active[p] == 0:
            continue
        n_active += 1
        diss_f += diss[p, 0]
        diss_d += diss[p, 1]
        a = pairs[p, 0]
        b = pairs[p, 1]
        fx = f_pair[p, 0]
        fy = f_pair[p, 1]
        for k in range(nen):
            na_ = element_nodes[a, k]
            nb_ = element_nodes[b, k]
            force[na_, 0] -= w_a[p, k] * fx
            force[na_, 1] -= w_a[p, k] * fy
            force[nb_, 0] += w_b[p, k] * fx
            force[nb_, 1] += w_b[p, k] * fy
        if with_split:
            for c in range(2):
                dx = f_split[p, 2 * c]
                dy = f_split[p, 2 * c + 1]
                for k in range(nen):
                    na_ = element_nodes[a, k]
                    nb_ = element_nodes[b, k]
                    split_force[c, na_, 0] -= w_a[p, k] * dx
                    split_force[c, na_, 1] -= w_a[p, k] * dy
                    split_force[c, nb_, 0] += w_b[p, k] * dx
                    split_force[c, nb_, 1] += w_b[p, k] * dy
    return n_active, diss_f, diss_d


_NO_SPLIT = np.zeros((2, 1, 2))


def contact_forces(
    x: np.ndarray,
    v: np.ndarray,
    mass: np.ndarray,
    element_nodes: np.ndarray,
    element_material: np.ndarray,
    contact_table: np.ndarray,
    pairs: np.ndarray,
    shear: np.ndarray,
    dt: float,
    force: np.ndarray,
    split_force: np.ndarray | None = None,
) -> tuple[int, float, float]:
    """Add the contact forces of the candidate ``pairs`` to ``force`` (n_nodes, 2) in place.

    Arguments (state layout of ``DiscreteState``): ``x``, ``v`` (n_nodes, 2) [m, m/s];
    ``mass`` (n_nodes,) lumped masses [t] (``inf`` on rigid elements, see
    ``rigid_contact_mass``); ``element_nodes`` (n_el, 3 or 4) ccw; ``element_material``
    (n_el,); ``contact_table`` (n_mat, 4) = [k_n kPa/m, k_t kPa/m, mu, zeta]; ``pairs``
    (n_pairs, 2); ``shear`` (n_pairs, 2) tangential force history on B [kN/m], updated in
    place (zeroed for separated pairs); ``dt`` [s].  ``split_force`` (2, n_nodes, 2), if
    given, receives (added) two parts of the nodal contact forces for the energy ledger:
    [0] the damping part of the normal forces as applied (after the no-adhesion clamp),
    [1] the tangential (friction spring) forces; their work with the mid-step velocity
    (``mid_step_work``) is the energy the central-difference update exchanges with them.

    Returns ``(n_active, dissipated_friction, dissipated_damping)``: number of pairs in
    contact and the energy dissipated during this step [kJ/m], both evaluated with the
    velocity ``v`` given (the start-of-step velocity v(t - dt/2) in the explicit loop: for
    damping this overestimates the dissipation when the contact vibrates near the time-step
    frequency, see ``mid_step_work``).  Per-pair forces are computed in parallel into a
    buffer, then scattered in pair order (deterministic).  This is the hot path: no input
    checks (``compute_contact_forces`` checks them).
    """
    if split_force is None:
        return _contact_kernel(x, v, mass, element_nodes, element_material, contact_table,
                               pairs, shear, dt, force, _NO_SPLIT, False)
    return _contact_kernel(x, v, mass, element_nodes, element_material, contact_table, pairs,
                           shear, dt, force, split_force, True)


@njit(cache=True)
def _mid_step_work(force, v_start, v_end, dt):
    s = 0.0
    for i in range(force.shape[0]):
        s += force[i, 0] * (v_start[i, 0] + v_end[i, 0])
        s += force[i, 1] * (v_start[i, 1] + v_end[i, 1])
    return 0.5 * dt * s


def mid_step_work(force: np.ndarray, v_start: np.ndarray, v_end: np.ndarray, dt: float) -> float:
    """Work [kJ/m] of nodal forces ``F(t)`` over one step with the mid-step velocity
    ``(v(t - dt/2) + v(t + dt/2)) / 2``: the central-difference update changes the kinetic
    energy by exactly ``sum F(t) . v_mid dt``, so this is the energy a force term gave the
    bodies in the step.  For the contact damping forces ``-mid_step_work`` is the
    dissipation that closes the ledger (``c_n v_n(t - dt/2)^2 dt`` overestimates it when a
    contact vibrates at a few time steps per period: D5 with zeta = 0.2 ran at -18 %)."""
    if not (force.shape == v_start.shape == v_end.shape) or force.ndim != 2:
        raise ValueError(
            f"force, v_start, v_end must have the same shape (n_nodes, 2), got "
            f"{force.shape}, {v_start.shape}, {v_end.shape}"
        )
    return float(_mid_step_work(force, v_start, v_end, float(dt)))


@njit(cache=True)
def _contact_energy(x, element_nodes, element_material, contact_table, pairs, shear):
    nen = element_nodes.shape[1]
    pa = np.empty((4, 2))
    pb = np.empty((4, 2))
    work = np.empty((4, _MAXV, 3))
    u_n = 0.0
    u_t = 0.0
    for p in range(pairs.shape[0]):
        a = pairs[p, 0]
        b = pairs[p, 1]
        for k in range(nen):
            pa[k, 0] = x[element_nodes[a, k], 0]
            pa[k, 1] = x[element_nodes[a, k], 1]
            pb[k, 0] = x[element_nodes[b, k], 0]
            pb[k, 1] = x[element_nodes[b, k], 1]
        area, cx, cy, gx, gy = _overlap_geometry(pa, nen, pb, nen, work)
        if area <= 0.0:
            continue
        nx, ny, lc = _normal_length(pa, pb, nen, area, gx, gy)
        ma_ = element_material[a]
        mb_ = element_material[b]
        kn = min(contact_table[ma_, 0], contact_table[mb_, 0])
        kt = min(contact_table[ma_, 1], contact_table[mb_, 1])
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
    _check_mesh(x, element_nodes)
    pairs = np.asarray(pairs, dtype=np.int64).reshape(-1, 2)
    shear = np.asarray(shear, dtype=np.float64)
    if shear.shape != pairs.shape:
        raise ValueError(f"shear must have shape (n_pairs, 2) = {pairs.shape}, got {shear.shape}")
    if pairs.shape[0] == 0:
        return 0.0, 0.0
    u_n, u_t = _contact_energy(x, element_nodes, np.asarray(element_material),
                               np.asarray(contact_table, dtype=np.float64), pairs, shear)
    return float(u_n), float(u_t)


# --------------------------------------------------------------------------------------
# Broad phase
# --------------------------------------------------------------------------------------
@njit(cache=True)
def _element_boxes(x, element_nodes, margin, boxes):
    """Axis-aligned boxes [xmin, ymin, xmax, ymax] of the elements, grown by ``margin``."""
    nen = element_nodes.shape[1]
    for e in range(element_nodes.shape[0]):
        n0 = element_nodes[e, 0]
        xmin = x[n0, 0]
        xmax = xmin
        ymin = x[n0, 1]
        ymax = ymin
        for k in range(1, nen):
            nk = element_nodes[e, k]
            xmin = min(xmin, x[nk, 0])
            xmax = max(xmax, x[nk, 0])
            ymin = min(ymin, x[nk, 1])
            ymax = max(ymax, x[nk, 1])
        boxes[e, 0] = xmin - margin
        boxes[e, 1] = ymin - margin
        boxes[e, 2] = xmax + margin
        boxes[e, 3] = ymax + margin


@njit(cache=True)
def _is_candidate(i, j, boxes, element_nodes, node_group, max_shared):
    """Boxes of i and j overlap (inclusive) and the elements share at most ``max_shared``
    tie groups."""
    if boxes[i, 0] > boxes[j, 2] or boxes[j, 0] > boxes[i, 2]:
        return False
    if boxes[i, 1] > boxes[j, 3] or boxes[j, 1] > boxes[i, 3]:
        return False
    nen = element_nodes.shape[1]
    shared = 0
    for ka in range(nen):
        ga = node_group[element_nodes[i, ka]]
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
    vertices, i.e. along an edge, are left out): two elements whose common edge has failed
    but that are still tied at one end (the other interfaces around that vertex hold) rotate
    about that vertex and would otherwise interpenetrate with no contact force, and enter
    contact with a deep overlap (a large energy kick) once the last tie goes.  Elements of a
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
    _check_mesh(x, element_nodes)
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
    """Copy the rows of ``old_shear`` whose pair is in ``new_pairs`` by merging the two pair
    lists; returns False (and copies nothing) unless both are strictly sorted
    lexicographically."""
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
    """Tangential history for ``new_pairs``: a pair present in ``old_pairs`` keeps its
    ``old_shear`` row, a new pair starts at zero.  Returns (n_new, 2) float64.
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


# --------------------------------------------------------------------------------------
# Python wrappers and helpers
# --------------------------------------------------------------------------------------
def _check_mesh(x: np.ndarray, element_nodes: np.ndarray) -> None:
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


def compute_contact_forces(
    x: np.ndarray,
    v: np.ndarray,
    mass: np.ndarray,
    element_nodes: np.ndarray,
    element_material: np.ndarray,
    contact_table: np.ndarray,
    pairs: np.ndarray,
    shear: np.ndarray,
    dt: float,
    force: np.ndarray,
    split_force: np.ndarray | None = None,
) -> tuple[int, float, float]:
    """Validate the inputs, then call ``contact_forces`` (same arguments)."""
    _check_mesh(np.asarray(x), np.asarray(element_nodes))
    n_nodes = x.shape[0]
    for name, arr, shape in (
        ("v", v, (n_nodes, 2)),
        ("force", force, (n_nodes, 2)),
        ("mass", mass, (n_nodes,)),
        ("element_material", element_material, (element_nodes.shape[0],)),
        ("shear", shear, (pairs.shape[0], 2)),
    ):
        if arr.shape != shape:
            raise ValueError(f"{name} must have shape {shape}, got {arr.shape}")
    if not np.isfinite(v).all():
        raise ValueError("v (velocities) contains NaN or inf: the run is unstable")
    if np.isnan(mass).any() or (mass < 0).any():
        raise ValueError("mass must be >= 0 (inf marks rigid elements), got NaN or negative")
    ct = np.asarray(contact_table)
    if ct.ndim != 2 or ct.shape[1] != 4:
        raise ValueError(f"contact_table must have shape (n_materials, 4), got {ct.shape}")
    if not np.isfinite(ct).all() or (ct < 0).any():
        raise ValueError(
            f"contact_table entries [k_n, k_t, mu, zeta] must be finite and >= 0, got {ct.tolist()}"
        )
    if element_material.size and (
        element_material.min() < 0 or element_material.max() >= ct.shape[0]
    ):
        raise ValueError(f"element_material must index contact_table rows 0..{ct.shape[0] - 1}")
    if pairs.ndim != 2 or pairs.shape[1] != 2:
        raise ValueError(f"pairs must have shape (n_pairs, 2), got {pairs.shape}")
    if pairs.size and (pairs.min() < 0 or pairs.max() >= element_nodes.shape[0]):
        raise ValueError(f"pairs must index elements 0..{element_nodes.shape[0] - 1}")
    if not (np.isfinite(dt) and dt > 0.0):
        raise ValueError(f"dt must be a finite time step > 0 [s], got {dt}")
    if split_force is not None and split_force.shape != (2, n_nodes, 2):
        raise ValueError(f"split_force must have shape {(2, n_nodes, 2)}, got {split_force.shape}")
    return contact_forces(
        x, v, mass, element_nodes, element_material, ct, pairs, shear, float(dt), force,
        split_force,
    )


def rigid_contact_mass(
    mass: np.ndarray, fixed: np.ndarray, element_nodes: np.ndarray
) -> np.ndarray:
    """Nodal masses for ``contact_forces``: ``inf`` on the nodes of elements whose nodes are
    all fixed in both directions (rigid ground, walls), the lumped mass elsewhere.
    """
    mass = np.asarray(mass, dtype=np.float64)
    fixed = np.asarray(fixed, dtype=bool)
    if fixed.shape != (mass.shape[0], 2):
        raise ValueError(f"fixed must have shape (n_nodes, 2) = ({mass.shape[0]}, 2)")
    rigid = fixed.all(axis=1)[element_nodes].all(axis=1)
    out = mass.copy()
    out[element_nodes[rigid].ravel()] = np.inf
    return out


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
        if _area_centroid(p, p.shape[0])[0] < 0.0:
            p[:] = p[::-1].copy()  # make it counter-clockwise
    work = np.empty((4, _MAXV, 3))
    area, cx, cy, gx, gy = _overlap_geometry(pa, pa.shape[0], pb, pb.shape[0], work)
    g = np.hypot(gx, gy)
    normal = np.array([gx / g, gy / g]) if g > 0.0 else np.zeros(2)
    return float(area), np.array([cx, cy]), normal
