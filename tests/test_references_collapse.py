"""Granular column collapse references (hybrid.references): published laws and the Bui et al.
(2008) aluminium-bar experiment (geometry and material). Which numbers are primary and which
secondary is in each test."""

import numpy as np
import pytest

from hybrid import references as ref


def test_lube2005_runout_branches():
    """Lube et al. (2005), Phys. Rev. E 72, 041301, as quoted (secondary): 1.2 a for a < 1.8,
    1.9 a^(2/3) for a > 2.8. At a = 4 the runout beyond the edge is 1.9 * 4^(2/3) = 4.79
    initial widths (the figure an open validation note quotes for Lube's series A)."""
    assert ref.granular_runout_lube2005(1.0) == pytest.approx(1.2, rel=1e-12)
    assert ref.granular_runout_lube2005(0.5) == pytest.approx(0.6, rel=1e-12)
    assert ref.granular_runout_lube2005(1.8) == pytest.approx(2.16, rel=1e-12)
    assert ref.granular_runout_lube2005(4.0) == pytest.approx(4.79, abs=0.005)
    assert ref.granular_runout_lube2005(2.8) == pytest.approx(1.9 * 2.8 ** (2 / 3), rel=1e-12)


def test_lube2005_runout_has_no_law_between_the_regimes():
    """The abstract of Lube et al. (2005) splits the regimes at a ~ 1.8; the quoted laws do not
    meet at 1.8, 2.3 or 2.8 (gaps of 10 % or more) and cross only at a = (1.9/1.2)^3 = 3.97.
    'auto' refuses the gap; an explicit branch is allowed."""
    crossing = (1.9 / 1.2) ** 3
    assert crossing == pytest.approx(3.97, abs=0.005)
    assert 1.2 * crossing == pytest.approx(1.9 * crossing ** (2 / 3), rel=1e-12)
    for a in (1.8, 2.3, 2.8):
        lin = ref.granular_runout_lube2005(a, branch="linear")
        pw = ref.granular_runout_lube2005(a, branch="power")
        assert (pw - lin) / lin > 0.10, a
    with pytest.raises(ValueError, match="between the two regimes"):
        ref.granular_runout_lube2005(2.3)
    assert ref.granular_runout_lube2005(2.3, branch="linear") == pytest.approx(2.76, rel=1e-12)
    with pytest.raises(ValueError, match="branch"):
        ref.granular_runout_lube2005(1.0, branch="cubic")
    with pytest.raises(ValueError, match="aspect"):
        ref.granular_runout_lube2005(0.0)


def test_lube2005_final_height_secondary():
    """H_inf / L0 = a (column height kept) up to a = 1.15, a^(2/5) above (secondary). The
    exponent matches Balmforth & Kerswell's (2005) wide-channel H / h_inf ~ a^0.6; the branches
    do not meet at 1.15."""
    assert ref.granular_final_height_lube2005(0.5) == 0.5
    assert ref.granular_final_height_lube2005(1.15) == pytest.approx(1.15, rel=1e-12)
    assert ref.granular_final_height_lube2005(4.0) == pytest.approx(4.0**0.4, rel=1e-12)
    assert ref.granular_final_height_lube2005(1.1501) == pytest.approx(1.057, abs=0.001)
    a = 6.0
    assert a / ref.granular_final_height_lube2005(a) == pytest.approx(a**0.6, rel=1e-12)


def test_rods2015_laws_from_the_abstract():
    """arXiv:1512.05180, abstract (aluminium rods, true 2-D): H_inf = H0 for a < 0.65;
    h0 / h_inf = 1.42 a^(2/3); (d - d0)/d0 = 3.25 a^0.96 (0.65 < a < 1.5), 3.80 a^0.73
    (a > 1.5); d / d0 = 4.30 a^0.72 (a > 0.65)."""
    assert ref.granular_final_height_rods2015(0.5) == 1.0
    assert ref.granular_final_height_rods2015(1.0) == pytest.approx(1 / 1.42, rel=1e-12)
    assert ref.granular_runout_rods2015(1.0) == pytest.approx(3.25, rel=1e-12)
    assert ref.granular_runout_rods2015(2.0) == pytest.approx(3.80 * 2**0.73, rel=1e-12)
    assert ref.granular_runout_rods2015(1.0, total=True) == pytest.approx(4.30, rel=1e-12)
    # the single d/d0 fit and the excess fit agree to 2 % at a = 1 (3.30 against 3.25)
    assert ref.granular_runout_rods2015(1.0, total=True) - 1.0 == pytest.approx(
        ref.granular_runout_rods2015(1.0), rel=0.02)
    # the abstract's branches do not meet: 4.80 against 5.11 at a = 1.5, 0.939 against 1 at 0.65
    assert 3.25 * 1.5**0.96 == pytest.approx(4.80, abs=0.005)
    assert ref.granular_runout_rods2015(1.5) == pytest.approx(5.11, abs=0.005)
    assert ref.granular_final_height_rods2015(0.6501) == pytest.approx(0.939, abs=0.001)
    with pytest.raises(ValueError, match="only for"):
        ref.granular_runout_rods2015(0.5)


def test_bui2008_geometry_and_material():
    """Bui et al. (2008), as reproduced by open inputs that cite it (secondary): 0.2 m x 0.1 m
    column (a = 0.5), phi = 19.8 deg, c = 0, psi = 0, rho = 2650 kg/m3, E = 840 kPa, nu = 0.3;
    MaterialPointSolver.jl's bulk modulus 700 kPa is the same material."""
    exp = ref.bui2008_collapse()
    assert (exp.length, exp.height) == (0.2, 0.1)
    assert exp.aspect == pytest.approx(0.5, rel=1e-12)
    assert exp.friction_angle == 19.8 and exp.cohesion == 0.0 and exp.dilatancy_angle == 0.0
    assert exp.density == 2650.0 and exp.poisson == 0.3
    bulk = exp.youngs_modulus / (3.0 * (1.0 - 2.0 * exp.poisson))
    assert bulk == pytest.approx(700.0, rel=1e-12)
    assert exp.unit_weight == pytest.approx(26.0, abs=0.01)


def test_bui2008_final_surface_fits_the_column():
    """The digitised final surface belongs to the column of ``bui2008_collapse``: it starts at
    the back wall at the column's height (a = 0.5 < 0.65: the deposit keeps H0, as the rods'
    law says), ends on the floor, runs along the flow and goes down it (within the digitising
    scatter of 0.1 mm), and holds the column's area (mass conserved, packing unchanged, within
    the 10 % that digitising and dilation allow)."""
    exp = ref.bui2008_collapse()
    pts = np.array(ref.bui2008_final_surface())
    x, y = pts[:, 0], pts[:, 1]
    assert x[0] == pytest.approx(0.0, abs=0.001)
    assert y[0] == pytest.approx(exp.height * ref.granular_final_height_rods2015(exp.aspect),
                                 rel=0.01)
    assert y[-1] < 0.02 * exp.height
    assert np.all(np.diff(x) > 0) and np.all(np.diff(y) < 1e-4)
    area = float(np.sum(0.5 * (y[1:] + y[:-1]) * np.diff(x)))
    assert area == pytest.approx(exp.length * exp.height, rel=0.10)
