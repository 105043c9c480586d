"""The hybrid cases end to end: continuum -> handover -> discrete to rest (H2 / H3).

Bars: the discrete phase reaches rest (E_kin below 1e-4 of its peak) with bounded
energy (E_kin + E_strain + E_contact never more than 1 % of the supply above E(0) + work of
gravity and loads), element count and mass unchanged, H3 wedge within 5 deg of 45 + phi/2;
every output opens in meshio. The default set runs coarse meshes; the full cases are slow.
"""

import json

import meshio
import pytest
from conftest import CASES, BarNotMet, assert_bars, assert_within

from hybrid.errors import StageIncomplete
from hybrid.references import strip_footing_estimates


def _assert_outputs(out, summary):
    """summary.json mirrors the checks; the continuum and discrete XDMF open in meshio (the
    discrete series with every element), the GIF and the figures exist."""
    data = json.loads((out / "summary.json").read_text())
    assert set(data["checks"]) == set(summary["checks"])
    mesh = meshio.read(out / "continuum.xdmf")
    assert mesh.cells[0].data.shape[0] == summary["handover"]["elements"]
    reader = meshio.xdmf.TimeSeriesReader(out / "discrete" / "discrete.xdmf")
    points, cells = reader.read_points_cells()
    assert cells[0].data.shape[0] == summary["discrete"]["elements"]
    assert reader.num_steps >= 2
    t_last, point_data, cell_data = reader.read_data(reader.num_steps - 1)
    assert point_data["displacement"].shape == points.shape
    assert {"sigma_yy", "failed_interfaces", "material"} <= set(cell_data)
    # one colour range and one set of axes for the whole animation
    frames = json.loads((out / "discrete" / "animation.json").read_text())["frames"]
    assert len(frames) == reader.num_steps
    assert all((f["colour_range"], f["xlim"], f["ylim"]) == (frames[0]["colour_range"],
               frames[0]["xlim"], frames[0]["ylim"]) for f in frames)
    movie = json.loads((out / "discrete" / "animation.json").read_text())["movie"]
    for name in (f"discrete/{movie}", "final.png", "discrete_start.png",
                 "handover_plastic_strain.png", "energy.png"):
        assert (out / name).is_file(), name


def _assert_continuum_series(path, times, report):
    """The continuum's series opens in meshio with one frame per time of the case's curve
    (the start and every load step), named as the discrete series."""
    reader = meshio.xdmf.TimeSeriesReader(path)
    reader.read_points_cells()
    assert reader.num_steps == len(times) == report["frames"]
    assert [reader.read_data(k)[0] for k in range(reader.num_steps)] == pytest.approx(
        times, rel=1e-12)
    _, point_data, cell_data = reader.read_data(reader.num_steps - 1)
    assert set(point_data) == {"displacement"}
    assert {"sigma_xx", "sigma_yy", "sigma_zz", "sigma_xy", "plastic_strain", "yielded",
            "material"} == set(cell_data)


def test_retaining_wall_collapse_coarse(case, tmp_path):
    """H3 on 1 m elements (240, 200 of them in the backfill): the wall removed, the backfill runs
    out and comes to rest; energy, rest and conservation at their bars. The wedge's bar (5 deg of
    45 + phi/2) is asserted on the 0.5 and 0.25 m meshes (slow tests): ten elements over the
    wall's height resolve the back of the moving zone to an element, and the docs report
    this mesh's wedge beside theirs."""
    s = case("retaining_wall_collapse").main(out=tmp_path, size=1.0, output_every=500,
                                                progress=False)
    assert_bars(s, except_=("wedge_angle",))
    assert 45.0 < s["discrete"]["wedge_angle_deg"] < 90.0  # a wedge, leaning back from the face
    assert s["discrete"]["stop"] == "rest"
    assert s["discrete"]["runout_m"] > 1.0  # the sand spread in front of the wall
    # the run-out is the continuous deposit's toe: never beyond the farthest element, and at it
    # when no element is flung apart
    farthest = -s["discrete"]["farthest_element_x_m"]
    assert s["discrete"]["runout_m"] <= farthest
    if s["discrete"]["detached_elements"] == 0:
        assert s["discrete"]["runout_m"] == pytest.approx(farthest, abs=1e-12)
    assert s["discrete"]["interfaces_failed"] > 0
    _assert_outputs(tmp_path, s)
    active = s["continuum"]["active"]["translation_m"]
    _assert_continuum_series(tmp_path / "continuum_active.xdmf",
                             [m / active[-1] for m in active],
                             s["continuum"]["series"]["active"])
    for name in ("deformed_mesh", "shear_strain", "plastic_points"):
        assert (tmp_path / f"active_{name}.png").is_file(), name


def test_footing_failure_coarse(case, tmp_path):
    """H2 on a coarse mesh: the softening soil's peak near Vesic's limit load of the peak
    strength (within 10 %: a coarse Q2 mesh, and a peak reached while only the band has
    softened; the formula is no reference for a softening soil, so the case reports it
    without one), the discrete phase loaded, unloaded and at rest with bounded energy,
    elements and mass kept."""
    s = case("footing_failure").main(out=tmp_path, fine=0.15, coarse=0.6, continuum_steps=12,
                                     output_every=500, progress=False)
    assert_bars(s)
    q = s["continuum"]["collapse_pressure_kPa"]
    p = s["parameters"]
    vesic = strip_footing_estimates(p["cohesion"], p["phi"], p["unit_weight"],
                                    p["footing_width"])["Vesic"]
    assert abs(q / vesic - 1.0) < 0.10
    assert s["checks"]["collapse_vs_Vesic"].reference is None  # the soil softens
    assert s["discrete"]["stop"] == "rest"
    assert s["discrete"]["settlement_at_unloading_m"] > 0.05
    assert s["discrete"]["interfaces_failed"] > 0
    _assert_outputs(tmp_path, s)
    # the series covers the loading and the rest runs, to the rest at the end
    reader = meshio.xdmf.TimeSeriesReader(tmp_path / "discrete" / "discrete.xdmf")
    reader.read_points_cells()
    t_first, t_last = reader.read_data(0)[0], reader.read_data(reader.num_steps - 1)[0]
    assert t_last - t_first == pytest.approx(s["discrete"]["time_to_rest_s"], rel=1e-12)
    frames = json.loads((tmp_path / "discrete" / "animation.json").read_text())["frames"]
    assert [f["phase"] for f in frames][::len(frames) - 1] == ["loading", "rest"]
    # the continuum's load steps: the time is the footing pressure, to the handover's
    _assert_continuum_series(tmp_path / "continuum_steps.xdmf",
                             [q for _, q in s["continuum"]["curve"]], s["continuum"]["series"])
    for name in ("deformed_mesh", "shear_strain", "plastic_points"):
        assert (tmp_path / f"continuum_{name}.png").is_file(), name


@pytest.fixture(scope="module")
def h3_meshes(tmp_path_factory):
    """H3 (no expert option) on the default structured 0.5 m grid, refined to 0.25 m, and on
    gmsh's unstructured 0.5 m quadrilaterals, run once for the tests below; each reaches rest
    with its wedge within 5 deg of 45 + phi/2 and the other bars met."""
    from hybrid.case import load_case

    out = tmp_path_factory.mktemp("h3_meshes")
    module = load_case(CASES / "retaining_wall_collapse.py")
    runs = {name: module.main(out=out / name, progress=False, **kw) for name, kw in (
        ("default", {}), ("fine", {"size": 0.25}), ("unstructured", {"structured": False}))}
    for s in runs.values():
        assert_bars(s)
        assert s["checks"]["wedge_angle"].bar is not None
        assert s["discrete"]["stop"] == "rest"
    _assert_outputs(out / "default", runs["default"])
    return {name: s["discrete"] for name, s in runs.items()}


@pytest.mark.slow
def test_retaining_wall_collapse_wedge_meshes(h3_meshes):
    """H3's wedge at 0.1 H on the refined and on the unstructured mesh within 5 deg (the bar
    of the Rankine comparison) of the default mesh's."""
    for other in ("fine", "unstructured"):
        assert abs(h3_meshes[other]["wedge_angle_deg"]
                   - h3_meshes["default"]["wedge_angle_deg"]) <= 5.0, other


@pytest.mark.slow
def test_retaining_wall_collapse_runout_refined(h3_meshes):
    """H3's run-out (the toe of the continuous deposit) on the refined mesh within 10 % of the
    default mesh's (a measure of one dynamic collapse, not a limit load)."""
    default, fine = h3_meshes["default"], h3_meshes["fine"]
    assert abs(fine["runout_m"] / default["runout_m"] - 1.0) <= 0.10


@pytest.mark.slow
@pytest.mark.xfail(strict=True, raises=AssertionError, reason=(
    "on gmsh's unstructured 0.5 m quadrilaterals the continuous deposit ends about a quarter "
    "short of the structured grid's (8.3 against 11.1 m); averaged over nine runs on each mesh "
    "(the backfill up to 0.2 % shorter and longer) about an eighth short, beyond the bar by "
    "less than one standard error (one run is one sample: docs/hybrid.md); refined to 0.25 m "
    "the two mesh types' five-run means agree within the bar (3.9 % apart)"))
def test_retaining_wall_collapse_runout_unstructured(h3_meshes):
    """H3's run-out (the toe of the continuous deposit) on the unstructured 0.5 m
    quadrilaterals within 10 % of the structured grid's (the bar of the refinement study)."""
    default, unstructured = h3_meshes["default"], h3_meshes["unstructured"]
    assert abs(unstructured["runout_m"] / default["runout_m"] - 1.0) <= 0.10


@pytest.mark.slow
def test_footing_failure_full(case, tmp_path):
    """H2 as `make demo` runs it: 1 800 kPa held until 0.5 m of settlement, then rest."""
    s = case("footing_failure").main(out=tmp_path, progress=False)
    assert_bars(s)
    assert s["discrete"]["settlement_at_unloading_m"] >= 0.5
    assert s["discrete"]["stop"] == "rest"
    _assert_outputs(tmp_path, s)


# H2's mesh study (docs/hybrid.md, "Mesh sensitivity"): the default mesh, its refinement and a
# structured mesh of the same size, all Q2 quadrilaterals in the continuum
H2_MESHES = {"unstructured_0.08": {}, "unstructured_0.04": {"fine": 0.04},
             "structured_0.08": {"structured": True}}


@pytest.mark.slow
def test_footing_failure_collapse_load_meshes(case, tmp_path):
    """H2's continuum collapse load on three meshes (gmsh's unstructured quadrilaterals at
    0.08 m and refined to 0.04 m at the footing edge, transfinite structured ones at 0.08 m)
    within 3 % of each other: the project's bar for a limit load on refinement."""
    loads = {}
    for name, mesh in H2_MESHES.items():
        s = case("footing_failure").main(out=tmp_path / name, discrete=False, progress=False,
                                         **mesh)
        assert s["continuum"]["collapse_pressure_kPa"] is not None, name
        loads[name] = s["continuum"]["collapse_pressure_kPa"]
    assert max(loads.values()) / min(loads.values()) - 1.0 < 0.03, loads


@pytest.mark.slow
def test_footing_failure_collapse_load_past_newton_cycles(case, tmp_path):
    """Under load control Newton cycles before H2's collapse on the default mesh 0.1 % wider
    (the ramp stalls) and on the structured mesh refined to 0.04 m in 48 increments (the ramp
    stops short with the settlement running away): a few points flip between the elastic and
    the plastic response. Retried holding them elastic (``continuum_hold_flipping``: an
    equilibrium of the material law itself, or no increment), both reach the collapse
    within 3 % (the bar of a limit load) of the default and the structured 0.08 m meshes'."""
    runs = {"default": {}, "structured": {"structured": True},
            "wider": {"width": 4.8048, "continuum_hold_flipping": True},
            "structured_0.04": {"structured": True, "fine": 0.04, "continuum_steps": 48,
                                "continuum_hold_flipping": True}}
    loads, held = {}, {}
    for name, mesh in runs.items():
        s = case("footing_failure").main(out=tmp_path / name, discrete=False, progress=False,
                                         **mesh)
        loads[name] = s["continuum"]["collapse_pressure_kPa"]
        held[name] = s["continuum"]["held_increments"]
    assert held["wider"] > 0 and held["structured_0.04"] > 0, held  # the retry was needed
    assert max(loads.values()) / min(loads.values()) - 1.0 < 0.03, loads


def test_footing_failure_settlement_control_needs_a_peak(case, tmp_path):
    """Under settlement control the collapse is the peak of the pressure, shown by its fall: a
    path stopped at 5 mm, the pressure still rising, is refused (no handover, a message naming
    the fix)."""
    with pytest.raises(StageIncomplete, match="did not fall 1 % below"):
        case("footing_failure").main(out=tmp_path, fine=0.15, coarse=0.6, continuum_steps=4,
                                     continuum_control="settlement",
                                     continuum_settlement=0.005, discrete=False,
                                     progress=False)


@pytest.mark.slow
def test_footing_failure_settlement_control_collapse(case, tmp_path):
    """H2's collapse load as the peak of the footing's settlement-controlled curve, passed
    and left behind: on the default mesh, the same mesh with the half-width 0.1 % larger (under
    load control Newton stalls there before the collapse) and the structured mesh, all within
    3 % of each other and of the default mesh's load-controlled collapse (the bar of a limit
    load; docs/hybrid.md)."""
    runs = {"default": {}, "wider": {"width": 4.8048}, "structured": {"structured": True}}
    loads = {}
    for name, mesh in runs.items():
        s = case("footing_failure").main(out=tmp_path / name, discrete=False, progress=False,
                                         continuum_control="settlement", **mesh)
        loads[name] = s["continuum"]["collapse_pressure_kPa"]
        assert s["continuum"]["settlement_control"]["final_pressure_kPa"] < 0.99 * loads[name]
    pressure = case("footing_failure").main(out=tmp_path / "pressure", discrete=False,
                                            progress=False)["continuum"]["collapse_pressure_kPa"]
    values = [*loads.values(), pressure]
    assert max(values) / min(values) - 1.0 < 0.03, (loads, pressure)


@pytest.mark.slow
@pytest.mark.xfail(strict=True, raises=AssertionError, reason=(
    "P2 triangles: under load control Newton stalls before the collapse; under settlement "
    "control in 100 increments the peak is 3.5 % below the quadrilaterals' (docs/hybrid.md)"))
def test_footing_failure_collapse_load_triangles(case, tmp_path):
    """H2's collapse load on gmsh's unstructured triangles within 3 % of the quadrilaterals'
    (both 0.08 m at the footing edge), each the peak of its settlement-controlled curve
    (triangles in 100 increments: in 24 their path stalls): the cell shape should not move a
    limit load."""
    tri = case("footing_failure").main(out=tmp_path / "tri", cells="triangle", discrete=False,
                                       continuum_control="settlement", continuum_steps=100,
                                       progress=False)
    quad = case("footing_failure").main(out=tmp_path / "quad", discrete=False,
                                        continuum_control="settlement", progress=False)
    q_tri, q_quad = (s["continuum"]["collapse_pressure_kPa"] for s in (tri, quad))
    assert abs(q_tri / q_quad - 1.0) < 0.03


@pytest.mark.slow
@pytest.mark.xfail(strict=True, raises=StageIncomplete, reason=(
    "the structured mesh refined to 0.04 m: under load control Newton stalls near 900 kPa "
    "before the settlement runs away (with the default 24 increments; with 48 it stops at "
    "about 1 000 kPa, a stall that Newton's retry of cycling increments passes to a collapse "
    "within 3 %; under settlement control it stalls near 900 kPa too, docs/hybrid.md)"))
def test_footing_failure_collapse_load_structured_refined(case, tmp_path):
    """H2's collapse load on the structured mesh and its refinement (0.08 and 0.04 m at the
    footing edge) within 3 % of each other: the bar of a limit load on refinement."""
    loads = [case("footing_failure").main(out=tmp_path / f"s{fine}", structured=True, fine=fine,
                                          discrete=False, progress=False)
             ["continuum"]["collapse_pressure_kPa"] for fine in (0.04, 0.08)]
    assert max(loads) / min(loads) - 1.0 < 0.03, loads


@pytest.fixture(scope="module")
def h2_refined(tmp_path_factory):
    """H2 to rest on the default mesh and its refinement (0.08 and 0.04 m at the footing
    edge), run once for the two tests below; both reach rest within their bars."""
    from hybrid.case import load_case

    h2 = load_case(CASES / "footing_failure.py")
    out = tmp_path_factory.mktemp("h2_refined")
    runs = [h2.main(out=out / name, output_every=0, progress=False, **mesh)
            for name, mesh in (("fine", {"fine": 0.04}), ("default", {}))]
    for s in runs:
        assert_bars(s)
        assert s["discrete"]["stop"] == "rest"
    return runs


@pytest.fixture(scope="module")
def h2_punch_refined(tmp_path_factory):
    """H2 under a displacement-controlled punch (``control=punch``, 0.25 m/s) to rest on the
    default mesh and its refinement, run once for the two tests below: both at rest with
    bounded energy, elements and mass kept, let go at the target settlement."""
    from hybrid.case import load_case

    h2 = load_case(CASES / "footing_failure.py")
    out = tmp_path_factory.mktemp("h2_punch_refined")
    runs = [h2.main(out=out / name, output_every=0, progress=False, control="punch", **mesh)
            for name, mesh in (("fine", {"fine": 0.04}), ("default", {}))]
    for s in runs:
        assert_bars(s)
        assert s["discrete"]["stop"] == "rest"
        assert s["discrete"]["settlement_at_unloading_m"] >= s["parameters"]["target_settlement"]
    return runs


@pytest.mark.slow
def test_footing_punch_refined(h2_punch_refined):
    """The punch's measured figures on the default mesh and its refinement: the mean bearing
    pressure over the push and the heave at rest within 10 % (the bar of the load-controlled
    runs: one mechanism through a band of failed bonds that follows the mesh, not a limit
    load)."""
    for measure in ("mean_bearing_pressure_kpa", "max_heave_beside_footing_m"):
        _discrete_change(h2_punch_refined, measure)


@pytest.mark.slow
@pytest.mark.xfail(strict=True, raises=BarNotMet, reason=(
    "not met: the footing rises 0.035 m on 0.04 m against 0.046 m on 0.08 m as its load comes "
    "off (docs/hybrid.md); the settlement before it is prescribed (0.5 m)"))
def test_footing_punch_rise_refined(h2_punch_refined):
    """The one settlement the punch measures rather than prescribes, the rise as the load
    comes off (settlement at unloading minus final), within 10 % on the two meshes."""
    a, b = (s["discrete"]["settlement_at_unloading_m"] - s["discrete"]["final_settlement_m"]
            for s in h2_punch_refined)
    assert_within(a, b, 0.10, "rise as the load comes off on 0.04 m against 0.08 m")


def _discrete_change(runs, measure: str) -> None:
    """``measure`` within 10 % between the refined and the default mesh. 10 %: the discrete
    phase follows one dynamic punch through a band of failed bonds whose path follows the
    mesh, a measure of the same mechanism, not a limit load (3 %)."""
    a, b = (s["discrete"][measure] for s in runs)
    assert_within(a, b, 0.10, f"{measure} on 0.04 m against 0.08 m")


@pytest.mark.slow
def test_footing_failure_heave_refined(h2_refined):
    """The largest heave beside the footing at rest on the default mesh and its refinement."""
    _discrete_change(h2_refined, "max_heave_beside_footing_m")


@pytest.mark.slow
@pytest.mark.xfail(strict=True, raises=BarNotMet, reason=(
    "not met: the footing settles 0.608 m (since the handover) on 0.04 m against 0.533 m on "
    "0.08 m: 0.50 m under load on both, then 0.11 against 0.03 m more after the load came off "
    "(docs/hybrid.md)"))
def test_footing_failure_settlement_refined(h2_refined):
    """The final settlement at rest on the default mesh and its refinement."""
    _discrete_change(h2_refined, "final_settlement_m")
