"""C9: factor of safety of a homogeneous slope by strength reduction.

Objective
    The slope factor of safety of the continuum phase against a published value.
Problem
    Griffiths & Lane (1999), example 1: a 2:1 slope (26.57 deg), H = 10 m, on a rigid base at
    toe level; c' = 10 kPa (c'/(gamma H) = 0.05), phi' = 20 deg, psi = 0, gamma = 20 kN/m3,
    E = 100 000 kPa, nu = 0.3.
Set-up
    Base fixed, far side on a vertical roller; gravity switched on elasto-plastically, then c
    and tan(phi) divided by F until no equilibrium (hybrid.continuum.strength_reduction).
Verification
    Bishop & Morgenstern (1960) charts give F = 1.38 (quoted by Griffiths & Lane, who found
    1.4 by finite elements); bar 5 %.
References
    D. V. Griffiths & P. A. Lane (1999), Slope stability analysis by finite elements,
    Geotechnique 49(3), 387-403; A. W. Bishop & N. Morgenstern (1960), Stability
    coefficients for earth slopes, Geotechnique 10(4), 129-150.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np

from hybrid.continuum.plastic import PlasticSolver
from hybrid.continuum.strength_reduction import factor_of_safety
from hybrid.geometry import build_mesh, load_builder
from hybrid.io import Check, plot_cell_field, write_continuum_xdmf, write_summary
from hybrid.materials import Material
from hybrid.model import Fixed, Model, Roller

MESHES = Path(__file__).resolve().parent.parent / "meshes"


@dataclass
class Parameters:
    height: float = 10.0  # slope height [m]
    gradient: float = 2.0  # horizontal : vertical (2 -> 26.57 deg)
    crest_length: float = 12.0  # crest modelled behind the slope [m]
    cohesion: float = 10.0  # c' [kPa]
    phi: float = 20.0  # phi' [deg]
    psi: float = 0.0  # dilation [deg]
    unit_weight: float = 20.0  # gamma [kN/m3]
    E: float = 100_000.0  # [kPa]
    nu: float = 0.3  # [-]
    size: float = 0.75  # element size [m]
    degree: int = 2  # displacement order
    tolerance: float = 0.01  # bracket width of F at the end


def main(out: str | Path = "results/slope_fos", **overrides) -> dict:
    """Slope factor of safety by strength reduction (C9)."""
    p = Parameters(**overrides)
    out = Path(out)
    angle = math.degrees(math.atan(1.0 / p.gradient))
    mesh = build_mesh(load_builder(MESHES / "slope.py"), height=p.height, angle=angle,
                      foundation_depth=0.0, toe_x=0.0, crest_length=p.crest_length,
                      size=p.size)
    soil = Material("soil", E=p.E, nu=p.nu, unit_weight=p.unit_weight, cohesion=p.cohesion,
                    phi=p.phi, psi=p.psi)
    model = Model(mesh, {"soil": soil}, supports=[Fixed("base"), Roller("right", "x")])
    solver = PlasticSolver(model, degree=p.degree)
    solver.apply_gravity(steps=4)
    result = factor_of_safety(solver, step=0.2, tolerance=p.tolerance)
    state = result.state
    summary = {
        "case": "slope_fos (C9)", "out": str(out), "parameters": asdict(p),
        "cells": state.info["cells"], "bracket": result.bracket,
        "trials": [{"F": f, "equilibrium": ok, "iterations": it} for f, ok, it in result.trials],
        "newton_iterations": solver.iterations_total, "wall_time_s": solver.wall_time,
        "checks": {"factor_of_safety": Check(result.factor, 1.38, 0.05, "-",
                                             "Bishop & Morgenstern (1960) via Griffiths & "
                                             "Lane (1999)")},
    }
    write_continuum_xdmf(out / "continuum.xdmf", state)
    plot_cell_field(out / "mechanism_plastic_strain.png", model.mesh,
                    state.cell_plastic_strain(),
                    title=f"Plastic strain at F = {result.factor:.3f}", label="plastic strain [-]",
                    cmap="magma_r")
    # displacement increment of the last converged reduction step: the failure mechanism
    magnitude = np.linalg.norm(state.cell_displacement(result.mechanism), axis=1)
    plot_cell_field(out / "mechanism_displacement.png", model.mesh, magnitude,
                    title="Failure mechanism: displacement increment of the last step",
                    label="|du| [m]", cmap="viridis")
    write_summary(out / "summary.json", summary, state.comm)
    return summary


if __name__ == "__main__":
    from hybrid.case import run_case

    raise SystemExit(run_case(main, Parameters))
