"""Splitting (thesis section 4.5): failure criteria, tie-group re-splitting, a bar pulled
apart at its tensile strength, a no-tension beam splitting where sigma_N > 0."""

import math

import numpy as np
import pytest

from hybrid.discrete import integrate, rectangle, ties
from hybrid.discrete.solver import run
from hybrid.materials import Bond, Material


def _mat(name: str = "block", **bond):
    """An elastic material whose bonds have the given strengths (the others unbreakable)."""
    return Material(name=name, E=1.0e4, nu=0.0, density=2.0, bond=Bond(**bond))


@pytest.mark.parametrize("element", ["Q4", "T3"])
def test_failure_criteria_thresholds(element):
    """Uniform prescribed stress: tension and Mohr-Coulomb shear thresholds to 1 %."""
    c, phi, ft = 10.0, 30.0, 5.0
    st = rectangle(3.0, 3.0, 3, 3, element, material=_mat(
        cohesion=c, phi=phi, tensile_strength=ft))
    ifn = st.interface_nodes
    d = st.x[ifn[:, 1]] - st.x[ifn[:, 0]]
    horizontal = np.abs(d[:, 1]) < 1e-12  # normal (0, +-1): sigma_N = sigma_yy
    vertical = np.abs(d[:, 0]) < 1e-12  # normal (+-1, 0): sigma_N = sigma_xx
    # tension: sigma_yy just above / below ft fails / holds the horizontal interfaces only
    for factor, expect in ((1.01, ties.FAIL_TENSION), (0.99, 0)):
        st.stress[:] = [0.0, factor * ft, 0.0, 0.0]
        modes = ties.check_interfaces(st)
        assert np.all(modes[horizontal] == expect)
        assert np.all(modes[vertical] == 0)
    # shear under compression p: fails iff tau > c + p tan(phi)
    p = 40.0
    tau_f = c + p * math.tan(math.radians(phi))
    for factor, expect in ((1.01, ties.FAIL_SHEAR), (0.99, 0)):
        st.stress[:] = [-p, -p, -p, factor * tau_f]
        modes = ties.check_interfaces(st)
        assert np.all(modes[horizontal | vertical] == expect)
    # interfaces marked not splittable are never checked
    st.interface_splittable[:] = False
    assert not ties.check_interfaces(st).any()


def test_weaker_material_governs():
    """An interface between two materials uses the smaller strength of the two."""
    strong = _mat(tensile_strength=100.0)
    weak = _mat(tensile_strength=10.0)
    from hybrid.discrete.builders import rectangle_mesh
    from hybrid.discrete.state import from_mesh

    pts, cells = rectangle_mesh(2.0, 1.0, 2, 1)
    st = from_mesh(pts, cells, [0, 1], [strong, weak])
    st.stress[:] = [20.0, 0.0, 0.0, 0.0]  # sigma_N = 20 kPa on the vertical interface
    assert ties.check_interfaces(st).tolist() == [ties.FAIL_TENSION]


@pytest.mark.parametrize("p, weaker", [(10.0, "sand"), (100.0, "clay")])
def test_weaker_shear_envelope_governs(p, weaker):
    """A clay bond (c 30 kPa, phi 0) beside a sand bond (c 0, phi 30 deg): the interface
    holds up to min(30, p tan 30) at compression p, the weaker of the two materials' strengths
    there (sand at 10 kPa: 5.77 kPa; clay at 100 kPa: 30 kPa), and fails 1 % above it. The
    smaller of c and of tan(phi) taken apart (0 and 0) would fail it under any shear; a bond
    to an elastic side (unbreakable) has the plastic side's strength."""
    from hybrid.discrete.builders import rectangle_mesh
    from hybrid.discrete.state import from_mesh

    clay = _mat("clay", cohesion=30.0, phi=0.0, tensile_strength=100.0)
    sand = _mat("sand", cohesion=0.0, phi=30.0, tensile_strength=100.0)
    tau_f = {"clay": 30.0, "sand": p * math.tan(math.radians(30.0))}[weaker]
    assert tau_f == min(30.0, p * math.tan(math.radians(30.0)))
    pts, cells = rectangle_mesh(2.0, 1.0, 2, 1)
    for pair in ([clay, sand], [sand, clay]):
        st = from_mesh(pts, cells, [0, 1], pair)
        for factor, expect in ((1.01, ties.FAIL_SHEAR), (0.99, 0)):
            st.stress[:] = [-p, -p, -p, factor * tau_f]  # on the vertical interface
            assert ties.check_interfaces(st).tolist() == [expect], (factor, pair[0].name)
    elastic = Material(name="rock", E=1.0e4, nu=0.0, density=2.0)
    st = from_mesh(pts, cells, [0, 1], [elastic, sand])
    tau_sand = p * math.tan(math.radians(30.0))
    for factor, expect in ((1.01, ties.FAIL_SHEAR), (0.99, 0)):
        st.stress[:] = [-p, -p, -p, factor * tau_sand]
        assert ties.check_interfaces(st).tolist() == [expect], factor


def test_tie_groups_resplit_into_connected_components():
    """2x2 mesh: one crack to the centre keeps the centre tied (still connected around it);
    a second crack through the centre splits it into two groups."""
    st = rectangle(2.0, 2.0, 2, 2, material=_mat())
    assert st.n_groups == 9
    ie = st.interface_elements.tolist()
    i01 = ie.index([0, 1])  # vertical interface, lower half
    ties.split_interfaces(st, [i01])
    # only the bottom-middle vertex (2 nodes) splits; the centre stays one group of 4
    assert st.n_groups == 10
    centre = np.flatnonzero(np.all(np.isclose(st.x_ref, [1.0, 1.0]), axis=1))
    assert len(set(st.node_group[centre])) == 1
    i23 = ie.index([2, 3])  # vertical interface, upper half: the crack goes through
    ties.split_interfaces(st, [i23])
    assert st.n_groups == 12
    groups = {}
    for n in centre:
        groups.setdefault(st.node_group[n], []).append(n // 4)  # owning element
    assert sorted(sorted(v) for v in groups.values()) == [[0, 2], [1, 3]]
    # CSR consistent with node_group
    for g in range(st.n_groups):
        members = st.group_nodes[st.group_ptr[g]:st.group_ptr[g + 1]]
        assert np.all(st.node_group[members] == g)


def test_bar_pulled_apart_splits_at_tensile_strength():
    """A bar pulled slowly at one end splits when the axial stress reaches the interface
    tensile strength: the support reaction at the split equals ft * h to 2 %."""
    ft, h, L = 20.0, 1.0, 10.0
    st = rectangle(L, h, 10, 1, material=_mat(tensile_strength=ft),
                   gravity=(0.0, 0.0))
    left = np.isclose(st.x_ref[:, 0], 0.0)
    right = np.isclose(st.x_ref[:, 0], L)
    st.fix(left, x=True, y=False)
    st.fix(left & np.isclose(st.x_ref[:, 1], 0.0), x=False, y=True)
    vel = 2.0e-3  # m/s: dynamic stress rho c V = 0.28 kPa, 1.4 % of ft
    st.fix(right, x=True, y=False, velocity=(vel, 0.0))
    dt = 0.5 * integrate.stable_time_step(st)
    alpha = 5.0
    reaction = None
    n_groups0 = st.n_groups
    for _ in range(20000):
        integrate.step(st, dt, mass_damping=alpha)
        modes = ties.check_interfaces(st)
        if modes.any():
            reaction = -np.sum(st.internal_force[left, 0])
            failed = np.flatnonzero(modes)
            assert np.all(modes[failed] == ties.FAIL_TENSION)
            ties.split_interfaces(st, failed)
            break
    assert reaction is not None
    # bar 2 %: the quasi-static reaction at the split is the tensile strength times h
    assert abs(reaction / (ft * h) - 1.0) < 0.02
    # every broken vertical interface splits its two vertices into two groups each
    assert st.n_groups == n_groups0 + 2 * failed.size
    # the pieces separate: the crack opens as the right end keeps moving
    for _ in range(2000):
        integrate.step(st, dt, mass_damping=alpha)
    ifn = st.interface_nodes[failed[0]]
    assert st.x[ifn[2], 0] - st.x[ifn[0], 0] > 0.5 * vel * 2000 * dt
    # and the released bar unloads (stress below 5 % of ft after the damped transient)
    assert np.max(np.abs(st.stress[..., 0])) < 0.05 * ft


def test_no_tension_beam_splits_where_normal_stress_is_tensile():
    """A simply supported elastic beam under gravity, no-tension interfaces: vertical
    interfaces in the middle half of the span split below the neutral axis (sigma_N =
    sigma_xx > 0, beam theory) and hold above it."""
    L, h = 10.0, 1.0
    mat = Material(name="block", E=1.0e5, nu=0.2, density=2.0,
                   bond=Bond(tensile_strength=0.0, cohesion=1e9))
    st = rectangle(L, h, 20, 4, material=mat)
    bottom = np.isclose(st.x_ref[:, 1], 0.0)
    st.fix(bottom & np.isclose(st.x_ref[:, 0], 0.0))
    st.fix(bottom & np.isclose(st.x_ref[:, 0], L), x=False, y=True)
    res = run(st, until_rest=1e-8, max_steps=40000, mass_damping=12.0)
    assert res.stop_reason == "rest"
    # sanity of the static state: the bottom layer's mean sigma_xx next to mid-span agrees
    # with beam theory M y / I at its mean distance 3h/8 from the neutral axis (10 %: a
    # 4-element-deep Q4 mesh represents the linear bending stress only per element)
    q = 2.0 * 9.81 * h
    cref = st.x_ref[st.element_nodes].mean(axis=1)
    mid = np.flatnonzero(np.isclose(cref[:, 0], L / 2 - 0.25) & np.isclose(cref[:, 1], h / 8))
    xm = L / 2 - 0.25
    M = q * xm * (L - xm) / 2.0
    assert abs(st.stress[mid, :, 0].mean() / (M * (3 * h / 8) / (h**3 / 12)) - 1.0) < 0.1
    modes = ties.check_interfaces(st)
    ifn = st.interface_nodes
    mid_pts = 0.5 * (st.x_ref[ifn[:, 0]] + st.x_ref[ifn[:, 1]])
    d = st.x_ref[ifn[:, 1]] - st.x_ref[ifn[:, 0]]
    vertical = np.abs(d[:, 0]) < 1e-9
    central = np.abs(mid_pts[:, 0] - L / 2) < L / 4
    below = mid_pts[:, 1] < h / 2
    assert np.all(modes[vertical & central & below] == ties.FAIL_TENSION)
    assert np.all(modes[vertical & central & ~below] == 0)


def test_splitting_limited_to_a_region():
    """Only interfaces touching the chosen elements are checked (the handover's region)."""
    st = rectangle(3.0, 1.0, 3, 1, material=_mat(tensile_strength=1.0))
    st.stress[:] = [10.0, 0.0, 0.0, 0.0]  # both vertical interfaces over-stressed in tension
    assert ties.limit_splitting(st, [0]) == 1  # only the interface between elements 0 and 1
    modes = ties.check_interfaces(st)
    ie = st.interface_elements.tolist()
    assert modes[ie.index([0, 1])] == ties.FAIL_TENSION
    assert modes[ie.index([1, 2])] == 0


def _no_tension(tensile_strength: float | None = 0.0, cohesion: float = 20.0) -> Material:
    """A plastic material with a tension cut-off (the no-tension fill of a dam when 0) whose
    bonds are given a far larger tensile strength, so that only the material's cut-off can
    fail them in tension."""
    return Material(name="fill", E=1.0e4, nu=0.0, density=2.0, cohesion=cohesion, phi=30.0,
                    tensile_strength=tensile_strength, bond=Bond(tensile_strength=1.0e3))


@pytest.mark.parametrize("element", ["Q4", "T3"])
def test_interface_fails_where_the_material_has_cracked_in_tension(element):
    """Points yielded on their tension cut-off: the crack is a discontinuity along the edges
    nearer its plane than its normal (the edge's normal stress above the in-plane mean),
    whatever the bond's tensile strength; not where the points are elastic at the same
    stress, nor at the Mohr-Coulomb apex (no cut-off given: every direction alike)."""
    st = rectangle(3.0, 3.0, 3, 3, element, material=_no_tension())
    ifn = st.interface_nodes
    d = st.x[ifn[:, 1]] - st.x[ifn[:, 0]]
    horizontal = np.abs(d[:, 1]) < 1e-12  # normal (0, +-1)
    vertical = np.abs(d[:, 0]) < 1e-12  # normal (+-1, 0)
    diagonal = ~(horizontal | vertical)  # T3: normal (1, -1) / sqrt(2), at 45 deg

    def modes(angle: float, yielded: int = 1) -> np.ndarray:
        """sigma_1 = 0 (the cut-off) at ``angle`` [deg] from x, sigma_3 = -40 kPa."""
        a = math.radians(angle)
        c, s = math.cos(a), math.sin(a)
        s1, s3 = 0.0, -40.0
        st.stress[:] = [s1 * c * c + s3 * s * s, s1 * s * s + s3 * c * c, s3,
                        (s1 - s3) * s * c]
        st.yielded[:] = yielded
        return ties.check_interfaces(st)

    for angle in (0.0, 30.0):  # the vertical edges' normal within 45 deg of sigma_1
        m = modes(angle)
        assert np.all(m[vertical] == ties.FAIL_TENSION)
        assert np.all(m[horizontal] == 0)
    m = modes(90.0)
    assert np.all(m[horizontal] == ties.FAIL_TENSION)
    assert np.all(m[vertical] == 0)
    # T3 diagonals (normal at -45 deg): nearer the crack's plane at -30, not at +30 deg
    assert np.all(modes(-30.0)[diagonal] == ties.FAIL_TENSION)
    assert np.all(modes(30.0)[diagonal] == 0)
    # both in-plane principal stresses on the cut-off (a biaxial crack): every edge fails
    st.stress[:] = [0.0, 0.0, -40.0, 0.0]
    assert np.all(ties.check_interfaces(st) == ties.FAIL_TENSION)
    # a point at the same stress whose last update was elastic has not cracked
    assert not modes(0.0, yielded=0).any()
    # yielded, but the stress 1 kPa below the cut-off (the out-of-plane stress at it): not
    # cracked
    st.stress[:] = [-1.0, -40.0, 0.0, 0.0]
    st.yielded[:] = 1
    assert not ties.check_interfaces(st).any()
    # no cut-off below the apex (here c = 0: the apex at 0, the same stress): the rule is off
    st_apex = rectangle(3.0, 3.0, 3, 3, element, material=_no_tension(None, cohesion=0.0))
    st_apex.stress[:] = [0.0, -40.0, -40.0, 0.0]
    st_apex.yielded[:] = 1
    assert not (ties.check_interfaces(st_apex) == ties.FAIL_TENSION).any()


def test_bar_of_a_tension_cut_off_material_cracks_at_its_tensile_strength():
    """A bar pulled slowly at one end, its material's tension cut-off ft below its bonds'
    tensile strength: inside the elements the stress is capped at ft, so the bonds' test
    alone would never fail; the bar cracks as its points yield on the cut-off, the support
    reaction then ft * h to 2 % (as a bar whose bonds have strength ft)."""
    ft, h, L = 5.0, 1.0, 10.0
    st = rectangle(L, h, 10, 1, material=_no_tension(ft), gravity=(0.0, 0.0))
    left = np.isclose(st.x_ref[:, 0], 0.0)
    right = np.isclose(st.x_ref[:, 0], L)
    st.fix(left, x=True, y=False)
    st.fix(left & np.isclose(st.x_ref[:, 1], 0.0), x=False, y=True)
    vel = 2.0e-3  # m/s: dynamic stress rho c V = 0.28 kPa, 5.7 % of ft, damped out
    st.fix(right, x=True, y=False, velocity=(vel, 0.0))
    dt = 0.5 * integrate.stable_time_step(st)
    reaction = None
    for _ in range(20000):
        integrate.step(st, dt, mass_damping=5.0)
        modes = ties.check_interfaces(st)
        if modes.any():
            reaction = -np.sum(st.internal_force[left, 0])
            assert np.all(modes[np.flatnonzero(modes)] == ties.FAIL_TENSION)
            break
    assert reaction is not None
    # the cut-off caps the reaction at ft h: 2 % below it at most says the crack waited for it
    assert abs(reaction / (ft * h) - 1.0) < 0.02


def test_a_crack_on_one_side_fails_the_edge():
    """As for softening, the points on one side of the edge having cracked suffice (a band of
    cracked elements one element wide parts from its neighbours); an undrained clay (phi = 0)
    with a given cut-off cracks alike; an elastic neighbour never cracks."""
    from hybrid.discrete.builders import rectangle_mesh
    from hybrid.discrete.state import from_mesh

    clay = Material(name="core", E=2.5e3, nu=0.43, density=1.9, cohesion=52.0,
                    tensile_strength=0.0, bond=Bond(tensile_strength=52.0))
    rock = Material(name="rock", E=1.0e5, nu=0.3, density=2.0, bond=Bond(tensile_strength=1e3))
    pts, cells = rectangle_mesh(2.0, 1.0, 2, 1)
    st = from_mesh(pts, cells, [0, 1], [clay, rock])
    st.stress[0] = [0.0, -40.0, -20.0, 0.0]  # the clay on its cut-off across the edge
    st.stress[1] = [-10.0, -40.0, -20.0, 0.0]  # the rock in compression
    st.yielded[0] = 1
    assert ties.check_interfaces(st).tolist() == [ties.FAIL_TENSION]
    st.yielded[0] = 0  # the clay's last update elastic: nothing has cracked
    assert ties.check_interfaces(st).tolist() == [0]
    st.yielded[:] = 1  # the rock flagged too: an elastic material never cracks
    st.stress[0] = [-5.0, -40.0, -20.0, 0.0]
    assert ties.check_interfaces(st).tolist() == [0]


def test_a_run_records_how_each_interface_failed(tmp_path):
    """The tension-cracked bar run by the solver: its failed interfaces are recorded as
    failed in tension (``interface_mode``, counted by ``failure_modes``) at the time of the
    splitting check that failed them (``interface_failure_time``), the record survives a
    checkpoint, and a checkpoint written without it loads with nothing recorded."""
    from hybrid.discrete.solver import ExplicitSolver, Observer, RunOptions
    from hybrid.discrete.state import DiscreteState

    st = rectangle(10.0, 1.0, 10, 1, material=_no_tension(5.0), gravity=(0.0, 0.0))
    left = np.isclose(st.x_ref[:, 0], 0.0)
    st.fix(left, x=True, y=False)
    st.fix(left & np.isclose(st.x_ref[:, 1], 0.0), x=False, y=True)
    st.fix(np.isclose(st.x_ref[:, 0], 10.0), x=True, y=False, velocity=(0.05, 0.0))
    assert not st.interface_mode.any() and np.isnan(st.interface_failure_time).all()
    seen: dict[int, tuple[float, int]] = {}  # interface -> (time, step) it was seen failed

    class Note(Observer):
        def stepped(self, solver: ExplicitSolver) -> None:
            for i in np.flatnonzero(~solver.state.interface_intact):
                seen.setdefault(int(i), (solver.state.time, solver.state.step))

    with ExplicitSolver(st, RunOptions(split_every=3, contact=False),
                        observers=[Note()]) as sol:
        sol.run(until_time=0.2)
    failed = ~st.interface_intact
    assert failed.any()
    assert np.all(st.interface_mode[failed] == ties.FAIL_TENSION)
    assert np.all(st.interface_mode[~failed] == 0)
    # the time of the step whose splitting check failed it; none for the intact ones
    assert np.isnan(st.interface_failure_time[~failed]).all()
    assert seen.keys() == set(np.flatnonzero(failed))
    assert {i: st.interface_failure_time[i] for i in seen} == {i: t for i, (t, _) in seen.items()}
    assert {k % 3 for _, k in seen.values()} == {0}  # at splitting checks only
    counts = ties.failure_modes(st)
    assert counts["tension"] == int(failed.sum())
    assert sum(counts.values()) == int(failed.sum())
    again = DiscreteState.load(st.save(tmp_path / "state.npz"))
    np.testing.assert_array_equal(again.interface_mode, st.interface_mode)
    np.testing.assert_array_equal(again.interface_failure_time, st.interface_failure_time)
    older = {k: v for k, v in st.arrays().items()
             if k not in ("interface_mode", "interface_failure_time")}
    np.savez(tmp_path / "older.npz", **older)
    loaded = DiscreteState.load(tmp_path / "older.npz")
    assert ties.failure_modes(loaded)["not_recorded"] == int(failed.sum())
    assert np.isnan(loaded.interface_failure_time).all()
