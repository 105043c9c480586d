"""Checkpoints: every field checked on load (shape, dtype, size, index range) with a clear
message before any kernel sees it; written atomically with the previous one kept."""

import zipfile

import numpy as np
import pytest

from hybrid.discrete import rectangle
from hybrid.discrete.state import DiscreteState
from hybrid.materials import Material

MAT = Material(name="block", E=1.0e5, nu=0.25, density=2.0)


def _fields(tmp_path):
    st = rectangle(2.0, 1.0, 2, 2, material=MAT)
    st.tie_rigidly(np.arange(3))
    path = st.save(tmp_path / "good.npz")
    with np.load(path) as data:
        return {k: data[k] for k in data.files}


def _save(tmp_path, arrays, name="bad.npz"):
    path = tmp_path / name
    np.savez(path, **arrays)
    return path


def test_a_good_checkpoint_loads(tmp_path):
    back = DiscreteState.load(_save(tmp_path, _fields(tmp_path)))
    assert back.n_elements == 4 and back.rigid_links.shape == (2, 2)


@pytest.mark.parametrize(("field", "value", "message"), [
    ("element_nodes", lambda a: a + 1000, "'element_nodes' holds indices outside 0..15"),
    ("element_material", lambda a: a + 7, "'element_material' holds indices outside 0..0"),
    ("node_group", lambda a: -a - 1, "'node_group' holds indices outside"),
    ("group_nodes", lambda a: np.zeros_like(a), "group_nodes is not a permutation"),
    ("group_ptr", lambda a: a[::-1].copy(), "group_ptr is not a CSR pointer"),
    ("interface_nodes", lambda a: a * 100, "'interface_nodes' holds indices outside"),
    ("interface_elements", lambda a: a + 4, "'interface_elements' holds indices outside 0..3"),
    ("rigid_links", lambda a: a + 10**6, "'rigid_links' holds indices outside"),
    ("contact_pairs", lambda a: np.array([[0, 9]]), "'contact_shear' has shape"),
    ("stress", lambda a: a[:, :2], r"'stress' has shape \(4, 2, 4\), expected \(4, 4, 4\)"),
    ("x", lambda a: a[:-1], "'x_ref' has shape"),
    ("mass", lambda a: a.astype(np.float32), "'mass' has dtype float32, expected float64"),
    ("element_nodes", lambda a: a.astype(float), "'element_nodes' has dtype float64"),
    ("element_nodes", lambda a: a[:, :2], "element_nodes has 2 nodes per element"),
    ("ledger", lambda a: a[:3], r"'ledger' has shape \(3,\), expected \(8,\)"),
    ("material_table", lambda a: a[:, :7], "'material_table' has shape"),
    ("time", lambda a: np.array(np.nan), "time = nan must be finite"),
    ("step", lambda a: np.array(-3), "step = -3 must be >= 0"),
    ("yielded", lambda a: a.astype(bool), "'yielded' has dtype bool, expected int8"),
])
def test_a_bad_checkpoint_is_refused_with_the_field_named(tmp_path, field, value, message):
    arrays = _fields(tmp_path)
    arrays[field] = value(arrays[field])
    with pytest.raises(ValueError, match=message):
        DiscreteState.load(_save(tmp_path, arrays))


def test_missing_field_refused(tmp_path):
    arrays = _fields(tmp_path)
    del arrays["interface_intact"]
    with pytest.raises(ValueError, match="lacks the field.*interface_intact"):
        DiscreteState.load(_save(tmp_path, arrays))


def test_object_arrays_refused_without_unpickling(tmp_path):
    arrays = _fields(tmp_path)
    arrays["x"] = np.array([{"a": 1}, None], dtype=object)
    with pytest.raises(ValueError, match="'x' holds Python objects"):
        DiscreteState.load(_save(tmp_path, arrays))


def test_not_a_checkpoint_refused(tmp_path):
    for name, data in (("empty.npz", b""), ("text.npz", b"hello"),):
        (tmp_path / name).write_bytes(data)
        with pytest.raises(ValueError, match="cannot be read.*truncated or not an npz"):
            DiscreteState.load(tmp_path / name)
    _fields(tmp_path)  # a good file, cut in half (a write interrupted)
    blob = (tmp_path / "good.npz").read_bytes()
    (tmp_path / "cut.npz").write_bytes(blob[: len(blob) // 2])
    with pytest.raises(ValueError, match="cannot be read"):
        DiscreteState.load(tmp_path / "cut.npz")
    with pytest.raises(ValueError, match="cannot be read"):
        DiscreteState.load(tmp_path / "nowhere.npz")


def test_a_zip_bomb_is_refused_before_it_is_inflated(tmp_path):
    """A small compressed file that would inflate to 800 MB."""
    arrays = _fields(tmp_path)
    path = tmp_path / "bomb.npz"
    np.savez(path, **arrays)
    with zipfile.ZipFile(path, "a", compression=zipfile.ZIP_DEFLATED) as zf, \
            zf.open("padding.npy", "w", force_zip64=True) as f:
        np.lib.format.write_array_header_1_0(
            f, {"descr": "<f8", "fortran_order": False, "shape": (10**8,)})
        chunk = bytes(2**20)
        for _ in range(800):
            f.write(chunk)
    assert path.stat().st_size < 2 * 2**20
    with pytest.raises(ValueError, match="would inflate to 800 MiB"):
        DiscreteState.load(path)
