"""Carsington Dam, Ch. 725, continuum phase: section, lifts, construction, F."""

import json

import meshio
import numpy as np
import pytest
from conftest import CASES, BarNotMet, assert_bars, assert_within

from hybrid import references
from hybrid.continuum.staging import lift_groups, split_into_lifts
from hybrid.geometry import build_mesh

GROUPS = {"foundation", "yellow_clay", "core", "zone_I", "zone_II", "berm"}
BOUNDARIES = {"base", "left", "right", "crest", "surface"}


def _shoelace(points) -> float:
    p = np.asarray(points, dtype=float)
    return 0.5 * abs(np.sum(p[:, 0] * np.roll(p[:, 1], -1) - np.roll(p[:, 0], -1) * p[:, 1]))


def _group_area(mesh, name: str) -> float:
    x, cells = mesh.cell_vertices()
    area = sum(_shoelace(x[c]) for c in cells[mesh.cells(name)])
    assert mesh.group_area(name) == pytest.approx(area, rel=1e-12)
    return area


def test_section_groups_areas_and_lifts(case):
    cars = case("carsington")
    sm = cars.section_module()
    section = sm.Section()
    mesh = build_mesh(sm.build, size=15.0)
    assert mesh.cell_type == "quadrilateral"
    assert set(mesh.cell_groups) == GROUPS
    assert BOUNDARIES <= set(mesh.facet_groups)
    # the regions are exact polygons: the core (with its boot in the key trench) and the
    # yellow clay (a layer of constant vertical thickness) have their outline's area
    assert _group_area(mesh, "core") == pytest.approx(_shoelace(section.core_outline()),
                                                      rel=1e-9)
    assert _group_area(mesh, "yellow_clay") == pytest.approx(
        section.yellow_clay_thickness * section.yellow_clay_length, rel=1e-9)
    # the key trench: the core reaches trench_depth below the foundation level
    x, cells = mesh.cell_vertices()
    core_y = x[cells[mesh.cells("core")], 1]
    assert core_y.min() == pytest.approx(section.foundation_level - section.trench_depth)
    assert core_y.max() == pytest.approx(section.crest_level)

    tops = sm.lift_tops(section.crest_level, section.berm_top, section.lifts)
    # the thesis's six stages: the foundation, then five lifts (the berm top, the history
    # levels 182, 190 and 198 m OD, the crest)
    assert tops == [175.6, 182.0, 190.0, 198.0, 200.5]
    assert sm.lift_tops(lifts=1) == [section.crest_level]
    assert sm.lift_tops(lifts=3) == [175.6, 188.05, 200.5]
    # the fill above a level in parts: the fill level of a collapse found more finely, the
    # lift tops kept
    assert sm.lift_tops(parts_above=198.0) == [175.6, 182.0, 190.0, 198.0, 198.5, 199.0,
                                               199.5, 200.0, 200.5]
    # equal parts in each lift: 4 x 1 m from 194 to 198, 2 x 1.25 m from 198 to 200.5
    assert sm.lift_tops(parts_above=194.0, part_height=1.25) == [
        175.6, 182.0, 190.0, 194.0, 195.0, 196.0, 197.0, 198.0, 199.25, 200.5]
    for bad in ({"lifts": 1, "parts_above": 190.0}, {"parts_above": 170.0},
                {"parts_above": 200.5}, {"parts_above": 190.0, "part_height": 0.0}):
        with pytest.raises(ValueError, match="parts_above"):
            sm.lift_tops(**bad)
    staged = split_into_lifts(mesh, cars.EMBANKMENT, tops)
    assert sum(len(staged.cells(g)) for g in staged.cell_groups) == mesh.num_owned_cells
    bottom = section.foundation_level - section.trench_depth
    for k, top in enumerate(tops, start=1):
        groups = lift_groups(staged, k)
        assert {f"core:{k}", f"zone_I:{k}", f"zone_II:{k}"} <= set(groups)
        assert ("berm:1" in groups) == (k == 1)  # the berm is complete in the first lift
        # no cell straddles a lift top
        y = x[cells[np.concatenate([staged.cells(g) for g in groups])], 1]
        assert y.min() >= bottom - 1e-9 and y.max() <= top + 1e-9
        bottom = top


# the thesis's element counts by zone (6.2.6; 1 061 in all; its berm is in Zone II)
THESIS_ELEMENTS = {"foundation": 441, "zone_I": 101, "zone_II": 319, "yellow_clay": 18,
                   "core": 182}


def test_node_a_candidates_and_published_bands(case):
    """The places node A may be lie in the core: on its axis at the foundation level, the
    top of the boot and the berm top, and on its upstream face (an outline vertex) at the top
    of the boot; the default node A is one of them. The first published bands are at the
    levels the case reports node A's displacement at."""
    cars = case("carsington")
    section = cars.section_module().Section()
    places = section.node_a_candidates()
    boot_top = section.foundation_level + section.boot_height
    assert places["axis_foundation_level"] == (0.0, section.foundation_level)
    assert places["axis_boot_top"] == (0.0, boot_top)
    assert places["axis_berm_top"] == (0.0, section.berm_top)
    assert places["upstream_face_boot_top"] == pytest.approx(section.core_outline()[1])
    defaults = cars.Parameters()
    assert (defaults.node_a_x, defaults.node_a_y) in places.values()
    bands = references.CARSINGTON_CORE_DISPLACEMENT
    assert [(b.level_low, b.level_high) for b in bands[:2]] == [
        (z, z) for z in references.CARSINGTON_REPORT_LEVELS]
    assert all(b.low < b.high for b in bands)


def test_zone_areas_against_the_thesis_element_counts(case):
    """Zone area / thesis element count: the element area each zone of the thesis's mesh
    would have if our zones had its zones' areas. The thesis refined the core, the yellow
    clay and the upstream Zone II (6.2.6), so the core comes out finest, Zone II (its
    downstream part coarse) coarser, Zone I coarser still. Its mesh is regular (refinement
    carried across a zone's range of coordinates): the yellow clay is one row of elements as
    wide as the core's (square) ones, so its length is 18 x the core's element width; ours
    is within 5 % of that (the former 100 m layer was 2.8 times it)."""
    cars = case("carsington")
    sm = cars.section_module()
    mesh = build_mesh(sm.build, size=15.0)
    area = {name: _group_area(mesh, name) for name in THESIS_ELEMENTS}
    area["zone_II"] += _group_area(mesh, "berm")
    per_element = {name: area[name] / n for name, n in THESIS_ELEMENTS.items()}
    assert (per_element["core"] < per_element["zone_II"] < per_element["zone_I"]
            < per_element["foundation"])
    core_width = np.sqrt(per_element["core"])
    length = area["yellow_clay"] / sm.Section().yellow_clay_thickness
    assert length / THESIS_ELEMENTS["yellow_clay"] == pytest.approx(core_width, rel=0.05)
    long_layer = build_mesh(sm.build, size=15.0, yellow_clay_length=None)
    long = _group_area(long_layer, "yellow_clay") / sm.Section().yellow_clay_thickness
    assert long / THESIS_ELEMENTS["yellow_clay"] > 2.5 * core_width


def test_thesis_sized_mesh(builder):
    """The default size gives about the thesis's 1 061 elements (within 30 %), all
    quadrilaterals."""
    mesh = build_mesh(builder("carsington"))
    assert mesh.cell_type == "quadrilateral"
    assert 700 <= mesh.comm.allreduce(mesh.num_owned_cells) <= 1300


def _check_run(summary: dict, tolerance: float) -> None:
    checks = summary["checks"]
    for key in ("far_field_sigma_v", "far_field_sigma_h", "max_stress_in_unplaced_lifts"):
        assert checks[key].passed, key
    stages = summary["construction"]["stages"]
    # every lift but possibly the last reaches equilibrium; a failing lift is the collapse
    assert all(st["completed"] for st in stages[:-1])
    assert stages[0]["completed"]
    if not summary["construction"]["completed"]:
        last = stages[-1]
        bottom = stages[-2]["top_m_OD"] if len(stages) > 1 else 164.5
        assert bottom <= last["fill_level_m_OD"] < last["top_m_OD"]
        assert 0.0 <= last["weight_placed"] < 1.0
        # the stop says whether the displacement ran away, from the path it records
        collapse = summary["construction"]["collapsing_lift"]
        assert last["path"][0] == [0.0, 0.0] and last["path"][-1][0] == last["weight_placed"]
        assert collapse["runaway"] == (collapse["runaway_ratio"] >= 10.0)
    # F after each complete lift: finite, above 1 (it stood), falling as the dam rises
    fos = [st["factor_of_safety"] for st in stages if "factor_of_safety" in st]
    assert fos and all(np.isfinite(fos)) and fos[0] > 1.0
    assert all(b <= a + tolerance for a, b in zip(fos, fos[1:]))
    assert summary["factor_of_safety"]["F"] == fos[-1]
    # the fill level carried is the top of the last complete lift; node A's displacement is
    # reported at the levels of complete lifts only (none from a part-loaded lift)
    complete = [st for st in stages if st["completed"]]
    assert summary["construction"]["fill_level_m_od"] == complete[-1]["top_m_OD"]
    core = summary["core_displacement_mm"]
    assert [level for level, _ in core["by_fill_level"]] == [st["top_m_OD"] for st in complete]
    for level in ("198", "200.5"):
        reached = any(st["top_m_OD"] == float(level) for st in complete)
        assert (core[level] is not None) == reached, level
    # the places node A may be, measured after the same lifts; the default is one of them
    assert core["node_A_m"] in [c["point_m"] for c in core["candidates"].values()]
    for candidate in core["candidates"].values():
        assert [z for z, _ in candidate["by_fill_level"]] == [st["top_m_OD"] for st in complete]
        if candidate["point_m"] == core["node_A_m"]:
            assert candidate["by_fill_level"] == core["by_fill_level"]


def test_carsington_smoke(case, tmp_path):
    """Coarse mesh: gravity, the lifts (to the crest or to collapse), F after each lift, then
    a few hundred steps of the discrete phase (elements and mass kept, energy bounded, the
    time series opens in meshio)."""
    tolerance = 0.05
    summary = case("carsington").main(out=tmp_path, size=15.0, layer_size=3.0,
                                      min_increment=0.01, fos_step=0.2,
                                      fos_tolerance=tolerance, discrete_time=0.4, frames=2,
                                      progress=False)
    _check_run(summary, tolerance)
    d = summary["discrete"]
    assert d["elements"] == summary["handover"]["elements"] > 0
    for name in ("elements_conserved", "mass_conserved", "energy_excess_over_sources"):
        assert summary["checks"][name].passed, name
    # stopped by its time limit, not at rest: the rest check fails and the movements are not
    # set beside the observed ones (a slide still moving is no final configuration)
    assert d["stop"] == "time" and not summary["checks"]["rest_kinetic_ratio"].passed
    for name, (_, source) in references.CARSINGTON_POST_FAILURE.items():
        check = summary["checks"][name]
        assert check.reference is None and source in check.source, name
    assert summary["checks"]["crest_drop"].computed == d["crest_drop_m"]
    # where and how the bonds began to fail: every failed interface counted by mode, no set
    # failing before the section as a whole
    onset = d["failure_onset"]
    assert onset["anywhere"]["failed"] == d["interfaces_failed"]
    assert sum(onset["anywhere"]["failed_by_mode"].values()) == d["interfaces_failed"]
    first = onset["anywhere"]["first_failure_s"]
    assert d["interfaces_failed"] > 0 and first is not None
    face = d["slip_along_core_upstream_face"]  # the core's upstream face against Zone I
    assert face["interfaces"] > 0 and face["length_m"] > 0.0
    assert face["slipped_interfaces"] <= face["interfaces"]
    assert face["slipped_length_m"] <= face["length_m"] * (1.0 + 1e-12)
    at_first = d["first_failures"]
    assert at_first["time_s"] == first
    assert sum(onset["anywhere"]["first_failure_modes"].values()) == at_first["interfaces"]
    assert at_first["interfaces"] >= max(at_first["crest_top"], at_first["yellow_clay"],
                                         at_first["elsewhere"]) > 0
    for name, o in onset.items():
        assert o["failed"] == sum(o["failed_by_mode"].values()) <= d["interfaces_failed"], name
        assert (o["first_failure_s"] is None) == (o["failed"] == 0), name
        if o["failed"]:
            assert 0.0 < first <= o["first_failure_s"] <= d["time_s"], name
    assert summary["checks"]["upstream_toe_movement"].computed == d["toe_runout_m"]
    series = meshio.xdmf.TimeSeriesReader(tmp_path / "discrete" / "discrete.xdmf")
    points, cells = series.read_points_cells()
    assert cells[0].data.shape[0] == d["elements"]
    saved = json.loads((tmp_path / "summary.json").read_text())
    assert saved["mesh"]["cells"] == summary["mesh"]["cells"]
    written = meshio.read(tmp_path / "continuum.xdmf")
    assert sum(len(c.data) for c in written.cells) == summary["mesh"]["cells"]
    for name in ("end_of_construction_sigma_yy.png", "end_of_construction_yielded.png",
                 "end_of_construction_displacement_vectors.png",
                 "end_of_construction_core_profiles.png", "fos_plastic_strain.png",
                 "core_displacement_vs_fill_level.png"):
        assert (tmp_path / name).is_file(), name


@pytest.mark.slow
def test_carsington_thesis_mesh(case, tmp_path):
    """The ~1 000-cell run of docs/carsington.md (Table 6.3 strengths)."""
    tolerance = 0.01
    summary = case("carsington").main(out=tmp_path, fos_tolerance=tolerance, progress=False)
    assert 700 <= summary["mesh"]["cells"] <= 1300
    _check_run(summary, tolerance)
    # bars of the discrete phase (the thesis's description, 6.3.2): at rest, the slip surface
    # (failed interfaces that slipped >= 0.1 m) through the yellow clay, the core's boot and
    # the core above it, the shoulder upstream; failure begins at the crest's top (bonds
    # failing in tension) or in the yellow clay. The crest cracks, but no crack from it opens
    # 0.1 m during the slide (docs/carsington.md: in the softening analysis on the finest mesh
    # only, and with softening in the discrete phase)
    d = summary["discrete"]
    assert d["stop"] == "rest"
    for name in ("failure_begins_at_crest_or_in_yellow_clay", "crest_cracks_in_tension",
                 "slip_surface_through_yellow_clay",
                 "slip_surface_through_boot", "slip_surface_through_core",
                 "shoulder_moves_upstream", "energy_excess_over_sources",
                 "elements_conserved", "mass_conserved"):
        assert summary["checks"][name].passed, name
    assert d["phase_wall_time_s"] + summary["continuum_wall_time_s"] < 15 * 60


@pytest.mark.slow
def test_carsington_two_meshes(case, tmp_path):
    """The fill level carried and node A's displacement on the default mesh (size 6) and a
    finer one (size 4.5): the same lift is the last carried, and node A's displacement after
    the lifts below the collapse agrees within 15 % (the bar: half the spread of the
    published analyses it is compared with, 100-150 mm (Chen) against 150 mm (thesis) at
    198 m OD, so that the mesh cannot change the comparison)."""
    runs = [case("carsington").main(out=tmp_path / f"size{size:g}", size=size, safety=False,
                                    discrete_time=0.0, progress=False) for size in (6.0, 4.5)]
    levels = [r["construction"]["fill_level_m_od"] for r in runs]
    assert levels[0] == levels[1]
    coarse, fine = (dict(map(tuple, r["core_displacement_mm"]["by_fill_level"])) for r in runs)
    for level in (175.6, 182.0, 190.0):
        assert fine[level] == pytest.approx(coarse[level], rel=0.15), level


@pytest.mark.slow
@pytest.mark.xfail(strict=True, raises=BarNotMet, reason=(
    "not met: the 4.5 m mesh carries lift 4 whole (198 m OD) and collapses in lift 5, the 3 m "
    "mesh collapses in lift 4 with 93 % of its weight carried (190 m OD carried): the collapse "
    "lies close to the top of lift 4 and falls below it on refinement (docs/carsington.md)"))
def test_carsington_fill_level_refined(case, tmp_path):
    """The fill level carried (in whole lifts, Table 6.3) the same on the 4.5 m mesh and the
    finer 3 m mesh: a lift top is the resolution of the figure, so no tolerance."""
    levels = [case("carsington").main(out=tmp_path / f"size{size:g}", size=size, safety=False,
                                      discrete_time=0.0, progress=False)["construction"][
                                          "fill_level_m_od"] for size in (4.5, 3.0)]
    assert_within(levels[1], levels[0], 0.0, "fill level carried on the 3 m mesh against 4.5 m")


@pytest.mark.slow
def test_carsington_collapse_level_in_parts_refined(case, tmp_path):
    """The fill level of the collapse (Table 6.3) with the fill above 194 m OD placed in 0.5 m
    parts, on the 3 and 2 m meshes: both carry the same part and fail in the next, and the
    levels at the weight carried in it agree within half a part (0.25 m: half the placement's
    resolution). docs/carsington.md: 196.34 and 196.45 m OD; the 6 and 4.5 m meshes
    overstate it."""
    runs = [case("carsington").main(out=tmp_path / f"size{size:g}", size=size, safety=False,
                                    discrete_time=0.0, progress=False, parts_above=194.0,
                                    part_height=0.5)["construction"] for size in (3.0, 2.0)]
    assert runs[0]["fill_level_m_od"] == runs[1]["fill_level_m_od"]
    levels = [r["stages"][-1]["fill_level_m_OD"] for r in runs]
    assert abs(levels[1] - levels[0]) <= 0.25, levels


@pytest.mark.slow
@pytest.mark.parametrize("length", [20.0, 30.0])
def test_carsington_yellow_clay_length_refined(case, tmp_path, length):
    """The fill level carried (Table 6.3, the fill above 194 m OD in 0.5 m parts) with the
    yellow clay 20 or 30 m long instead of 36 m, the same on the 3 and 2 m meshes: a part's
    top is the resolution of the figure, so no tolerance. docs/carsington.md, Sensitivity:
    with 20 m the section stands to the design crest, with 30 m it fails in the last part but
    one, with 36 m at 196.3-196.5 m OD (``test_carsington_collapse_level_in_parts_refined``)."""
    runs = [case("carsington").main(
        out=tmp_path / f"size{size:g}", size=size, safety=False, discrete_time=0.0,
        progress=False, parts_above=194.0, part_height=0.5, yellow_clay_length=length)[
            "construction"] for size in (3.0, 2.0)]
    levels = [r["fill_level_m_od"] for r in runs]
    assert levels[0] == levels[1], levels
    # 20 m: every part placed on both meshes; 30 m: a collapse before the crest on both
    assert [r["completed"] for r in runs] == [length == 20.0] * 2, levels


def test_carsington_softening_coarse(case, tmp_path):
    """Beyond the thesis, coarse mesh: with the strengths falling to residual the dam carries
    no more fill than with the thesis's perfectly plastic strengths (a residual is never above
    its peak), and the discrete phase runs to rest with no expert option (the softened bonds
    fail and carry the residual strength as contacts): slip through the yellow clay
    and the boot, the upstream shoulder moving upstream, energy bounded, elements and mass
    kept."""
    coarse = dict(size=15.0, layer_size=3.0, min_increment=0.01, safety=False, frames=2,
                  progress=False)
    thesis = case("carsington").main(out=tmp_path / "thesis", discrete_time=0.0, **coarse)
    soft = case("carsington").main(out=tmp_path / "soft", softening=True, **coarse)
    carried = soft["construction"]["fill_level_m_od"]
    assert carried <= thesis["construction"]["fill_level_m_od"]
    assert soft["discrete"]["stop"] == "rest"
    # the observed movements' bar is asserted on the shipped meshes (slow tests), not on this
    # coarse one; a crack from the crest open during the slide is a result the docs report per
    # mesh (found on none), not a bar
    assert_bars(soft, except_=("upstream_toe_movement", "crest_drop", "crack_at_crest"))
    for name in ("slip_surface_through_yellow_clay", "slip_surface_through_boot",
                 "shoulder_moves_upstream", "energy_excess_over_sources"):
        assert soft["checks"][name].passed, name


def _slid_to_rest(run: dict) -> None:
    """A Carsington run's discrete phase came to rest with the slip surface through the
    yellow clay, the boot and the core, the upstream shoulder moving upstream, energy
    bounded, elements and mass kept, and its toe the front of the whole mass."""
    assert run["discrete"]["stop"] == "rest"
    assert run["discrete"]["toe_detached_elements"] == 0  # the toe: the whole mass's front
    for name in ("slip_surface_through_yellow_clay",
                 "slip_surface_through_boot", "slip_surface_through_core",
                 "shoulder_moves_upstream", "energy_excess_over_sources",
                 "elements_conserved", "mass_conserved"):
        assert run["checks"][name].passed, name


@pytest.fixture(scope="module")
def softening_meshes(tmp_path_factory):
    """Beyond the thesis: the softening analysis on the 4, 3 and 2.5 m meshes of
    docs/carsington.md (its finer ones take longer), run once for the tests below; on each
    it collapses in the same lift, comes to rest with the slip surface through the yellow
    clay, the boot and the core, the upstream shoulder moving upstream, energy bounded,
    elements and mass kept (a crack from the crest open during the slide is a result
    docs/carsington.md reports per mesh, not a bar here)."""
    from hybrid.case import load_case

    cars = load_case(CASES / "carsington.py")
    out = tmp_path_factory.mktemp("carsington_softening")
    runs = [cars.main(out=out / f"size{size:g}", size=size, softening=True, safety=False,
                      frames=0, progress=False) for size in (4.0, 3.0, 2.5)]
    assert len({r["construction"]["fill_level_m_od"] for r in runs}) == 1
    for r in runs:
        _slid_to_rest(r)
    return cars, runs


# the most a post-failure movement may change from one mesh to the next [-]: half the bar on the
# observed movements, so that the mesh cannot decide the comparison
MESH_CHANGE = 0.15


def _converged(runs, key: str) -> None:
    """``key`` of the discrete phase within MESH_CHANGE from each mesh to the next finer."""
    for coarse, fine in zip(runs, runs[1:]):
        assert_within(fine["discrete"][key], coarse["discrete"][key], MESH_CHANGE,
                      f"{key} on the finer mesh against the coarser")


def _observed(cars, runs, name: str) -> None:
    """``name`` within the case's bar of the observed value on every mesh."""
    for r in runs:
        check = r["checks"][name]
        assert check.bar == cars.OBSERVED_BAR and check.reference is not None
        assert_within(check.computed, check.reference, check.bar, f"{name} against observed")


@pytest.mark.slow
def test_carsington_softening_crest_drop_three_meshes(softening_meshes):
    """The softening analysis's crest drop within 30 % of the observed 10 m (the case's bar:
    the observations are approximate, 30 % reproduces the slide's size, not its detail) on
    the three meshes, and within 15 % from each to the next."""
    cars, runs = softening_meshes
    _observed(cars, runs, "crest_drop")
    _converged(runs, "crest_drop_m")


@pytest.mark.slow
@pytest.mark.xfail(strict=True, raises=BarNotMet, reason=(
    "not met: the upstream toe advances 14.02, 14.49 and 8.38 m on the 4, 3 and 2.5 m meshes, "
    "the 2.5 m mesh's just beyond 30 % of the observed 12 m, and 73 % apart from the 3 to the "
    "2.5 m mesh, beyond the 15 % mesh bar; five runs on each mesh, the yellow clay 35.94 to "
    "36.06 m long, put the 2.5 m mesh's toe (7.63 to 8.55 m) apart from the 3 m mesh's (12.89 "
    "to 14.49 m): the mesh's, not one run's chance (docs/carsington.md)"))
def test_carsington_softening_toe_three_meshes(softening_meshes):
    """The softening analysis's upstream toe advance (the upstream end of the embankment's
    continuous mass, at rest against the start) within 30 % of the observed 11-13 m on the
    three meshes, and within 15 % from each to the next: a comparison the element size does
    not decide."""
    cars, runs = softening_meshes
    _observed(cars, runs, "upstream_toe_movement")
    _converged(runs, "toe_runout_m")


@pytest.fixture(scope="module")
def design_height_meshes(tmp_path_factory):
    """From the design height, as the thesis's discrete run started: with the yellow clay 25 m
    long the section carries the fill to the crest (Table 6.3, the fill above 194 m OD in
    0.5 m parts) on the 4 and 3 m meshes, and the discrete phase with softening runs to rest
    on each with the slip surface through the yellow clay, the boot and the core, the
    upstream shoulder moving upstream, energy bounded, elements and mass kept
    (docs/carsington.md: the 2 m mesh too)."""
    from hybrid.case import load_case

    cars = load_case(CASES / "carsington.py")
    out = tmp_path_factory.mktemp("carsington_design_height")
    runs = [cars.main(out=out / f"size{size:g}", size=size, yellow_clay_length=25.0,
                      parts_above=194.0, part_height=0.5, discrete_softening=True,
                      safety=False, frames=0, progress=False) for size in (4.0, 3.0)]
    for r in runs:
        assert r["construction"]["completed"]
        assert r["construction"]["fill_level_m_od"] == 200.5
        _slid_to_rest(r)
    return cars, runs


@pytest.mark.slow
def test_carsington_design_height_crack_at_crest(design_height_meshes):
    """Thesis 6.3.2: failure begins at the top of the dam or within the yellow clay, and a
    crack opens at the crest. From the design height, on both meshes: the first splitting
    check that fails a bond fails one in the yellow clay or at the crest's top (with others
    elsewhere), the crest's first failed bonds fail in tension, and during the slide a failed
    interface joined to the crest's top stands open by at least 0.1 m (``CrackWatch``: a
    crack, not a slip surface sliding closed)."""
    _, runs = design_height_meshes
    for r in runs:
        for name in ("failure_begins_at_crest_or_in_yellow_clay", "crest_cracks_in_tension",
                     "crack_at_crest"):
            assert r["checks"][name].passed, name


@pytest.mark.slow
@pytest.mark.xfail(strict=True, raises=BarNotMet, reason=(
    "not met: from the design height the upstream toe advances 2.35 and 7.15 m on the 4 and "
    "3 m meshes (observed 11-13 m), the crest drops 6.86 and 7.48 m (observed about 10 m): "
    "the toe short of the observed slide and not converged (docs/carsington.md)"))
def test_carsington_design_height_movements_two_meshes(design_height_meshes):
    """From the design height: the upstream toe's advance and the crest drop within the
    case's bar (30 %) of the observed 12 and 10 m on both meshes, and within 15 % from the
    4 to the 3 m mesh. The section is not the published one (the yellow clay's length is an
    assumption), so the runs' own checks set no reference: the observed values are read
    from ``references``."""
    cars, runs = design_height_meshes
    for key, observed in (("toe_runout_m", "upstream_toe_movement"),
                          ("crest_drop_m", "crest_drop")):
        for r in runs:
            assert_within(r["discrete"][key], references.CARSINGTON_POST_FAILURE[observed][0],
                          cars.OBSERVED_BAR, f"{key} against observed")
        _converged(runs, key)
