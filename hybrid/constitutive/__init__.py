"""Constitutive laws shared by the continuum (dolfinx) and discrete (numba) phases."""

from hybrid.constitutive.mohr_coulomb import (
    REGION_NAMES,
    VERTEX_STABILISATION,
    mohr_coulomb_point,
    mohr_coulomb_update,
    return_principal,
    update_stress,
    yield_function,
)
from hybrid.constitutive.table import (
    NO_TENSION_CUTOFF,
    NO_YIELD,
    kernel_row,
    kernel_table,
    tension_cutoff,
)

__all__ = [
    "kernel_row",
    "kernel_table",
    "mohr_coulomb_point",
    "mohr_coulomb_update",
    "return_principal",
    "tension_cutoff",
    "update_stress",
    "yield_function",
    "NO_TENSION_CUTOFF",
    "NO_YIELD",
    "VERTEX_STABILISATION",
    "REGION_NAMES",
]
