"""Indirect displacement control (``PlasticSolver.follow``): the load factor as an unknown
follows a pressure-loaded structure past its peak and down the softening branch; dissipation
control does so where the energy dissipated is the path's measure."""

import numpy as np
import pytest

from hybrid.continuum import DisplacementControl, DissipationControl, PlasticSolver
from hybrid.geometry import build_mesh
from hybrid.materials import Material, Strength
from hybrid.model import Displacement, Model, Pressure, Roller

E, NU = 1.0e4, 0.3  # kPa, -
C_PEAK, C_RES, U_R = 20.0, 5.0, 0.01  # kPa, kPa, m
SMOOTH_BOX = [Roller("base", "y"), Roller("left", "x")]


def _block(builder, material: Material, supports, loads=()) -> PlasticSolver:
    mesh = build_mesh(builder("block"), width=1.0, height=1.0, nx=2, ny=2,
                      cells="quadrilateral")
    return PlasticSolver(Model(mesh, {"soil": material}, supports=supports, loads=list(loads)),
                         degree=1)


def test_one_elastic_step_gives_the_closed_form_pressure(builder):
    """A 1 m elastic block on smooth supports, free on the right, its top shortened by
    1 mm under a uniform pressure: plane-strain uniaxial stress, p = E / (1 - nu^2) x
    0.001 m / 1 m exactly (linear problem: Newton's first iterate is the answer, 1e-9)."""
    rock = Material(name="rock", E=E, nu=NU, plastic=False)
    solver = _block(builder, rock, SMOOTH_BOX, [Pressure("top", 1.0)])
    analysis = solver.follow(DisplacementControl("top", 1), -1e-3, 1)
    assert analysis.completed and analysis.factor == pytest.approx(-1e-3, rel=1e-12)
    assert solver.load_factor == pytest.approx(E / (1 - NU**2) * 1e-3, rel=1e-9)


def test_a_pressure_follows_the_softening_law_where_load_control_stops(builder):
    """A homogeneous block of softening Tresca clay (c 20 -> 5 kPa over u_r = 0.01 m)
    compressed by a pressure on its smooth top. Under load control the ramp cannot pass the
    peak 2 c_p = 40 kPa; under control of the top's mean settlement the load factor (the
    pressure) rises to the peak, falls and ends at the residual 2 c_r = 10 kPa, and every
    Gauss point has the stress of the same block driven by a prescribed top displacement
    (two independent routes to one state: 1e-6 of c_p, the Newton tolerance being 1e-8)."""
    clay = Material(name="clay", E=E, nu=NU, cohesion=C_PEAK, plastic=True,
                    residual=Strength(cohesion=C_RES), softening_displacement=U_R)
    loaded = _block(builder, clay, SMOOTH_BOX, [Pressure("top", 1.0)])
    stalled = loaded.ramp(45.0, 30)
    assert not stalled.completed and stalled.factor <= 2 * C_PEAK * (1 + 1e-9)

    controlled = _block(builder, clay, SMOOTH_BOX, [Pressure("top", 1.0)])
    pushed = _block(builder, clay, [*SMOOTH_BOX, Displacement("top", uy=-0.06)])
    top = DisplacementControl("top", 1)
    pressures = []
    for k in range(30):
        assert controlled.follow(top, -0.002 * (k + 1), 1).completed, f"step {k + 1}"
        assert pushed.step(d_lambda=1.0 / 30) is not None
        np.testing.assert_allclose(controlled.stress, pushed.stress, rtol=0,
                                   atol=1e-6 * C_PEAK)
        # equilibrium of the block: the pressure is the vertical stress
        assert controlled.load_factor == pytest.approx(-controlled.stress[0, 1],
                                                       abs=1e-6 * C_PEAK)
        pressures.append(controlled.load_factor)
    peak = int(np.argmax(pressures))
    assert 0 < peak < 5 and pressures[peak] <= 2 * C_PEAK * (1 + 1e-9)
    assert np.all(np.diff(pressures[peak:]) <= 1e-6 * C_PEAK)  # the softening branch
    assert pressures[-1] == pytest.approx(2 * C_RES, rel=1e-6)


def test_the_path_refuses_what_it_cannot_drive(builder):
    """Clear errors: no surface load, prescribed displacements, an unknown boundary, a
    component other than x or y, no steps, a target that is not a number."""
    rock = Material(name="rock", E=E, nu=NU, plastic=False)
    top = DisplacementControl("top", 1)
    with pytest.raises(ValueError, match="has none; add a Pressure"):
        _block(builder, rock, SMOOTH_BOX).follow(top, -1e-3, 1)
    with pytest.raises(ValueError, match="remove the prescribed displacements"):
        _block(builder, rock, [*SMOOTH_BOX, Displacement("top", uy=-0.01)],
               [Pressure("top", 1.0)]).follow(top, -1e-3, 1)
    solver = _block(builder, rock, SMOOTH_BOX, [Pressure("top", 1.0)])
    with pytest.raises((ValueError, KeyError), match="crest"):
        solver.follow(DisplacementControl("crest", 1), -1e-3, 1)
    with pytest.raises(ValueError, match="must be 0"):
        DisplacementControl("top", 2)
    with pytest.raises(ValueError, match="steps = 0"):
        solver.follow(top, -1e-3, 0)
    with pytest.raises(ValueError, match="must be a finite number"):
        solver.follow(top, float("nan"), 1)


def _footing(fine: float, u_r: float = 0.2) -> PlasticSolver:
    """The H2 footing (B = 1.2 m, c 69 -> 10 kPa over u_r, phi 20 deg, psi 0, gamma 20 kN/m3,
    E 100 MPa, nu 0.3) under its own weight, loaded by its pressure (load factor 1 = 1 kPa)."""
    from pathlib import Path

    from hybrid.geometry import load_builder
    from hybrid.model import Fixed

    meshes = Path(__file__).resolve().parent.parent / "meshes"
    mesh = build_mesh(load_builder(meshes / "footing.py"), width=4.8, depth=3.0,
                      half_footing=0.6, fine=fine, coarse=0.4, cells="quadrilateral")
    soil = Material(name="soil", E=1.0e5, nu=0.3, unit_weight=20.0, cohesion=69.0, phi=20.0,
                    residual=Strength(cohesion=10.0, phi=20.0), softening_displacement=u_r)
    model = Model(mesh, {"soil": soil}, loads=[Pressure("footing", 1.0)],
                  supports=[Fixed("base"), Roller("symmetry", "x"), Roller("right", "x")])
    solver = PlasticSolver(model, degree=2)
    solver.apply_gravity(steps=2).require()
    solver.reset_displacement()
    return solver


def _footing_peak(fine: float) -> tuple[float, float]:
    """The footing (``_footing``) pushed by its pressure to 0.15 m mean settlement under
    displacement control. Returns (peak pressure, pressure at 0.15 m) [kPa]."""
    solver = _footing(fine)
    control = DisplacementControl("footing", 1)
    assert solver.follow(control, -0.15, 60).completed
    loads = [r.load_factor for r in solver.history]
    return max(loads), loads[-1]


@pytest.mark.slow
def test_softening_footing_collapse_load_on_two_meshes():
    """The softening footing's collapse load is the peak of its displacement-controlled curve,
    passed and left behind: on elements of 0.16 and 0.08 m at the footing edge the peak
    agrees within 3 % (the bar the collapse loads of the hybrid cases are set; measured
    0.1 %), and the load falls past it to less than half the peak by 0.15 m (softening
    towards c_r). The post-peak branch is not asserted: it steepens with refinement."""
    coarse, fine = _footing_peak(0.16), _footing_peak(0.08)
    assert fine[0] == pytest.approx(coarse[0], rel=0.03)
    for peak, end in (coarse, fine):
        assert end < 0.5 * peak


# --- dissipation control ---------------------------------------------------------------------
def _softening_clay() -> Material:
    return Material(name="clay", E=E, nu=NU, cohesion=C_PEAK, plastic=True,
                    residual=Strength(cohesion=C_RES), softening_displacement=U_R)


def _plastic_work(kappa: np.ndarray, h: float) -> float:
    """sqrt(3) int c(kappa) d kappa per unit volume of Tresca clay, c linear from C_PEAK to
    C_RES at kappa_r = U_R / (sqrt(3) h), then C_RES (isochoric flow in the x-y plane: the
    work sigma : d eps_p = (s1 - s3) d eps = 2 c d eps, with d kappa = 2 d eps / sqrt(3))."""
    kr = U_R / (np.sqrt(3.0) * h)
    k = np.minimum(kappa, kr)
    soft = C_PEAK * k - 0.5 * (C_PEAK - C_RES) * k**2 / kr
    return float(np.mean(np.sqrt(3.0) * (soft + C_RES * np.maximum(kappa - kr, 0.0))))


def test_dissipation_control_follows_the_softening_block_past_its_peak(builder):
    """The homogeneous softening block under a pressure (as above), its top pushed 4.5 mm
    under displacement control (just past the peak 2 c_p, its first yield), then driven by
    the energy dissipated, 0.01 kJ/m per increment (the whole softening dissipates about
    0.25 kJ/m here): the pressure falls along the softening branch to the residual 2 c_r = 10 kPa
    (1e-6) and stays there, and the block stays in equilibrium (pressure = -sigma_yy). The
    measure is the plastic work of the force at the start of each increment on the
    displacement an elastic unloading would not recover: it agrees with the kernel's plastic
    work sqrt(3) int c d kappa over the block within 5 % (a first-order estimate: the force
    of the increment's start, falling over it; measured 2.1 %)."""
    solver = _block(builder, _softening_clay(), SMOOTH_BOX, [Pressure("top", 1.0)])
    assert solver.follow(DisplacementControl("top", 1), -4.5e-3, 3).completed
    assert solver.plastic_strain.max() > 0.0
    work0 = _plastic_work(solver.plastic_strain, 0.5)
    control = DissipationControl()
    pressures = []
    for k in range(30):
        before = solver._paths.get(control)
        start = before.displacement() if before is not None else 0.0
        assert solver.follow(control, start + 0.01, 1).completed, f"increment {k + 1}"
        assert solver.load_factor == pytest.approx(-solver.stress[0, 1], abs=1e-6 * C_PEAK)
        pressures.append(solver.load_factor)
    assert max(pressures) <= 2 * C_PEAK * (1 + 1e-9)
    assert pressures[-1] == pytest.approx(2 * C_RES, rel=1e-6)
    dissipated = _plastic_work(solver.plastic_strain, 0.5) - work0  # [kJ/m3] x 1 m2
    assert solver._paths[control].displacement() == pytest.approx(dissipated, rel=0.05)


def test_an_elastic_state_cannot_be_steered_by_its_dissipation(builder):
    """From an elastic state (a load step that did not yield) nothing dissipates whatever the
    increment: the path stops at once, the state unchanged."""
    solver = _block(builder, _softening_clay(), SMOOTH_BOX, [Pressure("top", 1.0)])
    assert solver.step(d_lambda=10.0) is not None and solver.plastic_strain.max() == 0.0
    analysis = solver.follow(DissipationControl(), 0.01, 1)
    assert not analysis.completed and analysis.factor == 0.0 and solver.load_factor == 10.0


def test_dissipation_control_follows_a_snap_back_where_the_settlement_stops():
    """The footing on 0.16 m elements with a brittle band (u_r = 0.02 m instead of 0.2 m):
    under control of its mean settlement the path stops at the peak, the settlement having to
    turn back; driven on by the energy dissipated (0.25 kJ/m per increment) it passes: the
    pressure falls below 65 % of the peak while the settlement first decreases by more than
    1 mm (the snap-back; measured 1.4 mm) and then grows past the stop by more than 1 cm, on
    the branch where the band carries its residual strength (measured: the pressure then
    about 290 kPa, 37 % of the peak)."""
    solver = _footing(0.16, u_r=0.02)
    settle, dissipate = DisplacementControl("footing", 1), DissipationControl()
    stopped = solver.follow(settle, -0.1, 50)
    assert not stopped.completed
    peak, stop = max(r.load_factor for r in solver.history), -stopped.factor
    pressure, settlement = [], []
    for k in range(40):
        assert solver.follow(dissipate, 0.25 * (k + 1), 1).completed, f"increment {k + 1}"
        pressure.append(solver.load_factor)
        settlement.append(-solver._paths[settle].displacement())
    assert min(pressure) < 0.65 * peak
    assert min(settlement) < stop - 1e-3
    assert settlement[-1] > stop + 1e-2
