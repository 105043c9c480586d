"""The Mohr-Coulomb kernel's material table, built from ``Material`` for both phases.

One row per material, ``TABLE_WIDTH`` columns, as ``mohr_coulomb_update`` and the discrete
element kernels read it: the peak strength ``[K, G, c, sin phi, cos phi, sin psi, t]`` (kPa, -)
then the softening columns ``[c_r, phi_p, phi_r, psi_p, psi_r, t_r, u_r]`` (kPa, rad, kPa, m;
``hybrid.constitutive.softening``). A material without softening has ``u_r = 0`` and its
residual columns equal to the peak. The continuum (dolfinx) and discrete (numba) phases take
their tables from :func:`kernel_table`, so a material means the same in both.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from hybrid.materials import Material, Strength

__all__ = ["NO_TENSION_CUTOFF", "NO_YIELD", "TABLE_WIDTH", "kernel_row", "kernel_table",
           "tension_cutoff"]

# columns of a row
BULK_MODULUS = 0  # K [kPa]
SHEAR_MODULUS = 1  # G [kPa]
COHESION = 2  # peak c [kPa]
SIN_PHI = 3  # sin of the peak phi
COS_PHI = 4  # cos of the peak phi
SIN_PSI = 5  # sin of the peak psi
TENSION = 6  # peak tension cut-off t [kPa]
RESIDUAL_COHESION = 7  # c_r [kPa]
PEAK_PHI = 8  # phi_p [rad]
RESIDUAL_PHI = 9  # phi_r [rad]
PEAK_PSI = 10  # psi_p [rad]
RESIDUAL_PSI = 11  # psi_r [rad]
RESIDUAL_TENSION = 12  # t_r [kPa]
SOFTENING_DISPLACEMENT = 13  # u_r [m]; 0: no softening
#: Number of columns of a kernel-table row.
TABLE_WIDTH = 14

#: Tension cut-off of a frictionless (phi = 0) strength without a given one [kPa]: none.
NO_TENSION_CUTOFF = 1.0e30
#: Cohesion and tension cut-off of the row of an elastic material [kPa]: it never yields.
NO_YIELD = 1.0e30


def tension_cutoff(strength: Strength) -> float:
    """Tension cut-off t of a strength [kPa]: the given value, at most the apex c cot(phi).

    The kernel assumes t <= c cot(phi) (no tension beyond the apex); without a given value the
    cut-off is the apex, and for phi = 0 (Tresca) it is inactive (``NO_TENSION_CUTOFF``).
    """
    cutoff = strength.cutoff
    return NO_TENSION_CUTOFF if cutoff is None else float(min(cutoff, NO_TENSION_CUTOFF))


def kernel_row(material: Material) -> tuple[float, ...]:
    """The kernel-table row of a material (module docstring; ``TABLE_WIDTH`` values).

    An elastic material gets c = t = ``NO_YIELD`` and phi = psi = 0, so that it never yields;
    a material without a residual strength gets u_r = 0 (no softening).
    """
    K, G = material.bulk_modulus, material.shear_modulus
    if not material.is_plastic:
        return (K, G, NO_YIELD, 0.0, 1.0, 0.0, NO_YIELD,
                NO_YIELD, 0.0, 0.0, 0.0, 0.0, NO_YIELD, 0.0)
    p = material.peak
    r = p if material.residual is None else material.residual
    phi, psi = math.radians(p.phi), math.radians(p.psi)
    u_r = 0.0 if material.residual is None else float(material.softening_displacement or 0.0)
    return (K, G, p.cohesion, math.sin(phi), math.cos(phi), math.sin(psi), tension_cutoff(p),
            r.cohesion, phi, math.radians(r.phi), psi, math.radians(r.psi),
            residual_tension(p, r), u_r)


def residual_tension(peak: Strength, residual: Strength) -> float:
    """The residual column t_r of the tension cut-off [kPa] (``softening.strength_at``).

    A cut-off given at either end is interpolated linearly between finite values and never
    rises as the material softens: a residual left None keeps the peak's given cut-off (at
    most the residual apex), a residual given with a peak left None falls from the peak apex.
    Given at neither end, the cut-off is the apex c cot(phi) of the strength in force
    (``NO_TENSION_CUTOFF`` marks it).
    """
    apex = tension_cutoff(Strength(cohesion=residual.cohesion, phi=residual.phi))
    if residual.tensile_strength is not None:
        return min(float(residual.tensile_strength), apex)
    if peak.tensile_strength is not None:
        return min(tension_cutoff(peak), apex)
    return NO_TENSION_CUTOFF


def kernel_table(materials: Sequence[Material],
                 strength_factor: float = 1.0) -> tuple[np.ndarray, np.ndarray]:
    """The kernel's material table (n, ``TABLE_WIDTH``) and the elastic flags (n,) of ``materials``.

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
    return np.array(rows, dtype=float).reshape(len(rows), TABLE_WIDTH), elastic
