"""Strain softening of the Mohr-Coulomb strength, regularised by element size (crack band).

Law (one for both phases). The strength parameters fall linearly from peak to residual with
the plastic slip across a shear band one element wide::

    xi  = min(u_p / u_r, 1)            u_p = sqrt(3) kappa h                      (-, m)
    c   = c_p + (c_r - c_p) xi         phi = phi_p + (phi_r - phi_p) xi    (kPa, deg)
    psi = psi_p + (psi_r - psi_p) xi   t   = min(t_p + (t_r - t_p) xi, c cot phi)

The tension cut-off is interpolated only between values given at either end (a residual left
None keeps the peak's given cut-off, so it never rises; ``table.residual_tension``); given at
neither end it is the apex ``c cot phi`` of the strength in force.

``kappa`` is the kernel's accumulated equivalent plastic strain ``sqrt(2/3 e_p : e_p)``; in
isochoric simple shear with plastic shear strain ``gamma_p`` it is ``gamma_p / sqrt(3)``, so
``sqrt(3) kappa h = gamma_p h`` is the plastic slip across a band of width ``h``. ``u_r`` is the
material's ``softening_displacement`` [m]: the slip over which the strength falls to residual.
``h`` is the characteristic length of the point's element (:func:`characteristic_length`:
``sqrt(A)`` of a quadrilateral, ``sqrt(2 A)`` of a triangle, the band being one element wide;
Bazant & Oh 1983, Oliver 1989, Rots 1988). The energy dissipated per unit area of band beyond
the residual strength is then a material constant whatever the element size: for a drop of
cohesion at constant normal stress it is ``(c_p - c_r) u_r / 2`` [kJ/m2].

Return: implicit in the strength. With the strength in force at ``kappa_{n+1}``, the
closed-form return of ``return_principal`` gives the increment ``q(kappa_{n+1})``; the scalar
equation ``kappa_{n+1} = kappa_n + q(kappa_{n+1})`` is solved by bracketed false position
(Illinois). Its root lies in ``[kappa_n, kappa_r]`` (``kappa_r`` where the residual is reached);
beyond ``kappa_r`` the strength is the residual one and the return is perfectly plastic. Where
an element is larger than ``u_r G / (tau_p - tau_r)`` the softening is steeper than the elastic
unloading and the point snaps back (the response jumps towards residual and the dissipated
energy exceeds the regularised one): keep elements below that size.

Consistent tangent: with ``sigma = R(eps, kappa)`` the return at fixed strength and
``kappa = kappa_n + Q(eps, kappa)``,
``d sigma / d eps = R_eps + R_kappa (x) Q_eps / (1 - Q_kappa)``.
``R_eps`` is the perfect-plasticity tangent at the strength in force (``mohr_coulomb_point``),
``Q_eps = (dQ / d e_p) (I - C R_eps)`` in closed form, and ``R_kappa``, ``Q_kappa`` (derivatives
along the one softening variable) by a central difference of the closed-form return.
"""

from __future__ import annotations

import math
import warnings

import numba
import numpy as np

from hybrid.constitutive.principal import (
    REGION_ELASTIC,
    equivalent_plastic_strain,
    principal_plastic_strain,
    return_principal,
)
from hybrid.constitutive.table import (
    COHESION,
    COS_PHI,
    NO_TENSION_CUTOFF,
    PEAK_PHI,
    PEAK_PSI,
    RESIDUAL_COHESION,
    RESIDUAL_PHI,
    RESIDUAL_PSI,
    RESIDUAL_TENSION,
    SHEAR_MODULUS,
    SIN_PHI,
    SIN_PSI,
    SOFTENING_DISPLACEMENT,
    TENSION,
)

__all__ = ["characteristic_length", "softening_fraction", "softening_return",
           "softening_return_from", "strength_at",
           "add_softening_tangent", "residual_plastic_strain", "snap_back_length",
           "warn_snap_back"]

_SQRT3 = math.sqrt(3.0)


def characteristic_length(x: np.ndarray, cells: np.ndarray) -> np.ndarray:
    """Crack-band width h [m] of each cell: sqrt(A) (quadrilateral), sqrt(2 A) (triangle).

    ``x`` (n_vertices, 2) coordinates [m]; ``cells`` (n_cells, 3 or 4) vertex indices in
    order around the cell. A triangle of area A is half of the quadrilateral of side
    sqrt(2 A) it would come from, so both measure the width of a band one element wide.
    """
    p = np.asarray(x, dtype=float)[np.asarray(cells)]
    px, py = p[..., 0], p[..., 1]
    area = 0.5 * np.abs(np.sum(px * np.roll(py, -1, axis=1) - np.roll(px, -1, axis=1) * py,
                               axis=1))
    return np.sqrt(area * (2.0 if p.shape[1] == 3 else 1.0))


def snap_back_length(row: np.ndarray) -> float:
    """Largest element size [m] whose band unloads elastically faster than it softens.

    h_max = u_r G / (tau_p - tau_r) (crack band: Bazant & Oh 1983), with the drop of the
    shear strength at zero mean stress, tau = c cos(phi), of the kernel ``row``. Where phi
    falls too the drop grows with the confining stress and the limit is smaller there.
    inf for a material without softening or without a drop of c cos(phi).
    """
    u_r = float(row[SOFTENING_DISPLACEMENT])
    drop = (float(row[COHESION]) * float(row[COS_PHI])
            - float(row[RESIDUAL_COHESION]) * math.cos(float(row[RESIDUAL_PHI])))
    if u_r <= 0.0 or drop <= 0.0:
        return math.inf
    return u_r * float(row[SHEAR_MODULUS]) / drop


def warn_snap_back(length: np.ndarray, material: np.ndarray, table: np.ndarray,
                   stacklevel: int = 3) -> None:
    """Warn when elements exceed their material's :func:`snap_back_length`.

    ``length`` [m] and ``material`` (row of ``table``) of each element. Such an element jumps
    towards residual at the peak and dissipates more than the regularised energy.
    """
    for m in np.unique(material):
        h_max = snap_back_length(table[m])
        big = (material == m) & (length > h_max)
        if big.any():
            warnings.warn(
                f"{int(big.sum())} elements of softening material {int(m)} are larger than its "
                f"snap-back size u_r G / (tau_p - tau_r) = {h_max:.3g} m (largest "
                f"{float(length[big].max()):.3g} m): they soften faster than they unload and "
                "dissipate more than the regularised energy; refine them below that size or "
                "give a larger softening_displacement", UserWarning, stacklevel=stacklevel)


@numba.njit(cache=True, inline="always")
def residual_plastic_strain(table, m, length):
    """Equivalent plastic strain kappa_r at which the strength is residual (inf: no softening)."""
    ur = table[m, SOFTENING_DISPLACEMENT]
    if ur <= 0.0 or length <= 0.0:
        return np.inf
    return ur / (_SQRT3 * length)


@numba.njit(cache=True, inline="always")
def softening_fraction(table, m, kappa, length):
    """Xi = min(sqrt(3) kappa h / u_r, 1) in [0, 1] (0: peak, or a material without softening)."""
    kr = residual_plastic_strain(table, m, length)
    if kappa <= 0.0 or kr == np.inf:
        return 0.0
    return min(kappa / kr, 1.0)


@numba.njit(cache=True)
def strength_at(table, m, xi):
    """Strength in force at softening fraction ``xi``: (c, sin phi, cos phi, sin psi, t).

    ``xi`` = 0 gives the peak columns of the row as they are; 1 the residual strength.
    """
    if xi <= 0.0:
        return (table[m, COHESION], table[m, SIN_PHI], table[m, COS_PHI], table[m, SIN_PSI],
                table[m, TENSION])
    t = table[m, RESIDUAL_TENSION]  # NO_TENSION_CUTOFF: none given, the apex in force
    if xi >= 1.0:
        c = table[m, RESIDUAL_COHESION]
        phi = table[m, RESIDUAL_PHI]
        psi = table[m, RESIDUAL_PSI]
    else:
        c = table[m, COHESION] + (table[m, RESIDUAL_COHESION] - table[m, COHESION]) * xi
        phi = table[m, PEAK_PHI] + (table[m, RESIDUAL_PHI] - table[m, PEAK_PHI]) * xi
        psi = table[m, PEAK_PSI] + (table[m, RESIDUAL_PSI] - table[m, PEAK_PSI]) * xi
        if t < NO_TENSION_CUTOFF:  # given at one end at least: both ends finite
            t = table[m, TENSION] + (t - table[m, TENSION]) * xi
    sin_phi = math.sin(phi)
    cos_phi = math.cos(phi)
    if sin_phi > 0.0:
        t = min(t, c * cos_phi / sin_phi)
    return c, sin_phi, cos_phi, math.sin(psi), t


@numba.njit(cache=True)
def _return_at(s1, s2, s3, K, G, table, m, kappa, length):
    """Return of the trial (s1, s2, s3) at the strength in force at ``kappa``.

    Returns (r1, r2, r3, region, q) with q the equivalent plastic strain of the return.
    """
    c, sin_phi, cos_phi, sin_psi, t = strength_at(
        table, m, softening_fraction(table, m, kappa, length))
    return _return_with(s1, s2, s3, K, G, c, sin_phi, cos_phi, sin_psi, t)


@numba.njit(cache=True)
def _return_with(s1, s2, s3, K, G, c, sin_phi, cos_phi, sin_psi, t):
    """Return of the trial (s1, s2, s3) at the strength (c, phi, psi, t) given.

    Returns (r1, r2, r3, region, q) with q the equivalent plastic strain of the return.
    """
    r1, r2, r3, region = return_principal(s1, s2, s3, K, G, c, sin_phi, cos_phi, sin_psi, t)
    if region == REGION_ELASTIC:
        return r1, r2, r3, region, 0.0
    return r1, r2, r3, region, equivalent_plastic_strain(s1 - r1, s2 - r2, s3 - r3, K, G)


@numba.njit(cache=True)
def softening_return(s1, s2, s3, K, G, table, m, kappa_n, length):
    """Return of sorted trial principal stresses with the strength softening (module docstring).

    ``kappa_n``: the point's accumulated equivalent plastic strain before the step; ``length``:
    its element's characteristic length [m]. Returns (r1, r2, r3, region, d_kappa): the
    returned principal stresses, the region of the return at the final strength and the
    increment of kappa. A material without softening gives the perfectly plastic return at
    its peak strength.
    """
    c, sin_phi, cos_phi, sin_psi, t = strength_at(
        table, m, softening_fraction(table, m, kappa_n, length))
    return softening_return_from(s1, s2, s3, K, G, table, m, kappa_n, length, c, sin_phi,
                                 cos_phi, sin_psi, t)


@numba.njit(cache=True)
def softening_return_from(s1, s2, s3, K, G, table, m, kappa_n, length, c, sin_phi, cos_phi,
                          sin_psi, t):
    """``softening_return`` given the strength in force at ``kappa_n`` (``strength_at``).

    For a caller that keeps each point's strength while its ``kappa`` does not change (the
    discrete element kernel): the result is the same, bit for bit.
    """
    r1, r2, r3, region, q = _return_with(s1, s2, s3, K, G, c, sin_phi, cos_phi, sin_psi, t)
    kr = residual_plastic_strain(table, m, length)
    if region == REGION_ELASTIC or kr == np.inf or kappa_n >= kr:
        return r1, r2, r3, region, q
    a1, a2, a3, region_r, q_r = _return_at(s1, s2, s3, K, G, table, m, kr, length)
    if kappa_n + q_r >= kr:  # the root lies on the residual branch
        return a1, a2, a3, region_r, q_r
    # bracket of g(k) = kappa_n + q(k) - k: g(kappa_n) = q > 0, g(kr) = kappa_n + q_r - kr < 0
    lo, g_lo = kappa_n, q
    hi, g_hi = kr, kappa_n + q_r - kr
    k_try = kappa_n + q_r  # the root when q grows monotonically as the strength falls
    b1, b2, b3, region_b, q_b = _return_at(s1, s2, s3, K, G, table, m, k_try, length)
    g_try = kappa_n + q_b - k_try
    if g_try <= 0.0:
        hi, g_hi = k_try, g_try
        r1, r2, r3, region, q = b1, b2, b3, region_b, q_b
    else:
        lo, g_lo = k_try, g_try
    tol = 1.0e-14 * kr
    side = 0
    for _ in range(200):
        k = (lo * g_hi - hi * g_lo) / (g_hi - g_lo)
        r1, r2, r3, region, q = _return_at(s1, s2, s3, K, G, table, m, k, length)
        g = kappa_n + q - k
        if abs(g) <= tol or hi - lo <= tol:
            break
        if g > 0.0:
            lo, g_lo = k, g
            if side == 1:
                g_hi *= 0.5
            side = 1
        else:
            hi, g_hi = k, g
            if side == -1:
                g_lo *= 0.5
            side = -1
    return r1, r2, r3, region, q


@numba.njit(cache=True)
def add_softening_tangent(s1, s2, s3, r1, r2, r3, ia, ib, iz, c, s, K, G, table, m, kappa,
                          length, tangent):
    """Add the softening term R_kappa (x) Q_eps / (1 - Q_kappa) to ``tangent`` (4x4, in place).

    ``s1..s3``: sorted trial principal stresses; ``r1..r3`` the return; ``ia, ib, iz`` the
    sorted positions of the in-plane pair (a, b) and of zz; ``c, s`` cosine and sine of the
    direction of a; ``kappa``: kappa_{n+1}; ``tangent``: R_eps, the tangent at the strength in
    force. Nothing is added on the residual branch or without softening.
    """
    kr = residual_plastic_strain(table, m, length)
    if kr == np.inf or kappa >= kr:
        return
    h = 1.0e-6 * kr
    k_plus = min(kappa + h, kr)
    k_minus = max(kappa - h, 0.0)
    p1, p2, p3, _, qp = _return_at(s1, s2, s3, K, G, table, m, k_plus, length)
    n1, n2, n3, _, qm = _return_at(s1, s2, s3, K, G, table, m, k_minus, length)
    dk = k_plus - k_minus
    dr = ((p1 - n1) / dk, (p2 - n2) / dk, (p3 - n3) / dk)
    q_kappa = (qp - qm) / dk
    cc, ss, cs = c * c, s * s, c * s
    da, db = dr[ia], dr[ib]
    r_kappa = (da * cc + db * ss, da * ss + db * cc, dr[iz], (da - db) * cs)
    # plastic strain increment C (sigma_tr - sigma) in principal axes, then Voigt (eng. shear)
    e = principal_plastic_strain(s1 - r1, s2 - r2, s3 - r3, K, G)
    q = math.sqrt(2.0 / 3.0 * (e[0] * e[0] + e[1] * e[1] + e[2] * e[2]))
    if q <= 0.0:
        return
    ea, eb = e[ia], e[ib]
    # dQ/d(e_p) in Voigt with engineering shear: (2 / 3Q) (exx, eyy, ezz, gamma_xy / 2)
    f = 2.0 / (3.0 * q)
    grad = (f * (ea * cc + eb * ss), f * (ea * ss + eb * cc), f * e[iz], f * (ea - eb) * cs)
    # Q_eps_j = sum_i grad_i (delta_ij - (C R_eps)_ij), C the Voigt compliance
    cn = 1.0 / (9.0 * K) - 1.0 / (6.0 * G)
    cd = 1.0 / (2.0 * G)
    scale = 1.0 / (1.0 - q_kappa)
    for j in range(4):
        tr = tangent[0, j] + tangent[1, j] + tangent[2, j]
        qe = grad[j] - (grad[0] * (cn * tr + cd * tangent[0, j])
                        + grad[1] * (cn * tr + cd * tangent[1, j])
                        + grad[2] * (cn * tr + cd * tangent[2, j])
                        + grad[3] * tangent[3, j] / G)
        for i in range(4):
            tangent[i, j] += r_kappa[i] * qe * scale
