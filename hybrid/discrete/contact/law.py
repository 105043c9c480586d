"""The contact force of one element pair.

The force law at the contact point and its distribution to the nodes.

Thesis (G. S. Bala 2008) section 4.3, eqs 4.6, 4.9, 4.10.  Force on B (A gets the
opposite), from the overlap area ``A``, its centroid ``c``, the normal ``n`` (A -> B) and
the contact length ``L_c`` (``polygon.pair_overlap``):

* normal force: ``F_n = k_n A - c_n v_n`` (eq 4.6 plus viscous contact damping), clamped
  at zero (never adhesive), with ``v_n = v_rel . n`` (``v_rel = v_B - v_A`` at ``c``),
  ``c_n = 2 zeta sqrt(k_eff m_eff)``, ``k_eff = k_n L_c = dF_n/d(penetration)`` and
  ``m_eff = m_A m_B / (m_A + m_B)`` from the elements' lumped nodal masses (sum over their
  nodes); an element with a non-finite mass is rigid and ``m_eff`` is the other's mass;
* tangential force: incremental spring ``dF_t = -k_t L_c v_t dt`` (eq 4.9), history kept
  per pair (``shear``), rotated onto the current tangent each step (projected, magnitude
  kept), capped while the pair presses (``F_n > 0``) at the weaker of the two materials'
  strengths ``c L_c + mu F_n`` (eq 4.10 with a cohesion ``c`` [kPa] over the contact length:
  the Mohr-Coulomb strength of a slip surface ``tau <= c + sigma_n tan phi``, which runs
  through the weaker side).  Slip work ``cap * slip`` is the friction dissipation
  (``slip = (|F_trial| - cap) / (k_t L_c)``);
* ``k_n`` and ``k_t`` are interface stiffnesses in kPa/m (traction per unit displacement):
  a penetration ``d`` over a contact length ``L_c`` gives ``F_n = k_n A ~ k_n d L_c``, and
  the tangential spring stiffness of the pair is ``k_t L_c`` (kN/m per m); between two
  elements with different materials ``k_n``, ``k_t`` and ``zeta`` are the smaller of the
  two;
* the pair force acts at the overlap centroid ``c``; it goes to each element's nodes through
  the element's shape functions at ``c`` (Q4: bilinear, the isoparametric map inverted by
  Newton, clamped to [-1, 1]; T3: barycentric).  The shape functions sum to one and
  reproduce ``c`` (``sum N_i x_i = c``), so each element receives the full force and no
  moment about ``c``: the moment of the contact force about an element's centre comes out
  of the distribution itself.  The two elements get equal and opposite nodal sums.  (If
  ``c`` lies outside a non-convex element the Q4 clamp breaks the moment balance: a known
  limitation.)
"""

from __future__ import annotations

import numpy as np
from numba import njit

import hybrid  # noqa: F401  (sets NUMBA_CACHE_DIR / OMP_WAIT_POLICY before numba compiles)
from hybrid.discrete.contact.polygon import pair_overlap


@njit(cache=True)
def pair_properties(element_material, contact_table, a, b):
    """``(k_n, k_t, zeta, mu_a, c_a, mu_b, c_b)`` of the pair a-b.

    The stiffnesses and the damping ratio are the smaller of the two materials' entries; the
    strengths (friction coefficient, cohesion [kPa]) are each side's, the weaker one at the
    pair's normal force governing (``point_law``).
    """
    ma_ = element_material[a]
    mb_ = element_material[b]
    kn = min(contact_table[ma_, 0], contact_table[mb_, 0])
    kt = min(contact_table[ma_, 1], contact_table[mb_, 1])
    zeta = min(contact_table[ma_, 3], contact_table[mb_, 3])
    return (kn, kt, zeta, contact_table[ma_, 2], contact_table[ma_, 4], contact_table[mb_, 2],
            contact_table[mb_, 4])


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
    x0, x1, x2, x3 = poly[0, 0], poly[1, 0], poly[2, 0], poly[3, 0]
    y0, y1, y2, y3 = poly[0, 1], poly[1, 1], poly[2, 1], poly[3, 1]
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
def _effective_mass(m_a, m_b):
    """``m_A m_B / (m_A + m_B)``; a non-finite (rigid) side leaves the other's mass."""
    if np.isfinite(m_a) and np.isfinite(m_b):
        return m_a * m_b / (m_a + m_b) if m_a + m_b > 0.0 else 0.0
    if np.isfinite(m_a):
        return m_a
    if np.isfinite(m_b):
        return m_b
    return 0.0


@njit(cache=True)
def point_law(area, lc, nx, ny, vx, vy, m_eff, kn, kt, mu_a, c_a, mu_b, c_b, zeta, sx, sy,
              dt):
    """The force law at the contact point.

    Normal force (eq 4.6) with damping, never adhesive, and the tangential spring (eq 4.9)
    capped while ``F_n > 0`` at ``min(c_a L_c + mu_a F_n, c_b L_c + mu_b F_n)`` (eq 4.10 with
    the cohesion [kPa] of each side over the contact length ``L_c``: the weaker side's
    strength), at zero when the pair does not press.

    ``(vx, vy)``: velocity of B relative to A at the contact point; ``(sx, sy)``: the
    tangential history at the start of the step.  Returns ``(f_n, f_el, sx, sy, diss_f,
    diss_d)``: the normal force as applied and its elastic part ``k_n A``, the updated
    history (the tangential force on B) and the friction and damping dissipations of the
    step with the velocity given.
    """
    vn = vx * nx + vy * ny
    f_el = kn * area
    c_n = 2.0 * zeta * np.sqrt(kn * lc * m_eff)
    f_n = f_el - c_n * vn
    if f_n < 0.0:
        f_n = 0.0
    diss_d = -(f_n - f_el) * vn * dt

    # rotate the history onto the current tangent (magnitude kept), increment, cap
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
    cap = 0.0  # eq 4.10 with cohesion: the weaker side's strength
    if f_n > 0.0:
        cap = min(c_a * lc + mu_a * f_n, c_b * lc + mu_b * f_n)
    diss_f = 0.0
    if s_tr > cap:
        if k_t > 0.0:
            diss_f = cap * (s_tr - cap) / k_t  # force x slip
        scale = cap / s_tr
        sx *= scale
        sy *= scale
    return f_n, f_el, sx, sy, diss_f, diss_d


@njit(cache=True)
def pair_contact(a, b, ra, rb, x, v, mass, element_nodes, element_material, contact_table, shear,
                 p, dt, pa, pb, piece_a, piece_b, out, tmp, wa, wb):
    """Contact force on element B from element A (A gets the opposite), pair ``p``.

    The caller has checked that the boxes of A and B overlap; ``ra``/``rb`` are their reflex
    vertices (-1: convex); ``pa``, ``pb`` (4, 2) and ``piece_a`` ... ``tmp`` (MAXV, 3) are
    scratch.  Fills row ``p`` of ``wa``/``wb`` with the shape-function weights at the
    overlap centroid, updates the pair's tangential history ``shear[p]`` in place (zero when
    the elements do not overlap) and returns ``(active, fx, fy, diss_friction, diss_damping,
    f_damp, nx, ny)`` (``f_damp``: the damping part of the normal force as applied, after
    the clamp, along ``(nx, ny)``; the tangential part of the force is
    ``(fx, fy) - f_n (nx, ny)``).
    """
    area, cx, cy, nx, ny, lc = pair_overlap(a, b, ra, rb, x, element_nodes, pa, pb, piece_a,
                                            piece_b, out, tmp)
    if area <= 0.0:
        shear[p, 0] = 0.0
        shear[p, 1] = 0.0
        return 0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    kn, kt, zeta, mu_a, c_a, mu_b, c_b = pair_properties(element_material, contact_table, a, b)

    # shape functions at the contact point, relative velocity of B w.r.t. A, masses
    nen = element_nodes.shape[1]
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
    m_eff = _effective_mass(m_a, m_b)

    f_n, f_el, sx, sy, diss_f, diss_d = point_law(area, lc, nx, ny, vx, vy, m_eff, kn, kt, mu_a,
                                                  c_a, mu_b, c_b, zeta, shear[p, 0],
                                                  shear[p, 1], dt)
    shear[p, 0] = sx
    shear[p, 1] = sy
    return 1, f_n * nx + sx, f_n * ny + sy, diss_f, diss_d, f_n - f_el, nx, ny
