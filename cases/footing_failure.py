"""H2: a strip footing pushed past collapse and followed as it fails (thesis 5.4.1).

Objective
    The hybrid pipeline end to end: continuum load-settlement to collapse, handover to
    discrete elements, the failure followed under a pressure above the
    collapse load, then unloading and rest.
Problem
    The thesis footing: B = 1.2 m strip, soil c = 69 kPa, phi = 20 deg (Table 5.1 strengths),
    psi = 0, gamma = 20 kN/m3 (assumed), E = 100 MPa, nu = 0.3; half model by symmetry. Beyond
    the thesis, the soil softens (assumed: a clay losing most of its cohesion, c_r = 10 kPa,
    phi_r = phi, over a slip of u_r = 0.2 m across the shear band, the order of the slips
    at which clays reach residual in ring shear, Skempton 1985).
Set-up
    1. Continuum (dolfinx, degree 2 on unstructured gmsh quadrilaterals; ``cells`` and
       ``structured`` choose triangles or a structured mesh): gravity switched on, then the
       footing pressure raised until Newton finds no equilibrium: the last converged pressure
       is the collapse load (compare Terzaghi / Meyerhof / Vesic, C7) when the settlement ran
       away there (its rate per kPa at least 10 times the initial one); otherwise the case
       stops. ``continuum_control=settlement`` drives the footing's mean settlement instead
       (indirect displacement control, up to ``continuum_settlement``, 0.1 m, in
       ``continuum_steps`` increments) until the pressure has fallen ``PEAK_FALL`` (1 %)
       below its largest value: that peak is the collapse load and the handover state; a
       path whose pressure never falls (Newton stalled, or the settlement ended first)
       stops the case. The continuum's steps, iterations and time count the increments past
       the peak too. ``continuum_hold_flipping=true`` retries an increment whose Newton
       iterates cycle holding its flipping points elastic (``NewtonOptions.hold_flipping``),
       to tell a stall from the collapse.
    2. Handover at the last converged state: every cell becomes a Q4 (or T3) element;
       every bond may fail where its strength is exceeded (interface strength = the soil's
       c, phi, tension cut-off c cot phi) and no element is held (``region_layers`` and
       ``freeze_layers`` restrict both to so many cell layers around the yielded cells, a
       sensitivity only: N layers are N element sizes, so the region would shrink as the
       mesh is refined).
    3. Discrete (numba): the footing's nodes tied into one rigid rough platen
       (``DiscreteState.tie_rigidly``) carrying the same total load; the pressure raised to
       ``pressure`` (1 800 kPa) over ``ramp_time``, held until the footing has settled
       ``target_settlement`` (0.5 m), removed over ``ramp_time``, then run to rest. Bonds fail
       by the strength criteria and where the soil beside them has softened to residual; a
       failed bond carries the residual strength (c_r + sigma_n tan phi_r, ``Contact``).
       The rigid platen is the real footing. ``control=punch`` drives it by displacement
       instead, as a load test on a rigid footing (``hybrid.discrete.runs.PunchProgram``):
       pushed down at ``punch_speed`` (0.25 m/s, reached over ``punch_ramp_time``) to
       ``target_settlement`` (in target / speed + ramp / 2: 2.25 s), the bearing pressure
       measured from the work of the push, then the pressure it carried removed over
       ``punch_ramp_time`` (0.5 s: several periods of the soil layer's fundamental modes,
       quarter-wave 4 H / V_p = 0.05 s and 4 H / V_s = 0.09 s for H = 3 m, so that the load
       comes off slowly against them; removed over 0.05 s instead, from a push at 1 m/s, it
       leaves the intact soil vibrating with nothing to damp it and, with the far side
       reflecting, the default mesh's run does not come to rest);
       the summary adds the mean bearing pressure over the push and over its last fifth. The
       speed is slow enough that halving it moves the measures by a few per cent
       (docs/hybrid.md).
       No mass damping (``mass_damping`` = 0, as Carsington): it would drag every element as
       through a viscous fluid, and it does not decide the result: the energy of the punch
       goes into plastic work, friction and contact damping, and rest is judged by the
       kinetic energy and by the loads having stopped working, neither of which depends on
       alpha. With alpha = 0.5 ... 2 /s the settlement and heave at rest were within 10 % of
       the undamped run's (measured with the far side reflecting, below), a little smaller as
       alpha grows (damping brakes the footing while the load comes off).
       The far side (x = ``width``) is where the model stops, not where the ground does: in
       the discrete phase it is a transmitting boundary (``far_boundary``, default
       "transmitting": the roller keeps the soil from moving across it and viscous dashpots
       rho V_s per unit length on the vertical velocity let the shear waves of the punch and
       of the unloading leave, Lysmer & Kuhlemeyer 1969, ``Roller(transmitting=True)``; the
       held horizontal component still reflects pressure waves). As a plain roller
       ("reflecting") it sends them back and the soil rings in the model's box for longer
       (docs/hybrid.md). The base stays fixed (a rough rigid base, which reflects) and the
       symmetry plane a roller (a plane of symmetry reflects by definition).
Verification (H2 has no closed form)
    Bars: rest after unloading (E_kin <= ``rest`` x its peak, and the loads no longer
    working: ``hybrid.discrete.options.drift_ratio`` <= 1 %), bounded energy (E_kin +
    E_strain + E_contact at most 1 % of the supply above E(0) + work of loads and gravity),
    element count and mass unchanged. Reported: the collapse load against the classical
    estimates, the settlement at unloading, heave beside the footing, failed interfaces.
    Mesh study (docs/hybrid.md, "Mesh sensitivity"): the collapse load within 3 % on the
    default, refined and structured quadrilateral meshes; the heave at rest within 10 % on
    the default mesh and its refinement (not across mesh types: the structured mesh heaves
    and settles further); the settlement at rest moves by more (the footing runs on further
    while unloaded on the refined mesh): not verified. Under ``control=punch`` the mean
    bearing pressure and the heave at rest are within 10 % on the default mesh and one
    refinement (not across mesh types: the structured mesh heaves further); the settlement
    is prescribed up to the rise as the load comes off, and that rise is not converged.
References
    G. S. Bala (2008), thesis, section 5.4.1 (the footing is loaded to 1 800 kPa there).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from hybrid.continuum import DisplacementControl, NewtonOptions, PlasticSolver
from hybrid.continuum.series import ContinuumSeries
from hybrid.discrete.energy import energy_excess, energy_peak_ratio, phase_history
from hybrid.discrete.figures import plot_configuration
from hybrid.discrete.measures import FootingMarks
from hybrid.discrete.outputs import standard_outputs
from hybrid.discrete.runs import LoadProgram, PunchProgram
from hybrid.discrete.solver import ExplicitSolver, RunOptions
from hybrid.errors import StageIncomplete
from hybrid.figures import engineering_figures
from hybrid.geometry import build_mesh, load_builder
from hybrid.handover import Region, to_discrete
from hybrid.io import CaseSummary, Check, plot_cell_field, write_continuum_xdmf
from hybrid.materials import Bond, Contact, Material, Strength
from hybrid.model import Fixed, Model, Pressure, Roller
from hybrid.parameters import CELLS, CaseParameters, ParameterError, param
from hybrid.references import strip_footing_estimates
from hybrid.report import plot_energy, plot_load_settlement

MESHES = Path(__file__).resolve().parent.parent / "meshes"
#: (continuum_control=settlement) the pressure's fall below its largest value that shows the
#: peak passed [-]: a fall in the Newton tolerance's noise is far smaller
PEAK_FALL = 0.01


@dataclass
class Parameters(CaseParameters):
    cohesion: float = 69.0  # c [kPa]
    phi: float = 20.0  # [deg]
    psi: float = 0.0  # [deg]
    residual_cohesion: float = param(10.0, ge=0)  # c_r [kPa]
    residual_phi: float = param(20.0, ge=0)  # phi_r [deg]
    softening_displacement: float = param(0.2, gt=0)  # u_r: slip from peak to residual [m]
    unit_weight: float = 20.0  # gamma [kN/m3] (assumed)
    E: float = 100_000.0  # [kPa]
    nu: float = 0.3  # [-]
    footing_width: float = param(1.2, gt=0)  # B [m]
    width: float = param(4.8, gt=0)  # modelled half-width [m]
    depth: float = param(3.0, gt=0)  # modelled depth [m]
    cells: str = param("quadrilateral", choices=CELLS)  # or "triangle"
    structured: bool = False  # transfinite blocks graded from the footing edge (False: gmsh's
    #                           unstructured mesh under a size field, quads by recombination)
    fine: float = param(0.08, gt=0)  # element size at the footing edge [m]
    coarse: float = param(0.4, gt=0)  # element size far away [m]
    continuum_steps: int = param(24, ge=1)  # pressure increments up to ``pressure`` (or
    #                                          settlement increments: continuum_control)
    continuum_control: str = param("pressure", choices=("pressure", "settlement"))  # the
    #                           continuum's load path: the pressure raised until no
    #                           equilibrium, or the footing's settlement driven past the
    #                           pressure's peak (the header)
    continuum_settlement: float = param(0.1, gt=0)  # (settlement) the largest mean
    #                           settlement followed [m]
    continuum_hold_flipping: bool = False  # Newton's retry of a cycling increment, holding
    #                           its flipping points elastic (NewtonOptions.hold_flipping): a
    #                           diagnostic that tells a stall from the collapse
    control: str = param("pressure", choices=("pressure", "punch"))  # discrete loading (header)
    punch_speed: float = param(0.25, gt=0)  # speed of the pushed footing (control=punch) [m/s]
    punch_ramp_time: float = param(0.5, gt=0)  # (control=punch) the push's speed raised and
    #                         its load removed over it [s]: several periods of the soil's
    #                         fundamental modes (0.05-0.09 s here), so the unloading is slow
    pressure: float = param(1800.0, gt=0)  # footing pressure (control=pressure) [kPa]
    target_settlement: float = param(0.5, gt=0)  # settlement at which the footing is unloaded [m]
    ramp_time: float = param(0.05, gt=0)  # loading / unloading ramp [s]
    max_time: float = param(3.0, gt=0)  # give up the loaded phase after this time [s]
    #                                     (control=pressure; a punch's follows from its speed)
    region_layers: int | None = param(None, ge=0)  # None: any bond may fail; N: only those
    #                            within N cell layers of the yielded cells (a sensitivity)
    freeze_layers: int | None = param(None, ge=0)  # None: no element held; N: the cells beyond
    #                            N layers of that region are held (a sensitivity)
    mass_damping: float = param(0.0, ge=0)  # mass damping alpha [1/s] in the discrete phase
    #                                         (0: none; see the header)
    rest: float = param(1e-4, gt=0)  # kinetic / strain energy ratio taken as rest
    output_every: int = param(800, ge=0)  # discrete steps between outputs (0: none)
    checkpoint_every: int = param(0, ge=0)  # discrete steps between checkpoints (0: none;
    #                                         hybrid run --resume continues from the last)
    safety: float = param(0.5, gt=0, le=1)  # time step as a fraction of the time-step scale
    progress: bool = True  # progress bar of the discrete runs
    discrete: bool = True  # run the discrete phase (False: stop after the handover, as the
    #                        mesh study of the collapse load does)
    far_boundary: str = param("transmitting", choices=("transmitting", "reflecting"))  # the
    #                       far side in the discrete phase: viscous dashpots on its free
    #                       (vertical) component let shear waves leave (the header), or a
    #                       plain roller that reflects them
    contact_damping: float = param(0.2, ge=0, le=1)  # normal contact damping ratio zeta [-]
    interface_cohesion: float | None = None  # bond cohesion [kPa] (None: c)
    interface_phi: float | None = None  # bond friction angle [deg] (None: phi)
    interface_tensile_strength: float | None = None  # bond tension [kPa] (None: c cot phi)


def main(out: str | Path = "results/footing_failure", **overrides) -> CaseSummary:
    """Footing failure (H2): continuum to collapse, handover, discrete failure and rest."""
    p = Parameters(**overrides)
    if p.freeze_layers is not None and p.region_layers is None:
        raise ParameterError("case parameter freeze_layers needs region_layers: with every "
                             "bond free to fail (region_layers = None) no cell lies beyond the "
                             "region (--set region_layers=N --set freeze_layers=M)")
    out = Path(out)
    b = p.footing_width / 2
    mesh = build_mesh(load_builder(MESHES / "footing.py"), width=p.width, depth=p.depth,
                      half_footing=b, fine=p.fine, coarse=p.coarse, cells=p.cells,
                      structured=p.structured)
    soil = Material(name="soil", E=p.E, nu=p.nu, unit_weight=p.unit_weight, cohesion=p.cohesion,
                    phi=p.phi, psi=p.psi,
                    residual=Strength(cohesion=p.residual_cohesion, phi=p.residual_phi),
                    softening_displacement=p.softening_displacement,
                    bond=Bond(cohesion=p.interface_cohesion, phi=p.interface_phi,
                              tensile_strength=p.interface_tensile_strength),
                    contact=Contact(damping=p.contact_damping))
    # the load factor is the footing pressure in kPa
    model = Model(mesh, {"soil": soil},
                  supports=[Fixed("base"), Roller("symmetry", "x"),
                            Roller("right", "x", transmitting=p.far_boundary == "transmitting")],
                  loads=[Pressure("footing", 1.0)])

    # 1. continuum: gravity, then pressure until no equilibrium
    solver = PlasticSolver(model, degree=2,
                           options=NewtonOptions(hold_flipping=p.continuum_hold_flipping))
    solver.apply_gravity(steps=2).require()
    solver.reset_displacement()
    footing_point = np.array([[0.0, 0.0]])
    curve = [(0.0, 0.0)]
    solver.monitors["settlement"] = lambda: -float(
        _displacement(solver, footing_point)[0, 1])
    # the load steps as a time series, the time the footing pressure
    with ContinuumSeries(out / "continuum_steps.xdmf", solver,
                         meaning="load factor = footing pressure [kPa]") as series:
        if p.continuum_control == "pressure":
            analysis = solver.ramp(p.pressure, p.continuum_steps)
            history = [(r.monitors["settlement"], r.load_factor) for r in solver.history
                       if "settlement" in r.monitors]
            # stopped short of the pressure: a collapse only if the settlement ran away
            analysis.require_collapse([q for _, q in curve + history],
                                      [u for u, _ in curve + history])
            collapsed, q_handover, peak = not analysis.completed, analysis.factor, None
        else:
            q_handover, peak = _settlement_peak(solver, p)
            collapsed = True
    history = [(r.monitors["settlement"], r.load_factor) for r in solver.history
               if "settlement" in r.monitors]
    # the curve up to the state handed over (past a peak, the increments that showed the
    # pressure falling are in the continuum series only)
    curve += (history if peak is None
              else history[:int(np.argmax([q for _, q in history])) + 1])
    state = solver.state()
    estimates = strip_footing_estimates(p.cohesion, p.phi, p.unit_weight, p.footing_width)

    # 2. handover
    region = Region(everywhere=p.region_layers is None, layers=p.region_layers or 0)
    hand = to_discrete(state, region=region, freeze_layers=p.freeze_layers)
    summary = CaseSummary("footing_failure (H2)", out, p, results={
        "continuum": {"cells": state.info["cells"], "steps": state.info["steps"],
                      "newton_iterations": state.info["newton_iterations"],
                      "held_increments": state.info["held_increments"],
                      "wall_time_s": state.info["wall_time_s"],
                      "collapse_pressure_kPa": q_handover if collapsed else None,
                      "handover_pressure_kPa": q_handover,
                      "reached_target": not collapsed,
                      "curve": curve, "series": series.report(),
                      **({} if peak is None else {"settlement_control": peak})}},
        # the classical formulae are limit loads of rigid perfectly plastic soil: a reference
        # only when the soil does not soften
        checks={f"collapse_vs_{k}": Check.published(q_handover, v, None, "kPa", k,
                                                    applies=not soil.softens)
                for k, v in estimates.items() if collapsed})
    write_continuum_xdmf(out / "continuum.xdmf", state)
    plot_cell_field(out / "handover_plastic_strain.png", model.mesh,
                    state.cell_plastic_strain(), title="Plastic strain at handover",
                    label="plastic strain [-]", cmap="magma_r")
    engineering_figures(out, state, prefix="continuum_", when=f"q = {q_handover:.0f} kPa",
                        window=(0.0, -2.0 * p.footing_width, 3.0 * p.footing_width,
                                0.25 * p.footing_width))
    if hand.discrete is None:  # MPI ranks other than 0 stop here
        return summary
    disc = hand.discrete
    summary["handover"] = hand.report
    if not p.discrete:  # the continuum's collapse and the handover only
        summary.write(out / "summary.json")
        return summary

    # 3. discrete: raise, hold until the target settlement, remove, rest
    footing_nodes = hand.boundary_nodes["footing"]
    disc.tie_rigidly(footing_nodes)  # a rigid rough footing carries the load from here on
    window = (0.0, -1.5 * p.footing_width, 2.5 * p.footing_width, 0.5 * p.footing_width)
    plot_configuration(out / "discrete_start.png", disc, window=window,
                       title="Discrete start: plastic strain at handover")
    # settlement and heave count from the handover; the continuum's settlement comes before
    marks = FootingMarks.pick(disc, footing_nodes, hand.boundary_nodes["surface"], beside=b,
                              offset=curve[-1][0])
    q0 = q_handover
    program: PunchProgram | LoadProgram
    # a push reaches its target by construction, in target / speed + ramp / 2: its time limit
    push_time = p.target_settlement / p.punch_speed + p.punch_ramp_time  # (a margin: ramp / 2)
    if p.control == "punch":  # displacement control, the bearing pressure measured
        program = PunchProgram(footing_nodes, apply=lambda q: hand.set_load_factor(q / q0),
                               measure=lambda: marks.settlement(disc), width=b,
                               speed=p.punch_speed, target=p.target_settlement,
                               ramp_time=p.punch_ramp_time, max_time=push_time,
                               t_start=disc.time)
        program.start(disc)
    else:  # load control: the pressure applied
        program = LoadProgram(apply=lambda q: hand.set_load_factor(q / q0),
                              measure=lambda: marks.settlement(disc), start=q0,
                              peak=p.pressure, target=p.target_settlement,
                              ramp_time=p.ramp_time, max_time=p.max_time, t_start=disc.time)
    t_start = disc.time

    mass0, n0 = float(disc.mass.sum()), disc.n_elements
    options = RunOptions(mass_damping=p.mass_damping, safety=p.safety, split_every=10)
    outputs = standard_outputs(out / "discrete", output_every=p.output_every,
                               checkpoint_every=p.checkpoint_every, progress=p.progress,
                               material_names=hand.material_names)
    # one solver: the loading run and the rest run make one time series
    with ExplicitSolver(disc, options, observers=outputs) as solver:
        limit = (push_time + 2 * p.punch_ramp_time if p.control == "punch"
                 else p.max_time + 2 * p.ramp_time)
        loaded = solver.run(until_time=t_start + limit,
                            on_check=program, check_every=20, phase="loading")
        settled = solver.run(until_rest=p.rest, max_steps=200_000, phase="rest")
    settlement = marks.settlement(disc)
    curve_discrete = [*program.curve, (settlement, 0.0)]  # ending at rest
    excess = max(energy_excess(loaded.history, loaded.start),
                 energy_excess(settled.history, settled.start))
    h = settled.history
    steps = loaded.steps + settled.steps
    wall = loaded.wall_time + settled.wall_time
    summary["discrete"] = {
        "elements": disc.n_elements, "mass_t_per_m": float(disc.mass.sum()),
        "dt_s": loaded.dt, "time_loaded_s": loaded.time - t_start,
        "time_to_rest_s": settled.time - t_start,
        "unloaded_at_s": program.t_unload,
        "settlement_at_unloading_m": program.at_unloading,
        "control": p.control,
        "final_settlement_m": settlement,
        "final_total_settlement_m": marks.total_settlement(disc),
        "max_heave_beside_footing_m": marks.heave(disc),
        "interfaces_failed": int((~disc.interface_intact).sum()),
        "interfaces": int(disc.interface_intact.size),
        "energy_peak_over_supply": max(energy_peak_ratio(loaded.history, loaded.start),
                                       energy_peak_ratio(h, settled.start)),
        "steps": steps, "wall_time_s": wall, "stop": settled.stop_reason,
        "element_steps_per_s": steps * disc.n_elements / max(wall, 1e-9),
        "outputs": [str(f) for f in solver.files if f.suffix != ".png"],
    }
    if isinstance(program, PunchProgram):  # the bearing pressure the push took (None: the
        s_end = float(program.at_unloading or 0.0)  # push gave up before it settled at all)
        pushed = program.pressure_at_unloading is not None and s_end > 0.0
        summary["discrete"].update({
            "pressure_at_unloading_kpa": program.pressure_at_unloading,
            "mean_bearing_pressure_kpa": program.mean_pressure(0.0, s_end) if pushed else None,
            "bearing_pressure_last_fifth_kpa": (program.mean_pressure(0.8 * s_end, s_end)
                                                if pushed else None)})
    checks = summary["checks"]
    checks["reached_target_settlement"] = Check(
        float(program.at_unloading or settlement), p.target_settlement, None, "m",
        "report: settlement when the load was removed (target)")
    checks["energy_excess_over_sources"] = Check(
        excess, 0.0, 0.01, "-", "E_kin + E_strain + E_contact <= E(0) + work of loads/gravity")
    checks.update(settled.rest_checks(p.rest))
    checks["elements_conserved"] = Check(float(disc.n_elements), float(n0), 0.0)
    checks["mass_conserved"] = Check(float(disc.mass.sum()), mass0, 1e-12, "t/m")
    summary.write(out / "summary.json")
    sd, qd = np.array(curve_discrete).T if curve_discrete else (np.zeros(0), np.zeros(0))
    sc, qc = np.array(curve).T
    # the classical limit loads are drawn only for a soil they apply to (no softening)
    plot_load_settlement(out / "load_settlement.png", sc, qc,
                         {} if soil.softens else estimates, label="continuum",
                         more={("discrete (measured while pushed, applied while unloaded)"
                                if p.control == "punch" else "discrete (applied pressure)"):
                               (marks.offset + sd, qd)},
                         title="H2: footing load-settlement (settlement from the start)")
    # the whole discrete phase, loading and rest, as one ledger history
    when = ({"unloading starts": t_start + program.t_unload} if program.t_unload else {})
    plot_energy(out / "energy.png", phase_history([r.history for r in solver.results]),
                marks={**when, "rest run starts": loaded.time},
                title="H2: energy of the discrete phase (loading, unloading, rest)")
    plot_configuration(out / "final.png", disc, window=window, outline=True,
                       title=f"{settled.ending}\nsettlement {marks.total_settlement(disc):.3f} m "
                             f"({settlement:.3f} m since handover), "
                             f"{int((~disc.interface_intact).sum())} failed interfaces")
    return summary


def _settlement_peak(solver: PlasticSolver, p: Parameters) -> tuple[float, dict]:
    """The collapse load as the peak of a settlement-controlled path (continuum_control=settlement).

    The footing's mean settlement is driven to ``continuum_settlement`` in ``continuum_steps``
    increments (``PlasticSolver.follow``) until the pressure has fallen ``PEAK_FALL`` below
    its largest value. The solver is left at the peak. Returns (peak pressure [kPa], what the
    path did); raises StageIncomplete if the pressure did not fall past a peak (Newton
    stalled, or the settlement ended first).
    """
    best: list[Any] = [solver.load_factor, solver.snapshot()]  # peak pressure, its state

    def keep(s: PlasticSolver) -> bool:
        if s.load_factor > best[0]:
            best[:] = [s.load_factor, s.snapshot()]
        return s.load_factor < (1.0 - PEAK_FALL) * best[0]

    start = len(solver.history)
    followed = solver.follow(DisplacementControl("footing", 1), -p.continuum_settlement,
                             p.continuum_steps, stop=keep)
    if not solver.load_factor < (1.0 - PEAK_FALL) * best[0]:
        raise StageIncomplete(
            f"continuum under settlement control: the footing pressure did not fall "
            f"{100 * PEAK_FALL:g} % below its largest value {best[0]:.6g} kPa (settlement "
            f"{-followed.factor:.4g} m{'' if followed.completed else ', Newton stalled'}): "
            "no collapse found. Give a larger continuum_settlement or more continuum_steps")
    info = {"increments": len(solver.history) - start, "settlement_m": -followed.factor,
            "final_pressure_kPa": solver.load_factor}
    solver.restore(best[1])
    return best[0], info


def _displacement(solver: PlasticSolver, points: np.ndarray) -> np.ndarray:
    from hybrid.continuum.probe import evaluate

    return evaluate(solver.u, points)


if __name__ == "__main__":
    from hybrid.case import run_case

    raise SystemExit(run_case(main, Parameters))
