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
    load).
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

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
    "strip_load_angles",
    "flamant_strip_stress",
    "flamant_centreline",
    "oedometric_modulus",
    "oedometer_stress",
    "oedometer_settlement",
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
