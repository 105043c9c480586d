"""Distorted elements: a flowing one parts from its neighbours; one that cannot (held, or a
lone element squashed) stops the run with a clear message instead of ending in NaN."""

import math

import numpy as np
import pytest

from hybrid.discrete import rectangle, ties
from hybrid.discrete.builders import blocks
from hybrid.discrete.integrate import stable_time_step
from hybrid.discrete.outputs import standard_outputs
from hybrid.discrete.solver import ExplicitSolver, RunOptions, run
from hybrid.errors import RunUnstable
from hybrid.materials import Contact, Material


def test_pancaked_element_stops_the_run_clearly():
    """One elastic Q4 squashed by its top nodes: once its stable step (L_min / c_p, here the
    height) falls below the run's dt (0.5 x the initial stable step), the run stops."""
    st = rectangle(1.0, 1.0, 1, 1, "Q4", material=Material(name="block", E=1e4, nu=0.0,
                                                           density=2.0))
    bottom = st.x[:, 1] < 0.5
    st.fix(bottom)
    dt0 = stable_time_step(st)
    # the top moves down at a speed that flattens the element to 1/4 of its height in 2 000 steps
    st.fix(~bottom, velocity=(0.0, -0.75 / (2000 * 0.5 * dt0)))
    st.gravity[:] = 0.0
    with pytest.raises(RuntimeError, match="distorted so much that the time-step scale"):
        run(st, max_steps=2000, dt=0.5 * dt0, check_every=10, contact=False)
    # it stopped when the height was about half (the stable step ~ height here)
    height = st.x[~bottom, 1].mean() - st.x[bottom, 1].mean()
    assert 0.4 < height < 0.55


def test_stable_step_ratio_of_squashed_and_stretched_elements():
    """The ratio is the element's stable step over its initial one: the least altitude
    (A / longest edge for Q4, 2 A / longest edge for T3) and sqrt(1 / longest edge)."""
    for element, altitude in (("Q4", lambda a, lmax: a / lmax),
                              ("T3", lambda a, lmax: 2.0 * a / lmax)):
        st = rectangle(1.0, 1.0, 1, 1, element, material=Material(name="b", E=1e4, nu=0.0,
                                                                   density=2.0))
        assert np.allclose(ties.stable_step_ratio(st), 1.0)
        st.x[:, 1] *= 0.6  # squashed to 0.6 of its height
        ratio = ties.stable_step_ratio(st)
        area0, area = (0.5 if element == "T3" else 1.0), (0.3 if element == "T3" else 0.6)
        lmax0 = math.sqrt(2.0) if element == "T3" else 1.0
        lmax = math.sqrt(1.0 + 0.36) if element == "T3" else 1.0
        expect = min(altitude(area, lmax) / altitude(area0, lmax0), math.sqrt(lmax0 / lmax))
        np.testing.assert_allclose(ratio, expect, rtol=1e-12)
        st.x[:, 1] /= 0.6
        st.x[:, 0] *= 2.0  # stretched to twice its length: the longest edge rules
        lmax = math.sqrt(4.0 + 1.0) if element == "T3" else 2.0
        expect = min(altitude(2.0 * area0, lmax) / altitude(area0, lmax0),
                     math.sqrt(lmax0 / lmax))
        np.testing.assert_allclose(ties.stable_step_ratio(st), expect, rtol=1e-12)
        assert ties.mark_fragments(st) == (st.n_elements if expect < ties.DISTORTION_LIMIT
                                           else 0)


def _slump():
    """A 2 m block of soft clay (c = 3 kPa, phi = 0; a vertical cut stands to about 4 c /
    gamma = 0.6 m) on a rigid ground: it slumps under its own weight."""
    clay = Material(name="clay", E=5e3, nu=0.3, density=2.0, cohesion=3.0, phi=0.0,
                    plastic=True, contact=Contact(phi=20.0, damping=0.2))
    ground = Material(name="ground", E=5e3, nu=0.3, density=2.0,
                      contact=Contact(phi=20.0, damping=0.2))
    st = blocks([(2.0, 2.0, 4, 4, (0.0, 0.0), 0), (8.0, 0.5, 16, 1, (-3.0, -0.5), 1)],
                [clay, ground], rigid=(1,))
    options = RunOptions(split_every=10, mass_damping=1.0, contact=True,
                         contact_bounds=(-10.0, -2.0, 10.0, 4.0))
    return st, options


def test_a_flowing_element_parts_from_its_neighbours_instead_of_pancaking(monkeypatch):
    """Without expert options a perfectly plastic block that slumps comes to rest: elements
    distorted to the limit become fragments (their bonds fail, mode FAIL_DISTORTED) and
    yield no further than their most strained point had, so no element's stable step falls
    to the run's (half the initial one). Without the rule (a limit of 0) the same slump
    pancakes an element and stops the run."""
    st, options = _slump()
    first_marked: dict[int, np.ndarray] = {}

    def record(s):
        for e in np.flatnonzero(np.isfinite(s.fragment_cap)):
            first_marked.setdefault(int(e), s.plastic_strain[e].copy())
        return False

    with ExplicitSolver(st, options) as solver:
        res = solver.run(until_time=6.0, until_rest=1e-4, check_every=10, on_check=record)
    assert res.stop_reason == "rest"
    fragment = np.isfinite(st.fragment_cap)
    assert fragment.any() and (~st.interface_intact).sum() > 0
    # every splittable bond of a fragment has failed
    beside = fragment[st.interface_elements].any(axis=1) & st.interface_splittable
    assert not st.interface_intact[beside].any()
    assert ties.stable_step_ratio(st).min() > 0.5
    assert st.x[:, 0].max() > 3.0  # it spread (from 2 m wide)
    # a fragment's points yield no further than its most strained one had when it was marked
    # (the callback sees it at the check after the marking splitting check, same step here)
    for e, kappa in first_marked.items():
        assert st.fragment_cap[e] == kappa.max()
        assert st.plastic_strain[e][np.argmax(kappa)] == kappa.max()  # the cap held it
    np.testing.assert_array_equal(ties.plastic_cap(st)[fragment], st.fragment_cap[fragment])
    st, options = _slump()
    monkeypatch.setattr(ties, "mark_fragments", lambda state, limit=0.0: 0)
    with ExplicitSolver(st, options) as solver, pytest.raises(RunUnstable, match="distorted"):
        solver.run(until_time=3.0, until_rest=1e-4, check_every=50)


def test_fragments_continue_bit_for_bit_across_runs_and_restarts(tmp_path):
    """The fragments are part of the state: one long run, the same steps in two runs, and a
    run interrupted between splitting checks and resumed from its checkpoint end alike."""
    fields = ("x", "v", "stress", "plastic_strain", "fragment_cap", "interface_intact")
    whole, options = _slump()
    with ExplicitSolver(whole, options) as solver:
        solver.run(max_steps=600, check_every=5)
    assert np.isfinite(whole.fragment_cap).any()
    parts, _ = _slump()
    with ExplicitSolver(parts, options) as solver:
        solver.run(max_steps=205, check_every=5)
        solver.run(max_steps=395, check_every=5)
    for name in fields:
        np.testing.assert_array_equal(getattr(parts, name), getattr(whole, name), err_msg=name)

    def stop(s):
        if s.step >= 300:
            raise KeyboardInterrupt

    def outputs(resume=False):
        return standard_outputs(tmp_path, output_every=0, checkpoint_every=55, progress=False,
                                resume=resume)

    with pytest.raises(KeyboardInterrupt), \
            ExplicitSolver(_slump()[0], options, observers=outputs()) as solver:
        solver.run(max_steps=600, check_every=5, on_check=stop)
    resumed, _ = _slump()
    with ExplicitSolver(resumed, options, observers=outputs(resume=True)) as solver:
        assert solver.steps % 10 != 0  # the checkpoint lies between splitting checks
        solver.run(max_steps=600, check_every=5)
    for name in fields:
        np.testing.assert_array_equal(getattr(resumed, name), getattr(whole, name),
                                      err_msg=name)


def test_a_q4_folding_at_a_corner_becomes_a_fragment_though_its_stable_step_holds():
    """A 2 m x 1 m Q4 deformed into a dart, its lower left corner nearly flat: its area and
    longest edge keep its stable step (A / longest edge, sqrt(1 / longest edge)) at its
    initial value, so the stable-step rule alone leaves it; the corner's Jacobian (the cross
    product of the edges at that corner, 2 x 1 at creation, 2 x 0.1 now) marks it."""
    st = rectangle(2.0, 1.0, 1, 1, "Q4", material=Material(name="b", E=1e4, nu=0.0,
                                                           density=2.0))
    assert np.allclose(ties.corner_ratio(st), 1.0)
    moved = {(0.0, 0.0): (0.0, 0.0), (2.0, 0.0): (2.0, 0.0), (2.0, 1.0): (0.6, 1.4),
             (0.0, 1.0): (-0.8, 0.1)}
    for i, ref in enumerate(st.x_ref):
        st.x[i] = moved[(float(ref[0]), float(ref[1]))]
    # corner (0, 0): edges in from (-0.8, 0.1) and out to (2, 0): 0.8 x 0 + 0.1 x 2 = 0.2
    np.testing.assert_allclose(ties.corner_ratio(st), 0.2 / 2.0, rtol=1e-12)
    area = 0.5 * (2.0 * 1.4 + (0.6 * 0.1 + 0.8 * 1.4))  # shoelace
    lmax = max(2.0, math.hypot(1.4, 1.4), math.hypot(1.4, 1.3), math.hypot(0.8, 0.1))
    expect = min((area / lmax) / (2.0 / 2.0), math.sqrt(2.0 / lmax))
    np.testing.assert_allclose(ties.stable_step_ratio(st), expect, rtol=1e-12)
    assert expect > ties.DISTORTION_LIMIT
    assert ties.mark_fragments(st, corner_limit=0.0) == 0  # the stable step alone: left
    assert ties.mark_fragments(st) == 1
    assert np.isfinite(st.fragment_cap).all()
    # a parallelogram sheared at constant area keeps every corner's Jacobian
    st = rectangle(2.0, 1.0, 1, 1, "Q4", material=Material(name="b", E=1e4, nu=0.0,
                                                           density=2.0))
    st.x[:, 0] += 0.7 * st.x[:, 1]
    np.testing.assert_allclose(ties.corner_ratio(st), 1.0, rtol=1e-12)
