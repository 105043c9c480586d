"""D3: the tied discrete assembly equals the continuum (dolfinx Q1) on the same Q4 mesh.

The C4 slope (coarse, 2 m elements) under gravity: dolfinx Q1 elastic (2x2 Gauss, small
strain) against the discrete engine run to rest by dynamic relaxation from the undeformed,
stress-free mesh (Q4 with full 2x2 integration, the same element; updated Lagrangian). Bar
(verification-targets D3): nodal displacements and Gauss-point stresses within 1 % of the max.
"""

import numpy as np

from hybrid.discrete.solver import run
from hybrid.handover import to_discrete


def test_d3_tied_assembly_equals_dolfinx_q1(case):
    m = case("slope_gravity")
    state = m.solve(m.Parameters(size=2.0, flat=30.0, degree=1, cells="quadrilateral"))
    reference = to_discrete(state)  # nodes at x + u, Gauss stresses of dolfinx (same order)
    # the same mesh, undeformed and stress-free, settled under gravity
    u_fem, s_fem = state.u.x.array.copy(), state.stress.copy()
    state.u.x.array[:] = 0.0
    state.stress[:] = 0.0
    start = to_discrete(state)
    state.u.x.array[:], state.stress[:] = u_fem, s_fem
    disc = start.discrete
    x0 = disc.x.copy()
    u_ref = reference.discrete.x - x0
    result = run(disc, until_rest=1e-12, max_steps=50_000, local_damping=0.8, contact=False,
                 bbar=False)
    assert result.stop_reason == "rest"
    u = disc.x - x0
    assert np.abs(u - u_ref).max() < 0.01 * np.abs(u_ref).max()
    s_ref = reference.discrete.stress
    assert np.abs(disc.stress - s_ref).max() < 0.01 * np.abs(s_ref).max()
