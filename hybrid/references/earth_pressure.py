"""Earth pressure and at-rest coefficients: Rankine thrusts, K0, the strength ratio.

Rankine (1857): K_a, K_p and the thrusts on a smooth vertical wall behind level fill, with the
tension-crack convention of the active side; the elastic (oedometric) at-rest coefficient
K0 = nu / (1 - nu) and Jaky's (1944) K0 = 1 - sin phi; the residual-to-peak strength ratio
tan(phi_r) / tan(phi_p). Thrusts and coefficients are magnitudes (kN/m, dimensionless).
"""

from __future__ import annotations

import math

from hybrid.references._common import non_negative, phi_rad, positive


def rankine_ka(phi_deg: float) -> float:
    """Rankine active coefficient K_a = tan^2(45 deg - phi/2) (smooth vertical wall, level fill)."""
    phi = phi_rad(phi_deg)
    return math.tan(math.pi / 4 - phi / 2) ** 2


def rankine_kp(phi_deg: float) -> float:
    """Rankine passive coefficient K_p = tan^2(45 deg + phi/2) = 1 / K_a."""
    phi = phi_rad(phi_deg)
    return math.tan(math.pi / 4 + phi / 2) ** 2


def tension_crack_depth(c: float, phi_deg: float, gamma: float, q: float = 0.0) -> float:
    """Depth [m] where the Rankine active pressure K_a (gamma z + q) - 2 c sqrt(K_a) is zero."""
    c = non_negative(c, "c", "kPa")
    gamma = positive(gamma, "gamma", "kN/m3")
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
    gamma = non_negative(gamma, "gamma", "kN/m3")
    H = positive(H, "H", "m")
    c = non_negative(c, "c", "kPa")
    q = non_negative(q, "q", "kPa")
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
    return 1.0 - math.sin(phi_rad(phi_deg))


def friction_ratio(phi_residual_deg: float, phi_peak_deg: float) -> float:
    """Residual-to-peak shear strength ratio at one normal stress: tan(phi_r) / tan(phi_p).

    E.g. to carry a clay's drained loss of strength over to its undrained strength
    (c_u,r = c_u x this ratio), an assumption where only drained angles are published.
    """
    peak = math.tan(phi_rad(phi_peak_deg, "phi_peak_deg"))
    if peak == 0.0:
        raise ValueError("phi_peak_deg = 0: the ratio needs a peak friction angle above zero")
    return math.tan(phi_rad(phi_residual_deg, "phi_residual_deg")) / peak
