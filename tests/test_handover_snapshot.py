"""The discrete start from a CellSnapshot: numpy only, checked with dolfinx hidden.

Two unit Q4 cells side by side (x in [0, 2], y in [0, 1]), elastic, gamma = 20 kN/m3, a pressure of
50 kPa on the top, the base fixed. Closed forms: mass = (gamma / g) x area; the pressure's
nodal forces sum to -p x width in y; the shared edge is the one interface.
"""

import subprocess
import textwrap
from types import SimpleNamespace

import numpy as np
import pytest
from conftest import PYTHON, ROOT

from hybrid import handover
from hybrid.handover import (
    Handover,
    Region,
    discrete_materials,
    element_groups,
    from_construction,
    start_from,
)
from hybrid.materials import GRAVITY, Material, Strength
from hybrid.snapshot import CellSnapshot


def _snapshot(**changes) -> CellSnapshot:
    x = np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0], [0.0, 1.0], [1.0, 1.0], [2.0, 1.0]])
    fields = dict(
        x_undeformed=x, x=x.copy(), cells=np.array([[0, 1, 4, 3], [1, 2, 5, 4]]),
        material=np.array([0, 0]),
        materials=(Material(name="clay", E=1e5, nu=0.3, unit_weight=20.0),),
        material_names=("clay",), strength_factor=1.0, degree=2,
        points=np.zeros((2, 4, 2)), point_areas=np.full((2, 4), 0.25),
        stress=np.full((2, 4, 4), -10.0),
        plastic_strain=np.array([[0.0] * 4, [0.1] * 4]), yielded=np.zeros((2, 4), np.int8),
        boundary_edges={"base": np.array([[0, 1, 0], [1, 2, 1]]),
                        "top": np.array([[3, 4, 0], [4, 5, 1]])},
        supports=(("base", True, True),), loads={"top": (50.0, 0.0, 0.0)},
        load_factor=1.0, gravity=(0.0, -GRAVITY))
    fields.update(changes)
    return CellSnapshot(**fields)


def test_start_from_a_snapshot_carries_mass_loads_supports_and_region():
    hand = start_from(_snapshot(), region=Region(plastic_strain=0.05))
    disc = hand.discrete
    assert disc.n_elements == 2 and disc.n_nodes == 8
    assert disc.mass.sum() == pytest.approx(20.0 / GRAVITY * 2.0, rel=1e-12)
    assert hand.load_forces[:, 1].sum() == pytest.approx(-50.0 * 2.0, rel=1e-12)
    assert hand.load_forces[:, 0] == pytest.approx(0.0, abs=1e-12)
    base = hand.boundary_nodes["base"]
    assert disc.x[base, 1] == pytest.approx(0.0) and disc.fixed[base].all()
    assert disc.fixed.sum() == 2 * len(base)  # nothing else is held
    assert hand.splittable.tolist() == [False, True]  # only the cell beyond 0.05
    assert not disc.interface_splittable.any()  # the one interface needs both cells in
    assert np.all(disc.stress == -10.0)  # P2 -> cell mean at every Gauss point
    assert hand.report["strength_factor"] == 1.0 and hand.report["element"] == "Q4"
    both = start_from(_snapshot(), region=Region(plastic_strain=0.05, layers=1))
    assert both.discrete.interface_splittable.tolist() == [True]


def test_a_transmitting_roller_gets_dashpots_on_its_free_component():
    """The right side (x = 2, one edge of length 1) a transmitting roller held in x: its two
    nodes share the dashpot sqrt(G rho) x 1 m on y (Lysmer & Kuhlemeyer 1969), nothing on x
    and nowhere else; a transmitting boundary held in both directions is refused."""
    right = {"right": np.array([[2, 5, 1]])}
    snap = _snapshot(boundary_edges={**_snapshot().boundary_edges, **right},
                     supports=(("base", True, True), ("right", True, False)),
                     smooth=("right",), transmitting=("right",))
    disc = start_from(snap, region=Region(everywhere=True)).discrete
    clay = snap.materials[0]
    impedance = np.sqrt(clay.shear_modulus * clay.density)
    on = np.flatnonzero(disc.dashpot[:, 1])
    assert np.isclose(disc.x[on, 0], 2.0).all() and len(on) == 2
    assert disc.dashpot[on, 1] == pytest.approx([0.5 * impedance] * 2, rel=1e-12)  # L/2 each
    assert not disc.dashpot[:, 0].any()
    # a second support holding the other component: no longer a roller
    with pytest.raises(ValueError, match="held in both directions"):
        start_from(_snapshot(boundary_edges={**_snapshot().boundary_edges, **right},
                             supports=(("base", True, True), ("right", True, False),
                                       ("right", False, True)),
                             transmitting=("right",)), region=Region(everywhere=True))


def test_a_transmitting_boundary_without_a_support_is_refused():
    """A snapshot naming a transmitting boundary that no support holds."""
    with pytest.raises(ValueError, match="without a support"):
        _snapshot(transmitting=("top",))


def test_a_transmitting_roller_holding_its_tangent_gets_the_pressure_impedance():
    """The top (y = 1, length 2) a transmitting roller held in x, free in y, its normal: the
    dashpots sum to sqrt((K + 4G/3) rho) x 2 m; an inclined boundary is refused."""
    snap = _snapshot(supports=(("base", True, True), ("top", True, False)),
                     smooth=("top",), transmitting=("top",), loads={})
    disc = start_from(snap, region=Region(everywhere=True)).discrete
    clay = snap.materials[0]
    impedance = np.sqrt((clay.bulk_modulus + 4.0 * clay.shear_modulus / 3.0) * clay.density)
    assert disc.dashpot[:, 1].sum() == pytest.approx(impedance * 2.0, rel=1e-12)
    x = _snapshot().x.copy()
    x[5, 1] = 1.1  # the top's right end lifted: slope 0.1
    with pytest.raises(ValueError, match="does not run along x or y"):
        start_from(_snapshot(x=x, supports=(("base", True, True), ("top", True, False)),
                             transmitting=("top",), loads={}), region=Region(everywhere=True))


def test_a_quadratic_cell_hands_over_its_area_weighted_mean():
    """A P2 / Q2 cell's stress goes to every Gauss point as the local L2 projection onto
    constants, sum A_q sigma_q / sum A_q: with unequal point areas (a 3 x 3 Gauss rule's
    corner points carry 25/64 of the middle one's weight) the plain mean of the points is
    another number, so the test tells the two apart."""
    areas = np.array([[0.1, 0.2, 0.3, 0.4], [0.25, 0.25, 0.25, 0.25]])
    stress = np.zeros((2, 4, 4))
    stress[:, :, 1] = [[-10.0, -20.0, -30.0, -40.0], [-1.0, -2.0, -3.0, -6.0]]
    stress[:, :, 3] = [[4.0, 0.0, 0.0, 0.0], [0.0, 0.0, 0.0, 8.0]]
    disc = start_from(_snapshot(point_areas=areas, stress=stress),
                      region=Region(everywhere=True)).discrete
    expected_yy = [(1.0 + 4.0 + 9.0 + 16.0) / 1.0 * -1.0, -3.0]  # sum A s / sum A
    expected_xy = [0.4, 2.0]
    assert disc.stress[:, :, 1] == pytest.approx(np.repeat(expected_yy, 4).reshape(2, 4),
                                                 rel=1e-14)
    assert disc.stress[:, :, 3] == pytest.approx(np.repeat(expected_xy, 4).reshape(2, 4),
                                                 rel=1e-14)
    assert disc.stress[0, 0, 1] != pytest.approx(stress[0, :, 1].mean())  # not the plain mean


def test_a_snapshot_with_inconsistent_arrays_is_refused():
    with pytest.raises(ValueError, match="one row per cell"):
        _snapshot(stress=np.zeros((3, 4, 4)))
    with pytest.raises(ValueError, match="one area per quadrature point"):
        _snapshot(point_areas=np.full((2, 3), 0.25))
    with pytest.raises(ValueError, match="point_areas must be positive"):
        _snapshot(point_areas=np.zeros((2, 4)))
    with pytest.raises(ValueError, match="no such cell group"):
        start_from(_snapshot(), region=Region(group="rock"))


def test_handover_runs_without_dolfinx():
    """The discrete start and the tied settle need neither dolfinx nor ufl: they are
    imported with both made unimportable, and never loaded."""
    script = textwrap.dedent("""
        import sys
        for name in ("dolfinx", "ufl", "basix", "ffcx", "petsc4py"):
            sys.modules[name] = None  # import raises ImportError
        sys.path.insert(0, "tests")
        from test_handover_snapshot import _snapshot
        from hybrid.handover import Region, settle, start_from
        hand = start_from(_snapshot(), region=Region(everywhere=True))
        report = settle(hand, steps=200)
        assert report.final_residual < report.initial_residual
        assert not any(m.split(".")[0] in ("dolfinx", "ufl") and sys.modules[m] is not None
                       for m in list(sys.modules))
        print("ok", hand.discrete.n_elements)
    """)
    done = subprocess.run([PYTHON, "-c", script], cwd=ROOT, capture_output=True, text=True,
                          timeout=300)
    assert done.returncode == 0, done.stderr
    assert done.stdout.split() == ["ok", "2"]


def test_element_groups_merge_the_lifts():
    clay = Material(name="clay", E=1e5, nu=0.3, unit_weight=20.0)
    hand = start_from(_snapshot(material=np.array([1, 0]), materials=(clay, clay),
                                material_names=("core:2", "foundation")))
    assert hand.material_names == ("core:2", "foundation")
    assert element_groups(hand).tolist() == ["foundation", "core"]
    with pytest.raises(ValueError, match="no material names"):
        element_groups(Handover(hand.discrete, hand.splittable, hand.frozen, hand.load_forces))


def test_from_construction_restores_the_last_complete_lift(monkeypatch):
    """After a collapse the solver goes back to the last complete lift before the handover;
    after a complete construction it is handed over as it stands."""
    calls = []

    class Solver:
        def restore(self, snapshot):
            calls.append(("restore", snapshot))

        def state(self):
            calls.append(("state",))
            return "state"

    def fake_to_discrete(state, *, region, materials=None):
        calls.append(("to_discrete", state, region))
        return "hand"

    monkeypatch.setattr(handover, "to_discrete", fake_to_discrete)
    region = Region(layers=2)
    collapsed = SimpleNamespace(before_collapse="lift 3")
    assert from_construction(Solver(), collapsed, region=region) == "hand"
    assert calls == [("restore", "lift 3"), ("state",), ("to_discrete", "state", region)]
    calls.clear()
    assert from_construction(Solver(), SimpleNamespace(before_collapse=None)) == "hand"
    assert calls == [("state",), ("to_discrete", "state", None)]


def test_discrete_materials_replace_a_group_lifts_included():
    """The discrete phase's own materials: a group's lifts take it, other groups keep the
    continuum's, the snapshot's strength factor applies, and a stiffness or density that
    differs (the stresses are handed over as they are) is refused."""
    peak = Material(name="core", E=1e5, nu=0.3, unit_weight=20.0, cohesion=50.0)
    rock = Material(name="rock", E=1e6, nu=0.2, unit_weight=22.0)
    soft = Material(name="core", E=1e5, nu=0.3, unit_weight=20.0, cohesion=50.0,
                    residual=Strength(cohesion=30.0, phi=0.0), softening_displacement=0.5)
    snap = _snapshot(material=np.array([0, 1]), materials=(peak, rock),
                     material_names=("core:2", "foundation"))
    out = discrete_materials(snap, {"core": soft})
    assert out.materials == (soft, rock) and out.material_names == snap.material_names
    halved = discrete_materials(_snapshot(material=np.array([0, 1]), materials=(peak, rock),
                                          material_names=("core:2", "foundation"),
                                          strength_factor=2.0), {"core": soft})
    assert halved.materials[0] == soft.weakened(2.0)
    hand = start_from(out)
    assert hand.discrete.n_elements == 2
    with pytest.raises(ValueError, match="E = 200000.0 differs from the continuum's"):
        discrete_materials(snap, {"core": Material(name="core", E=2e5, nu=0.3,
                                                   unit_weight=20.0, cohesion=50.0)})
    with pytest.raises(ValueError, match=r"\['core:2'\]: no such cell group"):
        discrete_materials(snap, {"core:2": soft})
    with pytest.raises(ValueError, match="density"):
        discrete_materials(snap, {"core": Material(name="core", E=1e5, nu=0.3,
                                                   unit_weight=19.0, cohesion=50.0)})
