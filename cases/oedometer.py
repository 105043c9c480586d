"""C2: elastic column under gravity, laterally confined (oedometric).

Objective
    The one-dimensional geostatic state every gravity analysis starts from.
Problem
    A column H = 10 m high, 2 m wide, E = 20 000 kPa, nu = 0.3, gamma = 19 kN/m3.
Set-up
    Base on a vertical roller (smooth), both sides on horizontal rollers (no lateral strain);
    self-weight switched on in one step; free top.
Verification
    sigma_v = -gamma z, sigma_h = sigma_zz = K0 sigma_v with K0 = nu / (1 - nu), sigma_xy = 0,
    on a vertical through the column (bar 0.5 %); top settlement gamma H^2 / (2 M) with
    M = E (1 - nu) / ((1 + nu)(1 - 2 nu)). The stress is linear in depth, so quadratic elements
    reproduce it to rounding.
References
    Any soil-mechanics text (oedometric K0); hybrid.references.oedometer_stress.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from hybrid.continuum import solve_elastic
from hybrid.geometry import build_mesh, load_builder
from hybrid.io import CaseSummary, Check, continuum_figures
from hybrid.materials import Material
from hybrid.model import Model, Roller
from hybrid.parameters import CELLS, CaseParameters, param
from hybrid.references import oedometer_settlement, oedometer_stress
from hybrid.report import plot_profile

MESHES = Path(__file__).resolve().parent.parent / "meshes"


@dataclass
class Parameters(CaseParameters):
    height: float = param(10.0, gt=0)  # column height H [m]
    width: float = param(2.0, gt=0)  # column width [m]
    E: float = 20_000.0  # Young's modulus [kPa]
    nu: float = 0.3  # Poisson's ratio [-]
    unit_weight: float = 19.0  # gamma [kN/m3]
    nx: int = param(2, ge=1)  # elements across
    ny: int = param(8, ge=1)  # elements up
    cells: str = param("quadrilateral", choices=CELLS)  # "quadrilateral" or "triangle"
    degree: int = param(2, choices=(1, 2))  # displacement order (1 or 2)


def main(out: str | Path = "results/oedometer", **overrides) -> CaseSummary:
    """Confined column under gravity (C2): sigma_v = -gamma z, sigma_h = K0 sigma_v."""
    p = Parameters(**overrides)
    out = Path(out)
    mesh = build_mesh(load_builder(MESHES / "block.py"), width=p.width, height=p.height,
                      nx=p.nx, ny=p.ny, cells=p.cells)
    soil = Material(name="soil", E=p.E, nu=p.nu, unit_weight=p.unit_weight)
    model = Model(mesh, {"soil": soil}, supports=[Roller("base", "y"), Roller("left", "x"),
                                                  Roller("right", "x")])
    state = solve_elastic(model, gravity=True, degree=p.degree)

    z = np.linspace(0.05, 0.95, 10) * p.height
    pts = np.column_stack([np.full_like(z, 0.35 * p.width), p.height - z])
    s = state.stress_at(pts)
    sv_ref, sh_ref = oedometer_stress(p.unit_weight, p.nu, z)
    checks: dict[str, Check] = {}
    for name, computed, reference in (("sigma_v", s[:, 1], sv_ref), ("sigma_h", s[:, 0], sh_ref),
                                      ("sigma_zz", s[:, 2], sh_ref)):
        rel = np.abs(computed - reference) / np.abs(reference)
        i = int(np.argmax(rel))
        label = "gamma z" if name == "sigma_v" else "K0 gamma z"
        checks[f"{name}_worst"] = Check(float(computed[i]), float(reference[i]), 0.005, "kPa",
                                        f"{label}, z = {z[i]:.2f} m")
    settlement = -float(state.displacement_at(np.array([[0.5 * p.width, p.height]]))[0, 1])
    checks["settlement_top"] = Check(settlement,
                                     oedometer_settlement(p.unit_weight, p.height, p.E, p.nu),
                                     0.005, "m", "gamma H^2 / (2 M)")
    summary = CaseSummary("oedometer (C2)", out, p, results={
        "cells": state.info["cells"], "dofs": state.info["dofs"],
        "profile": {"z": z, "sigma_v": s[:, 1], "sigma_h": s[:, 0],
                    "sigma_v_reference": sv_ref, "sigma_h_reference": sh_ref}},
        checks=checks)
    continuum_figures(out, state)
    if state.comm.rank == 0:
        plot_profile(out / "stress_profile.png", z,
                     {"gamma z": (-sv_ref, "k-"), "K0 gamma z": (-sh_ref, "k--"),
                      "hybrid sigma_v": (-s[:, 1], "o"), "hybrid sigma_h": (-s[:, 0], "s")},
                     xlabel="compressive stress [kPa]",
                     title="C2: confined column under gravity")
    summary.write(out / "summary.json", state.comm)
    return summary


if __name__ == "__main__":
    from hybrid.case import run_case

    raise SystemExit(run_case(main, Parameters))
