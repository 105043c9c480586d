"""Mohr-Coulomb in the discrete element kernel: plane-strain yield plateau and the Prandtl
punch (B-bar Q4 does not lock in isochoric plastic flow; full integration does)."""

import math

import numpy as np
import pytest

from hybrid.discrete import integrate, rectangle
from hybrid.materials import Material


def test_plane_strain_compression_plateau_tresca():
    """A Tresca block (phi = 0, c = 10 kPa) compressed in plane strain between smooth
    platens: the stress difference sigma_x - sigma_y levels off at 2c exactly."""
    c = 10.0
    mat = Material(name="block", E=1.0e4, nu=0.3, density=1.0, plastic=True, cohesion=c)
    st = rectangle(1.0, 1.0, 2, 2, material=mat, gravity=(0.0, 0.0))
    xr = st.x_ref
    st.fix(np.isclose(xr[:, 1], 0.0), x=False, y=True)
    st.fix(np.isclose(xr[:, 0], 0.0), x=True, y=False)
    st.fix(np.isclose(xr[:, 1], 1.0), x=False, y=True, velocity=(0.0, -1e-3))
    dt = 0.5 * integrate.stable_time_step(st)
    for _ in range(int(0.01 / 1e-3 / dt)):  # 1 % axial strain, 10x the yield strain
        integrate.step(st, dt, local_damping=0.7)
    s = st.stress
    # principal stresses (in-plane pair and sigma_zz): the return is exact (closed form), so
    # s1 - s3 = 2c to 1e-6 of c at every Gauss point
    p, h = 0.5 * (s[..., 0] + s[..., 1]), 0.5 * (s[..., 0] - s[..., 1])
    rad = np.hypot(h, s[..., 3])
    s1 = np.maximum(p + rad, s[..., 2])
    s3 = np.minimum(p - rad, s[..., 2])
    np.testing.assert_allclose(s1 - s3, 2.0 * c, atol=1e-6 * c)
    # and the principal axes stay x / y (smooth platens): shear below 1 % of c
    assert np.max(np.abs(s[..., 3])) < 0.01 * c
    assert np.all(st.yielded == 1)
    assert np.all(st.plastic_strain > 0.0)


def _punch(bbar, n, smax, V=0.005):
    """Smooth rigid strip footing (half-width 1 m, half model 5 m x 5 m) pushed at V into
    weightless Tresca soil; returns (settlement, q / ((2 + pi) c)) at 8 samples."""
    c = 10.0
    mat = Material(name="block", E=1.0e4, nu=0.3, density=1.0, plastic=True, cohesion=c)
    W = 5.0
    st = rectangle(W, W, n, n, material=mat, gravity=(0.0, 0.0))
    xr = st.x_ref
    st.fix(np.isclose(xr[:, 1], 0.0))
    st.fix(np.isclose(xr[:, 0], 0.0) | np.isclose(xr[:, 0], W), x=True, y=False)
    foot = np.isclose(xr[:, 1], W) & (xr[:, 0] < 1.0 + 1e-9)
    st.fix(foot, x=False, y=True, velocity=(0.0, -V))
    dt = 0.5 * integrate.stable_time_step(st)
    nsteps = int(smax / V / dt)
    out = []
    for k in range(nsteps):
        integrate.step(st, dt, local_damping=0.7, bbar=bbar)
        if (k + 1) % (nsteps // 8) == 0:
            load = -np.sum(st.internal_force[foot, 1]) / 1.0  # kN/m over the half-width 1 m
            out.append((V * dt * (k + 1), load / ((2.0 + math.pi) * c)))
    return np.array(out)


def test_bbar_punch_reaches_prandtl_full_integration_locks():
    """Prandtl q_u = (2 + pi) c. On a coarse 20 x 20 mesh (4 elements under the half-footing)
    B-bar levels off within 15 % of it (mesh error of a coarse punch; 8 % at 40 x 40, see the
    slow test); full 2x2 integration locks: it is over 10 % stiffer and keeps hardening."""
    bb = _punch(True, 20, 0.06)
    full = _punch(False, 20, 0.06)
    assert abs(bb[-1, 1] - 1.0) < 0.15
    assert full[-1, 1] > 1.10 * bb[-1, 1]
    # plateau: B-bar's last quarter rises < 2 %, full integration's > 2x as much
    rise_bb = bb[-1, 1] - bb[-3, 1]
    rise_full = full[-1, 1] - full[-3, 1]
    assert rise_bb < 0.02
    assert rise_full > 2.0 * rise_bb


@pytest.mark.slow
def test_bbar_punch_converges_toward_prandtl():
    """40 x 40 mesh: B-bar within 8 % of Prandtl at 2 % settlement/width."""
    bb = _punch(True, 40, 0.04)
    assert abs(bb[-1, 1] - 1.0) < 0.08


def test_principal_split_matches_shared_point_kernel():
    """The element kernel's trig-free spectral split around the shared principal return gives
    the shared ``mohr_coulomb_point`` result (stress and plastic strain) to 1e-9 relative,
    over random trial stresses hitting every return region."""
    from hybrid.constitutive.mohr_coulomb import mohr_coulomb_point
    from hybrid.discrete.elements import _mc_update

    rng = np.random.default_rng(4)
    K, G = 8.0e3, 4.0e3
    out = np.zeros(4)
    tan = np.zeros((4, 4))
    n_plastic = 0
    for _ in range(2000):
        c = rng.uniform(0.0, 20.0)
        phi = math.radians(rng.uniform(0.0, 40.0))
        psi = rng.uniform(0.0, 1.0) * phi
        ft = rng.uniform(0.0, 10.0) if rng.random() < 0.5 else 1e30
        if c == 0.0 and phi == 0.0:
            continue
        s0 = rng.normal(0.0, 30.0, 4)
        de = rng.normal(0.0, 5e-3, 4)
        # a kernel-table row without softening (residual columns = peak, u_r = 0)
        table = np.array([[K, G, c, math.sin(phi), math.cos(phi), math.sin(psi), ft,
                           c, phi, phi, psi, psi, ft, 0.0]])
        dp_ref, y_ref = mohr_coulomb_point(*s0, de[0], de[1], 0.0, de[2], table, 0, 0.0, 1.0,
                                           out, tan, False)
        lam = K - 2.0 * G / 3.0
        ev = de[0] + de[1]
        trial = (s0[0] + lam * ev + 2 * G * de[0], s0[1] + lam * ev + 2 * G * de[1],
                 s0[2] + lam * ev, s0[3] + G * de[2])
        sxx, syy, szz, sxy, dp, y = _mc_update(*trial, K, G, table, 0, 0.0, 1.0,
                                               np.full((1, 1, 8), np.nan), 0, 0)
        scale = np.max(np.abs(trial)) + c
        np.testing.assert_allclose([sxx, syy, szz, sxy], out, rtol=0, atol=1e-9 * scale)
        assert abs(dp - dp_ref) <= 1e-9 * max(dp_ref, 1e-12) + 1e-15
        assert int(y) == int(y_ref)
        n_plastic += int(y)
    assert n_plastic > 500  # the sample really exercises the returns
