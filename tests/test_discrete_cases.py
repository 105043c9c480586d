"""The discrete-engine case scripts (D1/D2, D5, D6, D10) run end to end with reduced outputs.

Each case is run through its ``main`` into tmp_path; every check with a bar must pass (the bars
are those of verification-targets.md, stated again below), and the outputs users open must
exist: summary.json, discrete.xdmf (+h5, a meshio time series), the GIF and the energy plot.
"""

import json

import meshio
import numpy as np
import pytest
from conftest import assert_bars


def _assert_outputs(out, summary, min_frames=1):
    """summary.json mirrors the summary; the XDMF time series opens, names its materials
    and holds every element with the displacement and stress fields; the GIF, PNG frames
    and energy plot exist."""
    data = json.loads((out / "summary.json").read_text())
    assert set(data["checks"]) == set(summary["checks"])
    for name, check in summary["checks"].items():
        assert data["checks"][name]["passed"] == check.passed, name
    for name in ("discrete.xdmf", "discrete.h5", "discrete.gif", "energy.png"):
        assert (out / name).is_file(), name
    assert 'Name="material_names" Value="0: ' in (out / "discrete.xdmf").read_text()
    reader = meshio.xdmf.TimeSeriesReader(out / "discrete.xdmf")
    points, cells = reader.read_points_cells()
    assert reader.num_steps >= min_frames
    t, point_data, cell_data = reader.read_data(reader.num_steps - 1)
    assert point_data["displacement"].shape == points.shape
    assert cell_data["sigma_yy"][0].shape == (cells[0].data.shape[0],)
    assert len(list((out / "frames").glob("frame_*.png"))) == reader.num_steps


def test_free_fall_case(case, tmp_path):
    """D1: acceleration g to 1e-9 relative, a_x, v_x and stress zero to 1e-9 (of g, of
    rho g L); D2: terminal velocity g / alpha = 3.27 m/s to 0.5 % and the whole v(t) history
    within 0.5 % of g / alpha of the closed form (bars of verification-targets D1, D2)."""
    mod = case("free_fall")
    # t_end = 3 s: 1 - exp(-9) = 0.99988 of g / alpha, far inside the 0.5 % bar
    s = mod.main(out=tmp_path, t_end=3.0, output_every=1000, progress=False)
    checks = s["checks"]
    assert checks["D1_acceleration_y"].reference == pytest.approx(9.81)
    assert checks["D1_acceleration_y"].bar == 1e-9
    assert checks["D2_terminal_velocity"].reference == pytest.approx(9.81 / 3.0)
    assert checks["D2_terminal_velocity"].bar == 5e-3
    assert_bars(s)
    assert s["stop_reason"] == "time"
    _assert_outputs(tmp_path, s, min_frames=2)
    assert (tmp_path / "velocity.png").is_file()


def test_block_drop_case(case, tmp_path):
    """D5: at rest the dropped block's mean sigma_yy is -rho g h / 2 (statics, any support
    layout) and each base block's bottom row carries its column plus half the top block
    (5 % bar); E_kin + E_strain never exceeds E(0) + work of gravity by more than 1 %."""
    mod = case("block_drop")
    s = mod.main(out=tmp_path, output_every=5_000, progress=False)
    assert s["stop_reason"] == "rest"
    ref = s["checks"]["dropped_block_mean_sigma_yy"]
    assert ref.reference == pytest.approx(-2.0 * 9.81 * 0.5 / 2.0)  # -rho g h / 2 [kPa]
    assert ref.bar == 0.05
    assert s["checks"]["energy_excess_over_sources"].bar == 0.01
    assert_bars(s)
    # symmetric set-up: both base blocks carry the same load (to 5 %, the stress bar)
    left = s["checks"]["base_left_bottom_row_sigma_yy"].computed
    right = s["checks"]["base_right_bottom_row_sigma_yy"].computed
    assert abs(left / right - 1.0) < 0.05
    _assert_outputs(tmp_path, s, min_frames=2)


def test_fe_de_interaction_case(case, tmp_path):
    """D6: the block's vertical stress is -q = -200 kPa (load / width, 5 % bar); the top row
    of the assembly carries q B (5 %) and the base reaction is q B (1 %, equilibrium)."""
    mod = case("fe_de_interaction")
    s = mod.main(out=tmp_path, output_every=5000, progress=False)
    assert s["stop_reason"] == "rest"
    c = s["checks"]
    assert c["block_sigma_yy"].reference == -200.0 and c["block_sigma_yy"].bar == 0.05
    assert c["assembly_top_row_load"].reference == pytest.approx(400.0)
    assert c["base_reaction"].bar == 0.01
    assert_bars(s)
    # the block came down onto the assembly: it settled by more than its 0.02 m clearance
    assert s["block_settlement"] > 0.02
    _assert_outputs(tmp_path, s, min_frames=2)


def test_toppling_case(case, tmp_path):
    """D10: the no-tension face splits (every tension failure at a tensile major principal
    stress, exactly), topples, comes to rest before t_end, and its energy stays within 1 %
    of its sources (E(0) + work of gravity)."""
    mod = case("toppling")
    s = mod.main(out=tmp_path, output_every=5_000, progress=False)
    assert s["stop_reason"] == "rest"
    assert_bars(s)
    assert s["n_failed_tension"] > 0
    # it broke up: more than half of the face's 171 interfaces failed
    assert s["n_failed"] > 0.5 * (3 * 25 + 4 * 24)
    assert s["n_failed"] == s["n_failed_tension"] + s["n_failed_shear"]
    # it toppled: the top (10 m) ends below half the face height
    assert s["face_top_height_final"] < 0.5 * s["face_top_height_initial"]
    # and the pieces rest on the ground strip (top at y = 0), none fell past its ends;
    # 0.05 m allows the contact overlap (k_n = 10 E / element size)
    assert s["face_lowest_y"] > -0.05
    _assert_outputs(tmp_path, s, min_frames=2)
    assert (tmp_path / "failures.png").is_file()
    assert np.isfinite(s["first_failure_time"])
