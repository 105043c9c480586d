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
    weight ramped in to equilibrium (``PlasticSolver.activate``, increments halved when Newton
    fails): the displacements of a point count from its placement. A lift whose full weight
    finds no equilibrium is the collapse: its fill level is reported and construction stops
    there. After every complete lift, c and tan(phi) are divided by F until no equilibrium
    (``factor_of_safety``, from that lift's state, which is restored afterwards).
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
import importlib.util
import time
from dataclasses import asdict, dataclass
from pathlib import Path
from types import ModuleType
from typing import Any, NamedTuple

import numpy as np
from mpi4py import MPI

from hybrid.case import uses_defaults
from hybrid.continuum import ContinuumState, NewtonOptions, PlasticSolver, factor_of_safety
from hybrid.continuum.limit_equilibrium import bishop_circle
from hybrid.continuum.strength_reduction import SafetyResult, StrengthSearch
from hybrid.discrete import integrate
from hybrid.discrete.energy import energy_excess, energy_peak_ratio
from hybrid.discrete.figures import plot_configuration
from hybrid.discrete.run import run
from hybrid.geometry import MeshData, build_mesh
from hybrid.handover import Region, to_discrete
from hybrid.io import (
    Check,
    gather_cells,
    plot_cell_field,
    write_continuum_xdmf,
    write_summary,
)
from hybrid.materials import Material
from hybrid.model import Fixed, Model, Roller
from hybrid.references import SlipCircle

MESHES = Path(__file__).resolve().parent.parent / "meshes"
SECTION = MESHES / "carsington.py"
EMBANKMENT = ("core", "zone_I", "zone_II", "berm")  # built in lifts
GROUND = ("foundation", "yellow_clay")  # in place before construction

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
class Parameters:
    size: float = 6.0  # element size in the embankment [m] (6: ~1 000 cells; 12: coarse)
    layer_size: float | None = None  # element size in the yellow clay [m] (None: thickness)
    cells: str = "quadrilateral"  # or "triangle"
    degree: int = 2  # displacement order
    lifts: int = 6  # construction stages (thesis: 6)
    yellow_clay_thickness: float = 1.5  # [m] (published 1-2 m)
    boot_length: float = 35.0  # upstream end of the boot from the axis [m] (assumed)
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
    strength_factor: float = 1.0  # c, tan(phi) divided by this while building (< 1: stronger)
    gravity_steps: int = 2  # increments of the foundation's weight
    ramp_steps: int = 2  # increments of each lift's weight (halved on failure)
    min_increment: float = 1e-3  # smallest increment, x the first, before collapse is declared
    safety: bool = True  # strength-reduction factor of safety
    safety_every_lift: bool = True  # after every complete lift (False: only after the last)
    fos_step: float = 0.1  # first relative increase of F [-]
    fos_tolerance: float = 0.01  # F bracketed to this relative width [-]
    # discrete phase (post-failure)
    discrete_time: float = 15.0  # [s] at most (0: continuum only); stops earlier at rest
    region_layers: int = 2  # growth of the splittable region around the yielded cells
    split_plastic_strain: float = 0.02  # bonds also fail beyond this plastic strain [-]
    plastic_strain_cap: float | None = 2.0  # element flow limit [-] (None: none)
    damping: float = 0.5  # mass damping alpha [1/s]
    contact_damping: float = 0.2  # normal contact damping ratio [-]
    clay_residual_phi: float = 12.0  # contact friction of yellow clay and core [deg]
    fill_residual_phi: float = 14.5  # contact friction of Zone I, Zone II, berm [deg]
    slip_min: float = 0.1  # slip that puts a failed interface on the slip surface [m]
    rest: float = 1e-4  # kinetic / strain energy ratio taken as rest
    frames: int = 30  # animation frames of the discrete phase (0: none)
    progress: bool = True  # progress bar of the discrete run


class ContinuumPhase(NamedTuple):
    """What the continuum phase leaves for the discrete phase.

    ``solver`` holds the last equilibrium of construction at the construction strengths
    (``Parameters.strength_factor``): the end of construction, or, when a lift collapses,
    the state with that lift active and the last fraction of its weight that found
    equilibrium (``summary["construction"]["stages"][-1]["weight_placed"]``). ``state`` is a
    copy of it, ``safety`` the strength reduction after the last complete lift (None when not
    run), ``summary`` the figures for summary.json. ``before_collapse``: when a lift
    collapsed, the solver's snapshot of the last complete lift (``PlasticSolver.restore`` it to
    get that state with the collapsing lift in place, stress-free); None when the dam was built.
    """

    solver: PlasticSolver
    state: ContinuumState
    safety: SafetyResult | None
    summary: dict[str, Any]
    before_collapse: tuple | None = None


def materials(p: Parameters) -> dict[str, Material]:
    """Thesis Table 6.3 (undrained total stress), psi = 0; the berm as Zone II (assumed).

    For the discrete phase: bonds as strong as the material, with a tension cut-off of c for
    the phi = 0 clays (assumed); separated elements slide at residual friction angles
    (yellow clay 12 deg, Zone II 14.5 deg: thesis Table 6.2; the core as the yellow clay and
    Zone I and the berm as Zone II: assumed)."""
    contact = {"contact_damping": p.contact_damping}
    fill = {"cohesion": p.fill_c, "phi": p.fill_phi, "E": p.fill_E, "nu": p.fill_nu,
            "unit_weight": p.fill_gamma, "contact_phi": p.fill_residual_phi, **contact}
    return {
        "foundation": Material(name="mudstone", E=p.foundation_E, nu=p.foundation_nu,
                               unit_weight=p.foundation_gamma, contact_phi=p.fill_phi,
                               **contact),
        "yellow_clay": Material(name="yellow clay", E=p.yellow_clay_E, nu=p.yellow_clay_nu,
                                unit_weight=p.yellow_clay_gamma, cohesion=p.yellow_clay_cu,
                                interface_tensile_strength=p.yellow_clay_cu,
                                contact_phi=p.clay_residual_phi, **contact),
        "core": Material(name="core", E=p.core_E, nu=p.core_nu, unit_weight=p.core_gamma,
                         cohesion=p.core_cu, interface_tensile_strength=p.core_cu,
                         contact_phi=p.clay_residual_phi, **contact),
        "zone_I": Material(name="Zone I", **fill),
        "zone_II": Material(name="Zone II", **fill),
        "berm": Material(name="berm", **fill),
    }


@functools.cache
def section_module() -> ModuleType:
    """``meshes/carsington.py`` (the builder, ``Section``, ``lift_tops``, ``lift_of``)."""
    spec = importlib.util.spec_from_file_location("carsington_section", SECTION)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def staged_mesh(mesh: MeshData, tops: list[float]) -> MeshData:
    """The mesh with each embankment group split into its lifts, "core:1" ... "berm:1".

    A cell's lift follows from its centroid (the gmsh section is cut at the lift tops, so no
    cell straddles two lifts); the foundation groups keep their names.
    """
    from dolfinx.mesh import compute_midpoints, meshtags

    lift_of = section_module().lift_of
    msh, tags = mesh.mesh, mesh.cell_tags
    mid = compute_midpoints(msh, 2, tags.indices)
    lift = np.array([lift_of(y, tops) for y in mid[:, 1]], dtype=np.int32)
    names = {tag: name for name, tag in mesh.cell_groups.items()}
    values = np.where(np.isin(tags.values, [mesh.cell_tag(g) for g in EMBANKMENT]),
                      100 * tags.values + lift, tags.values).astype(np.int32)
    present = np.unique(np.concatenate(mesh.comm.allgather(np.unique(values)))).tolist()
    groups = {(names[v] if v in names else f"{names[v // 100]}:{v % 100}"): v for v in present}
    new_tags = meshtags(msh, 2, tags.indices, values)
    return MeshData(msh, new_tags, mesh.facet_tags, groups, mesh.facet_groups, mesh.cell_type)


def lift_groups(mesh: MeshData, lift: int) -> list[str]:
    """Cell groups of one lift of a :func:`staged_mesh`."""
    return sorted(g for g in mesh.cell_groups if g.endswith(f":{lift}"))


def continuum_phase(p: Parameters, out: Path) -> ContinuumPhase:
    """Gravity on the foundation, the lifts to the crest (or to collapse), factors of safety;
    writes the continuum outputs to ``out``."""
    start = time.perf_counter()
    sm = section_module()
    section = dict(yellow_clay_thickness=p.yellow_clay_thickness, boot_length=p.boot_length,
                   lifts=p.lifts)
    base_mesh = build_mesh(sm.build, size=p.size, layer_size=p.layer_size, cells=p.cells,
                           **section)
    geometry = sm.Section(**section)
    tops = sm.lift_tops(geometry.crest_level, geometry.berm_top, p.lifts)
    mesh = staged_mesh(base_mesh, tops)
    table = materials(p)
    model = Model(mesh, {g: table[g.split(":")[0]] for g in mesh.cell_groups},
                  supports=[Fixed("base"), Roller("left", "x"), Roller("right", "x")])
    solver = PlasticSolver(model, degree=p.degree,
                           options=NewtonOptions(min_increment=p.min_increment))
    solver.set_strength_factor(p.strength_factor)
    comm = base_mesh.comm

    # 1. gravity on the foundation (key trench open), then displacements zeroed
    solver.set_active(list(GROUND))
    solver.apply_gravity(steps=p.gravity_steps).require()
    gravity_iterations = solver.iterations_total
    xr, yb = geometry.extent[1], geometry.extent[2]
    far = np.array([[xr - 5.0, yb + 0.5 * (geometry.foundation_level - yb)]])
    s_far = solver.state().stress_at(far)[0]
    sv = -p.foundation_gamma * (geometry.foundation_level - far[0, 1])
    k0 = p.foundation_nu / (1.0 - p.foundation_nu)
    solver.reset_displacement()

    # 2. the lifts, each placed stress-free and brought to equilibrium under its weight;
    #    a strength-reduction factor of safety after each (or the last) complete lift
    strain = _StrainAccumulator(solver)
    stages: list[dict[str, Any]] = []
    safety: SafetyResult | None = None
    safety_active = solver.active.copy()
    leak, fos_time = 0.0, 0.0
    for k in range(1, p.lifts + 1):
        t0, it0 = time.perf_counter(), solver.iterations_total
        u0 = solver.u.x.array.copy()
        before = solver.snapshot()
        analysis = solver.activate(lift_groups(mesh, k), steps=p.ramp_steps)
        bottom = geometry.foundation_level if k == 1 else tops[k - 2]
        stage: dict[str, Any] = {
            "lift": k, "top_m_OD": tops[k - 1], "completed": analysis.completed,
            "weight_placed": analysis.factor,
            "fill_level_m_OD": bottom + analysis.factor * (tops[k - 1] - bottom),
            "newton_iterations": solver.iterations_total - it0, "step_cuts": analysis.cuts,
            "wall_time_s": time.perf_counter() - t0}
        stages.append(stage)
        strain.add(solver.u.x.array - u0)
        later = np.isin(model.material_ids(), [model.material_names.index(g)
                                               for j in range(k + 1, p.lifts + 1)
                                               for g in lift_groups(mesh, j)])
        s = solver.stress.reshape(solver.sspace.num_cells, -1, 4)
        leak = max(leak, comm.allreduce(float(np.max(np.abs(s[later]), initial=0.0)),
                                        op=MPI.MAX))
        stage["yielded_cells"] = comm.allreduce(int(np.sum(np.any(
            solver.yielded.reshape(solver.sspace.num_cells, -1) > 0, axis=1))))
        stage["max_displacement_m"] = comm.allreduce(float(np.max(np.linalg.norm(
            solver.u.x.array.reshape(-1, 2), axis=1), initial=0.0)), op=MPI.MAX)
        if not analysis.completed:
            break
        if p.safety and (p.safety_every_lift or k == p.lifts):
            t0 = time.perf_counter()
            safety = _factor_of_safety(solver, p)
            safety_active = solver.active.copy()
            fos_time += time.perf_counter() - t0
            stage["factor_of_safety"] = safety.factor
            stage["fos_wall_time_s"] = time.perf_counter() - t0
    built = stages[-1]["completed"] and len(stages) == p.lifts
    state = solver.state()
    construction_time = time.perf_counter() - start - fos_time

    # outputs of the end of construction (or of the last equilibrium before collapse)
    out.mkdir(parents=True, exist_ok=True)
    eps = strain.cell_mean(state)
    figures = _construction_figures(out, base_mesh, state, eps, geometry, tops, built,
                                    solver.active.copy())
    write_continuum_xdmf(out / "continuum.xdmf", state)
    circle = None if safety is None else bishop_circle(model, safety_active)
    if safety is not None:
        figures += _safety_figures(out, base_mesh, safety, geometry, safety_active, circle)

    summary: dict[str, Any] = {
        "case": "carsington", "out": str(out), "parameters": asdict(p),
        "mesh": {"cells": comm.allreduce(base_mesh.num_owned_cells),
                 "cell_type": base_mesh.cell_type, "dofs": state.info["dofs"],
                 "groups": {g: comm.allreduce(len(base_mesh.cells(g)))
                            for g in base_mesh.cell_groups},
                 "lift_tops_m_OD": tops},
        "gravity": {"newton_iterations": gravity_iterations, "far_field_stress_kPa": s_far},
        "construction": {
            "completed": built, "stages": stages,
            "fill_level_m_OD": stages[-1]["fill_level_m_OD"],
            "max_settlement_core_m": _extreme(state, base_mesh, "core", 1, min),
            "max_upstream_displacement_m": _extreme(state, base_mesh, None, 0, min),
            "max_downstream_displacement_m": _extreme(state, base_mesh, None, 0, max),
            "yielded_cells": comm.allreduce(len(state.yielded_cells())),
            "yellow_clay_yielded_fraction": _yielded_fraction(state, base_mesh, "yellow_clay"),
            "core_yielded_fraction": _yielded_fraction(state, base_mesh, "core"),
            "newton_iterations": solver.iterations_total,
            "wall_time_s": construction_time,
        },
        "figures": [str(f) for f in figures],
        "checks": {
            "far_field_sigma_v": Check(float(s_far[1]), sv, 0.01, "kPa",
                                       "gamma z below the level ground downstream"),
            "far_field_sigma_h": Check(float(s_far[0]), k0 * sv, 0.01, "kPa",
                                       "K0 gamma z, K0 = nu / (1 - nu)"),
            "max_stress_in_unplaced_lifts": Check(leak, 0.0, 0.0, "kPa", "exactly zero"),
        },
    }
    published = uses_defaults(p, PUBLISHED_PROBLEM)
    if not built:
        summary["checks"]["fill_level_at_collapse"] = Check.published(
            stages[-1]["fill_level_m_OD"], FAILURE_FILL_LEVEL, None, "m OD",
            "fill about 1 m below the 200.5 m crest when the slope slipped (Skempton 1985)",
            applies=published)
    if safety is not None:
        lift = max(st["lift"] for st in stages if "factor_of_safety" in st)
        summary["factor_of_safety"] = {
            **safety.as_dict(), "after_lift": lift,
            "fill_level_m_OD": tops[lift - 1], "strength_factor_of_construction":
                p.strength_factor,
            "yellow_clay_yielded_fraction": _yielded_fraction(safety.state, base_mesh,
                                                              "yellow_clay"),
            "core_yielded_fraction": _yielded_fraction(safety.state, base_mesh, "core"),
            "wall_time_s": fos_time,
        }
        assert circle is not None
        summary["factor_of_safety"]["bishop"] = {
            "F": circle.factor, "centre_m": list(circle.centre), "radius_m": circle.radius,
            "entry_x_m": circle.entry, "exit_x_m": circle.exit}
        summary["checks"]["fos_vs_bishop"] = Check(
            safety.factor, circle.factor, None, "-",
            "this project's Bishop simplified search over circles, same section and lift")
        if built:
            for key, (value, source) in PUBLISHED_FOS.items():
                summary["checks"][f"fos_vs_{key}"] = Check.published(
                    safety.factor, value, None, "-", source, applies=published)
    summary["continuum_wall_time_s"] = time.perf_counter() - start
    return ContinuumPhase(solver, state, safety, summary, None if built else before)


def main(out: str | Path = "results/carsington", **overrides) -> dict:
    """Carsington Dam Ch. 725: staged construction, factor of safety, post-failure run."""
    p = Parameters(**overrides)
    out = Path(out)
    phase = continuum_phase(p, out)
    summary = phase.summary
    if p.discrete_time > 0.0:
        summary.update(discrete_phase(phase, p, out))
    write_summary(out / "summary.json", summary, phase.state.comm)
    return summary


def discrete_phase(phase: ContinuumPhase, p: Parameters, out: Path) -> dict[str, Any]:
    """Handover and the post-failure run to rest (or ``discrete_time``).

    The start: when a lift collapsed, the last complete lift's equilibrium with the
    collapsing lift in place, stress-free and with all its weight (the discrete phase places
    it in one go); otherwise the end of construction. The yielded cells grown by
    ``region_layers`` may split; the foundation (elastic, "strong base") is held.
    """
    start = time.perf_counter()
    solver = phase.solver
    if phase.before_collapse is not None:
        solver.restore(phase.before_collapse)
    hand = to_discrete(solver.state(), region=Region(layers=p.region_layers))
    if hand.discrete is None:  # MPI ranks other than 0
        return {}
    disc = hand.discrete
    names = np.array([n.split(":")[0] for n in solver.model.material_names])
    group = names[disc.element_material]  # each element's region (lifts merged)
    disc.fix(np.unique(disc.element_nodes[group == "foundation"]))
    section = section_module().Section(yellow_clay_thickness=p.yellow_clay_thickness,
                                       boot_length=p.boot_length, lifts=p.lifts)
    centroid = disc.element_centroids()
    boot = (group == "core") & (centroid[:, 1] < section.foundation_level
                                + section.boot_height)
    embankment = ~np.isin(group, GROUND)
    upstream_shoulder = np.isin(group, ["zone_I", "zone_II", "berm"]) & (centroid[:, 0] < 0.0)
    emb_nodes = np.unique(disc.element_nodes[embankment])
    top = float(disc.x[emb_nodes, 1].max())
    crest_nodes = emb_nodes[(disc.x[emb_nodes, 1] > top - 0.5)
                            & (np.abs(disc.x[emb_nodes, 0]) < 0.5 * section.crest_width + 10.0)]
    toe_node = emb_nodes[np.argmin(disc.x[emb_nodes, 0])]
    mass0, n0 = float(disc.mass.sum()), disc.n_elements
    window = (section.berm_toe - 40.0, section.downstream_toe + 20.0,
              section.foundation_level - 15.0, section.crest_level + 5.0)
    figures = [plot_configuration(out / "discrete_t0.png", disc, window=window,
                                  title="Discrete start: plastic strain, bonds intact")]
    times = [1.0, 3.0, 6.0, 10.0]

    def snapshots(s) -> bool:
        while times and s.time >= times[0]:
            figures.append(plot_configuration(
                out / f"discrete_t{times[0]:g}.png", s, window=window,
                title=f"t = {s.time:.3g} s: failed interfaces (red), plastic strain"))
            times.pop(0)
        return False

    dt = 0.5 * integrate.stable_time_step(disc, contact=True)
    n_steps = int(p.discrete_time / dt)
    res = run(disc, until_time=p.discrete_time, until_rest=p.rest, rest_min_steps=2000,
              dt=dt, damping=p.damping, split_every=10,
              split_plastic_strain=p.split_plastic_strain,
              plastic_strain_cap=p.plastic_strain_cap, on_check=snapshots, check_every=50,
              output_every=max(n_steps // p.frames, 1) if p.frames else 0,
              out_dir=out / "discrete", progress=p.progress)
    slip = interface_slip(disc)
    on_surface = ~disc.interface_intact & (slip >= p.slip_min)
    surface = disc.x[disc.interface_nodes[on_surface][:, :2]]
    figures.append(plot_configuration(
        out / "discrete_final.png", disc, window=window,
        lines={f"slip surface: slipped >= {p.slip_min:g} m": surface},
        title=f"t = {res.time:.3g} s ({res.stop_reason})"))
    pairs = disc.interface_elements[on_surface]
    through_clay = int(np.sum((group[pairs] == "yellow_clay").any(axis=1)))
    through_boot = int(np.sum(boot[pairs].any(axis=1)))
    u = disc.x - disc.x_ref
    shoulder_dx = float(np.mean(u[disc.element_nodes[upstream_shoulder]][..., 0]))
    crest_drop = -float(np.mean(u[crest_nodes, 1]))
    toe_dx = float(u[toe_node, 0])
    h = res.history
    checks = {
        "slip_surface_through_yellow_clay": Check(float(through_clay > 0), 1.0, 0.0, "-",
                                                  f"failed interfaces slipped >= {p.slip_min}"
                                                  " m with a yellow-clay element"),
        "slip_surface_through_boot": Check(float(through_boot > 0), 1.0, 0.0, "-",
                                           f"failed interfaces slipped >= {p.slip_min} m "
                                           "with an element of the core's boot"),
        "shoulder_moves_upstream": Check(float(shoulder_dx < 0.0), 1.0, 0.0, "-",
                                         "mean x-displacement of the upstream shoulder < 0"),
        "energy_excess_over_sources": Check(energy_excess(h), 0.0, 0.01, "-",
                                            "E_kin + E_strain + E_contact <= E(0) + work"),
        "elements_conserved": Check(float(disc.n_elements), float(n0), 0.0),
        "mass_conserved": Check(float(disc.mass.sum()), mass0, 1e-12, "t/m"),
        "upstream_toe_movement": Check.published(
            -toe_dx, 12.0, None, "m", "observed: upstream toe moved about 11-13 m",
            applies=uses_defaults(p, PUBLISHED_PROBLEM)),
        "crest_drop": Check.published(
            crest_drop, 10.0, None, "m", "observed: crest dropped about 10 m (at the full "
            "height)", applies=uses_defaults(p, PUBLISHED_PROBLEM)),
    }
    trace = slip_trace(disc, on_surface)
    by_threshold = {}
    for t in (p.slip_min, 0.5, 1.0, 2.0):
        k = ~disc.interface_intact & (slip >= t)
        ie = disc.interface_elements[k]
        by_threshold[f"{t:g}"] = {"interfaces": int(k.sum()),
                                  "yellow_clay": int((group[ie] == "yellow_clay").any(1).sum()),
                                  "boot": int(boot[ie].any(axis=1).sum())}
    return {
        "handover": hand.report,
        "discrete": {
            "start": "last complete lift + collapsing lift placed at once"
                     if phase.before_collapse is not None else "end of construction",
            "elements": disc.n_elements, "dt_s": res.dt, "steps": res.steps,
            "time_s": res.time, "stop": res.stop_reason, "wall_time_s": res.wall_time,
            "phase_wall_time_s": time.perf_counter() - start,
            "interfaces_failed": int((~disc.interface_intact).sum()),
            "slip_surface_interfaces": int(on_surface.sum()),
            "slip_surface_yellow_clay": through_clay, "slip_surface_boot": through_boot,
            "slip_surface_trace_m": trace, "slipped_interfaces_by_threshold_m": by_threshold,
            "upstream_shoulder_mean_dx_m": shoulder_dx,
            "upstream_toe_dx_m": toe_dx, "crest_drop_m": crest_drop,
            "max_upstream_movement_m": float(-u[emb_nodes, 0].min()),
            "energy_peak_over_supply": energy_peak_ratio(h),
            "figures": [str(f) for f in figures],
            "outputs": [str(f) for f in res.files if f.suffix != ".png"],
        },
        "checks": {**phase.summary["checks"], **checks},
    }


def interface_slip(state) -> np.ndarray:
    """Relative movement [m] of the two sides of every interface (mean over its two node
    pairs, which coincided at the start)."""
    n = state.interface_nodes
    return 0.5 * (np.linalg.norm(state.x[n[:, 0]] - state.x[n[:, 2]], axis=1)
                  + np.linalg.norm(state.x[n[:, 1]] - state.x[n[:, 3]], axis=1))


def slip_trace(state, on_surface: np.ndarray, width: float = 5.0) -> list[list[float]]:
    """The slip surface as (x, y) [m, m OD] in the start geometry: in each ``width`` strip
    of x, the deepest slipping interface's midpoint."""
    mid = state.x_ref[state.interface_nodes[on_surface][:, :2]].mean(axis=1)
    trace = []
    for b in np.unique(np.floor(mid[:, 0] / width)):
        k = np.floor(mid[:, 0] / width) == b
        trace.append(mid[k][np.argmin(mid[k, 1])].tolist())
    return trace


# --- helpers -----------------------------------------------------------------------------
class _StrainAccumulator:
    """Strain of the fill counted from placement: sum over stages of eps(du) in active cells
    (the total displacement field cannot give it: a lift's nodes start at zero while the
    nodes at its base have already moved)."""

    def __init__(self, solver: PlasticSolver) -> None:
        from dolfinx import fem

        from hybrid.continuum.fields import strain

        self.solver = solver
        self.du = fem.Function(solver.disc.V)
        self.expr = fem.Expression(strain(self.du), solver.disc.points)
        n, nqp = solver.sspace.num_cells, solver.disc.num_points
        self.total = np.zeros((n, nqp, 4))

    def add(self, du: np.ndarray) -> None:
        self.du.x.array[:] = du
        self.du.x.scatter_forward()
        n = self.total.shape[0]
        values = self.expr.eval(np.arange(n, dtype=np.int32)).reshape(self.total.shape)
        self.total[self.solver.active] += values[self.solver.active]

    def cell_mean(self, state: ContinuumState) -> np.ndarray:
        """Area-weighted cell means (n_cells, 4) [-]."""
        import ufl

        from hybrid.continuum.quadrature import evaluate_at_points

        jac = evaluate_at_points(state.disc, abs(ufl.JacobianDeterminant(state.mesh)))[..., 0]
        w = jac * state.disc.weights[None, :]
        return np.einsum("cq,cqk->ck", w, self.total) / w.sum(axis=1)[:, None]


def _factor_of_safety(solver: PlasticSolver, p: Parameters) -> SafetyResult:
    """Strength reduction from the solver's state, which is restored afterwards."""
    snap = solver.snapshot()
    result = factor_of_safety(solver, search=StrengthSearch(
        initial_increment=p.fos_step, max_increment=max(p.fos_step, 0.25),
        tolerance=p.fos_tolerance))
    solver.restore(snap)
    return result


def _extreme(state: ContinuumState, mesh: MeshData, group: str | None, component: int,
             pick: Any) -> float:
    """Smallest/largest cell-mean displacement component [m] (in a group or everywhere)."""
    u = state.cell_displacement()[:, component]
    if group is not None:
        u = u[mesh.cells(group)]
    values = state.comm.allgather(float(pick(u)) if len(u) else None)
    return float(pick(v for v in values if v is not None))


def _yielded_fraction(state: ContinuumState, mesh: MeshData, group: str) -> float:
    cells = mesh.cells(group)
    hit = int(np.isin(state.yielded_cells(), cells).sum())
    return state.comm.allreduce(hit) / max(state.comm.allreduce(len(cells)), 1)


def _construction_figures(out: Path, mesh: MeshData, state: ContinuumState, eps: np.ndarray,
                          geometry: Any, tops: list[float], built: bool,
                          active: np.ndarray) -> list[Path]:
    """Stress contours, displacement vectors, core profiles, vertical strain, yielded zone
    (fill not yet placed is left blank)."""
    when = "end of construction" if built else "last equilibrium before collapse"
    blank = np.where(active, 1.0, np.nan)
    stress = state.cell_stress()
    fields = [(f"end_of_construction_{name}.png", stress[:, i], f"{name} [kPa], {when}",
               f"{name} [kPa] (tension +)", cmap)
              for i, name, cmap in ((1, "sigma_yy", "viridis"), (0, "sigma_xx", "viridis"),
                                    (3, "sigma_xy", "RdBu_r"))]
    fields += [("end_of_construction_yielded.png", np.any(state.yielded > 0, axis=1),
                f"Yielded zone, {when}", "yielded (1) [-]", "Reds"),
               ("end_of_construction_vertical_strain.png", eps[:, 1],
                f"Vertical strain from placement, {when}", "eps_yy [-]", "viridis")]
    figures = []
    for name, values, title, label, cmap in fields:
        path = plot_cell_field(out / name, mesh, blank * values, title=title, label=label,
                               cmap=cmap, symmetric=(cmap == "RdBu_r"),
                               overlay=_zoom(geometry))
        if path is not None:
            figures.append(path)
    polys, vectors = gather_cells(mesh, state.cell_displacement())
    _, eps_all = gather_cells(mesh, eps[:, 1])
    in_core = np.zeros(mesh.num_owned_cells)
    in_core[mesh.cells("core")] = 1.0
    _, core_flag = gather_cells(mesh, in_core * active)
    _, placed_flag = gather_cells(mesh, active.astype(float))
    ys = np.linspace(geometry.foundation_level - geometry.trench_depth + 0.1,
                     geometry.crest_level - 0.1, 80)
    u_axis = state.displacement_at(np.column_stack([np.zeros_like(ys), ys]))
    if polys is None:
        return figures
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    centres = polys.mean(axis=1)
    fig, ax = plt.subplots(figsize=(11, 4.5), dpi=120)
    show = ((centres[:, 0] > geometry.berm_toe - 30.0)
            & (centres[:, 0] < geometry.downstream_toe + 30.0) & (centres[:, 1] > 140.0)
            & (placed_flag > 0.5))
    magnitude = np.linalg.norm(vectors, axis=1)
    q = ax.quiver(centres[show, 0], centres[show, 1], vectors[show, 0], vectors[show, 1],
                  magnitude[show], cmap="viridis", angles="xy", scale_units="xy",
                  scale=float(np.max(magnitude[show], initial=1e-12)) / 6.0, width=0.0015)
    for poly in polys[show]:
        ax.fill(poly[:, 0], poly[:, 1], facecolor="none", edgecolor="0.85", linewidth=0.2)
    ax.set_aspect("equal")
    ax.set_xlabel("x from the axis [m] (upstream to the left)")
    ax.set_ylabel("elevation [m OD]")
    ax.set_title(f"Displacement vectors (from placement), {when}; longest = 6 m on the plot")
    fig.colorbar(q, ax=ax, label="|u| [m]", shrink=0.8)
    fig.tight_layout()
    figures.append(out / "end_of_construction_displacement_vectors.png")
    fig.savefig(figures[-1])
    plt.close(fig)

    fig, (a1, a2) = plt.subplots(1, 2, figsize=(9, 5), dpi=120, sharey=True)
    core = core_flag > 0.5
    placed = ys <= np.max(polys[core, :, 1], initial=ys[0])
    a1.plot(u_axis[placed, 0] * 1000.0, ys[placed], "k-")
    a1.set_xlabel("horizontal displacement at the axis [mm] (+ downstream)")
    a1.set_ylabel("elevation [m OD]")
    a2.plot(-eps_all[core] * 100.0, centres[core, 1], "o", ms=2.5)
    a2.set_xlabel("vertical compression -eps_yy, core cells [%]")
    for ax in (a1, a2):
        for top in tops:
            ax.axhline(top, color="0.8", linewidth=0.5)
        ax.grid(alpha=0.3)
    fig.suptitle(f"Core, {when} (grey lines: lift tops)")
    fig.tight_layout()
    figures.append(out / "end_of_construction_core_profiles.png")
    fig.savefig(figures[-1])
    plt.close(fig)
    return figures


def _zoom(geometry: Any) -> Any:
    """Plot overlay: the embankment and the top of the foundation only."""
    def zoom(ax: Any) -> None:
        ax.set_xlim(geometry.berm_toe - 30.0, geometry.downstream_toe + 30.0)
        ax.set_ylim(geometry.foundation_level - 25.0, geometry.crest_level + 3.0)

    return zoom


def _safety_figures(out: Path, mesh: MeshData, safety: SafetyResult, geometry: Any,
                    active: np.ndarray, circle: SlipCircle) -> list[Path]:
    state = safety.state
    zoom = _zoom(geometry)
    arc = circle.arc()

    def overlay(ax: Any) -> None:
        zoom(ax)
        ax.plot(arc[:, 0], arc[:, 1], "r--", lw=1.2,
                label=f"critical circle (Bishop), F = {circle.factor:.2f}")
        ax.legend(loc="lower left", fontsize=7)

    fields = [("fos_plastic_strain.png", state.cell_plastic_strain(),
               f"Plastic strain at F = {safety.factor:.3f}", "plastic strain [-]", "magma_r")]
    if any(ok for _, ok, _ in safety.trials):  # a reduction step converged: a mechanism
        fields.append(("fos_mechanism.png",
                       np.linalg.norm(state.cell_displacement(safety.mechanism), axis=1),
                       "Failure mechanism: displacement increment of the last reduction step",
                       "|du| [m]", "viridis"))
    figures = []
    for name, values, title, label, cmap in fields:
        path = plot_cell_field(out / name, mesh, np.where(active, values, np.nan), title=title,
                               label=label, cmap=cmap, overlay=overlay)
        if path is not None:
            figures.append(path)
    return figures


if __name__ == "__main__":
    from hybrid.case import run_case

    raise SystemExit(run_case(main, Parameters))
