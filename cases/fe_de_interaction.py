"""D6: a loaded block dropped on a 100-element tied assembly (thesis 4.9.2, "FE-DE interaction").

Objective
    A discrete body interacting by contact with a tied (continuum-like) assembly: the load it
    carries must pass through the contact into the assembly and down to its base.
Problem
    A 10 m x 10 m assembly of 10 x 10 tied Q4 elements; a 2 m x 0.5 m block (4 x 1 Q4) 0.02 m
    above the middle of its top, loaded on its top edge by q = 200 kPa. E = 100 000 kPa,
    nu = 0.3, rho = 2 t/m3, contact friction 30 deg, contact damping ratio 0.3; gravity off.
Set-up
    Assembly base fixed, sides on vertical rollers; the pressure is lumped to the block's top
    nodes (q x edge length / 2 per node); mass damping alpha = 5 1/s until rest
    (E_kin <= 1e-7 of its peak).
Verification
    * Vertical stress in the block at rest = -q, the load over its width (bar 5 %; the
      thesis reports ~200 kPa).
    * The assembly's top row carries the whole load q B (sum of its sigma_yy x element width,
      bar 5 %) and the base reaction equals q B (bar 1 %, global equilibrium).
    * Energy: E_kin + E_strain + E_contact never exceeds the work of the load (excess bar 1 %
      of the supply, as D5); the run ends at rest.
References
    G. S. Bala (2008), thesis, section 4.9.2.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from hybrid.discrete.builders import blocks
from hybrid.discrete.energy import energy_excess, energy_peak_ratio
from hybrid.discrete.outputs import standard_outputs
from hybrid.discrete.runs import require_serial
from hybrid.discrete.solver import ExplicitSolver, RunOptions
from hybrid.io import CaseSummary, Check
from hybrid.materials import Contact, Material
from hybrid.parameters import CaseParameters, param
from hybrid.report import plot_energy


@dataclass
class Parameters(CaseParameters):
    q: float = 200.0  # pressure on the block's top edge [kPa]
    E: float = 1.0e5  # Young's modulus [kPa]
    nu: float = 0.3  # Poisson's ratio [-]
    density: float = param(2.0, gt=0)  # [t/m3]
    width: float = param(10.0, gt=0)  # assembly width W [m]
    height: float = param(10.0, gt=0)  # assembly height H [m]
    n: int = param(10, ge=1)  # elements per side of the assembly (n x n)
    block_width: float = param(2.0, gt=0)  # B [m]
    block_height: float = param(0.5, gt=0)  # [m]
    block_nx: int = param(4, ge=1)  # elements across the block (one row)
    drop: float = param(0.02, ge=0)  # initial clearance under the block [m]
    contact_phi: float = 30.0  # contact friction angle [deg]
    contact_damping: float = param(0.3, ge=0, le=1)  # contact normal damping ratio [-]
    mass_damping: float = param(5.0, ge=0)  # mass damping alpha (dynamic relaxation) [1/s]
    rest: float = param(1e-7, gt=0)  # stop when E_kin <= rest x max(peak E_kin, E_strain) [-]
    max_steps: int = param(60_000, ge=1)  # step limit [-]
    check_every: int = param(200, ge=1)  # steps between energy records
    output_every: int = param(1000, ge=0)  # steps between XDMF frames and PNG snapshots
    progress: bool = True  # show a progress bar


def main(out: str | Path = "results/fe_de_interaction", **overrides) -> CaseSummary:
    """A loaded block on a tied assembly passes its load q B through the contact (D6)."""
    require_serial("fe_de_interaction")
    p = Parameters(**overrides)
    out = Path(out)
    W, H, B, q = p.width, p.height, p.block_width, p.q
    mat = Material(name="block", E=p.E, nu=p.nu, density=p.density,
                   contact=Contact(damping=p.contact_damping, phi=p.contact_phi))
    st = blocks([(W, H, p.n, p.n, (0.0, 0.0), 0),
                 (B, p.block_height, p.block_nx, 1, (W / 2 - B / 2, H + p.drop), 0)],
                [mat], gravity=(0.0, 0.0))
    n_ass = p.n * p.n
    xr = st.x_ref
    st.fix(np.isclose(xr[:, 1], 0.0))
    st.fix(np.isclose(xr[:, 0], 0.0) | np.isclose(xr[:, 0], W), x=True, y=False)
    for e in st.element_nodes[n_ass:]:  # Q4 nodes 2, 3 form the top edge (counter-clockwise)
        length = abs(xr[e[2], 0] - xr[e[3], 0])
        st.external_force[[e[2], e[3]], 1] -= q * length / 2.0
    outputs = standard_outputs(out, output_every=p.output_every, progress=p.progress,
                               material_names=[mat.name])
    with ExplicitSolver(st, RunOptions(mass_damping=p.mass_damping), observers=outputs) as solver:
        res = solver.run(until_rest=p.rest, max_steps=p.max_steps, check_every=p.check_every)
    h = res.history

    top_row = np.arange(n_ass - p.n, n_ass)
    base = np.isclose(xr[:, 1], 0.0)
    checks = {
        "block_sigma_yy": Check(float(st.stress[n_ass:, :, 1].mean()), -q, 0.05, "kPa",
                                "load / width = -q (thesis ~200 kPa)"),
        "assembly_top_row_load": Check(
            -float(st.stress[top_row, :, 1].mean(axis=1).sum() * (W / p.n)), q * B, 0.05,
            "kN/m", "whole load q B carried by the top row"),
        "base_reaction": Check(abs(float(np.sum(st.internal_force[base, 1]))), q * B, 0.01,
                               "kN/m", "global equilibrium: reaction = q B"),
        "energy_excess_over_sources": Check(
            energy_excess(h, res.start), 0.0, 0.01, "-",
            "E_kin + E_strain + E_contact <= E(0) + work of the load"),
        **res.rest_checks(p.rest),
    }
    summary = CaseSummary("fe_de_interaction (D6)", out, p, results={
        "dt": res.dt, "steps": res.steps, "time": res.time,
        "stop_reason": res.stop_reason, "wall_time": res.wall_time,
        "energy_peak_over_supply": energy_peak_ratio(h, res.start),
        "block_settlement": float(-(st.x - xr)[st.element_nodes[n_ass:], 1].mean())},
        checks=checks)
    plot_energy(out / "energy.png", h)
    summary.write(out / "summary.json")
    return summary


if __name__ == "__main__":
    from hybrid.case import run_case

    raise SystemExit(run_case(main, Parameters))
