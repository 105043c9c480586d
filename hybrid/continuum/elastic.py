"""Linear-elastic plane-strain solution: gravity switch-on, surface loads, supports.

Solves  int sigma(u) : eps(v) dx = int b . v dx + int t . v ds  with
sigma = sigma_0 + D eps(u) (Hooke, plane strain, sigma_zz kept), b = (0, -gamma) when gravity
is switched on. One sparse LU solve (MUMPS).
"""

from __future__ import annotations

import logging
import time

import numpy as np
import ufl
from dolfinx import fem

from hybrid.continuum.fields import (
    Discretisation,
    MaterialFields,
    body_force,
    boundary_conditions,
    elastic_stress,
    strain,
    surface_load,
)
from hybrid.continuum.quadrature import QuadratureSpace, evaluate_at_points
from hybrid.continuum.solver import solve_linear
from hybrid.continuum.state import ContinuumState
from hybrid.model import Model

__all__ = ["solve_elastic"]

log = logging.getLogger(__name__)


def solve_elastic(model: Model, *, gravity: bool = True, loads: bool = True, degree: int = 2,
                  initial_stress: np.ndarray | None = None) -> ContinuumState:
    """Solve the elastic problem of ``model`` in one step.

    Args:
        model: mesh, materials, supports, loads.
        gravity: switch the self-weight on (body force -gamma in y).
        loads: apply the model's surface loads.
        degree: displacement order, 1 (P1/Q1) or 2 (P2/Q2, recommended).
        initial_stress: stress already in equilibrium before this step,
            (n_owned_cells, nqp, 4) [kPa]; the result adds the elastic increment to it.

    Returns:
        The state: displacement, stress at quadrature points (including sigma_zz).
    """
    start = time.perf_counter()
    disc = Discretisation.create(model, degree)
    fields = MaterialFields.create(model)
    V = disc.V
    u, v, du = fem.Function(V, name="displacement"), ufl.TestFunction(V), ufl.TrialFunction(V)
    bc = boundary_conditions(model, V)
    sigma0 = None
    qspace = QuadratureSpace(disc, (4,))
    if initial_stress is not None:
        sigma0 = qspace.function("initial_stress")
        qspace.assign(sigma0, np.asarray(initial_stress, dtype=float))

    a = ufl.inner(elastic_stress(strain(du), fields.lam, fields.mu), strain(v)) * disc.dx
    rhs = 0
    if gravity:
        rhs += ufl.inner(body_force(fields, 1.0), v) * disc.dx
    if loads:
        rhs += surface_load(model, v, disc.ds)
    if sigma0 is not None:
        rhs += -ufl.inner(sigma0, strain(v)) * disc.dx
    if rhs == 0:
        rhs = ufl.inner(ufl.as_vector([0.0, 0.0]), v) * disc.dx
    solve_linear(a, rhs, bc.bcs, u)

    sigma = elastic_stress(strain(u), fields.lam, fields.mu)
    stress = evaluate_at_points(disc, sigma)
    if initial_stress is not None:
        stress = stress + initial_stress
    n, nqp = stress.shape[:2]
    elapsed = time.perf_counter() - start
    info = {"solver": "elastic", "degree": degree, "dofs": V.dofmap.index_map.size_global * 2,
            "cells": model.mesh.mesh.topology.index_map(2).size_global, "wall_time_s": elapsed,
            # what acts in this state, as a plastic solver records it (the handover reads them)
            "gravity_factor": 1.0 if gravity else 0.0, "load_factor": 1.0 if loads else 0.0}
    log.info("elastic solve: %(cells)d cells, %(dofs)d dofs, %(wall_time_s).2f s", info)
    return ContinuumState(model, disc, u, stress, np.zeros((n, nqp)),
                          np.zeros((n, nqp), dtype=np.int8), info)
