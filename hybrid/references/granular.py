"""Granular column collapse (plane strain): published run-out and height laws, one experiment.

Lube, Huppert, Sparks & Freundt (2005), Phys. Rev. E 72, 041301 (laws as quoted in open
secondary sources); arXiv:1512.05180 (2015), "Failure mechanism of true 2D granular flows"
(aluminium rods, laws of its abstract); Bui, Fukagawa, Sako & Ohno (2008), Int. J. Numer.
Anal. Meth. Geomech. 32(12), 1537-1570 (the aluminium-bar experiment: geometry and material).
The comment below says what was read where and what is unverified.
"""

from __future__ import annotations

from typing import NamedTuple

from hybrid.references._common import positive

# A column of height H0 and length L0 (aspect ratio a = H0 / L0) against a back wall is released
# by removing the other wall and spreads over a horizontal base to a deposit of run-out L_inf
# (measured from the back wall) and height H_inf. Provenance, read for this module:
#
# - Lube, Huppert, Sparks & Freundt (2005), "Collapses of two-dimensional granular columns",
#   Phys. Rev. E 72, 041301 (doi:10.1103/PhysRevE.72.041301). The paper itself was not
#   accessible; its abstract (quoted verbatim in the reference list of K. Kumar's Cambridge PhD
#   thesis, github.com/kks32/phd-thesis, References/references.bib) states the regime split:
#   "two main flow regimes at a ~ 1.8, where a = h_i/d_i and h_i and d_i are the initial height
#   and width of the column", final geometry "independent of basal and internal friction". The
#   coefficients (1.2 a; 1.9 a^(2/3); H_inf/d_i = a^(2/5)) are SECONDARY: open quotations, not
#   the paper (see the function docstrings).
# - arXiv:1512.05180 (Dec. 2015), "Failure mechanism of true 2D granular flows": column
#   collapses of aluminium rods (true 2-D grains, the material of Bui et al. 2008). The laws
#   below are stated in its abstract (text, read as mirrored at koineu.com); the author list
#   and journal version were not verified here.
# - Bui, Fukagawa, Sako & Ohno (2008): see :func:`bui2008_collapse` (geometry and material)
#   and :func:`bui2008_final_surface` (the measured final surface, as digitised by a third
#   party).
#
# Not encoded, because no value could be verified: Lajeunesse, Monnier & Homsy (2005), Phys.
# Fluids 17, 103302 (glass beads in a rectangular channel; its abstract gives only the form of
# the laws: H_f/L_i and dL/L_i "exhibit simple power laws whose exponents depend on a and on the
# flow geometry", time scale the free fall of the column, flowing-layer shear rate
# 0.3 sqrt(g/d); abstract as quoted in the bibliography of Kumar's thesis cited above), and
# Balmforth & Kerswell (2005), J. Fluid Mech. 538, 399-428, whose abstract gives exponents only
# ((l_inf - L)/L ~ a^(0.9 +- 0.1) in wide channels, a^(0.65 +- 0.05) in narrow slots;
# H/h_inf ~ a^0.6 wide, a^0.5 narrow) and states that the prefactors depend on the material.

#: Lube et al. (2005): largest a of the linear run-out regime (abstract: regimes split at
#: a ~ 1.8; the quotations give the linear law for a < 1.8).
LUBE2005_LINEAR_MAX = 1.8
#: Lube et al. (2005): smallest a of the a^(2/3) run-out regime (secondary: an open validation
#: note reports it so from Dunatunga & Kamrin 2015, arXiv:1411.5447, table p. 11, and reports a
#: single switch at a = 2.3 from Staron & Hinch, arXiv:physics/0501022, sec. III, and Szewc,
#: arXiv:1602.07881, eqs. 22, 24; none of these was read here). The two laws do not meet
#: anywhere in 1.8 <= a <= 2.8 (they cross only at a = (1.9/1.2)^3 = 3.97), so between the
#: bounds no law is given.
LUBE2005_POWER_MIN = 2.8
#: Lube et al. (2005): a below which the deposit keeps the initial height (secondary, one
#: quotation; see :func:`granular_final_height_lube2005`).
LUBE2005_HEIGHT_BREAK = 1.15
#: arXiv:1512.05180 (abstract): a below which H_inf = H0 (aluminium rods).
RODS2015_BREAK = 0.65
#: arXiv:1512.05180 (abstract): a where the excess run-out law changes exponent.
RODS2015_RUNOUT_BREAK = 1.5

def _aspect(aspect: float) -> float:
    return positive(aspect, "aspect", "(H0/L0, dimensionless)")


def granular_runout_lube2005(aspect: float, branch: str = "auto") -> float:
    """Normalised run-out (L_inf - L0) / L0 of a plane column collapse, Lube et al. (2005).

    Lube, Huppert, Sparks & Freundt (2005), Phys. Rev. E 72, 041301: a = H0 / L0 with L0 the
    initial width of the column (their d_i) and L_inf the farthest reach of the deposit
    (d_inf), both from the back wall; grains of several kinds (quartz sand among them) in a
    horizontal channel. The law, as quoted in open secondary sources (the paper itself was
    not read), is

    - ``branch="linear"``: 1.2 a, for a < 1.8 (every quotation found);
    - ``branch="power"``: 1.9 a^(2/3), for a > 2.8 (some quotations put a single switch at
      2.3 instead; see :data:`LUBE2005_POWER_MIN`).

    ``branch="auto"`` picks the linear law for a <= 1.8 and the power law for a >= 2.8 and
    raises ValueError in between, where the two do not meet (1.2 a and 1.9 a^(2/3) cross only
    at a = 3.97): there, choose a branch explicitly and say so.

    Args:
        aspect: initial aspect ratio a = H0 / L0 (> 0).
        branch: ``"auto"``, ``"linear"`` or ``"power"``.

    Returns:
        (L_inf - L0) / L0, dimensionless.
    """
    a = _aspect(aspect)
    if branch == "auto":
        if a <= LUBE2005_LINEAR_MAX:
            branch = "linear"
        elif a >= LUBE2005_POWER_MIN:
            branch = "power"
        else:
            raise ValueError(
                f"aspect = {a:g} is between the two regimes of Lube et al. (2005) "
                f"({LUBE2005_LINEAR_MAX} < a < {LUBE2005_POWER_MIN}), where the laws 1.2 a and "
                "1.9 a^(2/3) do not meet: pass branch='linear' or 'power'")
    if branch == "linear":
        return 1.2 * a
    if branch == "power":
        return 1.9 * a ** (2.0 / 3.0)
    raise ValueError(f"branch = {branch!r}: choose 'auto', 'linear' or 'power'")


def granular_final_height_lube2005(aspect: float) -> float:
    """Final deposit height over initial width, H_inf / L0, Lube et al. (2005). SECONDARY.

    H_inf / L0 = a (the deposit keeps the column height, H_inf = H0) for a <= 1.15 and
    a^(2/5) above. Not read in the paper: a^(2/5) is quoted for large a by an open code's
    validation notes, and the 1.15 break by one MATLAB script only; the exponent agrees with
    Balmforth & Kerswell's (2005) abstract for wide channels (H / h_inf ~ a^0.6, i.e.
    h_inf / L ~ a^0.4). The branches do not meet at 1.15 (1.15 against 1.057). Use as a band,
    not a bar, until checked against the paper.

    Args:
        aspect: initial aspect ratio a = H0 / L0 (> 0).

    Returns:
        H_inf / L0, dimensionless.
    """
    a = _aspect(aspect)
    return a if a <= LUBE2005_HEIGHT_BREAK else a ** 0.4


def granular_runout_rods2015(aspect: float, total: bool = False) -> float:
    """Run-out of a collapsing column of aluminium rods (true 2-D grains), arXiv:1512.05180.

    "Failure mechanism of true 2D granular flows" (arXiv:1512.05180, 2015), abstract (stated in
    text): with a = h0 / d0 (initial height over width) and d the maximum run-out,
    (d - d0) / d0 = 3.25 a^0.96 for 0.65 < a < 1.5 and 3.80 a^0.73 for a > 1.5; d / d0 =
    4.30 a^0.72 for every a > 0.65 (``total=True``). The abstract gives no run-out law for
    a <= 0.65 (ValueError). The excess laws do not meet at a = 1.5 (4.80 against 5.11).

    Args:
        aspect: initial aspect ratio a = H0 / L0 (> 0.65).
        total: return d / d0 (the single-law fit) instead of (d - d0) / d0.

    Returns:
        (L_inf - L0) / L0, or L_inf / L0 with ``total``, dimensionless.
    """
    a = _aspect(aspect)
    if a <= RODS2015_BREAK:
        raise ValueError(f"aspect = {a:g}: arXiv:1512.05180 states run-out laws only for "
                         f"a > {RODS2015_BREAK}")
    if total:
        return 4.30 * a**0.72
    if a < RODS2015_RUNOUT_BREAK:
        return 3.25 * a**0.96
    return 3.80 * a**0.73


def granular_final_height_rods2015(aspect: float) -> float:
    """Final height over initial height, H_inf / H0, aluminium rods, arXiv:1512.05180.

    Abstract (stated in text): H_inf / H0 = 1 for a < 0.65; h0 / h_inf = 1.42 a^(2/3) for
    a > 0.65, so H_inf / H0 = 1 / (1.42 a^(2/3)) (0.939 just above 0.65: the branches do not
    meet). a = 0.65 itself is given to the first branch.

    Args:
        aspect: initial aspect ratio a = H0 / L0 (> 0).

    Returns:
        H_inf / H0, dimensionless.
    """
    a = _aspect(aspect)
    if a <= RODS2015_BREAK:
        return 1.0
    return 1.0 / (1.42 * a ** (2.0 / 3.0))


class CollapseExperiment(NamedTuple):
    """A published plane column-collapse experiment: its geometry and material.

    The column 0 <= x <= ``length``, 0 <= y <= ``height`` [m] stands against a back wall at
    x = 0 and is released towards +x. Material values are those of the paper's simulation of
    the test (what a continuum model of it uses), not measurements of the grains unless
    ``notes`` says so.
    """

    name: str
    length: float  # L0 [m]
    height: float  # H0 [m]
    friction_angle: float  # [deg]
    cohesion: float  # [kPa]
    dilatancy_angle: float  # [deg]
    density: float  # [kg/m3]
    youngs_modulus: float  # [kPa]
    poisson: float
    source: str
    notes: str

    @property
    def aspect(self) -> float:
        """Initial aspect ratio a = H0 / L0."""
        return self.height / self.length

    @property
    def unit_weight(self) -> float:
        """Unit weight [kN/m3] of ``density`` under g = 9.81 m/s2."""
        return self.density * 9.81e-3


def bui2008_collapse() -> CollapseExperiment:
    """The aluminium-bar column collapse of Bui, Fukagawa, Sako & Ohno (2008).

    Bui, H. H., Fukagawa, R., Sako, K. & Ohno, S. (2008), "Lagrangian meshfree particles method
    (SPH) for large deformation and failure flows of geomaterial using elastic-plastic soil
    constitutive model", Int. J. Numer. Anal. Meth. Geomech. 32(12), 1537-1570,
    doi:10.1002/nag.688. The paper was not accessible; every value here is as reproduced by
    open benchmark inputs that cite it (secondary):

    - column L0 = 0.2 m long, H0 = 0.1 m high (a = 0.5) of aluminium bars, released towards
      +x (MaterialPointSolver.jl docs "2D Soil Collapse Test"; HydraxMPM and SPHinXsys inputs
      use the same column);
    - friction angle 19.8 deg, cohesion 0, dilatancy 0, density 2650 kg/m3, Young's modulus
      840 kPa, Poisson's ratio 0.3 (KratosMultiphysics/Examples,
      particle_mechanics/validation/granular_flow_2D/README.md, "according to the experiment
      conducted by Bui et al., 2008"; MaterialPointSolver.jl gives the same with bulk modulus
      700 kPa = 840 / (3 (1 - 2 x 0.3))). These are the simulation's parameters; 2650 kg/m3
      is close to solid aluminium, not a measured bulk density of the bar packing.

    Not found: the bar diameters and lengths, the packing, how the wall was removed, how the
    friction angle was measured, and any run-out or height the paper states in its text. The
    measured final surface is known here only as digitised from a figure by a third party
    (:func:`bui2008_final_surface`).

    Returns:
        The experiment as a :class:`CollapseExperiment`.
    """
    return CollapseExperiment(
        name="Bui et al. (2008) aluminium-bar collapse",
        length=0.2, height=0.1, friction_angle=19.8, cohesion=0.0, dilatancy_angle=0.0,
        density=2650.0, youngs_modulus=840.0, poisson=0.3,
        source="Bui, Fukagawa, Sako & Ohno (2008), Int. J. Numer. Anal. Meth. Geomech. 32(12), "
               "1537-1570, doi:10.1002/nag.688; parameters as in KratosMultiphysics/Examples "
               "granular_flow_2D",
        notes="material values are the simulation's (secondary); bar size, packing and wall "
              "removal not found",
    )


#: Bui et al.'s (2008) measured final surface of the a = 0.5 column, (x, y) [m] from the back
#: wall: the points of MaterialPointSolver.jl (github.com/LandslideSIM/MaterialPointSolver.jl,
#: docs/src/assets/data/2d_collapse_experiments/surface.csv, commit 932e6c77), which its
#: "2D Soil Collapse Test" documentation draws, as the experiment, over its simulation of Bui
#: et al.'s test (it cites the paper for the test). Digitised from the paper's figure by that
#: project, not read in the paper here: an accuracy of about a millimetre at best.
_BUI2008_SURFACE = (
    (0.00012288, 0.099231753), (0.019603788, 0.099281704), (0.03983696, 0.095872045),
    (0.060043158, 0.089000779), (0.080267338, 0.084437251), (0.100083918, 0.077564986),
    (0.120302104, 0.072232212), (0.140127675, 0.066513816), (0.160348858, 0.061565666),
    (0.180159444, 0.053924154), (0.199979021, 0.047436512), (0.220200204, 0.042488361),
    (0.240790026, 0.034848848), (0.262186058, 0.030672941), (0.282023617, 0.026493037),
    (0.3022448, 0.021544886), (0.322094348, 0.018903475), (0.342312534, 0.013570701),
    (0.362162081, 0.010929289), (0.38239825, 0.007904254), (0.402235809, 0.00372435),
    (0.422094348, 0.002236808), (0.442348498, 0.001519511),
)


def bui2008_final_surface() -> tuple[tuple[float, float], ...]:
    """The measured final surface of Bui et al.'s (2008) column (a = 0.5), (x, y) [m].

    x from the back wall along the flow, y above the floor, from the wall (y = 0.099 m: the
    column's height H0 = 0.1 m kept there) to the toe (x = 0.442 m, y = 0.0015 m: the
    run-out, (L_inf - L0) / L0 = 1.21). SECONDARY: digitised from the paper's figure by a
    third party (MaterialPointSolver.jl's documentation data,
    docs/src/assets/data/2d_collapse_experiments/surface.csv, drawn there as the experiment of
    Bui et al. 2008); the paper itself was not read.

    Returns:
        The points, ordered by x.
    """
    return _BUI2008_SURFACE
