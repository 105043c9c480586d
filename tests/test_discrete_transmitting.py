"""Transmitting (viscous) boundaries of the discrete engine: a wave leaves the model.

A strip of Q4 elements held in x carries only vertical motion: a one-dimensional shear
beam along x with the wave speed V_s = sqrt(G / rho) (held in y instead, a pressure wave
at V_p = sqrt((K + 4G/3) / rho), with the dashpots on the ends' normal). A dashpot c per
unit length on the vertical velocity at an end reflects a wave arriving along x with the
amplitude ratio R = (rho V_s - c) / (rho V_s + c) (Lysmer & Kuhlemeyer 1969): none at
c = rho V_s (``DiscreteState.set_transmitting``), the energy fraction
((1 - k) / (1 + k))^2 for c = k rho V_s, all of it for c = 0 (a plain roller).
"""

import math

import numpy as np
import pytest

from hybrid.discrete import integrate, rectangle
from hybrid.discrete.ledger import EnergyLedger
from hybrid.materials import Material
from hybrid.model import ModelError, Roller

SOIL = Material(name="soil", E=1.0e5, nu=0.3, density=2.0)
LENGTH = 100.0  # [m]
N = 200  # elements along the strip (h = 0.5 m)
WIDTH = 5.0  # the pulse's standard deviation [m]: 10 elements, little numerical dispersion


def _end_edges(st, x_end: float) -> np.ndarray:
    """(node a, node b, element) of the element edges on the line x = x_end."""
    rows = []
    for e, nodes in enumerate(st.element_nodes):
        on = [int(n) for n in nodes if math.isclose(st.x_ref[n, 0], x_end, abs_tol=1e-9)]
        if len(on) == 2:
            rows.append((on[0], on[1], e))
    return np.array(rows, dtype=np.int64)


def _beam(dashpot_factor: float, wave: str = "shear"):
    """The strip with a velocity pulse at mid-length and both ends' dashpots
    ``dashpot_factor`` x the matched ones: a shear wave (vertical motion, every node held in
    x, the ends' dashpots on their tangent) or a pressure wave (horizontal motion, every
    node held in y, the ends' dashpots on their normal). Returns the state and its
    mechanical energy [kJ/m]."""
    st = rectangle(LENGTH, 1.0, N, 1, material=SOIL, gravity=(0.0, 0.0))
    moving = 1 if wave == "shear" else 0
    st.fix(np.ones(st.n_nodes, dtype=bool), x=moving == 1, y=moving == 0)
    if dashpot_factor > 0.0:
        for x_end in (0.0, LENGTH):
            st.set_transmitting(_end_edges(st, x_end), axis=moving, normal=wave == "pressure")
        st.dashpot *= dashpot_factor
    st.v[:, moving] = 0.01 * np.exp(-0.5 * ((st.x_ref[:, 0] - 0.5 * LENGTH) / WIDTH) ** 2)
    return st, integrate.kinetic_energy(st)


def _shear_beam(dashpot_factor: float):
    """``_beam`` carrying a shear wave."""
    return _beam(dashpot_factor, "shear")


def _run_past_the_ends(st, speed: float | None = None, mass_damping: float = 0.0) -> float:
    """Step until every part of the pulse has met an end and come back past mid-length (at
    ``speed``, default V_s); returns the mechanical energy left (kinetic + strain) [kJ/m]."""
    speed = speed or math.sqrt(SOIL.shear_modulus / SOIL.density)
    dt = 0.5 * integrate.stable_time_step(st)
    while st.time < (LENGTH + 4 * WIDTH) / speed:
        integrate.step(st, dt, external=False, mass_damping=mass_damping)
    led = EnergyLedger.measure(st)
    return led.kinetic + led.strain


def test_matched_dashpots_absorb_a_shear_wave():
    """c = rho V_s: the pulse leaves through the ends (R = 0); the ledger's damping term
    takes what left. Bars 1e-4 of the pulse's energy, both: what is left (the discrete
    beam's dispersion of a pulse 10 elements wide; 2.5e-7 measured) and the ledger's
    residual (bar 1e-8: the dissipation is exactly what the step's mean velocity takes out,
    so only round-off is left; 1e-10 measured)."""
    st, e0 = _shear_beam(1.0)
    left = _run_past_the_ends(st)
    assert left <= 1e-4 * e0
    led = EnergyLedger.measure(st)
    assert abs(led.damping - (e0 - left)) <= 1e-8 * e0


def test_normal_dashpots_absorb_a_pressure_wave():
    """The same strip carrying a pressure wave (horizontal motion): dashpots on the ends'
    normal, sqrt((K + 4G/3) rho), let it leave. Bar 1e-4 of its energy, as for the shear
    wave (1.7e-7 measured)."""
    st, e0 = _beam(1.0, "pressure")
    v_p = math.sqrt((SOIL.bulk_modulus + 4.0 * SOIL.shear_modulus / 3.0) / SOIL.density)
    assert _run_past_the_ends(st, speed=v_p) <= 1e-4 * e0


def test_dashpots_with_mass_damping_keep_the_ledger():
    """Mass damping alpha = 2 1/s beside the dashpots: the ledger's damping term holds both
    dissipations (bar 1e-5 of the pulse's energy: the mass-damping term is taken with the
    mean velocity, as without dashpots; 1.4e-6 measured)."""
    st, e0 = _shear_beam(1.0)
    left = _run_past_the_ends(st, mass_damping=2.0)
    led = EnergyLedger.measure(st)
    assert abs(led.damping - (e0 - left)) <= 1e-5 * e0


def test_a_held_component_ignores_its_dashpot():
    """A dashpot on a component held at a prescribed velocity changes nothing: the state
    steps bit for bit as without it."""
    a = rectangle(2.0, 1.0, 2, 1, material=SOIL)
    a.fix(np.isclose(a.x_ref[:, 1], 0.0))
    b = a.copy()
    b.dashpot[np.isclose(b.x_ref[:, 1], 0.0)] = 1e6
    dt = 0.5 * integrate.stable_time_step(a)
    for _ in range(50):
        integrate.step(a, dt)
        integrate.step(b, dt)
    assert np.array_equal(a.x, b.x) and np.array_equal(a.group_energy, b.group_energy)


def test_dashpots_travel_with_a_checkpoint(tmp_path):
    """``save`` / ``load`` keep the dashpots."""
    from hybrid.discrete.state import DiscreteState

    st, _ = _shear_beam(1.0)
    st.save(tmp_path / "state.npz")
    back = DiscreteState.load(tmp_path / "state.npz")
    assert np.array_equal(back.dashpot, st.dashpot) and back.dashpot.any()


@pytest.mark.parametrize("k", [0.25, 0.5, 2.0])
def test_mismatched_dashpots_reflect_as_lysmer(k):
    """c = k rho V_s reflects the energy fraction ((1 - k) / (1 + k))^2: 0.36 for k = 1/4,
    1/9 for k = 1/2 and 2 (Lysmer & Kuhlemeyer 1969). Bar 0.002 of the pulse's energy
    (2e-4 measured, the discrete beam's dispersion): far below the change a wrong impedance
    makes (V_p for V_s, a factor 1.87 here, would give 0.13, 0.001 and 0.33 for the same
    k)."""
    st, e0 = _shear_beam(k)
    left = _run_past_the_ends(st)
    assert abs(left / e0 - ((1.0 - k) / (1.0 + k)) ** 2) <= 0.002


def test_plain_roller_reflects_everything():
    """No dashpot: the pulse rings between the ends; its energy stays. Bar 1e-3 (9e-5
    measured: the staggered velocity's kinetic energy is taken half a step from the
    strain energy)."""
    st, e0 = _shear_beam(0.0)
    left = _run_past_the_ends(st)
    assert abs(left - e0) <= 1e-3 * e0


def test_set_transmitting_refuses_bad_input():
    """An axis other than 0 or 1, an edge naming a node or an element that does not exist; a
    negative dashpot is refused when a run starts."""
    from hybrid.discrete.monitor import input_fault

    st = rectangle(2.0, 1.0, 2, 1, material=SOIL, gravity=(0.0, 0.0))
    with pytest.raises(ValueError, match="axis"):
        st.set_transmitting(_end_edges(st, 0.0), axis=2)
    with pytest.raises(ValueError, match="do not exist"):
        st.set_transmitting(np.array([[0, st.n_nodes, 0]]), axis=1)
    with pytest.raises(ValueError, match="do not exist"):
        st.set_transmitting(np.array([[0, 1, st.n_elements]]), axis=1)
    st.dashpot[3, 1] = -1.0
    assert "dashpot at node 3" in input_fault(st)


def test_roller_transmitting_must_be_a_bool():
    """A Roller's transmitting flag is True or False (a string would read as True)."""
    with pytest.raises(ModelError, match="transmitting"):
        Roller("right", "x", transmitting="yes")  # type: ignore[arg-type]
