"""Discrete engine dynamics: D1, D2, D4, D9 of verification-targets.md, B-bar, determinism."""

import math

import numpy as np
import pytest

from hybrid.discrete import integrate, rectangle
from hybrid.discrete import solver as discrete_solver
from hybrid.discrete.elements import internal_forces
from hybrid.discrete.outputs import Checkpoints
from hybrid.discrete.solver import run
from hybrid.materials import Bond, Contact, Material

import numba  # isort: skip

G_ACC = 9.81
ROCK = Material(name="block", E=1.0e5, nu=0.3, density=2.0)


def test_d1_free_fall_tied_group():
    """D1: a 4x4 tied group falls freely: every node accelerates at g, no stress, no drift."""
    st = rectangle(4.0, 4.0, 4, 4, material=ROCK)
    dt = 0.5 * integrate.stable_time_step(st)
    for _ in range(50):
        integrate.step(st, dt)
    v0 = st.v.copy()
    integrate.step(st, dt)
    acc = (st.v - v0) / dt
    # bar 1e-9 relative acceleration (verification-targets D1)
    np.testing.assert_allclose(acc[:, 1], -G_ACC, rtol=1e-9)
    assert np.max(np.abs(acc[:, 0])) <= 1e-9 * G_ACC
    # no stress: bar 1e-9 rho g L with L = 4 m
    assert np.max(np.abs(st.stress)) < 1e-9 * 2.0 * G_ACC * 4.0
    # horizontal velocity 0 (relative to the vertical speed g t, same 1e-9 bar)
    assert np.max(np.abs(st.v[:, 0])) <= 1e-9 * G_ACC * st.time
    # the fall itself: v = -g t exactly for constant acceleration (central differences)
    np.testing.assert_allclose(st.v[:, 1], -G_ACC * st.time, rtol=1e-9)


def test_d2_terminal_velocity_with_mass_damping():
    """D2: mass damping alpha = 3 1/s gives the terminal velocity g / alpha = 3.27 m/s."""
    st = rectangle(4.0, 4.0, 4, 4, material=ROCK)
    alpha = 3.0
    res = run(st, until_time=6.0, mass_damping=alpha, check_every=500)
    assert res.stop_reason == "time"
    # after 6 s, 1 - exp(-18) of the terminal speed is reached; bar 0.5 % (D2)
    np.testing.assert_allclose(-st.v[:, 1], G_ACC / alpha, rtol=5e-3)
    # the analytic approach v(t) = g/alpha (1 - exp(-alpha t)) checked early on too
    st2 = rectangle(4.0, 4.0, 4, 4, material=ROCK)
    run(st2, until_time=0.5, dt=res.dt, mass_damping=alpha)
    # the staggered velocity lives at t - dt/2: shift the exact value, 0.5 % bar
    v_exact = G_ACC / alpha * (1.0 - math.exp(-alpha * (st2.time - 0.5 * res.dt)))
    np.testing.assert_allclose(-st2.v[:, 1], v_exact, rtol=5e-3)


def test_d4_p_wave_arrival_in_confined_column():
    """D4: a velocity step at the top of a laterally confined column travels down at
    c_p = sqrt((K + 4G/3) / rho) (thesis eq 3.18)."""
    mat = Material(name="block", E=1.0e5, nu=0.25, density=2.0)
    H = 100.0
    st = rectangle(1.0, H, 1, 200, material=mat, gravity=(0.0, 0.0))
    st.fix(np.ones(st.n_nodes, dtype=bool), x=True, y=False)  # oedometric: u_x = 0
    top = np.isclose(st.x_ref[:, 1], H)
    v0 = -0.01
    st.fix(top, x=False, y=True, velocity=(0.0, v0))
    cp = math.sqrt((mat.bulk_modulus + 4.0 * mat.shear_modulus / 3.0) / mat.density)
    probe = np.flatnonzero(np.isclose(st.x_ref[:, 1], H / 2))  # 50 m below the top
    dt = 0.5 * integrate.stable_time_step(st)
    t_arrival = None
    while st.time < 1.5 * (H / 2) / cp:
        integrate.step(st, dt)
        # the front: the probe reaches half the imposed velocity; v is at t - dt/2
        if t_arrival is None and st.v[probe, 1].mean() <= 0.5 * v0:
            t_arrival = st.time - 0.5 * dt
    assert t_arrival is not None
    # bar 5 % (D4)
    assert abs(t_arrival - (H / 2) / cp) <= 0.05 * (H / 2) / cp


def _rotate_stress(s, a):
    c, si = math.cos(a), math.sin(a)
    R = np.array([[c, -si], [si, c]])
    S = np.array([[s[0], s[3]], [s[3], s[1]]])
    T = R @ S @ R.T
    return np.array([T[0, 0], T[1, 1], s[2], T[0, 1]])


@pytest.mark.parametrize("element", ["Q4", "T3"])
def test_d9_rigid_rotation_of_prestressed_element(element):
    """D9: a prestressed element spun as a rigid body: the stress rotates with it."""
    st = rectangle(2.0, 1.0, 1, 1, element, material=ROCK, gravity=(0.0, 0.0))
    s0 = np.array([100.0, -50.0, -20.0, 30.0])
    st.stress[:] = s0
    st.fix(np.ones(st.n_nodes, dtype=bool))
    c = st.x.mean(axis=0)
    n_steps, total = 40, 0.5 * math.pi + 0.3  # about 107 degrees in 40 steps of 2.7 deg
    da = total / n_steps
    dt = 1.0e-3
    R = np.array([[math.cos(da), -math.sin(da)], [math.sin(da), math.cos(da)]])
    for _ in range(n_steps):
        target = (st.x - c) @ R.T + c
        st.prescribed_velocity[:] = (target - st.x) / dt
        st.v[:] = st.prescribed_velocity
        integrate.step(st, dt)
    exact = _rotate_stress(s0, total)
    err = np.max(np.abs(st.stress - exact))
    # bar 1e-6 relative (D9); the Hughes-Winget update is exact for rigid rotation
    assert err <= 1e-6 * np.max(np.abs(s0))
    # the body itself rotated rigidly (positions to round-off of the prescribed motion)
    ref = (st.x_ref - c) @ np.array([[math.cos(total), -math.sin(total)],
                                     [math.sin(total), math.cos(total)]]).T + c
    np.testing.assert_allclose(st.x, ref, atol=1e-12)


def test_bbar_bending_mode_has_no_volumetric_stress():
    """B-bar: the Q4 bending (hourglass-like) mode u_x = d xi eta keeps the area, so the mean
    dilatation gives no pressure, while full 2x2 integration produces the parasitic pressure
    K d eta_gp / a that locks nearly incompressible / plastic (isochoric) flow."""
    mat = Material(name="block", E=1.0e4, nu=0.49, density=1.0)
    a = 1.0
    d = 1.0e-6
    results = {}
    for bbar in (True, False):
        st = rectangle(2 * a, 2 * a, 1, 1, material=mat, gravity=(0.0, 0.0),
                       origin=(-a, -a))
        xi = st.x[:, 0] / a
        eta = st.x[:, 1] / a
        st.v[:, 0] = d * xi * eta  # unit dt
        internal_forces(st, 1.0, bbar=bbar)
        results[bbar] = st.stress.copy()
    K, G = mat.bulk_modulus, mat.shear_modulus
    p_bbar = results[True][:, :, :3].sum(axis=2) / 3.0
    # exact zero up to round-off of the (K, G) ~ 1e5 products with strains ~ 1e-6
    assert np.max(np.abs(p_bbar)) <= 1e-9 * G * d
    # full integration: theta = du_x/dx = d eta_gp / a at the Gauss point (mid-step metric:
    # the O(d^2) geometric terms are far below the 1e-3 relative tolerance)
    eta_gp = np.array([-1, -1, 1, 1]) / math.sqrt(3.0)
    p_full = results[False][0, :, :3].sum(axis=1) / 3.0
    np.testing.assert_allclose(p_full, K * d * eta_gp / a, rtol=1e-3)
    # the deviatoric part is identical in both formulations (only sigma_xy here: G d xi / a)
    np.testing.assert_allclose(results[True][0, :, 3], results[False][0, :, 3], rtol=1e-9)


def test_dt_above_critical_step_refused():
    st = rectangle(4.0, 4.0, 4, 4, material=ROCK)
    scale = integrate.stable_time_step(st)
    # c_p = sqrt((K + 4G/3)/rho), L_min = 1 m for unit squares: closed form to 1e-12
    cp = math.sqrt((ROCK.bulk_modulus + 4 * ROCK.shear_modulus / 3) / ROCK.density)
    assert scale == pytest.approx(1.0 / cp, rel=1e-12)
    crit = integrate.critical_time_step(st)
    assert crit < scale  # the Courant scale is no bound (test_critical_time_step_is_the_limit)
    with pytest.raises(ValueError, match="above the critical time step"):
        run(st, max_steps=1, dt=1.01 * crit)


def _free_run(st, dt, steps=3000):
    """|v|max after ``steps`` from a small random velocity at ``dt``, the check bypassed
    (None: the run was stopped as unstable)."""
    from hybrid.discrete import solver as solver_mod
    from hybrid.errors import RunUnstable

    st.gravity[:] = 0.0
    st.v[:] = 1e-6 * np.random.default_rng(1).standard_normal(st.v.shape)
    orig = solver_mod.integrate.check_dt
    try:
        solver_mod.integrate.check_dt = lambda *a, **k: dt
        run(st, max_steps=steps, dt=dt, split_every=0)
    except RunUnstable:
        return None
    finally:
        solver_mod.integrate.check_dt = orig
    return float(np.abs(st.v).max())


@pytest.mark.parametrize("nu", [0.3, 0.49])
def test_critical_time_step_is_the_limit(nu):
    """critical_time_step is the stability limit of a free Q4 (2 / omega_max of the element
    kernel's own tangent): a run at 0.98 x it stays at its small start velocity, at 1.02 x
    it grows without bound. On a tied 6 x 6 mesh it is a lower bound (element eigenvalue
    theorem): 0.98 x is stable, while the Courant scale L_min / c_p (stable_time_step, 1.2 x
    the critical step at nu 0.3, 1.4 x at 0.49 on squares) is unstable, so check_dt refuses
    it."""
    mat = Material(name="m", E=1e4, nu=nu, density=2.0)
    one = rectangle(1.0, 1.0, 1, 1, material=mat)
    crit = integrate.critical_time_step(one, contact=False)
    # the ratio docs/hybrid.md quotes (measured to its three decimals, pinned so the docs stay
    # true); the check against the reference, the scheme's stability, is the bracket below
    assert integrate.stable_time_step(one, contact=False) / crit == pytest.approx(
        {0.3: 1.195, 0.49: 1.400}[nu], abs=1e-3)
    assert _free_run(rectangle(1.0, 1.0, 1, 1, material=mat), 0.98 * crit) < 1e-5
    assert _free_run(rectangle(1.0, 1.0, 1, 1, material=mat), 1.02 * crit) is None
    for element in ("Q4", "T3"):
        mesh = rectangle(1.0, 1.0, 6, 6, element, material=mat)
        crit = integrate.critical_time_step(mesh, contact=False)
        scale = integrate.stable_time_step(mesh, contact=False)
        assert _free_run(rectangle(1.0, 1.0, 6, 6, element, material=mat), 0.98 * crit) < 1e-5
        assert _free_run(rectangle(1.0, 1.0, 6, 6, element, material=mat), scale) is None
        with pytest.raises(ValueError, match="above the critical time step"):
            integrate.check_dt(mesh, scale, contact=False)
        # the solvers' default (half the scale) stays within 0.75 of the critical step
        assert integrate.default_dt(mesh, contact=False) <= 0.75 * crit


def _loaded_block(element="Q4"):
    mat = Material(name="block", E=5.0e4, nu=0.3, density=2.0,
                   bond=Bond(tensile_strength=2.0, cohesion=5.0, phi=30.0))
    st = rectangle(6.0, 3.0, 12, 6, element, material=mat)
    st.fix(np.isclose(st.x_ref[:, 1], 0.0))
    st.fix(np.isclose(st.x_ref[:, 0], 6.0) & (st.x_ref[:, 1] > 1.5), x=True, y=False,
           velocity=(0.05, 0.0))
    return st


def test_results_identical_with_one_and_two_threads(monkeypatch):
    """Bit-for-bit the same state with 1 and 2 numba threads (loads, damping, splitting)."""
    if numba.config.NUMBA_NUM_THREADS < 2:
        pytest.skip("numba has fewer than 2 threads here")
    monkeypatch.setattr(discrete_solver, "SERIAL_BELOW_ELEMENTS", 0)  # small: 2 threads too
    out = {}
    old = numba.get_num_threads()
    try:
        for n in (1, 2):
            numba.set_num_threads(n)
            st = _loaded_block()
            used = set()
            run(st, max_steps=400, mass_damping=2.0, local_damping=0.1, split_every=10,
                contact=False, on_check=lambda _, used=used: used.add(numba.get_num_threads()))
            assert used == {n}
            out[n] = st
    finally:
        numba.set_num_threads(old)
    assert not out[1].interface_intact.all()  # something did split, exercising ties
    for name in ("x", "v", "stress", "internal_force", "group_energy", "ledger", "node_group"):
        assert np.array_equal(getattr(out[1], name), getattr(out[2], name)), name


def test_contact_run_identical_with_one_and_two_threads(monkeypatch):
    """Bit-for-bit with contact too (two blocks dropped on a rigid base, friction, damping)."""
    from hybrid.discrete.builders import blocks

    if numba.config.NUMBA_NUM_THREADS < 2:
        pytest.skip("numba has fewer than 2 threads here")
    monkeypatch.setattr(discrete_solver, "SERIAL_BELOW_ELEMENTS", 0)  # small: 2 threads too
    mat = Material(name="block", E=1.0e5, nu=0.3, density=2.0,
                   contact=Contact(damping=0.1, phi=30.0))
    out = {}
    old = numba.get_num_threads()
    try:
        for n in (1, 2):
            numba.set_num_threads(n)
            st = blocks([(4.0, 0.5, 8, 1, (0.0, 0.0), 0), (1.0, 1.0, 2, 2, (0.5, 0.55), 0),
                         (1.0, 1.0, 2, 2, (1.2, 1.7), 0)], [mat], rigid=[0])
            st.v[:, 0] = 0.5
            st.fix(st.element_nodes[:8].ravel())
            used = set()
            run(st, max_steps=1500, mass_damping=0.5, contact=True,
                on_check=lambda _, used=used: used.add(numba.get_num_threads()))
            assert used == {n}
            out[n] = st
    finally:
        numba.set_num_threads(old)
    assert out[1].contact_pairs.shape[0] > 0
    for name in ("x", "v", "stress", "contact_shear", "ledger"):
        assert np.array_equal(getattr(out[1], name), getattr(out[2], name)), name


def test_checkpoint_restart_bit_for_bit(tmp_path):
    """A run stopped at a checkpoint and restarted from the npz gives the same numbers."""
    st = _loaded_block()
    run(st, max_steps=150, mass_damping=2.0, split_every=10, contact=False,
        observers=[Checkpoints(tmp_path, 150)])
    restarted = type(st).load(tmp_path / "checkpoint.npz")
    run(st, max_steps=150, mass_damping=2.0, split_every=10, contact=False)
    run(restarted, max_steps=150, mass_damping=2.0, split_every=10, contact=False)
    assert restarted.step == st.step == 300
    for name in ("x", "v", "stress", "internal_force", "group_energy", "ledger", "node_group",
                 "interface_intact", "group_ptr"):
        assert np.array_equal(getattr(st, name), getattr(restarted, name)), name


def test_small_runs_step_on_one_thread():
    """A run of fewer than ``SERIAL_BELOW_ELEMENTS`` elements steps on one numba thread (its
    parallel regions cost more than a second thread gains) and gives the caller's thread
    count back afterwards, also when the run raises."""
    if numba.config.NUMBA_NUM_THREADS < 2:
        pytest.skip("numba has fewer than 2 threads here")
    seen = []

    def watch(st):
        seen.append(numba.get_num_threads())
        if len(seen) == 2:
            raise KeyboardInterrupt

    old = numba.get_num_threads()
    try:
        numba.set_num_threads(2)
        st = _loaded_block()
        assert st.n_elements < discrete_solver.SERIAL_BELOW_ELEMENTS
        with pytest.raises(KeyboardInterrupt):
            run(st, max_steps=400, mass_damping=2.0, contact=False, check_every=50,
                on_check=watch)
        assert seen == [1, 1] and numba.get_num_threads() == 2
    finally:
        numba.set_num_threads(old)


def test_critical_time_step_edge_cases():
    """Far from the origin (coordinates of 1e7 m) the same bound as at it; a massless node
    tied to one with mass shares the group's mass (the bound stays below the tied pair's true
    limit); held components are left out; bad geometry is refused with the element named."""
    mat = Material(name="m", E=1e4, nu=0.3, density=2.0)
    here = rectangle(1.0, 1.0, 1, 1, material=mat)
    far = rectangle(1.0, 1.0, 1, 1, material=mat, origin=(1e7, 1e7))
    assert integrate.critical_time_step(far, contact=False) == pytest.approx(
        integrate.critical_time_step(here, contact=False), rel=1e-6)
    # two Q4 side by side, tied; the left element's nodes massless (its mass on the right's)
    pair = rectangle(2.0, 1.0, 2, 1, material=mat)
    left = np.unique(pair.element_nodes[0])
    pair.mass[np.unique(pair.element_nodes[1])] += pair.mass[left].sum() / 4.0
    pair.mass[left] = 0.0
    shared = [n for n in left if (pair.node_group == pair.node_group[n]).sum() > 1]
    assert len(shared) == 2  # the left element's right edge is tied to the right element
    pair.fix(np.isclose(pair.x_ref[:, 0], 0.0))  # its massless left edge held
    bound = integrate.critical_time_step(pair, contact=False)
    assert math.isfinite(bound) and _free_run(pair, 0.98 * bound, steps=2000) < 1e-5
    # a held element does not move: no bound from it; a half-held one still has one
    held = rectangle(1.0, 1.0, 1, 1, material=mat)
    held.fix(np.ones(held.x.shape[0], dtype=bool))
    assert integrate.critical_time_step(held, contact=False) == math.inf
    half = rectangle(1.0, 1.0, 1, 1, material=mat)
    half.fix(np.isclose(half.x_ref[:, 1], 0.0))
    assert integrate.critical_time_step(here, contact=False) <= integrate.critical_time_step(
        half, contact=False) < math.inf
    bad = rectangle(1.0, 1.0, 1, 1, material=mat)
    bad.x[0] = np.nan
    with pytest.raises(ValueError, match="element 0 has non-finite coordinates"):
        integrate.critical_time_step(bad, contact=False)
    flipped = rectangle(1.0, 1.0, 1, 1, material=mat)
    flipped.x[:, 0] *= -1.0  # mirrored: clockwise, negative area
    with pytest.raises(ValueError, match="element 0 is inverted or degenerate"):
        integrate.critical_time_step(flipped, contact=False)
