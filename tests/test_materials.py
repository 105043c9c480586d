"""Material validation: errors name the material and the parameter."""

import math
import warnings

import pytest

from hybrid.constitutive.table import tension_cutoff
from hybrid.materials import Bond, Contact, Material, MaterialError, MaterialWarning


@pytest.mark.parametrize(
    ("kwargs", "param"),
    [
        ({"E": 0.0}, "E"),
        ({"E": -5.0}, "E"),
        ({"nu": 0.5}, "nu"),
        ({"nu": -0.1}, "nu"),
        ({"unit_weight": -1.0}, "unit_weight"),
        ({"cohesion": -1.0}, "cohesion"),
        ({"phi": 90.0}, "phi"),
        ({"phi": 20.0, "psi": 25.0}, "psi"),
        ({"phi": 20.0, "psi": -1.0}, "psi"),
        ({"tensile_strength": -1.0}, "tensile_strength"),
        ({"E": float("nan")}, "E"),
        ({"plastic": True}, "cohesion"),
        ({"density": -1.0}, "density"),
        ({"unit_weight": 18.0, "density": 2.0}, "density"),
        ({"E": True}, "E"),
    ],
)
def test_invalid_parameters_are_named(kwargs, param):
    base = {"E": 1e4, "nu": 0.3}
    base.update(kwargs)
    with pytest.raises(MaterialError, match=rf"material 'clay': {param} = "):
        Material(name="clay", **base)


def test_derived_quantities():
    m = Material(name="sand", E=70_000.0, nu=0.35, unit_weight=16.5, phi=30.0)
    # closed forms, exact to rounding
    assert m.shear_modulus == pytest.approx(70_000 / 2.7, rel=1e-14)
    assert m.bulk_modulus == pytest.approx(70_000 / 0.9, rel=1e-14)
    assert m.k0 == pytest.approx(0.35 / 0.65, rel=1e-14)
    assert m.density == pytest.approx(16.5 / 9.81, rel=1e-14)
    assert m.is_plastic
    assert tension_cutoff(m.peak) == 0.0  # c = 0: no tension
    clay = Material(name="clay", E=1e4, nu=0.3, cohesion=69.0, phi=20.0)
    assert tension_cutoff(clay.peak) == pytest.approx(69 / math.tan(math.radians(20)))
    # a given tension cut-off is capped at the apex c cot(phi) (the kernel's assumption)
    capped = Material(name="clay", E=1e4, nu=0.3, cohesion=69.0, phi=20.0, tensile_strength=1e6)
    assert tension_cutoff(capped.peak) == tension_cutoff(clay.peak)
    weak = clay.weakened(1.5)
    assert weak.cohesion == pytest.approx(46.0)
    assert math.tan(math.radians(weak.phi)) == pytest.approx(math.tan(math.radians(20)) / 1.5)
    assert not Material(name="rock", E=1e6, nu=0.2).is_plastic


def test_material_is_keyword_only():
    """``Material("clay", 10, 0.3)`` would silently mean E = 10 kPa: refused."""
    with pytest.raises(TypeError):
        Material("clay", 10.0, 0.3)  # type: ignore[misc]


def test_values_in_the_wrong_unit_are_flagged():
    """E in MPa and angles in radians are valid numbers but are flagged; whole degrees,
    realistic moduli and reduced strengths are not."""
    with pytest.warns(MaterialWarning, match="E = 30 kPa"):
        Material(name="clay", E=30.0, nu=0.3)
    with pytest.warns(MaterialWarning, match="phi = 0.35 deg"):
        Material(name="sand", E=3e4, nu=0.3, phi=0.35)
    with warnings.catch_warnings():
        warnings.simplefilter("error", MaterialWarning)
        weak = Material(name="rock", E=3e4, nu=0.3, cohesion=1.0, phi=1.0)
        assert weak.weakened(2.0).phi < 1.0  # a reduced angle is not a unit slip


def test_bond_and_contact_records():
    """Bond and contact are records of their own: validated with the record and parameter
    named, weakened with the material (given angles reduced, None left to follow c and phi),
    and the weight is given once, as unit weight or as density."""
    with pytest.raises(MaterialError, match="Contact: normal_stiffness = 0.0"):
        Contact(normal_stiffness=0.0)
    with pytest.raises(MaterialError, match="Contact: damping = 1.5"):
        Contact(damping=1.5)
    with pytest.raises(MaterialError, match="Contact: cohesion = -2.0"):
        Contact(cohesion=-2.0)
    with pytest.raises(MaterialError, match="Bond: tensile_strength = -1.0"):
        Bond(tensile_strength=-1.0)
    with pytest.raises(MaterialError, match="Bond: phi = 95"):
        Bond(phi=95)
    with pytest.raises(MaterialError, match="bond = "):
        Material(name="clay", E=1e4, nu=0.3, bond={"cohesion": 1.0})
    clay = Material(name="clay", E=1e4, nu=0.3, density=2.0, cohesion=10.0, phi=30.0,
                    bond=Bond(cohesion=4.0, phi=20.0),
                    contact=Contact(phi=25.0, cohesion=3.0, damping=0.2))
    assert clay.unit_weight == 2.0 * 9.81 and clay.density == 2.0
    weak = clay.weakened(2.0)
    assert weak.bond.cohesion == 2.0 and weak.bond.tensile_strength is None
    assert math.tan(math.radians(weak.bond.phi)) == pytest.approx(math.tan(math.radians(20)) / 2)
    assert math.tan(math.radians(weak.contact.phi)) == pytest.approx(
        math.tan(math.radians(25)) / 2)
    assert weak.contact.cohesion == 1.5
    assert weak.contact.damping == 0.2 and weak.density == 2.0
    assert clay.peak.cohesion == 10.0 and clay.peak.phi == 30.0


def test_strengthening_keeps_a_residual_cut_off_within_the_peak_apex():
    """c = 10 kPa, phi = 30 deg (apex c cot(phi) = 17.32 kPa, the peak's cut-off), a residual
    cut-off of 17 kPa: strength reduction by F divides it by F but never lifts it above the
    weakened peak's cut-off, whose apex is the same at any F (F = 0.5 once raised an error)."""
    from hybrid.materials import Strength

    m = Material(name="a", E=1e5, nu=0.3, cohesion=10.0, phi=30.0,
                 residual=Strength(cohesion=10.0, phi=30.0, tensile_strength=17.0),
                 softening_displacement=0.05)
    apex = 10.0 / math.tan(math.radians(30.0))
    assert tension_cutoff(m.weakened(2.0).residual) == pytest.approx(8.5)
    assert tension_cutoff(m.weakened(0.5).residual) == pytest.approx(apex, rel=1e-12)
    assert tension_cutoff(m.weakened(0.5).peak) == pytest.approx(apex, rel=1e-12)
