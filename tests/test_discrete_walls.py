"""Smooth rigid walls (``hybrid.discrete.contact.walls``): the planes of the roller supports.

A free block thrown at a wall must bounce off it, not pass through: without contact damping
with its energy kept (the wall force is elastic), with contact damping losing what it loses at
the face of a held block of the same material. An element already beyond the plane, or
beside the wall's span, is left alone. The handover makes the wall of a straight roller
boundary, with the body on its inner side; a checkpoint keeps it; the wall goes when its
support's nodes are released.
"""

import numpy as np
import pytest
from test_handover_snapshot import _snapshot

from hybrid.discrete.builders import blocks
from hybrid.discrete.contact.walls import make_wall, wall_energy
from hybrid.discrete.ledger import EnergyLedger
from hybrid.discrete.solver import ExplicitSolver, RunOptions
from hybrid.discrete.state import DiscreteState
from hybrid.handover import Region, start_from
from hybrid.materials import Contact, Material


def _thrown_block(zeta: float, held_block: bool = False) -> tuple[DiscreteState, np.ndarray]:
    """A free 1 m block of 2 x 2 Q4 (no gravity) at x in [0.5, 1.5] moving at 2 m/s toward
    x = 0: a wall there (body side x > 0, spanning y in [-3, 2], held by a block at
    y in [-3, -2] with its side on the plane) or, with ``held_block``, a held 1 x 3 m block
    of the same material behind it. Returns the state and the free nodes."""
    mat = Material(name="block", E=1.0e5, nu=0.3, density=2.0,
                   contact=Contact(damping=zeta, phi=30.0))
    parts = [(1.0, 1.0, 2, 2, (0.5, 0.0), 0)]
    if held_block:
        parts.append((1.0, 3.0, 2, 6, (-1.0, -1.0), 0))
    else:  # the support the wall belongs to: a held block with its side on the plane
        parts.append((1.0, 1.0, 1, 1, (0.0, -3.0), 0))
    st = blocks(parts, [mat], gravity=(0.0, 0.0))
    free = np.unique(st.element_nodes[:4])
    st.fix(np.unique(st.element_nodes[4:]))
    if not held_block:
        st.walls = np.array([[1.0, 0.0, 0.0, -3.0, 2.0]])
        on_plane = np.flatnonzero(st.fixed[:, 0] & np.isclose(st.x[:, 0], 0.0))
        st.wall_nodes = np.column_stack([np.zeros_like(on_plane), on_plane])
    st.v[free, 0] = -2.0
    return st, free


def _bounce(st: DiscreteState, free: np.ndarray) -> tuple[float, float, float, EnergyLedger]:
    """Run 0.6 s (0.25 s to the wall, then back out). Returns the least x of the free nodes
    met on the way, the block's mean velocity in x at the end, its energy E_kin + E_strain +
    E_contact averaged over the last 0.2 s (the leapfrog's staggered E_kin swings from step
    to step while the block vibrates) and the final ledger."""
    x_min = np.inf
    energy = []
    with ExplicitSolver(st, RunOptions(contact=True)) as solver:
        while st.time < 0.6:
            solver.step()
            x_min = min(x_min, float(st.x[free, 0].min()))
            if st.time > 0.4:
                led = EnergyLedger.measure(st)
                energy.append(led.kinetic + led.strain + led.contact_elastic)
    m = st.mass[free]
    return x_min, float(np.dot(m, st.v[free, 0]) / m.sum()), float(np.mean(energy)), led


def test_a_block_bounces_off_a_smooth_wall_with_its_energy_kept():
    st, free = _thrown_block(zeta=0.0)
    e0 = EnergyLedger.measure(st).kinetic
    x_min, vx, energy, led = _bounce(st, free)
    assert x_min > -0.05  # the overlap stays a small fraction of the block
    assert st.x[free, 0].min() > 0.0 and vx > 0.0  # back out, moving away
    # elastic wall: the energy after the bounce (translation and vibration) is that before
    assert energy == pytest.approx(e0, rel=0.02)
    assert led.contact_damping == 0.0 and abs(led.friction) < 1e-12


def test_a_smooth_wall_acts_as_a_held_block_of_the_same_material():
    """With contact damping the block loses energy at the wall as at a held block's face."""
    st, free = _thrown_block(zeta=0.2)
    e0 = EnergyLedger.measure(st).kinetic
    _, vx, energy, led = _bounce(st, free)
    _, vx_held, energy_held, _ = _bounce(*_thrown_block(zeta=0.2, held_block=True))
    assert 0.0 < vx < 2.0 and energy < 0.9 * e0 and led.contact_damping > 0.0
    assert vx == pytest.approx(vx_held, rel=0.05)
    assert energy == pytest.approx(energy_held, rel=0.03)
    assert abs(led.friction) < 1e-12  # frictionless


def test_an_element_beyond_the_wall_is_left_alone():
    """An element whose centroid is already beyond the plane, or beside the wall's span, is
    not pushed (it would be shot back through the plane)."""
    st, free = _thrown_block(zeta=0.0)
    st.x[free, 0] -= 1.2  # centroids at x = -0.45 and +0.05 (columns of the 2 x 2)
    args = (st.x, st.element_nodes, st.element_material, st.contact_table, st.fixed)
    beyond = st.x[st.element_nodes[:4]].mean(axis=1)[:, 0] < 0.0
    beyond = np.concatenate([beyond, [False]])  # the held block: inside, held, no force
    assert beyond.any() and not beyond[:4].all()
    e_all = wall_energy(*args, st.walls)
    moved = st.element_nodes[~beyond].ravel()
    st.x[moved, 0] += 10.0  # the others taken away
    assert wall_energy(*args, st.walls) == 0.0 < e_all
    st.x[moved, 0] -= 10.0
    st.walls[0, 3:] = [5.0, 6.0]  # span elsewhere
    assert wall_energy(*args, st.walls) == 0.0


def test_a_released_roller_takes_its_wall_with_it():
    """Freeing the support's nodes along the normal (a gate opened) removes the wall when
    the solver starts: the block then passes the plane."""
    st, free = _thrown_block(zeta=0.0)
    support = st.wall_nodes[:, 1]
    st.fixed[support, 0] = False
    x_min, _, _, _ = _bounce(st, free)
    assert st.walls.shape == (0, 5) and st.wall_nodes.shape == (0, 2)
    assert x_min < -0.5
    st, free = _thrown_block(zeta=0.0)
    st.fixed[support, 1] = False  # held along the normal still: the wall stands
    with ExplicitSolver(st, RunOptions(contact=True)):
        assert st.walls.shape == (1, 5)
    st, free = _thrown_block(zeta=0.0)
    st.wall_nodes = st.wall_nodes[:0]  # a wall of no support stands for good
    st.fixed[support, 0] = False
    with ExplicitSolver(st, RunOptions(contact=True)):
        assert st.walls.shape == (1, 5)


def test_make_wall_places_the_plane_on_the_boundary_with_the_body_inside():
    pts = np.array([[0.0, 0.0], [1e-12, 1.0], [0.0, 3.0]])
    w = make_wall(pts, inside=np.array([2.0, 1.0]), axis=0)
    assert w.tolist() == [1.0, 0.0, 0.0, 0.0, 3.0]
    w = make_wall(pts + [4.0, 0.0], inside=np.array([2.0, 1.0]), axis=0)
    assert w[:2].tolist() == [-1.0, 0.0] and w[2] == pytest.approx(-(4.0 + 1e-12))
    assert make_wall(np.array([[0.0, 0.0], [0.5, 1.0]]), np.array([2.0, 1.0]), 0) is None


def test_the_handover_makes_walls_of_straight_roller_boundaries(tmp_path):
    left = np.array([[3, 0, 0]])  # the left edge x = 0 of cell 0
    snap = _snapshot(boundary_edges={**_snapshot().boundary_edges, "left": left},
                     supports=(("base", True, True), ("left", True, False)),
                     smooth=("left",))
    hand = start_from(snap, region=Region(everywhere=True))
    disc = hand.discrete
    assert disc.walls.tolist() == [[1.0, 0.0, 0.0, 0.0, 1.0]]
    assert disc.wall_nodes[:, 0].tolist() == [0, 0]
    assert np.array_equal(disc.wall_nodes[:, 1], hand.boundary_nodes["left"])
    assert start_from(_snapshot(), region=Region(everywhere=True)).discrete.walls.shape == (0, 5)
    back = DiscreteState.load(disc.save(tmp_path / "state.npz"))
    assert np.array_equal(back.walls, disc.walls)
    assert np.array_equal(back.wall_nodes, disc.wall_nodes)


def test_wall_bounce_identical_with_one_and_two_threads():
    """Bit for bit the same state and ledger with 1 and 2 numba threads."""
    import numba

    if numba.config.NUMBA_NUM_THREADS < 2:
        pytest.skip("numba has fewer than 2 threads here")
    out = {}
    old = numba.get_num_threads()
    try:
        for n in (1, 2):
            numba.set_num_threads(n)
            st, free = _thrown_block(zeta=0.2)
            _bounce(st, free)
            out[n] = st
    finally:
        numba.set_num_threads(old)
    for name in ("x", "v", "stress", "ledger", "group_energy"):
        assert np.array_equal(getattr(out[1], name), getattr(out[2], name)), name


@pytest.mark.parametrize("walls, wall_nodes, message", [
    ([[0.6, 0.0, 0.0, -3.0, 2.0]], None, "wall 0: its normal .* is not a unit vector"),
    ([[1.0, 0.0, np.nan, -3.0, 2.0]], None, "wall 0 holds non-finite values"),
    ([[1.0, 0.0, 0.0, 2.0, -3.0]], None, r"wall 0: s_min = 2.0 > s_max = -3.0"),
    ([[1.0, 0.0, 0.0, -3.0, 2.0]], [[1, 0]], "wall_nodes names a wall outside 0..0"),
    ([[1.0, 0.0, 0.0, -3.0]], None, r"walls has shape \(1, 4\)"),
])
def test_a_malformed_wall_is_refused_before_the_run(walls, wall_nodes, message):
    """The kernel takes a wall's row as given (a unit normal, an ordered span): a run with a
    wall that is not so is refused with what is wrong, before any step."""
    st, _ = _thrown_block(0.0)
    st.walls = np.array(walls, dtype=float)
    if wall_nodes is not None:
        st.wall_nodes = np.array(wall_nodes, dtype=np.int64)
    with pytest.raises(ValueError, match=f"discrete run refused: {message}"):
        with ExplicitSolver(st, RunOptions(contact=True)) as solver:
            solver.run(until_time=0.01)
    assert st.step == 0


def test_only_the_elements_near_a_wall_are_looked_at_with_the_same_result():
    """The walls' forces computed for the elements near a wall (``near_walls``, chosen with
    the contact search's margin at its refreshes) give the state and ledger of the search
    over every element bit for bit, while the block flies to the wall, bounces and leaves;
    the free block is left out while it is far from the wall."""
    out = {}
    for restricted in (True, False):
        st, free = _thrown_block(zeta=0.2)
        sizes = []
        with ExplicitSolver(st, RunOptions(contact=True)) as solver:
            if not restricted:  # every element, every refresh
                solver._near_walls = lambda x, en, walls, margin: np.arange(en.shape[0])
            while st.time < 0.6:
                solver.step()
                sizes.append(solver._wbuf.elements.size)
        out[restricted] = st, sizes
    (a, near), (b, every) = out[True], out[False]
    for name in ("x", "v", "stress", "ledger", "group_energy"):
        assert np.array_equal(getattr(a, name), getattr(b, name)), name
    # the held block's element only while the block is far, then with the block's two
    # elements on the wall's side (its other two never come within the margin)
    assert min(every) == 5 and min(near) == 1 and max(near) == 3
