"""Contact of discrete elements (hybrid.discrete.contact): narrow phase, forces, broad phase.

References are closed forms worked by hand (stated beside each test).  Geometry results are
exact up to round-off, so they are checked at 1e-12 (inputs of order 1, a few dozen flops);
force balances at 1e-10 of the force scale (Newton inversion of the Q4 map converges to
~1e-15, plus scatter round-off).
"""

import importlib

import numpy as np
import pytest

from hybrid.discrete import contact
from hybrid.discrete.contact import (
    carry_contact_history,
    contact_forces,
    find_contact_pairs,
    overlap,
    rigid_contact_mass,
)
from hybrid.discrete.contact.forces import ContactBuffers, add_contact_forces
from hybrid.discrete.contact.polygon import MAXV, convex_apart, overlap_geometry

GEOM_TOL = 1e-12  # exact geometry, O(1) coordinates: round-off only


def square(x0, y0, s=1.0):
    return np.array([[x0, y0], [x0 + s, y0], [x0 + s, y0 + s], [x0, y0 + s]], dtype=float)


def rotated_square(cx, cy, s, theta):
    c, sn = np.cos(theta), np.sin(theta)
    local = 0.5 * s * np.array([[-1, -1], [1, -1], [1, 1], [-1, 1]], dtype=float)
    return np.array([cx, cy]) + local @ np.array([[c, sn], [-sn, c]])


def random_pile(rng, n_el, span):
    """A pile of ``n_el`` squares (sides 0.6-1 m) placed at random in [0, span]^2 and
    rotated, with random velocities: (x, element_nodes, v, mass, material, contact_table)."""
    polys = [
        rotated_square(*rng.uniform(0, span, 2), rng.uniform(0.6, 1.0), rng.uniform(0, np.pi))
        for _ in range(n_el)
    ]
    x = np.concatenate(polys)
    en = np.arange(4 * n_el, dtype=np.int64).reshape(n_el, 4)
    v = rng.normal(size=x.shape)
    mass = np.full(4 * n_el, 0.25)
    # the full row [k_n, k_t, mu, zeta, c]: the unchecked path (add_contact_forces) reads the
    # cohesion column, which only the checked contact_forces adds to a 4-column table
    table = np.array([[1e5, 5e4, 0.6, 0.2, 0.0]])
    return x, en, v, mass, np.zeros(n_el, dtype=np.int32), table


def two_body(pa, pb, kn=1e5, kt=2e4, mu=0.5, zeta=0.0, mass_a=1.0, mass_b=1.0, c=0.0):
    """Arrays for a two-element contact problem (A = element 0, B = element 1)."""
    nen = len(pa)
    x = np.vstack([pa, pb]).astype(float)
    en = np.arange(2 * nen, dtype=np.int64).reshape(2, nen)
    mass = np.r_[np.full(nen, mass_a / nen), np.full(nen, mass_b / nen)]
    table = np.array([[kn, kt, mu, zeta, c]])
    return x, en, mass, np.zeros(2, dtype=np.int32), table, np.array([[0, 1]], dtype=np.int64)


def run_pair(x, v, mass, en, mat, table, pairs, shear, dt=1e-3):
    force = np.zeros_like(x)
    out = contact_forces(x, v, mass, en, mat, table, pairs, shear, dt, force)
    return force, out


# ---------------------------------------------------------------------------------------
# Overlap area, centroid, normal
# ---------------------------------------------------------------------------------------
def test_two_squares_diagonal_offset():
    # A = [0,1]^2, B = [0.5,1.5]x[0.25,1.25]: overlap [0.5,1]x[0.25,1], area 0.375,
    # centroid (0.75, 0.625); boundaries cross at (1,0.25) and (0.5,1): chord (-0.5,0.75),
    # chord normal towards B = (0.75, 0.5)/|.|
    area, c, n = overlap(square(0, 0), square(0.5, 0.25))
    assert area == pytest.approx(0.375, abs=GEOM_TOL)
    np.testing.assert_allclose(c, [0.75, 0.625], atol=GEOM_TOL)
    np.testing.assert_allclose(n, np.array([0.75, 0.5]) / np.hypot(0.75, 0.5), atol=GEOM_TOL)
    # swapping the bodies flips the normal (it points from the first to the second)
    area2, c2, n2 = overlap(square(0.5, 0.25), square(0, 0))
    assert area2 == pytest.approx(area, abs=GEOM_TOL)
    np.testing.assert_allclose(c2, c, atol=GEOM_TOL)
    np.testing.assert_allclose(n2, -n, atol=GEOM_TOL)
    # clockwise input gives the same answer; separated squares give nothing
    area3, _, n3 = overlap(square(0, 0)[::-1], square(0.5, 0.25))
    assert area3 == pytest.approx(area, abs=GEOM_TOL)
    np.testing.assert_allclose(n3, n, atol=GEOM_TOL)
    assert overlap(square(0, 0), square(1.5, 0))[0] == 0.0


def test_rotated_square_corner_penetration():
    # A = [-2,2]x[-2,0]; B = unit square rotated by theta with its lowest corner at
    # (x0, -d): the overlap is the triangle cut by y = 0, of area d^2 / sin(2 theta) and
    # centroid (x0 + d (cot - tan)/3, -d/3); the chord lies on y = 0, normal (0, 1).
    theta, d, x0 = np.radians(30.0), 0.1, 0.3
    c, s = np.cos(theta), np.sin(theta)
    corner = np.array([x0, -d])
    b = np.array([corner, corner + [c, s], corner + [c - s, s + c], corner + [-s, c]])
    a = np.array([[-2.0, -2.0], [2.0, -2.0], [2.0, 0.0], [-2.0, 0.0]])
    area, cen, n = overlap(a, b)
    assert area == pytest.approx(d**2 / np.sin(2 * theta), abs=GEOM_TOL)
    np.testing.assert_allclose(cen, [x0 + d * (c / s - s / c) / 3, -d / 3], atol=GEOM_TOL)
    np.testing.assert_allclose(n, [0.0, 1.0], atol=GEOM_TOL)
    # diamond (square rotated 45 deg) with its tip in A's right edge: triangle of area 0.25
    # (apex (0.5, 0.2), base on x = 1 from y = -0.3 to 0.7), centroid (2.5/3, 0.2), normal +x
    area, cen, n = overlap(square(-1, -1, 2.0), rotated_square(1.5, 0.2, np.sqrt(2), np.pi / 4))
    assert area == pytest.approx(0.25, abs=GEOM_TOL)
    np.testing.assert_allclose(cen, [2.5 / 3, 0.2], atol=GEOM_TOL)
    np.testing.assert_allclose(n, [1.0, 0.0], atol=GEOM_TOL)


def test_triangle_quad():
    # A = triangle (0,0),(2,0),(0,2); B = [0.5,1.5]x[0.2,1.2]. The hypotenuse x + y = 2 cuts
    # B at (1.5,0.5) and (0.8,1.2): overlap = square (area 1, centroid (1,0.7)) minus the
    # right triangle of legs 0.7 (area 0.245, centroid (3.8/3, 2.9/3)); normal (1,1)/sqrt2.
    tri = np.array([[0.0, 0.0], [2.0, 0.0], [0.0, 2.0]])
    area, cen, n = overlap(tri, square(0.5, 0.2))
    cut = 0.5 * 0.7 * 0.7
    assert area == pytest.approx(1.0 - cut, abs=GEOM_TOL)
    expected = (np.array([1.0, 0.7]) - cut * np.array([3.8 / 3, 2.9 / 3])) / (1.0 - cut)
    np.testing.assert_allclose(cen, expected, atol=GEOM_TOL)
    np.testing.assert_allclose(n, [np.sqrt(0.5), np.sqrt(0.5)], atol=GEOM_TOL)


def test_non_convex_quad():
    # Chevron (0,0),(2,1),(0,2),(0.5,1) (reflex vertex (0.5,1), area 1.5) against the strip
    # B = [0,0.5]x[0,2]: overlap = two triangles (0,0),(0.5,0.25),(0.5,1) and
    # (0.5,1),(0.5,1.75),(0,2) of area 0.1875 each: total 0.375, centroid (1/3, 1) (outside
    # the chevron, in its notch); B's edge x = 0.5 inside A has length 1.5: normal -x.
    chevron = np.array([[0.0, 0.0], [2.0, 1.0], [0.0, 2.0], [0.5, 1.0]])
    strip = np.array([[0.0, 0.0], [0.5, 0.0], [0.5, 2.0], [0.0, 2.0]])
    area, cen, n = overlap(chevron, strip)
    assert area == pytest.approx(0.375, abs=GEOM_TOL)
    np.testing.assert_allclose(cen, [1.0 / 3.0, 1.0], atol=GEOM_TOL)
    np.testing.assert_allclose(n, [-1.0, 0.0], atol=GEOM_TOL)
    # chevron against a square that covers it completely: the area of the chevron itself
    assert overlap(chevron, square(-1, -1, 4.0))[0] == pytest.approx(1.5, abs=GEOM_TOL)


def test_normal_is_area_gradient_random_pairs():
    # For random overlapping quads (often 4+ boundary intersections) the unnormalised normal
    # G must equal minus the gradient of the overlap area under a translation of B.  The
    # area is piecewise quadratic in the translation, so a central difference with
    # eps = 1e-6 is exact up to round-off ~1e-16/eps = 1e-10: tolerance 1e-6 relative.
    # Also G(A,B) = -G(B,A) and area(A,B) = area(B,A) (round-off: 1e-12).
    rng = np.random.default_rng(7)
    work = np.empty((4, MAXV, 3))
    eps = 1e-6
    checked = 0
    for _ in range(200):
        a = rotated_square(0, 0, rng.uniform(0.5, 1.5), rng.uniform(0, np.pi))
        a[rng.integers(4)] += rng.uniform(-0.15, 0.15, 2)  # distort (stays convex here)
        b = rotated_square(*rng.uniform(-0.8, 0.8, 2), rng.uniform(0.5, 1.5), rng.uniform(0, 3))
        ar, _, _, gx, gy = overlap_geometry(a, 4, b, 4, work)
        if ar < 1e-3:
            continue
        checked += 1
        grad = np.zeros(2)
        for k in range(2):
            e = np.zeros(2)
            e[k] = eps
            ap = overlap_geometry(a, 4, b + e, 4, work)[0]
            am = overlap_geometry(a, 4, b - e, 4, work)[0]
            grad[k] = (ap - am) / (2 * eps)
        np.testing.assert_allclose([gx, gy], -grad, rtol=1e-6, atol=1e-6)
        ar2, _, _, hx, hy = overlap_geometry(b, 4, a, 4, work)
        assert ar2 == pytest.approx(ar, abs=GEOM_TOL)
        np.testing.assert_allclose([hx, hy], [-gx, -gy], atol=GEOM_TOL)
    assert checked > 100


def test_separating_axis_agrees_with_the_clipping():
    # convex_apart (the separating-axis test before the clipping) must never call apart two
    # polygons whose clipped overlap has area, and must call apart the touching neighbours
    # of a conforming patch (they only touch: overlap area 0 exactly; the clipping alone
    # returns at most a sliver of round-off area for them, GEOM_TOL). Random convex quads
    # and triangles, placed at random (mostly overlapping or apart) and as neighbours of
    # distorted conforming grids (sharing an edge or one vertex, coordinates bit-identical
    # at the shared vertices as in a tied discrete mesh).
    rng = np.random.default_rng(11)
    work = np.empty((4, MAXV, 3))
    called_apart_with_area = 0
    for _ in range(2000):
        a = rotated_square(0, 0, rng.uniform(0.5, 1.5), rng.uniform(0, np.pi))
        a[rng.integers(4)] += rng.uniform(-0.15, 0.15, 2)
        b = rotated_square(*rng.uniform(-1.5, 1.5, 2), rng.uniform(0.5, 1.5), rng.uniform(0, 3))
        nb = 3 if rng.random() < 0.3 else 4
        area = overlap_geometry(a, 4, b[:nb], nb, work)[0]
        if convex_apart(a, 4, b[:nb], nb):
            called_apart_with_area += area > 0.0
        else:
            assert area > 0.0  # exact for convex polygons in general position
    assert called_apart_with_area == 0
    # distorted 6 x 6 grids: every edge and diagonal neighbour pair only touches
    touching = 0
    for _ in range(20):
        g = np.stack(np.meshgrid(np.arange(7.0), np.arange(7.0), indexing="ij"), axis=-1)
        g[1:-1, 1:-1] += rng.uniform(-0.2, 0.2, (5, 5, 2))
        for i in range(6):
            for j in range(6):
                q = np.array([g[i, j], g[i + 1, j], g[i + 1, j + 1], g[i, j + 1]])
                for di, dj in ((1, 0), (0, 1), (1, 1), (1, -1)):
                    k, m = i + di, j + dj
                    if not (0 <= k < 6 and 0 <= m < 6):
                        continue
                    r = np.array([g[k, m], g[k + 1, m], g[k + 1, m + 1], g[k, m + 1]])
                    assert overlap_geometry(q, 4, r, 4, work)[0] <= GEOM_TOL
                    assert convex_apart(q, 4, r, 4) and convex_apart(r, 4, q, 4)
                    touching += 1
    assert touching == 20 * (2 * 6 * 5 + 2 * 5 * 5)


# ---------------------------------------------------------------------------------------
# Forces
# ---------------------------------------------------------------------------------------
def _element_moment(x, f, nodes, c):
    r = x[nodes] - c
    return np.sum(r[:, 0] * f[nodes, 1] - r[:, 1] * f[nodes, 0])


@pytest.mark.parametrize(
    "pa,pb",
    [
        (  # distorted (non-parallelogram) Q4s: exercises the Newton inversion
            np.array([[0.0, 0.0], [1.1, -0.1], [1.2, 0.9], [-0.1, 1.05]]),
            np.array([[0.7, 0.3], [1.9, 0.5], [1.8, 1.4], [0.9, 1.6]]),
        ),
        (  # T3 pair
            np.array([[0.0, 0.0], [1.0, 0.0], [0.2, 1.0]]),
            np.array([[0.5, 0.2], [1.4, 0.6], [0.4, 1.2]]),
        ),
    ],
)
def test_normal_force_equal_opposite_no_moment(pa, pb):
    kn = 1e5
    x, en, mass, mat, table, pairs = two_body(pa, pb, kn=kn)
    area, c, n = overlap(pa, pb)
    assert area > 0.01
    force, (n_act, d_f, d_d) = run_pair(
        x, np.zeros_like(x), mass, en, mat, table, pairs, np.zeros((1, 2))
    )
    f_a = force[en[0]].sum(axis=0)
    f_b = force[en[1]].sum(axis=0)
    scale = kn * area
    tol = 1e-10 * scale  # see module docstring
    assert n_act == 1 and d_f == 0.0 and d_d == 0.0
    np.testing.assert_allclose(f_b, kn * area * n, atol=tol)  # F_n = k_n A along n (eq 4.6)
    np.testing.assert_allclose(f_a, -f_b, atol=tol)  # equal and opposite
    np.testing.assert_allclose(force.sum(axis=0), 0.0, atol=tol)
    # each element gets no moment about the contact point (shape functions reproduce c)
    for e in range(2):
        assert abs(_element_moment(x, force, en[e], c)) < tol


def test_normal_damping_and_no_adhesion():
    # B = [0,1]x[-0.01,0.99] on a rigid ground A = [-2,2]x[-1,0] (infinite mass): area 0.01,
    # contact length L_c = 1, normal +y, m_eff = m_B = 1 t. Approaching at 0.2 m/s:
    # F_n = k_n A + 2 zeta sqrt(k_n L_c m_B) 0.2, dissipation c_n v^2 dt per step.
    kn, zeta, dt = 1e5, 0.3, 1e-3
    ground = np.array([[-2.0, -1.0], [2.0, -1.0], [2.0, 0.0], [-2.0, 0.0]])
    x, en, mass, mat, table, pairs = two_body(ground, square(0, -0.01), kn=kn, zeta=zeta)
    fixed = np.zeros((8, 2), dtype=bool)
    fixed[:4] = True
    cmass = rigid_contact_mass(mass, fixed, en)
    assert np.isinf(cmass[:4]).all() and (cmass[4:] == mass[4:]).all()
    v = np.zeros_like(x)
    v[4:, 1] = -0.2
    force, (_, _, d_d) = run_pair(x, v, cmass, en, mat, table, pairs, np.zeros((1, 2)), dt)
    c_n = 2 * zeta * np.sqrt(kn * 1.0 * 1.0)
    f_b = force[4:].sum(axis=0)
    # tolerance: area 0.01 comes from differences of O(1) coordinates: ~1e-16 / 1e-2 relative
    np.testing.assert_allclose(f_b, [0.0, kn * 0.01 + c_n * 0.2], rtol=1e-12, atol=1e-9)
    assert d_d == pytest.approx(c_n * 0.2**2 * dt, rel=1e-12)
    # separating faster than k_n A / c_n: the damped force would pull: clamped to zero
    v[4:, 1] = 2.0 * kn * 0.01 / c_n
    force, (n_act, _, d_d) = run_pair(x, v, cmass, en, mat, table, pairs, np.zeros((1, 2)), dt)
    assert n_act == 1
    np.testing.assert_array_equal(force, 0.0)
    assert d_d == pytest.approx(kn * 0.01 * v[4, 1] * dt, rel=1e-12)  # elastic force x motion


@pytest.mark.parametrize("mu, c", [(0.5, 0.0), (0.0, 300.0), (0.5, 100.0)])
def test_friction_spring_cap_and_slip_work(mu, c):
    # B slides along +x at v on a wide rigid ground: K_t = k_t L_c = k_t (L_c = 1 m), the
    # tangential force grows by k_t v dt per step (eq 4.9) to the cap c L_c + mu k_n A (eq
    # 4.10 with the contact's cohesion c over L_c = 1 m: a crack's Mohr-Coulomb strength),
    # then stays there; the friction dissipation over N steps is cap x total slip with
    # slip = N v dt - cap / K_t (the spring stretch is not slip).  Round-off over 400
    # steps: 1e-9 relative.
    kn, kt, v_t, dt, n_steps = 1e5, 2e4, 0.1, 1e-3, 400
    ground = np.array([[-2.0, -1.0], [2.0, -1.0], [2.0, 0.0], [-2.0, 0.0]])
    x, en, mass, mat, table, pairs = two_body(ground, square(0, -0.01), kn=kn, kt=kt, mu=mu,
                                              c=c)
    mass[:4] = np.inf
    v = np.zeros_like(x)
    v[4:, 0] = v_t
    shear = np.zeros((1, 2))
    cap = c * 1.0 + mu * kn * 0.01
    total = 0.0
    for k in range(1, n_steps + 1):
        force, (_, d_f, _) = run_pair(x, v, mass, en, mat, table, pairs, shear, dt)
        total += d_f
        expected = min(k * kt * v_t * dt, cap)
        assert -shear[0, 0] == pytest.approx(expected, rel=1e-9)
        assert force[4:, 0].sum() == pytest.approx(-expected, rel=1e-9)
        assert abs(shear[0, 1]) < 1e-9 * cap
    assert total == pytest.approx(cap * (n_steps * v_t * dt - cap / kt), rel=1e-9)
    # once sliding, every step dissipates the Coulomb force x the step's slip v dt
    assert d_f == pytest.approx(cap * v_t * dt, rel=1e-9)
    # separated pair: history reset, no force
    x[4:, 1] += 0.5
    force, (n_act, _, _) = run_pair(x, v, mass, en, mat, table, pairs, shear, dt)
    assert n_act == 0 and (shear == 0.0).all() and (force == 0.0).all()


@pytest.mark.parametrize("zeta", [0.0, 0.1])
def test_head_on_collision_momentum_and_energy(zeta):
    # A square (m = 1 t) and a diamond (m = 1 t) collide head on at 1 m/s relative speed,
    # moved as rigid bodies (nodal forces summed) by leapfrog with the contact force only.
    # The tip overlap is a triangle of area d^2 along x, so the pair is a 1-D conservative
    # spring U = k_n d^3 / 3 plus the damper: momentum is exact up to round-off (1e-12 of
    # the initial momentum scale).  Energy: with zeta = 0 the leapfrog error of a smooth
    # conservative force over ~1200 steps per contact is O(dt^2) (measured 4e-10): 1e-6;
    # with zeta = 0.1 kinetic energy after separation + the reported damping dissipation
    # (evaluated with the half-step velocity, error O(dt)) = initial energy (measured
    # 1.4e-4): 1e-3.
    kn, dt = 1e4, 1e-4
    a = square(-1, -1, 2.0)
    b = rotated_square(2.0 + 1e-3, 0.0, np.sqrt(2.0), np.pi / 4)
    x, en, mass, mat, table, pairs = two_body(a, b, kn=kn, zeta=zeta, mass_a=1.0, mass_b=1.0)
    vel = np.array([[0.5, 0.0], [-0.5, 0.0]])  # rigid-body velocities of A and B
    ke0 = 0.5 * (vel**2).sum()
    shear = np.zeros((1, 2))
    dissipated = 0.0
    touched = False
    for _ in range(20000):
        v = np.repeat(vel, 4, axis=0)
        force, (n_act, _, d_d) = run_pair(x, v, mass, en, mat, table, pairs, shear, dt)
        dissipated += d_d
        touched |= n_act > 0
        if touched and n_act == 0:
            break
        f = force.reshape(2, 4, 2).sum(axis=1)
        vel += f * dt  # unit masses
        x += np.repeat(vel, 4, axis=0) * dt
    assert touched and n_act == 0
    np.testing.assert_allclose(vel.sum(axis=0), 0.0, atol=1e-12)  # momentum (initially 0)
    assert abs(vel[0, 1]) < 1e-12  # symmetric: no sideways force
    ke1 = 0.5 * (vel**2).sum()
    assert ke1 + dissipated == pytest.approx(ke0, rel=1e-6 if zeta == 0.0 else 1e-3)
    if zeta == 0.0:
        assert dissipated == 0.0
    else:
        assert dissipated > 0.05 * ke0  # the damper did take a visible share


def test_contact_forces_deterministic_over_threads():
    # A dense random pile: the per-pair buffer + ordered scatter must give bit-identical
    # results on 1 and 2 threads, and the forces sum to zero (action = reaction; round-off
    # of ~1e4 additions of forces ~k_n A: 1e-10 of the largest nodal force).
    numba = importlib.import_module("numba")  # after hybrid (sets the numba environment)
    rng = np.random.default_rng(3)
    n_el = 300
    x, en, v, mass, mat, table = random_pile(rng, n_el, 8.0)
    pairs = find_contact_pairs(x, en, np.arange(4 * n_el), 0.01)
    shear0 = rng.normal(size=(pairs.shape[0], 2))
    results = []
    threads = sorted({1, min(2, numba.config.NUMBA_NUM_THREADS)})
    old = numba.get_num_threads()
    try:
        for nt in threads:
            numba.set_num_threads(nt)
            shear = shear0.copy()
            force, out = run_pair(x, v, mass, en, mat, table, pairs, shear)
            results.append((force, shear, out))
    finally:
        numba.set_num_threads(old)
    force, shear, (n_act, d_f, d_d) = results[0]
    empty = contact_forces(
        x, v, mass, en, mat, table, np.zeros((0, 2), np.int64), np.zeros((0, 2)), 1e-3, force
    )
    assert empty == (0, 0.0, 0.0)
    assert n_act > 200 and d_f >= 0.0 and d_d >= 0.0
    np.testing.assert_allclose(force.sum(axis=0), 0.0, atol=1e-10 * np.abs(force).max())
    for f2, s2, out2 in results[1:]:
        np.testing.assert_array_equal(f2, force)
        np.testing.assert_array_equal(s2, shear)
        assert out2 == (n_act, d_f, d_d)


def test_unchecked_path_with_reused_buffers_matches_contact_forces():
    # The explicit loop calls add_contact_forces with one ContactBuffers for the whole run,
    # while the pair list grows and shrinks: same floating-point operations as the checked
    # contact_forces, so the results must be bit-identical (forces, split parts, history,
    # returns), whatever the buffers held before.
    rng = np.random.default_rng(17)
    n_el = 200
    x, en, v, mass, mat, table = random_pile(rng, n_el, 7.0)
    buffers = ContactBuffers()
    for margin in (0.0, 0.2, 0.05, 0.3):
        pairs = find_contact_pairs(x, en, np.arange(4 * n_el), margin)
        shear0 = rng.normal(size=(pairs.shape[0], 2))
        outs = []
        for hot in (False, True):
            force = np.zeros_like(x)
            split = np.zeros((2, *x.shape))
            shear = shear0.copy()
            args = (x, v, mass, en, mat, table, pairs, shear, 1e-3, force, split)
            ret = add_contact_forces(*args, buffers) if hot else contact_forces(*args)
            outs.append((force, split, shear, ret))
        for a, b in zip(outs[0][:3], outs[1][:3]):
            np.testing.assert_array_equal(a, b)
        assert outs[0][3] == outs[1][3] and outs[0][3][0] > 0


# ---------------------------------------------------------------------------------------
# Broad phase, history, bad input
# ---------------------------------------------------------------------------------------
def _brute_force_pairs(x, en, groups, margin):
    xe = x[en]
    lo = xe.min(axis=1) - margin
    hi = xe.max(axis=1) + margin
    ov = (
        (lo[:, None, 0] <= hi[None, :, 0])
        & (lo[None, :, 0] <= hi[:, None, 0])
        & (lo[:, None, 1] <= hi[None, :, 1])
        & (lo[None, :, 1] <= hi[:, None, 1])
    )
    i, j = np.nonzero(np.triu(ov, k=1))
    g = groups[en]
    tied = (g[i][:, :, None] == g[j][:, None, :]).any(axis=(1, 2))
    return np.stack([i[~tied], j[~tied]], axis=1)


def test_broad_phase_matches_brute_force_quads():
    # 3000 randomly placed and rotated quads of mixed sizes plus two oversized rigid blocks
    # (ground and wall): the grid must return exactly the brute-force pair list, sorted,
    # with pairs that share a tie group removed.  Integer output: exact equality.
    rng = np.random.default_rng(11)
    n_el = 3000
    polys = [
        rotated_square(*rng.uniform(0, 60, 2), rng.uniform(0.3, 1.4), rng.uniform(0, np.pi))
        for _ in range(n_el)
    ]
    polys.append(np.array([[-1.0, -2.0], [61.0, -2.0], [61.0, 0.3], [-1.0, 0.3]]))
    polys.append(np.array([[59.0, -2.0], [62.0, -2.0], [62.0, 61.0], [59.0, 61.0]]))
    x = np.concatenate(polys)
    en = np.arange(x.shape[0], dtype=np.int64).reshape(-1, 4)
    groups = np.arange(x.shape[0], dtype=np.int64)
    margin = 0.05
    untied = _brute_force_pairs(x, en, groups, margin)
    # tie 200 overlapping pairs at one node: they must disappear from the candidates
    tie = untied[rng.choice(untied.shape[0], 200, replace=False)]
    groups[en[tie[:, 1], 0]] = groups[en[tie[:, 0], 2]]
    expected = _brute_force_pairs(x, en, groups, margin)
    assert expected.shape[0] < untied.shape[0] - 150
    pairs = find_contact_pairs(x, en, groups, margin)
    assert pairs.dtype == np.int64
    np.testing.assert_array_equal(pairs, expected)  # nonzero(triu) order = lexicographic


def test_broad_phase_matches_brute_force_sparse_triangles():
    # T3 elements in a few far-apart clusters (the grid is coarsened to stay O(n) cells),
    # zero margin: exact agreement with brute force.
    rng = np.random.default_rng(5)
    centres = np.array([[0.0, 0.0], [5e3, 0.0], [0.0, 8e3], [7e3, 9e3]])
    polys = []
    for _ in range(800):
        c = centres[rng.integers(4)] + rng.uniform(0, 15, 2)
        polys.append(c + rng.uniform(-0.6, 0.6, (3, 2)))
    x = np.concatenate(polys)
    en = np.arange(x.shape[0], dtype=np.int64).reshape(-1, 3)
    groups = np.arange(x.shape[0])
    pairs = find_contact_pairs(x, en, groups, 0.0)
    np.testing.assert_array_equal(pairs, _brute_force_pairs(x, en, groups, 0.0))
    assert pairs.shape[0] > 100


def test_broad_phase_matches_brute_force_on_a_graded_tied_mesh_with_hinges():
    # A conforming quad mesh of 0.05 m cells graded outwards to about 1 m (as a mesh refined
    # under a footing), coincident nodes tied except along two lines where the mesh has
    # failed; hinges=True keeps pairs tied at one vertex. More than 64 elements are 4x the
    # median, so some large ones go through the grid and cover many cells. Exact agreement
    # with brute force.
    grow = 0.05 * 1.3 ** np.arange(1, 13)
    xs = np.cumsum(np.concatenate([[0.0], np.full(40, 0.05), grow]))
    ys = np.cumsum(np.concatenate([[0.0], np.full(30, 0.05), grow[:10]]))
    nx, ny = xs.size - 1, ys.size - 1
    gx, gy = np.meshgrid(xs, ys)
    verts = np.stack([gx.ravel(), gy.ravel()], axis=1)
    vid = np.arange(verts.shape[0]).reshape(ys.size, xs.size)
    cells = np.array([[vid[j, i], vid[j, i + 1], vid[j + 1, i + 1], vid[j + 1, i]]
                      for j in range(ny) for i in range(nx)])
    x = verts[cells].reshape(-1, 2)  # elements own their nodes
    en = np.arange(x.shape[0], dtype=np.int64).reshape(-1, 4)
    groups = cells.ravel().astype(np.int64)  # coincident nodes tied
    cut = (x[:, 0] > xs[12] - 1e-9) & (x[:, 0] < xs[12] + 1e-9)
    cut |= (x[:, 1] > ys[9] - 1e-9) & (x[:, 1] < ys[9] + 1e-9)
    groups[cut] = x.shape[0] + np.arange(int(cut.sum()))  # failed along two lines
    boxes = np.concatenate([x[en].min(axis=1), x[en].max(axis=1)], axis=1)
    size = (boxes[:, 2:] - boxes[:, :2]).max(axis=1)
    assert (size > 4 * np.median(size)).sum() > 64
    for margin in (0.0, 0.02):
        lo = boxes[:, :2] - margin
        hi = boxes[:, 2:] + margin
        ov = np.triu((lo[:, None] <= hi[None]).all(-1) & (lo[None] <= hi[:, None]).all(-1), 1)
        i, j = np.nonzero(ov)
        g = groups[en]
        shared = np.array([len(set(g[a]) & set(g[b])) for a, b in zip(i, j)])
        expected = np.stack([i[shared <= 1], j[shared <= 1]], axis=1)
        pairs = find_contact_pairs(x, en, groups, margin, hinges=True)
        np.testing.assert_array_equal(pairs, expected)
        assert pairs.shape[0] > en.shape[0]


def test_carry_contact_history():
    old_pairs = np.array([[0, 1], [0, 3], [2, 5], [4, 7]])
    old_shear = np.array([[1.0, 2.0], [3.0, 4.0], [5.0, 6.0], [7.0, 8.0]])
    new_pairs = np.array([[0, 1], [1, 2], [2, 5], [3, 4], [4, 7]])
    new = carry_contact_history(old_pairs, old_shear, new_pairs)
    np.testing.assert_array_equal(new, [[1.0, 2.0], [0.0, 0.0], [5.0, 6.0], [0.0, 0.0], [7.0, 8.0]])
    assert carry_contact_history(old_pairs, old_shear, np.zeros((0, 2))).shape == (0, 2)
    np.testing.assert_array_equal(
        carry_contact_history(np.zeros((0, 2)), np.zeros((0, 2)), new_pairs), 0.0
    )


def test_bad_input_clear_errors():
    x = np.concatenate([square(0, 0), square(0.5, 0.5)])
    en = np.arange(8).reshape(2, 4)
    groups = np.arange(8)
    bad = x.copy()
    bad[5, 1] = np.nan
    with pytest.raises(ValueError, match="x .*NaN.*node 5"):
        find_contact_pairs(bad, en, groups, 0.1)
    with pytest.raises(ValueError, match="escaped the contact grid"):
        find_contact_pairs(x, en, groups, 0.1, bounds=(-1.0, -1.0, 1.2, 1.2))
    with pytest.raises(ValueError, match="margin"):
        find_contact_pairs(x, en, groups, -0.1)
    with pytest.raises(ValueError, match="poly_b contains NaN"):
        overlap(square(0, 0), bad[4:])
    xx, en2, mass, mat, table, pairs = two_body(square(0, 0), square(0.5, 0.5))
    table[0, 0] = -1.0
    with pytest.raises(ValueError, match="contact_table"):
        run_pair(xx, np.zeros_like(xx), mass, en2, mat, table, pairs, np.zeros((1, 2)))
    table[0, 0] = 1e5
    table[0, 4] = np.nan
    with pytest.raises(ValueError, match=r"contact_table entries \[k_n, k_t, mu, zeta, c\]"):
        run_pair(xx, np.zeros_like(xx), mass, en2, mat, table, pairs, np.zeros((1, 2)))
    table[0, 4] = 0.0
    with pytest.raises(ValueError, match="x .*NaN"):
        run_pair(bad, np.zeros_like(xx), mass, en2, mat, table, pairs, np.zeros((1, 2)))
    with pytest.raises(ValueError, match="dt"):
        run_pair(xx, np.zeros_like(xx), mass, en2, mat, table, pairs, np.zeros((1, 2)), -1.0)
    # arrays updated in place must be writeable float64; index arrays integers in range
    args = (xx, np.zeros_like(xx), mass, en2, mat, table, pairs)
    with pytest.raises(ValueError, match="force is updated in place.*float64"):
        contact_forces(*args, np.zeros((1, 2)), 1e-3, np.zeros(xx.shape, dtype=np.int64))
    frozen = np.zeros((1, 2))
    frozen.flags.writeable = False
    with pytest.raises(ValueError, match="shear is updated in place"):
        contact_forces(*args, frozen, 1e-3, np.zeros_like(xx))
    with pytest.raises(ValueError, match=r"shear must have shape \(1, 2\)"):
        contact_forces(*args, np.zeros((2, 2)), 1e-3, np.zeros_like(xx))
    with pytest.raises(ValueError, match="split_force must have shape"):
        contact_forces(*args, np.zeros((1, 2)), 1e-3, np.zeros_like(xx), np.zeros((2, 2)))
    with pytest.raises(ValueError, match="pairs must hold integer"):
        run_pair(xx, np.zeros_like(xx), mass, en2, mat, table, pairs.astype(float),
                 np.zeros((1, 2)))
    with pytest.raises(ValueError, match="pairs must index elements 0..1"):
        run_pair(xx, np.zeros_like(xx), mass, en2, mat, table, pairs + 1, np.zeros((1, 2)))
    with pytest.raises(ValueError, match="element_material must index"):
        run_pair(xx, np.zeros_like(xx), mass, en2, mat + 1, table, pairs, np.zeros((1, 2)))
    with pytest.raises(ValueError, match="pairs must index elements"):
        contact.contact_energy(xx, en2, mat, table, pairs + 1, np.zeros((1, 2)))


def test_contact_energy_split_forces_and_mid_step_work():
    # B = [0,1]x[-0.01,0.99] on a rigid ground: flat penetration d = 0.01 over L_c = 1, so
    # the stored normal energy is k_n L_c d^2 / 2 = k_n A^2 / (2 L_c) = 5 kJ/m, and a
    # tangential history F_t = 3 kN/m stores F_t^2 / (2 k_t L_c).  Approaching at 0.2 m/s and
    # sliding at 0.1 m/s: the damping part of the force on B is c_n 0.2 along +y and the
    # tangential part is the updated history; the nodal parts sum to those (shape functions
    # sum to one) and A gets the opposite.  Round-off: 1e-12 relative.
    kn, kt, zeta, dt = 1e5, 2e4, 0.3, 1e-3
    ground = np.array([[-2.0, -1.0], [2.0, -1.0], [2.0, 0.0], [-2.0, 0.0]])
    x, en, mass, mat, table, pairs = two_body(ground, square(0, -0.01), kn=kn, kt=kt,
                                              zeta=zeta)
    mass[:4] = np.inf
    shear = np.array([[-3.0, 0.0]])
    u_n, u_t = contact.contact_energy(x, en, mat, table, pairs, shear)
    assert u_n == pytest.approx(kn * 0.01**2 / 2.0, rel=1e-12)
    assert u_t == pytest.approx(3.0**2 / (2.0 * kt * 1.0), rel=1e-12)
    v = np.zeros_like(x)
    v[4:] = [0.1, -0.2]
    split = np.zeros((2, 8, 2))
    force = np.zeros_like(x)
    contact_forces(x, v, mass, en, mat, table, pairs, shear, dt, force, split)
    c_n = 2 * zeta * np.sqrt(kn * 1.0 * 1.0)
    np.testing.assert_allclose(split[0, 4:].sum(axis=0), [0.0, c_n * 0.2], rtol=1e-12,
                               atol=1e-12)
    np.testing.assert_allclose(split[1, 4:].sum(axis=0), shear[0], rtol=1e-12, atol=1e-12)
    assert shear[0, 0] == pytest.approx(-3.0 - kt * 0.1 * dt, rel=1e-12)  # eq 4.9, below cap
    np.testing.assert_allclose(split[:, :4].sum(axis=1), -split[:, 4:].sum(axis=1),
                               atol=1e-12)
    # the total force is elastic + damping + tangential
    np.testing.assert_allclose(force[4:].sum(axis=0),
                               [shear[0, 0], kn * 0.01 + c_n * 0.2], rtol=1e-12)
    # mid-step work: F . (v0 + v1) / 2 dt
    f = np.array([[1.0, 2.0], [0.0, -1.0]])
    v0 = np.array([[1.0, 0.0], [0.0, 1.0]])
    v1 = np.array([[3.0, 0.0], [0.0, 3.0]])
    assert contact.mid_step_work(f, v0, v1, 0.5) == pytest.approx((2.0 - 2.0) * 0.5, abs=1e-15)
    assert contact.mid_step_work(f[:1], v0[:1], v1[:1], 0.5) == pytest.approx(1.0, rel=1e-15)
    with pytest.raises(ValueError, match="same shape"):
        contact.mid_step_work(f, v0[:1], v1, 0.5)


@pytest.mark.parametrize("mu_b, c_b, expected", [
    (0.0, 0.0, 0.0),  # a frictionless, cohesionless side: no strength
    (0.5, 0.0, 0.5 * 1e5 * 0.01),  # a sand's crack on a clay's: the sand's friction is weaker
    (0.5, 300.0, 600.0),  # stronger than the clay's c_u L_c: the clay's
])
def test_the_weaker_sides_strength_governs(mu_b, c_b, expected):
    # B (material 1) slides on a rigid ground of material 0, an undrained clay's crack (mu 0,
    # c 600 kPa): the tangential force settles at min(c_a L_c + mu_a F_n, c_b L_c + mu_b F_n)
    # with L_c = 1 m and F_n = k_n A = 1e5 x 0.01 = 1000 kN/m (flat penetration 0.01 m)
    ground = np.array([[-2.0, -1.0], [2.0, -1.0], [2.0, 0.0], [-2.0, 0.0]])
    x, en, mass, _, _, pairs = two_body(ground, square(0, -0.01))
    table = np.array([[1e5, 2e4, 0.0, 0.0, 600.0], [1e5, 2e4, mu_b, 0.0, c_b]])
    mat = np.array([0, 1], dtype=np.int32)
    mass[:4] = np.inf
    v = np.zeros_like(x)
    v[4:, 0] = 0.1
    shear = np.zeros((1, 2))
    for _ in range(600):  # the spring (2 kN/m a step) reaches every cap below 1200
        run_pair(x, v, mass, en, mat, table, pairs, shear, 1e-3)
    assert -shear[0, 0] == pytest.approx(expected, rel=1e-12, abs=1e-12)


def test_a_four_column_table_is_a_cohesionless_one():
    # contact_forces takes [k_n, k_t, mu, zeta] tables as c = 0: same forces and history
    x, en, mass, mat, table, pairs = two_body(square(0, 0), square(0.5, 0.3))
    v = np.zeros_like(x)
    v[4:, 0] = 0.3
    s4, s5 = np.zeros((1, 2)), np.zeros((1, 2))
    f4, _ = run_pair(x, v, mass, en, mat, table[:, :4], pairs, s4)
    f5, _ = run_pair(x, v, mass, en, mat, table, pairs, s5)
    np.testing.assert_array_equal(f4, f5)
    np.testing.assert_array_equal(s4, s5)


def test_contact_step_works_equal_three_mid_step_works_bit_for_bit():
    """The solver's one-pass ledger works (damping, tangential, all) are the three
    ``mid_step_work`` sums to the last bit (same terms in the same order)."""
    from hybrid.discrete.contact.energy import contact_step_works

    rng = np.random.default_rng(7)
    split, force = rng.normal(size=(2, 50, 2)), rng.normal(size=(50, 2))
    v0, v1 = rng.normal(size=(50, 2)), rng.normal(size=(50, 2))
    works = contact_step_works(split, force, v0, v1, 1.3e-4)
    assert works == tuple(contact.mid_step_work(f, v0, v1, 1.3e-4)
                          for f in (split[0], split[1], force))
