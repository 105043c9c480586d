"""Mohr-Coulomb return mapping: yield surface, regions, tangent, invariance, reference solver.

Conventions: tension positive, Voigt (xx, yy, zz, xy), engineering shear, kPa.
"""

import itertools
import math

import numpy as np
import pytest

from hybrid.constitutive import (
    NO_TENSION_CUTOFF,
    NO_YIELD,
    REGION_NAMES,
    VERTEX_STABILISATION,
    kernel_row,
    mohr_coulomb_point,
    mohr_coulomb_update,
    return_principal,
    update_stress,
    yield_function,
)
from hybrid.materials import Material, MaterialError

C = 10.0  # cohesion (kPa) of the test materials
E, NU = 2.0e4, 0.3


def _material(E, nu, cohesion, phi, psi=0.0, tensile_strength=None):
    """A plastic Mohr-Coulomb ``Material`` (kPa, degrees)."""
    return Material(name="test", E=E, nu=nu, cohesion=cohesion, phi=phi, psi=psi,
                    tensile_strength=tensile_strength, plastic=True)


def _row(m):
    """The kernel's material-table row of ``m`` as an array."""
    return np.array(kernel_row(m))


def _params(phi, psi, t=None):
    return _material(E, NU, C, phi, psi, t)


# (phi, psi, tensile strength): associated, non-associated, psi = 0; without (None -> c cot phi)
# and with a tension cut-off below the apex (c cot 30 deg = 17.3 kPa)
CASES = [
    (30.0, 30.0, None),
    (30.0, 10.0, None),
    (30.0, 0.0, None),
    (30.0, 30.0, 5.0),
    (30.0, 10.0, 5.0),
    (30.0, 0.0, 5.0),
]
MC_REGIONS = {"main plane", "edge s1=s2", "edge s2=s3", "apex"}
CUTOFF_REGIONS = set(REGION_NAMES[1:10])


def _elastic_matrix(K, G):
    lam = K - 2.0 * G / 3.0
    D = np.zeros((4, 4))
    D[:3, :3] = lam
    D[np.arange(3), np.arange(3)] += 2.0 * G
    D[3, 3] = G
    return D


def _principal(s):
    """Sorted principal stresses (n, 3) of Voigt stresses (n, 4) (numpy, not the kernel)."""
    s = np.atleast_2d(s)
    p = 0.5 * (s[:, 0] + s[:, 1])
    r = np.hypot(0.5 * (s[:, 0] - s[:, 1]), s[:, 3])
    return -np.sort(-np.stack([p + r, p - r, s[:, 2]], axis=1), axis=1)


def _voigt_from_principal(pr, theta):
    """In-plane principal values (a, b) at angle theta, zz given: Voigt stress."""
    c, s = np.cos(theta), np.sin(theta)
    a, b, z = pr[:, 0], pr[:, 1], pr[:, 2]
    return np.stack([a * c * c + b * s * s, a * s * s + b * c * c, z, (a - b) * c * s], axis=1)


def _states_from_principal(rng, pr, row):
    """Old stresses and strain increments whose elastic trial has principal values ``pr``."""
    D = _elastic_matrix(row[0], row[1])
    n = len(pr)
    trial = _voigt_from_principal(pr, rng.uniform(0, np.pi, n))
    old = rng.uniform(-30.0, 10.0, (n, 4))
    de = np.linalg.solve(D, (trial - old).T).T
    return old, de, trial


def _random_states(rng, n, row, low=-120.0, high=40.0):
    """Old stresses and strain increments whose elastic trial has principal values in a box."""
    return _states_from_principal(rng, rng.uniform(low, high, (n, 3)), row)


def _regions(trial, row):
    pr = _principal(trial)
    return np.array([return_principal(*p, *row[:7])[3] for p in pr])


def _yield_composite(stress, row):
    """max(F_MC, 2 (s1 - t)): zero on the composite surface (kPa)."""
    pr = _principal(stress)
    sphi, cphi, t = row[3], row[4], row[6]
    f = (pr[:, 0] - pr[:, 2]) + (pr[:, 0] + pr[:, 2]) * sphi - 2.0 * C * cphi
    return np.maximum(f, 2.0 * (pr[:, 0] - t)), f


@pytest.mark.parametrize("phi,psi,t", CASES)
def test_return_lies_on_yield_surface_all_regions(phi, psi, t):
    row = _row(_params(phi, psi, t))
    rng = np.random.default_rng(1)
    old, de, trial = _random_states(rng, 4000, row)
    new, _, deq, yielded = update_stress(old, de, _params(phi, psi, t), want_tangent=False)
    reg = _regions(trial, row)
    names = {REGION_NAMES[r] for r in reg}
    counts = {REGION_NAMES[k]: int(np.sum(reg == k)) for k in range(len(REGION_NAMES))}
    expected = MC_REGIONS if t is None else CUTOFF_REGIONS
    assert expected <= names, f"regions not hit: {expected - names}; counts {counts}"
    assert counts["vertex fallback"] == 0, counts
    plastic = yielded == 1
    assert np.array_equal(plastic, reg != 0)
    g, f = _yield_composite(new, row)
    # exact closed-form return: only round-off of stresses ~1e2 kPa remains (~1e-13 kPa)
    assert np.max(np.abs(g[plastic])) < 1e-9 * C
    # the Mohr-Coulomb function itself (F of hybrid and of this test agree, F <= 0 everywhere)
    fk = np.array([yield_function(*s, C, row[3], row[4]) for s in new[:50]])
    assert np.allclose(fk, f[:50], rtol=0, atol=1e-12 * C)
    assert np.all(f <= 1e-9 * C)
    assert np.all(deq[plastic] > 0) and np.all(deq[~plastic] == 0)


def test_elastic_states_unchanged():
    p = _params(30.0, 10.0, 5.0)
    row = _row(p)
    rng = np.random.default_rng(2)
    old, de, trial = _random_states(rng, 3000, row)
    g, _ = _yield_composite(trial, row)
    keep = g < -1e-3 * C
    old, de, trial = old[keep], de[keep], trial[keep]
    assert len(old) > 100
    new, tan, deq, yielded = update_stress(old, de, p)
    D = _elastic_matrix(p.bulk_modulus, p.shear_modulus)
    # the elastic predictor is returned as is: agreement to round-off (1e-12 relative)
    scale = np.max(np.abs(trial), axis=1, keepdims=True)
    assert np.max(np.abs(new - (old + de @ D.T)) / scale) < 1e-12
    assert np.all(yielded == 0) and np.all(deq == 0)
    assert np.allclose(tan, D, rtol=1e-14, atol=0)


def _fd_tangent(old, de, row, h):
    """Central finite differences of the kernel stress w.r.t. the strain increment."""
    out = np.empty(4)
    tg = np.empty((4, 4))
    J = np.empty((4, 4))
    for j in range(4):
        cols = []
        for sgn in (1.0, -1.0):
            d = de.copy()
            d[j] += sgn * h
            mohr_coulomb_point(*old, *d, row[None], 0, 0.0, 1.0, out, tg, False)
            cols.append(out.copy())
        J[:, j] = (cols[0] - cols[1]) / (2 * h)
    return J


@pytest.mark.parametrize("phi,psi,t", [(30.0, 10.0, 5.0), (30.0, 30.0, None), (20.0, 0.0, None)])
def test_tangent_matches_finite_differences(phi, psi, t):
    row = _row(_params(phi, psi, t))
    D = _elastic_matrix(row[0], row[1])
    rng = np.random.default_rng(3)
    old, de, trial = _random_states(rng, 600, row)
    reg = _regions(trial, row)
    h = 1e-7  # strain step: truncation O(h^2) of the smooth eigenvector part ~1e-10 relative,
    # round-off ~ eps * 1e2 kPa / h ~ 1e-7 kPa against entries ~1e4 kPa: both << 1e-5
    out = np.empty(4)
    tan = np.empty((4, 4))
    tested = {}
    worst = 0.0
    for i in range(len(old)):
        if reg[i] >= 7:  # vertices: zero principal tangent (stabilised), tested apart
            continue
        # skip points within reach of a region boundary (FD would straddle a kink)
        pert = [trial[i] + s * h * D[:, j] for j in range(4) for s in (-1, 1)]
        if np.any(_regions(np.array(pert), row) != reg[i]):
            continue
        mohr_coulomb_point(*old[i], *de[i], row[None], 0, 0.0, 1.0, out, tan, True)
        J = _fd_tangent(old[i], de[i], row, h)
        err = np.max(np.abs(J - tan)) / np.max(np.abs(tan))
        worst = max(worst, err)
        tested[REGION_NAMES[reg[i]]] = tested.get(REGION_NAMES[reg[i]], 0) + 1
        assert err < 1e-5, (REGION_NAMES[reg[i]], err)
    needed = {"elastic", "main plane", "edge s1=s2", "edge s2=s3"}
    if t is not None:
        needed |= {"tension plane", "tension edge", "shear-tension line"}
    assert needed <= set(tested), tested


def test_tangent_repeated_in_plane_eigenvalues():
    """sxx = syy, sxy = 0: the spin term takes its limit; FD still agrees (1e-5)."""
    p = _params(30.0, 10.0)
    row = _row(p)
    old = np.array([-20.0, -20.0, -20.0, 0.0])
    out = np.empty(4)
    tan = np.empty((4, 4))
    for de in (np.array([-1e-3, -1e-3, 4e-3, 0.0]), np.array([2e-3, 2e-3, -4e-3, 0.0])):
        mohr_coulomb_point(*old, *de, row[None], 0, 0.0, 1.0, out, tan, True)
        trial = old + _elastic_matrix(p.bulk_modulus, p.shear_modulus) @ de
        reg = _regions(trial[None], row)[0]
        assert REGION_NAMES[reg] in ("edge s1=s2", "edge s2=s3")
        J = _fd_tangent(old, de, row, 1e-8)
        assert np.max(np.abs(J - tan)) / np.max(np.abs(tan)) < 1e-5


def test_apex_tangent_is_stabilised_elastic():
    """Hydrostatic tension beyond the apex: stress = apex, tangent = 1e-5 D (documented)."""
    p = _params(30.0, 0.0)
    out = np.empty(4)
    tan = np.empty((4, 4))
    mohr_coulomb_point(0.0, 0.0, 0.0, 0.0, 1e-2, 1e-2, 1e-2, 0.0, _row(p)[None], 0, 0.0, 1.0,
                       out, tan, True)
    apex = C / math.tan(math.radians(30.0))
    assert np.allclose(out, [apex, apex, apex, 0.0], rtol=1e-14, atol=1e-12)
    D = _elastic_matrix(p.bulk_modulus, p.shear_modulus)
    assert np.allclose(tan, VERTEX_STABILISATION * D, rtol=1e-12)


def test_tresca_limit():
    """phi = 0: every plastic return has (s1 - s3)/2 = c (to round-off, 1e-12 c)."""
    p = _material(E=E, nu=NU, cohesion=50.0, phi=0.0, psi=0.0)
    row = _row(p)
    assert row[6] == NO_TENSION_CUTOFF
    rng = np.random.default_rng(4)
    old, de, trial = _random_states(rng, 2000, row, -400.0, 200.0)
    new, _, _, yielded = update_stress(old, de, p, want_tangent=False)
    pr = _principal(new)
    assert np.sum(yielded) > 1000
    # stresses up to ~400 kPa: round-off ~1e-13 kPa (7e-14 measured); bar 1e-12 c = 5e-11 kPa
    assert np.max(np.abs(0.5 * (pr[yielded == 1, 0] - pr[yielded == 1, 2]) - 50.0)) < 1e-12 * 50
    reg = {REGION_NAMES[r] for r in _regions(trial, row)}
    assert {"main plane", "edge s1=s2", "edge s2=s3"} <= reg


def _rotation(theta):
    """Voigt rotation of stress (T_s) and engineering strain (T_e) by theta about z."""
    c, s = math.cos(theta), math.sin(theta)
    Ts = np.array(
        [
            [c * c, s * s, 0, -2 * c * s],
            [s * s, c * c, 0, 2 * c * s],
            [0, 0, 1, 0],
            [c * s, -c * s, 0, c * c - s * s],
        ]
    )
    Te = np.array(
        [
            [c * c, s * s, 0, -c * s],
            [s * s, c * c, 0, c * s],
            [0, 0, 1, 0],
            [2 * c * s, -2 * c * s, 0, c * c - s * s],
        ]
    )
    return Ts, Te


@pytest.mark.parametrize("phi,psi,t", [(30.0, 10.0, 5.0), (30.0, 0.0, None)])
def test_rotation_invariance(phi, psi, t):
    p = _params(phi, psi, t)
    rng = np.random.default_rng(5)
    old, de, _ = _random_states(rng, 500, _row(p))
    new, tan, deq, _ = update_stress(old, de, p)
    for theta in (0.3, 1.1, -2.0):
        Ts, Te = _rotation(theta)
        new_r, tan_r, deq_r, _ = update_stress(old @ Ts.T, de @ Te.T, p)
        scale = np.max(np.abs(new), axis=1) + C
        # rotation only re-orders round-off: 1e-10 relative
        assert np.max(np.abs(new_r - new @ Ts.T).max(axis=1) / scale) < 1e-10
        assert np.allclose(deq_r, deq, rtol=1e-8, atol=1e-14)
        # the tangent is a 4th-order tensor: D_r = T_s D T_e^-1
        tan_expected = Ts @ tan @ np.linalg.inv(Te)
        assert np.max(np.abs(tan_r - tan_expected)) < 1e-8 * np.max(np.abs(tan))


@pytest.mark.parametrize("psi", [0.0, 10.0, 25.0])
def test_plastic_flow_direction_main_plane(psi):
    """Main-plane return: d_eps_p parallel to dG/dsigma = (1 + sin psi, 0, -(1 - sin psi))."""
    p = _params(30.0, psi)
    row = _row(p)
    rng = np.random.default_rng(6)
    old, de, trial = _random_states(rng, 1500, row)
    reg = _regions(trial, row)
    new, _, deq, _ = update_stress(old, de, p, want_tangent=False)
    D = _elastic_matrix(p.bulk_modulus, p.shear_modulus)
    sel = reg == 1
    assert sel.sum() > 100
    ep = de[sel] - np.linalg.solve(D, (new[sel] - old[sel]).T).T  # engineering shear
    ep_t = ep.copy()
    ep_t[:, 3] *= 0.5  # tensor shear: principal values like a stress
    pe = _principal(ep_t)
    dev = pe[:, 0] - pe[:, 2]
    # plastic strain is recovered from stress differences: cancellation bounds accuracy
    # to ~1e-12 * |de| / |ep|; 1e-8 keeps a wide margin
    assert np.max(np.abs(pe.sum(axis=1) / dev - math.sin(math.radians(psi)))) < 1e-8
    assert np.max(np.abs(pe[:, 1]) / dev) < 1e-8
    # the returned equivalent plastic strain is sqrt(2/3 eps_p : eps_p) (tensor components)
    assert np.allclose(deq[sel], np.sqrt(2.0 / 3.0 * np.sum(pe**2, axis=1)), rtol=1e-8)


# --- slow, independent reference: brute-force Kuhn-Tucker search in unsorted principal space


def _planes_unsorted(row):
    """All 9 planes of the composite surface in unsorted principal space: (n, m, r)."""
    _, _, c, sphi, cphi, spsi, t = row[:7]
    out = []
    for i, j in itertools.permutations(range(3), 2):
        n = np.zeros(3)
        m = np.zeros(3)
        n[i], n[j] = 1 + sphi, -(1 - sphi)
        m[i], m[j] = 1 + spsi, -(1 - spsi)
        out.append((n, m, 2 * c * cphi))
    for i in range(3):
        e = np.eye(3)[i]
        out.append((e, e, t))
    return out


def _reference_returns(s_tr, row):
    """Every Kuhn-Tucker point (stress) of the return: active sets of 1 to 3 planes."""
    K, G = row[0], row[1]
    Dp = (K - 2 * G / 3) * np.ones((3, 3)) + 2 * G * np.eye(3)
    planes = _planes_unsorted(row)
    scale = np.max(np.abs(s_tr)) + row[2] + 1.0
    if max(n @ s_tr - r for n, _, r in planes) <= 0:
        return [s_tr]
    sols = []
    for k in (1, 2, 3):
        for S in itertools.combinations(range(9), k):
            N = np.array([planes[a][0] for a in S])
            Mt = np.array([Dp @ planes[a][1] for a in S]).T
            r = np.array([planes[a][2] for a in S])
            A = N @ Mt
            if abs(np.linalg.det(A)) < 1e-9 * np.prod(np.abs(A).sum(axis=1)):
                continue
            dg = np.linalg.solve(A, N @ s_tr - r)
            s = s_tr - Mt @ dg
            if np.all(dg >= -1e-12 * scale / G) and all(
                n @ s - r <= 1e-10 * scale for n, _, r in planes
            ):
                if not any(np.allclose(s, q, rtol=0, atol=1e-9 * scale) for q in sols):
                    sols.append(s)
    return sols


def _vertex_states(rng, row, per_vertex):
    """Trial principal stresses beyond every vertex of the surface (brute-force vertices)."""
    K, G = row[0], row[1]
    Dp = (K - 2 * G / 3) * np.ones((3, 3)) + 2 * G * np.eye(3)
    planes = _planes_unsorted(row)
    tol = 1e-10 * (row[2] + 1.0)
    out = []
    verts = []
    for S in itertools.combinations(range(9), 3):
        N = np.array([planes[a][0] for a in S])
        if abs(np.linalg.det(N)) < 1e-9:
            continue
        v = np.linalg.solve(N, [planes[a][2] for a in S])
        if all(n @ v - r <= tol for n, _, r in planes) and not any(
            np.allclose(v, w, atol=tol) for w in verts
        ):
            verts.append(v)
    for v in verts:
        gens = np.array([Dp @ m for n, m, r in planes if abs(n @ v - r) <= tol])
        alpha = rng.uniform(0.0, 2e-3, (per_vertex, len(gens)))
        out.append(v + alpha @ gens)
    return np.vstack(out)


@pytest.mark.parametrize(
    "phi,psi,t,c", [case + (C,) for case in CASES] + [(35.0, 5.0, None, 0.0), (0.0, 0.0, 30.0, C)]
)
def test_matches_bruteforce_kuhn_tucker_reference(phi, psi, t, c):
    """Random trials vs. an exhaustive Kuhn-Tucker search (unsorted, all 9 planes).

    Trials: 200 in a wide box, 100 near the tension zone, 15 beyond every vertex. Associated
    flow: the return is the unique closest point in the energy norm (convex set) and the search
    finds exactly one point. Non-associated: the kernel must be one of the points found.
    Agreement 1e-8 relative (both are exact linear solves; round-off ~1e-13 measured).
    """
    p = _material(E, NU, c, phi, psi, t)
    row = _row(p)
    rng = np.random.default_rng(7)
    pr = np.vstack(
        [
            rng.uniform(-120.0, 40.0, (200, 3)),
            rng.uniform(-40.0, 25.0, (100, 3)),
            _vertex_states(rng, row, 15),
        ]
    )
    old, de, trial = _states_from_principal(rng, pr, row)
    new, _, _, _ = update_stress(old, de, p, want_tangent=False)
    pr_new = _principal(new)
    pr_tr = _principal(trial)
    for i in range(len(old)):
        sols = _reference_returns(pr_tr[i], row)
        assert sols, "reference found no Kuhn-Tucker point"
        if psi == phi:
            assert len(sols) == 1
        scale = np.max(np.abs(pr_tr[i])) + c + 1.0
        err = min(np.max(np.abs(pr_new[i] - s)) for s in sols) / scale
        assert err < 1e-8, (i, pr_tr[i], pr_new[i], sols)
    names = {REGION_NAMES[r] for r in _regions(trial, row)}
    assert "vertex fallback" not in names
    if c > 0 and phi > 0:
        assert (MC_REGIONS if t is None else CUTOFF_REGIONS) <= names, names


def test_associated_return_is_energy_closest_point_scipy():
    """Associated case against scipy SLSQP (independent QP solver), 1e-6 (SLSQP's accuracy)."""
    optimize = pytest.importorskip("scipy.optimize")
    p = _params(30.0, 30.0, 5.0)
    row = _row(p)
    K, G = p.bulk_modulus, p.shear_modulus
    Cp = np.linalg.inv((K - 2 * G / 3) * np.ones((3, 3)) + 2 * G * np.eye(3))
    planes = _planes_unsorted(row)
    rng = np.random.default_rng(8)
    old, de, trial = _random_states(rng, 40, row)
    new, _, _, _ = update_stress(old, de, p, want_tangent=False)
    for s_tr, s_k in zip(_principal(trial), _principal(new)):
        cons = [
            {"type": "ineq", "fun": (lambda x, n=n, r=r: r - n @ x), "jac": (lambda x, n=n: -n)}
            for n, _, r in planes
        ]
        res = optimize.minimize(
            lambda x, s=s_tr: 0.5 * (x - s) @ Cp @ (x - s) * p.shear_modulus,
            s_tr,
            jac=lambda x, s=s_tr: Cp @ (x - s) * p.shear_modulus,
            constraints=cons,
            method="SLSQP",
            options={"ftol": 1e-14, "maxiter": 200},
        )
        x = -np.sort(-res.x)
        assert np.max(np.abs(x - s_k)) < 1e-6 * (np.max(np.abs(s_tr)) + C)


def test_vectorised_update_million_points_matches_point_function():
    p1 = _params(30.0, 10.0, 5.0)
    p2 = _material(E=5.0e4, nu=0.25, cohesion=0.0, phi=35.0, psi=5.0)
    table = np.stack([_row(p1), _row(p2)])
    n = 1_000_000
    rng = np.random.default_rng(9)
    old, de, _ = _random_states(rng, n, _row(p1))
    mat = rng.integers(0, 2, n)
    stress = np.empty((n, 4))
    tangent = np.empty((n, 4, 4))
    peq = np.full(n, 0.5)  # accumulated value: incremented in place
    yielded = np.zeros(n, dtype=np.int8)
    mohr_coulomb_update(old, de, mat, table, np.ones(n), stress, tangent, peq, yielded, True)
    assert 0.1 < yielded.mean() < 0.95
    out = np.empty(4)
    tg = np.empty((4, 4))
    for q in rng.choice(n, 300, replace=False):
        d, f = mohr_coulomb_point(*old[q], *de[q], table, mat[q], 0.5, 1.0, out, tg, True)
        # same code, same inputs: identical up to compiler re-association (1e-13 relative)
        assert np.allclose(stress[q], out, rtol=1e-13, atol=1e-13 * C)
        assert np.allclose(tangent[q], tg, rtol=1e-13, atol=1e-13 * np.abs(tg).max())
        assert peq[q] == pytest.approx(0.5 + d, rel=1e-13) and yielded[q] == f


def test_no_allocation_per_point():
    """The NRT allocation count of one vectorised call does not grow with the point count."""
    rtsys = pytest.importorskip("numba.core.runtime").rtsys
    p = _params(30.0, 10.0, 5.0)
    table = _row(p)[None]
    counts = []
    for n in (10, 20_000):
        old, de, _ = _random_states(np.random.default_rng(10), n, _row(p))
        args = (
            old,
            de,
            np.zeros(n, np.int64),
            table,
            np.ones(n),
            np.empty((n, 4)),
            np.empty((n, 4, 4)),
            np.zeros(n),
            np.zeros(n, np.int8),
            True,
        )
        mohr_coulomb_update(*args)  # compiled / loaded
        before = rtsys.get_allocation_stats().alloc
        mohr_coulomb_update(*args)
        counts.append(rtsys.get_allocation_stats().alloc - before)
    assert counts[0] == counts[1], counts  # only the parallel launch allocates (8 measured)


def test_single_point_wrapper():
    """A (4,) input gives a (4,) stress, (4, 4) tangent and scalars. With nu = 0 an axial
    strain is uniaxial stress while elastic: the elastic limit is the closed-form uniaxial
    compressive strength q_u = 2 c cos(phi) / (1 - sin(phi)) (yield at 1.01 q_u, not 0.99)."""
    p = _material(E=E, nu=0.0, cohesion=C, phi=30.0, psi=30.0)
    # nu = 0: a pure axial strain gives uniaxial stress while elastic
    s, tan, deq, y = update_stress(np.zeros(4), np.array([0.0, -5e-3, 0.0, 0.0]), p)
    assert s.shape == (4,) and tan.shape == (4, 4) and np.ndim(deq) == 0 and y == 1
    qu = 2 * C * math.cos(math.radians(30)) / (1 - math.sin(math.radians(30)))
    # past yield the stress is on the surface (round-off ~1e-14 kPa)
    assert abs(yield_function(*s, C, 0.5, math.sqrt(0.75))) < 1e-9 * C
    s_el, _, _, y_el = update_stress(np.zeros(4), np.array([0.0, -0.99 * qu / E, 0.0, 0.0]), p)
    assert y_el == 0 and s_el[1] == pytest.approx(-0.99 * qu, rel=1e-12)
    _, _, d_pl, y_pl = update_stress(np.zeros(4), np.array([0.0, -1.01 * qu / E, 0.0, 0.0]), p)
    assert y_pl == 1 and d_pl > 0


def test_kernel_row_of_a_material():
    """The kernel row: K, G, c, sin/cos phi, sin psi and the tension cut-off, the apex
    c cot(phi) unless a lower one is given; phi = 0 without a cut-off has none; an elastic
    material's row never yields. Validation of the numbers is the Material's (test_materials)."""
    p = _material(E=1.0e4, nu=0.25, cohesion=5.0, phi=30.0, psi=0.0)
    row = _row(p)
    np.testing.assert_allclose(row[:6], [1.0e4 / 1.5, 4.0e3, 5.0, 0.5, math.sqrt(0.75), 0.0],
                               rtol=1e-14)
    assert row[6] == pytest.approx(5.0 / math.tan(math.radians(30.0)), rel=1e-14)
    assert _row(_material(1e4, 0.25, 5.0, 30.0, 0.0, 2.0))[6] == 2.0
    assert _row(_material(1e4, 0.25, 5.0, 0.0))[6] == NO_TENSION_CUTOFF
    elastic = _row(Material(name="rock", E=1e4, nu=0.25))
    assert elastic[2] == elastic[6] == NO_YIELD and elastic[3] == 0.0
    with pytest.raises(MaterialError, match="cohesion"):
        _material(1e4, 0.25, 0.0, 0.0)  # plastic without strength


def test_update_stress_input_errors():
    p = _params(30.0, 0.0)
    with pytest.raises(ValueError, match="stress_old"):
        update_stress(np.zeros((3, 3)), np.zeros((3, 3)), p)
    with pytest.raises(ValueError, match="strain_increment"):
        update_stress(np.zeros((3, 4)), np.zeros((2, 4)), p)
    with pytest.raises(ValueError, match="NaN"):
        update_stress(np.full((1, 4), np.nan), np.zeros((1, 4)), p)
    with pytest.raises(ValueError, match="material_of_point"):
        update_stress(
            np.zeros((2, 4)),
            np.zeros((2, 4)),
            material_of_point=[0, 3],
            material_table=_row(p)[None],
        )
    with pytest.raises(ValueError, match="material_table"):
        update_stress(
            np.zeros((2, 4)),
            np.zeros((2, 4)),
            material_of_point=[0, 0],
            material_table=np.zeros((1, 6)),
        )


def test_elastic_update_is_the_kernel_where_it_answers_elastically():
    """``elastic_update`` (a solver's points held elastic) writes at the listed points exactly
    what ``mohr_coulomb_update`` writes where its response is elastic, stress and tangent, and
    leaves the other points alone."""
    from hybrid.constitutive.mohr_coulomb import elastic_update

    rng = np.random.default_rng(3)
    n = 400
    table = _row(_material(E, NU, C, 30.0)).reshape(1, -1)
    p = -rng.uniform(5.0, 50.0, n)  # compressive mean stress [kPa], small deviators
    old = np.column_stack([p, p, p, np.zeros(n)]) + rng.uniform(-2.0, 2.0, (n, 4))
    deps = rng.uniform(-1e-3, 1e-3, (n, 4))
    mat, length = np.zeros(n, dtype=np.int64), np.ones(n)
    stress, tangent = np.empty((n, 4)), np.empty((n, 4, 4))
    kappa, yielded = np.zeros(n), np.zeros(n, dtype=np.int8)
    mohr_coulomb_update(old, deps, mat, table, length, stress, tangent, kappa, yielded, True)
    elastic = np.flatnonzero(yielded == 0)
    assert 0 < elastic.size < n  # both responses among the points
    held_stress, held_tangent = np.full((n, 4), np.nan), np.full((n, 4, 4), np.nan)
    elastic_update(old, deps, mat, table, elastic, held_stress, held_tangent)
    np.testing.assert_array_equal(held_stress[elastic], stress[elastic])
    np.testing.assert_array_equal(held_tangent[elastic], tangent[elastic])
    others = np.setdiff1d(np.arange(n), elastic)
    assert np.isnan(held_stress[others]).all() and np.isnan(held_tangent[others]).all()
