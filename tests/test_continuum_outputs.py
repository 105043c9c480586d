"""The continuum's time series (``ContinuumSeries``) and its engineering figures."""

import meshio
import numpy as np
import pytest

from hybrid.continuum import PlasticSolver
from hybrid.continuum.series import CELL_FIELDS, ContinuumSeries
from hybrid.continuum.strength_reduction import StrengthSearch, factor_of_safety
from hybrid.figures import (
    MOHR_COULOMB,
    TENSION_CUTOFF,
    _nice_scale,
    engineering_figures,
    plastic_points,
    shear_strain,
)
from hybrid.geometry import build_mesh
from hybrid.materials import Material
from hybrid.model import Displacement, Fixed, Model, Pressure, Roller

SMOOTH_BOX = [Roller("base", "y"), Roller("left", "x")]


def _pressed_block(builder) -> PlasticSolver:
    """A 1 m block of Tresca clay (c = 20 kPa) on smooth supports, a pressure on its top."""
    mesh = build_mesh(builder("block"), width=1.0, height=1.0, nx=2, ny=2,
                      cells="quadrilateral")
    clay = Material(name="clay", E=1e4, nu=0.3, cohesion=20.0, plastic=True)
    return PlasticSolver(Model(mesh, {"soil": clay}, supports=SMOOTH_BOX,
                               loads=[Pressure("top", 1.0)]), degree=1)


def _read(path):
    """(times, point data, cell data) of every step of a series read by meshio."""
    with meshio.xdmf.TimeSeriesReader(path) as reader:
        points, cells = reader.read_points_cells()
        steps = [reader.read_data(k) for k in range(reader.num_steps)]
    return points, cells, steps


def test_load_steps_make_a_series_meshio_reads(builder, tmp_path):
    """The start and each of 3 load steps are frames, the time is the load factor (the
    pressure, 10 kPa a step), the fields are named as in the discrete series, the material
    names and the time's meaning are in the file, and the uniform vertical stress of the
    block is the pressure at each frame (rounding level)."""
    solver = _pressed_block(builder)
    with ContinuumSeries(tmp_path / "load.xdmf", solver) as series:
        assert solver.ramp(30.0, 3).completed
    assert solver not in solver.observers
    points, cells, steps = _read(tmp_path / "load.xdmf")
    assert len(points) == 9 and cells[0].data.shape == (4, 4)
    assert [t for t, _, _ in steps] == pytest.approx([0.0, 10.0, 20.0, 30.0], rel=1e-12)
    for time, point_data, cell_data in steps:
        assert set(point_data) == {"displacement"} and point_data["displacement"].shape == (9, 2)
        assert set(cell_data) == {*CELL_FIELDS, "material"}
        np.testing.assert_allclose(cell_data["sigma_yy"][0], -time, atol=1e-9 * 30.0)
        assert np.all(cell_data["material"][0] == 0)
    text = (tmp_path / "load.xdmf").read_text()
    assert 'Name="material_names" Value="0: soil"' in text
    assert "load factor" in text
    report = series.report()
    assert report["frames"] == 4 and report["times"][-1] == pytest.approx(30.0)
    assert report["time"].startswith("load factor")


def test_every_other_step_and_the_last_one(builder, tmp_path):
    """every = 2 over 3 steps: the start, step 2 and, at close, step 3."""
    solver = _pressed_block(builder)
    with ContinuumSeries(tmp_path / "s.xdmf", solver, every=2, time="step"):
        solver.ramp(30.0, 3)
    _, _, steps = _read(tmp_path / "s.xdmf")
    assert [t for t, _, _ in steps] == [0.0, 2.0, 3.0]
    assert len(list((tmp_path / "s_frames").glob("frame_*.h5"))) == 3


def test_strength_search_series_follows_the_path_back(builder, tmp_path):
    """A slope too weak for its weight at F = 1: the search restores the unloaded state and
    strengthens (F down to 0.5), so the series drops the frames above; its times rise
    strictly and end at the factor of safety found."""
    mesh = build_mesh(builder("slope"), height=10.0, angle=60.0, foundation_depth=0.0,
                      toe_x=0.0, crest_length=6.0, size=2.0)
    soil = Material(name="soil", E=5e4, nu=0.3, unit_weight=20.0, cohesion=2.0, phi=5.0)
    solver = PlasticSolver(Model(mesh, {"soil": soil},
                                 supports=[Fixed("base"), Roller("right", "x")]), degree=1)
    with ContinuumSeries(tmp_path / "fos.xdmf", solver, time="strength_factor") as series:
        result = factor_of_safety(solver, search=StrengthSearch(tolerance=0.02),
                                  gravity_steps=2)
    assert result.start < 1.0
    _, _, steps = _read(tmp_path / "fos.xdmf")
    times = np.array([t for t, _, _ in steps])
    assert len(steps) == len(series.frames) >= 3
    assert np.all(np.diff(times) > 0.0)
    assert times[0] == pytest.approx(result.start) and times[-1] == pytest.approx(result.factor)
    assert len(list((tmp_path / "fos_frames").glob("frame_*.h5"))) == len(steps)


def test_a_time_function_needs_its_meaning(builder, tmp_path):
    """A time given as a function without what it means, an unknown name, a bad every."""
    solver = _pressed_block(builder)
    with pytest.raises(ValueError, match="needs its meaning"):
        ContinuumSeries(tmp_path / "a.xdmf", solver, time=lambda s: 0.0)
    with pytest.raises(ValueError, match="choose one of load_factor"):
        ContinuumSeries(tmp_path / "a.xdmf", solver, time="pressure")
    with pytest.raises(ValueError, match="every = 0"):
        ContinuumSeries(tmp_path / "a.xdmf", solver, every=0)
    assert solver.observers == []


def _block_moved(builder, uy: float, **strength) -> PlasticSolver:
    """The 1 m block with its top moved by ``uy`` [m] in one step (smooth box, free right)."""
    mesh = build_mesh(builder("block"), width=1.0, height=1.0, nx=2, ny=2,
                      cells="quadrilateral")
    clay = Material(name="clay", E=1e4, nu=0.3, plastic=True, **strength)
    solver = PlasticSolver(Model(mesh, {"soil": clay},
                                 supports=[*SMOOTH_BOX, Displacement("top", uy=uy)]), degree=1)
    assert solver.step(d_lambda=1.0) is not None
    return solver


def test_plastic_points_tell_shear_from_tension(builder):
    """The block squeezed 1 % (100 kPa elastic, Tresca c = 20 kPa) has every point on the
    Mohr-Coulomb surface (4 cells x 4 points); pulled 1 % with a 5 kPa tension cut-off, the
    stress is the cut-off everywhere (sigma_yy = 5 kPa) and the points that flowed (the top
    row) are tension cut-off points."""
    squeezed = _block_moved(builder, -0.01, cohesion=20.0).state()
    xy, kinds = plastic_points(squeezed)
    assert xy.shape == (16, 2) and np.all(kinds == MOHR_COULOMB)
    pulled = _block_moved(builder, 0.01, cohesion=20.0, tensile_strength=5.0).state()
    np.testing.assert_allclose(pulled.stress[..., 1], 5.0, rtol=1e-9)
    xy, kinds = plastic_points(pulled)
    assert len(kinds) == int((pulled.yielded > 0).sum()) >= 8
    assert np.all(kinds == TENSION_CUTOFF)
    assert np.all((xy > 0.0) & (xy < 1.0))  # the points inside the block


def test_shear_strain_of_a_uniform_squeeze(builder):
    """Elastic block (c large) squeezed 0.1 % on a smooth box, free to bulge: eps_yy =
    -0.001, eps_xx = nu / (1 - nu) x 0.001 (plane strain), so gamma_s = eps_xx - eps_yy."""
    state = _block_moved(builder, -0.001, cohesion=1e4).state()
    expected = 0.001 * (1.0 + 0.3 / 0.7)
    np.testing.assert_allclose(shear_strain(state), expected, rtol=1e-9)
    np.testing.assert_allclose(shear_strain(state, increment=0.5 * state.u.x.array),
                               0.5 * expected, rtol=1e-9)


def test_engineering_figures_are_written(builder, tmp_path):
    """The deformed mesh, total and incremental shear strain and plastic points; a 1-2-5
    scale that draws the largest displacement about 5 % of the model."""
    state = _block_moved(builder, -0.01, cohesion=20.0).state()
    paths = engineering_figures(tmp_path, state, prefix="x_", when="squeezed",
                                increment=state.u.x.array)
    assert [p.name for p in paths] == ["x_deformed_mesh.png", "x_shear_strain.png",
                                       "x_plastic_points.png", "x_incremental_shear_strain.png"]
    assert all(p.stat().st_size > 10_000 for p in paths)
    assert _nice_scale(0.0224, 32.0) == 50.0 and _nice_scale(0.01, 1.0) == 5.0
    assert _nice_scale(0.0, 1.0) == 1.0
