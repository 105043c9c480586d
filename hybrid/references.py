"""Closed-form references the verification cases are checked against.

Pure functions, SI units (m, kPa, kN/m, kN/m3), angles in degrees at the interface.
Sign convention of the package: **tension positive, compression negative**. The bearing
capacities, earth-pressure thrusts and coefficients below are magnitudes (positive numbers,
as in the textbooks); the stress fields (strip load, oedometer) are signed, tension positive.

Sources
    Prandtl (1920) / Reissner (1924): N_q, N_c. Terzaghi (1943), Theoretical Soil Mechanics:
    N_q, N_c of the rough-base mechanism. Kumbhojkar (1993), J. Geotech. Eng. 119(3), 575-582:
    Terzaghi's N_gamma, as tabulated in B. M. Das, Principles of Foundation Engineering
    (7th ed., 2011), Table 3.1. Meyerhof (1963), Can. Geotech. J. 1(1); Vesic (1973),
    J. Soil Mech. Found. Div. 99(SM1); Brinch Hansen (1970), Danish Geotech. Inst. Bull. 28.
    Rankine (1857); Jaky (1944). Poulos & Davis (1974), Elastic Solutions for Soil and Rock
    Mechanics, section 2.4 / eq. 3.4 (uniform strip load, by integration of Flamant's line
    load). Fellenius (1936) and Bishop (1955), Geotechnique 5(1), 7-17: the ordinary and the
    simplified methods of slices on circular slip surfaces; Whitman & Bailey (1967), J. Soil
    Mech. Found. Div. 93(SM4): the m_alpha >= 0.2 rule.
    Granular column collapse (plane strain): Lube, Huppert, Sparks & Freundt (2005), Phys. Rev.
    E 72, 041301; arXiv:1512.05180 (2015), "Failure mechanism of true 2D granular flows"
    (aluminium rods); Bui, Fukagawa, Sako & Ohno (2008), Int. J. Numer. Anal. Meth. Geomech.
    32(12), 1537-1570 (the aluminium-bar experiment: geometry and material). See the section
    "granular column collapse" for what was read where and what is unverified.
    Carsington Dam, chainage 725: G. S. Bala (2008), thesis, chapter 6 (6.2.5, 6.3, 6.3.1.2,
    Figure 6.19); A. W. Skempton (1985); Z. Chen, N. R. Morgenstern & D. H. Chan (1992),
    Canadian Geotechnical Journal. See the section "Carsington Dam".
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, NamedTuple

import numpy as np

from hybrid.parameters import CaseParameters

__all__ = [
    "BEARING_METHODS",
    "StripStress",
    "bearing_capacity_factors",
    "n_c",
    "n_q",
    "n_gamma",
    "terzaghi_n_c",
    "terzaghi_n_q",
    "prandtl_limit_load",
    "strip_footing_capacity",
    "strip_footing_estimates",
    "rankine_ka",
    "rankine_kp",
    "rankine_active_thrust",
    "rankine_passive_thrust",
    "tension_crack_depth",
    "k0_elastic",
    "k0_jaky",
    "friction_ratio",
    "strip_load_angles",
    "flamant_strip_stress",
    "flamant_centreline",
    "oedometric_modulus",
    "oedometer_stress",
    "oedometer_settlement",
    "Soil",
    "SlipCircle",
    "uniform_soil",
    "circle_factor",
    "critical_circle",
    "LUBE2005_LINEAR_MAX",
    "LUBE2005_POWER_MIN",
    "LUBE2005_HEIGHT_BREAK",
    "RODS2015_BREAK",
    "RODS2015_RUNOUT_BREAK",
    "granular_runout_lube2005",
    "granular_final_height_lube2005",
    "granular_runout_rods2015",
    "granular_final_height_rods2015",
    "CollapseExperiment",
    "bui2008_collapse",
    "Band",
    "CarsingtonTable63",
    "CarsingtonTable62",
    "CARSINGTON_FAILURE_FILL_LEVEL",
    "CARSINGTON_FOS",
    "CARSINGTON_CORE_DISPLACEMENT",
    "CARSINGTON_REPORT_LEVELS",
    "CARSINGTON_POST_FAILURE",
]

BEARING_METHODS = ("terzaghi", "meyerhof", "vesic", "hansen")

# Terzaghi's N_gamma by Kumbhojkar (1993), phi = 0, 1, ..., 50 degrees (Das, Principles of
# Foundation Engineering, Table 3.1). Terzaghi gave N_gamma only as a chart; this table is the
# usual numerical reproduction. Between whole degrees it is interpolated linearly in log.
_TERZAGHI_N_GAMMA = np.array([
    0.00, 0.01, 0.04, 0.06, 0.10, 0.14, 0.20, 0.27, 0.35, 0.44,
    0.56, 0.69, 0.85, 1.04, 1.26, 1.52, 1.82, 2.18, 2.59, 3.07,
    3.64, 4.31, 5.09, 6.00, 7.08, 8.34, 9.84, 11.60, 13.70, 16.18,
    19.13, 22.65, 26.87, 31.94, 38.04, 45.41, 54.36, 65.27, 78.61, 95.03,
    115.31, 140.51, 171.99, 211.56, 261.60, 325.34, 407.11, 512.84, 650.67, 831.99,
    1072.80,
])


def _phi_rad(phi_deg: float, name: str = "phi_deg", upper: float = 90.0) -> float:
    phi = float(phi_deg)
    if not math.isfinite(phi) or phi < 0.0 or phi >= upper:
        raise ValueError(f"{name} = {phi_deg!r} deg is outside [0, {upper:g}): give the friction "
                         "angle in degrees")
    return math.radians(phi)


def _non_negative(value: float, name: str, unit: str) -> float:
    value = float(value)
    if not math.isfinite(value) or value < 0.0:
        raise ValueError(f"{name} = {value!r} {unit} must be >= 0")
    return value


def _positive(value: float, name: str, unit: str) -> float:
    value = float(value)
    if not math.isfinite(value) or value <= 0.0:
        raise ValueError(f"{name} = {value!r} {unit} must be > 0")
    return value


# --- bearing capacity ------------------------------------------------------------------------

def n_q(phi_deg: float) -> float:
    """Prandtl-Reissner N_q = e^(pi tan phi) tan^2(45 deg + phi/2) (smooth or rough base)."""
    phi = _phi_rad(phi_deg)
    return math.exp(math.pi * math.tan(phi)) * math.tan(math.pi / 4 + phi / 2) ** 2


def n_c(phi_deg: float) -> float:
    """Prandtl N_c = (N_q - 1) cot phi; its limit at phi = 0 is 2 + pi (Tresca)."""
    phi = _phi_rad(phi_deg)
    if phi < 1e-7:  # (N_q - 1) cot phi = 2 + pi + O(phi): avoid 0/0
        return 2.0 + math.pi
    return (n_q(phi_deg) - 1.0) / math.tan(phi)


def terzaghi_n_q(phi_deg: float) -> float:
    """Terzaghi (1943) N_q = e^(2 (3 pi/4 - phi/2) tan phi) / (2 cos^2(45 deg + phi/2))."""
    phi = _phi_rad(phi_deg)
    return (math.exp(2.0 * (0.75 * math.pi - phi / 2) * math.tan(phi))
            / (2.0 * math.cos(math.pi / 4 + phi / 2) ** 2))


def terzaghi_n_c(phi_deg: float) -> float:
    """Terzaghi (1943) N_c = (N_q - 1) cot phi, -> 1.5 pi + 1 = 5.71 at phi = 0."""
    phi = _phi_rad(phi_deg)
    if phi < 1e-7:
        return 1.5 * math.pi + 1.0
    return (terzaghi_n_q(phi_deg) - 1.0) / math.tan(phi)


def n_gamma(phi_deg: float, method: str = "vesic") -> float:
    """Self-weight factor N_gamma by ``method``.

    - ``"terzaghi"``: Kumbhojkar's (1993) numerical values of Terzaghi's mechanism (Das,
      Table 3.1), 0 <= phi <= 50 deg, log-linear between whole degrees.
    - ``"meyerhof"``: Meyerhof (1963), (N_q - 1) tan(1.4 phi).
    - ``"vesic"``: Vesic (1973), 2 (N_q + 1) tan phi.
    - ``"hansen"``: Brinch Hansen (1970), 1.5 (N_q - 1) tan phi.
    """
    phi = _phi_rad(phi_deg)
    if method == "terzaghi":
        if phi_deg > 50.0:
            raise ValueError(f"phi_deg = {phi_deg} deg: the Terzaghi N_gamma table stops at 50 "
                             "deg; use method='vesic' or 'meyerhof'")
        i = min(int(math.floor(phi_deg)), 49)
        t = float(phi_deg) - i
        lo, hi = _TERZAGHI_N_GAMMA[i], _TERZAGHI_N_GAMMA[i + 1]
        if lo <= 0.0:  # between 0 and 1 degree: linear (log of 0 undefined)
            return float(lo + t * (hi - lo))
        return float(lo * (hi / lo) ** t)
    nq = n_q(phi_deg)
    if method == "meyerhof":
        return (nq - 1.0) * math.tan(1.4 * phi)
    if method == "vesic":
        return 2.0 * (nq + 1.0) * math.tan(phi)
    if method == "hansen":
        return 1.5 * (nq - 1.0) * math.tan(phi)
    raise ValueError(f"method = {method!r}: choose one of {', '.join(BEARING_METHODS)}")


def bearing_capacity_factors(phi_deg: float, method: str = "vesic") -> tuple[float, float, float]:
    """(N_c, N_q, N_gamma) of a strip footing by ``method``.

    Terzaghi uses his own N_c, N_q (rough base, 5.71 at phi = 0); Meyerhof, Vesic and Hansen
    share the Prandtl-Reissner N_c, N_q and differ in N_gamma (see :func:`n_gamma`).
    """
    if method == "terzaghi":
        return terzaghi_n_c(phi_deg), terzaghi_n_q(phi_deg), n_gamma(phi_deg, method)
    if method not in BEARING_METHODS:
        raise ValueError(f"method = {method!r}: choose one of {', '.join(BEARING_METHODS)}")
    return n_c(phi_deg), n_q(phi_deg), n_gamma(phi_deg, method)


def prandtl_limit_load(c: float, phi_deg: float, q_surcharge: float = 0.0) -> float:
    """Prandtl's limit pressure of a strip footing on weightless soil [kPa]: c N_c + q N_q.

    ``c`` cohesion [kPa], ``q_surcharge`` overburden beside the footing [kPa]. For phi = 0 it is
    (2 + pi) c_u + q. Exact (plasticity) for a weightless Mohr-Coulomb half-space.
    """
    c = _non_negative(c, "c", "kPa")
    q = _non_negative(q_surcharge, "q_surcharge", "kPa")
    return c * n_c(phi_deg) + q * n_q(phi_deg)


def strip_footing_capacity(c: float, phi_deg: float, gamma: float, B: float, q: float = 0.0,
                           method: str = "vesic") -> float:
    """Ultimate pressure of a strip footing [kPa]: c N_c + q N_q + 0.5 gamma B N_gamma.

    ``gamma`` unit weight [kN/m3], ``B`` footing width [m], ``q`` surcharge [kPa]; factors by
    ``method`` (:func:`bearing_capacity_factors`). No shape, depth or inclination factors.
    """
    c = _non_negative(c, "c", "kPa")
    gamma = _non_negative(gamma, "gamma", "kN/m3")
    B = _positive(B, "B", "m")
    q = _non_negative(q, "q", "kPa")
    nc, nq, ng = bearing_capacity_factors(phi_deg, method)
    return c * nc + q * nq + 0.5 * gamma * B * ng


def strip_footing_estimates(c: float, phi_deg: float, gamma: float, B: float,
                            q: float = 0.0) -> dict[str, float]:
    """Ultimate pressure [kPa] by every method, plus Prandtl (weightless), for reference lines."""
    out = {"Prandtl (weightless)": prandtl_limit_load(c, phi_deg, q)}
    for method in BEARING_METHODS:
        if method == "terzaghi" and phi_deg > 50.0:
            continue
        out[method.capitalize()] = strip_footing_capacity(c, phi_deg, gamma, B, q, method)
    return out


# --- earth pressure --------------------------------------------------------------------------

def rankine_ka(phi_deg: float) -> float:
    """Rankine active coefficient K_a = tan^2(45 deg - phi/2) (smooth vertical wall, level fill)."""
    phi = _phi_rad(phi_deg)
    return math.tan(math.pi / 4 - phi / 2) ** 2


def rankine_kp(phi_deg: float) -> float:
    """Rankine passive coefficient K_p = tan^2(45 deg + phi/2) = 1 / K_a."""
    phi = _phi_rad(phi_deg)
    return math.tan(math.pi / 4 + phi / 2) ** 2


def tension_crack_depth(c: float, phi_deg: float, gamma: float, q: float = 0.0) -> float:
    """Depth [m] where the Rankine active pressure K_a (gamma z + q) - 2 c sqrt(K_a) is zero."""
    c = _non_negative(c, "c", "kPa")
    gamma = _positive(gamma, "gamma", "kN/m3")
    ka = rankine_ka(phi_deg)
    return max(0.0, (2.0 * c / math.sqrt(ka) - q) / gamma)


def rankine_active_thrust(gamma: float, H: float, phi_deg: float, c: float = 0.0,
                          q: float = 0.0, tension_crack: bool = True) -> float:
    """Rankine active thrust on a smooth vertical wall of height ``H`` [kN/m].

    Pressure p(z) = K_a (gamma z + q) - 2 c sqrt(K_a); for c = q = 0 the thrust is
    0.5 K_a gamma H^2. Tension-crack convention: with ``tension_crack=True`` (default) the
    soil cannot pull on the wall, so the negative pressure above the crack depth
    z_c = 2 c / (gamma sqrt(K_a)) is dropped (thrust 0.5 K_a gamma (H - z_c)^2 when q = 0, and
    never negative); with ``False`` the full integral 0.5 K_a gamma H^2 - 2 c sqrt(K_a) H is
    returned (it may be negative).
    """
    return _rankine_thrust(rankine_ka(phi_deg), -1.0, gamma, H, c, q, tension_crack)


def rankine_passive_thrust(gamma: float, H: float, phi_deg: float, c: float = 0.0,
                           q: float = 0.0) -> float:
    """Rankine passive thrust [kN/m]: integral of K_p (gamma z + q) + 2 c sqrt(K_p) over H.

    For q = 0: 0.5 K_p gamma H^2 + 2 c sqrt(K_p) H (no tension anywhere).
    """
    return _rankine_thrust(rankine_kp(phi_deg), 1.0, gamma, H, c, q, False)


def _rankine_thrust(k: float, sign: float, gamma: float, H: float, c: float, q: float,
                    crack: bool) -> float:
    gamma = _non_negative(gamma, "gamma", "kN/m3")
    H = _positive(H, "H", "m")
    c = _non_negative(c, "c", "kPa")
    q = _non_negative(q, "q", "kPa")
    p0 = k * q + sign * 2.0 * c * math.sqrt(k)  # pressure at the top [kPa]
    slope = k * gamma  # [kPa/m]
    full = p0 * H + 0.5 * slope * H**2
    if not crack or p0 >= 0.0:
        return full
    if slope <= 0.0 or p0 + slope * H <= 0.0:
        return 0.0
    zc = -p0 / slope
    return 0.5 * slope * (H - zc) ** 2


def k0_elastic(nu: float) -> float:
    """At-rest (oedometric) coefficient of an elastic soil: K0 = nu / (1 - nu)."""
    nu = float(nu)
    if not -1.0 < nu < 0.5:
        raise ValueError(f"nu = {nu!r} must be in (-1, 0.5)")
    return nu / (1.0 - nu)


def k0_jaky(phi_deg: float) -> float:
    """Jaky's (1944) at-rest coefficient of normally consolidated soil: K0 = 1 - sin phi."""
    return 1.0 - math.sin(_phi_rad(phi_deg))


def friction_ratio(phi_residual_deg: float, phi_peak_deg: float) -> float:
    """Residual-to-peak shear strength ratio at one normal stress: tan(phi_r) / tan(phi_p).

    E.g. to carry a clay's drained loss of strength over to its undrained strength
    (c_u,r = c_u x this ratio), an assumption where only drained angles are published.
    """
    peak = math.tan(_phi_rad(phi_peak_deg, "phi_peak_deg"))
    if peak == 0.0:
        raise ValueError("phi_peak_deg = 0: the ratio needs a peak friction angle above zero")
    return math.tan(_phi_rad(phi_residual_deg, "phi_residual_deg")) / peak


# --- elastic strip load (Flamant integrated) ---------------------------------------------------

class StripStress(NamedTuple):
    """Stress [kPa] under a uniform strip load, tension positive, x horizontal, y up."""

    sigma_xx: np.ndarray
    sigma_yy: np.ndarray
    sigma_xy: np.ndarray


def strip_load_angles(width: float, x: np.ndarray, z: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Angles (alpha, delta) [rad] of Poulos & Davis (1974) for a strip -B/2 <= x <= B/2.

    ``z`` is the depth below the surface (> 0). alpha is the angle the strip subtends at the
    point; delta = atan((x - B/2) / z) is the angle from the vertical to the line joining the
    point to the strip edge at x = +B/2 (so delta = -alpha/2 on the centreline).
    """
    B = _positive(width, "width", "m")
    x = np.asarray(x, dtype=float)
    z = np.asarray(z, dtype=float)
    if np.any(z <= 0.0):
        raise ValueError("z: depths below the loaded surface must be > 0 m")
    theta_a = np.arctan((x - B / 2) / z)
    theta_b = np.arctan((x + B / 2) / z)
    return theta_b - theta_a, theta_a


def flamant_strip_stress(q: float, width: float, x: np.ndarray, z: np.ndarray) -> StripStress:
    """Elastic stress under a uniform vertical strip load ``q`` [kPa] of width ``width`` [m].

    Poulos & Davis (1974) eq. 3.4 (compression positive there), returned tension positive:
    sigma_yy = -(q/pi) (alpha + sin alpha cos(alpha + 2 delta)),
    sigma_xx = -(q/pi) (alpha - sin alpha cos(alpha + 2 delta)),
    sigma_xy = (q/pi) sin alpha sin(alpha + 2 delta), at horizontal offset ``x`` from the strip
    centre and depth ``z`` > 0 (angles of :func:`strip_load_angles`). Independent of the elastic
    constants (homogeneous isotropic half-space, plane strain). On the centreline it reduces to
    -(q/pi)(alpha + sin alpha).
    """
    alpha, delta = strip_load_angles(width, x, z)
    s = float(q) / math.pi
    sa, c2 = np.sin(alpha), np.cos(alpha + 2 * delta)
    return StripStress(sigma_xx=-s * (alpha - sa * c2), sigma_yy=-s * (alpha + sa * c2),
                       sigma_xy=s * sa * np.sin(alpha + 2 * delta))


def flamant_centreline(q: float, half_width: float, z: np.ndarray) -> np.ndarray:
    """Vertical stress [kPa] under the centre of a strip load, tension positive.

    -(q/pi)(alpha + sin alpha) with alpha = 2 atan(b / z), b the half-width [m].
    """
    return flamant_strip_stress(q, 2.0 * half_width, np.zeros_like(np.asarray(z, float)),
                                z).sigma_yy


# --- oedometric (laterally confined) column ----------------------------------------------------

def oedometric_modulus(E: float, nu: float) -> float:
    """Constrained modulus M = E (1 - nu) / ((1 + nu)(1 - 2 nu)) [kPa]."""
    E = _positive(E, "E", "kPa")
    k0_elastic(nu)  # validates nu
    return E * (1 - nu) / ((1 + nu) * (1 - 2 * nu))


def oedometer_stress(gamma: float, nu: float, z: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(sigma_v, sigma_h) [kPa] in a laterally confined elastic column under self-weight.

    sigma_v = -gamma z, sigma_h = K0 sigma_v with K0 = nu / (1 - nu); tension positive, ``z``
    the depth below the free top [m]. sigma_zz (out of plane) equals sigma_h.
    """
    gamma = _non_negative(gamma, "gamma", "kN/m3")
    z = np.asarray(z, dtype=float)
    sv = -gamma * z
    return sv, k0_elastic(nu) * sv


def oedometer_settlement(gamma: float, H: float, E: float, nu: float) -> float:
    """Settlement [m] of the top of a confined column of height H under self-weight.

    gamma H^2 / (2 M), M the constrained modulus (positive downward movement).
    """
    gamma = _non_negative(gamma, "gamma", "kN/m3")
    H = _positive(H, "H", "m")
    return gamma * H**2 / (2.0 * oedometric_modulus(E, nu))


# --- slope stability: limit equilibrium on circular slip surfaces ------------------------------

#: A soil description for the methods of slices: ``soil(x, y) -> (unit weight [kN/m3],
#: cohesion [kPa], friction angle [deg])``, arrays of the shape of ``x``; unit weight 0 where
#: there is no soil, cohesion inf where the ground cannot be cut (no slip passes there).
Soil = Callable[[np.ndarray, np.ndarray], tuple[np.ndarray, np.ndarray, np.ndarray]]

# smallest m_alpha = cos(alpha) (1 + tan(alpha) tan(phi) / F) of a valid circle (Whitman &
# Bailey 1967: below it Bishop's normal force becomes unrealistic near a steep exit)
_M_ALPHA_MIN = 0.2


def uniform_soil(unit_weight: float, cohesion: float, phi_deg: float) -> Soil:
    """A homogeneous soil (kN/m3, kPa, degrees) for :func:`circle_factor`."""
    gamma = _non_negative(unit_weight, "unit_weight", "kN/m3")
    c = _non_negative(cohesion, "cohesion", "kPa")
    phi = math.degrees(_phi_rad(phi_deg))

    def soil(x: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        shape = np.shape(x)
        return np.full(shape, gamma), np.full(shape, c), np.full(shape, phi)

    return soil


class SlipCircle(NamedTuple):
    """A circular slip surface and its factor of safety.

    ``centre`` (x, y) [m], ``radius`` [m]; ``entry`` and ``exit`` the x [m] where the arc meets
    the ground surface (entry < exit); ``factor`` by ``method``.
    """

    factor: float
    centre: tuple[float, float]
    radius: float
    entry: float
    exit: float
    method: str = "bishop"

    def as_dict(self) -> dict[str, Any]:
        """The figures for a summary: F, centre, radius, entry and exit x [m]."""
        return {"F": self.factor, "centre_m": list(self.centre), "radius_m": self.radius,
                "entry_x_m": self.entry, "exit_x_m": self.exit}

    def arc(self, n: int = 100) -> np.ndarray:
        """(n, 2) points of the slip surface from entry to exit [m]."""
        x = np.linspace(self.entry, self.exit, n)
        xc, yc = self.centre
        return np.stack([x, yc - np.sqrt(np.maximum(self.radius**2 - (x - xc) ** 2, 0.0))],
                        axis=1)


def _surface(surface: np.ndarray) -> np.ndarray:
    pts = np.asarray(surface, dtype=float)
    if pts.ndim != 2 or pts.shape[1] != 2 or len(pts) < 2:
        raise ValueError(f"surface has shape {pts.shape}: give the ground surface as (n >= 2, 2) "
                         "points (x, y) [m]")
    if not np.all(np.isfinite(pts)) or np.any(np.diff(pts[:, 0]) <= 0):
        raise ValueError("surface: x must be finite and strictly increasing (a ground profile "
                         "y(x) from left to right)")
    return pts


def _arc_interval(pts: np.ndarray, xc: float, yc: float, R: float) -> tuple[float, float] | None:
    """The widest x-interval where the lower arc lies below the ground surface."""
    lo, hi = max(xc - R, pts[0, 0]), min(xc + R, pts[-1, 0])
    if hi <= lo:
        return None
    x = np.linspace(lo, hi, 801)
    below = yc - np.sqrt(np.maximum(R * R - (x - xc) ** 2, 0.0)) < np.interp(x, *pts.T)
    if not below.any():
        return None
    edges = np.flatnonzero(np.diff(np.concatenate([[0], below.astype(np.int8), [0]])))
    starts, stops = edges[0::2], edges[1::2] - 1
    k = int(np.argmax(x[stops] - x[starts]))

    def crossing(a: float, b: float) -> float:  # bisection on arc - surface
        fa = yc - math.sqrt(max(R * R - (a - xc) ** 2, 0.0)) - float(np.interp(a, *pts.T))
        for _ in range(60):
            m = 0.5 * (a + b)
            fm = yc - math.sqrt(max(R * R - (m - xc) ** 2, 0.0)) - float(np.interp(m, *pts.T))
            if (fm > 0) == (fa > 0):
                a, fa = m, fm
            else:
                b = m
        return 0.5 * (a + b)

    i, j = starts[k], stops[k]
    x0 = x[i] if i == 0 else crossing(x[i - 1], x[i])
    x1 = x[j] if j == len(x) - 1 else crossing(x[j + 1], x[j])
    return (x0, x1) if x1 > x0 else None


def _method_of_slices(xm: np.ndarray, b: np.ndarray, top: np.ndarray, xc: np.ndarray,
                      yc: np.ndarray, R: np.ndarray, soil: Soil, method: str,
                      column_points: int) -> np.ndarray:
    """F of C circles from their slices; inf where the circle is not admissible.

    Slice centres ``xm`` and widths ``b`` (C, n) [m], ground level ``top`` (C, n) [m] above
    them.
    """
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        return _slices(xm, b, top, xc, yc, R, soil, method, column_points)


def _slices(xm: np.ndarray, b: np.ndarray, top: np.ndarray, xc: np.ndarray, yc: np.ndarray,
            R: np.ndarray, soil: Soil, method: str, column_points: int) -> np.ndarray:
    # an arc through ground that cannot be cut (cohesion inf), checked at 4 points a slice
    t4 = (np.arange(4) + 0.5) / 4.0
    xd = (xm - 0.5 * b)[..., None] + t4 * b[..., None]
    yd = yc[:, None, None] - np.sqrt(np.maximum(R[:, None, None] ** 2
                                                - (xd - xc[:, None, None]) ** 2, 0.0))
    blocked = np.any(np.isinf(soil(xd, yd)[1]), axis=(1, 2))
    base = yc[:, None] - np.sqrt(np.maximum(R[:, None] ** 2 - (xm - xc[:, None]) ** 2, 0.0))
    height = np.maximum(top - base, 0.0)  # 0 where the arc runs in the air
    t = (np.arange(column_points) + 0.5) / column_points
    ys = base[..., None] + t * height[..., None]
    gamma = soil(np.broadcast_to(xm[..., None], ys.shape), ys)[0].mean(axis=-1)
    weight = b * height * gamma  # [kN/m]
    _, c, phi = soil(xm, base)
    c = np.where(height > 0.0, c, 0.0)  # no strength along the arc where it is in the air
    tan_phi = np.tan(np.radians(phi))
    lever = (xm - xc[:, None]) / R[:, None]
    sin_a = np.where(np.sum(weight * lever, axis=1) > 0, 1.0, -1.0)[:, None] * lever
    cos_a = np.sqrt(np.maximum(1.0 - sin_a**2, 0.0))
    driving = np.sum(weight * sin_a, axis=1)
    valid = (driving > 0.0) & np.all(cos_a > 0.0, axis=1) & ~blocked
    c = np.where(np.isfinite(c), c, 0.0)
    cos_a = np.where(cos_a > 0.0, cos_a, 1.0)
    safe = np.where(valid, driving, 1.0)
    F = np.sum(c * b / cos_a + weight * cos_a * tan_phi, axis=1) / safe  # ordinary
    F = np.where(valid & np.isfinite(F) & (F > 0.0), F, 1.0)
    if method == "bishop":
        for _ in range(200):
            m_alpha = cos_a + sin_a * tan_phi / F[:, None]
            m_alpha = np.where(m_alpha > 0.0, m_alpha, 1.0)
            new = np.sum((c * b + weight * tan_phi) / m_alpha, axis=1) / safe
            done = np.all(np.abs(new - F) <= 1e-12 * np.abs(F))
            F = new
            if done:
                break
        # the m_alpha rule at the converged F, on the slices that carry soil
        m_alpha = cos_a + sin_a * tan_phi / F[:, None]
        valid &= ~np.any((weight > 0.0) & (m_alpha < _M_ALPHA_MIN), axis=1)
    return np.where(valid & np.isfinite(F), F, math.inf)


def _lowest(x0: Any, x1: Any, xc: Any, yc: Any, R: Any) -> Any:
    """Lowest level [m] of the lower arc between x0 and x1 (scalars or arrays)."""
    near = np.minimum((x0 - xc) ** 2, (x1 - xc) ** 2)
    inside = (x0 < xc) & (xc < x1)
    return np.where(inside, yc - R, yc - np.sqrt(np.maximum(R * R - near, 0.0)))


def circle_factor(surface: np.ndarray, soil: Soil, centre: tuple[float, float], radius: float,
                  *, method: str = "bishop", slices: int = 60, floor: float | None = None,
                  column_points: int = 16) -> float:
    """Factor of safety of one circular slip surface by the method of slices.

    ``surface``: the ground profile (n, 2) [m], x increasing; ``soil`` (:data:`Soil`);
    ``centre`` (x, y) and ``radius`` [m] of the circle; ``floor``: no slip below this level
    [m]. ``method``: ``"bishop"`` (Bishop 1955, simplified: moment equilibrium about the
    centre, interslice shear neglected, F = sum[(c b + W tan phi) / m_alpha] / sum W sin alpha,
    m_alpha = cos alpha + sin alpha tan phi / F, iterated) or ``"ordinary"`` (Fellenius:
    F = sum(c l + W cos alpha tan phi) / sum W sin alpha). Dry soil (no pore pressure).
    The sliding mass is the part above the arc where it lies below the surface (its widest
    stretch); slices are ``slices`` equal widths plus the surface's vertices; a slice weight
    integrates the unit weight over ``column_points`` points of its centre line.

    Returns inf for a circle that does not cut the ground, dips below ``floor`` or into
    ground that cannot be cut, drives no mass, or has m_alpha < 0.2 on a slice (Whitman &
    Bailey 1967).
    """
    pts = _surface(surface)
    xc, yc, R = float(centre[0]), float(centre[1]), float(radius)
    if not (math.isfinite(xc) and math.isfinite(yc) and R > 0 and math.isfinite(R)):
        raise ValueError(f"circle centre {centre} and radius {radius} must be finite, radius > 0")
    if method not in ("bishop", "ordinary"):
        raise ValueError(f"method = {method!r}: choose 'bishop' or 'ordinary'")
    span = _arc_interval(pts, xc, yc, R)
    if span is None:
        return math.inf
    x0, x1 = span
    if floor is not None and _lowest(x0, x1, xc, yc, R) < floor - 1e-9:
        return math.inf
    inner = pts[(pts[:, 0] > x0) & (pts[:, 0] < x1), 0]
    edges = np.union1d(np.linspace(x0, x1, slices + 1), inner)
    xm = 0.5 * (edges[:-1] + edges[1:])[None, :]
    return float(_method_of_slices(xm, np.diff(edges)[None, :], np.interp(xm, *pts.T),
                                   np.array([xc]), np.array([yc]), np.array([R]), soil,
                                   method, column_points)[0])


def critical_circle(surface: np.ndarray, soil: Soil, *, floor: float | None = None,
                    x_range: tuple[float, float] | None = None, method: str = "bishop",
                    slices: int = 60, grid: int = 40) -> SlipCircle:
    """The circle of least factor of safety (entry-and-exit search).

    Circles are parametrised by where they meet the ground (x_entry < x_exit, within
    ``x_range``, default the whole surface) and the half-angle beta (2 to 90 deg) that the
    arc subtends at its centre (centres above the ends: no overhanging arc). Every circle of
    a grid is evaluated with 40 equal slices: ``grid`` entries and the surface's corners
    (slope changes above 1 deg: toes, crests) as entries or exits, ``grid`` / 2 chord lengths
    from 1/64 of the range to all of it (log scale), 10 angles; the 40 best distinct ones are
    ranked again with ``slices`` equal slices plus the surface's vertices, and the 8 best
    refined by a pattern search (steps from a tenth of the chord, halved down to 1e-5 of it,
    restarted from where it stops while that still lowers F), whose value is returned: the F
    of the arc between ``entry`` and ``exit``. A circle must leave the ground at both ends
    (the circle just beyond them in the air).
    ``floor``, ``method``: as :func:`circle_factor`. Raises ValueError when no admissible
    circle exists.
    """
    pts = _surface(surface)
    lo, hi = (pts[0, 0], pts[-1, 0]) if x_range is None else map(float, x_range)
    if not pts[0, 0] <= lo < hi <= pts[-1, 0]:
        raise ValueError(f"x_range {x_range} must lie within the surface [{pts[0, 0]}, "
                         f"{pts[-1, 0]}] with x_min < x_max")
    if method not in ("bishop", "ordinary"):
        raise ValueError(f"method = {method!r}: choose 'bishop' or 'ordinary'")
    width = hi - lo
    beta_range = (math.radians(2.0), math.pi / 2)

    def circles(P: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        xa, xb, beta = P.T
        ya, yb = np.interp(xa, *pts.T), np.interp(xb, *pts.T)
        chord = np.hypot(xb - xa, yb - ya)
        chord = np.where(chord > 0, chord, 1.0)
        R = chord / (2.0 * np.sin(beta))
        d = R * np.cos(beta)
        xc = 0.5 * (xa + xb) - d * (yb - ya) / chord
        yc = 0.5 * (ya + yb) + d * (xb - xa) / chord
        ok = ((lo <= xa) & (xa < xb) & (xb <= hi) & (beta >= beta_range[0])
              & (beta <= beta_range[1]) & (yc >= np.maximum(ya, yb) - 1e-9))
        if floor is not None:
            ok &= _lowest(xa, xb, xc, yc, R) >= floor - 1e-9
        # the arc leaves the ground at its ends: just outside them the circle is in the air
        # (else the ground it cuts beyond an end belongs to the sliding mass too)
        for x_end, side in ((xa, -1.0), (xb, 1.0)):
            x = x_end + side * 1e-6 * width
            arc = yc - np.sqrt(np.maximum(R * R - (x - xc) ** 2, 0.0))
            ok &= (np.abs(x - xc) >= R) | (arc >= np.interp(x, *pts.T) - 1e-9 * width)
        return xc, yc, R, ok

    def factors(P: np.ndarray, n: int = 40, column: int = 8,
                vertices: bool = False) -> np.ndarray:
        """F of the circles P (C, 3) with n equal slices between where they meet the ground.

        With ``vertices``, the surface's vertices between them are slice boundaries too (as
        :func:`circle_factor`: a slice then never straddles a toe or a crest).
        """
        out = np.full(len(P), math.inf)
        with np.errstate(divide="ignore", invalid="ignore"):
            geometry = circles(P)
        for k in range(0, len(P), 400):
            xc, yc, R, ok = (g[k:k + 400] for g in geometry)
            if not ok.any():
                continue
            q = P[k:k + 400][ok]
            edges = q[:, 0:1] + (q[:, 1:2] - q[:, 0:1]) * np.linspace(0.0, 1.0, n + 1)[None, :]
            if vertices:  # vertices outside the arc collapse onto its ends: empty slices
                inner = np.clip(pts[None, :, 0], q[:, 0:1], q[:, 1:2])
                edges = np.sort(np.concatenate([edges, inner], axis=1), axis=1)
            xm = 0.5 * (edges[:, :-1] + edges[:, 1:])
            out[k + np.flatnonzero(ok)] = _method_of_slices(
                xm, np.diff(edges, axis=1), np.interp(xm, *pts.T), xc[ok], yc[ok], R[ok],
                soil, method, column)
        return out

    def fine(P: np.ndarray) -> np.ndarray:
        return factors(P, slices, 16, vertices=True)

    # entries on a grid and at the surface's corners (toes, crests), chords on a log scale
    # (small and large circles alike), angles; circles also ending at a corner
    slope = np.degrees(np.arctan2(np.diff(pts[:, 1]), np.diff(pts[:, 0])))
    corners = pts[1:-1, 0][np.abs(np.diff(slope)) > 1.0]
    corners = corners[(corners > lo) & (corners < hi)]
    chords = np.geomspace(width / 64.0, width, grid // 2)
    betas = np.radians([5.0, 10.0, 15.0, 20.0, 30.0, 40.0, 50.0, 60.0, 75.0, 90.0])
    x0, L, beta = np.meshgrid(np.union1d(np.linspace(lo, hi, grid), corners), chords, betas,
                              indexing="ij")
    xc_, Lc, bc = np.meshgrid(corners, chords, betas, indexing="ij")
    P = np.concatenate([np.column_stack([x0.ravel(), (x0 + L).ravel(), beta.ravel()]),
                        np.column_stack([(xc_ - Lc).ravel(), xc_.ravel(), bc.ravel()])])
    P = P[(P[:, 0] >= lo) & (P[:, 1] <= hi)]
    F = factors(P)
    order = np.argsort(F)
    order = order[np.isfinite(F[order])]
    if not order.size:
        raise ValueError("no admissible slip circle: check the surface, the floor and x_range")
    starts: list[np.ndarray] = []
    for i in order:  # the best circles that are not neighbours of a better one
        if all(np.abs(P[i] - s)[:2].max() > 1.5 * width / grid or
               abs(P[i, 2] - s[2]) > math.radians(10.0) for s in starts):
            starts.append(P[i])
        if len(starts) == 40:
            break
    # the coarse slices can miss a thin unbreakable layer the arc grazes: rank again with the
    # fine ones and refine the 8 best
    ranked = fine(np.array(starts))
    starts = [starts[i] for i in np.argsort(ranked)[:8] if math.isfinite(ranked[i])]
    if not starts:
        raise ValueError("no admissible slip circle: check the surface, the floor and x_range")
    moves = np.array([[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1],
                      [1, 1, 0], [-1, -1, 0], [1, -1, 0], [-1, 1, 0]], dtype=float)
    best_p, best_f = starts[0], math.inf
    for p in starts:
        f = float(fine(p[None, :])[0])
        for _ in range(4):  # restarted from where it stopped: a corner of F can stall it
            start_f = f
            size = 0.1 * (p[1] - p[0])  # steps on the scale of the circle
            step = np.array([size, size, math.radians(5.0)])
            while step[0] > 1e-4 * size:
                trial = p[None, :] + moves * step[None, :]
                ft = fine(trial)
                k = int(np.argmin(ft))
                if ft[k] < f:
                    p, f = trial[k], float(ft[k])
                else:
                    step *= 0.5
            if not f < start_f:
                break
        if f < best_f:
            best_p, best_f = p, f
    if not math.isfinite(best_f):
        raise ValueError("no admissible slip circle: check the surface, the floor and x_range")
    xc, yc, R, _ = circles(best_p[None, :])
    return SlipCircle(best_f, (float(xc[0]), float(yc[0])), float(R[0]), float(best_p[0]),
                      float(best_p[1]), method)


# --- granular column collapse (plane strain) ---------------------------------------------------
#
# A column of height H0 and length L0 (aspect ratio a = H0 / L0) against a back wall is released
# by removing the other wall and spreads over a horizontal base to a deposit of run-out L_inf
# (measured from the back wall) and height H_inf. Provenance, read for this module:
#
# - Lube, Huppert, Sparks & Freundt (2005), "Collapses of two-dimensional granular columns",
#   Phys. Rev. E 72, 041301 (doi:10.1103/PhysRevE.72.041301). The paper itself was not
#   accessible; its abstract (quoted verbatim in the reference list of K. Kumar's Cambridge PhD
#   thesis, github.com/kks32/phd-thesis, References/references.bib) states the regime split:
#   "two main flow regimes at a ~ 1.8, where a = h_i/d_i and h_i and d_i are the initial height
#   and width of the column", final geometry "independent of basal and internal friction". The
#   coefficients (1.2 a; 1.9 a^(2/3); H_inf/d_i = a^(2/5)) are SECONDARY: open quotations, not
#   the paper (see the function docstrings).
# - arXiv:1512.05180 (Dec. 2015), "Failure mechanism of true 2D granular flows": column
#   collapses of aluminium rods (true 2-D grains, the material of Bui et al. 2008). The laws
#   below are stated in its abstract (text, read as mirrored at koineu.com); the author list
#   and journal version were not verified here.
# - Bui, Fukagawa, Sako & Ohno (2008): see :func:`bui2008_collapse` (geometry and material
#   only: the measured profile is not shipped).
#
# Not encoded, because no value could be verified: Lajeunesse, Monnier & Homsy (2005), Phys.
# Fluids 17, 103302 (glass beads in a rectangular channel; its abstract gives only the form of
# the laws: H_f/L_i and dL/L_i "exhibit simple power laws whose exponents depend on a and on the
# flow geometry", time scale the free fall of the column, flowing-layer shear rate
# 0.3 sqrt(g/d); abstract as quoted in the bibliography of Kumar's thesis cited above), and
# Balmforth & Kerswell (2005), J. Fluid Mech. 538, 399-428, whose abstract gives exponents only
# ((l_inf - L)/L ~ a^(0.9 +- 0.1) in wide channels, a^(0.65 +- 0.05) in narrow slots;
# H/h_inf ~ a^0.6 wide, a^0.5 narrow) and states that the prefactors depend on the material.

#: Lube et al. (2005): largest a of the linear run-out regime (abstract: regimes split at
#: a ~ 1.8; the quotations give the linear law for a < 1.8).
LUBE2005_LINEAR_MAX = 1.8
#: Lube et al. (2005): smallest a of the a^(2/3) run-out regime (secondary: an open validation
#: note reports it so from Dunatunga & Kamrin 2015, arXiv:1411.5447, table p. 11, and reports a
#: single switch at a = 2.3 from Staron & Hinch, arXiv:physics/0501022, sec. III, and Szewc,
#: arXiv:1602.07881, eqs. 22, 24; none of these was read here). The two laws do not meet
#: anywhere in 1.8 <= a <= 2.8 (they cross only at a = (1.9/1.2)^3 = 3.97), so between the
#: bounds no law is given.
LUBE2005_POWER_MIN = 2.8
#: Lube et al. (2005): a below which the deposit keeps the initial height (secondary, one
#: quotation; see :func:`granular_final_height_lube2005`).
LUBE2005_HEIGHT_BREAK = 1.15
#: arXiv:1512.05180 (abstract): a below which H_inf = H0 (aluminium rods).
RODS2015_BREAK = 0.65
#: arXiv:1512.05180 (abstract): a where the excess run-out law changes exponent.
RODS2015_RUNOUT_BREAK = 1.5

def _aspect(aspect: float) -> float:
    return _positive(aspect, "aspect", "(H0/L0, dimensionless)")


def granular_runout_lube2005(aspect: float, branch: str = "auto") -> float:
    """Normalised run-out (L_inf - L0) / L0 of a plane column collapse, Lube et al. (2005).

    Lube, Huppert, Sparks & Freundt (2005), Phys. Rev. E 72, 041301: a = H0 / L0 with L0 the
    initial width of the column (their d_i) and L_inf the farthest reach of the deposit
    (d_inf), both from the back wall; grains of several kinds (quartz sand among them) in a
    horizontal channel. The law, as quoted in open secondary sources (the paper itself was
    not read), is

    - ``branch="linear"``: 1.2 a, for a < 1.8 (every quotation found);
    - ``branch="power"``: 1.9 a^(2/3), for a > 2.8 (some quotations put a single switch at
      2.3 instead; see :data:`LUBE2005_POWER_MIN`).

    ``branch="auto"`` picks the linear law for a <= 1.8 and the power law for a >= 2.8 and
    raises ValueError in between, where the two do not meet (1.2 a and 1.9 a^(2/3) cross only
    at a = 3.97): there, choose a branch explicitly and say so.

    Args:
        aspect: initial aspect ratio a = H0 / L0 (> 0).
        branch: ``"auto"``, ``"linear"`` or ``"power"``.

    Returns:
        (L_inf - L0) / L0, dimensionless.
    """
    a = _aspect(aspect)
    if branch == "auto":
        if a <= LUBE2005_LINEAR_MAX:
            branch = "linear"
        elif a >= LUBE2005_POWER_MIN:
            branch = "power"
        else:
            raise ValueError(
                f"aspect = {a:g} is between the two regimes of Lube et al. (2005) "
                f"({LUBE2005_LINEAR_MAX} < a < {LUBE2005_POWER_MIN}), where the laws 1.2 a and "
                "1.9 a^(2/3) do not meet: pass branch='linear' or 'power'")
    if branch == "linear":
        return 1.2 * a
    if branch == "power":
        return 1.9 * a ** (2.0 / 3.0)
    raise ValueError(f"branch = {branch!r}: choose 'auto', 'linear' or 'power'")


def granular_final_height_lube2005(aspect: float) -> float:
    """Final deposit height over initial width, H_inf / L0, Lube et al. (2005). SECONDARY.

    H_inf / L0 = a (the deposit keeps the column height, H_inf = H0) for a <= 1.15 and
    a^(2/5) above. Not read in the paper: a^(2/5) is quoted for large a by an open code's
    validation notes, and the 1.15 break by one MATLAB script only; the exponent agrees with
    Balmforth & Kerswell's (2005) abstract for wide channels (H / h_inf ~ a^0.6, i.e.
    h_inf / L ~ a^0.4). The branches do not meet at 1.15 (1.15 against 1.057). Use as a band,
    not a bar, until checked against the paper.

    Args:
        aspect: initial aspect ratio a = H0 / L0 (> 0).

    Returns:
        H_inf / L0, dimensionless.
    """
    a = _aspect(aspect)
    return a if a <= LUBE2005_HEIGHT_BREAK else a ** 0.4


def granular_runout_rods2015(aspect: float, total: bool = False) -> float:
    """Run-out of a collapsing column of aluminium rods (true 2-D grains), arXiv:1512.05180.

    "Failure mechanism of true 2D granular flows" (arXiv:1512.05180, 2015), abstract (stated in
    text): with a = h0 / d0 (initial height over width) and d the maximum run-out,
    (d - d0) / d0 = 3.25 a^0.96 for 0.65 < a < 1.5 and 3.80 a^0.73 for a > 1.5; d / d0 =
    4.30 a^0.72 for every a > 0.65 (``total=True``). The abstract gives no run-out law for
    a <= 0.65 (ValueError). The excess laws do not meet at a = 1.5 (4.80 against 5.11).

    Args:
        aspect: initial aspect ratio a = H0 / L0 (> 0.65).
        total: return d / d0 (the single-law fit) instead of (d - d0) / d0.

    Returns:
        (L_inf - L0) / L0, or L_inf / L0 with ``total``, dimensionless.
    """
    a = _aspect(aspect)
    if a <= RODS2015_BREAK:
        raise ValueError(f"aspect = {a:g}: arXiv:1512.05180 states run-out laws only for "
                         f"a > {RODS2015_BREAK}")
    if total:
        return 4.30 * a**0.72
    if a < RODS2015_RUNOUT_BREAK:
        return 3.25 * a**0.96
    return 3.80 * a**0.73


def granular_final_height_rods2015(aspect: float) -> float:
    """Final height over initial height, H_inf / H0, aluminium rods, arXiv:1512.05180.

    Abstract (stated in text): H_inf / H0 = 1 for a < 0.65; h0 / h_inf = 1.42 a^(2/3) for
    a > 0.65, so H_inf / H0 = 1 / (1.42 a^(2/3)) (0.939 just above 0.65: the branches do not
    meet). a = 0.65 itself is given to the first branch.

    Args:
        aspect: initial aspect ratio a = H0 / L0 (> 0).

    Returns:
        H_inf / H0, dimensionless.
    """
    a = _aspect(aspect)
    if a <= RODS2015_BREAK:
        return 1.0
    return 1.0 / (1.42 * a ** (2.0 / 3.0))


class CollapseExperiment(NamedTuple):
    """A published plane column-collapse experiment: its geometry and material.

    The column 0 <= x <= ``length``, 0 <= y <= ``height`` [m] stands against a back wall at
    x = 0 and is released towards +x. Material values are those of the paper's simulation of
    the test (what a continuum model of it uses), not measurements of the grains unless
    ``notes`` says so.
    """

    name: str
    length: float  # L0 [m]
    height: float  # H0 [m]
    friction_angle: float  # [deg]
    cohesion: float  # [kPa]
    dilatancy_angle: float  # [deg]
    density: float  # [kg/m3]
    youngs_modulus: float  # [kPa]
    poisson: float
    source: str
    notes: str

    @property
    def aspect(self) -> float:
        """Initial aspect ratio a = H0 / L0."""
        return self.height / self.length

    @property
    def unit_weight(self) -> float:
        """Unit weight [kN/m3] of ``density`` under g = 9.81 m/s2."""
        return self.density * 9.81e-3


def bui2008_collapse() -> CollapseExperiment:
    """The aluminium-bar column collapse of Bui, Fukagawa, Sako & Ohno (2008).

    Bui, H. H., Fukagawa, R., Sako, K. & Ohno, S. (2008), "Lagrangian meshfree particles method
    (SPH) for large deformation and failure flows of geomaterial using elastic-plastic soil
    constitutive model", Int. J. Numer. Anal. Meth. Geomech. 32(12), 1537-1570,
    doi:10.1002/nag.688. The paper was not accessible; every value here is as reproduced by
    open benchmark inputs that cite it (secondary):

    - column L0 = 0.2 m long, H0 = 0.1 m high (a = 0.5) of aluminium bars, released towards
      +x (MaterialPointSolver.jl docs "2D Soil Collapse Test"; HydraxMPM and SPHinXsys inputs
      use the same column);
    - friction angle 19.8 deg, cohesion 0, dilatancy 0, density 2650 kg/m3, Young's modulus
      840 kPa, Poisson's ratio 0.3 (KratosMultiphysics/Examples,
      particle_mechanics/validation/granular_flow_2D/README.md, "according to the experiment
      conducted by Bui et al., 2008"; MaterialPointSolver.jl gives the same with bulk modulus
      700 kPa = 840 / (3 (1 - 2 x 0.3))). These are the simulation's parameters; 2650 kg/m3
      is close to solid aluminium, not a measured bulk density of the bar packing.

    Not found: the bar diameters and lengths, the packing, how the wall was removed, and any
    run-out or height the paper states in its text. The measured final profile is known here
    only as digitised from a figure by a third party, which is not shipped.

    Returns:
        The experiment as a :class:`CollapseExperiment`.
    """
    return CollapseExperiment(
        name="Bui et al. (2008) aluminium-bar collapse",
        length=0.2, height=0.1, friction_angle=19.8, cohesion=0.0, dilatancy_angle=0.0,
        density=2650.0, youngs_modulus=840.0, poisson=0.3,
        source="Bui, Fukagawa, Sako & Ohno (2008), Int. J. Numer. Anal. Meth. Geomech. 32(12), "
               "1537-1570, doi:10.1002/nag.688; parameters as in KratosMultiphysics/Examples "
               "granular_flow_2D",
        notes="material values are the simulation's (secondary); bar size, packing and wall "
              "removal not found",
    )


# --- Carsington Dam, chainage 725 ---------------------------------------------------------------

class Band(NamedTuple):
    """A published value drawn beside a computed history.

    ``low`` to ``high`` (in the plotted unit) at the levels ``level_low`` to ``level_high``.
    """

    label: str
    low: float
    high: float
    level_low: float
    level_high: float

    @property
    def middle(self) -> float:
        """The middle of the published range, (low + high) / 2: the value a check compares."""
        return 0.5 * (self.low + self.high)


@dataclass
class CarsingtonTable63(CaseParameters):
    """The thesis's Table 6.3 at Ch. 725 (undrained total stress), as case parameters.

    A case derives its ``Parameters`` from it, so each value is overridable (``--set``) under
    its name here; a run with all of them at these defaults uses the published section's
    materials. The mudstone is elastic, the clays phi = 0; Zone I and Zone II share "fill".
    """

    foundation_E: float = 125_000.0  # mudstone, elastic [kPa] (Table 6.3)
    foundation_nu: float = 0.35  # [-]
    foundation_gamma: float = 20.0  # [kN/m3]
    yellow_clay_cu: float = 15.0  # undrained strength [kPa] (Table 6.3, phi = 0)
    yellow_clay_E: float = 3_000.0  # [kPa]
    yellow_clay_nu: float = 0.42  # [-]
    yellow_clay_gamma: float = 19.5  # [kN/m3]
    core_cu: float = 52.0  # [kPa] (Table 6.3, phi = 0)
    core_E: float = 2_500.0  # [kPa]
    core_nu: float = 0.43  # [-]
    core_gamma: float = 18.5  # [kN/m3]
    fill_c: float = 13.5  # Zone I and Zone II cohesion [kPa] (Table 6.3)
    fill_phi: float = 24.0  # [deg]
    fill_E: float = 60_000.0  # [kPa]
    fill_nu: float = 0.38  # [-]
    fill_gamma: float = 21.0  # [kN/m3]


@dataclass
class CarsingtonTable62(CaseParameters):
    """The thesis's Table 6.2 drained angles at Ch. 725, as case parameters.

    The peak angles give the residual-to-peak ratio of the clays' softening; the residual
    angles are the friction of separated elements (the fill's: Zone II's).
    """

    yellow_clay_peak_phi: float = 20.0  # drained phi' [deg] (Table 6.2; softening's ratio)
    core_peak_phi: float = 21.0  # drained phi' [deg] (Table 6.2; softening's ratio)
    yellow_clay_residual_phi: float = 12.0  # contact friction [deg] (Table 6.2)
    core_residual_phi: float = 13.0  # [deg] (Table 6.2)
    fill_residual_phi: float = 14.5  # Zone I, Zone II, berm [deg] (Table 6.2, Zone II)


#: fill level when the upstream slope slipped [m OD] (Skempton 1985)
CARSINGTON_FAILURE_FILL_LEVEL = 199.5
#: factors of safety at Ch. 725 (thesis 6.2.5, 6.3; Chen et al. 1992): (F, source)
CARSINGTON_FOS = {
    "limit_equilibrium_intact_peak": (1.4, "LE, intact peak strengths (> 1.4)"),
    "limit_equilibrium_pre_sheared": (1.2, "LE, reduced yellow-clay strength for pre-shears"),
    "finite_element_before_collapse": (1.1, "FE (strain softening), just before collapse"),
}
#: horizontal displacement of the core at node A [mm] against the fill level [m OD] (thesis
#: 6.3.1.2, Figure 6.19); the first two are at :data:`CARSINGTON_REPORT_LEVELS`
CARSINGTON_CORE_DISPLACEMENT = (
    Band("thesis: about 150 mm up to 198 m OD", 140.0, 160.0, 198.0, 198.0),
    Band("thesis: 400-450 mm at 200.5 m OD", 400.0, 450.0, 200.5, 200.5),
    Band("observed at the core's base: 200-275 mm", 200.0, 275.0, 199.0, 200.0),
    Band("Chen (1992), finite elements: 100-150 mm", 100.0, 150.0, 199.0, 200.0))
#: fill levels of the thesis's core displacements [m OD]
CARSINGTON_REPORT_LEVELS = (198.0, 200.5)
#: movements observed after the 1984 slip [m]: (value, source), keyed by the discrete phase's
#: measure ("upstream_toe_movement": towards upstream; "crest_drop": down)
CARSINGTON_POST_FAILURE = {
    "upstream_toe_movement": (12.0, "observed: upstream toe moved about 11-13 m"),
    "crest_drop": (10.0, "observed: crest dropped about 10 m (at the full height)"),
}
