"""Element kernels: objective stress update and internal forces (updated Lagrangian).

One call does, for every element (``prange``, elements own their nodes: no write conflicts):

1. strain increment from the displacement increment du = dt v(t+dt/2) on the mid-step
   configuration x - du/2 (thesis section 4.4; Belytschko, Liu & Moran 2014 sec. 6.3):
   L = dJ Jm^-1 with dJ = d(du)/d(xi), Jm = d(x_mid)/d(xi); d_eps = sym L (engineering gxy);
2. objective rotation by the Hughes-Winget increment R = (I - W/2)^-1 (I + W/2), W = skew L
   (in 2D a rotation by a with tan(a/2) = w/2; exact for any rigid rotation because L is then
   2 tan(a/2) times the unit skew matrix): sigma_n is rotated by a, and the increment C:d_eps,
   which lives on the mid-step frame, by a/2 (to first order). Adding the unrotated mid-step
   increment to R sigma_n R^T (the textbook form) mixes frames: we measured that it pumps
   energy into a spinning, vibrating element (x25 in 3 s); this form does not (tested).
3. constitutive update: linear elastic trial, corrected unless the material is elastic_only by
   the shared closed-form Mohr-Coulomb principal return
   (``hybrid.constitutive.softening.softening_return``, or ``softening_return_from`` with the
   point's strength kept by ``StrengthMemo``; the spectral split around it is done here
   without trigonometry or arrays, the same algebra as ``mohr_coulomb_point``);
4. internal force I_a = sum_gp B_a^T sigma detJ w on the new configuration.

Q4: 2x2 Gauss with B-bar / mean dilatation (Nagtegaal et al. 1974, Hughes 1980): the in-plane
volumetric strain increment at each Gauss point is replaced by the element's exact area change
(A1 - A0)/A_mid, and the matching force uses the area gradient dA/dx_a times the mean pressure,
so Q4 does not lock in isochoric plastic flow. T3: one point, constant strain.
"""

from __future__ import annotations

import math

import numpy as np

import hybrid  # noqa: F401  (sets NUMBA_CACHE_DIR / OMP_WAIT_POLICY before numba loads)
from hybrid.constitutive.principal import equivalent_plastic_strain, return_principal
from hybrid.constitutive.softening import (
    softening_fraction,
    softening_return,
    softening_return_from,
    strength_at,
)
from hybrid.constitutive.table import (
    COHESION,
    COS_PHI,
    SIN_PHI,
    SIN_PSI,
    SOFTENING_DISPLACEMENT,
    TENSION,
)
from hybrid.discrete.state import DiscreteState

import numba  # isort: skip

__all__ = ["element_forces", "internal_forces", "strain_energy", "StrengthMemo"]

# No fastmath, not even {"contract"} (fused multiply-add, ~15 % faster element loop): with
# numba 0.56 a kernel compiled in this process and the same kernel loaded from the cache gave
# different last bits (measured), which breaks bit-for-bit restarts across processes.


@numba.njit(cache=True, inline="always")
def _objective_trial(sxx, syy, szz, sxy, l12, l21, dexx, deyy, dgxy, lam, G):
    """Elastic trial stress on the end-of-step frame (Hughes-Winget, section 2 of the module).

    sigma_n is rotated by the increment angle a, tan(a/2) = t = (L21 - L12)/4 (Cayley: exact
    for rigid rotation); the increment C:d_eps, computed on the mid-step frame, is turned by
    a/2 to the end frame to first order (the neglected O(a^2 d_sigma) is far below the
    O(a d_sigma) frame error this removes). Returns (txx, tyy, tzz, txy).
    """
    t = 0.25 * (l21 - l12)
    den = 1.0 / (1.0 + t * t)
    c = (1.0 - t * t) * den
    s = 2.0 * t * den
    rxx, ryy, rxy = _rotate(sxx, syy, sxy, c, s)
    ev = dexx + deyy
    dxx = lam * ev + 2.0 * G * dexx
    dyy = lam * ev + 2.0 * G * deyy
    dxy = G * dgxy
    return (rxx + (dxx - 2.0 * t * dxy), ryy + (dyy + 2.0 * t * dxy), szz + lam * ev,
            rxy + (dxy + t * (dxx - dyy)))


@numba.njit(cache=True, inline="always")
def _rotate(sxx, syy, sxy, c, s):
    """In-plane stress rotated by the angle with cosine c and sine s: R sigma R^T."""
    cc = c * c
    ss = s * s
    cs = c * s
    rxx = cc * sxx - 2.0 * cs * sxy + ss * syy
    ryy = ss * sxx + 2.0 * cs * sxy + cc * syy
    rxy = cs * (sxx - syy) + (cc - ss) * sxy
    return rxx, ryy, rxy


@numba.njit(cache=True, inline="always")
def _mc_update(txx, tyy, tzz, txy, K, G, material_table, m, kappa, length, memo, e, gp):
    """Mohr-Coulomb correction of the elastic trial stress (tension positive).

    Uses the shared closed-form principal return (``softening_return_from``: the strength in
    force at the point's plastic strain ``kappa`` and its element's characteristic ``length``,
    kept in ``memo[e, gp]`` while kappa stays the same (``StrengthMemo``; an empty ``memo``:
    ``softening_return``, computed afresh; the peak strength without softening): the
    in-plane principal pair from p +- sqrt(h^2 + txy^2),
    sorted with sigma_zz, returned, and rotated back with the trial eigenvectors
    (cos 2theta = h / rad, sin 2theta = txy / rad: no trigonometry). Scalars only, so that it
    parallelises without reference counting. Returns (sxx, syy, szz, sxy, d_eps_p_eq, yielded)
    with d_eps_p_eq = sqrt(2/3 e_p:e_p), e_p = C:(sigma_tr - sigma), as ``mohr_coulomb_point``.
    """
    p = 0.5 * (txx + tyy)
    h = 0.5 * (txx - tyy)
    rad = math.sqrt(h * h + txy * txy)
    sa = p + rad
    sb = p - rad
    if tzz >= sa:
        s1, s2, s3 = tzz, sa, sb
    elif tzz >= sb:
        s1, s2, s3 = sa, tzz, sb
    else:
        s1, s2, s3 = sa, sb, tzz
    if material_table[m, SOFTENING_DISPLACEMENT] > 0.0:
        if memo.shape[0] == 0:
            r1, r2, r3, region, deq = softening_return(s1, s2, s3, K, G, material_table, m,
                                                       kappa, length)
        else:
            if not (memo[e, gp, 0] == kappa and memo[e, gp, 1] == m
                    and memo[e, gp, 2] == length):
                c, sin_phi, cos_phi, sin_psi, t = strength_at(
                    material_table, m, softening_fraction(material_table, m, kappa, length))
                memo[e, gp, 0] = kappa
                memo[e, gp, 1] = m
                memo[e, gp, 2] = length
                memo[e, gp, 3] = c
                memo[e, gp, 4] = sin_phi
                memo[e, gp, 5] = cos_phi
                memo[e, gp, 6] = sin_psi
                memo[e, gp, 7] = t
            r1, r2, r3, region, deq = softening_return_from(
                s1, s2, s3, K, G, material_table, m, kappa, length, memo[e, gp, 3],
                memo[e, gp, 4], memo[e, gp, 5], memo[e, gp, 6], memo[e, gp, 7])
    else:  # perfect plasticity: the closed-form return at the peak strength
        r1, r2, r3, region = return_principal(
            s1, s2, s3, K, G, material_table[m, COHESION], material_table[m, SIN_PHI],
            material_table[m, COS_PHI], material_table[m, SIN_PSI], material_table[m, TENSION])
        deq = 0.0
        if region != 0:
            deq = equivalent_plastic_strain(s1 - r1, s2 - r2, s3 - r3, K, G)
    if region == 0:
        return txx, tyy, tzz, txy, 0.0, 0
    if tzz >= sa:
        ra, rb, rz = r2, r3, r1
    elif tzz >= sb:
        ra, rz, rb = r1, r2, r3
    else:
        ra, rb, rz = r1, r2, r3
    if rad > 0.0:
        c2 = h / rad
        s2t = txy / rad
    else:
        c2 = 1.0
        s2t = 0.0
    hm = 0.5 * (ra + rb)
    hd = 0.5 * (ra - rb)
    return hm + hd * c2, hm - hd * c2, rz, hd * s2t, deq, 1


@numba.njit(cache=True, inline="always")
def _increment_gradient(j11, j12, j21, j22, k11, k12, k21, k22):
    """Gradient of the displacement increment on the mid-step configuration, L = dJ Jm^-1.

    J is the Jacobian at the end of the step, dJ (k) its increment, Jm = J - dJ / 2 and
    Jm^-1 = [[m22, -m12], [-m21, m11]] / det Jm. Returns (L11, L12, L21, L22).
    """
    m11 = j11 - 0.5 * k11
    m12 = j12 - 0.5 * k12
    m21 = j21 - 0.5 * k21
    m22 = j22 - 0.5 * k22
    idm = 1.0 / (m11 * m22 - m12 * m21)
    l11 = (k11 * m22 - k12 * m21) * idm
    l12 = (-k11 * m12 + k12 * m11) * idm
    l21 = (k21 * m22 - k22 * m21) * idm
    l22 = (-k21 * m12 + k22 * m11) * idm
    return l11, l12, l21, l22


@numba.njit(cache=True, inline="always")
def _point_update(stress, plastic_strain, yielded, e, gp, l12, l21, dexx, deyy, dgxy,
                  material_table, m, elastic, length, plastic_cap, memo):
    """Stress update of Gauss point ``gp`` of element ``e``, written in place.

    The objective elastic trial (``_objective_trial``), then the isotropic Mohr-Coulomb
    return (it commutes with the rotation) unless the material is elastic or the point's
    plastic strain has reached ``plastic_cap`` (the element's entry of the per-element cap).
    Returns the new (sxx, syy, szz, sxy).
    """
    K = material_table[m, 0]
    G = material_table[m, 1]
    lam = K - 2.0 * G / 3.0
    sxx, syy, szz, sxy = _objective_trial(
        stress[e, gp, 0], stress[e, gp, 1], stress[e, gp, 2], stress[e, gp, 3], l12, l21,
        dexx, deyy, dgxy, lam, G)
    if not elastic and plastic_strain[e, gp] < plastic_cap:
        sxx, syy, szz, sxy, dp, yl = _mc_update(sxx, syy, szz, sxy, K, G, material_table, m,
                                                plastic_strain[e, gp], length, memo, e, gp)
        plastic_strain[e, gp] += dp
        yielded[e, gp] = yl
    else:
        yielded[e, gp] = 0
    stress[e, gp, 0] = sxx
    stress[e, gp, 1] = syy
    stress[e, gp, 2] = szz
    stress[e, gp, 3] = sxy
    return sxx, syy, szz, sxy


@numba.njit(cache=True, parallel=True)
def _q4_kernel(x, v, dt, element_nodes, element_material, material_table, elastic_only,
               element_length, stress, plastic_strain, yielded, bbar, plastic_cap, memo, force):
    """Q4 stress update + internal force (module docstring); writes force (n_nodes, 2).

    bbar False: plain 2x2 integration of the volumetric part too (locks; for comparison).
    """
    ne = element_nodes.shape[0]
    g = 1.0 / math.sqrt(3.0)
    for e in numba.prange(ne):
        n0 = element_nodes[e, 0]
        n1 = element_nodes[e, 1]
        n2 = element_nodes[e, 2]
        n3 = element_nodes[e, 3]
        x0 = x[n0, 0]
        x1 = x[n1, 0]
        x2 = x[n2, 0]
        x3 = x[n3, 0]
        y0 = x[n0, 1]
        y1 = x[n1, 1]
        y2 = x[n2, 1]
        y3 = x[n3, 1]
        u0 = dt * v[n0, 0]
        u1 = dt * v[n1, 0]
        u2 = dt * v[n2, 0]
        u3 = dt * v[n3, 0]
        w0 = dt * v[n0, 1]
        w1 = dt * v[n1, 1]
        w2 = dt * v[n2, 1]
        w3 = dt * v[n3, 1]
        m = element_material[e]
        elastic = elastic_only[m]
        # exact area change of the bilinear element (shoelace; quadratic in x so the mid-step
        # area gradient times du equals A1 - A0 exactly)
        a1 = 0.5 * ((x2 - x0) * (y3 - y1) - (x3 - x1) * (y2 - y0))
        xo0 = x0 - u0
        xo1 = x1 - u1
        xo2 = x2 - u2
        xo3 = x3 - u3
        yo0 = y0 - w0
        yo1 = y1 - w1
        yo2 = y2 - w2
        yo3 = y3 - w3
        a0 = 0.5 * ((xo2 - xo0) * (yo3 - yo1) - (xo3 - xo1) * (yo2 - yo0))
        am = 0.5 * ((x2 - 0.5 * u2 - x0 + 0.5 * u0) * (y3 - 0.5 * w3 - y1 + 0.5 * w1)
                    - (x3 - 0.5 * u3 - x1 + 0.5 * u1) * (y2 - 0.5 * w2 - y0 + 0.5 * w0))
        theta_bar = (a1 - a0) / am
        vol = 1.0 if bbar else 0.0
        # bilinear map: J = [[ax + cx eta, bx + cx xi], [ay + cy eta, by + cy xi]] (same form
        # for the displacement increment, k = dJ, and the mid-step configuration, Jm = J - k/2)
        ax = 0.25 * (-x0 + x1 + x2 - x3)
        bx = 0.25 * (-x0 - x1 + x2 + x3)
        cx = 0.25 * (x0 - x1 + x2 - x3)
        ay = 0.25 * (-y0 + y1 + y2 - y3)
        by = 0.25 * (-y0 - y1 + y2 + y3)
        cy = 0.25 * (y0 - y1 + y2 - y3)
        au = 0.25 * (-u0 + u1 + u2 - u3)
        bu = 0.25 * (-u0 - u1 + u2 + u3)
        cu = 0.25 * (u0 - u1 + u2 - u3)
        aw = 0.25 * (-w0 + w1 + w2 - w3)
        bw = 0.25 * (-w0 - w1 + w2 + w3)
        cw = 0.25 * (w0 - w1 + w2 - w3)
        # force sums: I_a = sum_gp dN_a/dxi P + dN_a/deta Q with P, Q the columns of
        # adj(J)^T sigma; dN_a/dxi = xa (1 + ea eta)/4, dN_a/deta = ea (1 + xa xi)/4
        spx = 0.0
        spy = 0.0
        sepx = 0.0
        sepy = 0.0
        sqx = 0.0
        sqy = 0.0
        sxqx = 0.0
        sxqy = 0.0
        psum = 0.0
        for gp in range(4):
            xi = -g if (gp == 0 or gp == 3) else g
            eta = -g if gp < 2 else g
            j11 = ax + cx * eta
            j12 = bx + cx * xi
            j21 = ay + cy * eta
            j22 = by + cy * xi
            k11 = au + cu * eta
            k12 = bu + cu * xi
            k21 = aw + cw * eta
            k22 = bw + cw * xi
            l11, l12, l21, l22 = _increment_gradient(j11, j12, j21, j22, k11, k12, k21, k22)
            corr = 0.5 * (theta_bar - l11 - l22) * vol
            dexx = l11 + corr
            deyy = l22 + corr
            dgxy = l12 + l21
            sxx, syy, szz, sxy = _point_update(stress, plastic_strain, yielded, e, gp, l12, l21,
                                               dexx, deyy, dgxy, material_table, m, elastic,
                                               element_length[e], plastic_cap[e], memo)
            # force on the new configuration: det J dN/dx = j22 dNxi - j21 dNeta,
            # det J dN/dy = -j12 dNxi + j11 dNeta
            det = j11 * j22 - j12 * j21
            if det <= 0.0:
                det = math.nan  # inverted element: poison the forces, the run monitor stops
            p2 = 0.5 * (sxx + syy) * vol
            psum += det * p2
            qxx = sxx - p2
            qyy = syy - p2
            px = j22 * qxx - j12 * sxy
            py = j22 * sxy - j12 * qyy
            qx = j11 * sxy - j21 * qxx
            qy = j11 * qyy - j21 * sxy
            spx += px
            spy += py
            sepx += eta * px
            sepy += eta * py
            sqx += qx
            sqy += qy
            sxqx += xi * qx
            sxqy += xi * qy
        # mean-pressure part with the area gradient: dA/dx_a = (y_{a+1} - y_{a-1}) / 2
        pm = psum / a1
        # node signs (xa, ea): 0 (-1, -1), 1 (1, -1), 2 (1, 1), 3 (-1, 1)
        force[n0, 0] = 0.25 * (-(spx - sepx) - (sqx - sxqx)) + 0.5 * (y1 - y3) * pm
        force[n0, 1] = 0.25 * (-(spy - sepy) - (sqy - sxqy)) + 0.5 * (x3 - x1) * pm
        force[n1, 0] = 0.25 * ((spx - sepx) - (sqx + sxqx)) + 0.5 * (y2 - y0) * pm
        force[n1, 1] = 0.25 * ((spy - sepy) - (sqy + sxqy)) + 0.5 * (x0 - x2) * pm
        force[n2, 0] = 0.25 * ((spx + sepx) + (sqx + sxqx)) + 0.5 * (y3 - y1) * pm
        force[n2, 1] = 0.25 * ((spy + sepy) + (sqy + sxqy)) + 0.5 * (x1 - x3) * pm
        force[n3, 0] = 0.25 * (-(spx + sepx) + (sqx - sxqx)) + 0.5 * (y0 - y2) * pm
        force[n3, 1] = 0.25 * (-(spy + sepy) + (sqy - sxqy)) + 0.5 * (x2 - x0) * pm


@numba.njit(cache=True, parallel=True)
def _t3_kernel(x, v, dt, element_nodes, element_material, material_table, elastic_only,
               element_length, stress, plastic_strain, yielded, plastic_cap, memo, force):
    """T3 (one point) stress update + internal force; writes force (n_nodes, 2)."""
    ne = element_nodes.shape[0]
    for e in numba.prange(ne):
        n0 = element_nodes[e, 0]
        n1 = element_nodes[e, 1]
        n2 = element_nodes[e, 2]
        x0 = x[n0, 0]
        x1 = x[n1, 0]
        x2 = x[n2, 0]
        y0 = x[n0, 1]
        y1 = x[n1, 1]
        y2 = x[n2, 1]
        u0 = dt * v[n0, 0]
        u1 = dt * v[n1, 0]
        u2 = dt * v[n2, 0]
        w0 = dt * v[n0, 1]
        w1 = dt * v[n1, 1]
        w2 = dt * v[n2, 1]
        m = element_material[e]
        # J = [[x1-x0, x2-x0], [y1-y0, y2-y0]] (area coordinates)
        j11 = x1 - x0
        j12 = x2 - x0
        j21 = y1 - y0
        j22 = y2 - y0
        k11 = u1 - u0
        k12 = u2 - u0
        k21 = w1 - w0
        k22 = w2 - w0
        l11, l12, l21, l22 = _increment_gradient(j11, j12, j21, j22, k11, k12, k21, k22)
        dexx = l11
        deyy = l22
        dgxy = l12 + l21
        sxx, syy, szz, sxy = _point_update(stress, plastic_strain, yielded, e, 0, l12, l21, dexx,
                                           deyy, dgxy, material_table, m, elastic_only[m],
                                           element_length[e], plastic_cap[e], memo)
        det = j11 * j22 - j12 * j21
        h = 0.5 if det > 0.0 else math.nan
        # A dN_a/dx = (y_{a+1} - y_{a+2}) / 2, A dN_a/dy = (x_{a+2} - x_{a+1}) / 2
        bx = h * (y1 - y2)
        by = h * (x2 - x1)
        force[n0, 0] = sxx * bx + sxy * by
        force[n0, 1] = sxy * bx + syy * by
        bx = h * (y2 - y0)
        by = h * (x0 - x2)
        force[n1, 0] = sxx * bx + sxy * by
        force[n1, 1] = sxy * bx + syy * by
        bx = h * (y0 - y1)
        by = h * (x1 - x0)
        force[n2, 0] = sxx * bx + sxy * by
        force[n2, 1] = sxy * bx + syy * by


@numba.njit(cache=True, parallel=True)
def _strain_energy_kernel(x, element_nodes, element_material, material_table, stress, out):
    """Elastic energy per element [kJ/m], written into ``out`` (n_elements,).

    sum_gp A/ngp [I1^2/(18K) + s:s/(4G)] (3D deviator s, plane strain with sigma_zz).
    """
    ne = element_nodes.shape[0]
    nen = element_nodes.shape[1]
    ngp = stress.shape[1]
    for e in numba.prange(ne):
        area = 0.0
        for a in range(nen):
            i = element_nodes[e, a]
            j = element_nodes[e, (a + 1) % nen]
            area += 0.5 * (x[i, 0] * x[j, 1] - x[j, 0] * x[i, 1])
        m = element_material[e]
        K = material_table[m, 0]
        G = material_table[m, 1]
        acc = 0.0
        for gp in range(ngp):
            sxx = stress[e, gp, 0]
            syy = stress[e, gp, 1]
            szz = stress[e, gp, 2]
            sxy = stress[e, gp, 3]
            i1 = sxx + syy + szz
            mn = i1 / 3.0
            ss = (sxx - mn) ** 2 + (syy - mn) ** 2 + (szz - mn) ** 2 + 2.0 * sxy * sxy
            acc += i1 * i1 / (18.0 * K) + ss / (4.0 * G)
        out[e] = acc * area / ngp


@numba.njit(cache=True)
def _same_bits(a, b):
    """True when two int64 arrays of one shape (a table's bit patterns) are equal."""
    for i in range(a.shape[0]):
        for j in range(a.shape[1]):
            if a[i, j] != b[i, j]:
                return False
    return True


_NO_MEMO = np.empty((0, 0, 8))  # every strength computed afresh


class StrengthMemo:
    """Each Gauss point's strength in force, kept while its plastic strain does not change.

    The softened strength (``strength_at``: three trigonometric calls) is the same function of
    the point's plastic strain every step; the element kernel recomputes it only where the
    plastic strain, the element's material row or its characteristic length differ from
    those it was computed for, so the result is the same bit for bit. ``values`` (n_elements,
    n_points, 8): [kappa, material row, length, c, sin phi, cos phi, sin psi, t] (nan: not
    computed). Made once by the caller of a stepping loop (``ExplicitSolver``); ``fit``
    starts it afresh when the element count or the material table changes (bit for bit),
    and keeps nothing when no material softens.
    """

    def __init__(self) -> None:
        self.values = np.empty((0, 0, 8))
        self._table = np.empty((0, 0))

    def fit(self, n_elements: int, n_points: int, material_table: np.ndarray) -> np.ndarray:
        """The memo for this mesh and table (reset when either changed)."""
        if (self.values.shape[:2] != (n_elements, n_points)
                or self._table.shape != material_table.shape
                or not _same_bits(self._table.view(np.int64), material_table.view(np.int64))):
            self._table = material_table.copy()
            softens = bool(np.any(material_table[:, SOFTENING_DISPLACEMENT] > 0.0))
            self.values = (np.full((n_elements, n_points, 8), np.nan) if softens
                           else np.empty((n_elements, n_points, 0)))
        return self.values if self.values.shape[2] else _NO_MEMO


def element_forces(x, v, dt, element_nodes, element_material, material_table, elastic_only,
                   element_length, stress, plastic_strain, yielded, force, bbar: bool = True,
                   plastic_strain_cap: np.ndarray | None = None,
                   memo: StrengthMemo | None = None) -> None:
    """Array-level call of the element kernel (no validation: the engine's hot path).

    Updates stress / plastic_strain / yielded for the increment du = dt v and writes the
    internal force I on the current configuration x into force (n_nodes, 2). A Gauss point
    of element e whose accumulated plastic strain has reached ``plastic_strain_cap[e]``
    (n_elements,; None: no cap) responds elastically from then on (``ExplicitSolver``: the
    residual plastic strain of an element whose softened band has split, and the expert
    option ``RunOptions.plastic_strain_cap``). ``element_length`` (n_elements,) is the
    characteristic length of strain softening [m] (``DiscreteState.element_length``).
    ``memo``: the points' strengths kept from call to call (``StrengthMemo``; None: computed
    afresh).
    """
    ne = element_nodes.shape[0]
    cap = np.full(ne, np.inf) if plastic_strain_cap is None else plastic_strain_cap
    kept = _NO_MEMO if memo is None else memo.fit(ne, stress.shape[1], material_table)
    if element_nodes.shape[1] == 4:
        _q4_kernel(x, v, dt, element_nodes, element_material, material_table, elastic_only,
                   element_length, stress, plastic_strain, yielded, bbar, cap, kept, force)
    else:
        _t3_kernel(x, v, dt, element_nodes, element_material, material_table, elastic_only,
                   element_length, stress, plastic_strain, yielded, cap, kept, force)


def internal_forces(state: DiscreteState, dt: float = 0.0, *, bbar: bool = True) -> np.ndarray:
    """Stress update for du = dt * state.v, then the internal force (n_nodes, 2) [kN/m].

    With dt = 0 (the default) the stresses are unchanged (elastic) and only I is computed.
    The result is also stored in ``state.internal_force``.
    """
    if not (math.isfinite(dt) and dt >= 0.0):
        raise ValueError(f"dt = {dt!r}: must be a finite number >= 0 [s]")
    if state.nen not in (3, 4):
        raise ValueError(f"element_nodes has {state.nen} columns: expected 4 (Q4) or 3 (T3)")
    # dt = 0: no return mapping, so that stresses outside the yield surface (elastic points
    # beside failed bonds) stay as they are
    cap = np.zeros(state.element_nodes.shape[0]) if dt == 0.0 else None
    element_forces(state.x, state.v, float(dt), state.element_nodes, state.element_material,
                   state.material_table, state.elastic_only, state.element_length, state.stress,
                   state.plastic_strain, state.yielded, state.internal_force, bbar, cap)
    assert state.internal_force is not None  # set in DiscreteState.__post_init__
    return state.internal_force


def strain_energy(state: DiscreteState) -> float:
    """Elastic strain energy of the current stresses [kJ per m thickness]."""
    out = np.empty(state.n_elements)
    _strain_energy_kernel(state.x, state.element_nodes, state.element_material,
                          state.material_table, state.stress, out)
    return float(np.sum(out))
