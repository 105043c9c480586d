"""C10: staged construction of a fill placed in lifts (thesis 6.3.1).

Objective
    Check staged construction: material switched on lift by lift, each lift brought to
    equilibrium, no stress in material not yet placed, displacements of a lift counted from
    its placement.
Problem
    A laterally confined fill column (wide embankment centre) 8 m high placed in 4 lifts of
    2 m: gamma = 20 kN/m3, E = 20 000 kPa, nu = 0.3, elastic (a plastic variant may be set with
    ``cohesion``/``phi``; the closed forms below then no longer hold).
Set-up
    Base fixed, sides on vertical rollers; each lift is activated and its weight ramped in.
Verification (bar 1 %)
    * after every stage, zero stress in the lifts not yet placed (exactly);
    * end state: sigma_v = -gamma (H - y), sigma_h = K0 sigma_v, K0 = nu / (1 - nu);
    * settlement of each lift top at the end against the one-dimensional staged closed form
      u(y_k) = -(gamma / M) sum_{j >= k} dsigma_j(y_k) ..., with M the constrained modulus:
      lift j adds gamma h below it and gamma (y_j - s) inside it, and a node moves only under
      the lifts placed from its own lift on (its displacement starts when it is placed).
References
    G. S. Bala (2008), thesis, section 6.3.1; any text on 1-D consolidation-free staged fills.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from hybrid.continuum.plastic import PlasticSolver
from hybrid.geometry import build_mesh, load_builder
from hybrid.io import CaseSummary, Check, plot_cell_field, write_continuum_xdmf
from hybrid.materials import Material
from hybrid.model import Fixed, Model, Roller
from hybrid.parameters import CaseParameters, param

MESHES = Path(__file__).resolve().parent.parent / "meshes"


@dataclass
class Parameters(CaseParameters):
    lifts: int = param(4, ge=1)  # number of lifts
    lift_thickness: float = param(2.0, gt=0)  # [m]
    width: float = param(2.0, gt=0)  # column width [m]
    unit_weight: float = 20.0  # gamma [kN/m3]
    E: float = 20_000.0  # [kPa]
    nu: float = 0.3  # [-]
    cohesion: float = 0.0  # [kPa] (0 and phi = 0: elastic)
    phi: float = 0.0  # [deg]
    degree: int = param(2, choices=(1, 2))  # displacement order
    ramp_steps: int = param(2, ge=1)  # increments of each lift's weight


def staged_settlement(y_top: float, lifts: int, h: float, gamma: float, M: float) -> float:
    """Closed-form 1-D displacement [m] at the end of a lift-top node at height y_top."""
    k = int(round(y_top / h))  # the node is the top of lift k (placed with lift k)
    u = 0.0
    for j in range(k, lifts + 1):
        if j == k:  # own lift: weight gamma (y_k - s) inside it, gamma h below
            u -= gamma / M * (h * (k - 1) * h + h * h / 2.0)
        else:  # later lifts add gamma h over the whole column below the node
            u -= gamma * h / M * y_top
    return u


def main(out: str | Path = "results/staged_embankment", **overrides) -> CaseSummary:
    """Fill column placed in lifts (C10)."""
    p = Parameters(**overrides)
    out = Path(out)
    mesh = build_mesh(load_builder(MESHES / "layers.py"), width=p.width,
                      lift_thickness=p.lift_thickness, lifts=p.lifts)
    fill = Material(name="fill", E=p.E, nu=p.nu, unit_weight=p.unit_weight, cohesion=p.cohesion,
                    phi=p.phi)
    names = [f"lift{k + 1}" for k in range(p.lifts)]
    model = Model(mesh, dict.fromkeys(names, fill),
                  supports=[Fixed("base"), Roller("left", "x"), Roller("right", "x")])
    solver = PlasticSolver(model, degree=p.degree)
    solver.set_active([])  # nothing built yet; each lift comes with its weight
    leak = 0.0
    for k, name in enumerate(names):
        solver.activate([name], steps=p.ramp_steps).require()
        later = np.concatenate([mesh.cells(n) for n in names[k + 1:]] or [np.array([], int)])
        s = solver.stress.reshape(solver.sspace.num_cells, -1, 4)
        leak = max(leak, float(np.max(np.abs(s[later]), initial=0.0)))
    state = solver.state()
    H = p.lifts * p.lift_thickness
    M = p.E * (1 - p.nu) / ((1 + p.nu) * (1 - 2 * p.nu))
    k0 = p.nu / (1 - p.nu)
    ys = np.linspace(0.25, H - 0.25, 15)
    pts = np.column_stack([np.full_like(ys, 0.37 * p.width), ys])
    s = state.stress_at(pts)
    sv = -p.unit_weight * (H - ys)
    tops = np.arange(1, p.lifts + 1) * p.lift_thickness
    u = state.displacement_at(np.column_stack([np.full_like(tops, 0.5 * p.width), tops]))[:, 1]
    u_ref = np.array([staged_settlement(y, p.lifts, p.lift_thickness, p.unit_weight, M)
                      for y in tops])
    iv = int(np.argmax(np.abs(s[:, 1] - sv) / np.abs(sv)))
    ih = int(np.argmax(np.abs(s[:, 0] - k0 * sv) / np.abs(k0 * sv)))
    iu = int(np.argmax(np.abs(u - u_ref) / np.abs(u_ref)))
    checks = {
        "sigma_v_worst": Check(float(s[iv, 1]), float(sv[iv]), 0.01, "kPa", "gamma (H - y)"),
        "sigma_h_worst": Check(float(s[ih, 0]), float(k0 * sv[ih]), 0.01, "kPa", "K0 gamma z"),
        "lift_top_settlement_worst": Check(float(u[iu]), float(u_ref[iu]), 0.01, "m",
                                           f"1-D staged closed form, y = {tops[iu]:.1f} m"),
        "max_stress_in_unplaced_lifts": Check(leak, 0.0, 0.0, "kPa", "exactly zero"),
    }
    summary = CaseSummary("staged_embankment (C10)", out, p, results={
        "lift_tops_m": tops, "settlement_m": u, "settlement_closed_form_m": u_ref},
        checks=checks)
    write_continuum_xdmf(out / "continuum.xdmf", state)
    plot_cell_field(out / "settlement.png", model.mesh, state.cell_displacement()[:, 1],
                    title="Settlement at the end of construction", label="u_y [m]")
    summary.write(out / "summary.json", state.comm)
    return summary


if __name__ == "__main__":
    from hybrid.case import run_case

    raise SystemExit(run_case(main, Parameters))
