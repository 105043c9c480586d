"""Staged construction helpers: groups split into lifts, placement lift by lift, strain from
placement, MPI-safe reductions of a state, and the standard construction figures."""

import dataclasses
from pathlib import Path

import numpy as np
import pytest

from hybrid.continuum import NewtonOptions
from hybrid.continuum.analysis import RUNAWAY_JUMP, at_rest_checks
from hybrid.continuum.plastic import PlasticSolver
from hybrid.continuum.staging import (
    Construction,
    build_in_lifts,
    lift_groups,
    lift_materials,
    split_into_lifts,
)
from hybrid.continuum.strength_reduction import SafetyResult
from hybrid.figures import (
    Column,
    construction_figures,
    safety_engineering_figures,
    safety_figures,
    staged_figures,
)
from hybrid.geometry import GeometryError, build_mesh, load_builder
from hybrid.handover import element_groups, from_construction
from hybrid.materials import Material
from hybrid.model import Fixed, Model, Roller
from hybrid.references import SlipCircle

E, NU, GAMMA = 10_000.0, 0.3, 20.0
MESHES = Path(__file__).resolve().parent.parent / "meshes"
M = E * (1 - NU) / ((1 + NU) * (1 - 2 * NU))  # constrained modulus [kPa]


@pytest.fixture(scope="module")
def column():
    """A 2 m wide confined column: "lift1" (0-2 m) in place, "lift2" (2-4 m) built in two
    lifts of 1 m."""
    base = build_mesh(load_builder(MESHES / "layers.py"), width=2.0, lift_thickness=2.0,
                      lifts=2)
    mesh = split_into_lifts(base, ["lift2"], [3.0, 4.0])
    soil = Material(name="soil", E=E, nu=NU, unit_weight=GAMMA)
    model = Model(mesh, dict.fromkeys(mesh.cell_groups, soil),
                  supports=[Fixed("base"), Roller("left", "x"), Roller("right", "x")])
    solver = PlasticSolver(model, degree=2)
    solver.set_active(["lift1"])
    solver.apply_gravity().require()
    solver.reset_displacement()
    built = build_in_lifts(solver, mesh, [3.0, 4.0], 2.0, steps=2)
    return base, mesh, solver, built


def test_split_into_lifts(column):
    base, mesh, _, _ = column
    assert set(mesh.cell_groups) == {"lift1", "lift2:1", "lift2:2"}
    assert lift_groups(mesh, 2) == ["lift2:2"]
    assert lift_groups(mesh, 3) == []
    x, cells = mesh.cell_vertices()
    for name, (bottom, top) in {"lift1": (0.0, 2.0), "lift2:1": (2.0, 3.0),
                                "lift2:2": (3.0, 4.0)}.items():
        y = x[cells[mesh.cells(name)], 1]
        assert len(y) and y.min() == pytest.approx(bottom) and y.max() == pytest.approx(top)
    assert sorted(np.concatenate([mesh.cells(g) for g in mesh.cell_groups])) == list(
        range(base.num_owned_cells))


def test_lift_materials(column):
    """Every lift takes its group's material, a group not split its own."""
    _, mesh, _, _ = column
    table = {"lift1": "ground", "lift2": "fill"}
    assert lift_materials(mesh, table) == {"lift1": "ground", "lift2:1": "fill",
                                           "lift2:2": "fill"}
    with pytest.raises(KeyError):
        lift_materials(mesh, {"lift1": "ground"})


def test_split_into_lifts_refuses_bad_input(column):
    base = column[0]
    with pytest.raises(ValueError, match="rising"):
        split_into_lifts(base, ["lift2"], [4.0, 3.0])
    with pytest.raises(GeometryError, match="unknown cell"):
        split_into_lifts(base, ["fill"], [4.0])


def test_build_in_lifts_records_and_strain_from_placement(column):
    _, mesh, solver, built = column
    assert built.completed and built.before_collapse is None and built.safety is None
    assert [st["lift"] for st in built.stages] == [1, 2]
    assert [st["fill_level_m"] for st in built.stages] == [3.0, 4.0]
    assert [st["top_m"] for st in built.stages] == [3.0, 4.0]
    assert all(st["completed"] and st["weight_placed"] == 1.0 for st in built.stages)
    assert built.max_unplaced_stress == 0.0
    # confined column, strain from placement (1-D): the ground under 2 m of fill, lift 1 under
    # its own weight and lift 2, lift 2 under its own weight only
    state = solver.state()
    eps = built.strain.cell_mean(state)[:, 1]
    for name, expected in {"lift1": -2.0, "lift2:1": -1.5, "lift2:2": -0.5}.items():
        np.testing.assert_allclose(eps[mesh.cells(name)], expected * GAMMA / M, rtol=1e-8)


def test_state_reductions(column):
    _, mesh, solver, _ = column
    state = solver.state()
    uy = state.cell_displacement()[:, 1]
    assert state.extreme_displacement(1) == uy.min() < 0.0
    assert state.extreme_displacement(1, largest=True) == uy.max()
    top = mesh.cells("lift2:2")
    assert state.extreme_displacement(1, cells=top) == uy[top].min()
    assert state.yielded_fraction(top) == 0.0  # elastic
    assert state.yielded_fractions({"top": top, "none": top[:0]}) == {
        "top_yielded_fraction": 0.0, "none_yielded_fraction": 0.0}


def test_mesh_report(column):
    base = column[0]
    report = base.report()
    assert report["cells"] == base.num_owned_cells == sum(report["groups"].values())
    assert report["cell_type"] == base.cell_type
    assert report["group_areas_m2"] == pytest.approx({"lift1": 4.0, "lift2": 4.0}, rel=1e-12)


def test_at_rest_checks(column):
    """The confined column after all its lifts: at rest under the whole 4 m (the staged
    placement of an elastic column is oedometric lift by lift); a wrong ground level fails."""
    _, _, solver, _ = column
    state = solver.state()
    found = at_rest_checks(state, (1.0, 1.0), ground_level=4.0, unit_weight=GAMMA, nu=NU)
    assert set(found.checks) == {"far_field_sigma_v", "far_field_sigma_h"}
    assert all(c.passed for c in found.checks.values())
    assert found.checks["far_field_sigma_v"].reference == pytest.approx(-3.0 * GAMMA)
    assert found.checks["far_field_sigma_h"].reference == pytest.approx(
        -3.0 * GAMMA * NU / (1 - NU))
    assert found.stress[1] == found.checks["far_field_sigma_v"].computed
    high = at_rest_checks(state, (1.0, 1.0), ground_level=5.0, unit_weight=GAMMA, nu=NU)
    assert not any(c.passed for c in high.checks.values())


def test_construction_after_a_collapse(column):
    """Level carried, the collapsing lift, the history of complete lifts and the last
    equilibrium (the collapsing lift's cells out of the state, still active in the solver)."""
    _, mesh, solver, built = column
    assert built.level_carried == 4.0 and built.collapse is None
    assert built.history("lift") == [(3.0, 1), (4.0, 2)]
    stages = [built.stages[0], {**built.stages[1], "completed": False, "weight_placed": 0.4,
                                "runaway_ratio": 50.0, "softening": False}]
    collapsed = dataclasses.replace(built, stages=stages, completed=False,
                                    before_collapse=solver.snapshot())
    assert collapsed.level_carried == 3.0
    assert collapsed.collapse == {"lift": 2, "top_m": 4.0, "weight_carried": 0.4,
                                  "runaway_ratio": 50.0, "runaway": True, "softening": False}
    slow = dataclasses.replace(collapsed, stages=[stages[0], {**stages[1], "runaway_ratio": 2.0}])
    assert slow.collapse["runaway"] is False
    assert collapsed.history("lift") == [(3.0, 1)]
    state = collapsed.last_equilibrium(solver, mesh)
    assert np.flatnonzero(~state.active).tolist() == sorted(mesh.cells("lift2:2"))
    assert solver.active.all()
    none = dataclasses.replace(collapsed, stages=[{**stages[0], "completed": False}])
    assert none.level_carried == 2.0  # the base level: no lift carried


def free_column(cohesion: float, **newton) -> tuple[PlasticSolver, Construction]:
    """A 2 m wide, 4 m high column of clay (phi = 0) free at both sides on a fixed base:
    2 m in place under gravity, then two lifts of 1 m."""
    base = build_mesh(load_builder(MESHES / "layers.py"), width=2.0, lift_thickness=2.0,
                      lifts=2)
    mesh = split_into_lifts(base, ["lift2"], [3.0, 4.0])
    clay = Material(name="clay", E=E, nu=NU, unit_weight=GAMMA, cohesion=cohesion, phi=0.0)
    model = Model(mesh, dict.fromkeys(mesh.cell_groups, clay), supports=[Fixed("base")])
    solver = PlasticSolver(model, degree=2, options=NewtonOptions(**newton))
    solver.set_active(["lift1"])
    solver.apply_gravity(steps=2).require()
    solver.reset_displacement()
    return solver, build_in_lifts(solver, mesh, [3.0, 4.0], 2.0, steps=2)


def test_a_lift_that_stops_short_says_whether_it_ran_away():
    """A free-standing clay column fails in unconfined compression near gamma H = 2 c k, k
    somewhat above 1 from the fixed base: with c = 24 kPa 3 m stand (60 kPa at the base)
    and the lift to 4 m collapses, its displacement running away (metres against millimetres
    at the start: the path recorded). With c = 32 kPa the 4 m stand, but Newton allowed 2
    iterations stops the plastic lift short without a run-away: a stall, said as such."""
    _, collapsed = free_column(24.0)
    assert collapsed.level_carried == 3.0 and collapsed.collapse["lift"] == 2
    assert 0.5 < collapsed.collapse["weight_carried"] < 1.0
    assert collapsed.collapse["runaway_ratio"] > 100.0  # thousands here
    assert collapsed.collapse["runaway"] and not collapsed.collapse["softening"]
    path = collapsed.stages[-1]["path"]
    assert path[0] == [0.0, 0.0] and path[-1][0] == collapsed.collapse["weight_carried"]
    assert path[-1][1] > 1.0 > 100 * path[1][1]
    # the strain from placement is that of the last equilibrium, as the figures show it:
    # none in the collapsing lift, whose part-placed state was given up
    assert not collapsed.strain.total[collapsed.strain.solver.model.mesh.cells("lift2:2")].any()
    _, stalled = free_column(32.0, max_iterations=2)
    assert len(stalled.stages[-1]["path"]) >= 3  # two increments at least: a ratio
    assert stalled.collapse["runaway_ratio"] < RUNAWAY_JUMP
    assert not stalled.collapse["runaway"]
    assert free_column(32.0)[1].completed  # with Newton's default


def test_construction_and_safety_figures(column, tmp_path):
    _, mesh, solver, built = column
    state = solver.state()
    eps = built.strain.cell_mean(state)
    cells = np.zeros(mesh.num_owned_cells, bool)
    cells[mesh.cells("lift2:1")] = True
    window = (-1.0, -1.0, 3.0, 5.0)
    paths = construction_figures(tmp_path, mesh, state, eps, active=state.active,
                                 window=window, when="test",
                                 column=Column(cells, 1.0, 0.1, 3.9, (3.0, 4.0), name="fill"))
    names = {p.name for p in paths}
    assert names == {f"end_of_construction_{n}.png" for n in (
        "sigma_yy", "sigma_xx", "sigma_xy", "yielded", "vertical_strain",
        "displacement_vectors", "fill_profiles")}
    safety = SafetyResult(1.5, (1.5, 1.6), 1.0, trials=[(1.5, True, 3)], state=state,
                          mechanism=state.u.x.array.copy())
    paths = safety_figures(tmp_path, mesh, safety, active=state.active, window=window,
                           circle=SlipCircle(1.4, (1.0, 5.0), 3.0, 0.0, 2.0))
    assert [p.name for p in paths] == ["fos_plastic_strain.png", "fos_mechanism.png"]
    assert all(p.is_file() and p.stat().st_size > 0 for p in paths)
    # the engineering figures at F: the incremental shear strain only with a mechanism
    circle = SlipCircle(1.4, (1.0, 5.0), 3.0, 0.0, 2.0)
    paths = safety_engineering_figures(tmp_path / "a", safety, circle=circle, window=window)
    assert [p.name for p in paths] == ["fos_deformed_mesh.png", "fos_shear_strain.png",
                                       "fos_plastic_points.png"]
    confirmed = dataclasses.replace(safety, mechanism_confirmed=True)
    paths = safety_engineering_figures(tmp_path / "b", confirmed, prefix="f_")
    assert paths[-1].name == "f_incremental_shear_strain.png" and len(paths) == 4
    with pytest.raises(ValueError, match="no state"):
        safety_engineering_figures(tmp_path, dataclasses.replace(safety, state=None))


def test_construction_checks_and_safety_report(column):
    """The unplaced-fill check; the last factor of safety with the lift it was found after."""
    _, _, solver, built = column
    check = built.checks()["max_stress_in_unplaced_lifts"]
    assert check.passed and check.computed == built.max_unplaced_stress == 0.0
    assert built.safety_report() == {}  # none asked for
    safety = SafetyResult(1.5, (1.5, 1.6), 1.0, trials=[(1.5, False, 3)],
                          state=solver.state(), mechanism=solver.u.x.array.copy())
    stages = [{**built.stages[0], "factor_of_safety": 1.7}, built.stages[1]]
    with_fos = dataclasses.replace(built, stages=stages, safety=safety, safety_wall_time=2.5)
    report = with_fos.safety_report()
    assert report["F"] == 1.5 and report["after_lift"] == 1 and report["fill_level_m"] == 3.0
    assert report["wall_time_s"] == 2.5
    assert set(safety.as_dict()) < set(report)


def test_staged_figures(column, tmp_path):
    """The construction figures, and the safety figures only with a factor of safety."""
    _, mesh, solver, built = column
    state, window = solver.state(), (-1.0, -1.0, 3.0, 5.0)
    paths = staged_figures(tmp_path / "a", mesh, state, built, window=window)
    assert {p.name for p in paths} == {f"end_of_construction_{n}.png" for n in (
        "sigma_yy", "sigma_xx", "sigma_xy", "yielded", "vertical_strain",
        "displacement_vectors")}
    safety = SafetyResult(1.5, (1.5, 1.6), 1.0, trials=[(1.5, False, 3)], state=state,
                          mechanism=state.u.x.array.copy())
    with_fos = dataclasses.replace(built, completed=False, safety=safety)
    paths = staged_figures(tmp_path / "b", mesh, state, with_fos, window=window)
    assert len(paths) == 7 and paths[-1].name == "fos_plastic_strain.png"
    # with the engineering figures: those of the state, then those at F
    paths = staged_figures(tmp_path / "c", mesh, state, with_fos, window=window,
                           engineering="fill at 4 m")
    assert [p.name for p in paths[7:]] == [
        "end_of_construction_deformed_mesh.png", "end_of_construction_shear_strain.png",
        "end_of_construction_plastic_points.png", "fos_deformed_mesh.png",
        "fos_shear_strain.png", "fos_plastic_points.png"]
    assert all(p.is_file() for p in paths)


def test_handover_after_construction(column):
    """The cells in place are handed over, the lifts of a group merged into the group."""
    _, mesh, solver, built = column
    snap = solver.snapshot()  # as if the next lift had collapsed: back to this state
    hand = from_construction(solver, dataclasses.replace(built, before_collapse=snap))
    assert hand.discrete.n_elements == mesh.num_owned_cells  # every lift is in place
    groups = element_groups(hand)
    assert set(groups) == {"lift1", "lift2"}
    assert (groups == "lift2").sum() == len(mesh.cells("lift2:1")) + len(mesh.cells("lift2:2"))


def test_construction_report(column):
    """The construction block of a summary: the record's own numbers, the caller's measures
    after the level, the state's yielded cells and fractions, the solver's iterations."""
    _, mesh, solver, built = column
    state = solver.state()
    top = mesh.cells("lift2:2")
    report = built.report(solver, state, 3.5, measures={"max_settlement_m": -0.01},
                          groups={"top": top})
    assert list(report) == ["completed", "stages", "fill_level_m", "collapsing_lift",
                            "max_settlement_m", "yielded_cells", "top_yielded_fraction",
                            "newton_iterations", "wall_time_s"]
    assert report["completed"] is built.completed and report["stages"] is built.stages
    assert report["fill_level_m"] == built.level_carried == 4.0
    assert report["collapsing_lift"] is None
    assert report["yielded_cells"] == len(state.yielded_cells()) == 0  # elastic
    assert report["top_yielded_fraction"] == state.yielded_fraction(top)
    assert report["newton_iterations"] == solver.iterations_total > 0
    assert report["wall_time_s"] == 3.5
    # the unit's key in lower case
    od = dataclasses.replace(built, unit="m_OD", stages=[
        {**st, "top_m_OD": st["top_m"]} for st in built.stages])
    assert od.report(solver, state, 0.0)["fill_level_m_od"] == 4.0


def test_safety_report_with_circle_and_groups(column):
    """The factor of safety with the caller's measures, the yielded fractions at F and the
    limit-equilibrium circle; the check against the circle only with both."""
    _, mesh, solver, built = column
    state = solver.state()
    safety = SafetyResult(1.5, (1.5, 1.6), 1.0, trials=[(1.5, False, 3)], state=state,
                          mechanism=state.u.x.array.copy())
    stages = [built.stages[0], {**built.stages[1], "factor_of_safety": 1.5}]
    with_fos = dataclasses.replace(built, stages=stages, safety=safety)
    circle = SlipCircle(1.4, (1.0, 5.0), 3.0, 0.0, 2.0)
    report = with_fos.safety_report(measures={"note": 1}, groups={"top": mesh.cells("lift2:2")},
                                    circle=circle)
    assert list(report)[-3:] == ["note", "top_yielded_fraction", "bishop"]
    assert report["bishop"] == circle.as_dict() and report["after_lift"] == 2
    check = with_fos.safety_checks(circle)["fos_vs_bishop"]
    assert (check.computed, check.reference, check.bar) == (1.5, 1.4, None)
    assert with_fos.safety_checks(None) == {} and built.safety_checks(circle) == {}


def test_ground_stage_and_levels(column):
    """The first stage on a fresh solver of the column: only the ground active, at rest under
    its own weight (the checks pass), displacements zeroed, stresses kept; a construction's
    values at fixed levels (None where no complete lift has that top) and one item of a
    mapping recorded per lift."""
    from hybrid.continuum.staging import ground_stage

    _, mesh, solver, built = column
    fresh = PlasticSolver(solver.model, degree=2)
    iterations, far = ground_stage(fresh, ["lift1"], (1.0, 1.0), ground_level=2.0,
                                   unit_weight=GAMMA, nu=NU, steps=2)
    assert iterations == fresh.iterations_total > 0
    assert fresh.active[mesh.cells("lift1")].all() and not fresh.active[mesh.cells("lift2:1")].any()
    assert all(c.passed for c in far.checks.values())
    assert far.checks["far_field_sigma_v"].reference == pytest.approx(-GAMMA)
    assert not fresh.u.x.array.any()
    assert far.stress[1] == pytest.approx(fresh.state().stress_at(np.array([[1.0, 1.0]]))[0][1])
    assert built.at_levels("lift", [3.0, 3.5, 4.0]) == {"3": 1, "3.5": None, "4": 2}
    marked = dataclasses.replace(built, stages=[{**st, "at": {"a": st["lift"], "b": 0}}
                                                for st in built.stages])
    assert marked.history("at", "a") == [(3.0, 1), (4.0, 2)] == marked.history("lift")


def test_fill_not_yet_placed_never_yields():
    """A 4 m wide, 6 m high fill of three 2 m lifts (c = 5 kPa, phi = 25 deg, no tension)
    placed lift by lift: the lift not yet placed carries no stress and gathers no plastic
    strain, though the lifts below it settle and drag its lowest nodes (the trial stress of
    its cells is tensile); before, its points gathered plastic strain (3.7e-2 here) that
    the handover and the yielded-zone reports counted."""
    mesh = build_mesh(load_builder(MESHES / "layers.py"), width=4.0, lift_thickness=2.0,
                      lifts=3)
    fill = Material(name="fill", E=5000.0, nu=0.3, unit_weight=20.0, cohesion=5.0, phi=25.0,
                    tensile_strength=0.0)
    names = ["lift1", "lift2", "lift3"]
    solver = PlasticSolver(Model(mesh, dict.fromkeys(names, fill), supports=[
        Fixed("base"), Roller("left", "x"), Roller("right", "x")]), degree=2)
    solver.set_active([])
    for lift in names[:2]:
        solver.activate([lift], steps=2).require()
    unplaced = mesh.cells("lift3")
    n = solver.sspace.num_cells
    assert solver.plastic_strain.reshape(n, -1)[unplaced].max() == 0.0
    assert np.abs(solver.stress.reshape(n, -1, 4)[unplaced]).max() == 0.0
    assert solver.state().yielded_fractions({"lift3": unplaced}) == {"lift3_yielded_fraction": 0.0}
