"""R1, the plane granular column collapse: a column of elastic grains with frictional, cohesionless
bonds released from its gravity state spreads to rest; run-out and height against experiments.

Fast: coarse runs (8 grains along the column) keep energy bounded, elements and mass, reach
rest, and spread further for a taller column and less far on a rough floor; the rough floor's
mesh; the deposit measure on a hand-made state. Slow:
the shipped mesh at a = 0.5, 1 and 2 against the aluminium-rod laws (arXiv:1512.05180), with
the committed figures of docs/hybrid.md; the run-out's grain size, L0 / 10 against L0 / 20 (not
converged: a strict xfail) and L0 / 40 against L0 / 60 (converged), and there against Bui et
al.'s measured run-out (a strict xfail).
"""

import json

import numpy as np
import pytest
from conftest import CASES, ROOT, assert_bars

from hybrid.discrete.measures import deposit


def test_deposit_counts_the_continuous_mass_only():
    """Three unit squares: two touching at x = 0..2, one alone at 3..4 (a flung grain). The
    run-out is 2 (the far end of the continuous mass), the flung one is detached; the height is
    the highest node of the deposit; the profile takes the highest node per bin."""
    from hybrid.discrete.state import from_mesh
    from hybrid.materials import Material

    sq = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], float)
    x = np.vstack([sq, sq + [1.0, 0.0], sq + [3.0, 0.0]])
    x[10:12, 1] = 2.0  # the flung grain is taller: it must not set the height
    x[2, 1] = 1.5  # the first square's top-right corner raised, at x = 1 (second bin)
    grain = Material(name="grain", E=1000.0, nu=0.3, density=1.0)
    st = from_mesh(x, np.arange(12).reshape(3, 4), np.zeros(3, np.int32), [grain])
    dep = deposit(st, np.ones(3, bool), bin_width=1.0)
    assert dep.runout == pytest.approx(2.0, abs=1e-12)
    assert dep.detached == 1 and list(dep.elements) == [0, 1]
    assert dep.height == pytest.approx(1.5, abs=1e-12)
    assert dep.profile[:, 1] == pytest.approx([1.0, 1.5], abs=1e-12)  # bins [0,1), [1,2]
    with pytest.raises(ValueError, match="no element"):
        deposit(st, np.zeros(3, bool), bin_width=1.0)
    # the same squares seen from a wall at x = 4, spreading towards -x: the lone square is the
    # start (nearest the wall, at 0..1 from it), a gap of 1 follows it, so the deposit is that
    # square alone and the two touching ones are detached
    back = deposit(st, np.ones(3, bool), wall_x=4.0, bin_width=1.0, direction=-1)
    assert back.runout == pytest.approx(1.0, abs=1e-12)
    assert back.detached == 2 and list(back.elements) == [2]
    assert back.height == pytest.approx(2.0, abs=1e-12)
    assert back.profile.tolist() == [[0.5, 2.0]]  # one bin, 0..1 from the wall
    with pytest.raises(ValueError, match="direction"):
        deposit(st, np.ones(3, bool), bin_width=1.0, direction=0)


def test_deposit_walks_from_the_wall_not_from_behind_it():
    """A mass on both sides of its wall (a dam seen from its axis): a square flung far behind
    the wall (x = -3..-2, the wall at x = 0.5) is no part of the deposit and does not cut it;
    the walk starts with the square across the wall (0..1) and ends at the far edge of the
    next (1..2): run-out 1.5 from the wall, nothing detached."""
    from hybrid.discrete.state import from_mesh
    from hybrid.materials import Material

    sq = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], float)
    x = np.vstack([sq + [-3.0, 0.0], sq, sq + [1.0, 0.0]])
    grain = Material(name="grain", E=1000.0, nu=0.3, density=1.0)
    st = from_mesh(x, np.arange(12).reshape(3, 4), np.zeros(3, np.int32), [grain])
    dep = deposit(st, np.ones(3, bool), wall_x=0.5, bin_width=1.0)
    assert dep.runout == pytest.approx(1.5, abs=1e-12)
    assert dep.detached == 0 and list(dep.elements) == [1, 2]
    with pytest.raises(ValueError, match="no element of the mask lies on the side"):
        deposit(st, np.array([True, False, False]), wall_x=0.5, bin_width=1.0)


def test_granular_collapse_coarse(case, tmp_path):
    """Coarse grains (L0 / 8): a = 0.5 and a = 1.5 reach rest with bounded energy and their
    elements and mass; the taller column runs out further (normalised by L0) and keeps less of
    its height, as in every experiment. On a rough floor (a sawtooth standing in for grains
    fixed to it) the a = 1.5 column reaches rest too, and runs out less far and keeps more of
    its height than on the smooth one: the packing must shear above the teeth instead of
    sliding on a plane at the contact angle."""
    mod = case("granular_collapse")
    runs = {a: mod.main(out=tmp_path / f"a{a}", aspect=a, nx=8, progress=False)
            for a in (0.5, 1.5)}
    rough = mod.main(out=tmp_path / "rough", aspect=1.5, nx=8, floor="rough", progress=False)
    assert_bars(rough)
    assert rough["discrete"]["stop"] == "rest"
    assert rough["deposit"]["normalised_runout"] < runs[1.5]["deposit"]["normalised_runout"]
    assert rough["deposit"]["height_over_H0"] > runs[1.5]["deposit"]["height_over_H0"]
    for s in runs.values():
        assert_bars(s)
        assert s["discrete"]["stop"] == "rest"
        assert s["discrete"]["interfaces_failed"] > 0
        assert s["deposit"]["runout_m"] > s["parameters"]["length"]  # it spread
    from hybrid.discrete.biaxial import contact_friction

    for s in runs.values():  # the grains' contact angle is the calibrated one, not phi
        grains = s["grains"]
        assert grains["bulk_phi_deg"] == s["parameters"]["phi"]
        assert grains["contact_phi_deg"] == contact_friction(s["parameters"]["phi"])
    low, tall = runs[0.5]["deposit"], runs[1.5]["deposit"]
    assert tall["normalised_runout"] > low["normalised_runout"]
    assert tall["height_over_H0"] < low["height_over_H0"]


def test_rough_floor_is_a_sawtooth_under_an_unchanged_column(case):
    """``floor="rough"``: the floor's top, under the column and along the runway, is a triangle
    wave of half a grain from valley to peak about y = 0 (vertices at 0, the two ends, and
    +-size/4, both signs), the column keeps the flat floor's area L0 H0 (whole wavelengths
    under it, nx even) and about its number of grains (one edge a cell along the teeth: the
    grains keep their size), and a structured or quadrilateral column is refused with the
    parameters to change."""
    from hybrid.geometry import build_mesh, load_builder
    from hybrid.parameters import ParameterError

    mod = case("granular_collapse")
    L0, nx, a = 0.2, 20, 1.0
    size = L0 / nx
    meshes = {r: build_mesh(load_builder(mod.MESHES / "column.py"), length=L0, height=a * L0,
                            nx=nx, ny=nx, runway=mod.runway(L0, a), wall=2 * size,
                            depth=2 * size, cells="triangle", structured=False, roughness=r)
              for r in (0.0, 0.5 * size)}
    mesh = meshes[0.5 * size]
    assert mesh.group_area("column") == pytest.approx(L0 * a * L0, rel=1e-12)
    grains = len(mesh.cells("column")) / len(meshes[0.0].cells("column"))
    assert 0.9 < grains < 1.1
    pts, cells = mesh.cell_vertices()
    floor = cells[mesh.cells("floor")]
    edges = np.sort(np.stack([floor, np.roll(floor, -1, axis=1)], axis=2).reshape(-1, 2), axis=1)
    edge, count = np.unique(edges, axis=0, return_counts=True)
    nodes = np.unique(edge[count == 1])  # the floor's outline
    top = pts[nodes][(pts[nodes, 0] > 1e-12) & (pts[nodes, 0] < mod.runway(L0, a) - 1e-12)
                     & (pts[nodes, 1] > -1.5 * size)]  # its top from the back wall on
    assert np.abs(top[:, 1]).max() == pytest.approx(0.25 * size, rel=1e-12)
    assert top[:, 1].min() == pytest.approx(-0.25 * size, rel=1e-12)
    assert np.all(np.isclose(np.abs(top[:, 1]), 0.25 * size) | np.isclose(top[:, 1], 0.0))
    for bad in ({"structured": True}, {"cells": "quadrilateral"}):
        with pytest.raises(ParameterError, match="structured=false --set cells=triangle"):
            mod.Parameters(floor="rough", **bad)


def test_a_deposit_still_moving_is_compared_with_nothing(case, tmp_path):
    """Stopped by its time limit before rest: the rest check fails, the deposit is marked not
    at rest, and neither the case nor the verification row compares it with the rods."""
    from hybrid.verification import _collapse_extra

    s = case("granular_collapse").main(out=tmp_path, aspect=1.5, nx=8, t_end=0.05,
                                       progress=False)
    assert s["discrete"]["stop"] == "time"
    assert not s["checks"]["rest_kinetic_ratio"].passed
    assert s["deposit"]["at_rest"] is False
    assert not any("rods2015" in name for name in s["checks"])
    rows = _collapse_extra(s)
    assert rows and all(c.reference is None and "not compared" in c.source for c in rows.values())


def _committed(name: str) -> dict:
    return json.loads((ROOT / "docs" / "summaries" / f"{name}.json").read_text())


@pytest.mark.slow
@pytest.mark.parametrize("aspect", [0.5, 1.0, 2.0])
def test_granular_collapse_against_experiments(case, tmp_path, aspect):
    """The shipped mesh (L0 / 20), the contact angle calibrated from the bulk one. Against
    the 15 % bar of the cited experiment (the rods, arXiv:1512.05180):

    * the final height at every aspect ratio (H0 for a < 0.65): within the bar;
    * the run-out at a = 1 and 2: one run is one packing, whose run-out scatters up to as
      much as the bar between packings; the bar is judged in docs/hybrid.md on three packings
      (not met), not asserted here;

    and the run reproduces the committed figures quoted there (the same code gives the same
    deposit bit for bit: rel 1e-9)."""
    s = case("granular_collapse").main(out=tmp_path, aspect=aspect, progress=False)
    assert_bars(s)
    d = s["deposit"]
    refs = d["references"]
    assert d["height_over_H0"] == pytest.approx(refs["rods2015_height"], rel=0.15)
    committed = _committed(f"r1_a{aspect:g}")["deposit"]
    assert d["runout_m"] == pytest.approx(committed["runout_m"], rel=1e-9)
    assert d["height_m"] == pytest.approx(committed["height_m"], rel=1e-9)


@pytest.mark.slow
@pytest.mark.xfail(strict=True, raises=AssertionError, reason=(
    "not met: with the calibrated contact angle the run-out at a = 0.5 moves 26 % from "
    "grains of L0 / 10 to L0 / 20 (0.402 against 0.506 m), beyond the 10 % bar; the run-out "
    "is not converged at L0 / 20 (it stops growing beyond L0 / 40: docs/hybrid.md)"))
def test_granular_collapse_mesh_sensitivity(case, tmp_path):
    """a = 0.5 with grains of L0 / 10 and L0 / 20: run-out within 10 % of each other (the
    mesh bar of docs/hybrid.md), the height H0 on both."""
    mod = case("granular_collapse")
    runs = [mod.main(out=tmp_path / f"nx{n}", nx=n, progress=False)["deposit"] for n in (10, 20)]
    coarse, fine = (r["runout_m"] for r in runs)
    assert abs(coarse - fine) / fine < 0.10
    for r in runs:
        assert r["height_over_H0"] == pytest.approx(1.0, rel=0.01)


@pytest.fixture(scope="module")
def fine_grains(tmp_path_factory):
    """a = 0.5 on grains of L0 / 40 and L0 / 60 (the case's flat floor): their deposits."""
    from hybrid.case import load_case

    out = tmp_path_factory.mktemp("r1_fine")
    mod = load_case(CASES / "granular_collapse.py")
    return {n: mod.main(out=out / f"nx{n}", nx=n, progress=False)["deposit"] for n in (40, 60)}


@pytest.mark.slow
def test_granular_collapse_grain_size_converged(fine_grains):
    """a = 0.5 on grains of L0 / 40 and L0 / 60, the sizes beyond which docs/hybrid.md finds
    the run-out no longer growing: run-out within 10 % of each other (the mesh bar), and the
    committed figures the docs quote reproduced (the same code gives the same deposit bit for
    bit: rel 1e-9)."""
    coarse, fine = (fine_grains[n]["runout_m"] for n in (40, 60))
    assert abs(coarse - fine) / fine < 0.10
    for n, d in fine_grains.items():
        assert d["runout_m"] == pytest.approx(
            _committed(f"r1_a0.5_nx{n}")["deposit"]["runout_m"], rel=1e-9)


@pytest.mark.slow
@pytest.mark.xfail(strict=True, raises=AssertionError, reason=(
    "not met: on grains where the run-out stops growing the flat floor's deposit ends "
    "about a third further than Bui et al.'s measured one (0.61 and 0.60 m against 0.44 m "
    "at L0 / 40 and L0 / 60; the experiment's floor is not known: docs/hybrid.md)"))
def test_granular_collapse_converged_runout_against_bui(fine_grains):
    """a = 0.5 on grains of L0 / 40 and L0 / 60: the deposit ends within 15 % (the bar of the
    comparison) of Bui et al.'s measured one (the end of their final surface)."""
    from hybrid.references import bui2008_final_surface

    measured = bui2008_final_surface()[-1][0]  # m from the back wall
    for d in fine_grains.values():
        assert d["runout_m"] == pytest.approx(measured, rel=0.15)
