"""C5-C7: bearing capacity of a rigid smooth strip footing (thesis 5.4.1).

Objective
    The limit load of the Mohr-Coulomb continuum against Prandtl's closed form.
Problem
    A rigid smooth strip footing B = 1.2 m wide pushed into soil with c = 69 kPa,
    phi = 20 deg (thesis Table 5.1 strengths); weightless soil for C6 (and c_u = 50 kPa,
    phi = 0 for C5); with self-weight for C7. Half model by symmetry.
Set-up
    Footing: prescribed vertical displacement under the footing (smooth: horizontal free),
    raised in equal steps; symmetry line and far side on vertical rollers, base fixed.
    With self-weight the gravity stage comes first (its displacement is then reset).
Verification
    Average footing pressure at the end of the push (the plateau) against
    q_u = c N_c (weightless), N_c = (N_q - 1) cot phi, N_q = e^(pi tan phi) tan^2(45 + phi/2)
    = 1023.6 kPa (C6) and (2 + pi) c_u = 257.1 kPa (C5); bar 3 % with psi = phi. With
    psi < phi the plateau is reported beside Prandtl.
References
    Prandtl (1920); Terzaghi (1943); G. S. Bala (2008), thesis, section 5.4.1.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from hybrid.continuum.analysis import plateau_rise
from hybrid.continuum.plastic import NewtonOptions, PlasticSolver
from hybrid.geometry import build_mesh, load_builder
from hybrid.io import CaseSummary, Check, plot_cell_field, write_continuum_xdmf
from hybrid.materials import Material
from hybrid.model import Displacement, Fixed, Model, Roller
from hybrid.parameters import CELLS, CaseParameters, param
from hybrid.report import plot_load_settlement

MESHES = Path(__file__).resolve().parent.parent / "meshes"


@dataclass
class Parameters(CaseParameters):
    cohesion: float = 69.0  # c [kPa]
    phi: float = 20.0  # friction angle [deg]
    psi: float | None = None  # dilation angle [deg]; None = phi (associated)
    unit_weight: float = param(0.0, ge=0)  # gamma [kN/m3] (0: weightless, C5/C6)
    E: float = 100_000.0  # Young's modulus [kPa]
    nu: float = 0.3  # Poisson's ratio [-]
    footing_width: float = param(1.2, gt=0)  # B [m]
    width: float = param(6.0, gt=0)  # modelled half-width of the domain [m]
    depth: float = param(4.0, gt=0)  # modelled depth [m]
    fine: float = param(0.04, gt=0)  # element size at the footing edge [m]
    coarse: float = param(0.6, gt=0)  # element size far away [m]
    cells: str = param("triangle", choices=CELLS)  # "triangle" or "quadrilateral"
    degree: int = param(2, choices=(1, 2))  # displacement order
    settlement: float = param(0.08, gt=0)  # final footing settlement [m]
    steps: int = param(40, ge=1)  # displacement increments
    plateau: float = param(0.001, ge=0, lt=1)  # stop once the pressure rises less than this
    #                                            (relative) over the last 10 % of the push
    #                                            (after half of it); 0 = push to the end
    case_id: str = "C6"  # label in the summary


def prandtl(cohesion: float, phi_deg: float) -> float:
    """Prandtl's limit pressure c N_c of a weightless soil [kPa] ((2 + pi) c at phi = 0)."""
    if phi_deg == 0:
        return (2.0 + math.pi) * cohesion
    t = math.tan(math.radians(phi_deg))
    nq = math.exp(math.pi * t) * math.tan(math.radians(45.0 + phi_deg / 2.0)) ** 2
    return cohesion * (nq - 1.0) / t


def main(out: str | Path = "results/bearing_capacity", **overrides) -> CaseSummary:
    """Rigid smooth strip footing pushed to collapse (C5-C7)."""
    p = Parameters(**overrides)
    out = Path(out)
    b = p.footing_width / 2
    psi = p.phi if p.psi is None else p.psi
    mesh = build_mesh(load_builder(MESHES / "footing.py"), width=p.width, depth=p.depth,
                      half_footing=b, fine=p.fine, coarse=p.coarse, cells=p.cells)
    soil = Material(name="soil", E=p.E, nu=p.nu, unit_weight=p.unit_weight, cohesion=p.cohesion,
                    phi=p.phi, psi=psi, plastic=True)
    model = Model(mesh, {"soil": soil},
                  supports=[Fixed("base"), Roller("symmetry", "x"), Roller("right", "x"),
                            Displacement("footing", uy=-p.settlement)])
    solver = PlasticSolver(model, degree=p.degree, options=NewtonOptions(max_iterations=30))
    if p.unit_weight > 0:
        solver.apply_gravity(steps=2).require()
        solver.reset_displacement()
    base_force = solver.reaction("footing", 1)  # the self-weight share of the footing force
    solver.monitors["pressure"] = lambda: -(solver.reaction("footing", 1) - base_force) / b
    def on_plateau(s: PlasticSolver) -> bool:
        """The pressure has stopped rising: the limit load is reached."""
        lam = s.load_factor
        if p.plateau <= 0 or lam < 0.5:
            return False
        past = [r for r in s.history if "pressure" in r.monitors and r.load_factor <= lam - 0.1]
        return bool(past) and (s.history[-1].monitors["pressure"] - past[-1].monitors[
            "pressure"]) < p.plateau * s.history[-1].monitors["pressure"]

    analysis = solver.ramp(1.0, p.steps, stop=on_plateau)
    settle = np.array([0.0] + [r.load_factor * p.settlement for r in solver.history
                               if "pressure" in r.monitors])
    pressure = np.array([0.0] + [r.monitors["pressure"] for r in solver.history
                                 if "pressure" in r.monitors])
    analysis.require_limit(settle, pressure)  # stopped short: only on the load plateau
    limit = float(pressure[-1])
    reference = prandtl(p.cohesion, p.phi)
    associated = abs(psi - p.phi) < 1e-12
    state = solver.state()
    # plateau: rise of the pressure over the last fifth of the push, relative to its end value
    rise = plateau_rise(settle, pressure) if limit else 0.0
    summary = CaseSummary(f"bearing_capacity ({p.case_id})", out, p, results={
        "cells": state.info["cells"], "dofs": state.info["dofs"],
        "steps": state.info["steps"], "newton_iterations": state.info["newton_iterations"],
        "wall_time_s": state.info["wall_time_s"], "completed": analysis.completed,
        "plateau_rise_last_fifth": rise,
        "curve": {"settlement_m": settle, "pressure_kPa": pressure},
        "residual_histories": [r.residuals for r in solver.history[-3:]],
    }, checks={"limit_pressure": Check(
        limit, reference, 0.03 if associated and p.unit_weight == 0 else None, "kPa",
        "Prandtl c N_c" + ("" if associated else " (psi < phi: reported beside)"))})
    write_continuum_xdmf(out / "continuum.xdmf", state)
    plot_cell_field(out / "plastic_strain.png", model.mesh, state.cell_plastic_strain(),
                    title="Equivalent plastic strain at the end", label="plastic strain [-]",
                    cmap="magma_r")
    if state.comm.rank == 0:
        plot_load_settlement(out / "load_settlement.png", settle, pressure,
                             {"Prandtl c N_c": reference}, title=f"{p.case_id}: rigid footing")
    summary.write(out / "summary.json", state.comm)
    return summary


if __name__ == "__main__":
    from hybrid.case import run_case

    raise SystemExit(run_case(main, Parameters))
