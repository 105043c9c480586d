"""Rigid platens (``DiscreteState.tie_rigidly``) and the plastic-strain cap of the element
kernel (``run(plastic_strain_cap=...)``), both added for the hybrid footing failure (H2)."""

import math

import numpy as np
import pytest

from hybrid.discrete import DiscreteState, integrate, rectangle, ties
from hybrid.discrete.solver import run
from hybrid.materials import Bond, Contact, Material, MaterialError


def _block(nx=4, ny=3):
    mat = Material(name="block", E=1.0e4, nu=0.3, density=2.0,
                   bond=Bond(cohesion=0.0, tensile_strength=0.0))
    return rectangle(2.0, 1.5, nx, ny, material=mat, gravity=(0.0, -9.81))


def test_tie_rigidly_keeps_momentum_and_survives_splitting():
    """The platen's nodes get the mass-weighted mean velocity (momentum unchanged, to
    rounding) and stay one tie group, with one velocity, after every interface has failed."""
    st = _block()
    top = np.flatnonzero(np.isclose(st.x_ref[:, 1], 1.5))
    rng = np.random.default_rng(1)
    st.v[:] = rng.normal(size=st.v.shape)
    # ties: members of a group share a velocity (as the engine keeps them)
    for g in range(st.n_groups):
        members = st.group_nodes[st.group_ptr[g]:st.group_ptr[g + 1]]
        st.v[members] = st.v[members[0]]
    p0 = (st.mass[:, None] * st.v).sum(axis=0)
    st.tie_rigidly(top)
    np.testing.assert_allclose((st.mass[:, None] * st.v).sum(axis=0), p0, rtol=1e-12)
    assert len(np.unique(st.node_group[top])) == 1
    np.testing.assert_array_equal(st.v[top], np.broadcast_to(st.v[top[0]], st.v[top].shape))
    n_before = st.n_groups
    ties.split_interfaces(st, np.ones(st.interface_intact.size, dtype=bool))
    assert len(np.unique(st.node_group[top])) == 1  # the platen is still one group
    assert st.n_groups > n_before  # everything else came apart
    # it moves as one: every platen node has the same velocity after a short run
    st.v[:] = 0.0
    run(st, max_steps=50, contact=False)
    np.testing.assert_array_equal(st.v[top], np.broadcast_to(st.v[top[0]], st.v[top].shape))


def test_tie_rigidly_in_checkpoints(tmp_path):
    """The platen links are part of the checkpoint: a restart keeps the platen together."""
    st = _block()
    top = np.flatnonzero(np.isclose(st.x_ref[:, 1], 1.5))
    st.tie_rigidly(top)
    back = DiscreteState.load(st.save(tmp_path / "c.npz"))
    np.testing.assert_array_equal(back.rigid_links, st.rigid_links)
    ties.split_interfaces(back, np.ones(back.interface_intact.size, dtype=bool))
    assert len(np.unique(back.node_group[top])) == 1
    with pytest.raises(ValueError, match="out of range"):
        st.tie_rigidly([0, st.n_nodes])


def _sheared(cap):
    """A Tresca block (c = 10 kPa) sheared by its top at constant speed: (plastic strain,
    max |sigma_xy|) after a shear strain of 4 %, 20 times the yield strain."""
    c = 10.0
    mat = Material(name="block", E=1.0e4, nu=0.3, density=1.0, plastic=True, cohesion=c)
    st = rectangle(1.0, 1.0, 2, 2, material=mat, gravity=(0.0, 0.0))
    st.fix(np.isclose(st.x_ref[:, 1], 0.0))
    st.fix(np.isclose(st.x_ref[:, 1], 1.0), velocity=(1e-3, 0.0))
    dt = 0.5 * integrate.stable_time_step(st)
    for _ in range(int(0.04 / 1e-3 / dt)):
        integrate.step(st, dt, local_damping=0.7, plastic_strain_cap=cap)
    return st.plastic_strain.copy(), float(np.max(np.abs(st.stress[..., 3])))


def test_plastic_cap_stops_flow():
    """Without a cap the block flows (Tresca: tau <= c everywhere, plastic strain beyond 2 %);
    with a cap of 1 % no Gauss point goes more than one step's increment past the cap, and the
    shear stress then rises elastically well above c."""
    eps_free, tau_free = _sheared(np.inf)
    eps_cap, tau_cap = _sheared(0.01)
    assert eps_free.max() > 0.02  # flowing freely
    assert tau_free <= 10.0 * (1.0 + 1e-9)
    assert eps_cap.max() >= 0.01 and eps_cap.max() < 0.0101
    assert tau_cap > 2.0 * 10.0


def test_run_rejects_bad_cap():
    st = _block()
    with pytest.raises(ValueError, match="plastic_strain_cap"):
        run(st, max_steps=1, plastic_strain_cap=0.0)


def test_material_reaches_the_discrete_tables():
    """One ``Material`` fills the discrete tables: the contact record (damping, friction, k_n
    defaulting to 10 E / element size, k_t to k_n), the bond (a plastic material's own c, phi
    and apex cut-off; an elastic one's unbreakable), and the weight as density gamma / g.
    Out-of-range contact damping is refused with the record and parameter named."""
    from hybrid.discrete.state import material_rows

    sand = Material(name="sand", E=7e4, nu=0.3, unit_weight=18.0, cohesion=2.0, phi=30.0,
                    contact=Contact(damping=0.2))
    rock = Material(name="rock", E=1e6, nu=0.2, density=2.5,
                    contact=Contact(normal_stiffness=5e6, shear_stiffness=5e5, phi=40.0))
    mt, dens, elastic, bond, contact = material_rows([sand, rock], 0.5)
    assert dens.tolist() == [18.0 / 9.81, 2.5] and elastic.tolist() == [False, True]
    # [k_n, k_t, mu, zeta, c]: no softening, so the contacts carry no cohesion
    np.testing.assert_allclose(contact[0], [1.4e6, 1.4e6, math.tan(math.radians(30)), 0.2, 0.0])
    np.testing.assert_allclose(contact[1], [5e6, 5e5, math.tan(math.radians(40)), 0.0, 0.0])
    np.testing.assert_allclose(bond[0], [2.0, math.tan(math.radians(30)),
                                         2.0 / math.tan(math.radians(30))])
    assert bond[1, 0] == bond[1, 2] == math.inf
    with pytest.raises(MaterialError, match="Contact: damping = 1.5"):
        Material(name="sand", E=7e4, nu=0.3, unit_weight=18.0, phi=30.0,
                 contact=Contact(damping=1.5))


def test_frozen_elements_do_not_limit_the_time_step():
    """A held (frozen) stiff element does not move, so only the free soft element sets the
    stable time step; with nothing free the elements' own bound is returned."""
    from hybrid.discrete.builders import blocks

    soft = Material(name="block", E=1.0e3, nu=0.3, density=2.0)
    stiff = Material(name="block", E=1.0e7, nu=0.3, density=2.0)
    st = blocks([(1.0, 1.0, 1, 1, (0.0, 0.0), 0), (1.0, 1.0, 1, 1, (2.0, 0.0), 1)],
                [soft, stiff], gravity=(0.0, 0.0))
    both = integrate.stable_time_step(st, contact=False)
    st.fix(st.element_nodes[1])
    free = integrate.stable_time_step(st, contact=False)
    assert free == pytest.approx(both * 100.0, rel=1e-12)  # c_p ratio sqrt(1e7 / 1e3)
    st.fix(st.element_nodes[0])
    assert integrate.stable_time_step(st, contact=False) == pytest.approx(both, rel=1e-12)


def _punched_block(speed, target, *, other_moving=False):
    """An elastic block (E = 10 MPa, nu = 0.3, no gravity) on a smooth base, its top a smooth
    rigid platen pushed down by a :class:`PunchProgram` to ``target``, then unloaded."""
    from hybrid.discrete.runs import PunchProgram

    mat = Material(name="block", E=1.0e4, nu=0.3, density=2.0)
    st = rectangle(1.0, 1.0, 4, 4, material=mat, gravity=(0.0, 0.0))
    base = np.isclose(st.x_ref[:, 1], 0.0)
    st.fix(base, x=False, y=True)
    st.fix(np.flatnonzero(base & np.isclose(st.x_ref[:, 0], 0.0)), x=True, y=False,
           velocity=(0.1 if other_moving else 0.0, 0.0))
    top = np.flatnonzero(np.isclose(st.x_ref[:, 1], 1.0))  # a smooth platen: y held only
    applied = []
    program = PunchProgram(top, apply=applied.append,
                           measure=lambda: -float(np.mean(st.x[top, 1] - st.x_ref[top, 1])),
                           width=1.0, speed=speed, target=target, ramp_time=0.05,
                           max_time=10.0, t_start=0.0, window=0.2 * target)
    return st, program, applied


def test_punch_program_measures_the_elastic_bearing_pressure():
    """A slow push of an elastic block on a smooth base is a plane-strain uniaxial test: the
    platen's pressure is E / (1 - nu^2) * s / H (Timoshenko & Goodier, plane strain with the
    sides free). Pushed at 2 mm/s (inertia rho v^2 ~ 1e-5 kPa against about 2 kPa), the mean
    pressure over the push is half the final one, measured from the supports' work within 1 %
    (the explicit push rings a little about the static response). The program then asks for
    that pressure and lowers it to 0 (recorded here, not put on the block: the platen is let
    go) and the block springs back elastic."""
    from hybrid.discrete.solver import ExplicitSolver, RunOptions

    target, h = 2.0e-4, 1.0
    st, program, applied = _punched_block(2.0e-3, target)
    program.start(st)
    assert applied == [0.0] and st.fixed[program.nodes, 1].all()
    modulus = 1.0e4 / (1.0 - 0.3 ** 2)  # [kPa]
    with ExplicitSolver(st, RunOptions(contact=False, mass_damping=2.0)) as solver:
        solver.run(until_time=1.0, on_check=program, check_every=2)
        assert program.removed and applied[-1] == 0.0
        s_end = program.at_unloading
        assert s_end == pytest.approx(target, rel=0.02)
        # the pressure let go: the mean over the last window (a fifth of the push, or a little
        # more: it ends at a check), so the pressure at its middle, 0.1 target back or more
        expected_end = modulus * (s_end - 0.1 * target) / h
        assert program.pressure_at_unloading == pytest.approx(expected_end, rel=0.02)
        assert program.mean_pressure(0.0, s_end) == pytest.approx(
            0.5 * modulus * s_end / h, rel=0.01)
        assert applied[1] == program.pressure_at_unloading  # let go under what it carried
        solver.run(until_rest=1e-4, max_steps=200_000)
    assert abs(program.measure()) < 0.01 * target  # elastic: back where it started


def test_punch_program_refuses_other_moving_supports():
    """The supports' work is the platen's only if no other support moves."""
    st, program, _ = _punched_block(1.0e-3, 1.0e-4, other_moving=True)
    with pytest.raises(ValueError, match="other supports move"):
        program.start(st)
    from hybrid.discrete.runs import PunchProgram
    with pytest.raises(ValueError, match="window"):
        PunchProgram(program.nodes, apply=print, measure=float, width=1.0, speed=1.0,
                     target=0.1, ramp_time=0.1, max_time=1.0, t_start=0.0, window=0.2)
    with pytest.raises(ValueError, match="speed"):
        PunchProgram(program.nodes, apply=print, measure=float, width=1.0, speed=0.0,
                     target=0.1, ramp_time=0.1, max_time=1.0, t_start=0.0)
