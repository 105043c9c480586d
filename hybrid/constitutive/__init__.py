"""Constitutive laws shared by the continuum (dolfinx) and discrete (numba) phases."""

from hybrid.constitutive.mohr_coulomb import (
    NO_TENSION_CUTOFF,
    REGION_NAMES,
    VERTEX_STABILISATION,
    MohrCoulombParameters,
    mohr_coulomb_point,
    mohr_coulomb_update,
    return_principal,
    update_stress,
    yield_function,
)

__all__ = [
    "MohrCoulombParameters",
    "mohr_coulomb_point",
    "mohr_coulomb_update",
    "return_principal",
    "update_stress",
    "yield_function",
    "NO_TENSION_CUTOFF",
    "VERTEX_STABILISATION",
    "REGION_NAMES",
]
