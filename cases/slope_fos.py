"""C9: factor of safety of a homogeneous slope by strength reduction, on several meshes.

Objective
    The slope factor of safety of the continuum phase against a published value, its mesh
    sensitivity, and an independent limit-equilibrium check (Bishop's simplified method).
Problem
    Griffiths & Lane (1999), example 1: a 2:1 slope (26.57 deg), H = 10 m, on a rigid base at
    toe level; c' = 10 kPa (c'/(gamma H) = 0.05), phi' = 20 deg, psi = 0, gamma = 20 kN/m3,
    E = 100 000 kPa, nu = 0.3.
Set-up
    P2 triangles of size H / n for each n of ``meshes``. Base fixed, far side on a vertical
    roller. The strength search switches the self-weight on (strengths multiplied up if the
    slope cannot carry it: F < 1), then raises F from the newest converged state until no
    equilibrium is found for an increase below ``fos_tolerance``; the jump of the largest
    nodal displacement confirms the mechanism (hybrid.continuum.strength_reduction).
    Bishop's simplified method searches the circles of the same section (rigid base as the
    lowest level a circle may reach).
Verification
    Bishop & Morgenstern (1960) charts give F = 1.38 for this slope (Bishop's simplified
    method; quoted by Griffiths & Lane, who found 1.4 by finite elements): every mesh within
    3 %, the meshes within 2 % of each other, the Bishop search within 1 % (the charts' two
    decimals). With other parameters the published value does not apply and the summary says
    so; F is then reported beside the Bishop value of the same section.
References
    D. V. Griffiths & P. A. Lane (1999), Slope stability analysis by finite elements,
    Geotechnique 49(3), 387-403; A. W. Bishop & N. Morgenstern (1960), Stability
    coefficients for earth slopes, Geotechnique 10(4), 129-150; A. W. Bishop (1955), The use
    of the slip circle in the stability analysis of slopes, Geotechnique 5(1), 7-17.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from hybrid.case import uses_defaults
from hybrid.continuum.plastic import NewtonOptions, PlasticSolver
from hybrid.continuum.series import ContinuumSeries
from hybrid.continuum.strength_reduction import StrengthSearch, factor_of_safety
from hybrid.figures import engineering_figures
from hybrid.geometry import build_mesh, load_builder
from hybrid.io import CaseSummary, Check, plot_cell_field, write_continuum_xdmf
from hybrid.materials import Material
from hybrid.model import Fixed, Model, Roller
from hybrid.parameters import CaseParameters, param
from hybrid.references import critical_circle, uniform_soil
from hybrid.report import plot_curve

MESHES = Path(__file__).resolve().parent.parent / "meshes"
PUBLISHED_F = 1.38  # Bishop & Morgenstern (1960) charts, via Griffiths & Lane (1999)
# the fields that define Griffiths & Lane's example 1 (the published value needs them)
PUBLISHED_PROBLEM = ("height", "gradient", "cohesion", "phi", "unit_weight")


@dataclass
class Parameters(CaseParameters):
    height: float = param(10.0, gt=0)  # slope height H [m]
    gradient: float = param(2.0, gt=0)  # horizontal : vertical (2 -> 26.57 deg)
    crest_length: float = 12.0  # ground modelled behind the crest [m]
    cohesion: float = 10.0  # c' [kPa]
    phi: float = 20.0  # phi' [deg]
    psi: float = 0.0  # dilation angle [deg]
    unit_weight: float = 20.0  # gamma [kN/m3]
    E: float = 100_000.0  # Young's modulus [kPa]
    nu: float = 0.3  # Poisson's ratio [-]
    meshes: str = "16"  # elements per slope height, one analysis each (e.g. "16,24,32") [-]
    degree: int = param(2, choices=(1, 2))  # displacement order (P2 triangles)
    gravity_steps: int = param(4, ge=1)  # increments of the self-weight switch-on [-]
    fos_initial_increment: float = param(0.05, gt=0)  # first relative increase of F [-]
    fos_max_increment: float = param(0.25, gt=0)  # largest relative increase of F [-]
    fos_tolerance: float = param(0.005, gt=0)  # F bracketed to this relative width [-]
    newton_tolerance: float = param(1e-8, gt=0, lt=1)  # relative residual norm at convergence [-]
    newton_max_iterations: int = param(25, ge=1)  # Newton iterations per step [-]


def main(out: str | Path = "results/slope_fos", **overrides: Any) -> CaseSummary:
    """Slope factor of safety by strength reduction on each mesh, beside Bishop (C9)."""
    p = Parameters(**overrides)
    out = Path(out)
    divisions = _divisions(p.meshes)
    crest_x = p.height * p.gradient
    search = StrengthSearch(initial_increment=p.fos_initial_increment,
                            max_increment=p.fos_max_increment, tolerance=p.fos_tolerance)
    newton = NewtonOptions(tolerance=p.newton_tolerance, max_iterations=p.newton_max_iterations)
    soil = Material(name="soil", E=p.E, nu=p.nu, unit_weight=p.unit_weight, cohesion=p.cohesion,
                    phi=p.phi, psi=p.psi)

    # limit equilibrium of the same section: toe at (0, 0), rigid base at toe level
    surface = np.array([[0.0, 0.0], [crest_x, p.height], [crest_x + p.crest_length, p.height]])
    bishop = critical_circle(surface, uniform_soil(p.unit_weight, p.cohesion, p.phi),
                             floor=0.0)

    runs, result, model = [], None, None
    for n in divisions:
        mesh = build_mesh(load_builder(MESHES / "slope.py"), height=p.height,
                          angle=math.degrees(math.atan(1.0 / p.gradient)), foundation_depth=0.0,
                          toe_x=0.0, crest_length=p.crest_length, size=p.height / n)
        model = Model(mesh, {"soil": soil}, supports=[Fixed("base"), Roller("right", "x")])
        solver = PlasticSolver(model, degree=p.degree, options=newton)
        # every switch-on step and trial with equilibrium, the time the strength factor F
        with ContinuumSeries(out / f"strength_reduction_H{n}.xdmf", solver,
                             time="strength_factor") as series:
            result = factor_of_safety(solver, search=search, gravity_steps=p.gravity_steps)
        runs.append({"elements_per_height": n, "element_size_m": p.height / n,
                     "cells": result.state.info["cells"],
                     "newton_iterations": solver.iterations_total,
                     "wall_time_s": solver.wall_time, **result.as_dict(),
                     "series": series.report()})
    assert result is not None and model is not None
    state = result.state
    F = [r["F"] for r in runs]
    published = uses_defaults(p, PUBLISHED_PROBLEM)
    source = "Bishop & Morgenstern (1960) via Griffiths & Lane (1999)"
    checks: dict[str, Check] = {}
    for r in runs:
        checks[f"factor_of_safety_H/{r['elements_per_height']}"] = Check.published(
            r["F"], PUBLISHED_F, 0.03, "-", source, applies=published)
    checks["bishop_search"] = Check.published(bishop.factor, PUBLISHED_F, 0.01, "-", source,
                                              applies=published)
    checks["factor_of_safety_vs_bishop"] = Check(
        F[-1], bishop.factor, None, "-",
        f"this project's Bishop simplified search, same section (finest mesh, H/{divisions[-1]})")
    if len(runs) > 1:  # C9's 2 % bar is for the published slope; reported otherwise
        checks["mesh_spread"] = Check((max(F) - min(F)) / min(F), 0.0,
                                      0.02 if published else None, "-",
                                      "(max F - min F) / min F over the meshes")
    summary = CaseSummary("slope_fos (C9)", out, p, results={
        "factor_of_safety": F[-1], "below_one": runs[-1]["below_one"],
        "mechanism_confirmed": runs[-1]["mechanism_confirmed"],
        "cells": runs[-1]["cells"], "newton_iterations": runs[-1]["newton_iterations"],
        "wall_time_s": runs[-1]["wall_time_s"], "meshes": runs,
        "bishop": {**bishop.as_dict(), "method": "Bishop (1955) simplified, circles from an "
                   "entry-and-exit search, no slip below the rigid base"},
        "published": (f"F = {PUBLISHED_F} ({source})" if published
                      else "no reference for these parameters"),
    }, checks=checks)
    write_continuum_xdmf(out / "continuum.xdmf", state)
    arc = bishop.arc()

    def circle(ax: Any) -> None:
        ax.plot(arc[:, 0], arc[:, 1], "r--", lw=1.5,
                label=f"critical circle (Bishop), F = {bishop.factor:.3f}")
        ax.legend(loc="upper left", fontsize=8)

    plot_cell_field(out / "mechanism_plastic_strain.png", model.mesh,
                    state.cell_plastic_strain(), title=f"Plastic strain at F = {F[-1]:.3f}",
                    label="plastic strain [-]", cmap="magma_r", overlay=circle)
    engineering_figures(out, state, prefix="fos_", when=f"F = {F[-1]:.3f}",
                        increment=result.mechanism, overlay=circle)
    magnitude = np.linalg.norm(state.cell_displacement(result.mechanism), axis=1)
    plot_cell_field(out / "mechanism_displacement.png", model.mesh, magnitude,
                    title="Failure mechanism: displacement increment of the last step",
                    label="|du| [m]", cmap="viridis", overlay=circle)
    if state.comm.rank == 0:
        curves = {f"H/{r['elements_per_height']}": (r["curve"]["displacement_m"],
                                                     r["curve"]["F"]) for r in runs}
        first = curves.pop(f"H/{divisions[0]}")
        refs = {"Bishop simplified (this project)": bishop.factor}
        if published:
            refs["Bishop & Morgenstern (1960)"] = PUBLISHED_F
        plot_curve(out / "strength_reduction_curve.png", *first, label=f"H/{divisions[0]}",
                   xlabel="largest nodal displacement since the search started [m]",
                   ylabel="strength reduction factor F [-]", references=refs, more=curves,
                   title="Strength reduction: F against displacement", xscale="log",
                   origin=False)
    summary.write(out / "summary.json", state.comm)
    return summary


def _divisions(text: str) -> list[int]:
    """Elements per slope height from ``meshes`` ("16,24,32"), coarse to fine."""
    try:
        values = sorted({int(v) for v in text.split(",") if v.strip()})
    except ValueError:
        raise ValueError(f"meshes = {text!r}: give elements per slope height as integers, "
                         "e.g. 16,24,32") from None
    if not values or values[0] < 2:
        raise ValueError(f"meshes = {text!r}: need at least one value >= 2")
    return values


if __name__ == "__main__":
    from hybrid.case import run_case

    raise SystemExit(run_case(main, Parameters))
