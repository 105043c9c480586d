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

Strain softening: a material with a residual strength softens from peak to residual with the
accumulated equivalent plastic strain, regularised by its element's size; the return is then
implicit in the strength and the tangent gains one rank-one term
(``hybrid.constitutive.softening``). Without softening the update is the perfectly plastic one
above, unchanged. The return in principal stresses lives in ``hybrid.constitutive.principal``.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numba
import numpy as np

from hybrid.constitutive.principal import (
    REGION_ELASTIC,
    REGION_NAMES,
    REGION_VERTEX_12,
    equivalent_plastic_strain,
    principal_tangent,
    return_principal,
    yield_function,
)
from hybrid.constitutive.softening import (
    add_softening_tangent,
    softening_fraction,
    softening_return,
    strength_at,
)
from hybrid.constitutive.table import SOFTENING_DISPLACEMENT, TABLE_WIDTH, kernel_row

if TYPE_CHECKING:
    from hybrid.materials import Material

__all__ = [
    "mohr_coulomb_point",
    "equivalent_plastic_strain",
    "mohr_coulomb_update",
    "elastic_update",
    "elastic_tangent",
    "return_principal",
    "update_stress",
    "yield_function",
    "VERTEX_STABILISATION",
    "REGION_NAMES",
]

#: Fraction of the elastic matrix added to the tangent at a vertex (apex) return.
VERTEX_STABILISATION = 1.0e-5

@numba.njit(cache=True)
def elastic_tangent(lam, G, out_tangent):
    """The isotropic elastic matrix into ``out_tangent[0:4, 0:4]`` (kPa).

    Lame's ``lam`` and ``G``; Voigt (xx, yy, zz, xy) with engineering shear.
    """
    for i in range(4):
        for j in range(4):
            out_tangent[i, j] = 0.0
    for i in range(3):
        for j in range(3):
            out_tangent[i, j] = lam
        out_tangent[i, i] += 2.0 * G
    out_tangent[3, 3] = G


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
    table,
    m,
    kappa,
    length,
    out_stress,
    out_tangent,
    want_tangent,
):
    """Stress update of one point: elastic predictor + closed-form principal return.

    Old stress ``(sxx, syy, szz, sxy)`` (kPa), strain increment ``(dexx, deyy, dezz, dgxy)``
    (engineering shear); material row ``table[m]`` (``hybrid.constitutive.table``), the
    point's accumulated equivalent plastic strain ``kappa`` and its element's characteristic
    length ``length`` [m] (both used only when the material softens:
    ``hybrid.constitutive.softening``). Writes the new stress into ``out_stress[0:4]`` and, if
    ``want_tangent``, the consistent tangent ``d sigma_i / d(delta eps)_j`` into
    ``out_tangent[0:4, 0:4]`` (kPa). Returns ``(d_eps_p_eq, yielded)``: the increment of
    ``sqrt(2/3 eps_p : eps_p)`` and 1 if a plastic correction was applied, else 0.
    No allocation: safe inside hot loops.
    """
    K = table[m, 0]
    G = table[m, 1]
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
    r1, r2, r3, region, deq = softening_return(s1, s2, s3, K, G, table, m, kappa, length)
    if region == REGION_ELASTIC:
        out_stress[0] = txx
        out_stress[1] = tyy
        out_stress[2] = tzz
        out_stress[3] = txy
        if want_tangent:
            elastic_tangent(lam, G, out_tangent)
        return 0.0, 0
    ret = (r1, r2, r3)
    ra = ret[ia]
    rb = ret[ib]
    out_stress[0] = ra * c * c + rb * s * s
    out_stress[1] = ra * s * s + rb * c * c
    out_stress[2] = ret[iz]
    out_stress[3] = (ra - rb) * c * s
    if want_tangent:
        # the strength in force at kappa_{n+1} (the peak without softening)
        cohesion, sin_phi, cos_phi, sin_psi, t = strength_at(
            table, m, softening_fraction(table, m, kappa + deq, length))
        cc = c * c
        ss = s * s
        cs = c * s
        # eigenprojections (stress columns = strain rows with engineering shear)
        mv = ((cc, ss, 0.0, cs), (ss, cc, 0.0, -cs), (0.0, 0.0, 1.0, 0.0))
        A = principal_tangent(region, lam, G, sin_phi, cos_phi, sin_psi, cohesion, t)
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
        add_softening_tangent(s1, s2, s3, r1, r2, r3, ia, ib, iz, c, s, K, G, table, m,
                              kappa + deq, length, out_tangent)
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
    point_length,
    stress_new,
    tangent,
    plastic_strain,
    yielded,
    want_tangent,
):
    """Vectorised ``mohr_coulomb_point`` over ``n`` points (prange, points independent).

    ``stress_old, strain_increment, stress_new``: (n, 4); ``material_of_point``: (n,) int;
    ``material_table``: (nmat, ``TABLE_WIDTH``) rows (``hybrid.constitutive.table``);
    ``point_length``: (n,) characteristic length of each point's element [m] (softening);
    ``tangent``: (n, 4, 4) (with ``want_tangent`` False any (>=1, 4, 4) array, untouched);
    ``plastic_strain``: (n,) accumulated equivalent plastic strain, incremented in place;
    ``yielded``: (n,) int8, set to 1 where a plastic correction was applied, else 0.
    """
    n = stress_old.shape[0]
    for q in numba.prange(n):
        m = material_of_point[q]
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
            material_table,
            m,
            plastic_strain[q],
            point_length[q],
            stress_new[q],
            tq,
            want_tangent,
        )
        plastic_strain[q] += deq
        yielded[q] = flag


@numba.njit(cache=True)
def elastic_update(stress_old, strain_increment, material_of_point, material_table, points,
                   stress_new, tangent):
    """The elastic predictor of ``mohr_coulomb_point`` at the listed ``points`` only.

    Overwrites ``stress_new[q]`` with sigma_old + D : d_eps and ``tangent[q]`` with D for q in
    ``points`` (int array); the arrays as in :func:`mohr_coulomb_update`. A solver holds
    points on the elastic branch with it (:class:`hybrid.continuum.plastic.PlasticSolver`).
    """
    for k in range(points.shape[0]):
        q = points[k]
        m = material_of_point[q]
        K = material_table[m, 0]
        G = material_table[m, 1]
        lam = K - 2.0 * G / 3.0
        tr = lam * (strain_increment[q, 0] + strain_increment[q, 1] + strain_increment[q, 2])
        for i in range(3):
            stress_new[q, i] = stress_old[q, i] + tr + 2.0 * G * strain_increment[q, i]
        stress_new[q, 3] = stress_old[q, 3] + G * strain_increment[q, 3]
        elastic_tangent(lam, G, tangent[q])


def _check_table(table: np.ndarray) -> None:
    if table.ndim != 2 or table.shape[1] != TABLE_WIDTH or table.shape[0] < 1:
        raise ValueError(
            f"material_table has shape {table.shape}; need (nmat, {TABLE_WIDTH}) rows as "
            "hybrid.constitutive.table.kernel_table builds them"
        )
    if not np.all(np.isfinite(table)):
        raise ValueError("material_table holds NaN or inf; use finite values (kernel_table)")
    K, G, c, sphi, cphi, spsi, t = table.T[:7]
    c_r, phi_p, phi_r, psi_p, psi_r, t_r, u_r = table.T[7:]
    if np.any(K <= 0) or np.any(G <= 0):
        raise ValueError("material_table: K and G (columns 0, 1) must be > 0 kPa")
    if np.any(c < 0) or np.any(t < 0) or np.any(c_r < 0) or np.any(t_r < 0):
        raise ValueError("material_table: c, t, c_r and t_r (columns 2, 6, 7, 12) must be "
                         ">= 0 kPa")
    if np.any(sphi < 0) or np.any(sphi >= 1) or np.any(np.abs(sphi**2 + cphi**2 - 1) > 1e-12):
        raise ValueError("material_table: need 0 <= sin_phi < 1 and cos_phi = sqrt(1 - sin_phi^2)")
    if np.any(spsi < 0) or np.any(spsi > sphi):
        raise ValueError("material_table: need 0 <= sin_psi <= sin_phi (column 5)")
    if np.any((c == 0) & (sphi == 0)):
        raise ValueError("material_table: a row has c = 0 and phi = 0 (no strength)")
    soft = u_r > 0
    if np.any(u_r < 0) or np.any(soft & ((phi_r < 0) | (phi_r > phi_p) | (psi_r < 0)
                                         | (psi_r > phi_r) | ((c_r == 0) & (phi_r == 0)))):
        raise ValueError("material_table: a softening row (u_r > 0, column 13) needs "
                         "0 <= psi_r <= phi_r <= phi_p and some residual strength")


def update_stress(
    stress_old: np.ndarray,
    strain_increment: np.ndarray,
    material: Material | None = None,
    *,
    material_of_point: np.ndarray | None = None,
    material_table: np.ndarray | None = None,
    plastic_strain: np.ndarray | float = 0.0,
    length: np.ndarray | float | None = None,
    want_tangent: bool = True,
) -> tuple[np.ndarray, np.ndarray | None, np.ndarray, np.ndarray]:
    """Mohr-Coulomb stress update of ``n`` points (checked wrapper of ``mohr_coulomb_update``).

    ``stress_old``, ``strain_increment``: (n, 4) or (4,), Voigt (xx, yy, zz, xy), kPa and
    engineering shear. Give either ``material`` (one ``Material``; its row from ``kernel_row``)
    or ``material_of_point`` (n,) with ``material_table`` (nmat, ``TABLE_WIDTH``). A softening
    material also needs ``plastic_strain`` (the points' accumulated equivalent plastic strain
    before the step, scalar or (n,)) and ``length`` (their elements' characteristic length
    [m], scalar or (n,)). Returns ``(stress_new (n, 4), tangent (n, 4, 4) or None, d_eps_p_eq
    (n,), yielded (n,) int8)`` (one point: shapes (4,), (4, 4), scalars).
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
        table = np.array(kernel_row(material)).reshape(1, TABLE_WIDTH)
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
    kappa = _per_point("plastic_strain", plastic_strain, n, 0.0)
    if length is None:
        if n and np.any(table[mat, SOFTENING_DISPLACEMENT] > 0):
            raise ValueError("a softening material needs length= (the characteristic length "
                             "of each point's element [m], softening.characteristic_length)")
        h = np.ones(n)
    else:
        h = _per_point("length", length, n, 1e-300)
    stress_new = np.empty_like(s0)
    tangent = np.empty((n if want_tangent else 1, 4, 4))
    kappa_new = kappa.copy()
    yielded = np.zeros(n, dtype=np.int8)
    mohr_coulomb_update(s0, de, mat, table, h, stress_new, tangent, kappa_new, yielded,
                        bool(want_tangent))
    dpeq = kappa_new - kappa
    tan = tangent if want_tangent else None
    if single:
        return stress_new[0], (tan[0] if tan is not None else None), dpeq[0], yielded[0]
    return stress_new, tan, dpeq, yielded


def _per_point(name: str, value: np.ndarray | float, n: int, minimum: float) -> np.ndarray:
    """A scalar or (n,) argument of ``update_stress`` as a finite (n,) array >= ``minimum``."""
    a = np.asarray(value, dtype=np.float64)
    a = np.full(n, float(a)) if a.ndim == 0 else np.ascontiguousarray(a).reshape(-1)
    if a.shape[0] != n:
        raise ValueError(f"{name} has {a.shape[0]} entries; need a scalar or n = {n}")
    if not np.all(np.isfinite(a)) or np.any(a < minimum):
        raise ValueError(f"{name} must be finite and >= {minimum:g}")
    return a
