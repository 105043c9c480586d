"""C1: uniform load on a block (thesis 3.4.1).

Objective
    The simplest patch test of the continuum phase: a uniform pressure on a free block gives
    a uniform uniaxial stress exactly.
Problem
    A 12 m x 12 m block of 3 x 3 elements (4 m), E = 35 000 kPa, nu = 0.3, q = 5 kPa on top.
Set-up
    Smooth base (vertical roller); sides free to move horizontally (the left side carries a
    horizontal roller only to remove the rigid-body translation: it takes no force because the
    horizontal stress is zero). No self-weight.
Verification
    sigma_yy = -5 kPa, sigma_xx = tau_xy = 0 at every quadrature point (bar 1e-6 relative to q);
    sigma_zz = nu (sigma_xx + sigma_yy) = -1.5 kPa in plane strain; top settlement
    q (1 - nu^2) H / E.
References
    G. S. Bala (2008), thesis, section 3.4.1.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
from mpi4py import MPI

from hybrid.continuum import solve_elastic
from hybrid.geometry import build_mesh, load_builder
from hybrid.io import CaseSummary, Check, continuum_figures, write_continuum_xdmf
from hybrid.materials import Material
from hybrid.model import Model, Pressure, Roller
from hybrid.parameters import CELLS, CaseParameters, param

MESHES = Path(__file__).resolve().parent.parent / "meshes"


@dataclass
class Parameters(CaseParameters):
    q: float = 5.0  # pressure on top [kPa]
    E: float = 35_000.0  # Young's modulus [kPa]
    nu: float = 0.3  # Poisson's ratio [-]
    size: float = param(12.0, gt=0)  # block width and height [m]
    n: int = param(3, ge=1)  # elements per side
    cells: str = param("quadrilateral", choices=CELLS)  # "quadrilateral" or "triangle"
    degree: int = param(1, choices=(1, 2))  # displacement order (1 or 2)


def main(out: str | Path = "results/uniform_load", **overrides) -> CaseSummary:
    """Uniform load on a block (C1): uniform uniaxial stress."""
    p = Parameters(**overrides)
    out = Path(out)
    mesh = build_mesh(load_builder(MESHES / "block.py"), width=p.size, height=p.size,
                      nx=p.n, ny=p.n, cells=p.cells)
    model = Model(mesh, {"soil": Material(name="soil", E=p.E, nu=p.nu)},
                  supports=[Roller("base", "y"), Roller("left", "x")],
                  loads=[Pressure("top", p.q)])
    state = solve_elastic(model, gravity=False, degree=p.degree)

    s = state.stress.reshape(-1, 4)
    comm = state.comm
    worst = {name: comm.allreduce(float(np.max(np.abs(s[:, i] - ref))) if len(s) else 0.0,
                                  op=MPI.MAX)
             for name, i, ref in (("sigma_xx", 0, 0.0), ("sigma_yy", 1, -p.q),
                                  ("sigma_xy", 3, 0.0), ("sigma_zz", 2, -p.nu * p.q))}
    settlement = -float(state.displacement_at(np.array([[p.size, p.size]]))[0, 1])
    checks = {
        # absolute deviations measured against q: Check's relative error is |dev| / q
        f"{name}_max_deviation_over_q": Check(dev / p.q, 0.0, 1e-6, "-", "uniform stress")
        for name, dev in worst.items()
    }
    checks["settlement_top"] = Check(settlement, p.q * (1 - p.nu**2) * p.size / p.E, 1e-6,
                                     "m", "q (1 - nu^2) H / E, plane strain")
    summary = CaseSummary("uniform_load (C1)", out, p, checks)
    write_continuum_xdmf(out / "continuum.xdmf", state)
    continuum_figures(out, state)
    summary.write(out / "summary.json", comm)
    return summary


if __name__ == "__main__":
    from hybrid.case import run_case

    raise SystemExit(run_case(main, Parameters))
