"""Elastic stress fields: a uniform strip load on a half-space and a laterally confined column.

Poulos & Davis (1974), Elastic Solutions for Soil and Rock Mechanics, section 2.4 / eq. 3.4:
the stress under a uniform strip load, by integration of Flamant's line load (plane strain,
independent of the elastic constants). The oedometric column under self-weight: constrained
modulus, vertical and horizontal stress (K0 = nu / (1 - nu)) and the settlement of its top.
Stresses are signed, tension positive, in kPa.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from hybrid.references._common import non_negative, positive
from hybrid.references.earth_pressure import k0_elastic

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
    B = positive(width, "width", "m")
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
    E = positive(E, "E", "kPa")
    k0_elastic(nu)  # validates nu
    return E * (1 - nu) / ((1 + nu) * (1 - 2 * nu))


def oedometer_stress(gamma: float, nu: float, z: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(sigma_v, sigma_h) [kPa] in a laterally confined elastic column under self-weight.

    sigma_v = -gamma z, sigma_h = K0 sigma_v with K0 = nu / (1 - nu); tension positive, ``z``
    the depth below the free top [m]. sigma_zz (out of plane) equals sigma_h.
    """
    gamma = non_negative(gamma, "gamma", "kN/m3")
    z = np.asarray(z, dtype=float)
    sv = -gamma * z
    return sv, k0_elastic(nu) * sv


def oedometer_settlement(gamma: float, H: float, E: float, nu: float) -> float:
    """Settlement [m] of the top of a confined column of height H under self-weight.

    gamma H^2 / (2 M), M the constrained modulus (positive downward movement).
    """
    gamma = non_negative(gamma, "gamma", "kN/m3")
    H = positive(H, "H", "m")
    return gamma * H**2 / (2.0 * oedometric_modulus(E, nu))
