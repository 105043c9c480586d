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


def _seeded_biaxial(builder, n: int) -> tuple[np.ndarray, np.ndarray, float]:
    """A 1 m x 2 m block of softening Tresca clay (c 20 -> 5 kPa over u_r = 0.05 m) on smooth
    base and left wall, its smooth top pushed down 0.25 m; the cells in the bottom-right
    0.125 m square start half-way to residual (a softened seed, the same on every mesh, so
    that one band forms instead of a mesh-dependent set of symmetric bands). Returns the
    (top displacement [m], top load [kN/m]) curve and the fraction of points past xi = 0.5."""
    u_r = 0.05
    clay = Material(name="clay", E=1.0e4, nu=0.3, cohesion=20.0, plastic=True,
                    residual=Strength(cohesion=5.0), softening_displacement=u_r)
    mesh = build_mesh(builder("block"), width=1.0, height=2.0, nx=n, ny=2 * n)
    model = Model(mesh, {"soil": clay}, supports=[Roller("base", "y"), Roller("left", "x"),
                                                  Displacement("top", uy=-0.25)])
    solver = PlasticSolver(model, degree=2)
    x, cells = model.mesh.cell_vertices()
    centre = x[cells].mean(axis=1)
    seed = np.repeat((centre[:, 0] > 0.875) & (centre[:, 1] < 0.125), solver.disc.num_points)
    h = solver.point_length
    solver.plastic_strain[seed] = 0.5 * u_r / (np.sqrt(3.0) * h[seed])
    curve: list[tuple[float, float]] = []

    def record(s: PlasticSolver) -> bool:
        curve.append((0.25 * s.load_factor, -s.reaction("top", 1)))
        return False

    assert solver.ramp(1.0, 100, stop=record, min_increment=1e-4).completed
    d, load = np.array(curve).T
    xi = np.minimum(np.sqrt(3.0) * solver.plastic_strain * h / u_r, 1.0)
    return d, load, float(np.mean(xi > 0.5))


@pytest.mark.slow
def test_post_peak_load_is_mesh_objective_once_one_band_forms(builder):
    """The crack band regularises the structure's response: with 16 and 32 cells across
    (h = 1/16 and 1/32 m) the peak load agrees to 0.5 % (measured 0.05 %) and the post-peak
    load at 0.04, 0.08, 0.12 and 0.2 m of top displacement to 5 % (measured 3.8, 2.8, 1.7 and
    0.6 %: converging as the band softens through), while the softened band, one element
    wide, halves its share of the points (0.146 -> 0.078). 5 % is the bar the issue sets for
    the discrete-phase measures; the peak bar is tighter than the 3 % of the collapse loads."""
    d16, p16, band16 = _seeded_biaxial(builder, 16)
    d32, p32, band32 = _seeded_biaxial(builder, 32)
    assert p32.max() == pytest.approx(p16.max(), rel=5e-3)
    for at in (0.04, 0.08, 0.12, 0.2):
        assert np.interp(at, d32, p32) == pytest.approx(np.interp(at, d16, p16), rel=0.05)
    assert band32 == pytest.approx(0.5 * band16, rel=0.15)
