"""C3: flexible strip footing on an elastic layer (thesis 3.4.2).

Objective
    Check the continuum phase against the elastic strip-load (Flamant) solution and report
    the settlement at the footing edge, with its mesh convergence, beside the thesis's figure.
Problem
    A flexible strip footing, B = 12 m wide, carries q = 100 kPa on an elastic soil
    (E = 10 000 kPa, nu = 0.4) 20 m deep on a rigid rough base. By symmetry half of it is
    modelled: 20 m x 20 m, footing 6 m wide at the top left.
Set-up
    Supports: base fixed (rough rigid), symmetry line and far side on vertical rollers.
    No self-weight: the stresses are those due to the footing alone.
Verification
    Vertical stress under the centreline for depths z <= B/2 against
    sigma_z = -(q/pi)(alpha + sin alpha) (alpha = 2 atan(B / (2 z)), compression negative):
    bar 5 %. Settlement at the footing edge: computed on the given mesh and on a mesh twice as
    fine; the thesis's coarse mesh gave 0.101 m (reported, not a bar).
References
    Poulos & Davis (1974), Elastic Solutions for Soil and Rock Mechanics, 3.4 (strip load);
    G. S. Bala (2008), thesis, section 3.4.2.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from hybrid.case import uses_defaults
from hybrid.continuum import solve_elastic
from hybrid.geometry import build_mesh, load_builder
from hybrid.io import CaseSummary, Check, continuum_figures, plot_cell_field, write_continuum_xdmf
from hybrid.materials import Material
from hybrid.model import Fixed, Model, Pressure, Roller
from hybrid.parameters import CELLS, CaseParameters, param
from hybrid.references import flamant_centreline
from hybrid.report import plot_profile

MESHES = Path(__file__).resolve().parent.parent / "meshes"
THESIS_SETTLEMENT = 0.101  # footing-edge settlement of the thesis's coarse mesh (3.4.2) [m]
# the fields of the thesis's problem (its settlement applies only with them)
THESIS_PROBLEM = ("q", "E", "nu", "footing_width", "width", "depth")


@dataclass
class Parameters(CaseParameters):
    q: float = 100.0  # footing pressure [kPa]
    E: float = 10_000.0  # Young's modulus [kPa]
    nu: float = 0.4  # Poisson's ratio [-]
    footing_width: float = param(12.0, gt=0)  # B [m] (half modelled)
    width: float = param(20.0, gt=0)  # modelled width [m]
    depth: float = param(20.0, gt=0)  # layer depth to the rigid base [m]
    fine: float = param(0.25, gt=0)  # element size at the footing edge [m]
    coarse: float = param(2.0, gt=0)  # element size far away [m]
    cells: str = param("triangle", choices=CELLS)  # "triangle" or "quadrilateral"
    degree: int = param(2, choices=(1, 2))  # displacement order (1 or 2)
    convergence: bool = True  # also solve on a mesh twice as fine for the settlement


def solve(p: Parameters, refinement: float = 1.0):
    """Build the half model and solve it; returns the continuum state."""
    mesh = build_mesh(load_builder(MESHES / "footing.py"), width=p.width, depth=p.depth,
                      half_footing=p.footing_width / 2, fine=p.fine / refinement,
                      coarse=p.coarse / refinement, cells=p.cells)
    soil = Material(name="soil", E=p.E, nu=p.nu)
    model = Model(mesh, {"soil": soil},
                  supports=[Fixed("base"), Roller("symmetry", "x"), Roller("right", "x")],
                  loads=[Pressure("footing", p.q)])
    return solve_elastic(model, gravity=False, degree=p.degree)


def main(out: str | Path = "results/flexible_footing", **overrides) -> CaseSummary:
    """Flexible strip footing (C3): Flamant stress check and footing-edge settlement."""
    p = Parameters(**overrides)
    out = Path(out)
    b = p.footing_width / 2
    state = solve(p)

    z = np.linspace(0.25, b, 24)
    points = np.column_stack([np.zeros_like(z), -z])
    computed = state.stress_at(points)[:, 1]
    reference = flamant_centreline(p.q, b, z)
    rel = np.abs(computed - reference) / np.abs(reference)
    worst = int(np.argmax(rel))
    edge = np.array([[b, 0.0]])
    settlement = -float(state.displacement_at(edge)[0, 1])

    thesis = uses_defaults(p, THESIS_PROBLEM)
    checks = {
        "sigma_z_centreline_worst": Check(float(computed[worst]), float(reference[worst]), 0.05,
                                          "kPa", f"Flamant strip load, z = {z[worst]:.2f} m"),
        "settlement_footing_edge": Check.published(
            settlement, THESIS_SETTLEMENT, None, "m",
            "thesis 3.4.2 coarse mesh (reported, not a bar)", applies=thesis),
    }
    summary = CaseSummary("flexible_footing (C3)", out, p, results={
        "cells": state.info["cells"], "dofs": state.info["dofs"],
        "centreline": {"z": z, "sigma_z": computed, "flamant": reference}}, checks=checks)
    if p.convergence:
        fine = solve(p, refinement=2.0)
        s_fine = -float(fine.displacement_at(edge)[0, 1])
        summary["settlement_convergence"] = {
            "cells": [state.info["cells"], fine.info["cells"]],
            "settlement_m": [settlement, s_fine],
            "relative_change": abs(settlement - s_fine) / abs(s_fine)}
        checks["settlement_footing_edge_fine_mesh"] = Check.published(
            s_fine, THESIS_SETTLEMENT, None, "m", "mesh twice as fine", applies=thesis)

    write_continuum_xdmf(out / "continuum.xdmf", state)
    continuum_figures(out, state)
    plot_cell_field(out / "vertical_displacement.png", state.model.mesh,
                    state.cell_displacement()[:, 1], title="Vertical displacement", label="u_y [m]",
                    cmap="viridis")
    if state.comm.rank == 0:
        plot_profile(out / "centreline_stress.png", z,
                     {"Flamant (strip load)": (-reference, "k-"),
                      "hybrid (dolfinx)": (-computed, "o")},
                     xlabel="vertical stress -sigma_yy [kPa]",
                     ylabel="depth below the footing centre z [m]",
                     title="C3: stress under the centreline")
    summary.write(out / "summary.json", state.comm)
    return summary


if __name__ == "__main__":
    from hybrid.case import run_case

    raise SystemExit(run_case(main, Parameters))
