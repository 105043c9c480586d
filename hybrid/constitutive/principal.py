"""Closed-form Mohr-Coulomb return in sorted principal stresses (perfect plasticity).

The return mapping of ``hybrid.constitutive.mohr_coulomb`` (its module docstring states the
yield surface, the tension cut-off, the regions and the references): ``return_principal``
returns sorted trial principal stresses to the main plane, an edge, the tension plane, a
tension/shear line or a vertex for fixed strength parameters; ``principal_tangent`` is its
derivative; ``equivalent_plastic_strain`` measures the plastic strain of a return. The
strain-softening return (``hybrid.constitutive.softening``) calls the same return with the
strength in force.
"""

from __future__ import annotations

import math

import numba
import numpy as np

__all__ = [
    "REGION_NAMES",
    "equivalent_plastic_strain",
    "principal_plastic_strain",
    "principal_tangent",
    "return_principal",
    "yield_function",
]

# Region codes returned by ``return_principal`` (sorted principal stresses s1 >= s2 >= s3).
REGION_ELASTIC = 0
REGION_MAIN = 1  # main Mohr-Coulomb plane
REGION_TENSION = 2  # Rankine plane s1 = t
REGION_EDGE_12 = 3  # Mohr-Coulomb edge s1 = s2 (triaxial compression meridian)
REGION_EDGE_23 = 4  # Mohr-Coulomb edge s2 = s3 (triaxial extension meridian)
REGION_TENSION_EDGE = 5  # Rankine edge s1 = s2 = t
REGION_SHEAR_TENSION = 6  # line where the main plane meets s1 = t
REGION_VERTEX_12 = 7  # vertex (t, t, s3*)
REGION_VERTEX_23 = 8  # vertex (t, s3*, s3*)
REGION_APEX = 9  # (t, t, t); the Mohr-Coulomb apex when t = c cot(phi)
REGION_VERTEX_FALLBACK = 10  # no Kuhn-Tucker test passed (not met in tests): nearest vertex

REGION_NAMES = (
    "elastic",
    "main plane",
    "tension plane",
    "edge s1=s2",
    "edge s2=s3",
    "tension edge",
    "shear-tension line",
    "vertex (t,t,s3*)",
    "vertex (t,s3*,s3*)",
    "apex",
    "vertex fallback",
)

# relative tolerance of the Kuhn-Tucker checks (times the stress scale of the trial state)
_TOL = 1.0e-12

# active planes of each region (-1: none): 0 = main plane (s1, s3), 1 = plane (s2, s3),
# 2 = plane (s1, s2), 3/4/5 = Rankine planes s1/s2/s3 = t
_REGION_PLANES = ((-1, -1), (0, -1), (3, -1), (0, 1), (0, 2), (3, 4), (0, 3))


@numba.njit(cache=True)
def _plane(k, sin_phi, cos_phi, sin_psi, cohesion, t):
    """Plane ``k``: gradient n, flow m (both in sorted principal space) and right side r."""
    two_c_cos = 2.0 * cohesion * cos_phi
    if k == 0:
        return (1.0 + sin_phi, 0.0, sin_phi - 1.0, 1.0 + sin_psi, 0.0, sin_psi - 1.0, two_c_cos)
    if k == 1:
        return (0.0, 1.0 + sin_phi, sin_phi - 1.0, 0.0, 1.0 + sin_psi, sin_psi - 1.0, two_c_cos)
    if k == 2:
        return (1.0 + sin_phi, sin_phi - 1.0, 0.0, 1.0 + sin_psi, sin_psi - 1.0, 0.0, two_c_cos)
    if k == 3:
        return (1.0, 0.0, 0.0, 1.0, 0.0, 0.0, t)
    if k == 4:
        return (0.0, 1.0, 0.0, 0.0, 1.0, 0.0, t)
    return (0.0, 0.0, 1.0, 0.0, 0.0, 1.0, t)


@numba.njit(cache=True)
def _dmul(v0, v1, v2, lam, G):
    """Isotropic elasticity in principal space: D v = lam tr(v) 1 + 2 G v."""
    tr = lam * (v0 + v1 + v2)
    return tr + 2.0 * G * v0, tr + 2.0 * G * v1, tr + 2.0 * G * v2


@numba.njit(cache=True)
def _admissible(x0, x1, x2, sin_phi, cos_phi, cohesion, t, tol):
    """Sorted (within tol) and inside main Mohr-Coulomb plane and tension cut-off."""
    if x0 < x1 - tol or x1 < x2 - tol:
        return False
    f = (x0 - x2) + (x0 + x2) * sin_phi - 2.0 * cohesion * cos_phi
    return f <= 2.0 * tol and x0 - t <= tol


@numba.njit(cache=True)
def _return_one(k, s0, s1, s2, lam, G, sin_phi, cos_phi, sin_psi, cohesion, t):
    """Return to one plane: sigma = sigma_tr - dgamma D m, dgamma = f_tr / (n . D m)."""
    n0, n1, n2, m0, m1, m2, r = _plane(k, sin_phi, cos_phi, sin_psi, cohesion, t)
    d0, d1, d2 = _dmul(m0, m1, m2, lam, G)
    dg = (n0 * s0 + n1 * s1 + n2 * s2 - r) / (n0 * d0 + n1 * d1 + n2 * d2)
    return s0 - dg * d0, s1 - dg * d1, s2 - dg * d2, dg


@numba.njit(cache=True)
def _return_two(k, l, s0, s1, s2, lam, G, sin_phi, cos_phi, sin_psi, cohesion, t):
    """Return to the line of planes k and l (2x2 solve for the two multipliers)."""
    a0, a1, a2, p0, p1, p2, ra = _plane(k, sin_phi, cos_phi, sin_psi, cohesion, t)
    b0, b1, b2, q0, q1, q2, rb = _plane(l, sin_phi, cos_phi, sin_psi, cohesion, t)
    dp0, dp1, dp2 = _dmul(p0, p1, p2, lam, G)
    dq0, dq1, dq2 = _dmul(q0, q1, q2, lam, G)
    g11 = a0 * dp0 + a1 * dp1 + a2 * dp2
    g12 = a0 * dq0 + a1 * dq1 + a2 * dq2
    g21 = b0 * dp0 + b1 * dp1 + b2 * dp2
    g22 = b0 * dq0 + b1 * dq1 + b2 * dq2
    fa = a0 * s0 + a1 * s1 + a2 * s2 - ra
    fb = b0 * s0 + b1 * s1 + b2 * s2 - rb
    det = g11 * g22 - g12 * g21
    dga = (g22 * fa - g12 * fb) / det
    dgb = (g11 * fb - g21 * fa) / det
    return (
        s0 - dga * dp0 - dgb * dq0,
        s1 - dga * dp1 - dgb * dq1,
        s2 - dga * dp2 - dgb * dq2,
        dga,
        dgb,
    )


@numba.njit(cache=True)
def _in_cone(planes, v0, v1, v2, s0, s1, s2, lam, G, sin_phi, cos_phi, sin_psi, cohesion, t, tolg):
    """True if sigma_tr - v = sum_k dgamma_k D m_k with dgamma >= 0 over three planes."""
    i, j, k = planes
    _, _, _, a0, a1, a2, _ = _plane(i, sin_phi, cos_phi, sin_psi, cohesion, t)
    _, _, _, b0, b1, b2, _ = _plane(j, sin_phi, cos_phi, sin_psi, cohesion, t)
    _, _, _, c0, c1, c2, _ = _plane(k, sin_phi, cos_phi, sin_psi, cohesion, t)
    a0, a1, a2 = _dmul(a0, a1, a2, lam, G)
    b0, b1, b2 = _dmul(b0, b1, b2, lam, G)
    c0, c1, c2 = _dmul(c0, c1, c2, lam, G)
    r0, r1, r2 = s0 - v0, s1 - v1, s2 - v2
    det = a0 * (b1 * c2 - b2 * c1) - b0 * (a1 * c2 - a2 * c1) + c0 * (a1 * b2 - a2 * b1)
    scale = (abs(a0) + abs(a1) + abs(a2)) * (abs(b0) + abs(b1) + abs(b2))
    scale *= abs(c0) + abs(c1) + abs(c2)
    if abs(det) <= 1.0e-12 * scale:
        return False
    x = (r0 * (b1 * c2 - b2 * c1) - b0 * (r1 * c2 - r2 * c1) + c0 * (r1 * b2 - r2 * b1)) / det
    y = (a0 * (r1 * c2 - r2 * c1) - r0 * (a1 * c2 - a2 * c1) + c0 * (a1 * r2 - a2 * r1)) / det
    z = (a0 * (b1 * r2 - b2 * r1) - b0 * (a1 * r2 - a2 * r1) + r0 * (a1 * b2 - a2 * b1)) / det
    return x >= -tolg and y >= -tolg and z >= -tolg


@numba.njit(cache=True)
def return_principal(s1, s2, s3, K, G, cohesion, sin_phi, cos_phi, sin_psi, tensile_strength):
    """Closed-form return of sorted trial principal stresses ``s1 >= s2 >= s3`` (kPa).

    Returns ``(r1, r2, r3, region)``: the returned principal stresses (still sorted) and the
    region code (``REGION_NAMES[region]``). The tension cut-off is
    ``t = min(tensile_strength, c cot(phi))``; when it equals ``c cot(phi)`` the Rankine
    planes only meet the cone at its apex and the return is the classical Mohr-Coulomb one
    (main plane, two edges, apex; de Souza Neto et al. 2008, box 8.5).
    """
    lam = K - 2.0 * G / 3.0
    t = tensile_strength
    degenerate = False
    if sin_phi > 0.0:
        apex = cohesion * cos_phi / sin_phi
        if t >= apex * (1.0 - 1.0e-10):
            t = apex
            degenerate = True
    scale = max(abs(s1), abs(s2), abs(s3)) + cohesion
    tol = _TOL * scale
    tolg = tol / G
    f_main = (s1 - s3) + (s1 + s3) * sin_phi - 2.0 * cohesion * cos_phi
    f_tension = s1 - t
    if f_main <= 2.0 * tol and f_tension <= tol:
        return s1, s2, s3, REGION_ELASTIC
    if f_main > 0.0:
        x0, x1, x2, dg = _return_one(0, s1, s2, s3, lam, G, sin_phi, cos_phi, sin_psi, cohesion, t)
        if dg >= -tolg and _admissible(x0, x1, x2, sin_phi, cos_phi, cohesion, t, tol):
            return x0, x1, x2, REGION_MAIN
    if not degenerate and f_tension > 0.0:
        x0, x1, x2, dg = _return_one(3, s1, s2, s3, lam, G, sin_phi, cos_phi, sin_psi, cohesion, t)
        if dg >= -tolg and _admissible(x0, x1, x2, sin_phi, cos_phi, cohesion, t, tol):
            return x0, x1, x2, REGION_TENSION
    nlines = 2 if degenerate else 4
    for region in range(REGION_EDGE_12, REGION_EDGE_12 + nlines):
        k, l = _REGION_PLANES[region]
        x0, x1, x2, da, db = _return_two(
            k, l, s1, s2, s3, lam, G, sin_phi, cos_phi, sin_psi, cohesion, t
        )
        if da >= -tolg and db >= -tolg:
            if _admissible(x0, x1, x2, sin_phi, cos_phi, cohesion, t, tol):
                return x0, x1, x2, region
    if degenerate:
        return t, t, t, REGION_APEX
    # vertices of the cut-off cone: s3* closes the main plane at s1 = t
    s3s = ((1.0 + sin_phi) * t - 2.0 * cohesion * cos_phi) / (1.0 - sin_phi)
    args = (lam, G, sin_phi, cos_phi, sin_psi, cohesion, t, tolg)
    # (t, t, s3*): planes 0, 1, 3, 4 active; Caratheodory: one of the 3-subsets holds
    for planes in ((0, 1, 3), (0, 1, 4), (0, 3, 4), (1, 3, 4)):
        if _in_cone(planes, t, t, s3s, s1, s2, s3, *args):
            return t, t, s3s, REGION_VERTEX_12
    if _in_cone((0, 2, 3), t, s3s, s3s, s1, s2, s3, *args):
        return t, s3s, s3s, REGION_VERTEX_23
    if _in_cone((3, 4, 5), t, t, t, s1, s2, s3, *args):
        return t, t, t, REGION_APEX
    # not met in the tests: the nearest vertex in the complementary-energy norm
    best = 0
    best_e = np.inf
    for v in range(3):
        v1 = t
        v2 = t if v != 1 else s3s
        v3 = t if v == 2 else s3s
        d0, d1, d2 = s1 - v1, s2 - v2, s3 - v3
        mean = (d0 + d1 + d2) / 3.0
        e = mean * mean * 3.0 / K + ((d0 - mean) ** 2 + (d1 - mean) ** 2 + (d2 - mean) ** 2) / G
        if e < best_e:
            best_e = e
            best = v
    return t, (t if best != 1 else s3s), (t if best == 2 else s3s), REGION_VERTEX_FALLBACK


@numba.njit(cache=True)
def principal_tangent(region, lam, G, sin_phi, cos_phi, sin_psi, cohesion, t):
    """d(returned principal stress)/d(trial principal strain), 3x3 row-major, sorted order.

    Affine return sigma = P sigma_tr + const, so the derivative is P D (D elastic in
    principal space): D - sum_kl D m_k (g^-1)_kl (D n_l)^T, g_kl = n_k . D m_l, written as
    D - u1 v1^T - u2 v2^T. Zero at a vertex.
    """
    if region >= REGION_VERTEX_12:
        return (0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
    u1 = (0.0, 0.0, 0.0)
    v1 = (0.0, 0.0, 0.0)
    u2 = (0.0, 0.0, 0.0)
    v2 = (0.0, 0.0, 0.0)
    if region != REGION_ELASTIC:
        k, l = _REGION_PLANES[region]
        a0, a1, a2, p0, p1, p2, _ = _plane(k, sin_phi, cos_phi, sin_psi, cohesion, t)
        u1 = _dmul(p0, p1, p2, lam, G)
        v1 = _dmul(a0, a1, a2, lam, G)
        g11 = a0 * u1[0] + a1 * u1[1] + a2 * u1[2]
        if l < 0:
            v1 = (v1[0] / g11, v1[1] / g11, v1[2] / g11)
        else:
            b0, b1, b2, q0, q1, q2, _ = _plane(l, sin_phi, cos_phi, sin_psi, cohesion, t)
            u2 = _dmul(q0, q1, q2, lam, G)
            db = _dmul(b0, b1, b2, lam, G)
            g12 = a0 * u2[0] + a1 * u2[1] + a2 * u2[2]
            g21 = b0 * u1[0] + b1 * u1[1] + b2 * u1[2]
            g22 = b0 * u2[0] + b1 * u2[1] + b2 * u2[2]
            det = g11 * g22 - g12 * g21
            # g^-1 = [[g22, -g12], [-g21, g11]] / det
            v2 = (
                (g11 * db[0] - g21 * v1[0]) / det,
                (g11 * db[1] - g21 * v1[1]) / det,
                (g11 * db[2] - g21 * v1[2]) / det,
            )
            v1 = (
                (g22 * v1[0] - g12 * db[0]) / det,
                (g22 * v1[1] - g12 * db[1]) / det,
                (g22 * v1[2] - g12 * db[2]) / det,
            )
    d = lam + 2.0 * G
    return (
        d - u1[0] * v1[0] - u2[0] * v2[0],
        lam - u1[0] * v1[1] - u2[0] * v2[1],
        lam - u1[0] * v1[2] - u2[0] * v2[2],
        lam - u1[1] * v1[0] - u2[1] * v2[0],
        d - u1[1] * v1[1] - u2[1] * v2[1],
        lam - u1[1] * v1[2] - u2[1] * v2[2],
        lam - u1[2] * v1[0] - u2[2] * v2[0],
        lam - u1[2] * v1[1] - u2[2] * v2[1],
        d - u1[2] * v1[2] - u2[2] * v2[2],
    )


@numba.njit(cache=True)
def yield_function(sxx, syy, szz, sxy, cohesion, sin_phi, cos_phi):
    """Mohr-Coulomb yield function (kPa), ``F <= 0`` admissible (tension positive).

    ``F = (s1 - s3) + (s1 + s3) sin(phi) - 2 c cos(phi)`` with ``s1 >= s2 >= s3`` the
    principal stresses of ``(sxx, syy, szz, sxy)`` (twice the textbook form; the thesis's
    invariant form written in principal stresses). The tension cut-off is not included.
    """
    p = 0.5 * (sxx + syy)
    r = math.sqrt((0.5 * (sxx - syy)) ** 2 + sxy * sxy)
    s1 = max(p + r, szz)
    s3 = min(p - r, szz)
    return (s1 - s3) + (s1 + s3) * sin_phi - 2.0 * cohesion * cos_phi


@numba.njit(cache=True, inline="always")
def principal_plastic_strain(d0, d1, d2, K, G):
    """Principal plastic strains e_p = C (sigma_trial - sigma) of a return (tensor components).

    ``d0, d1, d2`` are the principal components of sigma_trial - sigma [kPa]; C is the
    elastic compliance of K and G, volumetric part included.
    """
    mean = (d0 + d1 + d2) / 3.0
    ev = mean / (3.0 * K)
    return ev + (d0 - mean) / (2.0 * G), ev + (d1 - mean) / (2.0 * G), ev + (d2 - mean) / (2.0 * G)


@numba.njit(cache=True, inline="always")
def equivalent_plastic_strain(d0, d1, d2, K, G):
    """Equivalent plastic strain sqrt(2/3 e_p : e_p) of a return in principal axes.

    ``d0, d1, d2`` are the principal components of sigma_trial - sigma [kPa]
    (``principal_plastic_strain`` gives e_p).
    """
    e0, e1, e2 = principal_plastic_strain(d0, d1, d2, K, G)
    return math.sqrt(2.0 / 3.0 * (e0 * e0 + e1 * e1 + e2 * e2))
