"""Energy ledger of the discrete engine with contact.

The ledger (``hybrid.discrete.ledger.EnergyLedger``) must balance:

    E_kin + E_strain + E_contact + D_damping + D_friction + D_contact_damping
        + D_normal_defect + residual = E(0) + W_loads + W_supports,

and the residual (plastic dissipation is zero here) is asserted within 2 % of the energy scale
(the largest work of gravity and loads during the run), the bar.  Before the fix
the block drop with contact damping 0.2 ran at -18 %: the damping dissipation was taken as
c_n v_n^2 dt with the start-of-step velocity, which overestimates it when the contact vibrates
at a few time steps per period.
"""

import math

import numpy as np
import pytest

from hybrid.discrete.builders import blocks
from hybrid.discrete.ledger import EnergyLedger
from hybrid.discrete.solver import run
from hybrid.materials import Contact, Material

G_ACC = 9.81


def _residual_ratio(res):
    """max |residual| over the run / energy scale (largest |work of gravity and loads|)."""
    h = res.history
    scale = float(np.max(np.abs(h["work_loads"])))
    return float(np.max(np.abs(h["residual"]))) / scale, scale


@pytest.mark.parametrize("zeta", [0.2, 0.0])
def test_block_drop_ledger_balances(zeta):
    """D5 set-up (a block dropped on two base blocks, run to rest): the ledger balances
    within 2 % of the work of gravity with and without contact damping."""
    mat = Material(name="block", E=1.0e5, nu=0.3, density=2.0,
                   contact=Contact(damping=zeta, phi=30.0))
    st = blocks([(1.0, 1.0, 4, 4, (0.0, 0.0), 0), (1.0, 1.0, 4, 4, (1.2, 0.0), 0),
                 (2.2, 0.5, 8, 2, (0.0, 1.05), 0)], [mat])
    st.fix(np.isclose(st.x_ref[:, 1], 0.0))
    res = run(st, until_rest=1e-6, max_steps=40000, mass_damping=2.0,
              check_every=200)
    assert res.stop_reason == "rest"
    ratio, scale = _residual_ratio(res)
    # bar: 2 % of the energy scale (measured 0.6 % with zeta = 0.2, 1.4 % with 0:
    # the staggered kinetic energy during the impacts)
    assert ratio < 0.02
    led = EnergyLedger.measure(st)
    if zeta > 0.0:
        # the damper took a visible share of the energy (measured 35 % of the work of gravity)
        assert led.contact_damping > 0.1 * scale
    else:
        assert led.contact_damping == 0.0
    # the area-based normal force is nearly conservative: what it absorbs or gives over the
    # impacts stays small (measured +3.0 % and -0.9 %; 5 % would flag a gross error such as
    # the 18 % of the old damping estimate)
    assert abs(led.contact_normal_defect) < 0.05 * scale


def test_sliding_block_friction_is_mu_n_slip_and_ledger_balances():
    """A block pushed along a rigid plane by F = 2 mu N slides: the friction dissipation
    over the sliding phase is mu N x slip, and the ledger balances within 2 %."""
    mu = math.tan(math.radians(30.0))
    mat = Material(name="block", E=1.0e5, nu=0.3, density=2.0,
                   contact=Contact(damping=0.2, phi=30.0))
    st = blocks([(20.0, 0.5, 40, 1, (0.0, 0.0), 0), (1.0, 1.0, 2, 2, (1.0, 0.5), 0)], [mat],
                rigid=[0])
    blk = np.unique(st.element_nodes[40:].ravel())
    m = st.mass[blk].sum()
    N = m * G_ACC
    st.external_force[blk, 0] = 2.0 * mu * N * st.mass[blk] / m
    run(st, until_time=0.3, contact=True)  # contact established, sliding
    x0 = st.x[blk, 0].mean()
    d0 = EnergyLedger.measure(st).friction
    res = run(st, until_time=0.8, contact=True, check_every=50)
    slip = st.x[blk, 0].mean() - x0
    d_fric = EnergyLedger.measure(st).friction - d0
    assert slip > 0.1  # it slid (measured 1.56 m)
    # Coulomb: mu N x slip; 2 % (bar of D7; measured -1.5 %: the normal force, on which the
    # cap mu F_n rides, oscillates about N)
    assert abs(d_fric / (mu * N * slip) - 1.0) < 0.02
    ratio, _ = _residual_ratio(res)
    assert ratio < 0.02  # the bar


def test_local_damping_books_nothing_on_a_moving_support():
    """An elastic 1 m x 1 m block (E = 10 MPa) squeezed by its top moving down at 2 mm/s
    (0.5 % strain over the run, base held), with Cundall's local damping 0.7 as the biaxial
    test runs it: a held component moves as prescribed and feels no damping force, so the
    ledger balances as without damping: residual within 1 % of the supports' work (0.2 %
    without damping, the hypoelastic update's error at this strain). Before: the damping of
    the top's prescribed velocity was booked, a residual of 0.7 x the work in size."""
    from hybrid.discrete import rectangle
    from hybrid.discrete.solver import ExplicitSolver, RunOptions

    mat = Material(name="m", E=1.0e4, nu=0.3, density=2.0, plastic=False)
    st = rectangle(1.0, 1.0, 4, 4, material=mat, gravity=(0.0, 0.0))
    st.fix(np.isclose(st.x_ref[:, 1], 0.0))
    st.fix(np.isclose(st.x_ref[:, 1], 1.0), x=False, y=True, velocity=(0.0, -0.002))
    with ExplicitSolver(st, RunOptions(local_damping=0.7, contact=False)) as solver:
        led0 = solver.ledger()
        solver.run(max_steps=4000, check_every=4000)
        led = solver.ledger()
    assert led.work_supports > 0.0
    assert abs(led.residual(led0)) < 0.01 * led.work_supports


def test_supply_of_a_continued_run_counts_from_its_own_start():
    """The ledger's works are totals since the state was made; a run's supply is its energy
    at the start plus the works since (RunResult.start), so a continued run cannot hide
    energy it created behind the work done before it began."""
    from hybrid.discrete.energy import energy_excess, energy_peak_ratio

    start = {"kinetic": 1.0, "strain": 0.0, "contact_elastic": 0.0, "work_loads": 10.0,
             "work_supports": 0.0}
    steady = {"kinetic": np.array([1.0, 1.0]), "strain": np.zeros(2),
              "contact_elastic": np.zeros(2), "work_loads": np.array([10.0, 10.0]),
              "work_supports": np.zeros(2)}
    assert energy_excess(steady, start) == 0.0
    assert energy_peak_ratio(steady, start) == pytest.approx(1.0)
    created = {**steady, "kinetic": np.array([1.0, 2.0])}  # energy from nowhere
    assert energy_excess(created, start) == pytest.approx(1.0)  # (2 - 1) / max |supply| = 1
    # a block falling freely over two runs: each run's start is the ledger it began with,
    # and its energy stays within its supply (E = E(start) + work of gravity, to the
    # staggered kinetic energy's O(dt) lag)
    mat = Material(name="block", E=1.0e5, nu=0.3, density=2.0)
    st = blocks([(1.0, 1.0, 2, 2, (0.0, 0.0), 0)], [mat])
    first = run(st, max_steps=400, dt=1e-4, check_every=50)
    at_second = EnergyLedger.measure(st).as_dict()
    second = run(st, max_steps=400, dt=1e-4, check_every=50)
    assert first.start["work_loads"] == 0.0 and second.start == pytest.approx(at_second)
    assert second.start["work_loads"] > 0.0  # the works carry over from the first run
    for res in (first, second):
        assert energy_excess(res.history, res.start) < 1e-3
        assert energy_peak_ratio(res.history, res.start) == pytest.approx(1.0, abs=1e-2)


def test_runaway_monitor_counts_the_works_from_the_run_start():
    """The monitor's sources of a continued run: its energy at the start plus the work of the
    loads and of the supports since then, each counted from the start (the works before the
    run, and the loads' and supports' works against each other, no longer hide a runaway)."""
    from hybrid.discrete import rectangle
    from hybrid.discrete.monitor import Monitor
    from hybrid.errors import RunUnstable

    st = rectangle(1.0, 1.0, 1, 1, material=Material(name="m", E=1e4, nu=0.3, density=2.0))
    zero = dict.fromkeys(EnergyLedger.__dataclass_fields__, 0.0)
    start = EnergyLedger(**{**zero, "kinetic": 1.0, "work_loads": 100.0,
                            "work_supports": -100.0})
    monitor = Monitor(st, start, dt=1e-3)
    monitor.check(st, EnergyLedger(**{**zero, "kinetic": 1.5, "work_loads": 100.0,
                                      "work_supports": -100.0}))  # within 2 x its sources
    created = EnergyLedger(**{**zero, "kinetic": 151.0, "work_loads": 100.0,
                              "work_supports": -100.0})
    with pytest.raises(RunUnstable, match="above the margin"):
        monitor.check(st, created)
    # checkpointed and restored, the same verdict
    again = Monitor(st, start, dt=1e-3)
    again.restore(monitor.state())
    with pytest.raises(RunUnstable, match="above the margin"):
        again.check(st, created)
    with pytest.raises(ValueError, match="another version"):
        again.restore(monitor.state()[:4])
