"""C8: earth pressure on a smooth rigid wall translated away from / toward sand (thesis 5.4.2).

Objective
    Active and passive thrusts of the Mohr-Coulomb continuum against Rankine.
Problem
    A smooth rigid wall H = 10 m retains sand: gamma = 16.5 kN/m3, phi = 30 deg, c = 0,
    E = 70 000 kPa, nu = 0.35 (thesis 5.4.2). Backfill modelled 2H long on a smooth base
    (with wall and base both smooth the Rankine state is the exact plastic solution and is
    reproduced to rounding; with ``rough_base`` the thrust at 20 mm was measured 5-12 % below
    Rankine, the base friction at the heel carrying part of the load: reported, no bar).
Set-up
    Gravity switched on with the wall held (at-rest state), then the wall (the "left" side of
    the block, horizontal displacement prescribed, vertical free: smooth) is translated away
    from the backfill (active) or toward it (passive); far side on a vertical roller.
Verification
    Horizontal thrust on the wall at the end of the translation against Rankine:
    K_a = tan^2(45 - phi/2) = 1/3, P_a = K_a gamma H^2 / 2 = 275 kN/m (bar 5 %);
    K_p = 3, P_p = 2475 kN/m (bar 10 %).
References
    Rankine (1857); G. S. Bala (2008), thesis, section 5.4.2.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from hybrid.continuum.plastic import PlasticSolver
from hybrid.geometry import build_mesh, load_builder
from hybrid.io import CaseSummary, Check, plot_cell_field, write_continuum_xdmf
from hybrid.materials import Material
from hybrid.model import Displacement, Fixed, Model, Roller
from hybrid.parameters import CaseParameters, param
from hybrid.report import plot_thrust_translation

MESHES = Path(__file__).resolve().parent.parent / "meshes"


@dataclass
class Parameters(CaseParameters):
    mode: str = param("active", choices=("active", "passive"))  # "active" (wall moves away) or
    #                                                             "passive" (toward the backfill)
    height: float = param(10.0, gt=0)  # wall height H [m]
    length: float = param(20.0, gt=0)  # backfill modelled behind the wall [m]
    unit_weight: float = 16.5  # gamma [kN/m3]
    phi: float = 30.0  # [deg]
    psi: float | None = None  # dilation [deg]; None = phi
    cohesion: float = 0.0  # [kPa]
    E: float = 70_000.0  # [kPa]
    nu: float = 0.35  # [-]
    nx: int = param(24, ge=1)  # cells along the backfill
    ny: int = param(12, ge=1)  # cells along the wall
    degree: int = param(2, choices=(1, 2))  # displacement order
    translation: float | None = param(None, gt=0)  # wall movement [m]; None: 0.02 (active), 0.4
    #                                                (passive)
    steps: int = param(20, ge=1)  # translation increments
    rough_base: bool = False  # fix the base (rough) instead of a vertical roller (smooth)


def rankine(mode: str, phi: float, gamma: float, height: float) -> tuple[float, float]:
    """(K, thrust [kN/m]) of Rankine for a cohesionless backfill."""
    sign = -1.0 if mode == "active" else 1.0
    k = math.tan(math.radians(45.0 + sign * phi / 2.0)) ** 2
    return k, 0.5 * k * gamma * height**2


def main(out: str | Path = "results/retaining_wall", **overrides) -> CaseSummary:
    """Smooth rigid wall translated to the active or passive state (C8)."""
    p = Parameters(**overrides)
    if p.mode not in ("active", "passive"):
        raise ValueError(f"mode must be 'active' or 'passive', not {p.mode!r}")
    out = Path(out)
    move = p.translation if p.translation is not None else (
        0.02 if p.mode == "active" else 0.4)
    mesh = build_mesh(load_builder(MESHES / "block.py"), width=p.length, height=p.height,
                      nx=p.nx, ny=p.ny, cells="triangle")
    sand = Material(name="sand", E=p.E, nu=p.nu, unit_weight=p.unit_weight, cohesion=p.cohesion,
                    phi=p.phi, psi=p.phi if p.psi is None else p.psi, plastic=True)
    sign = -1.0 if p.mode == "active" else 1.0
    model = Model(mesh, {"soil": sand},
                  supports=[Fixed("base") if p.rough_base else Roller("base", "y"),
                            Roller("right", "x"),
                            Displacement("left", ux=sign * move)])
    solver = PlasticSolver(model, degree=p.degree)
    solver.apply_gravity(steps=2).require()
    at_rest = abs(solver.reaction("left", 0))
    solver.monitors["thrust"] = lambda: abs(solver.reaction("left", 0))
    analysis = solver.ramp(1.0, p.steps)
    translation = np.array([0.0] + [r.load_factor * move for r in solver.history
                                    if "thrust" in r.monitors])
    thrust = np.array([at_rest] + [r.monitors["thrust"] for r in solver.history
                                   if "thrust" in r.monitors])
    analysis.require_limit(translation, thrust if p.mode == "passive" else -thrust)
    k, reference = rankine(p.mode, p.phi, p.unit_weight, p.height)
    bar = 0.05 if p.mode == "active" else 0.10
    state = solver.state()
    summary = CaseSummary(f"retaining_wall {p.mode} (C8)", out, p, results={
        "cells": state.info["cells"], "steps": state.info["steps"],
        "newton_iterations": state.info["newton_iterations"],
        "wall_time_s": state.info["wall_time_s"], "completed": analysis.completed,
        "K_rankine": k, "at_rest_thrust_kN_per_m": at_rest,
        "curve": {"translation_m": translation, "thrust_kN_per_m": thrust},
    }, checks={f"{p.mode}_thrust": Check(float(thrust[-1]), reference,
                                         None if p.rough_base else bar, "kN/m",
                                         f"Rankine K = {k:.4g}")})
    write_continuum_xdmf(out / "continuum.xdmf", state)
    plot_cell_field(out / f"{p.mode}_plastic_strain.png", model.mesh, state.cell_plastic_strain(),
                    title=f"{p.mode.capitalize()} state: plastic strain",
                    label="plastic strain [-]", cmap="magma_r")
    if state.comm.rank == 0:
        plot_thrust_translation(out / f"{p.mode}_thrust.png", translation, thrust,
                                {f"Rankine {p.mode}": reference},
                                title=f"C8: smooth wall, {p.mode}")
    summary.write(out / "summary.json", state.comm)
    return summary


if __name__ == "__main__":
    from hybrid.case import run_case

    raise SystemExit(run_case(main, Parameters))
