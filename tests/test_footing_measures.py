"""Footing settlement and heave measured once (FootingMarks); the outline of a discrete start."""

import numpy as np
import pytest

from hybrid.discrete.builders import rectangle
from hybrid.discrete.figures import outline_segments, plot_configuration
from hybrid.discrete.measures import FootingMarks
from hybrid.materials import Material

SOIL = Material(name="soil", E=1.0e4, nu=0.3, density=2.0)


def _ground():
    """A 4 m x 1 m ground of 4 x 1 Q4 elements; the footing on its left metre."""
    st = rectangle(4.0, 1.0, 4, 1, material=SOIL)
    top = np.flatnonzero(np.isclose(st.x_ref[:, 1], 1.0))
    footing = top[st.x_ref[top, 0] <= 1.0]
    return st, footing, top


def test_settlement_and_heave_of_a_footing():
    """Settlement: the footing nodes' mean drop since the start, plus the continuum's offset
    for the total; heave: the largest rise of the surface beside the footing, wherever it is
    (not the node at one height)."""
    st, footing, top = _ground()
    marks = FootingMarks.pick(st, footing, top, beside=1.0, offset=0.05)
    assert set(marks.surface) == set(top[st.x_ref[top, 0] > 1.0])
    st.x[footing, 1] -= 0.2
    beside = marks.surface[np.argsort(st.x_ref[marks.surface, 0])]
    st.x[beside[0], 1] += 0.1  # the first vertex beside the footing rises 0.1 m
    st.x[beside[1], 1] += 0.3  # one further out rises 0.3 m: the heave
    assert marks.settlement(st) == pytest.approx(0.2, rel=1e-12)
    assert marks.total_settlement(st) == pytest.approx(0.25, rel=1e-12)
    assert marks.heave(st) == pytest.approx(0.3, rel=1e-12)
    with pytest.raises(ValueError, match="no surface node beyond x = 9"):
        FootingMarks.pick(st, footing, top, beside=9.0)


def test_outline_is_the_boundary_at_the_start(tmp_path):
    """The outline of a 4 x 1 strip is its 10 boundary edges (perimeter 10 m), in the start
    geometry whatever the elements did since; the figure draws it."""
    st, footing, _ = _ground()
    st.x[footing, 1] -= 0.2
    seg = outline_segments(st)
    assert seg.shape == (10, 2, 2)
    assert np.linalg.norm(seg[:, 1] - seg[:, 0], axis=1).sum() == pytest.approx(10.0)
    path = plot_configuration(tmp_path / "c.png", st, outline=True, window=(-1, -1, 5, 2))
    assert path.stat().st_size > 0
