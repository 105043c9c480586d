"""Optional plastic-strain splitting criterion (an addition to thesis 4.5, see ties.py)."""

import math

import numpy as np
import pytest

from hybrid.discrete import rectangle, ties
from hybrid.materials import Bond, Material


@pytest.mark.parametrize("element", ["Q4", "T3"])
def test_plastic_strain_limit_splits_only_strained_interfaces(element):
    """Interfaces fail (mode 3) where the mean plastic strain of the Gauss points next to the
    edge exceeds the limit, hold elsewhere, and never fail without a limit."""
    mat = Material(name="block", E=1.0e4, nu=0.0, density=2.0,
                   bond=Bond(cohesion=1e3, phi=30.0, tensile_strength=1e3))
    st = rectangle(3.0, 1.0, 3, 1, element, material=mat)
    st.stress[:] = [-10.0, -10.0, -10.0, 0.0]  # far from the traction criteria
    centroids = st.element_centroids()
    left = centroids[:, 0] < 2.0  # the first two columns of cells yield
    st.plastic_strain[left] = 0.06
    assert not ties.check_interfaces(st).any()  # default: no plastic criterion
    modes = ties.check_interfaces(st, split_plastic_strain=0.05)
    a, b = st.interface_elements[:, 0], st.interface_elements[:, 1]
    both = left[a] & left[b]
    one = left[a] ^ left[b]
    assert both.any() and np.all(modes[both] == ties.FAIL_PLASTIC)
    # an edge between a yielded and an intact column: mean 0.03 < 0.05 holds
    assert np.all(modes[one] == 0) and np.all(modes[~(both | one)] == 0)
    assert not ties.check_interfaces(st, split_plastic_strain=math.inf).any()
