"""R1: a plane granular column collapses when its gate is removed, and runs out to rest.

Objective
    The standard benchmark of run-out codes, against published measurements: a column of
    cohesionless grains against a back wall is released by removing the gate in front of it and
    spreads over a floor; its run-out and final height are compared with experiments for
    several aspect ratios a = H0 / L0.
Problem
    The column of Bui et al. (2008): aluminium bars, L0 = ``length`` = 0.2 m long, H0 = a L0
    high (0.1 m at a = 0.5), friction angle 19.8 deg, no cohesion, density 2.65 t/m3,
    E = 840 kPa, nu = 0.3 (the values of their simulation of the test). A held back wall at
    x = 0 and a held floor strip (both elastic, same material) carry it.
Set-up
    1. Continuum (dolfinx, elastic): the column's gravity state with the gate in place (gate
       and back wall smooth rollers, the base bonded to the floor).
    2. Handover: every cell an element with its stress. The column is a packing of elastic
       grains (``cells`` = "triangle", unstructured, of size L0 / ``nx``: grains of random
       shapes and orientations) bonded by interfaces without cohesion and tensile strength:
       they fail as soon as they open or slide, and from then on the grains meet by contact
       with Coulomb friction (shear contact stiffness k_t = k_n / 10, the thesis's ratio).
       The grains' contact angle (and their bonds') is not the material's friction angle
       ``phi``: a packing of angular triangles is stronger in bulk than its contacts. It is
       calibrated as DEM practice does, so that the packing's critical-state bulk angle in a
       plane-strain biaxial test equals ``phi``
       (``hybrid.discrete.biaxial.contact_friction``: 19.8 deg in bulk takes a smaller
       contact angle); ``contact_phi`` overrides it. The floor and the wall are held; the
       column's interfaces with them split as its own do, and a grain on them slides at the
       contact angle too (a contact takes the smaller of its two materials' angles). The
       experiments' floor is not known here (the rods' source investigates the influence of
       hard and soft beds on the run-out; its abstract does not say which bed its laws are for):
       ``floor`` = "flat" (default) is a smooth plane on which a grain slides at the contact
       angle, smoother than the packing; "rough" a sawtooth standing in for a layer of grains
       fixed to the floor, half a grain from valley to peak, its wavelength two grains, over
       which the packing must shear (meshes/column.py). The grains themselves stay elastic:
       the flow is grains sliding and rolling on each other, not plastic flow inside elements.
    3. Discrete: the gate is removed (its rollers released) at t = 0 and the run followed until
       rest (E_kin <= ``rest`` x its peak). No mass damping: nothing in the experiment resists
       the flight of a grain (air drag on a 1 mm bar at 1 m/s is negligible). Collisions
       between grains lose energy through a normal contact damping ratio ``contact_damping``
       = 0.3, a coefficient of restitution e = exp(-pi zeta / sqrt(1 - zeta^2)) = 0.37:
       assumed, of the order of the restitution within dense packings, not measured for these
       bars (the run-out's sensitivity to it is reported in docs/hybrid.md).
Verification
    * The run keeps its elements and mass, reaches rest, and its energy stays bounded
      (E_kin + E_strain + E_contact <= E(0) + work of gravity, bar 1 % of the supply).
    * Run-out L_inf (the far end of the continuous deposit from the back wall, a grain flung
      beyond a stretch of bare floor not counted: ``hybrid.discrete.measures.deposit``) and
      final height H_inf, beside the experiments (reports, the bar of 15 % is assessed in
      docs/hybrid.md): for a > 0.65 the aluminium-rod laws of arXiv:1512.05180,
      (L_inf - L0) / L0 = 3.25 a^0.96 (a < 1.5), 3.80 a^0.73 (a > 1.5) and H0 / H_inf =
      1.42 a^(2/3); for a <= 0.65 H_inf = H0 (same source). Lube et al.'s (2005) sand laws
      are reported beside them. Both measure L_inf from the back wall and a = H0 / L0 with L0
      the column's length along the flow.
References
    Bui, Fukagawa, Sako & Ohno (2008), Int. J. Numer. Anal. Meth. Geomech. 32(12),
    1537-1570; arXiv:1512.05180 (2015), "Failure mechanism of true 2D granular flows"; Lube,
    Huppert, Sparks & Freundt (2005), Phys. Rev. E 72, 041301 (see ``hybrid.references``).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from hybrid import references as ref
from hybrid.continuum import solve_elastic
from hybrid.discrete import ties
from hybrid.discrete.biaxial import contact_friction
from hybrid.discrete.energy import conservation_checks, energy_peak_ratio
from hybrid.discrete.figures import plot_configuration
from hybrid.discrete.measures import deposit
from hybrid.discrete.outputs import standard_outputs
from hybrid.discrete.runs import require_serial
from hybrid.discrete.solver import ExplicitSolver, RunOptions
from hybrid.geometry import build_mesh, load_builder
from hybrid.handover import Region, to_discrete
from hybrid.io import CaseSummary, Check, save_figure
from hybrid.materials import Bond, Contact, Material
from hybrid.model import Fixed, Model, Roller
from hybrid.parameters import CaseParameters, ParameterError, param
from hybrid.report import plot_energy

MESHES = Path(__file__).resolve().parent.parent / "meshes"


@dataclass
class Parameters(CaseParameters):
    aspect: float = param(0.5, gt=0, le=5)  # a = H0 / L0, column height over length [-]
    length: float = param(0.2, gt=0)  # L0, the column's length along the flow [m]
    nx: int = param(20, ge=2)  # elements along L0 (element size L0 / nx) [-]
    cells: str = param("triangle", choices=("triangle", "quadrilateral"))  # cell shape
    structured: bool = False  # structured cells (a regular stack of grains) or unstructured
    floor: str = param("flat", choices=("flat", "rough"))  # the floor's surface: "flat", or
    #     "rough": a sawtooth half a grain from valley to peak (for grains fixed to the floor)
    density: float = param(2.65, gt=0)  # [t/m3]
    E: float = param(840.0, gt=0)  # Young's modulus [kPa]
    nu: float = param(0.3, ge=0, lt=0.5)  # Poisson's ratio [-]
    phi: float = param(19.8, gt=0, lt=90)  # the material's (bulk) friction angle [deg]
    contact_phi: float | None = param(None, ge=0, lt=90)  # grains' contact and bond angle [deg]
    #     (None: the angle whose packing has the bulk angle phi, hybrid.discrete.biaxial)
    contact_damping: float = param(0.3, ge=0, le=1)  # normal contact damping ratio zeta [-]
    rest: float = param(1e-4, gt=0)  # stop when E_kin <= rest x max(peak E_kin, E_strain) [-]
    t_end: float = param(5.0, gt=0)  # time limit [s]
    output_every: int = param(0, ge=0)  # steps between XDMF frames and PNG snapshots (0: none)
    progress: bool = True  # show a progress bar

    def __post_init__(self) -> None:
        super().__post_init__()
        if self.floor == "rough" and (self.structured or self.cells != "triangle"):
            raise ParameterError("case parameter floor = 'rough' needs unstructured triangle "
                                 "grains (its teeth are not a grid's row, and gmsh leaves "
                                 "triangles among quadrilaterals beside them): give "
                                 "--set structured=false --set cells=triangle")


def references(aspect: float) -> dict[str, float | None]:
    """The experiments' (L_inf - L0) / L0 and H_inf / H0 at ``aspect`` (None: no law there)."""
    rods_runout = (ref.granular_runout_rods2015(aspect)
                   if aspect > ref.RODS2015_BREAK else None)
    lube = (ref.granular_runout_lube2005(aspect)
            if not ref.LUBE2005_LINEAR_MAX < aspect < ref.LUBE2005_POWER_MIN else None)
    return {"rods2015_runout": rods_runout,
            "rods2015_height": ref.granular_final_height_rods2015(aspect),
            "lube2005_runout": lube,
            "lube2005_height": ref.granular_final_height_lube2005(aspect) / aspect}


def runway(length: float, aspect: float) -> float:
    """Floor length [m] from the back wall: beyond the rod law's run-out, with a margin."""
    return length * (1.0 + 1.5 * (1.0 + 4.3 * aspect**0.72)) + 0.1


def main(out: str | Path = "results/granular_collapse", **overrides) -> CaseSummary:
    """A granular column released from its gravity state spreads to rest (R1)."""
    require_serial("granular_collapse")
    p = Parameters(**overrides)
    out = Path(out)
    L0 = p.length
    H0 = p.aspect * L0
    ny = max(int(round(p.nx * p.aspect)), 1)
    floor_end = runway(L0, p.aspect)
    size = L0 / p.nx
    # 1. continuum: the column's elastic gravity state behind the gate (dolfinx)
    mesh = build_mesh(load_builder(MESHES / "column.py"), length=L0, height=H0, nx=p.nx, ny=ny,
                      runway=floor_end, wall=2.0 * size, depth=2.0 * size, cells=p.cells,
                      structured=p.structured, roughness=0.5 * size if p.floor == "rough" else 0.0)
    kn = 10.0 * p.E / size  # the default normal contact stiffness, written out for k_t
    phi_c = contact_friction(p.phi) if p.contact_phi is None else p.contact_phi
    contact = Contact(phi=phi_c, damping=p.contact_damping, normal_stiffness=kn,
                      shear_stiffness=kn / 10.0)
    grains = Material(name="column", E=p.E, nu=p.nu, density=p.density, plastic=False,
                      bond=Bond(cohesion=0.0, phi=phi_c, tensile_strength=0.0),
                      contact=contact)
    support = Material(name="support", E=p.E, nu=p.nu, density=p.density, plastic=False,
                       contact=contact)
    state = solve_elastic(Model(mesh, {"column": grains, "wall": support, "floor": support},
                                supports=[Fixed("base"), Fixed("back"), Roller("gate", "x")]))
    summary = CaseSummary("granular_collapse (R1)", out, p, results={
        "continuum": {"cells": state.info["cells"], "wall_time_s": state.info["wall_time_s"]}})
    # 2. handover: the column's interfaces (and those with the floor and the wall) may split
    hand = to_discrete(state, region=Region(group="column"))
    disc = hand.discrete
    summary["handover"] = hand.report
    summary["grains"] = {"bulk_phi_deg": p.phi, "contact_phi_deg": phi_c,
                         "contact_phi_from": "parameter contact_phi" if p.contact_phi is not None
                         else "hybrid.discrete.biaxial.contact_friction(phi)"}
    column = hand.splittable.copy()
    ties.limit_splitting(disc, column)
    disc.fix(np.unique(disc.element_nodes[~column]))
    disc.fixed[hand.boundary_nodes["gate"], 0] = False  # 3. the gate is removed
    disc.primed = False
    mass0, n0 = float(disc.mass.sum()), disc.n_elements
    window = (-2.0 * size, -2.0 * size, floor_end, 1.1 * H0)
    plot_configuration(out / "discrete_start.png", disc, window=window,
                       title="Discrete start: the column behind its gate")
    options = RunOptions(split_every=10, contact=True,
                         contact_bounds=(-L0, -L0, floor_end + L0, H0 + L0))
    outputs = standard_outputs(out / "discrete", output_every=p.output_every,
                               progress=p.progress)
    with ExplicitSolver(disc, options, observers=outputs) as solver:
        res = solver.run(until_rest=p.rest, until_time=p.t_end, rest_min_steps=2000,
                         check_every=50)
    h = res.history
    dep = deposit(disc, column, bin_width=size)
    runout = (dep.runout - L0) / L0
    height = dep.height / H0
    refs = references(p.aspect)
    checks = {
        **conservation_checks(h, res.start, disc, n0, mass0),
        **res.rest_checks(p.rest),
    }
    # a deposit still moving is no final profile: compared only at rest
    at_rest = res.stop_reason == "rest"
    if at_rest:
        checks["final_height_rods2015"] = Check(
            height, refs["rods2015_height"], None, "-",
            "report: H_inf / H0 against the aluminium rods (arXiv:1512.05180)")
    if at_rest and refs["rods2015_runout"] is not None:
        checks["runout_rods2015"] = Check(
            runout, refs["rods2015_runout"], None, "-",
            "report: (L_inf - L0) / L0 against the aluminium rods (arXiv:1512.05180)")
    summary["discrete"] = {
        "elements": disc.n_elements, "column_elements": int(column.sum()), "dt_s": res.dt,
        "steps": res.steps, "time_s": res.time, "stop": res.stop_reason,
        "wall_time_s": res.wall_time, "element_steps_per_s": res.element_steps_per_s,
        "interfaces_failed": int((~disc.interface_intact).sum()),
        "energy_peak_over_supply": energy_peak_ratio(h, res.start),
    }
    summary["deposit"] = {
        "runout_m": dep.runout, "height_m": dep.height, "normalised_runout": runout,
        "height_over_H0": height, "detached_elements": dep.detached, "at_rest": at_rest,
        "profile_m": dep.profile.tolist(), "references": refs,
    }
    summary.checks.update(checks)
    summary.write(out / "summary.json")
    plot_energy(out / "energy.png", h)
    plot_configuration(out / "final.png", disc, window=window, outline=True,
                       title=f"{res.ending}: run-out {dep.runout:.3g} m, "
                             f"height {dep.height:.3g} m")
    return summary


def plot_deposits(path: str | Path, summaries: list[dict]) -> Path:
    """The final surfaces of several runs (summary.json contents), normalised by L0.

    Beside the run of Bui et al.'s (2008) column (a = 0.5, L0 = 0.2 m) their measured final
    surface (``hybrid.references.bui2008_final_surface``); beside the others the rods'
    run-out.
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(8.0, 3.5), dpi=100)
    colours: dict[tuple[float, float], str] = {}  # one colour per column; its start and
    #     references drawn once
    for s in sorted(summaries, key=lambda s: s["parameters"]["aspect"]):
        a, L0 = s["parameters"]["aspect"], s["parameters"]["length"]
        prof = np.asarray(s["deposit"]["profile_m"]) / L0
        x = np.concatenate([[0.0], prof[:, 0], [s["deposit"]["runout_m"] / L0]])
        y = np.concatenate([[prof[0, 1]], prof[:, 1], [0.0]])
        rough = s["parameters"].get("floor", "flat") == "rough"  # older summaries: flat
        line, = ax.plot(x, y, color=colours.get((a, L0)), ls="--" if rough else "-",
                        label=f"a = {a:g}: computed" + (", rough floor" if rough else ""))
        if (a, L0) in colours:
            continue
        colours[(a, L0)] = line.get_color()
        ax.plot([0, 1, 1], [a, a, 0], ls=":", color=line.get_color(), lw=0.8)
        bui = ref.bui2008_collapse()
        if a == bui.aspect and L0 == bui.length:
            meas = np.asarray(ref.bui2008_final_surface()) / L0
            ax.plot(meas[:, 0], meas[:, 1], ls="none", marker="D", ms=3,
                    color=line.get_color(),
                    label=f"a = {a:g}: Bui et al. (2008), measured (digitised)")
        rods = s["deposit"]["references"]["rods2015_runout"]
        if rods is not None:
            ax.plot([1.0 + rods], [0.0], marker="v", ms=8, color=line.get_color(),
                    label=f"a = {a:g}: rod run-out (arXiv:1512.05180)")
    ax.set_xlabel("x / L0 from the back wall")
    ax.set_ylabel("y / L0")
    ax.set_aspect("equal")
    ax.set_ylim(top=max(a for a, _ in colours) + 0.4)
    ax.legend(fontsize=7, loc="upper right", ncol=2 if len(summaries) > 3 else 1)
    ax.set_title("Final deposits (dotted: the columns at the start)")
    return save_figure(fig, Path(path))


if __name__ == "__main__":
    from hybrid.case import run_case

    raise SystemExit(run_case(main, Parameters))

