"""The Mohr-Coulomb kernel's material table, built from ``Material`` for both phases.

One row per material, ``[K, G, c, sin phi, cos phi, sin psi, t]`` (kPa, -), as
``mohr_coulomb_update`` reads it. The continuum (dolfinx) and discrete (numba) phases take
their tables from :func:`kernel_table`, so a material means the same in both.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from hybrid.materials import Material, Strength

__all__ = ["NO_TENSION_CUTOFF", "NO_YIELD", "kernel_row", "kernel_table", "tension_cutoff"]

#: Tension cut-off of a frictionless (phi = 0) strength without a given one [kPa]: none.
NO_TENSION_CUTOFF = 1.0e30
#: Cohesion and tension cut-off of the row of an elastic material [kPa]: it never yields.
NO_YIELD = 1.0e30


def tension_cutoff(strength: Strength) -> float:
    """Tension cut-off t of a strength [kPa]: the given value, at most the apex c cot(phi).

    The kernel assumes t <= c cot(phi) (no tension beyond the apex); without a given value the
    cut-off is the apex, and for phi = 0 (Tresca) it is inactive (``NO_TENSION_CUTOFF``).
    """
    if strength.phi > 0:
        apex = strength.cohesion / math.tan(math.radians(strength.phi))
    else:
        apex = NO_TENSION_CUTOFF
    if strength.tensile_strength is not None:
        return min(float(strength.tensile_strength), apex)
    return apex


def kernel_row(material: Material, strength: Strength | None = None) -> tuple[float, ...]:
    """``[K, G, c, sin phi, cos phi, sin psi, t]`` of a material (kPa, -).

    ``strength`` replaces the material's peak strength (a reduced or residual strength); an
    elastic material gets c = t = ``NO_YIELD`` and phi = psi = 0, so that it never yields.
    """
    K, G = material.bulk_modulus, material.shear_modulus
    if not material.is_plastic:
        return (K, G, NO_YIELD, 0.0, 1.0, 0.0, NO_YIELD)
    s = material.peak if strength is None else strength
    phi, psi = math.radians(s.phi), math.radians(s.psi)
    return (K, G, s.cohesion, math.sin(phi), math.cos(phi), math.sin(psi), tension_cutoff(s))


def kernel_table(materials: Sequence[Material],
                 strength_factor: float = 1.0) -> tuple[np.ndarray, np.ndarray]:
    """The kernel's material table (n, 7) and the elastic flags (n,) of ``materials``.

    Strengths are divided by ``strength_factor`` (``Material.weakened``; 1: as given). The
    flag marks the materials whose Mohr-Coulomb return the discrete kernels skip (their rows
    never yield, so the continuum needs no flag).
    """
    rows = []
    for i, m in enumerate(materials):
        if not isinstance(m, Material):
            raise TypeError(f"materials[{i}] is {type(m).__name__}: expected "
                            "hybrid.materials.Material")
        if m.is_plastic and strength_factor != 1.0:
            m = m.weakened(strength_factor)
        rows.append(kernel_row(m))
    elastic = np.array([not m.is_plastic for m in materials], dtype=bool)
    return np.array(rows, dtype=float).reshape(len(rows), 7), elastic
