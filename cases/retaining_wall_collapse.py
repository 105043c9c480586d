"""H3: the backfill of a retaining wall collapses when the wall is removed (thesis 5.4.2).

Objective
    The hybrid pipeline on a cohesionless backfill: continuum active state, handover, then the
    wall taken away and the backfill followed as it fails and runs out to rest; the angle of the
    failure wedge is measured from the zone that moves and compared with Rankine's
    45 + phi / 2.
Problem
    The thesis wall: H = 10 m, dry sand phi = 30 deg, c = 0, gamma = 16.5 kN/m3, E = 70 MPa,
    nu = 0.35, psi = phi (associated, as Rankine's theory assumes; with psi = 0 the continuum's
    shear band leaves the heel at about 50 deg, between Coulomb and Roscoe). The backfill
    (``length`` = 2 H) stands on a 1 m ground layer (elastic, same E and gamma) that runs on
    ``front`` = 2 H in front of the wall, where the collapsed sand spreads. Rough base (the
    backfill is tied to the ground), smooth wall, quadrilaterals of ``size``: a structured grid,
    or gmsh's unstructured quadrilaterals with ``structured`` false (``meshes/wall.py``).
Set-up
    1. Continuum (dolfinx, Q2): gravity switched on with the wall held (at rest); active
       stage: the wall translated ``translation`` away from the backfill (thrust against
       Rankine, K_a = 1/3); passive stage on a copy (``passive_translation`` toward the
       backfill, K_p = 3), reported.
    2. Handover of the active state: every cell becomes a Q4 element; the backfill's
       interfaces may split (bond strength = the sand's: c = 0, phi, no tension); the ground is
       held (a rigid base and run-out surface).
    3. Discrete: the wall is removed (its nodes released) and the backfill is followed until
       rest. The sand is perfectly plastic and sets no expert option: its bonds fail in
       tension, and an element that has distorted as far as an element can follow the flow
       parts from its neighbours and goes on as a fragment that yields no further
       (``hybrid.discrete.ties.DISTORTION_LIMIT``).
Verification
    Wedge angle: the back of the zone that moves (at each level of the backfill, walking out
    from the wall, the last element that has moved ``MOVING_FRACTION`` = 5 % of the face
    top's movement before the first that has not; reference shape:
    ``hybrid.discrete.measures.moving_zone_back``) is fitted with a straight line; its
    inclination when the top
    of the wall face has moved ``wedge_at`` = 0.1 H is compared with 45 + phi/2 = 60 deg (bar
    5 deg). The same fit at 0.01 H ... 0.2 H of movement and at rest is reported: the scarp
    retreats and flattens as the debris runs out. The run must
    reach rest (E_kin <= ``rest`` x its peak, and gravity no longer working:
    ``hybrid.discrete.options.drift_ratio`` <= 1 %) with bounded energy (E_kin + E_strain +
    E_contact never above the initial energy plus the work of gravity) and keep its elements
    and mass. Reported: the run-out
    (the toe of the continuous deposit in front of the wall: ``hybrid.discrete.measures.
    deposit``; an element flung beyond bare ground is counted apart, with the farthest element's
    position), the final slope angle, the active / passive thrusts against Rankine.
References
    Rankine (1857); G. S. Bala (2008), thesis, section 5.4.2.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from hybrid.continuum import PlasticSolver
from hybrid.continuum.series import ContinuumSeries
from hybrid.discrete.energy import energy_excess, energy_peak_ratio
from hybrid.discrete.figures import plot_configuration
from hybrid.discrete.measures import MOVING_FRACTION, deposit, moving_zone_back
from hybrid.discrete.outputs import standard_outputs
from hybrid.discrete.solver import ExplicitSolver, RunOptions
from hybrid.figures import engineering_figures
from hybrid.geometry import build_mesh, load_builder
from hybrid.handover import Region, to_discrete
from hybrid.io import CaseSummary, Check, plot_cell_field, write_continuum_xdmf
from hybrid.materials import Bond, Contact, Material
from hybrid.model import Displacement, Fixed, Model, Roller
from hybrid.parameters import CaseParameters, param
from hybrid.report import plot_energy, plot_thrust_translation

MESHES = Path(__file__).resolve().parent.parent / "meshes"


@dataclass
class Parameters(CaseParameters):
    height: float = param(10.0, gt=0)  # wall height H [m]
    length: float = param(20.0, gt=0)  # backfill modelled behind the wall [m]
    front: float = param(20.0, gt=0)  # ground in front of the wall [m]
    size: float = param(0.5, gt=0)  # element size [m]
    structured: bool = True  # structured quadrilateral grid (false: gmsh's unstructured quads)
    unit_weight: float = 16.5  # gamma [kN/m3]
    phi: float = 30.0  # [deg]
    psi: float = 30.0  # dilation [deg] (associated, as Rankine's theory and C8)
    E: float = 70_000.0  # [kPa]
    nu: float = 0.35  # [-]
    translation: float = param(0.02, gt=0)  # active wall movement in the continuum [m]
    passive_translation: float = param(0.4, ge=0)  # passive stage (0: skipped) [m]
    steps: int = param(10, ge=1)  # continuum increments per stage
    contact_damping: float = param(0.2, ge=0, le=1)  # normal contact damping ratio zeta [-]
    mass_damping: float = param(1.0, ge=0)  # mass damping alpha [1/s]
    wedge_at: float = param(1.0, gt=0)  # face-top movement at which the wedge is measured (0.1 H)
    #                                     [m]
    max_time: float = param(30.0, gt=0)  # give up after this time [s]
    rest: float = param(1e-4, gt=0)  # kinetic / strain energy ratio taken as rest
    output_every: int = param(1000, ge=0)  # discrete steps between outputs (0: none)
    progress: bool = True  # progress bar of the discrete runs


def main(out: str | Path = "results/retaining_wall_collapse", **overrides) -> CaseSummary:
    """Retaining wall removed: continuum active state, handover, collapse to rest (H3)."""
    p = Parameters(**overrides)
    out = Path(out)
    mesh = build_mesh(load_builder(MESHES / "wall.py"), height=p.height, length=p.length,
                      front=p.front, size=p.size, cells="quadrilateral",
                      structured=p.structured)
    sand = Material(name="sand", E=p.E, nu=p.nu, unit_weight=p.unit_weight, cohesion=0.0, phi=p.phi,
                    psi=p.psi, plastic=True, bond=Bond(tensile_strength=0.0),
                    contact=Contact(damping=p.contact_damping))
    ground = Material(name="ground", E=p.E, nu=p.nu, unit_weight=p.unit_weight,
                      contact=Contact(phi=p.phi, damping=p.contact_damping))
    # the ground is only a support in the continuum: the backfill base is held (rough; it also
    # holds the heel node, which the wall's prescribed movement would otherwise drag through
    # the elastic ground)
    supports = [Fixed("base"), Roller("right", "x"), Roller("left", "x")]

    def continuum(move: float) -> tuple[PlasticSolver, list[float], list[float]]:
        model = Model(mesh, {"backfill": sand, "ground": ground},
                      supports=[Displacement("wall", ux=move), *supports,
                                Fixed("backfill_base")])
        solver = PlasticSolver(model, degree=2)
        solver.apply_gravity(steps=2).require()
        thrust = [abs(solver.reaction("wall", 0))]
        solver.monitors["thrust"] = lambda: abs(solver.reaction("wall", 0))
        stage = "active" if move < 0 else "passive"
        # the stage's steps as a time series, the time the wall's translation
        with ContinuumSeries(out / f"continuum_{stage}.xdmf", solver,
                             meaning=f"load factor = wall translation / {abs(move):g} m "
                                     f"({stage})") as series:
            analysis = solver.ramp(1.0, p.steps)
        series_reports[stage] = series.report()
        moves = [0.0] + [r.load_factor * abs(move) for r in solver.history
                         if "thrust" in r.monitors]
        thrust += [r.monitors["thrust"] for r in solver.history if "thrust" in r.monitors]
        # stopped short: only on the limit (the thrust falls to active, rises to passive)
        analysis.require_limit(moves, thrust if move > 0 else [-t for t in thrust])
        return solver, moves, thrust

    # 1. continuum: at rest, active (and passive) translation of the smooth wall
    series_reports: dict[str, dict] = {}
    solver, moves, thrust = continuum(-p.translation)
    state = solver.state()
    ka = math.tan(math.radians(45.0 - p.phi / 2.0)) ** 2
    half_gh2 = 0.5 * p.unit_weight * p.height**2
    checks = {"active_thrust": Check(thrust[-1], ka * half_gh2, None, "kN/m",
                                     "report: Rankine K_a (rough base: below it, see C8)")}
    summary = CaseSummary("retaining_wall_collapse (H3)", out, p, results={
        "continuum": {"cells": state.info["cells"],
                      "wall_time_s": state.info["wall_time_s"],
                      "at_rest_thrust_kN_per_m": thrust[0],
                      "active": {"translation_m": moves, "thrust_kN_per_m": thrust}}},
        checks=checks)
    if p.passive_translation > 0.0:
        _, pm, pt = continuum(p.passive_translation)
        kp = 1.0 / ka
        summary["continuum"]["passive"] = {"translation_m": pm, "thrust_kN_per_m": pt}
        checks["passive_thrust"] = Check(pt[-1], kp * half_gh2, None, "kN/m",
                                         "report: Rankine K_p")
    if state.comm.rank == 0:
        passive = summary["continuum"].get("passive")
        plot_thrust_translation(
            out / "thrust_translation.png", moves, thrust,
            {"Rankine active": ka * half_gh2, "Rankine passive": half_gh2 / ka},
            label="active", title="H3: smooth wall, rough base",
            more={"passive": (passive["translation_m"], passive["thrust_kN_per_m"])}
            if passive else None)
    summary["continuum"]["series"] = series_reports
    write_continuum_xdmf(out / "continuum.xdmf", state)
    plot_cell_field(out / "handover_plastic_strain.png", state.model.mesh,
                    state.cell_plastic_strain(), title="Active state: plastic strain",
                    label="plastic strain [-]", cmap="magma_r")
    engineering_figures(out, state, prefix="active_",
                        when=f"wall moved {p.translation:g} m away",
                        window=(-0.25 * p.front, -1.0, p.length, 1.05 * p.height))

    # 2. handover: the backfill may split, the ground is held
    hand = to_discrete(state, region=Region(group="backfill"))
    if hand.discrete is None:  # MPI ranks other than 0 stop here
        return summary
    disc = hand.discrete
    summary["handover"] = hand.report
    backfill = hand.splittable.copy()  # the region is the backfill group
    disc.fix(np.unique(disc.element_nodes[~backfill]))
    wall = hand.boundary_nodes["wall"]
    disc.fixed[wall, 0] = False  # 3. the wall is removed
    disc.primed = False
    top = wall[np.argmax(disc.x[wall, 1])]
    x_top = float(disc.x[top, 0])
    mass0, n0 = float(disc.mass.sum()), disc.n_elements
    window = (-p.front, -1.0, p.length, 1.1 * p.height)
    plot_configuration(out / "discrete_start.png", disc, window=window,
                       title="Discrete start (active state): plastic strain")
    # the back of the moving zone as the face top moves: fractions of H, the bar at wedge_at
    marks = sorted({p.wedge_at, *(f * p.height for f in (0.01, 0.02, 0.05, 0.1, 0.2))})
    wedge: dict[str, dict] = {}

    def watch(s) -> bool:
        moved = x_top - s.x[top, 0]
        while marks and moved >= marks[0]:
            angle, a = moving_zone_back(s, backfill, p.height, p.size,
                                        MOVING_FRACTION * marks[0])
            wedge[f"{marks[0]:g}"] = {"time_s": s.time, "angle_deg": angle, "intercept_m": a}
            if marks[0] == p.wedge_at:
                rk = 1.0 / math.tan(math.radians(45.0 + p.phi / 2.0))
                ck = 1.0 / math.tan(math.radians(angle))
                lines = {f"back of the moving zone: {angle:.1f} deg": [
                             [[a, 0.0], [a + p.height * ck, p.height]]],
                         "45 + phi/2": [[[a, 0.0], [a + p.height * rk, p.height]]]}
                plot_configuration(out / "wedge.png", s, window=(-5.0, -1.0, 15.0, 11.0),
                                   lines=lines, reference=True,
                                   title=f"t = {s.time:.3g} s, face top moved {moved:.2g} m "
                                         "(reference shape)")
            marks.pop(0)
        return False

    options = RunOptions(
        mass_damping=p.mass_damping, split_every=10,
        contact_bounds=(-p.front - p.height, -2.0, p.length + 1.0, 2.0 * p.height))
    outputs = standard_outputs(out / "discrete", output_every=p.output_every,
                               progress=p.progress)
    with ExplicitSolver(disc, options, observers=outputs) as solver:
        res = solver.run(until_rest=p.rest, until_time=p.max_time, rest_min_steps=5000,
                         on_check=watch, check_every=50)
    h = res.history
    sand_nodes = np.unique(disc.element_nodes[backfill])
    # the toe of the continuous deposit, followed from the back of the backfill towards the
    # front (a grain flung beyond bare ground is not the run-out)
    spread = deposit(disc, backfill, wall_x=p.length, bin_width=p.size, direction=-1)
    toe = float(disc.x[disc.element_nodes[spread.elements], 0].min())
    angle = wedge.get(f"{p.wedge_at:g}", {}).get("angle_deg", float("nan"))
    rest_angle, rest_a = moving_zone_back(disc, backfill, p.height, p.size,
                                          MOVING_FRACTION * (x_top - disc.x[top, 0]))
    checks["wedge_angle"] = Check(angle, 45.0 + p.phi / 2.0, 5.0 / (45.0 + p.phi / 2.0), "deg",
                                  f"45 + phi/2, within 5 deg; face top moved {p.wedge_at:g} m")
    checks["energy_excess_over_sources"] = Check(
        energy_excess(h, res.start), 0.0, 0.01, "-",
        "E_kin + E_strain + E_contact <= E(0) + work of gravity")
    checks.update(res.rest_checks(p.rest))
    checks["elements_conserved"] = Check(float(disc.n_elements), float(n0), 0.0)
    checks["mass_conserved"] = Check(float(disc.mass.sum()), mass0, 1e-12, "t/m")
    summary["discrete"] = {
        "elements": disc.n_elements, "dt_s": res.dt, "steps": res.steps, "time_s": res.time,
        "stop": res.stop_reason, "wall_time_s": res.wall_time,
        "element_steps_per_s": res.element_steps_per_s,
        "wedge_angle_deg": angle, "moving_zone_back_by_face_movement_m": wedge,
        "moving_zone_back_at_rest": {"angle_deg": rest_angle, "intercept_m": rest_a},
        "interfaces_failed": int((~disc.interface_intact).sum()),
        "toe_x_m": toe, "runout_m": -toe, "detached_elements": spread.detached,
        "farthest_element_x_m": float(disc.x[sand_nodes, 0].min()),
        "final_slope_deg": final_slope(disc, sand_nodes, p.height),
        "energy_peak_over_supply": energy_peak_ratio(h, res.start),
    }
    summary.write(out / "summary.json")
    plot_energy(out / "energy.png", h)
    plot_configuration(out / "final.png", disc, window=window, outline=True,
                       title=f"{res.ending}: run-out {-toe:.3g} m")
    return summary


def final_slope(state, nodes: np.ndarray, height: float) -> float:
    """Mean angle [deg] of the sand surface between 10 % and 90 % of its final height:
    the surface as the highest node in 0.5 m columns, fitted with a line."""
    x, y = state.x[nodes, 0], state.x[nodes, 1]
    top = y.max()
    cols = np.floor(x / 0.5)
    xs, ys = [], []
    for c in np.unique(cols):
        k = cols == c
        yy = y[k].max()
        if 0.1 * top < yy < 0.9 * top:
            xs.append(x[k][np.argmax(y[k])])
            ys.append(yy)
    if len(xs) < 2:
        return float("nan")
    slope = np.polyfit(xs, ys, 1)[0]
    return math.degrees(math.atan(abs(slope)))


if __name__ == "__main__":
    from hybrid.case import run_case

    raise SystemExit(run_case(main, Parameters))
