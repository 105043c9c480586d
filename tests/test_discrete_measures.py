"""Interface measures of a discrete state (slip, slip surface, its trace) and the snapshot
figures of a run."""

import numpy as np
import pytest

from hybrid.discrete import rectangle
from hybrid.discrete.figures import Snapshots
from hybrid.discrete.measures import (
    interface_slip,
    slip_surface,
    slip_trace,
    slipped_interfaces,
)
from hybrid.materials import Material

ROCK = Material(name="block", E=1e4, nu=0.2, density=2.0)


def _two_blocks(slide: float):
    """Two 1 m squares side by side; the right one moved up by ``slide`` [m] with their common
    interface failed."""
    st = rectangle(2.0, 1.0, 2, 1, material=ROCK)
    assert len(st.interface_intact) == 1
    st.interface_intact[:] = False
    st.x[st.element_nodes[1]] += (0.0, slide)
    return st


def test_interface_slip_and_surface():
    st = _two_blocks(0.3)
    assert interface_slip(st) == pytest.approx([0.3], rel=1e-12)
    assert slip_surface(st, 0.1).tolist() == [True]
    assert slip_surface(st, 0.5).tolist() == [False]
    st.interface_intact[:] = True  # an intact interface is never on the slip surface
    assert slip_surface(st, 0.1).tolist() == [False]


def test_slip_trace_is_in_the_start_geometry():
    st = _two_blocks(0.3)
    assert slip_trace(st, slip_surface(st, 0.1)) == [[1.0, 0.5]]
    assert slip_trace(st, slip_surface(st, 1.0)) == []


def test_slipped_interfaces_by_threshold_and_element_set():
    st = _two_blocks(0.3)
    sets = {"left": np.array([True, False]), "none": np.zeros(2, bool)}
    assert slipped_interfaces(st, (0.1, 0.5), sets) == {
        "0.1": {"interfaces": 1, "left": 1, "none": 0},
        "0.5": {"interfaces": 0, "left": 0, "none": 0}}


def test_snapshots_once_per_time(tmp_path):
    st = _two_blocks(0.0)
    shots = Snapshots(tmp_path, [1.0, 0.5], prefix="s", title="at {time:.2f} s")
    st.time = 0.2
    assert shots(st) is False and shots.paths == []
    st.time = 1.5  # past both times: both written, with the current time in the title
    assert shots(st) is False
    assert shots.paths == [tmp_path / "s0.5.png", tmp_path / "s1.png"]
    assert all(p.is_file() for p in shots.paths)
    st.time = 2.0
    shots(st)
    assert len(shots.paths) == 2
