"""DiscreteState construction (builders, from_mesh), layout invariants and bad input."""

import math

import numpy as np
import pytest

from hybrid.constitutive.table import kernel_row
from hybrid.discrete import DiscreteState, from_mesh, rectangle
from hybrid.discrete.builders import rectangle_mesh
from hybrid.materials import Material, MaterialError

MAT = Material(name="block", E=1.0e5, nu=0.3, density=2.0)


@pytest.mark.parametrize("element,nen,ngp", [("Q4", 4, 4), ("T3", 3, 1)])
def test_rectangle_layout(element, nen, ngp):
    nx, ny = 3, 2
    st = rectangle(3.0, 2.0, nx, ny, element, material=MAT)
    ne = nx * ny * (1 if element == "Q4" else 2)
    assert st.element_nodes.shape == (ne, nen)
    assert st.n_nodes == ne * nen  # element-owned nodes
    assert st.stress.shape == (ne, ngp, 4)
    # one tie group per mesh vertex, all coincident nodes in it
    assert st.n_groups == (nx + 1) * (ny + 1)
    for g in range(st.n_groups):
        members = st.group_nodes[st.group_ptr[g]:st.group_ptr[g + 1]]
        assert np.all(st.node_group[members] == g)
        assert np.ptp(st.x[members], axis=0).max() == 0.0
    # interfaces: every inner edge once; Q4 (nx-1) ny + nx (ny-1), T3 adds the diagonals
    n_if = (nx - 1) * ny + nx * (ny - 1) + (0 if element == "Q4" else nx * ny)
    assert st.interface_nodes.shape == (n_if, 4)
    a0, a1, b0, b1 = st.interface_nodes.T
    assert np.array_equal(st.x[a0], st.x[b0]) and np.array_equal(st.x[a1], st.x[b1])
    # nodes a0-a1 belong to element A, b0-b1 to B
    ea, eb = st.interface_elements.T
    assert all(a in st.element_nodes[e] for a, e in zip(a0, ea))
    assert all(b in st.element_nodes[e] for b, e in zip(b1, eb))
    # lumped mass: total = rho x area (exact, 1e-12)
    assert math.isclose(st.mass.sum(), 2.0 * 3.0 * 2.0, rel_tol=1e-12)


def test_lumped_mass_of_distorted_quad():
    """Row-sum mass of a trapezoid: rho * integral of N_a (exact with 2x2 Gauss)."""
    pts = np.array([[0.0, 0.0], [2.0, 0.0], [1.5, 1.0], [0.5, 1.0]])
    st = from_mesh(pts, [[0, 1, 2, 3]], [0], [MAT])
    # integral of N_a over the trapezoid: (2 w_bottom + w_top)/6 * h / 2 per bottom node etc.
    bottom = (2 * 2.0 + 1.0) / 12.0
    top = (2 * 1.0 + 2.0) / 12.0
    np.testing.assert_allclose(st.mass, 2.0 * np.array([bottom, bottom, top, top]),
                               rtol=1e-12)


def test_material_table_is_the_shared_kernel_row():
    """The discrete table holds the same kernel row as the continuum (``kernel_row``) and the
    bond defaults to the material's own strength."""
    m = Material(name="clay", E=1.0e4, nu=0.3, unit_weight=19.62, cohesion=10.0, phi=30.0)
    st = rectangle(2.0, 2.0, 2, 2, material=m)
    assert math.isclose(st.density[0], 2.0, rel_tol=1e-12)
    assert not st.elastic_only[0]
    np.testing.assert_allclose(st.material_table[0], kernel_row(m), rtol=1e-12)
    np.testing.assert_allclose(st.interface_table[0, :2], [10.0, math.tan(math.pi / 6)],
                               rtol=1e-12)


def test_save_load_roundtrip(tmp_path):
    st = rectangle(2.0, 1.0, 2, 1, material=MAT)
    st.stress[:] = 3.0
    st.time = 1.25
    st.step = 7
    path = st.save(tmp_path / "ck.npz")
    back = DiscreteState.load(path)
    assert back.time == 1.25 and back.step == 7
    for name in ("x", "stress", "group_ptr", "interface_nodes", "material_table"):
        assert np.array_equal(getattr(back, name), getattr(st, name))
    with np.load(path, allow_pickle=False) as data:  # plain arrays, no pickle
        assert "x" in data.files


def test_a_checkpoint_of_the_older_contact_law_is_refused(tmp_path):
    """A checkpoint whose contact table has the four columns [k_n, k_t, mu, zeta] was written
    by the version without contact cohesion (and with elements beside failed bonds held at
    residual): continuing it with this law would be neither run, so it is refused by name."""
    st = rectangle(2.0, 1.0, 2, 1, material=MAT)
    arrays = st.arrays()
    arrays["contact_table"] = arrays["contact_table"][:, :4]
    np.savez(tmp_path / "old.npz", **arrays)
    with pytest.raises(ValueError, match="older version .*restart from the handover"):
        DiscreteState.load(tmp_path / "old.npz")
    with pytest.raises(ValueError, match=r"contact_table has shape \(1, 4\)"):
        DiscreteState(**{**{k: getattr(st, k) for k in ("x", "x_ref", "v", "mass")},
                         **{f: getattr(st, f) for f in st.arrays() if f not in
                            ("x", "x_ref", "v", "mass")},
                         "contact_table": arrays["contact_table"]})


# --- bad input: clear ValueErrors naming the problem ----------------------------------------
def test_inverted_element_refused():
    pts, cells = rectangle_mesh(2.0, 1.0, 2, 1)
    cells[1] = cells[1, ::-1]  # clockwise
    with pytest.raises(ValueError, match="element 1 is inverted"):
        from_mesh(pts, cells, [0, 0], [MAT])
    # fix_orientation repairs clockwise input
    st = from_mesh(pts, cells, [0, 0], [MAT], fix_orientation=True)
    assert st.interface_nodes.shape == (1, 4)


def test_zero_area_element_refused():
    pts = np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]])
    with pytest.raises(ValueError, match="element 0 is zero-area"):
        from_mesh(pts, [[0, 1, 2]], [0], [MAT])


def test_nan_coordinates_refused():
    pts, cells = rectangle_mesh(2.0, 1.0, 2, 1)
    pts[4, 1] = np.nan
    with pytest.raises(ValueError, match="non-finite coordinates"):
        from_mesh(pts, cells, [0, 0], [MAT])


@pytest.mark.parametrize("kw,name", [(dict(E=-1.0), "E"), (dict(density=-2.0), "density"),
                                     (dict(nu=0.5), "nu"), (dict(phi=20.0, psi=30.0), "psi")])
def test_bad_material_refused(kw, name):
    base = dict(E=1.0e5, nu=0.3, density=2.0)
    base.update(kw)
    with pytest.raises(MaterialError, match=f"material 'block': {name} = "):
        Material(name="block", **base)


def test_weightless_material_refused_by_the_discrete_engine():
    pts, cells = rectangle_mesh(2.0, 1.0, 2, 1)
    with pytest.raises(ValueError, match="needs mass"):
        from_mesh(pts, cells, [0, 0], [Material(name="air", E=1e5, nu=0.3)])


def test_bad_mesh_arguments_refused():
    pts, cells = rectangle_mesh(2.0, 1.0, 2, 1)
    with pytest.raises(ValueError, match="cell_material"):
        from_mesh(pts, cells, [0, 3], [MAT])
    with pytest.raises(ValueError, match="expected"):
        from_mesh(pts, cells[:, :2], [0, 0], [MAT])
    with pytest.raises(ValueError, match="element"):
        rectangle(1.0, 1.0, 1, 1, "Q8", material=MAT)
    with pytest.raises(ValueError, match="width"):
        rectangle(-1.0, 1.0, 1, 1, material=MAT)
