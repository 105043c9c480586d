"""A run whose elements pancake stops with a clear message instead of ending in NaN."""

import pytest

from hybrid.discrete import rectangle
from hybrid.discrete.integrate import stable_time_step
from hybrid.discrete.solver import run
from hybrid.materials import Material


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
    with pytest.raises(RuntimeError, match="distorted so much that the stable time step"):
        run(st, max_steps=2000, dt=0.5 * dt0, check_every=10, contact=False)
    # it stopped when the height was about half (the stable step ~ height here)
    height = st.x[~bottom, 1].mean() - st.x[bottom, 1].mean()
    assert 0.4 < height < 0.55
