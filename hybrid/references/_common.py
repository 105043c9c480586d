"""Argument checks shared by the closed-form references: friction angles, signs of magnitudes.

Each returns the value as a float (an angle in radians) or raises ValueError naming the
argument, its unit and the admissible range, so that every reference refuses a bad input with
the same message.
"""

from __future__ import annotations

import math

__all__ = ["non_negative", "phi_rad", "positive"]


def phi_rad(phi_deg: float, name: str = "phi_deg", upper: float = 90.0) -> float:
    """``phi_deg`` in radians; ValueError outside [0, ``upper``) degrees or not finite."""
    phi = float(phi_deg)
    if not math.isfinite(phi) or phi < 0.0 or phi >= upper:
        raise ValueError(f"{name} = {phi_deg!r} deg is outside [0, {upper:g}): give the friction "
                         "angle in degrees")
    return math.radians(phi)


def non_negative(value: float, name: str, unit: str) -> float:
    """``value`` as a float; ValueError when negative or not finite."""
    value = float(value)
    if not math.isfinite(value) or value < 0.0:
        raise ValueError(f"{name} = {value!r} {unit} must be >= 0")
    return value


def positive(value: float, name: str, unit: str) -> float:
    """``value`` as a float; ValueError when not above zero or not finite."""
    value = float(value)
    if not math.isfinite(value) or value <= 0.0:
        raise ValueError(f"{name} = {value!r} {unit} must be > 0")
    return value
