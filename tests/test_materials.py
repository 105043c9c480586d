"""Material validation: errors name the material and the parameter."""

import math
import warnings

import pytest

from hybrid.materials import Material, MaterialError, MaterialWarning


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
        ({"contact_stiffness": 0.0}, "contact_stiffness"),
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
    assert m.resolved_tensile_strength() == 0.0  # c = 0: no tension
    clay = Material(name="clay", E=1e4, nu=0.3, cohesion=69.0, phi=20.0)
    assert clay.resolved_tensile_strength() == pytest.approx(69 / math.tan(math.radians(20)))
    # a given tension cut-off is capped at the apex c cot(phi) (the kernel's assumption)
    capped = Material(name="clay", E=1e4, nu=0.3, cohesion=69.0, phi=20.0, tensile_strength=1e6)
    assert capped.resolved_tensile_strength() == clay.resolved_tensile_strength()
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
