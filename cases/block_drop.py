"""D5: a block dropped on two base blocks (thesis 4.9.1).

Objective
    Contact between deformable discrete bodies: impact, damping to rest, and the stresses of
    the resting pile against statics.
Problem
    Two base blocks 1 m x 1 m (4 x 4 Q4 each) 0.2 m apart on a fixed ground line; a
    2.2 m x 0.5 m block (8 x 2 Q4) released 0.05 m above them. E = 100 000 kPa, nu = 0.3,
    rho = 2 t/m3, contact friction 30 deg, contact damping ratio 0.2, gravity 9.81 m/s2.
Set-up
    Base nodes fixed at y = 0; mass damping alpha = 2 1/s (dynamic relaxation) until rest
    (E_kin <= 1e-6 of its peak), contact by the overlap-area law (thesis eq 4.6).
Verification
    * Dropped block at rest: its mean vertical stress is -rho g h / 2 whatever the support
      layout. For a body in equilibrium, integral sigma_yy dA = sum x_y t_y ds + integral
      y b_y dA (divergence theorem); with support tractions only on its base (resultant W,
      the weight) this is -W h / 2, so mean sigma_yy = -rho g h / 2 (bar 5 %).
    * Base blocks: the bottom row (centroid depth d) carries its own column plus half of the
      dropped block (symmetry): sigma_yy = -(rho g d + W_top / (2 b)) (bar 5 %).
    * Energy: E_kin + E_strain (+ the elastic contact energy) never exceeds E(0) + work of
      gravity (excess bar 1 % of the supply); the run ends at rest.
References
    G. S. Bala (2008), thesis, section 4.9.1.
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
from hybrid.materials import GRAVITY, Contact, Material
from hybrid.parameters import CaseParameters, param
from hybrid.report import plot_energy


@dataclass
class Parameters(CaseParameters):
    E: float = 1.0e5  # Young's modulus [kPa]
    nu: float = 0.3  # Poisson's ratio [-]
    density: float = param(2.0, gt=0)  # [t/m3]
    g: float = GRAVITY  # gravity [m/s2]
    base_width: float = param(1.0, gt=0)  # width of each base block [m]
    base_height: float = param(1.0, gt=0)  # height of the base blocks [m]
    gap: float = param(0.2, ge=0)  # horizontal gap between the base blocks [m]
    top_height: float = param(0.5, gt=0)  # height of the dropped block (its width spans both
    #                                       bases) [m]
    drop: float = param(0.05, ge=0)  # initial clearance under the dropped block [m]
    element_size: float = param(0.25, gt=0)  # Q4 element size [m]
    contact_phi: float = 30.0  # contact friction angle [deg]
    contact_damping: float = param(0.2, ge=0, le=1)  # contact normal damping ratio [-]
    mass_damping: float = param(2.0, ge=0)  # mass damping alpha (dynamic relaxation) [1/s]
    rest: float = param(1e-6, gt=0)  # stop when E_kin <= rest x max(peak E_kin, E_strain) [-]
    max_steps: int = param(40_000, ge=1)  # step limit [-]
    check_every: int = param(200, ge=1)  # steps between energy records
    output_every: int = param(1000, ge=0)  # steps between XDMF frames and PNG snapshots
    progress: bool = True  # show a progress bar


def main(out: str | Path = "results/block_drop", **overrides) -> CaseSummary:
    """A block dropped on two base blocks comes to rest with self-weight stresses (D5)."""
    require_serial("block_drop")
    p = Parameters(**overrides)
    out = Path(out)
    b, hb, ht, s = p.base_width, p.base_height, p.top_height, p.element_size
    wt = 2.0 * b + p.gap
    mat = Material(name="block", E=p.E, nu=p.nu, density=p.density,
                   contact=Contact(damping=p.contact_damping, phi=p.contact_phi))

    def n(length: float) -> int:
        return max(round(length / s), 1)

    st = blocks([(b, hb, n(b), n(hb), (0.0, 0.0), 0),
                 (b, hb, n(b), n(hb), (b + p.gap, 0.0), 0),
                 (wt, ht, n(wt), n(ht), (0.0, hb + p.drop), 0)], [mat], gravity=(0.0, -p.g))
    n_base = n(b) * n(hb)
    top = np.arange(2 * n_base, st.n_elements)
    st.fix(np.isclose(st.x_ref[:, 1], 0.0))
    outputs = standard_outputs(out, output_every=p.output_every, progress=p.progress,
                               material_names=[mat.name])
    with ExplicitSolver(st, RunOptions(mass_damping=p.mass_damping), observers=outputs) as solver:
        res = solver.run(until_rest=p.rest, max_steps=p.max_steps, check_every=p.check_every)
    h = res.history

    rg = p.density * p.g
    checks = {
        "dropped_block_mean_sigma_yy": Check(float(st.stress[top, :, 1].mean()), -rg * ht / 2,
                                             0.05, "kPa", "statics: -rho g h / 2"),
    }
    cref = st.x_ref[st.element_nodes].mean(axis=1)
    dy = hb / n(hb)
    expected = -(rg * (hb - dy / 2) + rg * ht * wt / 2.0 / b)
    for side, lo in (("left", 0.0), ("right", b + p.gap)):
        row = (cref[:, 1] < dy) & (cref[:, 0] > lo) & (cref[:, 0] < lo + b)
        checks[f"base_{side}_bottom_row_sigma_yy"] = Check(
            float(st.stress[row, :, 1].mean()), expected, 0.05, "kPa",
            "own column + half the dropped block's weight per base width")
    checks["energy_excess_over_sources"] = Check(
        energy_excess(h, res.start), 0.0, 0.01, "-",
            "E_kin + E_strain + E_contact <= E(0) + work of gravity")
    checks.update(res.rest_checks(p.rest))
    summary = CaseSummary("block_drop (D5)", out, p, results={
        "dt": res.dt, "steps": res.steps, "time": res.time,
        "stop_reason": res.stop_reason, "wall_time": res.wall_time,
        "energy_peak_over_supply": energy_peak_ratio(h, res.start),
        "n_contact_pairs": int(st.contact_pairs.shape[0])}, checks=checks)
    plot_energy(out / "energy.png", h)
    summary.write(out / "summary.json")
    return summary


if __name__ == "__main__":
    from hybrid.case import run_case

    raise SystemExit(run_case(main, Parameters))
