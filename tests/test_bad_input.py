"""Bad input gets a clear message (or a non-zero exit), never a traceback, a crash or a number.

One test per kind of fault: the discrete run's monitors, the continuum's singular systems,
meshes and loads, case parameters, and (slow) MPI jobs that must fail fast.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from hybrid.discrete.builders import blocks, rectangle
from hybrid.discrete.ledger import EnergyLedger
from hybrid.discrete.solver import RUNAWAY_MARGIN, _Monitor, run
from hybrid.materials import Contact, Material

BLOCK = Material(name="block", E=1.0e5, nu=0.3, density=2.0,
                 contact=Contact(damping=0.2, phi=30.0))


def _stacked():
    """A block resting 2 cm above a held one: contact, gravity, 4 elements."""
    st = blocks([(1.0, 0.5, 2, 1, (0.0, 0.0), 0), (1.0, 0.5, 2, 1, (0.0, 0.52), 0)], [BLOCK])
    st.fix(np.isclose(st.x_ref[:, 1], 0.0))
    return st


# -- discrete: monitors on the ledger ----------------------------------------------------------

@pytest.mark.parametrize("fault, message", [
    (lambda st: st.gravity.__setitem__(1, math.nan), "gravity holds non-finite values"),
    (lambda st: st.external_force.__setitem__((3, 0), math.inf),
     "external_force holds non-finite values at node 3"),
    (lambda st: st.prescribed_velocity.__setitem__((0, 1), math.nan),
     "prescribed_velocity holds non-finite values at node 0"),
    (lambda st: st.contact_table.__setitem__((0, 3), 1.5),
     r"contact damping ratio 1.5 of material 0 is outside \[0, 1\]"),
])
def test_discrete_run_refuses_bad_inputs(fault, message):
    st = _stacked()
    fault(st)
    with pytest.raises(ValueError, match=f"discrete run refused: {message}"):
        run(st, max_steps=10)


def test_discrete_run_refuses_a_massless_free_tie_group():
    st = rectangle(1.0, 1.0, 1, 1, material=BLOCK)
    st.mass[:] = 0.0
    st.refresh_groups()
    with pytest.raises(ValueError, match=r"tie group\(s\) free to move have no mass"):
        run(st, max_steps=10)


def test_energy_without_a_source_stops_the_run_and_names_the_cause():
    """Contact damping of 1.5 slipped in after the start: the bodies are pushed apart, the
    energy grows past its sources and the run stops, blaming the damping ratio (not dt)."""
    st = _stacked()

    def corrupt(state):
        state.contact_table[:, 3] = 1.5

    with pytest.raises(RuntimeError, match=(
            r"unstable at step \d+ .*above the margin of 2 x.*Cause: contact damping ratio "
            r"1.5 of material 0")):
        run(st, max_steps=20_000, mass_damping=2.0, check_every=200, on_check=corrupt)


def test_nan_gravity_mid_run_is_named_not_dt():
    st = _stacked()

    def corrupt(state):
        state.gravity[1] = math.nan

    with pytest.raises(RuntimeError, match="non-finite .*Cause: gravity holds non-finite"):
        run(st, max_steps=2000, check_every=50, on_check=corrupt)


def test_monitor_stops_slow_growth_beyond_the_margin():
    """The energy grows 1.2x per check (never 10x) and is stopped once above the margin."""
    st = rectangle(1.0, 1.0, 1, 1, material=BLOCK)
    terms = dict.fromkeys(EnergyLedger.__dataclass_fields__, 0.0)
    start = EnergyLedger(**{**terms, "kinetic": 1.0})
    monitor = _Monitor(st, start, 1e-4)
    energy, checks = 1.0, 0
    with pytest.raises(RuntimeError, match="above the margin"):
        while checks < 100:
            energy *= 1.2
            monitor.check(st, EnergyLedger(**{**terms, "kinetic": energy}))
            monitor.e_prev = energy
            checks += 1
    assert RUNAWAY_MARGIN < energy <= 1.2 * RUNAWAY_MARGIN + 1e-9


def test_discrete_run_refuses_a_nan_end_time():
    with pytest.raises(ValueError, match="until_time = nan: must be a finite time"):
        run(rectangle(1.0, 1.0, 1, 1, material=BLOCK), until_time=math.nan)
