"""Carsington Dam, Ch. 725 (thesis chapter 6): staged construction, F, post-failure run.

Objective
    The thesis's real dam, the 1984 Carsington failure: the six-stage continuum analysis with the
    Table 6.3 strengths (fill level carried in equilibrium, the core's horizontal displacement at
    node A against fill level, yielded zone, stresses), strength-reduction factors of safety, then
    the discrete post-failure run to rest, beside the thesis's, published and observed values.
Problem
    Ch. 725 rebuilt from the thesis (``meshes/carsington.py``; sources and assumptions in
    docs/carsington.md): a 36 m embankment on mudstone, a clay core with an upstream boot in a
    3 m key trench, Zone I and II shoulders, an upstream berm (as Zone II), 1.5 m of yellow
    clay upstream of the boot. Undrained total stress, Table 6.3, psi = 0, no tension in the
    fill and the clays (thesis 6.3.1.1). Beyond the thesis (``softening``): the strengths fall
    to residual over a slip ``softening_displacement``, the fill to c = 0 and Table 6.2's
    phi_r, the phi = 0 clays to c_u tan(phi_r') / tan(phi') (the drained ratio, assumed to
    hold undrained), and a failed bond carries that residual strength (in the clays the
    residual c_u on any normal stress, as the undrained analysis has it); with
    ``discrete_softening`` only in the discrete phase (the dam built at Table 6.3's peak
    strengths, the failed mass softening once it moves). No analysis sets an
    expert option of the discrete phase.
Set-up
    Base fixed, sides on vertical rollers. Stage 1: gravity on the foundation (key trench open),
    displacements zeroed. Stages 2-6: five lifts (``lift_tops``) placed stress-free, their
    weight ramped in (``build_in_lifts``), to the crest or to the first lift whose full weight
    finds no equilibrium (the collapse: the fill level carried is the last complete lift's top;
    ``parts_above`` places the fill above a level in parts; whether the displacement ran away is
    in ``collapsing_lift``). After each complete lift: node A's
    horizontal displacement (``node_a_x``, ``node_a_y``; also ``Section.node_a_candidates``) and
    F by strength reduction. Discrete phase: the end of construction, or the last complete lift
    with the collapsing one placed whole, handed over (every bond may fail where its strength
    is exceeded, the foundation held) and run to rest. No mass damping (``mass_damping`` = 0): it
    would drag every element as through a viscous fluid (alpha v / g of its weight, at 1 m/s
    and the thesis's alpha = 3 /s a third of it), so the slide's energy goes only into plastic
    work, friction and contact damping; the thesis's 3 /s and 0.5 /s are reported beside it
    (docs/carsington.md).
Verification (asserted in ``tests/test_carsington.py``)
    * every lift before a collapsing one reaches equilibrium (Newton to 1e-8);
    * no stress in fill not yet placed, after every lift (exactly zero);
    * far-field foundation after gravity: sigma_v = -gamma z, sigma_h = K0 sigma_v (1 %);
    * F > 1 after the first lift and F falling as the dam rises;
    * the fill level carried and node A's displacement agree on two meshes (6 and 4.5 m; on
      3 and 2 m meshes lift 4 collapses near its top instead: docs/carsington.md);
    * the discrete phase as the thesis describes it (6.3.2): failure beginning at the crest's
      top or in the yellow clay (the first splitting check that fails a bond fails one there:
      ``first_failures``, from the time recorded for each failed interface; how many it fails
      there and elsewhere is reported, and when each zone's first bond failed:
      ``failure_onset``), the crest's first failed bonds failing in tension; at rest,
      how much of the core's upstream face against Zone I has slipped (reported:
      ``slip_along_core_upstream_face``), the slip surface
      through the yellow clay, the boot and the core above it, the upstream shoulder moving
      upstream, energy bounded, elements and mass kept; a crack from the crest down (failed
      interfaces open >= ``slip_min`` joined to the crest, at any check during the slide:
      ``CrackWatch``; the thesis's cracks are the white spaces of its Figure 6.21) is checked
      and reported, with the widest opening at the crest during the slide beside the crack
      surveyed on the dam (50-130 mm) and the crack still open at rest;
    * the post-failure movements at rest against the observed ones (12 m, 10 m) with a bar of
      30 % (``OBSERVED_BAR``), on the modelled dam's section and strengths whatever the
      analysis (the collapse level is reported beside them): the upstream toe's advance (the
      upstream end of the embankment's continuous mass, ``deposit``, at rest against the
      start; the toe as a place, as surveyed, not the node first at the toe, which the
      fragmented berm can leave behind) and the crest drop (the crest nodes' mean
      settlement). The softening analysis meets the crest-drop bar on eight meshes from 8 to
      1.5 m, within 15 % from one to the next in every step; its toe advance is not
      converged (from one mesh to the next it moves by up to 91 %); the thesis's set-up moves
      far less (docs/carsington.md says why).
    Beside published values, no bar (docs/carsington.md): fill level (thesis: the design crest;
    observed: the slip at about 199.5 m OD, on the modelled dam whatever the analysis), node A
    (thesis about 150 mm at 198, 400-450 mm at 200.5 m OD; observed 200-275 mm; Chen's (1990)
    finite elements 100-150 mm), F.
References
    G. S. Bala (2008), thesis, chapter 6, Tables 6.2, 6.3; A. W. Skempton & P. R. Vaughan (1993),
    The failure of Carsington Dam, Geotechnique 43(1); D. M. Potts, G. T. Dounias & P. R. Vaughan
    (1990), Geotechnique; Z. Chen, N. R. Morgenstern & D. H. Chan (1992), Canadian Geotechnical
    Journal; Environment Agency, Lessons from historical dam incidents (quoting A. W. Skempton
    1985).
"""

from __future__ import annotations

import functools
import time
from dataclasses import dataclass, fields, replace
from pathlib import Path
from types import ModuleType
from typing import Any

import numpy as np

from hybrid import references
from hybrid.case import uses_defaults
from hybrid.continuum import NewtonOptions, PlasticSolver
from hybrid.continuum.limit_equilibrium import bishop_circle
from hybrid.continuum.probe import evaluate
from hybrid.continuum.staging import build_in_lifts, ground_stage, lift_materials, split_into_lifts
from hybrid.continuum.strength_reduction import StrengthSearch
from hybrid.discrete.integrate import default_dt
from hybrid.discrete.measures import (
    CrackWatch,
    Deposit,
    SlipSurface,
    SlopeMarks,
    crack_from_top,
    deposit,
    failure_onset,
    first_failures,
    interfaces_between,
    interfaces_of,
    mean_displacement,
    slip_along,
    top_interfaces,
)
from hybrid.discrete.runs import run_to_rest
from hybrid.discrete.solver import RunOptions
from hybrid.figures import Column, plot_level_history, staged_figures
from hybrid.geometry import build_mesh, load_mesh_script
from hybrid.handover import Region, element_groups, from_construction
from hybrid.io import CaseSummary, Check, write_continuum_xdmf
from hybrid.materials import Bond, Contact, Material, Strength
from hybrid.model import Fixed, Model, Roller
from hybrid.parameters import CELLS, param

MESHES = Path(__file__).resolve().parent.parent / "meshes"
EMBANKMENT = ("core", "zone_I", "zone_II", "berm")  # built in lifts
GROUND = ("foundation", "yellow_clay")  # in place before construction
CREST_DEPTH = 0.1  # a crack at the crest has an end within this of the crest's top [m]
SECTION = ("yellow_clay_thickness", "yellow_clay_length", "boot_length", "lifts",
           "parts_above", "part_height")

# the section and the strengths it is built with (Table 6.3, no factor on them)
BUILT_AS_PUBLISHED = (*SECTION, *(f.name for f in fields(references.CarsingtonTable63)),
                      "strength_factor")
# the fields that make the modelled section the thesis's (published figures apply with them)
PUBLISHED_PROBLEM = (*BUILT_AS_PUBLISHED, "no_tension", "softening", "discrete_softening")
# the fields that make the modelled dam the one that failed: the observed movements apply with
# them, whichever analysis follows it (with or without softening, damping)
OBSERVED_PROBLEM = (*BUILT_AS_PUBLISHED,
                    *(f.name for f in fields(references.CarsingtonTable62)))
# bar on the post-failure movements against the observed ones [-]: the observations are
# approximate ("about 10 m" of crest drop; 11 m (EA) to 13 m (thesis 6.2.4) at the toe),
# so an analysis within 30 % of them reproduces the size of the slide, not its detail
OBSERVED_BAR = 0.30


@dataclass
class Parameters(references.CarsingtonTable62, references.CarsingtonTable63):
    # the materials: the fields of Table 6.3 and 6.2 (foundation_E, core_cu, fill_phi, ...)
    size: float = param(6.0, gt=0)  # element size in the embankment [m] (12: coarse)
    layer_size: float | None = param(None, gt=0)  # in the yellow clay [m] (None: its thickness)
    cells: str = param("quadrilateral", choices=CELLS)  # or "triangle"
    degree: int = param(2, choices=(1, 2))  # displacement order
    lifts: int = param(5, ge=1)  # lifts after the foundation's stage (thesis: 6 stages in all)
    parts_above: float | None = param(None, gt=0)  # the fill above this level [m OD] in parts
    part_height: float = param(0.5, gt=0)  # the parts' largest height [m] (with parts_above)
    yellow_clay_thickness: float = param(1.5, gt=0)  # [m] (assumed; weathered 1-2 m deep)
    yellow_clay_length: float | None = param(36.0, gt=0)  # from the boot [m] (None: toe + 30 m)
    boot_length: float = param(35.0, gt=0)  # upstream end of the boot from the axis [m] (assumed)
    no_tension: bool = True  # tension cut-off 0 in the fill and the clays (thesis 6.3.1.1)
    softening: bool = False  # strengths fall to residual (beyond the thesis: its Problem)
    softening_displacement: float = param(0.5, gt=0)  # u_r: slip from peak to residual [m]
    discrete_softening: bool = False  # softening in the discrete phase only (built at peak)
    node_a_x: float = 0.0  # the thesis's node A [m from the axis] (assumed: the core's axis,
    node_a_y: float = 166.5  # [m OD] at the top of the boot)
    strength_factor: float = param(1.0, gt=0)  # c, tan(phi) / this while building (< 1: stronger)
    gravity_steps: int = param(2, ge=1)  # increments of the foundation's weight
    ramp_steps: int = param(2, ge=1)  # increments of each lift's weight (halved on failure)
    min_increment: float = param(1e-3, gt=0, le=1)  # least increment, x the first, before collapse
    safety: bool = True  # strength-reduction factor of safety
    safety_every_lift: bool = True  # after every complete lift (False: only after the last)
    fos_step: float = param(0.1, gt=0)  # first relative increase of F [-]
    fos_tolerance: float = param(0.01, gt=0)  # F bracketed to this relative width [-]
    # discrete phase (post-failure)
    discrete_time: float = param(120.0, ge=0)  # at most, earlier at rest [s] (0: continuum only)
    region_layers: int | None = param(None, ge=0)  # None: any bond may fail; N: only those
    #                            within N cell layers of the yielded cells (a sensitivity: N
    #                            layers are N element sizes, shrinking as the mesh is refined)
    mass_damping: float = param(0.0, ge=0)  # mass damping alpha [1/s] (thesis: 3; see header)
    contact_damping: float = param(0.2, ge=0, le=1)  # normal contact damping ratio [-]
    slip_min: float = param(0.1, gt=0)  # slip that puts a failed interface on the slip surface,
    #                                     opening that makes it part of a crack [m]
    rest: float = param(1e-4, gt=0)  # kinetic / strain energy ratio taken as rest
    frames: int = param(30, ge=0)  # animation frames of the discrete phase (0: none)
    progress: bool = True  # progress bar of the discrete run


def materials(p: Parameters) -> dict[str, Material]:
    """Table 6.3 as in the module's Problem (the berm as Zone II: Table 6.3 names no berm).

    Discrete phase: bonds as strong as the material, a tension cut-off of c for the phi = 0
    clays (assumed); separated elements slide at Table 6.2's residual angles (Zone I and the
    berm at Zone II's: assumed), as the thesis's cracks do. With ``softening`` the residual
    strengths of the Problem, which a crack then carries (``Contact``): the fill's c = 0 and
    phi_r, the clays' residual c_u on any normal stress (undrained, phi = 0)."""
    def contact(phi: float) -> Contact:
        return Contact(damping=p.contact_damping) if p.softening else Contact(
            phi=phi, damping=p.contact_damping)

    def residual(c: float, phi: float) -> dict[str, Any]:
        return ({"residual": Strength(cohesion=c, phi=phi),
                 "softening_displacement": p.softening_displacement} if p.softening else {})

    cut = 0.0 if p.no_tension else None
    fill = {"cohesion": p.fill_c, "phi": p.fill_phi, "E": p.fill_E, "nu": p.fill_nu,
            "unit_weight": p.fill_gamma, "tensile_strength": cut,
            "contact": contact(p.fill_residual_phi), **residual(0.0, p.fill_residual_phi)}
    clay = {"yellow_clay": ("yellow clay", p.yellow_clay_E, p.yellow_clay_nu,
                            p.yellow_clay_gamma, p.yellow_clay_cu, p.yellow_clay_residual_phi,
                            p.yellow_clay_peak_phi),
            "core": ("core", p.core_E, p.core_nu, p.core_gamma, p.core_cu, p.core_residual_phi,
                     p.core_peak_phi)}
    return {
        "foundation": Material(name="mudstone", E=p.foundation_E, nu=p.foundation_nu,
                               unit_weight=p.foundation_gamma,
                               contact=Contact(phi=p.fill_phi, damping=p.contact_damping)),
        **{key: Material(name=name, E=E, nu=nu, unit_weight=gamma, cohesion=cu,
                         tensile_strength=cut, bond=Bond(tensile_strength=cu),
                         contact=contact(phi_r),
                         **residual(cu * references.friction_ratio(phi_r, phi_peak), 0.0))
           for key, (name, E, nu, gamma, cu, phi_r, phi_peak) in clay.items()},
        **{key: Material(name=name, **fill)
           for key, name in (("zone_I", "Zone I"), ("zone_II", "Zone II"), ("berm", "berm"))},
    }


@functools.cache
def section_module() -> ModuleType:
    """``meshes/carsington.py`` (the builder, ``Section``, ``lift_tops``)."""
    return load_mesh_script(MESHES / "carsington.py")


def main(out: str | Path = "results/carsington", **overrides) -> CaseSummary:
    """Carsington Dam Ch. 725: staged construction, factor of safety, post-failure run."""
    p = Parameters(**overrides)
    out, start = Path(out), time.perf_counter()
    g = section_module().Section(**p.pick(SECTION))  # the modelled section's dimensions
    base_mesh = build_mesh(section_module().build, size=p.size, layer_size=p.layer_size,
                           cells=p.cells, **p.pick(SECTION))
    tops = section_module().lift_tops(g.crest_level, g.berm_top, p.lifts, p.parts_above,
                                      p.part_height)
    mesh = split_into_lifts(base_mesh, EMBANKMENT, tops)
    model = Model(mesh, lift_materials(mesh, materials(p)),
                  supports=[Fixed("base"), Roller("left", "x"), Roller("right", "x")])
    solver = PlasticSolver(model, degree=p.degree,
                           options=NewtonOptions(min_increment=p.min_increment))
    solver.set_strength_factor(p.strength_factor)

    # stage 1: gravity on the foundation (key trench open), then displacements zeroed
    gravity_iterations, far = ground_stage(
        solver, GROUND, g.far_field_point(), ground_level=g.foundation_level,
        unit_weight=p.foundation_gamma, nu=p.foundation_nu, steps=p.gravity_steps,
        where="below the level ground downstream")

    # stages 2-6: the lifts; node A and F after each complete lift
    candidates = g.node_a_candidates()
    node_a = np.array([[p.node_a_x, p.node_a_y], *candidates.values()])

    def monitor(s: PlasticSolver) -> dict[str, Any]:
        dx = 1e3 * evaluate(s.u, node_a)[:, 0]
        return {"node_A_dx_mm": float(dx[0]),
                "core_dx_mm": dict(zip(candidates, map(float, dx[1:]), strict=True))}

    search = StrengthSearch(initial_increment=p.fos_step, max_increment=max(p.fos_step, 0.25),
                            tolerance=p.fos_tolerance) if p.safety else None
    built = build_in_lifts(solver, mesh, tops, g.foundation_level, steps=p.ramp_steps,
                           safety=search, safety_every_lift=p.safety_every_lift, unit="m_OD",
                           monitor=monitor)
    state = built.last_equilibrium(solver, mesh)  # figures and their numbers
    construction_time = time.perf_counter() - start - built.safety_wall_time
    carried, history, safety = built.level_carried, built.history("node_A_dx_mm"), built.safety
    at_level = built.at_levels("node_A_dx_mm", references.CARSINGTON_REPORT_LEVELS)
    circle = None if safety is None else bishop_circle(model, built.safety_active)

    # figures: the end of construction (or the last equilibrium), node A against the fill level
    core = np.isin(np.arange(base_mesh.num_owned_cells), base_mesh.cells("core")) & state.active
    column = Column(core, p.node_a_x, g.foundation_level - g.trench_depth + 0.1,
                    g.crest_level - 0.1, tops, "the axis", "core")
    paths = staged_figures(out, base_mesh, state, built, window=g.window(), column=column,
                           circle=circle, elevation_label="elevation [m OD]",
                           engineering=f"fill at {carried:g} m OD")
    paths.append(plot_level_history(
        out / "core_displacement_vs_fill_level.png", [g.foundation_level] + [z for z, _ in history],
        [0.0] + [abs(dx) for _, dx in history], bands=references.CARSINGTON_CORE_DISPLACEMENT,
        label=f"this analysis, node A ({p.node_a_x:g} m, {p.node_a_y:g} m OD)",
        xlabel="horizontal displacement of the core at node A, |u_x| [mm]",
        ylabel="fill level [m OD]", title="Core displacement against fill level"))
    write_continuum_xdmf(out / "continuum.xdmf", state)

    clays = {name: base_mesh.cells(name) for name in ("yellow_clay", "core")}
    extremes = {"max_settlement_core_m": state.extreme_displacement(1, cells=clays["core"]),
                "max_upstream_displacement_m": state.extreme_displacement(0),
                "max_downstream_displacement_m": state.extreme_displacement(0, largest=True)}
    summary = CaseSummary("carsington", out, p, results={
        "mesh": {**base_mesh.report(), "dofs": state.info["dofs"], "lift_tops_m_OD": tops},
        "gravity": {"newton_iterations": gravity_iterations, "far_field_stress_kPa": far.stress},
        "construction": built.report(solver, state, construction_time, measures=extremes,
                                     groups=clays),
        "core_displacement_mm": {
            **at_level, "node_A_m": node_a[0].tolist(), "by_fill_level": history,
            "sign": "+ downstream", "candidates": {
                name: {"point_m": list(point), "by_fill_level": built.history("core_dx_mm", name)}
                for name, point in candidates.items()}},
        "figures": [str(f) for f in paths]},
        checks={**far.checks, **built.checks()})
    published, checks = uses_defaults(p, PUBLISHED_PROBLEM), summary["checks"]
    checks["fill_level_vs_thesis"] = Check.published(
        carried, g.crest_level, None, "m OD", "thesis: stands to the design crest (Table 6.3)",
        applies=published)
    checks["fill_level_vs_observed"] = Check.published(
        carried, references.CARSINGTON_FAILURE_FILL_LEVEL, None, "m OD",
        "observed: the upstream slope slipped at about 199.5 m OD (Skempton 1985)",
        applies=uses_defaults(p, OBSERVED_PROBLEM))
    for band, (level, dx) in zip(references.CARSINGTON_CORE_DISPLACEMENT, at_level.items()):
        if dx is not None:
            checks[f"core_displacement_{level}_vs_thesis"] = Check.published(
                abs(dx), band.middle, None, "mm", band.label, applies=published)
    if safety is not None and circle is not None:
        summary["factor_of_safety"] = built.safety_report(groups=clays, circle=circle, measures={
            "strength_factor_of_construction": p.strength_factor})
        checks.update(built.safety_checks(circle))
        for key, (value, source) in references.CARSINGTON_FOS.items() if built.completed else ():
            checks[f"fos_vs_{key}"] = Check.published(safety.factor, value, None, "-", source,
                                                      applies=published)
    summary["continuum_wall_time_s"] = time.perf_counter() - start

    # discrete phase (``discrete_time`` > 0): handover, the foundation ("strong base") held
    start = time.perf_counter()
    after = (materials(replace(p, softening=True))
             if p.discrete_softening and not p.softening else None)
    region = Region(everywhere=p.region_layers is None, layers=p.region_layers or 0)
    hand = (from_construction(solver, built, region=region, materials=after)
            if p.discrete_time > 0.0 else None)
    if hand is None or hand.discrete is None:  # continuum only, or MPI ranks other than 0
        summary.write(out / "summary.json", solver.model.mesh.comm)
        return summary
    disc, group = hand.discrete, element_groups(hand)  # lifts merged
    disc.fix(np.unique(disc.element_nodes[group == "foundation"]))
    zone = g.zones(group, disc.element_centroids())
    slope = SlopeMarks.pick(disc, zone["embankment"], crest_x=g.crest_range)

    def upstream_front() -> Deposit:  # the embankment's continuous mass, followed upstream
        return deposit(disc, zone["embankment"], bin_width=p.size, direction=-1)

    front_at_start = upstream_front()
    options = RunOptions(dt=default_dt(disc), split_every=10, mass_damping=p.mass_damping)
    watch = CrackWatch(g.crest_range, min_opening=p.slip_min, top_depth=CREST_DEPTH)
    run = run_to_rest(disc, out, options, until_time=p.discrete_time, rest=p.rest,
                      frames=p.frames, snapshot_times=(1.0, 3.0, 6.0, 10.0), window=g.window(True),
                      progress=p.progress, material_names=hand.material_names, watch=[watch])
    surface = SlipSurface.of(disc, p.slip_min, {"yellow_clay": group == "yellow_clay",
                                                "boot": zone["boot"], "core": zone["core"]})
    crack = crack_from_top(disc, g.crest_range, min_opening=p.slip_min,
                           top_depth=CREST_DEPTH)
    crack_lines = {f"crack from the crest ({crack.depth:.1f} m deep)":
                   disc.x[disc.interface_nodes[crack.interfaces][:, :2]]}
    paths = [*run.figures, run.final_figure(out / "discrete_final.png",
                                            {**surface.lines(disc), **crack_lines})]
    moved, shoulder_dx = slope.movement(disc), mean_displacement(disc, zone["upstream_shoulder"])[0]
    # where and how the bonds began to fail (thesis: at the crest or in the yellow clay)
    began = {"crest_top": top_interfaces(disc, g.crest_range, top_depth=CREST_DEPTH),
             "yellow_clay": interfaces_of(disc, group == "yellow_clay")}
    onset = failure_onset(disc, {
        **began, "boot": interfaces_of(disc, zone["boot"]),
        "core": interfaces_of(disc, zone["core"]),
        "upstream_shoulder": interfaces_of(disc, zone["upstream_shoulder"]),
        "anywhere": np.ones(disc.interface_elements.shape[0], dtype=bool)})
    first_time, first = first_failures(disc, began)
    # the core's boundary with the upstream Zone I, where the thesis's large failure surface
    # develops (6.3.2)
    core_face = slip_along(disc, interfaces_between(
        disc, group == "core", zone["upstream_shoulder"] & (group == "zone_I")), p.slip_min)
    front = upstream_front()
    toe_runout = front.runout - front_at_start.runout  # how far the upstream toe advanced
    checks.update({
        **surface.checks({"yellow_clay": "a yellow-clay element",
                          "boot": "an element of the core's boot",
                          "core": "an element of the core above its boot"}),
        "crack_at_crest": Check(float(watch.seen), 1.0, 0.0, "-",
                                f"failed interfaces open >= {p.slip_min} m from the crest down "
                                "at a check during the slide (CrackWatch)"),
        "failure_begins_at_crest_or_in_yellow_clay": Check(
            float(first["crest_top"] + first["yellow_clay"] > 0), 1.0, 0.0, "-",
            "the first splitting check that fails a bond fails one at the crest's top or in "
            "the yellow clay (thesis 6.3.2: failure begins at the top of the dam or within "
            "the yellow clay layer; first_failures: how many there and elsewhere)"),
        "crest_cracks_in_tension": Check(
            float(set(onset["crest_top"].first_modes) == {"tension"}), 1.0, 0.0, "-",
            "the first bonds to fail at the crest's top fail in tension (a crack)"),
        "shoulder_moves_upstream": Check(float(shoulder_dx < 0.0), 1.0, 0.0, "-",
                                         "mean x-displacement of the upstream shoulder < 0"),
        **run.checks()})
    observed = {"upstream_toe_movement": toe_runout, "crest_drop": moved.crest_drop}
    for key, (value, source) in references.CARSINGTON_POST_FAILURE.items():  # final only
        checks[key] = Check.published(observed[key], value, OBSERVED_BAR, "m", source,
                                      applies=uses_defaults(p, OBSERVED_PROBLEM) and run.at_rest)
    summary.update(handover=hand.report, discrete={
        "start": "last complete lift + collapsing lift placed at once"
                 if built.before_collapse is not None else "end of construction (design height)",
        **run.report(), "phase_wall_time_s": time.perf_counter() - start,
        **surface.summary(), "crest_crack_interfaces": int(crack.interfaces.sum()),
        "crest_crack_depth_m": crack.depth, "crest_crack_max_opening_m": crack.max_opening,
        "crest_crack_max_slip_m": crack.max_slip, **watch.summary("crest_crack_during_slide"),
        "failure_onset": {name: o.summary() for name, o in onset.items()},
        "first_failures": {"time_s": None if np.isnan(first_time) else first_time, **first},
        "slip_along_core_upstream_face": core_face,
        "upstream_shoulder_mean_dx_m": shoulder_dx,
        "upstream_toe_dx_m": moved.toe_dx, "crest_drop_m": moved.crest_drop,
        "toe_runout_m": toe_runout, "toe_detached_elements": front.detached,
        "max_upstream_movement_m": moved.run_out,
        "figures": [str(f) for f in paths]})
    summary.write(out / "summary.json", solver.model.mesh.comm)
    return summary


if __name__ == "__main__":
    from hybrid.case import run_case

    raise SystemExit(run_case(main, Parameters))
