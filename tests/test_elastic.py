"""Continuum elasticity against closed forms: C1-C4 of verification-targets.md."""

import numpy as np
import pytest

from hybrid.continuum import solve_elastic
from hybrid.geometry import build_mesh
from hybrid.materials import Material
from hybrid.model import Model, Roller


@pytest.mark.parametrize("cells", ["quadrilateral", "triangle"])
@pytest.mark.parametrize("degree", [1, 2])
def test_c1_uniform_load(case, tmp_path, cells, degree):
    """C1: uniform stress; any element reproduces it exactly (patch test), bar 1e-6."""
    summary = case("uniform_load").main(out=tmp_path, cells=cells, degree=degree)
    for name, check in summary["checks"].items():
        assert check.passed, (name, check)
        assert check.error < 1e-6


@pytest.mark.parametrize("cells", ["quadrilateral", "triangle"])
def test_c2_oedometric_column(builder, cells):
    """C2: confined column under gravity: sigma_v = -gamma z, sigma_h = K0 sigma_v.

    The stress is linear in depth, so quadratic displacements represent it exactly: the
    0.5 % bar of the target is met with rounding-level error (checked at 1e-9).
    """
    H, gamma, nu, E = 10.0, 19.0, 0.3, 20_000.0
    mesh = build_mesh(builder("block"), width=2.0, height=H, nx=2, ny=8, cells=cells)
    soil = Material(name="soil", E=E, nu=nu, unit_weight=gamma)
    model = Model(mesh, {"soil": soil}, supports=[Roller("base", "y"), Roller("left", "x"),
                                                  Roller("right", "x")])
    state = solve_elastic(model, gravity=True, degree=2)
    pts = np.column_stack([np.full(9, 0.7), np.linspace(0.5, 9.5, 9)])
    s = state.stress_at(pts)
    z = H - pts[:, 1]
    np.testing.assert_allclose(s[:, 1], -gamma * z, rtol=1e-9)
    np.testing.assert_allclose(s[:, 0], -nu / (1 - nu) * gamma * z, rtol=1e-9)
    np.testing.assert_allclose(s[:, 2], -nu / (1 - nu) * gamma * z, rtol=1e-9)
    np.testing.assert_allclose(s[:, 3], 0.0, atol=1e-9 * gamma * H)
    # top settlement gamma H^2 / (2 M), M = E (1 - nu) / ((1 + nu)(1 - 2 nu))
    M = E * (1 - nu) / ((1 + nu) * (1 - 2 * nu))
    u_top = state.displacement_at(np.array([[1.0, H]]))[0, 1]
    assert u_top == pytest.approx(-gamma * H**2 / (2 * M), rel=1e-9)


def test_c3_flexible_footing(case, tmp_path):
    """C3: centreline vertical stress within 5 % of the strip-load solution (target bar).

    Reduced mesh (fine = 0.4 m at the footing edge) keeps the test fast; the full case uses
    0.25 m. The settlement is reported beside the thesis's 0.101 m, not asserted against it;
    its mesh convergence is asserted (< 1 % change when the mesh is halved).
    """
    summary = case("flexible_footing").main(out=tmp_path, fine=0.4, coarse=3.0)
    check = summary["checks"]["sigma_z_centreline_worst"]
    assert check.passed and check.error < 0.05
    assert summary["settlement_convergence"]["relative_change"] < 0.01
    for name in ("continuum.xdmf", "continuum.h5", "summary.json", "sigma_yy.png",
                 "centreline_stress.png"):
        assert (tmp_path / name).is_file(), name


def test_c4_slope_gravity(case, tmp_path):
    """C4: far-field geostatic stresses within the 2 % bar; mesh-converged (< 2 % change)."""
    summary = case("slope_gravity").main(out=tmp_path, size=1.5)
    for name, check in summary["checks"].items():
        assert check.passed, (name, check)
    assert summary["mesh_convergence"]["max_change_over_max_stress"] < 0.02


def test_c2_oedometer_case(case, tmp_path):
    """The C2 case script: every check within the 0.5 % bar (exact to rounding for P2)."""
    summary = case("oedometer").main(out=tmp_path)
    for name, check in summary["checks"].items():
        assert check.passed and check.error < 1e-6, (name, check)
    assert (tmp_path / "stress_profile.png").is_file()
