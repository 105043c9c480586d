"""Closed-form references the verification cases are checked against.

Pure functions, SI units (m, kPa, kN/m, kN/m3), angles in degrees at the interface.
Sign convention of the package: **tension positive, compression negative**. The bearing
capacities, earth-pressure thrusts and coefficients below are magnitudes (positive numbers,
as in the textbooks); the stress fields (strip load, oedometer) are signed, tension positive.

Every name is importable from here (``from hybrid import references as ref``); the sources are
cited in the sub-module that holds them:

- ``bearing``: strip-footing bearing capacity (Prandtl-Reissner, Terzaghi, Meyerhof, Vesic,
  Brinch Hansen).
- ``earth_pressure``: Rankine's coefficients and thrusts, K0 (elastic, Jaky), the
  residual-to-peak strength ratio.
- ``elastic``: the uniform strip load on an elastic half-space (Poulos & Davis, Flamant
  integrated) and the oedometric column under self-weight.
- ``slopes``: limit equilibrium on circular slip surfaces (Fellenius, Bishop, Whitman & Bailey).
- ``granular``: granular column collapse (Lube et al. 2005, arXiv:1512.05180, Bui et al. 2008),
  with what was read where and what is unverified.
- ``carsington``: Carsington Dam, chainage 725 (Bala 2008, Skempton 1985, Chen et al. 1992).
"""

from __future__ import annotations

from hybrid.references.bearing import (
    BEARING_METHODS,
    bearing_capacity_factors,
    n_c,
    n_gamma,
    n_q,
    prandtl_limit_load,
    strip_footing_capacity,
    strip_footing_estimates,
    terzaghi_n_c,
    terzaghi_n_q,
)
from hybrid.references.carsington import (
    CARSINGTON_CORE_DISPLACEMENT,
    CARSINGTON_CREST_CRACK_MM,
    CARSINGTON_FAILURE_FILL_LEVEL,
    CARSINGTON_FOS,
    CARSINGTON_POST_FAILURE,
    CARSINGTON_REPORT_LEVELS,
    Band,
    CarsingtonTable62,
    CarsingtonTable63,
)
from hybrid.references.earth_pressure import (
    friction_ratio,
    k0_elastic,
    k0_jaky,
    rankine_active_thrust,
    rankine_ka,
    rankine_kp,
    rankine_passive_thrust,
    tension_crack_depth,
)
from hybrid.references.elastic import (
    StripStress,
    flamant_centreline,
    flamant_strip_stress,
    oedometer_settlement,
    oedometer_stress,
    oedometric_modulus,
    strip_load_angles,
)
from hybrid.references.granular import (
    LUBE2005_HEIGHT_BREAK,
    LUBE2005_LINEAR_MAX,
    LUBE2005_POWER_MIN,
    RODS2015_BREAK,
    RODS2015_RUNOUT_BREAK,
    CollapseExperiment,
    bui2008_collapse,
    bui2008_final_surface,
    granular_final_height_lube2005,
    granular_final_height_rods2015,
    granular_runout_lube2005,
    granular_runout_rods2015,
)
from hybrid.references.slopes import (
    SlipCircle,
    Soil,
    circle_factor,
    critical_circle,
    uniform_soil,
)

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
    "bui2008_final_surface",
    "Band",
    "CarsingtonTable63",
    "CarsingtonTable62",
    "CARSINGTON_FAILURE_FILL_LEVEL",
    "CARSINGTON_FOS",
    "CARSINGTON_CORE_DISPLACEMENT",
    "CARSINGTON_REPORT_LEVELS",
    "CARSINGTON_POST_FAILURE",
    "CARSINGTON_CREST_CRACK_MM",
]
