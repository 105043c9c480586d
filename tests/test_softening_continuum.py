"""Strain softening in the continuum phase: the solver's points use their own cell's
characteristic length and Newton follows the softening branch under displacement control."""

import numpy as np
import pytest

from hybrid.constitutive.mohr_coulomb import update_stress
from hybrid.continuum import PlasticSolver
from hybrid.geometry import build_mesh
from hybrid.materials import Material, Strength
from hybrid.model import Displacement, Model, Roller

C_PEAK, C_RES, U_R = 20.0, 5.0, 0.01  # kPa, kPa, m


@pytest.mark.parametrize("cells,n,length", [("quadrilateral", 2, 0.5),
                                           ("triangle", 4, 0.25)])
def test_homogeneous_compression_follows_the_point_law_with_the_cell_length(builder, cells, n,
                                                                           length):
    """A 1 m x 1 m block of softening Tresca clay on smooth supports, its top pushed down in
    30 steps to 6 % strain (past the residual slip): the state stays homogeneous, and every
    Gauss point follows the point kernel driven by the same strain increments with its cell's
    crack-band width (sqrt(A) of a square cell of side 0.5 m; sqrt(2 A) = 0.25 m of a triangle
    of area 0.25^2 / 2). Stress agrees to 1e-6 relative at every step (Newton to 1e-8); |sigma_yy|
    never exceeds 2 c_p and ends at 2 c_r; a kernel given twice the length ends more than 1 kPa
    away on the softening branch (the length is really used)."""
    clay = Material(name="clay", E=1.0e4, nu=0.3, cohesion=C_PEAK, plastic=True,
                    residual=Strength(cohesion=C_RES), softening_displacement=U_R)
    mesh = build_mesh(builder("block"), width=1.0, height=1.0, nx=n, ny=n, cells=cells)
    model = Model(mesh, {"soil": clay}, supports=[Roller("base", "y"), Roller("left", "x"),
                                                  Displacement("top", uy=-0.06)])
    solver = PlasticSolver(model, degree=1)
    np.testing.assert_allclose(solver.point_length, length, rtol=1e-10)  # gmsh coordinates
    steps = 30
    point, kappa = np.zeros(4), 0.0
    longer, kappa_longer = np.zeros(4), 0.0
    strain = np.zeros(2)
    sigma_yy, gap = [], 0.0
    for k in range(steps):
        assert solver.step(d_lambda=1.0 / steps) is not None, f"no equilibrium at step {k + 1}"
        s = solver.stress
        np.testing.assert_allclose(s, np.broadcast_to(s[0], s.shape), rtol=0, atol=1e-6 * 40)
        # homogeneous strain: exx from the lateral expansion of the right side, eyy imposed
        ux = solver.u.x.array.reshape(-1, 2)[:, 0]
        now = np.array([ux.max(), -0.06 * (k + 1) / steps])
        de = np.array([*(now - strain), 0.0, 0.0])[[0, 1, 2, 3]]
        strain = now
        point, _, dk, _ = update_stress(point, de, clay, plastic_strain=kappa, length=length,
                                        want_tangent=False)
        kappa += dk
        longer, _, dk, _ = update_stress(longer, de, clay, plastic_strain=kappa_longer,
                                         length=2 * length, want_tangent=False)
        kappa_longer += dk
        np.testing.assert_allclose(s[0], point, rtol=1e-6, atol=1e-6 * C_PEAK)
        sigma_yy.append(s[0, 1])
        gap = max(gap, abs(longer[1] - point[1]))
    assert min(sigma_yy) >= -2 * C_PEAK * (1 + 1e-9)  # never beyond the peak strength
    assert min(sigma_yy) < -2 * C_RES - 10.0  # and well above residual on the way
    assert sigma_yy[-1] == pytest.approx(-2 * C_RES, rel=1e-6)
    assert gap > 1.0
