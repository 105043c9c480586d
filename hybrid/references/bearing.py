"""Bearing capacity of a strip footing: the published factors N_c, N_q, N_gamma and limit loads.

Prandtl (1920) / Reissner (1924): N_q, N_c. Terzaghi (1943), Theoretical Soil Mechanics: N_q,
N_c of the rough-base mechanism. Kumbhojkar (1993), J. Geotech. Eng. 119(3), 575-582:
Terzaghi's N_gamma, as tabulated in B. M. Das, Principles of Foundation Engineering (7th ed.,
2011), Table 3.1. Meyerhof (1963), Can. Geotech. J. 1(1); Vesic (1973), J. Soil Mech. Found.
Div. 99(SM1); Brinch Hansen (1970), Danish Geotech. Inst. Bull. 28. Capacities are magnitudes
(positive, as in the textbooks) in kPa; angles in degrees.
"""

from __future__ import annotations

import math

import numpy as np

from hybrid.references._common import non_negative, phi_rad, positive

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


def n_q(phi_deg: float) -> float:
    """Prandtl-Reissner N_q = e^(pi tan phi) tan^2(45 deg + phi/2) (smooth or rough base)."""
    phi = phi_rad(phi_deg)
    return math.exp(math.pi * math.tan(phi)) * math.tan(math.pi / 4 + phi / 2) ** 2


def n_c(phi_deg: float) -> float:
    """Prandtl N_c = (N_q - 1) cot phi; its limit at phi = 0 is 2 + pi (Tresca)."""
    phi = phi_rad(phi_deg)
    if phi < 1e-7:  # (N_q - 1) cot phi = 2 + pi + O(phi): avoid 0/0
        return 2.0 + math.pi
    return (n_q(phi_deg) - 1.0) / math.tan(phi)


def terzaghi_n_q(phi_deg: float) -> float:
    """Terzaghi (1943) N_q = e^(2 (3 pi/4 - phi/2) tan phi) / (2 cos^2(45 deg + phi/2))."""
    phi = phi_rad(phi_deg)
    return (math.exp(2.0 * (0.75 * math.pi - phi / 2) * math.tan(phi))
            / (2.0 * math.cos(math.pi / 4 + phi / 2) ** 2))


def terzaghi_n_c(phi_deg: float) -> float:
    """Terzaghi (1943) N_c = (N_q - 1) cot phi, -> 1.5 pi + 1 = 5.71 at phi = 0."""
    phi = phi_rad(phi_deg)
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
    phi = phi_rad(phi_deg)
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
    c = non_negative(c, "c", "kPa")
    q = non_negative(q_surcharge, "q_surcharge", "kPa")
    return c * n_c(phi_deg) + q * n_q(phi_deg)


def strip_footing_capacity(c: float, phi_deg: float, gamma: float, B: float, q: float = 0.0,
                           method: str = "vesic") -> float:
    """Ultimate pressure of a strip footing [kPa]: c N_c + q N_q + 0.5 gamma B N_gamma.

    ``gamma`` unit weight [kN/m3], ``B`` footing width [m], ``q`` surcharge [kPa]; factors by
    ``method`` (:func:`bearing_capacity_factors`). No shape, depth or inclination factors.
    """
    c = non_negative(c, "c", "kPa")
    gamma = non_negative(gamma, "gamma", "kN/m3")
    B = positive(B, "B", "m")
    q = non_negative(q, "q", "kPa")
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
