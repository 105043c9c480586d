"""Carsington Dam, chainage 725: staged construction, factor of safety, post-failure run
(thesis chapter 6).

Objective
    The thesis's headline case on a real dam, the 1984 Carsington failure: staged
    construction to the crest or to collapse, strength-reduction factors of safety, then the
    discrete post-failure run to rest, next to the published observations and values.
Problem
    The cross-section at Ch. 725 (``meshes/carsington.py``; every dimension with its source or
    as an assumption in ``docs/carsington.md``): a 36 m embankment on mudstone, upstream slope
    1:3 with a toe berm, downstream 1:2.5, a rolled clay core with an upstream boot in a 3 m
    key trench, Zone I and Zone II shoulders, a 1.5 m layer of yellow clay in the top of the
    foundation under the upstream shoulder. Undrained total-stress parameters of the thesis's
    Table 6.3 (psi = 0 everywhere; the berm has the Zone II properties, an assumption); pore
    pressures are not modelled (they are inside the undrained strengths).
Set-up
    Base fixed, sides on vertical rollers. Gravity switched on in the foundation (the key
    trench open), displacements zeroed, then six lifts (the first up to the berm top, then
    five equal lifts to the design crest 200.5 m OD) each placed with zero stress and its
    weight ramped in to equilibrium (``build_in_lifts``: ``PlasticSolver.activate``,
    increments halved when Newton fails): the displacements of a point count from its
    placement. A lift whose full weight finds no equilibrium is the collapse: its fill level
    is reported and construction stops there. After every complete lift, c and tan(phi) are
    divided by F until no equilibrium (``factor_of_safety``, from that lift's state, which is
    restored afterwards).
    ``strength_factor`` < 1 builds with stronger materials (c and tan(phi) divided by it), to
    reach the crest and measure F of the completed section against the Table 6.3 strengths.
    Discrete phase (``discrete_phase``): from the last complete lift with the collapsing lift
    in place (all its weight, stress-free), the yielded cells + ``region_layers`` may split,
    the foundation is held; run to rest. The slip surface is the set of failed interfaces
    that slipped at least ``slip_min``; checked: it has yellow-clay and boot elements on it,
    and the upstream shoulder moved upstream.
Verification (asserted in ``tests/test_carsington.py``)
    * every lift but a collapsing last one reaches equilibrium (Newton to 1e-8);
    * no stress in fill not yet placed, after every lift (exactly zero);
    * far-field foundation after gravity: sigma_v = -gamma z, sigma_h = K0 sigma_v (1 %);
    * F > 1 after the first lift and F falling as the dam rises.
    Reported beside published values, without a bar (methods and parameters differ, see
    docs/carsington.md): the fill level at collapse (the slope slipped at 199.5 m OD), F of
    the completed section (limit equilibrium 1.4 intact peak, 1.2 with pre-existing shears;
    finite elements with strain softening about 1.1 to 1.05 just before collapse).
References
    G. S. Bala (2008), thesis, chapter 6, Table 6.3; A. W. Skempton & P. R. Vaughan (1993),
    The failure of Carsington Dam, Geotechnique; D. M. Potts, G. T. Dounias & P. R. Vaughan
    (1990), Finite element analysis of progressive failure of Carsington embankment,
    Geotechnique; Z. Chen, N. R. Morgenstern & D. H. Chan (1992), Progressive failure of the
    Carsington Dam: a numerical study, Canadian Geotechnical Journal; Environment Agency,
    Lessons from historical dam incidents.
"""

from __future__ import annotations

import functools
import time
from dataclasses import dataclass
from pathlib import Path
from types import ModuleType
from typing import Any, NamedTuple

import numpy as np

from hybrid.case import uses_defaults
from hybrid.continuum import ContinuumState, NewtonOptions, PlasticSolver
from hybrid.continuum.limit_equilibrium import bishop_circle
from hybrid.continuum.staging import Construction, build_in_lifts, split_into_lifts
from hybrid.continuum.strength_reduction import StrengthSearch
from hybrid.discrete.energy import energy_excess, energy_peak_ratio
from hybrid.discrete.figures import plot_configuration
from hybrid.discrete.integrate import stable_time_step
from hybrid.discrete.measures import SlipSurface, SlopeMarks
from hybrid.discrete.runs import run_to_rest
from hybrid.discrete.solver import RunOptions
from hybrid.figures import Column, staged_figures
from hybrid.geometry import MeshData, build_mesh, load_mesh_script
from hybrid.handover import Region, element_groups, from_construction
from hybrid.io import CaseSummary, Check, write_continuum_xdmf
from hybrid.materials import Bond, Contact, Material
from hybrid.model import Fixed, Model, Roller
from hybrid.parameters import CELLS, CaseParameters, param
from hybrid.references import SlipCircle

MESHES = Path(__file__).resolve().parent.parent / "meshes"
EMBANKMENT = ("core", "zone_I", "zone_II", "berm")  # built in lifts
GROUND = ("foundation", "yellow_clay")  # in place before construction
SECTION = ("yellow_clay_thickness", "boot_length", "lifts")  # parameters of the gmsh section

FAILURE_FILL_LEVEL = 199.5  # fill level when the upstream slope slipped [m OD] (Skempton 1985)
# Published factors of safety at Ch. 725 (thesis ch. 6; Chen et al. 1992)
PUBLISHED_FOS = {
    "limit_equilibrium_intact_peak": (1.4, "LE, intact peak strengths (> 1.4)"),
    "limit_equilibrium_pre_sheared": (1.2, "LE, reduced yellow-clay strength for pre-shears"),
    "finite_element_before_collapse": (1.1, "FE (strain softening), just before collapse"),
}


# the fields that make the modelled section the real dam at Ch. 725 (published and observed
# figures apply only with them)
PUBLISHED_PROBLEM = ("lifts", "yellow_clay_thickness", "boot_length", "foundation_E",
                     "foundation_nu", "foundation_gamma", "yellow_clay_cu", "yellow_clay_E",
                     "yellow_clay_nu", "yellow_clay_gamma", "core_cu", "core_E", "core_nu",
                     "core_gamma", "fill_c", "fill_phi", "fill_E", "fill_nu", "fill_gamma",
                     "strength_factor")


@dataclass
class Parameters(CaseParameters):
    size: float = param(6.0, gt=0)  # element size in the embankment [m] (6: ~1 000 cells; 12:
    #                                 coarse)
    layer_size: float | None = param(None, gt=0)  # element size in the yellow clay [m] (None:
    #                                               thickness)
    cells: str = param("quadrilateral", choices=CELLS)  # or "triangle"
    degree: int = param(2, choices=(1, 2))  # displacement order
    lifts: int = param(6, ge=1)  # construction stages (thesis: 6)
    yellow_clay_thickness: float = param(1.5, gt=0)  # [m] (published 1-2 m)
    boot_length: float = param(35.0, gt=0)  # upstream end of the boot from the axis [m] (assumed)
    foundation_E: float = 125_000.0  # mudstone, elastic [kPa] (Table 6.3)
    foundation_nu: float = 0.35  # [-]
    foundation_gamma: float = 20.0  # [kN/m3]
    yellow_clay_cu: float = 15.0  # undrained strength [kPa] (Table 6.3, phi = 0)
    yellow_clay_E: float = 3_000.0  # [kPa]
    yellow_clay_nu: float = 0.42  # [-]
    yellow_clay_gamma: float = 19.5  # [kN/m3]
    core_cu: float = 52.0  # [kPa] (Table 6.3, phi = 0)
    core_E: float = 2_500.0  # [kPa]
    core_nu: float = 0.43  # [-]
    core_gamma: float = 18.5  # [kN/m3]
    fill_c: float = 13.5  # Zone I and Zone II cohesion [kPa] (Table 6.3)
    fill_phi: float = 24.0  # [deg]
    fill_E: float = 60_000.0  # [kPa]
    fill_nu: float = 0.38  # [-]
    fill_gamma: float = 21.0  # [kN/m3]
    strength_factor: float = param(1.0, gt=0)  # c, tan(phi) divided by this while building (< 1:
    #                                            stronger)
    gravity_steps: int = param(2, ge=1)  # increments of the foundation's weight
    ramp_steps: int = param(2, ge=1)  # increments of each lift's weight (halved on failure)
    min_increment: float = param(1e-3, gt=0, le=1)  # smallest increment, x the first, before
    #                                                 collapse is declared
    safety: bool = True  # strength-reduction factor of safety
    safety_every_lift: bool = True  # after every complete lift (False: only after the last)
    fos_step: float = param(0.1, gt=0)  # first relative increase of F [-]
    fos_tolerance: float = param(0.01, gt=0)  # F bracketed to this relative width [-]
    # discrete phase (post-failure)
    discrete_time: float = param(15.0, ge=0)  # [s] at most (0: continuum only); stops earlier at
    #                                           rest
    region_layers: int = param(2, ge=0)  # growth of the splittable region around the yielded cells
    split_plastic_strain: float = param(0.02, gt=0)  # bonds also fail beyond this plastic strain
    #                                                  [-]
    plastic_strain_cap: float | None = param(2.0, gt=0)  # element flow limit [-] (None: none)
    mass_damping: float = param(0.5, ge=0)  # mass damping alpha [1/s]
    contact_damping: float = param(0.2, ge=0, le=1)  # normal contact damping ratio [-]
    clay_residual_phi: float = 12.0  # contact friction of yellow clay and core [deg]
    fill_residual_phi: float = 14.5  # contact friction of Zone I, Zone II, berm [deg]
    slip_min: float = param(0.1, gt=0)  # slip that puts a failed interface on the slip surface [m]
    rest: float = param(1e-4, gt=0)  # kinetic / strain energy ratio taken as rest
    frames: int = param(30, ge=0)  # animation frames of the discrete phase (0: none)
    progress: bool = True  # progress bar of the discrete run


class ContinuumPhase(NamedTuple):
    """What the continuum phase leaves for the discrete phase: the ``solver`` at the last
    equilibrium of construction at the construction strengths (the end of construction or,
    when a lift collapsed, that lift active with the last fraction of its weight that found
    equilibrium), a copy of its ``state``, the lift-by-lift record (``construction``; its
    ``before_collapse`` restores the last complete lift) and the ``summary``."""

    solver: PlasticSolver
    state: ContinuumState
    construction: Construction
    summary: CaseSummary


def materials(p: Parameters) -> dict[str, Material]:
    """Thesis Table 6.3 (undrained total stress), psi = 0; the berm as Zone II (assumed).

    For the discrete phase: bonds as strong as the material, with a tension cut-off of c for
    the phi = 0 clays (assumed); separated elements slide at residual friction angles
    (yellow clay 12 deg, Zone II 14.5 deg: thesis Table 6.2; the core as the yellow clay and
    Zone I and the berm as Zone II: assumed)."""
    def contact(phi: float) -> Contact:
        return Contact(phi=phi, damping=p.contact_damping)

    fill = {"cohesion": p.fill_c, "phi": p.fill_phi, "E": p.fill_E, "nu": p.fill_nu,
            "unit_weight": p.fill_gamma, "contact": contact(p.fill_residual_phi)}
    return {
        "foundation": Material(name="mudstone", E=p.foundation_E, nu=p.foundation_nu,
                               unit_weight=p.foundation_gamma, contact=contact(p.fill_phi)),
        "yellow_clay": Material(name="yellow clay", E=p.yellow_clay_E, nu=p.yellow_clay_nu,
                                unit_weight=p.yellow_clay_gamma, cohesion=p.yellow_clay_cu,
                                bond=Bond(tensile_strength=p.yellow_clay_cu),
                                contact=contact(p.clay_residual_phi)),
        "core": Material(name="core", E=p.core_E, nu=p.core_nu, unit_weight=p.core_gamma,
                         cohesion=p.core_cu, bond=Bond(tensile_strength=p.core_cu),
                         contact=contact(p.clay_residual_phi)),
        "zone_I": Material(name="Zone I", **fill),
        "zone_II": Material(name="Zone II", **fill),
        "berm": Material(name="berm", **fill),
    }


@functools.cache
def section_module() -> ModuleType:
    """``meshes/carsington.py`` (the builder, ``Section``, ``lift_tops``)."""
    return load_mesh_script(MESHES / "carsington.py")


def section(p: Parameters) -> Any:
    """The modelled section's dimensions (``Section`` of ``meshes/carsington.py``)."""
    return section_module().Section(**{k: getattr(p, k) for k in SECTION})


def continuum_phase(p: Parameters, out: Path) -> ContinuumPhase:
    """Gravity on the foundation, the lifts to the crest (or to collapse), factors of safety;
    writes the continuum outputs to ``out``."""
    start, g, sm = time.perf_counter(), section(p), section_module()
    base_mesh = build_mesh(sm.build, size=p.size, layer_size=p.layer_size, cells=p.cells,
                           **{k: getattr(p, k) for k in SECTION})
    tops = sm.lift_tops(g.crest_level, g.berm_top, p.lifts)
    mesh, table, comm = split_into_lifts(base_mesh, EMBANKMENT, tops), materials(p), base_mesh.comm
    model = Model(mesh, {name: table[name.split(":")[0]] for name in mesh.cell_groups},
                  supports=[Fixed("base"), Roller("left", "x"), Roller("right", "x")])
    solver = PlasticSolver(model, degree=p.degree,
                           options=NewtonOptions(min_increment=p.min_increment))
    solver.set_strength_factor(p.strength_factor)

    # 1. gravity on the foundation (key trench open), then displacements zeroed
    solver.set_active(list(GROUND))
    solver.apply_gravity(steps=p.gravity_steps).require()
    gravity_iterations = solver.iterations_total
    xr, yb = g.extent[1], g.extent[2]
    far = np.array([[xr - 5.0, yb + 0.5 * (g.foundation_level - yb)]])
    s_far = solver.state().stress_at(far)[0]
    sv = -p.foundation_gamma * (g.foundation_level - far[0, 1])
    k0 = p.foundation_nu / (1.0 - p.foundation_nu)
    solver.reset_displacement()

    # 2. the lifts, each placed stress-free and brought to equilibrium under its weight;
    #    a strength-reduction factor of safety after each (or the last) complete lift
    search = StrengthSearch(initial_increment=p.fos_step, max_increment=max(p.fos_step, 0.25),
                            tolerance=p.fos_tolerance)
    built = build_in_lifts(solver, mesh, tops, g.foundation_level, steps=p.ramp_steps,
                           safety=search if p.safety else None,
                           safety_every_lift=p.safety_every_lift, unit="m_OD")
    stages, safety, state = built.stages, built.safety, solver.state()
    construction_time = time.perf_counter() - start - built.safety_wall_time

    # outputs of the end of construction (or of the last equilibrium before collapse)
    circle = None if safety is None else bishop_circle(model, built.safety_active)
    paths = figures(out, p, base_mesh, state, built, circle)
    write_continuum_xdmf(out / "continuum.xdmf", state)

    def yielded(s: ContinuumState) -> dict[str, float]:
        return {f"{name}_yielded_fraction": s.yielded_fraction(base_mesh.cells(name))
                for name in ("yellow_clay", "core")}

    summary = CaseSummary("carsington", out, p, results={
        "mesh": {"cells": comm.allreduce(base_mesh.num_owned_cells),
                 "cell_type": base_mesh.cell_type, "dofs": state.info["dofs"],
                 "groups": {name: comm.allreduce(len(base_mesh.cells(name)))
                            for name in base_mesh.cell_groups}, "lift_tops_m_OD": tops},
        "gravity": {"newton_iterations": gravity_iterations, "far_field_stress_kPa": s_far},
        "construction": {
            "completed": built.completed, "stages": stages,
            "fill_level_m_OD": stages[-1]["fill_level_m_OD"],
            "max_settlement_core_m": state.extreme_displacement(1, cells=base_mesh.cells("core")),
            "max_upstream_displacement_m": state.extreme_displacement(0),
            "max_downstream_displacement_m": state.extreme_displacement(0, largest=True),
            "yielded_cells": comm.allreduce(len(state.yielded_cells())), **yielded(state),
            "newton_iterations": solver.iterations_total, "wall_time_s": construction_time},
        "figures": [str(f) for f in paths]},
        checks={
            "far_field_sigma_v": Check(float(s_far[1]), sv, 0.01, "kPa",
                                       "gamma z below the level ground downstream"),
            "far_field_sigma_h": Check(float(s_far[0]), k0 * sv, 0.01, "kPa",
                                       "K0 gamma z, K0 = nu / (1 - nu)"),
            "max_stress_in_unplaced_lifts": Check(built.max_unplaced_stress, 0.0, 0.0, "kPa",
                                                  "exactly zero")})
    published, checks = uses_defaults(p, PUBLISHED_PROBLEM), summary["checks"]
    if not built.completed:
        checks["fill_level_at_collapse"] = Check.published(
            stages[-1]["fill_level_m_OD"], FAILURE_FILL_LEVEL, None, "m OD",
            "fill about 1 m below the 200.5 m crest when the slope slipped (Skempton 1985)",
            applies=published)
    if safety is not None and circle is not None:
        lift = max(st["lift"] for st in stages if "factor_of_safety" in st)
        summary["factor_of_safety"] = {
            **safety.as_dict(), "after_lift": lift, "fill_level_m_OD": tops[lift - 1],
            "strength_factor_of_construction": p.strength_factor, **yielded(safety.state),
            "wall_time_s": built.safety_wall_time, "bishop": circle.as_dict()}
        checks["fos_vs_bishop"] = Check(
            safety.factor, circle.factor, None, "-",
            "this project's Bishop simplified search over circles, same section and lift")
        for key, (value, source) in PUBLISHED_FOS.items() if built.completed else ():
            checks[f"fos_vs_{key}"] = Check.published(safety.factor, value, None, "-", source,
                                                      applies=published)
    summary["continuum_wall_time_s"] = time.perf_counter() - start
    return ContinuumPhase(solver, state, built, summary)


def main(out: str | Path = "results/carsington", **overrides) -> CaseSummary:
    """Carsington Dam Ch. 725: staged construction, factor of safety, post-failure run."""
    p = Parameters(**overrides)
    out = Path(out)
    phase = continuum_phase(p, out)
    summary = phase.summary
    if p.discrete_time > 0.0:
        summary.update(discrete_phase(phase, p, out))
    summary.write(out / "summary.json", phase.state.comm)
    return summary


def discrete_phase(phase: ContinuumPhase, p: Parameters, out: Path) -> dict[str, Any]:
    """Handover and the post-failure run to rest (or ``discrete_time``).

    The start: when a lift collapsed, the last complete lift's equilibrium with the
    collapsing lift in place, stress-free and with all its weight (the discrete phase places
    it in one go); otherwise the end of construction. The yielded cells grown by
    ``region_layers`` may split; the foundation (elastic, "strong base") is held.
    """
    start, before = time.perf_counter(), phase.construction.before_collapse
    hand = from_construction(phase.solver, phase.construction,
                             region=Region(layers=p.region_layers))
    if hand.discrete is None:  # MPI ranks other than 0
        return {}
    disc, g, group = hand.discrete, section(p), element_groups(hand)  # lifts merged
    disc.fix(np.unique(disc.element_nodes[group == "foundation"]))
    centroid = disc.element_centroids()
    boot = (group == "core") & (centroid[:, 1] < g.foundation_level + g.boot_height)
    upstream_shoulder = np.isin(group, ["zone_I", "zone_II", "berm"]) & (centroid[:, 0] < 0.0)
    half_crest = 0.5 * g.crest_width + 10.0  # the fill top near the axis
    slope = SlopeMarks.pick(disc, ~np.isin(group, GROUND), crest_x=(-half_crest, half_crest))
    mass0, n0 = float(disc.mass.sum()), disc.n_elements
    window = (g.berm_toe - 40.0, g.foundation_level - 15.0, g.downstream_toe + 20.0,
              g.crest_level + 5.0)
    options = RunOptions(dt=0.5 * stable_time_step(disc, contact=True),
                         mass_damping=p.mass_damping, split_every=10,
                         split_plastic_strain=p.split_plastic_strain,
                         plastic_strain_cap=p.plastic_strain_cap)
    run = run_to_rest(disc, out, options, until_time=p.discrete_time, rest=p.rest,
                      frames=p.frames, snapshot_times=(1.0, 3.0, 6.0, 10.0), window=window,
                      progress=p.progress)
    res, h = run.result, run.result.history
    surface = SlipSurface.of(disc, p.slip_min,
                             {"yellow_clay": group == "yellow_clay", "boot": boot})
    paths = [*run.figures, plot_configuration(
        out / "discrete_final.png", disc, window=window, lines=surface.lines(disc),
        title=f"t = {res.time:.3g} s ({res.stop_reason})")]
    through, published = surface.through, uses_defaults(p, PUBLISHED_PROBLEM)
    u, moved = disc.x - disc.x_ref, slope.movement(disc)
    shoulder_dx = float(np.mean(u[disc.element_nodes[upstream_shoulder]][..., 0]))
    crest_drop, toe_dx = moved.crest_drop, moved.toe_dx
    checks = {
        "slip_surface_through_yellow_clay": Check(
            float(through["yellow_clay"] > 0), 1.0, 0.0, "-",
            f"failed interfaces slipped >= {p.slip_min} m with a yellow-clay element"),
        "slip_surface_through_boot": Check(
            float(through["boot"] > 0), 1.0, 0.0, "-",
            f"failed interfaces slipped >= {p.slip_min} m with an element of the core's boot"),
        "shoulder_moves_upstream": Check(float(shoulder_dx < 0.0), 1.0, 0.0, "-",
                                         "mean x-displacement of the upstream shoulder < 0"),
        "energy_excess_over_sources": Check(energy_excess(h), 0.0, 0.01, "-",
                                            "E_kin + E_strain + E_contact <= E(0) + work"),
        "elements_conserved": Check(float(disc.n_elements), float(n0), 0.0),
        "mass_conserved": Check(float(disc.mass.sum()), mass0, 1e-12, "t/m"),
        "upstream_toe_movement": Check.published(
            -toe_dx, 12.0, None, "m", "observed: upstream toe moved about 11-13 m",
            applies=published),
        "crest_drop": Check.published(
            crest_drop, 10.0, None, "m", "observed: crest dropped about 10 m (at the full "
            "height)", applies=published)}
    return {
        "handover": hand.report,
        "discrete": {
            "start": "last complete lift + collapsing lift placed at once"
                     if before is not None else "end of construction",
            "elements": disc.n_elements, "dt_s": res.dt, "steps": res.steps,
            "time_s": res.time, "stop": res.stop_reason, "wall_time_s": res.wall_time,
            "phase_wall_time_s": time.perf_counter() - start,
            "interfaces_failed": int((~disc.interface_intact).sum()),
            "slip_surface_interfaces": int(surface.interfaces.sum()),
            "slip_surface_yellow_clay": through["yellow_clay"],
            "slip_surface_boot": through["boot"],
            "slip_surface_trace_m": surface.trace,
            "slipped_interfaces_by_threshold_m": surface.by_threshold,
            "upstream_shoulder_mean_dx_m": shoulder_dx,
            "upstream_toe_dx_m": toe_dx, "crest_drop_m": crest_drop,
            "max_upstream_movement_m": moved.run_out,
            "energy_peak_over_supply": energy_peak_ratio(h),
            "figures": [str(f) for f in paths],
            "outputs": [str(f) for f in run.outputs]},
        "checks": {**phase.summary["checks"], **checks}}


def figures(out: Path, p: Parameters, mesh: MeshData, state: ContinuumState,
            built: Construction, circle: SlipCircle | None) -> list[Path]:
    """Figures of the end of construction (or the last equilibrium before collapse) in a
    window on the dam, with the core's profiles at the axis; with a factor of safety, the
    plastic strain and the mechanism at F with Bishop's critical circle."""
    g = section(p)
    window = (g.berm_toe - 30.0, g.foundation_level - 25.0, g.downstream_toe + 30.0,
              g.crest_level + 3.0)
    core = np.isin(np.arange(mesh.num_owned_cells), mesh.cells("core")) & state.active
    column = Column(core, 0.0, g.foundation_level - g.trench_depth + 0.1, g.crest_level - 0.1,
                    section_module().lift_tops(g.crest_level, g.berm_top, p.lifts),
                    "the axis", "core")
    return staged_figures(out, mesh, state, built, window=window, column=column,
                          circle=circle, elevation_label="elevation [m OD]")


if __name__ == "__main__":
    from hybrid.case import run_case

    raise SystemExit(run_case(main, Parameters))
