"""C4: gravity switch-on in a 10 m high, 30 degree slope (thesis 3.4.4).

Objective
    The initial stress state of a slope, the starting point of every slope analysis.
Problem
    A 10 m high slope at 30 degrees on a 10 m thick foundation layer; flat ground 100 m beyond
    the toe and the crest (far enough for the lateral spreading under the slope to fade).
    Soil: E = 20 000 kPa, nu = 0.3, gamma = 20 kN/m3 (elastic).
Set-up
    Base fixed, sides on vertical rollers; self-weight switched on in one step.
Verification
    Far from the slope the state is one-dimensional: sigma_v = -gamma z and
    sigma_h = K0 sigma_v with K0 = nu / (1 - nu), checked on verticals 1 m inside both side
    boundaries (bar 2 %). Mesh convergence: the stress at points inside the slope on the given
    mesh and on a mesh twice as fine (reported).
References
    G. S. Bala (2008), thesis, section 3.4.4; any soil-mechanics text for the oedometric K0.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from hybrid.continuum import solve_elastic
from hybrid.geometry import build_mesh, load_builder
from hybrid.io import CaseSummary, Check, continuum_figures, write_continuum_xdmf
from hybrid.materials import Material
from hybrid.model import Fixed, Model, Roller
from hybrid.parameters import CELLS, CaseParameters, param

MESHES = Path(__file__).resolve().parent.parent / "meshes"


@dataclass
class Parameters(CaseParameters):
    height: float = param(10.0, gt=0)  # slope height [m]
    angle: float = param(30.0, gt=0, lt=90)  # slope angle [deg]
    foundation_depth: float = param(10.0, gt=0)  # layer below the toe [m]
    flat: float = param(100.0, gt=0)  # flat ground modelled beyond the toe and beyond the crest
    #                                   [m]
    E: float = 20_000.0  # Young's modulus [kPa]
    nu: float = 0.3  # Poisson's ratio [-]
    unit_weight: float = 20.0  # gamma [kN/m3]
    size: float = param(1.0, gt=0)  # element size [m]
    cells: str = param("triangle", choices=CELLS)  # "triangle" or "quadrilateral"
    degree: int = param(2, choices=(1, 2))  # displacement order
    convergence: bool = True  # also solve with elements half as large


def solve(p: Parameters, refinement: float = 1.0):
    """Build and solve the slope under self-weight."""
    mesh = build_mesh(load_builder(MESHES / "slope.py"), height=p.height, angle=p.angle,
                      foundation_depth=p.foundation_depth, toe_x=p.flat,
                      crest_length=p.flat, size=p.size / refinement,
                      cells=p.cells)
    soil = Material(name="soil", E=p.E, nu=p.nu, unit_weight=p.unit_weight)
    model = Model(mesh, {"soil": soil},
                  supports=[Fixed("base"), Roller("left", "x"), Roller("right", "x")])
    return solve_elastic(model, gravity=True, degree=p.degree)


def main(out: str | Path = "results/slope_gravity", **overrides) -> CaseSummary:
    """Slope under gravity switch-on (C4): far-field geostatic stresses."""
    p = Parameters(**overrides)
    out = Path(out)
    state = solve(p)
    k0 = p.nu / (1 - p.nu)
    crest_x = p.flat + p.height / math.tan(math.radians(p.angle))
    right_x = crest_x + p.flat
    checks: dict[str, Check] = {}
    profiles = {}
    for side, x, top in (("toe_side", 1.0, 0.0), ("crest_side", right_x - 1.0, p.height)):
        depth_total = top + p.foundation_depth
        z = np.linspace(0.2, 0.9, 8) * depth_total
        pts = np.column_stack([np.full_like(z, x), top - z])
        s = state.stress_at(pts)
        sv_ref = -p.unit_weight * z
        profiles[side] = {"x": x, "z": z, "sigma_v": s[:, 1], "sigma_h": s[:, 0]}
        ev = np.abs(s[:, 1] - sv_ref) / np.abs(sv_ref)
        eh = np.abs(s[:, 0] - k0 * sv_ref) / np.abs(k0 * sv_ref)
        iv, ih = int(np.argmax(ev)), int(np.argmax(eh))
        checks[f"sigma_v_{side}_worst"] = Check(float(s[iv, 1]), float(sv_ref[iv]), 0.02, "kPa",
                                                f"gamma z, z = {z[iv]:.2f} m")
        checks[f"sigma_h_{side}_worst"] = Check(float(s[ih, 0]), float(k0 * sv_ref[ih]), 0.02,
                                                "kPa", f"K0 gamma z, z = {z[ih]:.2f} m")
    summary = CaseSummary("slope_gravity (C4)", out, p, results={
        "K0": k0, "cells": state.info["cells"], "far_field": profiles}, checks=checks)
    if p.convergence:
        probe = np.array([[0.5 * (p.flat + crest_x), 0.0], [crest_x, 0.5 * p.height],
                          [p.flat, -5.0]])
        coarse_s = state.stress_at(probe)
        fine_s = solve(p, 2.0).stress_at(probe)
        change = float(np.max(np.abs(coarse_s - fine_s)) / np.max(np.abs(fine_s)))
        summary["mesh_convergence"] = {"points": probe, "stress": coarse_s,
                                       "stress_fine_mesh": fine_s,
                                       "max_change_over_max_stress": change}
    write_continuum_xdmf(out / "continuum.xdmf", state)
    continuum_figures(out, state)
    summary.write(out / "summary.json", state.comm)
    return summary


if __name__ == "__main__":
    from hybrid.case import run_case

    raise SystemExit(run_case(main, Parameters))
