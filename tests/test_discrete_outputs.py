"""The progress bar's rate after compilation and the energy history of a whole phase."""

import numpy as np
import pytest

from hybrid.discrete import rectangle
from hybrid.discrete.energy import phase_history
from hybrid.discrete.ledger import EnergyLedger
from hybrid.discrete.outputs import ProgressBar
from hybrid.discrete.solver import ExplicitSolver, RunOptions
from hybrid.materials import Material


class _Counter:
    """What the bar reads of a solver: its step count."""

    steps = 0


def test_the_bar_rate_starts_after_the_first_check():
    """The bar opens at the run's first check with the steps before it (numba compiling on
    a first run) as its start: 100 more steps in 10 s read as 10 steps/s and the remaining
    800 steps as 80 s, whatever the first 100 took."""
    tqdm = pytest.importorskip("tqdm").tqdm
    bar, solver = ProgressBar(), _Counter()
    bar.run_started(solver, 1000)
    assert bar._bar is None  # nothing shown while the kernels compile
    solver.steps = 100
    bar.checked(solver, None)
    assert (bar._bar.initial, bar._bar.n) == (100, 100)
    solver.steps = 200
    bar.checked(solver, None)
    meter = dict(bar._bar.format_dict, elapsed=10.0, rate=None)
    text = tqdm.format_meter(**meter)
    assert "10.00step/s" in text and "00:10<01:20" in text, text
    bar.run_ended(solver, None)
    assert bar._bar is None
    # the next run of the solver starts its own bar at its own first check
    bar.run_started(solver, 50)
    solver.steps = 220
    bar.checked(solver, None)
    assert (bar._bar.initial, bar._bar.total) == (20, 50)
    bar.run_ended(solver, None)


def test_phase_history_joins_the_runs_of_a_solver():
    """A plastic block dropped under gravity then brought to rest by damping, in two runs of
    one solver: the phase history has every record of both, in time order, the ledger terms
    as recorded, and its last residual is the energy missing since the start of the first
    run (start balance - end balance), which the second run's own residual is not."""
    soft = Material(name="soft", E=2.0e4, nu=0.3, density=2.0, cohesion=8.0, phi=0.0,
                    plastic=True)
    st = rectangle(2.0, 1.0, 4, 2, material=soft)
    st.fix(np.isclose(st.x_ref[:, 1], 0.0))
    start = EnergyLedger.measure(st)
    with ExplicitSolver(st, RunOptions(mass_damping=5.0)) as solver:
        first = solver.run(max_steps=300, check_every=50)
        second = solver.run(max_steps=300, check_every=50)
    end = EnergyLedger.measure(st)
    assert [r.history["step"][-1] for r in solver.results] == [300.0, 600.0]
    h = phase_history([r.history for r in solver.results])
    assert len(h["time"]) == len(first.history["time"]) + len(second.history["time"])
    assert np.all(np.diff(h["time"]) > 0.0)
    np.testing.assert_array_equal(h["work_loads"][-1], end.work_loads)
    missing = start.balance() - end.balance()
    assert first.history["residual"][-1] > 0.0  # plastic dissipation
    assert h["residual"][-1] == pytest.approx(missing, rel=1e-9)
    assert abs(second.history["residual"][-1] - missing) > 0.1 * abs(missing)
    with pytest.raises(ValueError, match="one run at least"):
        phase_history([])
