"""Carsington Dam, chainage 725: the published section's materials, factors of safety, movements.

G. S. Bala (2008), thesis, chapter 6 (Tables 6.2 and 6.3; 6.2.4, 6.2.5, 6.3, 6.3.1.2, Figure
6.19), which quotes B. S. Morton & A. W. Skempton (1986, report to Severn Trent), A. W.
Skempton & P. R. Vaughan (1993, Geotechnique) and Z. Chen (1990, PhD thesis, Alberta); A. W.
Skempton (1985), as quoted by the Environment Agency (Lessons from historical dam
incidents). The material tables are case parameters (each value overridable by name); the
factors of safety, core displacements and post-failure movements are the values a case
compares with, the displacements as :class:`Band` ranges.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple

from hybrid.parameters import CaseParameters


class Band(NamedTuple):
    """A published value drawn beside a computed history.

    ``low`` to ``high`` (in the plotted unit) at the levels ``level_low`` to ``level_high``.
    """

    label: str
    low: float
    high: float
    level_low: float
    level_high: float

    @property
    def middle(self) -> float:
        """The middle of the published range, (low + high) / 2: the value a check compares."""
        return 0.5 * (self.low + self.high)


@dataclass
class CarsingtonTable63(CaseParameters):
    """The thesis's Table 6.3 at Ch. 725 (undrained total stress), as case parameters.

    A case derives its ``Parameters`` from it, so each value is overridable (``--set``) under
    its name here; a run with all of them at these defaults uses the published section's
    materials. The mudstone is elastic, the clays phi = 0; Zone I and Zone II share "fill".
    """

    foundation_E: float = 125_000.0  # mudstone, elastic [kPa] (Table 6.3)
    foundation_nu: float = 0.35  # [-]
    foundation_gamma: float = 20.0  # [kN/m3]
    yellow_clay_cu: float = 15.0  # undrained strength [kPa] (Table 6.3, phi = 0)
    yellow_clay_E: float = 3_000.0  # [kPa]
    yellow_clay_nu: float = 0.42  # [-]
    yellow_clay_gamma: float = 19.5  # [kN/m3]
    core_cu: float = 52.0  # [kPa] (Table 6.3, phi = 0)
    core_E: float = 2_500.0  # [kPa]
    core_nu: float = 0.43  # [-]
    core_gamma: float = 18.5  # [kN/m3]
    fill_c: float = 13.5  # Zone I and Zone II cohesion [kPa] (Table 6.3)
    fill_phi: float = 24.0  # [deg]
    fill_E: float = 60_000.0  # [kPa]
    fill_nu: float = 0.38  # [-]
    fill_gamma: float = 21.0  # [kN/m3]


@dataclass
class CarsingtonTable62(CaseParameters):
    """The thesis's Table 6.2 drained angles at Ch. 725, as case parameters.

    The peak angles give the residual-to-peak ratio of the clays' softening; the residual
    angles are the friction of separated elements (the fill's: Zone II's).
    """

    yellow_clay_peak_phi: float = 20.0  # drained phi' [deg] (Table 6.2; softening's ratio)
    core_peak_phi: float = 21.0  # drained phi' [deg] (Table 6.2; softening's ratio)
    yellow_clay_residual_phi: float = 12.0  # contact friction [deg] (Table 6.2)
    core_residual_phi: float = 13.0  # [deg] (Table 6.2)
    fill_residual_phi: float = 14.5  # Zone I, Zone II, berm [deg] (Table 6.2, Zone II)


#: fill level when the upstream slope slipped [m OD]: one metre below the final crest level
#: (200.5 m OD) on 4 June 1984 (Skempton 1985, as quoted by the Environment Agency); the
#: thesis (6.3) quotes earlier analyses: "0.5 m lower than the final height", 200.0 m OD
CARSINGTON_FAILURE_FILL_LEVEL = 199.5
#: factors of safety at Ch. 725 (thesis 6.2.5, quoting Morton & Skempton 1986; 6.3, quoting
#: Skempton & Vaughan 1993): (F, source)
CARSINGTON_FOS = {
    "limit_equilibrium_intact_peak": (1.4, "LE, intact peak strengths (1.41)"),
    "limit_equilibrium_pre_sheared": (1.2, "LE, peak strengths with pre-existing shears (1.21)"),
    "finite_element_before_collapse": (1.1, "FE and LE analyses, just before collapse (about 1.1)"),
}
#: horizontal displacement of the core at node A [mm] against the fill level [m OD] (thesis
#: 6.3.1.2, Figure 6.19); the first two are at :data:`CARSINGTON_REPORT_LEVELS` ("about
#: 150 mm" drawn 140-160 mm). The thesis gives no fill level for the observed range or for
#: Chen's: both are drawn at 199-200 m OD, where the dam slipped
CARSINGTON_CORE_DISPLACEMENT = (
    Band("thesis: about 150 mm up to 198 m OD", 140.0, 160.0, 198.0, 198.0),
    Band("thesis: 400-450 mm at 200.5 m OD", 400.0, 450.0, 200.5, 200.5),
    Band("observed at the core's base: 200-275 mm", 200.0, 275.0, 199.0, 200.0),
    Band("Chen (1990), finite elements: 100-150 mm", 100.0, 150.0, 199.0, 200.0))
#: fill levels of the thesis's core displacements [m OD]
CARSINGTON_REPORT_LEVELS = (198.0, 200.5)
#: the longitudinal crack on the crest before the slide [mm]: about 50 mm wide when first
#: reported (07:30, 4 June 1984), 130 mm at most by that evening (thesis section 6.2.4)
CARSINGTON_CREST_CRACK_MM = (50.0, 130.0)
#: movements observed after the 1984 slip [m]: (value, source), keyed by the discrete phase's
#: measure ("upstream_toe_movement": towards upstream; "crest_drop": down)
CARSINGTON_POST_FAILURE = {
    "upstream_toe_movement": (12.0, "observed: upstream toe moved 11-13 m (Environment Agency: "
                              "slipped some 11 m; thesis 6.2.4: 13 m)"),
    "crest_drop": (10.0, "observed: crest dropped about 10 m (at the full height)"),
}
