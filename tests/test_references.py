"""Closed-form references (hybrid.references) against published numbers and exact identities."""

import math

import numpy as np
import pytest

from hybrid import references as ref

# Textbook tables print 2 decimals: a value agrees with the table when it rounds to it, i.e.
# within half a unit of the last printed digit (0.005), plus a hair for binary rounding.
TABLE_ROUNDING = 0.005 + 1e-9


def test_c6_prandtl_limit_load():
    """C6 of verification-targets: c = 69 kPa, phi = 20 deg -> c N_c = 1023.6 kPa (1 decimal)."""
    assert ref.prandtl_limit_load(69.0, 20.0) == pytest.approx(1023.6, abs=0.05)


def test_c5_tresca_limit_load():
    """C5: phi = 0, c_u = 50 kPa -> (2 + pi) c_u = 257.1 kPa; N_c(0) is exactly 2 + pi."""
    assert ref.n_c(0.0) == (2.0 + math.pi)
    assert ref.prandtl_limit_load(50.0, 0.0) == pytest.approx(257.1, abs=0.05)
    # the phi -> 0 limit is continuous: N_c(1e-4 deg) differs from 2 + pi by O(phi) ~ 1e-5
    assert ref.n_c(1e-4) == pytest.approx(2.0 + math.pi, rel=1e-5)
    # surcharge term: N_q(0) = 1, so q adds q
    assert ref.prandtl_limit_load(50.0, 0.0, q_surcharge=10.0) == pytest.approx(267.08, abs=0.005)


# Das, Principles of Foundation Engineering (7th ed.), Table 3.3: Prandtl-Reissner N_c, N_q and
# Vesic's N_gamma = 2 (N_q + 1) tan phi.
DAS_TABLE_3_3 = {  # phi: (N_c, N_q, N_gamma)
    0: (5.14, 1.00, 0.00),
    20: (14.83, 6.40, 5.39),
    25: (20.72, 10.66, 10.88),
    30: (30.14, 18.40, 22.40),
    35: (46.12, 33.30, 48.03),
    40: (75.31, 64.20, 109.41),
}


@pytest.mark.parametrize("phi", sorted(DAS_TABLE_3_3))
def test_vesic_factors_against_das_table(phi):
    """N_c, N_q, N_gamma (Vesic) equal the table to its printed 2 decimals (4 digits)."""
    expected = DAS_TABLE_3_3[phi]
    computed = ref.bearing_capacity_factors(phi, "vesic")
    for c, e in zip(computed, expected):
        assert abs(c - e) <= TABLE_ROUNDING, (phi, computed, expected)


# Das, Table 3.1: Terzaghi's N_c, N_q (closed forms) and Kumbhojkar's (1993) N_gamma.
DAS_TABLE_3_1 = {20: (17.69, 7.44, 3.64), 30: (37.16, 22.46, 19.13), 40: (95.66, 81.27, 115.31)}


@pytest.mark.parametrize("phi", sorted(DAS_TABLE_3_1))
def test_terzaghi_factors_against_das_table(phi):
    """Terzaghi's closed-form N_c, N_q reproduce Das Table 3.1 to its 2 decimals."""
    nc, nq, ng = ref.bearing_capacity_factors(phi, "terzaghi")
    assert abs(nc - DAS_TABLE_3_1[phi][0]) <= TABLE_ROUNDING
    assert abs(nq - DAS_TABLE_3_1[phi][1]) <= TABLE_ROUNDING
    assert abs(ng - DAS_TABLE_3_1[phi][2]) <= TABLE_ROUNDING  # table look-up, whole degree


def test_terzaghi_n_gamma_interpolation_and_phi0():
    """Between whole degrees N_gamma is the geometric mean at mid-degree (log-linear)."""
    assert ref.terzaghi_n_c(0.0) == pytest.approx(1.5 * math.pi + 1.0, rel=1e-15)
    assert ref.n_gamma(30.5, "terzaghi") == pytest.approx(math.sqrt(19.13 * 22.65), rel=1e-12)
    assert ref.n_gamma(0.5, "terzaghi") == pytest.approx(0.005, rel=1e-12)
    with pytest.raises(ValueError, match="phi_deg"):
        ref.n_gamma(55.0, "terzaghi")


def test_meyerhof_and_hansen_n_gamma():
    """Meyerhof (N_q - 1) tan 1.4 phi and Hansen 1.5 (N_q - 1) tan phi against Bowles,
    Foundation Analysis and Design (5th ed., 1996), Table 4-4, which prints 1 decimal
    (tolerance half a unit of it): phi = 20: 2.9 / 2.9, phi = 30: 15.7 / 15.1
    (Meyerhof / Hansen)."""
    for phi, meyerhof, hansen in ((20, 2.9, 2.9), (30, 15.7, 15.1)):
        assert abs(ref.n_gamma(phi, "meyerhof") - meyerhof) <= 0.05 + 1e-9, phi
        assert abs(ref.n_gamma(phi, "hansen") - hansen) <= 0.05 + 1e-9, phi
    with pytest.raises(ValueError, match="method"):
        ref.n_gamma(30.0, "bogus")


def test_strip_footing_capacity_sums_terms():
    """c N_c + q N_q + 0.5 gamma B N_gamma with Das 3.3 factors at 30 deg (rounding-level)."""
    qu = ref.strip_footing_capacity(10.0, 30.0, 18.0, 2.0, q=20.0, method="vesic")
    by_table = 10 * 30.14 + 20 * 18.40 + 0.5 * 18 * 2 * 22.40
    # the table rounds each factor by <= 0.005: bound of the difference 0.005 (10 + 20 + 18)
    assert abs(qu - by_table) <= 0.005 * (10 + 20 + 18)
    est = ref.strip_footing_estimates(69.0, 20.0, 20.0, 1.2)
    assert est["Prandtl (weightless)"] == pytest.approx(1023.595, abs=1e-3)
    # with weight every estimate exceeds the weightless Prandtl load by 0.5 gamma B N_gamma
    for name in ("Terzaghi", "Meyerhof", "Vesic", "Hansen"):
        assert est[name] > est["Prandtl (weightless)"]


def test_rankine_c8():
    """C8: gamma = 16.5, H = 10 m, phi = 30: K_a = 1/3, P_a = 275; K_p = 3, P_p = 2475 kN/m."""
    assert ref.rankine_ka(30.0) == pytest.approx(1 / 3, rel=1e-14)
    assert ref.rankine_kp(30.0) == pytest.approx(3.0, rel=1e-14)
    assert ref.rankine_active_thrust(16.5, 10.0, 30.0) == pytest.approx(275.0, rel=1e-14)
    assert ref.rankine_passive_thrust(16.5, 10.0, 30.0) == pytest.approx(2475.0, rel=1e-14)


def test_rankine_cohesion_and_tension_crack():
    """c > 0: passive 0.5 K_p g H^2 + 2 c sqrt(K_p) H; active with and without the crack."""
    g, H, phi, c = 18.0, 6.0, 30.0, 10.0
    ka, kp = 1 / 3, 3.0
    assert ref.rankine_passive_thrust(g, H, phi, c) == pytest.approx(
        0.5 * kp * g * H**2 + 2 * c * math.sqrt(kp) * H, rel=1e-13)
    raw = 0.5 * ka * g * H**2 - 2 * c * math.sqrt(ka) * H
    assert ref.rankine_active_thrust(g, H, phi, c, tension_crack=False) == pytest.approx(
        raw, rel=1e-13)
    zc = 2 * c / (g * math.sqrt(ka))
    assert ref.tension_crack_depth(c, phi, g) == pytest.approx(zc, rel=1e-14)
    assert ref.rankine_active_thrust(g, H, phi, c) == pytest.approx(
        0.5 * ka * g * (H - zc) ** 2, rel=1e-13)
    # a wall shorter than the crack depth carries nothing
    assert ref.rankine_active_thrust(g, 0.5 * zc, phi, c) == 0.0


def test_k0():
    """K0 = nu/(1 - nu) (0.3 -> 3/7) and Jaky 1 - sin phi (30 deg -> 0.5)."""
    assert ref.k0_elastic(0.3) == pytest.approx(3 / 7, rel=1e-15)
    assert ref.k0_jaky(30.0) == pytest.approx(0.5, rel=1e-15)
    with pytest.raises(ValueError, match="nu"):
        ref.k0_elastic(0.5)


def test_invalid_inputs_name_the_parameter():
    with pytest.raises(ValueError, match="phi_deg"):
        ref.n_q(90.0)
    with pytest.raises(ValueError, match="phi_deg"):
        ref.rankine_ka(-1.0)
    with pytest.raises(ValueError, match="B"):
        ref.strip_footing_capacity(10.0, 30.0, 18.0, 0.0)
    with pytest.raises(ValueError, match="^c "):
        ref.prandtl_limit_load(-1.0, 20.0)
    with pytest.raises(ValueError, match="z"):
        ref.flamant_strip_stress(100.0, 2.0, 0.0, 0.0)


# --- strip load ---------------------------------------------------------------------------------

Q, WIDTH = 100.0, 12.0


def test_flamant_centreline_reduces():
    """On the centreline delta = -alpha/2, so sigma_z = -(q/pi)(alpha + sin alpha) (P&D)."""
    z = np.linspace(0.1, 30.0, 50)
    alpha = 2 * np.arctan(WIDTH / 2 / z)
    s = ref.flamant_strip_stress(Q, WIDTH, np.zeros_like(z), z)
    np.testing.assert_allclose(s.sigma_yy, -(Q / np.pi) * (alpha + np.sin(alpha)), rtol=1e-14)
    np.testing.assert_allclose(s.sigma_xx, -(Q / np.pi) * (alpha - np.sin(alpha)), rtol=1e-13)
    np.testing.assert_allclose(s.sigma_xy, 0.0, atol=1e-13 * Q)
    np.testing.assert_allclose(ref.flamant_centreline(Q, WIDTH / 2, z), s.sigma_yy, rtol=1e-15)


def test_flamant_symmetry():
    """sigma_xx, sigma_yy even in x and sigma_xy odd (load symmetric about x = 0), to rounding."""
    rng = np.random.default_rng(1)
    x, z = rng.uniform(0, 40, 200), rng.uniform(0.01, 40, 200)
    a, b = ref.flamant_strip_stress(Q, WIDTH, x, z), ref.flamant_strip_stress(Q, WIDTH, -x, z)
    np.testing.assert_allclose(a.sigma_yy, b.sigma_yy, rtol=1e-12, atol=1e-12 * Q)
    np.testing.assert_allclose(a.sigma_xx, b.sigma_xx, rtol=1e-12, atol=1e-12 * Q)
    np.testing.assert_allclose(a.sigma_xy, -b.sigma_xy, rtol=1e-12, atol=1e-12 * Q)


def test_flamant_surface_and_far_field():
    """Just below the surface: -q under the strip, 0 beside it; far away: Flamant's line load
    P = q B, sigma_z = -(2P/pi) z^3/r^4, with relative difference O((B/r)^2) (< 1e-6 at
    r = 1e4 B)."""
    eps = 1e-9
    s = ref.flamant_strip_stress(Q, WIDTH, np.array([0.0, 3.0, 10.0]), np.full(3, eps))
    np.testing.assert_allclose(s.sigma_yy, [-Q, -Q, 0.0], atol=1e-8 * Q)
    np.testing.assert_allclose(s.sigma_xx, [-Q, -Q, 0.0], atol=1e-8 * Q)
    r, theta = 1e4 * WIDTH, np.linspace(-1.2, 1.2, 9)
    x, z = r * np.sin(theta), r * np.cos(theta)
    P = Q * WIDTH
    far = ref.flamant_strip_stress(Q, WIDTH, x, z)
    line = -(2 * P / np.pi) * z**3 / r**4
    np.testing.assert_allclose(far.sigma_yy, line, rtol=1e-6)
    np.testing.assert_allclose(far.sigma_xy, (2 * P / np.pi) * x * z**2 / r**4, rtol=1e-6)


@pytest.mark.parametrize("depth", [0.5, 6.0, 40.0])
def test_flamant_equilibrium(depth):
    """Integral of sigma_z over a horizontal line = -q B (vertical equilibrium), of sigma_xy = 0
    and of x sigma_z = 0 (moment), numerically to 1e-6 of q B.

    x = z tan(t) maps the line onto (-pi/2, pi/2) where the integrand is smooth; 2000-point
    Gauss-Legendre per sub-interval (breaks at the strip edges) is far below 1e-6.
    """
    edges = np.arctan(np.array([-WIDTH / 2, WIDTH / 2]) / depth)
    breaks = np.concatenate([[-np.pi / 2], edges, [np.pi / 2]])
    t_ref, w_ref = np.polynomial.legendre.leggauss(2000)
    fz = fxy = mz = 0.0
    for lo, hi in zip(breaks[:-1], breaks[1:]):
        t = 0.5 * (hi - lo) * t_ref + 0.5 * (hi + lo)
        w = 0.5 * (hi - lo) * w_ref
        x = depth * np.tan(t)
        jac = depth / np.cos(t) ** 2
        s = ref.flamant_strip_stress(Q, WIDTH, x, np.full_like(x, depth))
        fz += np.sum(w * jac * s.sigma_yy)
        fxy += np.sum(w * jac * s.sigma_xy)
        mz += np.sum(w * jac * x * s.sigma_yy)
    assert fz == pytest.approx(-Q * WIDTH, rel=1e-6)
    assert abs(fxy) < 1e-6 * Q * WIDTH
    assert abs(mz) < 1e-6 * Q * WIDTH * WIDTH


def test_oedometer():
    """C2: sigma_v = -gamma z, sigma_h = K0 sigma_v; top settlement gamma H^2 / (2 M)."""
    sv, sh = ref.oedometer_stress(19.0, 0.3, np.array([0.0, 5.0, 10.0]))
    np.testing.assert_allclose(sv, [0.0, -95.0, -190.0], rtol=1e-15)
    np.testing.assert_allclose(sh, np.array([0.0, -95.0, -190.0]) * 3 / 7, rtol=1e-15)
    M = 20_000.0 * 0.7 / (1.3 * 0.4)
    assert ref.oedometric_modulus(20_000.0, 0.3) == pytest.approx(M, rel=1e-15)
    assert ref.oedometer_settlement(19.0, 10.0, 20_000.0, 0.3) == pytest.approx(
        19.0 * 100 / (2 * M), rel=1e-15)


# --- slope stability: methods of slices on circles -------------------------------------------

# Fredlund & Krahn (1977), Can. Geotech. J. 14(3), 429-439, case 1: a 2:1 slope 40 ft high,
# c' = 600 psf, phi' = 20 deg, gamma = 120 pcf, dry; the circle centred at (120, 90) ft with an
# 80 ft radius (coordinates of the reproduction in pyBIMstab: crest at y = 60 from x = 0 to 60,
# toe at (140, 20), toe ground to x = 170). Published: ordinary 1.928, Bishop simplified 2.080
# (MacSlope 1.929 / 2.078). Any consistent units work (F is a ratio): ft, psf, pcf here.
FREDLUND_KRAHN = np.array([[0.0, 60.0], [60.0, 60.0], [140.0, 20.0], [170.0, 20.0]])


def test_fredlund_krahn_case_1():
    """Bishop 2.080 and ordinary 1.928 within 0.5 %: the published programs differ by 0.1 %
    between themselves (slices, exit handling); 60 slices here."""
    soil = ref.uniform_soil(120.0, 600.0, 20.0)
    bishop = ref.circle_factor(FREDLUND_KRAHN, soil, (120.0, 90.0), 80.0)
    ordinary = ref.circle_factor(FREDLUND_KRAHN, soil, (120.0, 90.0), 80.0, method="ordinary")
    assert bishop == pytest.approx(2.080, rel=0.005)
    assert ordinary == pytest.approx(1.928, rel=0.005)
    assert ordinary < bishop  # Fellenius neglects all interslice forces: conservative here


def _sliding_mass(surface, centre, radius, n=20001):
    """Area [m2] and centroid x [m] of the mass above the arc (exact up to 1e-8)."""
    xc, yc = centre
    x = np.linspace(xc - radius, xc + radius, n)
    arc = yc - np.sqrt(np.maximum(radius**2 - (x - xc) ** 2, 0.0))
    top = np.interp(x, *surface.T)
    h = np.maximum(top - arc, 0.0)
    dx = x[1] - x[0]  # uniform grid: the midpoint sums of the strips
    area = float(np.sum(h) * dx)
    return area, float(np.sum(h * x) * dx) / area, x[h > 0]


def test_undrained_circle_equals_exact_moments():
    """phi = 0: every moment method gives F = c R^2 theta / (W |x_G - x_c|) exactly; slices
    agree to 0.1 % (60 slices: weights by the midpoint rule)."""
    surface = np.array([[0.0, 0.0], [20.0, 10.0], [40.0, 10.0]])
    centre, R, c, gamma = (8.0, 24.0), 24.5, 30.0, 18.0
    area, xg, inside = _sliding_mass(surface, centre, R)
    x0, x1 = inside.min(), inside.max()
    theta = abs(math.asin((x1 - centre[0]) / R) - math.asin((x0 - centre[0]) / R))
    exact = c * R**2 * theta / (gamma * area * abs(xg - centre[0]))
    for method in ("bishop", "ordinary"):
        F = ref.circle_factor(surface, ref.uniform_soil(gamma, c, 0.0), centre, R,
                              method=method)
        assert F == pytest.approx(exact, rel=1e-3)


def test_griffiths_lane_critical_circle():
    """Bishop & Morgenstern (1960) charts give 1.38 for c'/(gamma H) = 0.05, phi' = 20 deg,
    2:1, firm base at toe level (D = 1): the search finds it within 1 % (two decimals of the
    chart), on a circle that keeps above the base and cuts the face and the crest."""
    surface = np.array([[0.0, 0.0], [20.0, 10.0], [32.0, 10.0]])
    circle = ref.critical_circle(surface, ref.uniform_soil(20.0, 10.0, 20.0), floor=0.0)
    assert circle.factor == pytest.approx(1.38, rel=0.01)
    arc = circle.arc()
    assert arc[:, 1].min() >= -1e-9  # never below the rigid base
    assert 0.0 <= circle.entry < 20.0 < circle.exit <= 32.0
    # the same circle evaluated alone gives the same F (the search's slices leave out the
    # surface's vertices: 1e-4); the search found a minimum: moved circles are no better
    again = ref.circle_factor(surface, ref.uniform_soil(20.0, 10.0, 20.0), circle.centre,
                              circle.radius, floor=0.0)
    assert again == pytest.approx(circle.factor, rel=1e-4)
    for dx, dy, dr in ((0.5, 0, 0), (0, 0.5, 0), (0, 0, 0.5), (0, 0, -0.5)):
        moved = ref.circle_factor(surface, ref.uniform_soil(20.0, 10.0, 20.0),
                                  (circle.centre[0] + dx, circle.centre[1] + dy),
                                  circle.radius + dr, floor=0.0)
        assert moved >= again * (1.0 - 1e-4)


def test_slip_circle_inputs():
    soil = ref.uniform_soil(20.0, 10.0, 20.0)
    with pytest.raises(ValueError, match="strictly increasing"):
        ref.circle_factor(np.array([[0.0, 0.0], [0.0, 1.0]]), soil, (0.0, 5.0), 5.0)
    with pytest.raises(ValueError, match="radius > 0"):
        ref.circle_factor(FREDLUND_KRAHN, soil, (120.0, 90.0), -1.0)
    with pytest.raises(ValueError, match="method"):
        ref.circle_factor(FREDLUND_KRAHN, soil, (120.0, 90.0), 80.0, method="spencer")
    # a circle in the air, or through the floor, is not a slip surface
    assert ref.circle_factor(FREDLUND_KRAHN, soil, (120.0, 200.0), 10.0) == math.inf
    assert ref.circle_factor(FREDLUND_KRAHN, soil, (120.0, 90.0), 80.0, floor=15.0) == math.inf


def test_critical_circle_of_a_berm_does_not_depend_on_the_grid():
    """A 3 m berm at 1:1 in front of a 1:3 slope: the critical circle is a small one at the
    berm toe, found the same (to 1e-6) whatever the search grid: entries at the surface's
    corners and chords on a log scale catch small circles."""
    surface = np.array([[-40.0, 0.0], [-20.0, 0.0], [-17.0, 3.0], [-10.0, 3.0], [20.0, 13.0],
                        [40.0, 13.0]])
    soil = ref.uniform_soil(20.0, 5.0, 30.0)
    found = [ref.critical_circle(surface, soil, floor=-10.0, grid=g) for g in (24, 40, 60)]
    assert found[0].entry == pytest.approx(-20.0, abs=0.05)  # through the berm toe
    assert found[0].exit < -10.0  # out on the berm top: a berm slip, not the main slope
    for circle in found[1:]:
        assert circle.factor == pytest.approx(found[0].factor, rel=1e-6)


def test_slip_circle_as_dict():
    circle = ref.SlipCircle(1.25, (3.0, 12.0), 10.0, -4.0, 9.0)
    assert circle.as_dict() == {"F": 1.25, "centre_m": [3.0, 12.0], "radius_m": 10.0,
                                "entry_x_m": -4.0, "exit_x_m": 9.0}


def test_friction_ratio():
    """tan(phi_r) / tan(phi_p): 1 at equal angles, 1/3 for tan 30 against tan 60; a peak of
    zero or an angle outside [0, 90) deg is refused."""
    assert ref.friction_ratio(25.0, 25.0) == pytest.approx(1.0, rel=1e-15)
    assert ref.friction_ratio(30.0, 60.0) == pytest.approx(1 / 3, rel=1e-14)
    assert ref.friction_ratio(0.0, 20.0) == 0.0
    with pytest.raises(ValueError, match="phi_peak_deg"):
        ref.friction_ratio(10.0, 0.0)
    with pytest.raises(ValueError, match="phi_residual_deg"):
        ref.friction_ratio(-5.0, 20.0)


def test_band_middle():
    """The middle of a published range is the value its checks compare with."""
    band = ref.Band("a range", 400.0, 450.0, 200.5, 200.5)
    assert band.middle == 425.0
    assert [b.middle for b in ref.CARSINGTON_CORE_DISPLACEMENT[:2]] == [150.0, 425.0]


def test_carsington_tables_as_parameters():
    """Tables 6.3 and 6.2 as checked case parameters: the published values by default, an
    override checked as any case parameter's (a number, finite)."""
    from hybrid.parameters import ParameterError

    t63, t62 = ref.CarsingtonTable63(), ref.CarsingtonTable62()
    assert (t63.core_cu, t63.yellow_clay_cu, t63.fill_c, t63.fill_phi) == (52.0, 15.0, 13.5, 24.0)
    assert (t62.yellow_clay_residual_phi, t62.core_residual_phi) == (12.0, 13.0)
    assert ref.CarsingtonTable63(core_cu=40.0).core_cu == 40.0
    with pytest.raises(ParameterError, match="core_cu"):
        ref.CarsingtonTable63(core_cu=math.inf)
