"""Measures of a discrete state (slip, slip surface, its trace, a slope's movement) and the
snapshot figures of a run."""

import math

import numpy as np
import pytest

from hybrid.discrete import rectangle
from hybrid.discrete.figures import Snapshots
from hybrid.discrete.measures import (
    CrackWatch,
    SlipSurface,
    SlopeMarks,
    crack_from_top,
    failure_onset,
    first_failures,
    interface_opening,
    interface_slip,
    interfaces_between,
    interfaces_of,
    mean_displacement,
    moving_zone_back,
    slip_along,
    slip_surface,
    slip_trace,
    slipped_interfaces,
    surface_opening,
    top_interfaces,
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


def test_interface_opening_is_the_separation_along_the_normal():
    """Pulling B away from A opens the interface; sliding along it does not; pushing overlaps."""
    st = _two_blocks(0.0)
    b = int(st.interface_elements[0, 1])
    away = 1.0 if st.element_centroids()[b, 0] > st.element_centroids()[1 - b, 0] else -1.0
    for move, expected in (((0.2 * away, 0.0), 0.2), ((0.0, 0.3), 0.0),
                           ((-0.05 * away, 0.1), -0.05)):
        st.x[:] = st.x_ref
        st.x[st.element_nodes[b]] += move
        assert interface_opening(st) == pytest.approx([expected], abs=1e-12), move


def _column_with_cracks(failed_rows):
    """Two columns of three 1 m squares; the vertical interfaces of ``failed_rows`` failed,
    the right column's elements of those rows pulled 0.2 m to the right."""
    st = rectangle(2.0, 3.0, 2, 3, material=ROCK)
    centre = st.element_centroids()
    mid = st.x_ref[st.interface_nodes[:, :2]].mean(axis=1)
    vertical = np.flatnonzero(np.isclose(mid[:, 0], 1.0))
    for row in failed_rows:
        st.interface_intact[vertical[np.isclose(mid[vertical, 1], row + 0.5)]] = False
        right = np.flatnonzero((centre[:, 0] > 1.0) & np.isclose(centre[:, 1], row + 0.5))
        st.x[st.element_nodes[right]] += (0.2, 0.0)
    return st, mid


def test_crack_from_top_follows_connected_failed_interfaces_down():
    st, mid = _column_with_cracks([2, 1])  # the top two rows: one crack 2 m deep
    crack = crack_from_top(st, (0.5, 1.5), min_opening=0.1, top_depth=0.01)
    assert crack.top == 3.0 and crack.depth == pytest.approx(2.0)
    assert sorted(mid[crack.interfaces, 1].tolist()) == [1.5, 2.5]
    assert crack.max_opening == pytest.approx(0.2) and crack.max_slip == pytest.approx(0.2)
    # a failed interface not joined to the top does not count: the crack stops at 1 m
    st, mid = _column_with_cracks([2, 0])
    crack = crack_from_top(st, (0.5, 1.5), min_opening=0.1, top_depth=0.01)
    assert mid[crack.interfaces, 1].tolist() == [2.5] and crack.depth == pytest.approx(1.0)
    # nothing reaches the top, or it opened less than min_opening: no crack
    st, _ = _column_with_cracks([0])
    assert crack_from_top(st, (0.5, 1.5), min_opening=0.1, top_depth=0.01).depth == 0.0
    st, _ = _column_with_cracks([2])
    none = crack_from_top(st, (0.5, 1.5), min_opening=0.5, top_depth=0.01)
    assert not none.interfaces.any() and none.depth == 0.0
    with pytest.raises(ValueError, match="no node in the column"):
        crack_from_top(st, (5.0, 6.0), min_opening=0.1, top_depth=0.01)
    # the right column slid 0.3 m down along the failed interfaces from the top without
    # opening: a slip surface, no crack
    st, _ = _column_with_cracks([2, 1])
    st.x[:] = st.x_ref
    st.x[np.unique(st.element_nodes[st.element_centroids()[:, 0] > 1.0])] += (0.0, -0.3)
    assert interface_slip(st).max() == pytest.approx(0.3)
    slid = crack_from_top(st, (0.5, 1.5), min_opening=0.1, top_depth=0.01)
    assert not slid.interfaces.any() and slid.depth == 0.0


def test_failure_onset_by_interface_set():
    """Where and how bonds began to fail, from the recorded time and mode of each failed
    interface: the first time and its modes per set, all modes, sets with none failed, the
    first check's bonds by set, failures not recorded by a run (nan time) counted but never
    first, and a failure by a run without a time making the first time unknown."""
    from hybrid.discrete import ties

    st, mid = _column_with_cracks([])
    top = top_interfaces(st, (0.5, 1.5), top_depth=0.01)
    assert mid[top].tolist() == [[1.0, 2.5]]  # the vertical interface reaching the top
    left = interfaces_of(st, st.element_centroids()[:, 0] < 1.0)
    assert left.sum() == 5  # the left column's two horizontal and the three vertical ones
    vertical = np.isclose(mid[:, 0], 1.0)
    low = vertical & (mid[:, 1] < 1.0)
    # the top vertical interface failed in tension at 0.2 s, the lowest one in shear at 0.1 s
    # and the one between them by the caller (no time, no mode)
    for where, t, mode in ((top, 0.2, ties.FAIL_TENSION), (low, 0.1, ties.FAIL_SHEAR),
                           (vertical & ~top & ~low, math.nan, 0)):
        st.interface_intact[where] = False
        st.interface_failure_time[where] = t
        st.interface_mode[where] = mode
    onset = failure_onset(st, {"top": top, "left": left, "right_top": ~left & ~vertical,
                               "all": np.ones_like(top)})
    assert onset["top"].first_time == 0.2 and onset["top"].first_modes == {"tension": 1}
    assert onset["all"].first_time == 0.1 and onset["all"].first_modes == {"shear": 1}
    assert onset["all"].failed == 3
    assert onset["all"].modes == {"not_recorded": 1, "tension": 1, "shear": 1}
    assert onset["left"].modes == onset["all"].modes  # every vertical one borders the left
    none = onset["right_top"]
    assert math.isnan(none.first_time) and none.failed == 0 and none.modes == {}
    assert none.summary()["first_failure_s"] is None
    assert onset["top"].summary() == {"first_failure_s": 0.2,
                                      "first_failure_modes": {"tension": 1}, "failed": 1,
                                      "failed_by_mode": {"tension": 1}}
    # the first check that failed a bond, and where its bonds lie
    assert first_failures(st, {"top": top, "left": left}) == (
        0.1, {"interfaces": 1, "top": 0, "left": 1, "elsewhere": 0})
    assert first_failures(st, {"top": top}) == (
        0.1, {"interfaces": 1, "top": 0, "elsewhere": 1})
    # one failed in a run without a time (resumed from an older checkpoint): not known
    st.interface_failure_time[low] = math.nan
    unknown = failure_onset(st, {"all": np.ones_like(top)})["all"]
    assert math.isnan(unknown.first_time) and unknown.first_modes == {}
    assert unknown.modes == {"not_recorded": 1, "tension": 1, "shear": 1}
    first, counts = first_failures(st, {"top": top})
    assert math.isnan(first) and counts == {"interfaces": 0, "top": 0, "elsewhere": 0}
    # failed, but none by a run: counted, no first time
    st.interface_failure_time[:] = math.nan
    st.interface_mode[:] = 0
    caller = failure_onset(st, {"all": np.ones_like(top)})["all"]
    assert math.isnan(caller.first_time) and caller.failed == 3 and caller.first_modes == {}


def test_slip_along_the_face_between_two_zones():
    """The face between the two columns: its three vertical interfaces, 3 m long; those of
    the rows pulled apart by 0.2 m slipped (failed, slip >= min_slip), the others not."""
    st, mid = _column_with_cracks([2, 1])
    left = st.element_centroids()[:, 0] < 1.0
    face = interfaces_between(st, left, ~left)
    assert np.isclose(mid[face, 0], 1.0).all() and face.sum() == 3
    assert not interfaces_between(st, left, left & ~left).any()  # an empty zone: no face
    along = slip_along(st, face, 0.1)
    assert along == pytest.approx({"interfaces": 3, "length_m": 3.0, "slipped_interfaces": 2,
                                   "slipped_length_m": 2.0, "max_slip_m": 0.2})
    assert slip_along(st, face, 0.5)["slipped_interfaces"] == 0
    st.interface_intact[:] = True  # intact: on no slip surface, whatever the separation
    assert slip_along(st, face, 0.1)["slipped_length_m"] == 0.0
    assert slip_along(st, face, 0.1)["max_slip_m"] == 0.0


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


def test_slip_surface_gathers_the_measures():
    st = _two_blocks(0.3)
    sets = {"left": np.array([True, False])}
    surface = SlipSurface.of(st, 0.1, sets, thresholds=(0.5,))
    assert surface.interfaces.tolist() == [True]
    assert surface.by_threshold == slipped_interfaces(st, (0.1, 0.5), sets)
    assert surface.through == {"interfaces": 1, "left": 1}
    assert surface.trace == [[1.0, 0.5]]
    (label, segments), = surface.lines(st).items()
    assert label == "slip surface: slipped >= 0.1 m"
    # the interface on its first element's side, where that element is now
    np.testing.assert_allclose(segments, st.x[st.interface_nodes[:, :2]][None, 0])
    assert SlipSurface.of(st, 1.0, sets).interfaces.tolist() == [False]
    assert surface.summary() == {
        "slip_surface_interfaces": 1, "slip_surface_left": 1,
        "slip_surface_trace_m": [[1.0, 0.5]],
        "slipped_interfaces_by_threshold_m": surface.by_threshold}
    checks = SlipSurface.of(st, 0.1, {**sets, "none": np.zeros(2, bool)}).checks(
        {"left": "a left element", "none": "no element"})
    assert checks["slip_surface_through_left"].passed
    assert not checks["slip_surface_through_none"].passed
    assert checks["slip_surface_through_left"].source == (
        "failed interfaces slipped >= 0.1 m with a left element")


def test_mean_displacement():
    st = _two_blocks(0.3)  # the right block moved 0.3 m up
    assert mean_displacement(st, np.array([False, True])) == pytest.approx((0.0, 0.3))
    assert mean_displacement(st, np.array([True, True])) == pytest.approx((0.0, 0.15))


def test_slope_marks_toe_crest_and_movement():
    """A 3 x 2 block of 1 m cells: the crest is the top row inside the x range, the toe the
    first node of smallest (facing -x) or largest (facing +x) x."""
    st = rectangle(3.0, 2.0, 3, 2, material=ROCK)
    marks = SlopeMarks.pick(st, np.ones(st.n_elements, bool), crest_x=(0.5, 2.5))
    assert sorted(map(tuple, st.x[marks.crest])) == [(1.0, 2.0)] * 2 + [(2.0, 2.0)] * 2
    assert tuple(st.x[marks.toe]) == (0.0, 0.0) and marks.facing == -1
    st.x[:, 0] -= 0.4  # everything slides 0.4 m towards -x ...
    st.x[marks.crest, 1] -= 0.2  # ... and the crest drops 0.2 m
    st.x[marks.toe, 0] -= 1.0  # the toe runs out 1 m further
    moved = marks.movement(st)
    assert moved.toe_dx == pytest.approx(-1.4)
    assert moved.crest_drop == pytest.approx(0.2)
    assert moved.run_out == pytest.approx(1.4)
    ahead = SlopeMarks.pick(st, np.ones(st.n_elements, bool), crest_x=(-1.0, 3.0),
                            crest_depth=0.1, facing=1)  # the crest nodes that did not drop
    assert sorted(st.x[ahead.crest, 0]) == pytest.approx([-0.4, 2.6])  # corner nodes
    assert st.x[ahead.toe, 0] == st.x[:, 0].max()
    assert ahead.movement(st).run_out == pytest.approx(-0.4)  # nothing moved towards +x
    with pytest.raises(ValueError, match="facing"):
        SlopeMarks.pick(st, np.ones(st.n_elements, bool), crest_x=(0.0, 1.0), facing=0)


def test_moving_zone_back_finds_a_wedge_and_ignores_a_flung_fragment():
    """A 60 deg wedge behind a face at x = 0 moved by 0.5 m, and one element far behind it
    moved too: the back of the moving zone is the wedge's (within the 0.5 m bins: the line
    through the last moving centroids of each level, 1.5 deg), the far element is not."""
    st = rectangle(10.0, 10.0, 20, 20, material=ROCK)
    c = st.element_centroids()
    wedge = c[:, 0] < 1.0 + c[:, 1] / math.tan(math.radians(60.0))
    far = np.flatnonzero((c[:, 0] > 8.0) & (c[:, 1] < 1.0))[:1]
    for moved in (wedge, far):
        nodes = np.unique(st.element_nodes[moved])
        st.x[nodes, 0] -= 0.5
    everything = np.ones(st.n_elements, dtype=bool)
    angle, a = moving_zone_back(st, everything, 10.0, 0.5, 0.05)
    assert abs(angle - 60.0) < 1.5 and abs(a - 1.0) < 0.5
    assert np.isnan(moving_zone_back(st, everything, 10.0, 0.5, 1.0)[0])  # nothing moved 1 m


def test_crack_watch_keeps_a_crack_that_closed_before_rest():
    """The deepest crack from the top over a run, though it closed again by the end (what
    crack_from_top at rest misses), its first time and the widest opening at the surface."""
    class Run:  # what the watch reads of a solver: its state
        def __init__(self, state):
            self.state = state

    watch = CrackWatch((0.5, 1.5), min_opening=0.1, top_depth=0.01)
    stages = [([], 0.0), ([2], 1.0), ([2, 1], 2.0), ([2, 1], 3.0)]
    for rows, time in stages:
        st, _ = _column_with_cracks(rows)
        st.time = time
        if time == 3.0:  # closed again: the failed interfaces' sides back together
            st.x[:] = st.x_ref
        watch.checked(Run(st), None)
    assert not crack_from_top(st, (0.5, 1.5), min_opening=0.1, top_depth=0.01).interfaces.any()
    assert watch.seen and watch.first_time == 1.0 and watch.deepest_time == 2.0
    assert watch.depth == pytest.approx(2.0) and watch.interfaces == 2
    assert watch.max_opening == pytest.approx(0.2)
    assert watch.surface_opening == pytest.approx(0.2) and watch.checks == 4
    summary = watch.summary("crack")
    assert summary["crack_seen"] and summary["crack_deepest_m"] == pytest.approx(2.0)
    # a checkpoint restores what it had seen
    again = CrackWatch((0.5, 1.5), min_opening=0.1, top_depth=0.01)
    again.restore(watch.state())
    assert again.summary("crack") == summary
    with pytest.raises(ValueError, match="no crack watch's state"):
        again.restore({})  # a checkpoint without it: refused, not resumed empty
    # never open: none seen, times None; a crack narrower than min_opening is still a width
    # at the surface
    narrow = CrackWatch((0.5, 1.5), min_opening=0.5, top_depth=0.01)
    st, _ = _column_with_cracks([2])
    narrow.checked(Run(st), None)
    assert not narrow.seen and narrow.summary("c")["c_first_time_s"] is None
    assert narrow.surface_opening == pytest.approx(0.2)
    assert surface_opening(st, (0.5, 1.5), top_depth=0.01) == pytest.approx(0.2)
    st, _ = _column_with_cracks([0])  # failed below the top only
    assert surface_opening(st, (0.5, 1.5), top_depth=0.01) == 0.0
