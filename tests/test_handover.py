"""Handover continuum -> discrete: H1 (no jump), conservation, region choice, MPI = serial."""

import subprocess

import numpy as np
import pytest
from conftest import MESHES, PYTHON, ROOT

from hybrid.handover import Region, settle, to_discrete

_SCRIPT = """
import sys
import numpy as np
from mpi4py import MPI
from hybrid.case import load_case
from hybrid.handover import Region, to_discrete
m = load_case("cases/slope_gravity.py")
state = m.solve(m.Parameters(size=2.0, flat=30.0, degree={degree}, cells="{cells}"))
h = to_discrete(state, region=Region(everywhere=True))
if MPI.COMM_WORLD.rank == 0:
    h.discrete.save(sys.argv[1])
"""


def _slope_state(case, degree=2, cells="triangle"):
    m = case("slope_gravity")
    return m.solve(m.Parameters(size=2.0, flat=30.0, degree=degree, cells=cells))


@pytest.mark.parametrize(("degree", "cells"), [(1, "quadrilateral"), (2, "triangle")])
def test_h1_no_jump_at_handover(case, degree, cells):
    """H1: after 2 000 tied steps the stress change is < 2 % of the max stress (target bar),
    the velocities have died out and the out-of-balance force has dropped by > 1e3."""
    state = _slope_state(case, degree, cells)
    h = to_discrete(state, region=Region(everywhere=True))
    report = settle(h, steps=2000)
    assert report.stress_change < 0.02
    assert report.max_velocity < 1e-6  # m/s, against ~1e-1 m of gravity settlement
    assert report.final_residual < 1e-3 * report.initial_residual
    # the settle moves the discrete start by a small fraction of the continuum displacement
    u_max = float(np.max(np.abs(state.u.x.array)))
    assert report.max_displacement < 0.02 * u_max


def test_conservation_and_mapping(case):
    """Element count and mass are carried exactly; Q1 2x2 stresses map point by point."""
    state = _slope_state(case, degree=1, cells="quadrilateral")
    h = to_discrete(state)
    d = h.discrete
    cells = state.comm.allreduce(state.model.mesh.num_owned_cells)
    assert d.n_elements == cells and d.n_nodes == 4 * cells
    # total mass = integral of gamma / g over the deformed mesh (small strain: 1e-3)
    area = state.comm.allreduce(float(np.sum(_areas(state))))
    assert d.mass.sum() == pytest.approx(20.0 / 9.81 * area, rel=1e-3)
    # Gauss-point stresses of the same rule are carried unchanged (as a set per cell)
    n = state.model.mesh.num_owned_cells
    order = np.argsort(state.mesh.topology.original_cell_index[:n])  # the discrete order
    np.testing.assert_allclose(np.sort(d.stress[:, :, 1], axis=1),
                               np.sort(state.stress[order, :, 1], axis=1), rtol=1e-12,
                               atol=1e-9)
    # ... and point by point: each discrete Gauss point gets the stress of the continuum
    # quadrature point at the same place (the 2x2 rules coincide)
    import ufl

    from hybrid.continuum.quadrature import evaluate_at_points
    from hybrid.discrete.state import Q4_GAUSS

    qp = evaluate_at_points(state.disc, ufl.SpatialCoordinate(state.mesh))[order]
    x0 = d.x_ref  # handover geometry (deformed by u: the match is unaffected)
    xi, eta = Q4_GAUSS[:, 0], Q4_GAUSS[:, 1]
    shape = 0.25 * np.stack([(1 - xi) * (1 - eta), (1 + xi) * (1 - eta),
                             (1 + xi) * (1 + eta), (1 - xi) * (1 + eta)], axis=1)
    gp = np.einsum("ka,nad->nkd", shape, x0[d.element_nodes])
    nearest = np.argmin(np.sum((gp[:, :, None] - qp[:, None]) ** 2, axis=-1), axis=2)
    expected = np.take_along_axis(state.stress[order, :, 1], nearest, axis=1)
    np.testing.assert_allclose(d.stress[:, :, 1], expected, rtol=1e-12, atol=1e-9)
    assert h.report["stress_mapping"] == "point by point"
    # supports carried: base nodes held in both directions, side nodes horizontally
    base = h.boundary_nodes["base"]
    assert d.fixed[base].all()
    assert d.fixed[h.boundary_nodes["left"], 0].all()


def test_quadratic_cells_hand_over_their_area_weighted_means(case):
    """Q2 (3 x 3 Gauss) and P2 cells -> Q4 / T3: every discrete Gauss point gets the cell's
    area-weighted mean stress, the continuum's own cell mean (``cell_stress``, the local L2
    projection onto constants), to round-off; on the Q2 cells the plain mean of the nine
    points differs from it (the 3 x 3 rule's weights are unequal). The points' areas sum to
    each cell's own area (the shoelace formula on its undeformed vertices), independently of
    the quadrature. On the affine P2 triangles (equal weights) the two means coincide: that
    part guards the plumbing only."""
    from hybrid.continuum.snapshot import cell_snapshot

    state = _slope_state(case, degree=2, cells="quadrilateral")
    snap = cell_snapshot(state)
    xc = snap.x_undeformed[snap.cells]
    shoelace = 0.5 * np.abs(np.sum(xc[:, :, 0] * np.roll(xc[:, :, 1], -1, axis=1)
                                   - np.roll(xc[:, :, 0], -1, axis=1) * xc[:, :, 1], axis=1))
    np.testing.assert_allclose(snap.point_areas.sum(axis=1), shoelace, rtol=1e-12)
    d = to_discrete(state).discrete
    n = state.model.mesh.num_owned_cells
    order = np.argsort(state.mesh.topology.original_cell_index[:n])  # the discrete order
    expected = state.cell_stress()[order]
    scale = float(np.max(np.abs(expected)))
    for k in range(d.stress.shape[1]):
        np.testing.assert_allclose(d.stress[:, k], expected, rtol=0, atol=1e-12 * scale)
    plain = state.stress[order].mean(axis=1)
    assert np.max(np.abs(plain - expected)) > 1e-6 * scale  # the test tells the two apart
    tri = _slope_state(case, degree=2, cells="triangle")
    order = np.argsort(tri.mesh.topology.original_cell_index[:tri.model.mesh.num_owned_cells])
    np.testing.assert_allclose(to_discrete(tri).discrete.stress[:, 0],
                               tri.cell_stress()[order], rtol=0,
                               atol=1e-12 * float(np.max(np.abs(tri.stress))))


def test_region_selection(case):
    """Region by plastic strain (none in an elastic state), by layers, everywhere."""
    state = _slope_state(case)
    none = to_discrete(state)  # elastic: nothing yielded -> no splittable interface
    assert none.report["splittable_interfaces"] == 0
    every = to_discrete(state, region=Region(everywhere=True))
    assert every.report["splittable_interfaces"] == every.report["interfaces"]
    frozen = to_discrete(state, region=Region(everywhere=True), freeze_layers=0)
    assert frozen.report["frozen_elements"] == 0


def _areas(state):
    x, cells = state.model.mesh.cell_vertices()
    p = x[cells]
    return 0.5 * np.abs(np.sum(p[:, :, 0] * np.roll(p[:, :, 1], -1, 1)
                               - np.roll(p[:, :, 0], -1, 1) * p[:, :, 1], axis=1))


@pytest.mark.mpi
def test_mpi_handover_equals_serial(tmp_path):
    """A handover from an mpirun -n 2 continuum gives the serial discrete start (1e-9)."""
    import os
    import shutil

    if shutil.which("mpirun") is None:
        pytest.skip("mpirun not installed")
    script = tmp_path / "h.py"
    script.write_text(_SCRIPT.format(degree=2, cells="triangle"))
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
               NUMBA_NUM_THREADS="1", OMPI_MCA_rmaps_base_oversubscribe="1")
    for n, name in ((1, "serial.npz"), (2, "mpi.npz")):
        cmd = ["mpirun", "-n", "2", PYTHON, str(script), str(tmp_path / name)] if n == 2 else [
            PYTHON, str(script), str(tmp_path / name)]
        r = subprocess.run(cmd, cwd=ROOT, env=env, capture_output=True, text=True, timeout=300)
        assert r.returncode == 0, r.stderr
    a, b = np.load(tmp_path / "serial.npz"), np.load(tmp_path / "mpi.npz")
    for key in ("element_nodes", "node_group", "interface_nodes", "fixed"):
        np.testing.assert_array_equal(a[key], b[key])
    for key in ("x", "mass", "stress"):
        np.testing.assert_allclose(b[key], a[key], rtol=1e-9, atol=1e-9 * np.abs(a[key]).max())


def test_handover_of_a_staged_state():
    """Staged construction: only the lifts in place become elements (2 of 4 lifts here);
    their stresses are carried and the settle shows the start in equilibrium."""
    from hybrid.continuum import PlasticSolver
    from hybrid.geometry import build_mesh, load_builder
    from hybrid.materials import Material
    from hybrid.model import Fixed, Model, Roller

    mesh = build_mesh(load_builder(MESHES / "layers.py"), width=4.0, lift_thickness=1.0,
                      lifts=4)
    fill = Material(name="fill", E=2e4, nu=0.3, unit_weight=20.0, cohesion=20.0, phi=30.0)
    names = [f"lift{k + 1}" for k in range(4)]
    model = Model(mesh, dict.fromkeys(names, fill),
                  supports=[Fixed("base"), Roller("left", "x"), Roller("right", "x")])
    solver = PlasticSolver(model, degree=1)
    solver.set_active([])
    for name in names[:2]:
        assert solver.activate([name]).completed
    state = solver.state()
    hand = to_discrete(state, region=Region(everywhere=True))
    disc = hand.discrete
    placed = sum(len(mesh.cells(n)) for n in names[:2])
    assert disc.n_elements == placed < state.stress.shape[0]
    assert disc.x[:, 1].max() == pytest.approx(2.0, abs=0.01)  # lift 2 top, deformed (~1 mm)
    # base stress of the two lifts: gamma x 2 m (cell means within a cell's depth of it)
    assert disc.stress[:, :, 1].min() == pytest.approx(-40.0, rel=0.15)
    report = settle(hand, steps=1000)
    assert report.stress_change < 0.02


@pytest.mark.parametrize(("gravity", "loads"), [(False, True), (True, False)])
def test_an_elastic_state_hands_over_only_what_acts_in_it(builder, gravity, loads):
    """A state solved without its self-weight (or without its loads) starts the discrete
    phase without them: what acts is what the state was solved with, as after a plastic
    solver's stages (a 2 m x 1 m block, 10 kPa on its top, base fixed)."""
    from hybrid.continuum import solve_elastic
    from hybrid.geometry import build_mesh
    from hybrid.materials import GRAVITY, Material
    from hybrid.model import Fixed, Model, Pressure

    mesh = build_mesh(builder("block"), width=2.0, height=1.0, nx=2, ny=1)
    model = Model(mesh, {"soil": Material(name="soil", E=1e4, nu=0.3, unit_weight=20.0)},
                  supports=[Fixed("base")], loads=[Pressure("top", 10.0)])
    h = to_discrete(solve_elastic(model, gravity=gravity, loads=loads))
    assert h.discrete.gravity.tolist() == ([0.0, -GRAVITY] if gravity else [0.0, 0.0])
    # the pressure acts on the deformed top, stretched by the elastic strain (~1e-4 here)
    assert abs(h.load_forces[:, 1].sum()) == pytest.approx(10.0 * 2.0 if loads else 0.0,
                                                           rel=1e-3)
