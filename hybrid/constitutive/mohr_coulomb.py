"""Mohr-Coulomb elastic-perfectly plastic stress update (plane strain), shared by both phases.

Conventions (the whole package uses them):

* units: stress and moduli in kPa, strains dimensionless;
* sign: **tension positive, compression negative**;
* Voigt order ``(xx, yy, zz, xy)`` for stress, the same order for strain with the
  **engineering** shear ``gamma_xy = 2 eps_xy``; the out-of-plane shears are zero (plane
  strain), ``sigma_zz`` is carried as the third principal stress;
* principal stresses sorted ``s1 >= s2 >= s3`` (``s1`` the most tensile).

Yield criterion (the thesis's invariant form, chapter 5 / design.md section 1, written in
principal stresses as in de Souza Neto, Peric & Owen 2008, chapter 6, tension positive)::

    F = (s1 - s3) + (s1 + s3) sin(phi) - 2 c cos(phi)        F <= 0 admissible   (kPa)

i.e. twice the usual ``(s1 - s3)/2 + (s1 + s3)/2 sin(phi) - c cos(phi)``. The plastic
potential ``G`` is ``F`` with the dilation angle ``psi`` in place of ``phi`` (non-associated
flow). A Rankine tension cut-off limits every principal stress to ``t = min(tensile_strength,
c cot(phi))`` with associated flow. Elasticity is isotropic (bulk modulus ``K``, shear modulus
``G``).

Return mapping: the exact closed-form return in principal stresses for perfect plasticity with
linear yield planes (de Souza Neto et al. 2008, boxes 8.4-8.5; Clausen, Damkilde & Andersen
2006, 2007): the trial stress is returned to the main plane, to one of the two edges
(``s1 = s2`` or ``s2 = s3``), to the tension plane, to a tension/shear line, or to a vertex.
Each candidate is a linear solve of at most 2x2 (vertices: a 3x3 cone test); the first one
satisfying the Kuhn-Tucker conditions (multipliers >= 0, returned stress admissible and still
sorted) is taken. Beyond the apex (``t = c cot(phi)``) the stress returns to the apex whatever
``psi``: the cut-off planes meeting there carry the volumetric plastic strain. The in-plane
principal directions come from ``sxx, syy, sxy`` of the trial stress; ``szz`` is the third
principal stress; the returned principal stresses are rotated back with the trial
eigenvectors (isotropy: trial and returned stress are coaxial).

Consistent tangent: closed form, ``d sigma / d(strain increment)`` (4x4, Voigt as above,
columns per engineering strain): principal part ``P D`` of the affine return of the active
region plus the spin term ``2 G (s_a - s_b) / (s_a^tr - s_b^tr)`` of the in-plane eigenvectors
(de Souza Neto et al. 2008, appendix A, derivatives of isotropic tensor functions). At a
vertex the principal part is zero: ``VERTEX_STABILISATION = 1e-5`` times the elastic matrix is
added there so that direct solvers do not meet a singular matrix.

Equivalent plastic strain: the increment returned is
``d_eps_p_eq = sqrt(2/3 d_eps_p : d_eps_p)`` with the tensor (not engineering) components of
the plastic strain increment ``d_eps_p = C : (sigma_trial - sigma)`` (C the elastic
compliance), volumetric part included. The accumulated value is the sum of the increments.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numba
import numpy as np

from hybrid.constitutive.table import kernel_row

if TYPE_CHECKING:
    from hybrid.materials import Material

__all__ = [
    "mohr_coulomb_point",
    "equivalent_plastic_strain",
    "mohr_coulomb_update",
    "return_principal",
    "update_stress",
    "yield_function",
    "VERTEX_STABILISATION",
    "REGION_NAMES",
]

#: Fraction of the elastic matrix added to the tangent at a vertex (apex) return.
VERTEX_STABILISATION = 1.0e-5

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
def _principal_tangent(region, lam, G, sin_phi, cos_phi, sin_psi, cohesion, t):
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
def equivalent_plastic_strain(d0, d1, d2, K, G):
    """Equivalent plastic strain sqrt(2/3 e_p : e_p) of a return in principal axes.

    ``d0, d1, d2`` are the principal components of sigma_trial - sigma [kPa]; the plastic
    strain is e_p = C (sigma_trial - sigma) with the elastic compliance C of K and G (tensor
    components, volumetric part included).
    """
    mean = (d0 + d1 + d2) / 3.0
    ev = mean / (3.0 * K)
    e0 = ev + (d0 - mean) / (2.0 * G)
    e1 = ev + (d1 - mean) / (2.0 * G)
    e2 = ev + (d2 - mean) / (2.0 * G)
    return math.sqrt(2.0 / 3.0 * (e0 * e0 + e1 * e1 + e2 * e2))


@numba.njit(cache=True)
def mohr_coulomb_point(
    sxx,
    syy,
    szz,
    sxy,
    dexx,
    deyy,
    dezz,
    dgxy,
    K,
    G,
    cohesion,
    sin_phi,
    cos_phi,
    sin_psi,
    tensile_strength,
    out_stress,
    out_tangent,
    want_tangent,
):
    """Stress update of one point: elastic predictor + closed-form principal return.

    Old stress ``(sxx, syy, szz, sxy)`` (kPa), strain increment ``(dexx, deyy, dezz, dgxy)``
    (engineering shear). Writes the new stress into ``out_stress[0:4]`` and, if
    ``want_tangent``, the consistent tangent ``d sigma_i / d(delta eps)_j`` into
    ``out_tangent[0:4, 0:4]`` (kPa). Returns ``(d_eps_p_eq, yielded)``: the increment of
    ``sqrt(2/3 eps_p : eps_p)`` and 1 if a plastic correction was applied, else 0.
    No allocation: safe inside hot loops.
    """
    lam = K - 2.0 * G / 3.0
    tr = lam * (dexx + deyy + dezz)
    txx = sxx + tr + 2.0 * G * dexx
    tyy = syy + tr + 2.0 * G * deyy
    tzz = szz + tr + 2.0 * G * dezz
    txy = sxy + G * dgxy
    # in-plane principal pair (a >= b) and direction of a
    p = 0.5 * (txx + tyy)
    h = 0.5 * (txx - tyy)
    rad = math.sqrt(h * h + txy * txy)
    sa = p + rad
    sb = p - rad
    theta = 0.5 * math.atan2(txy, h)
    c = math.cos(theta)
    s = math.sin(theta)
    # sorted positions of a, b, z
    if tzz >= sa:
        ia, ib, iz = 1, 2, 0
        s1, s2, s3 = tzz, sa, sb
    elif tzz >= sb:
        ia, ib, iz = 0, 2, 1
        s1, s2, s3 = sa, tzz, sb
    else:
        ia, ib, iz = 0, 1, 2
        s1, s2, s3 = sa, sb, tzz
    r1, r2, r3, region = return_principal(
        s1, s2, s3, K, G, cohesion, sin_phi, cos_phi, sin_psi, tensile_strength
    )
    if region == REGION_ELASTIC:
        out_stress[0] = txx
        out_stress[1] = tyy
        out_stress[2] = tzz
        out_stress[3] = txy
        if want_tangent:
            for i in range(4):
                for j in range(4):
                    out_tangent[i, j] = 0.0
            for i in range(3):
                for j in range(3):
                    out_tangent[i, j] = lam
                out_tangent[i, i] += 2.0 * G
            out_tangent[3, 3] = G
        return 0.0, 0
    ret = (r1, r2, r3)
    ra = ret[ia]
    rb = ret[ib]
    out_stress[0] = ra * c * c + rb * s * s
    out_stress[1] = ra * s * s + rb * c * c
    out_stress[2] = ret[iz]
    out_stress[3] = (ra - rb) * c * s
    # plastic strain increment (principal, tensor components) = C (sigma_tr - sigma)
    deq = equivalent_plastic_strain(s1 - r1, s2 - r2, s3 - r3, K, G)
    if want_tangent:
        t = tensile_strength
        if sin_phi > 0.0:
            t = min(t, cohesion * cos_phi / sin_phi)
        cc = c * c
        ss = s * s
        cs = c * s
        # eigenprojections (stress columns = strain rows with engineering shear)
        mv = ((cc, ss, 0.0, cs), (ss, cc, 0.0, -cs), (0.0, 0.0, 1.0, 0.0))
        A = _principal_tangent(region, lam, G, sin_phi, cos_phi, sin_psi, cohesion, t)
        # principal tangent re-ordered to (a, b, z)
        pt = (
            A[3 * ia + ia],
            A[3 * ia + ib],
            A[3 * ia + iz],
            A[3 * ib + ia],
            A[3 * ib + ib],
            A[3 * ib + iz],
            A[3 * iz + ia],
            A[3 * iz + ib],
            A[3 * iz + iz],
        )
        # sum_XY pt_XY M_X (x) M_Y, contracted as M_X (x) (sum_Y pt_XY M_Y)
        for i in range(4):
            for j in range(4):
                out_tangent[i, j] = 0.0
        for X in range(3):
            for j in range(4):
                row_j = pt[3 * X] * mv[0][j] + pt[3 * X + 1] * mv[1][j] + pt[3 * X + 2] * mv[2][j]
                if row_j != 0.0:
                    for i in range(4):
                        out_tangent[i, j] += mv[X][i] * row_j
        # spin of the in-plane eigenvectors: 2 G (r_a - r_b) / (s_a - s_b) (2 w)(w)^T,
        # limit (A_aa - A_ab - A_ba + A_bb) / 2 for repeated in-plane trial eigenvalues
        if sa - sb > 1.0e-10 * (abs(sa) + abs(sb) + cohesion):
            coef = 2.0 * G * (ra - rb) / (sa - sb)
        else:
            coef = 0.5 * (pt[0] - pt[1] - pt[3] + pt[4])
        w = (-cs, cs, 0.0, 0.5 * (cc - ss))
        for i in range(4):
            for j in range(4):
                out_tangent[i, j] += 2.0 * coef * w[i] * w[j]
        if region >= REGION_VERTEX_12:
            eps = VERTEX_STABILISATION
            for i in range(3):
                for j in range(3):
                    out_tangent[i, j] += eps * lam
                out_tangent[i, i] += eps * 2.0 * G
            out_tangent[3, 3] += eps * G
    return deq, 1


@numba.njit(cache=True, parallel=True)
def mohr_coulomb_update(
    stress_old,
    strain_increment,
    material_of_point,
    material_table,
    stress_new,
    tangent,
    plastic_strain,
    yielded,
    want_tangent,
):
    """Vectorised ``mohr_coulomb_point`` over ``n`` points (prange, points independent).

    ``stress_old, strain_increment, stress_new``: (n, 4); ``material_of_point``: (n,) int;
    ``material_table``: (nmat, 7) rows ``[K, G, c, sin_phi, cos_phi, sin_psi, t]``;
    ``tangent``: (n, 4, 4) (with ``want_tangent`` False any (>=1, 4, 4) array, untouched);
    ``plastic_strain``: (n,) accumulated equivalent plastic strain, incremented in place;
    ``yielded``: (n,) int8, set to 1 where a plastic correction was applied, else 0.
    """
    n = stress_old.shape[0]
    for q in numba.prange(n):
        m = material_of_point[q]
        row = material_table[m]
        tq = tangent[q] if want_tangent else tangent[0]
        deq, flag = mohr_coulomb_point(
            stress_old[q, 0],
            stress_old[q, 1],
            stress_old[q, 2],
            stress_old[q, 3],
            strain_increment[q, 0],
            strain_increment[q, 1],
            strain_increment[q, 2],
            strain_increment[q, 3],
            row[0],
            row[1],
            row[2],
            row[3],
            row[4],
            row[5],
            row[6],
            stress_new[q],
            tq,
            want_tangent,
        )
        plastic_strain[q] += deq
        yielded[q] = flag


def _check_table(table: np.ndarray) -> None:
    if table.ndim != 2 or table.shape[1] != 7 or table.shape[0] < 1:
        raise ValueError(
            f"material_table has shape {table.shape}; need (nmat, 7) rows "
            "[K, G, c, sin_phi, cos_phi, sin_psi, t] (hybrid.constitutive.table.kernel_table)"
        )
    if not np.all(np.isfinite(table)):
        raise ValueError("material_table holds NaN or inf; use finite values (kernel_table)")
    K, G, c, sphi, cphi, spsi, t = table.T
    if np.any(K <= 0) or np.any(G <= 0):
        raise ValueError("material_table: K and G (columns 0, 1) must be > 0 kPa")
    if np.any(c < 0) or np.any(t < 0):
        raise ValueError("material_table: c and t (columns 2, 6) must be >= 0 kPa")
    if np.any(sphi < 0) or np.any(sphi >= 1) or np.any(np.abs(sphi**2 + cphi**2 - 1) > 1e-12):
        raise ValueError("material_table: need 0 <= sin_phi < 1 and cos_phi = sqrt(1 - sin_phi^2)")
    if np.any(spsi < 0) or np.any(spsi > sphi):
        raise ValueError("material_table: need 0 <= sin_psi <= sin_phi (column 5)")
    if np.any((c == 0) & (sphi == 0)):
        raise ValueError("material_table: a row has c = 0 and phi = 0 (no strength)")


def update_stress(
    stress_old: np.ndarray,
    strain_increment: np.ndarray,
    material: Material | None = None,
    *,
    material_of_point: np.ndarray | None = None,
    material_table: np.ndarray | None = None,
    want_tangent: bool = True,
) -> tuple[np.ndarray, np.ndarray | None, np.ndarray, np.ndarray]:
    """Mohr-Coulomb stress update of ``n`` points (checked wrapper of ``mohr_coulomb_update``).

    ``stress_old``, ``strain_increment``: (n, 4) or (4,), Voigt (xx, yy, zz, xy), kPa and
    engineering shear. Give either ``material`` (one ``Material``; its row from ``kernel_row``)
    or ``material_of_point`` (n,) with ``material_table`` (nmat, 7). Returns ``(stress_new
    (n, 4), tangent (n, 4, 4) or None, d_eps_p_eq (n,), yielded (n,) int8)`` (one point: shapes
    (4,), (4, 4), scalars).
    """
    s0 = np.ascontiguousarray(stress_old, dtype=np.float64)
    de = np.ascontiguousarray(strain_increment, dtype=np.float64)
    single = s0.ndim == 1
    s0 = np.atleast_2d(s0)
    de = np.atleast_2d(de)
    if s0.ndim != 2 or s0.shape[1] != 4:
        raise ValueError(f"stress_old has shape {np.shape(stress_old)}; need (n, 4) or (4,)")
    if de.shape != s0.shape:
        raise ValueError(
            f"strain_increment has shape {np.shape(strain_increment)}; "
            f"need the shape of stress_old {s0.shape}"
        )
    if not (np.all(np.isfinite(s0)) and np.all(np.isfinite(de))):
        raise ValueError("stress_old or strain_increment holds NaN/inf; pass finite values")
    n = s0.shape[0]
    if material is not None:
        if material_of_point is not None or material_table is not None:
            raise ValueError("give either material or material_of_point + material_table, "
                             "not both")
        table = np.array(kernel_row(material)).reshape(1, 7)
        mat = np.zeros(n, dtype=np.int64)
    else:
        if material_of_point is None or material_table is None:
            raise ValueError("give material, or both material_of_point and material_table")
        table = np.ascontiguousarray(material_table, dtype=np.float64)
        mat = np.asarray(material_of_point)
        if not np.issubdtype(mat.dtype, np.integer):
            raise ValueError(f"material_of_point has dtype {mat.dtype}; need integers")
        mat = np.ascontiguousarray(mat, dtype=np.int64).reshape(-1)
        if mat.shape[0] != n:
            raise ValueError(f"material_of_point has {mat.shape[0]} entries; need n = {n}")
    _check_table(table)
    if n and (mat.min() < 0 or mat.max() >= table.shape[0]):
        raise ValueError(f"material_of_point must lie in [0, {table.shape[0] - 1}]")
    stress_new = np.empty_like(s0)
    tangent = np.empty((n if want_tangent else 1, 4, 4))
    dpeq = np.zeros(n)
    yielded = np.zeros(n, dtype=np.int8)
    mohr_coulomb_update(s0, de, mat, table, stress_new, tangent, dpeq, yielded, bool(want_tangent))
    tan = tangent if want_tangent else None
    if single:
        return stress_new[0], (tan[0] if tan is not None else None), dpeq[0], yielded[0]
    return stress_new, tan, dpeq, yielded
