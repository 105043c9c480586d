"""Indirect displacement control: the load factor as an unknown, past a peak.

Under load control a Newton solver cannot pass a limit point: beyond the peak of a softening
structure there is no equilibrium at a higher load, and a ramp stops there without telling a
peak from a failure to converge. Indirect displacement control (Batoz & Dhatt 1979; de Borst,
Crisfield, Remmers & Verhoosel 2012, *Non-linear Finite Element Analysis of Solids and
Structures*, 2nd ed., section 4.2) prescribes instead the increment of one displacement measure
and solves for the load factor that goes with it. Each increment solves

    R(Du, lambda) = f_int(Du) - f_grav - lambda f_ext = 0,      c . Du = Delta s,

with f_ext the model's surface loads at load factor 1 and c . u the mean of one displacement
component over the dofs of a boundary (``DisplacementControl``: for a footing, its mean
settlement). Newton on the bordered system, with the tangent K of the shared kernel:

    K a = R,   K b = f_ext,   delta lambda = (c . a - g) / (c . b),   delta u = -a + delta lambda b,

g = c . Du - Delta s the constraint's residual (two solves with one factorisation). The load
factor may fall: the curve is followed through the peak and down the softening branch as
long as the controlled displacement keeps growing; a snap-back of that measure (it would have
to turn back) is not followed, and the step then fails like any other non-converged one.
The safeguards of :class:`~hybrid.continuum.plastic.PlasticSolver` apply unchanged (line
search on the joint step, divergence test, ``max_displacement`` per increment, halving of
the increment down to ``min_increment``).
"""

from __future__ import annotations

import logging
import math
import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
import ufl
from dolfinx import fem
from dolfinx.fem import petsc as fem_petsc
from mpi4py import MPI
from petsc4py import PETSc

from hybrid.continuum.analysis import Analysis
from hybrid.continuum.fields import surface_load

if TYPE_CHECKING:
    from hybrid.continuum.plastic import PlasticSolver, StepRecord

__all__ = ["ControlledPath", "DisplacementControl"]

log = logging.getLogger(__name__)


@dataclass(frozen=True)
class DisplacementControl:
    """The displacement measure that drives a load [m].

    The mean of component ``component`` (0: x, 1: y) of the displacement over the dofs of
    boundary ``boundary``.

    For a footing under a pressure: ``DisplacementControl("footing", 1)`` is its mean vertical
    displacement (negative downwards).
    """

    boundary: str
    component: int = 1

    def __post_init__(self) -> None:
        if self.component not in (0, 1):
            raise ValueError(f"DisplacementControl: component = {self.component!r} must be 0 "
                             "(x) or 1 (y)")


class ControlledPath:
    """Newton under indirect displacement control for one :class:`PlasticSolver`.

    Built once (it assembles the reference load vector and locates the controlled dofs);
    :meth:`follow` moves the controlled measure to a target in increments.
    """

    def __init__(self, solver: PlasticSolver, control: DisplacementControl) -> None:
        model = solver.model
        if not model.loads:
            raise ValueError("displacement control drives the model's surface loads: the model "
                             "has none; add a Pressure or a Traction")
        if any(value != 0.0 for _, value in solver.bc.prescribed):
            raise ValueError("displacement control scales the surface loads only: remove the "
                             "prescribed displacements (Displacement supports) from the model, "
                             "or ramp them with PlasticSolver.ramp")
        V = solver.disc.V
        facets = model.mesh.facets(control.boundary)  # raises a clear error for an unknown name
        dofs = fem.locate_dofs_topological(V.sub(control.component), 1, facets)
        owned = V.dofmap.index_map.size_local * V.dofmap.index_map_bs
        self._dofs = np.asarray(dofs[dofs < owned], dtype=np.int64)
        self._count = V.mesh.comm.allreduce(len(self._dofs), op=MPI.SUM)
        if self._count == 0:
            raise ValueError(f"displacement control: boundary '{control.boundary}' has no "
                             "dofs; choose a boundary of the mesh")
        self.solver = solver
        self.control = control
        one = fem.Constant(V.mesh, PETSc.ScalarType(1.0))
        self._load_form = fem.form(surface_load(model, ufl.TestFunction(V), solver.disc.ds, one))
        self._b = fem.Function(V)  # K^-1 f_ext
        # the last converged increment (Du, d lambda, d s) and the step count after it: it is
        # the first iterate of the next one only if nothing else moved the solver since
        self._last: tuple[np.ndarray, float, float] | None = None
        self._last_count = -1
        self._d_lam = 0.0  # the load-factor increment of the line search's last move

    # --- the controlled measure ------------------------------------------------------------
    def measure(self, values: np.ndarray) -> float:
        """The measure c . u: the controlled component's mean over the boundary's dofs [m]."""
        local = float(np.sum(values[self._dofs]))
        return self.solver.disc.V.mesh.comm.allreduce(local, op=MPI.SUM) / self._count

    def displacement(self) -> float:
        """The controlled measure of the solver's total displacement [m]."""
        return self.measure(self.solver.u.x.array)

    def _reference_load(self, bcs: list) -> PETSc.Vec:
        f = fem_petsc.assemble_vector(self._load_form)
        f.ghostUpdate(addv=PETSc.InsertMode.ADD, mode=PETSc.ScatterMode.REVERSE)
        fem_petsc.set_bc(f, bcs)
        return f

    # --- one increment --------------------------------------------------------------------
    def _newton(self, ds: float, guess: tuple[np.ndarray, float] | None
                ) -> tuple[bool, list[float], float]:
        """Solve one increment c . Du = ``ds``; returns (converged, residuals, d lambda)."""
        s = self.solver
        opts = s.options
        bcs = s.bc.bcs + s._inactive_bcs
        s.bc.scale(0.0)
        s._bcs_hom = bcs
        lam0 = s.load_factor
        s._grav.value = s.gravity_factor
        du = s.Du.x.array
        if guess is not None:
            du[:] = guess[0]
            d_lam = guess[1]
        else:
            du[:] = 0.0
            d_lam = 0.0
        fem.set_bc(du, bcs)
        s.Du.x.scatter_forward()
        f_ext = self._reference_load(bcs)
        s._lam.value = lam0 + d_lam
        s._update_stress()
        norm = s._residual()
        gap = self.measure(du) - ds
        residuals: list[float] = []
        scale = max(s._internal_norm(), abs(float(s._lam.value)) + 1.0, 1.0)
        try:
            for _ in range(opts.max_iterations):
                residuals.append(norm)
                if not np.isfinite(norm):
                    return False, residuals, d_lam
                if norm <= opts.tolerance * scale and abs(gap) <= 1e-10 * abs(ds):
                    return True, residuals, d_lam
                # divergence against the first residual of the increment; from a zero first
                # iterate that residual is the converged one (~0): use the predictor's instead
                if len(residuals) > 1 and norm > opts.divergence * max(residuals[:2]):
                    return False, residuals, d_lam
                s.A.zeroEntries()
                fem_petsc.assemble_matrix(s.A, s._jacobian_form, bcs=bcs)  # type: ignore[misc]
                s.A.assemble()
                s.ksp.solve(s.b, s.delta.vector)  # a = K^-1 R
                if s.ksp.getConvergedReason() < 0:
                    return False, residuals, d_lam
                s.ksp.solve(f_ext, self._b.vector)  # b = K^-1 f_ext
                if s.ksp.getConvergedReason() < 0:
                    return False, residuals, d_lam
                s.delta.x.scatter_forward()
                self._b.x.scatter_forward()
                a, b = s.delta.x.array, self._b.x.array
                cb = self.measure(b)
                if not math.isfinite(cb) or cb == 0.0:
                    return False, residuals, d_lam  # the load does not move the measure
                dd_lam = (self.measure(a) - gap) / cb
                move = self._joint(du.copy(), -a + dd_lam * b, lam0, d_lam, dd_lam)
                norm = s._line_search(move, norm)
                d_lam = self._d_lam
                gap = self.measure(du) - ds
                s.iterations_total += 1
            residuals.append(norm)
            return (norm <= opts.tolerance * scale and abs(gap) <= 1e-10 * abs(ds),
                    residuals, d_lam)
        finally:
            f_ext.destroy()

    def _joint(self, du: np.ndarray, direction: np.ndarray, lam0: float, d_lam: float,
               change: float) -> Callable[[float], None]:
        """The line search's joint move of Du and of the load factor.

        Du + step x ``direction`` and d lambda + step x ``change`` (kept in ``_d_lam``).
        """
        s = self.solver
        along = s._along(du, direction)

        def move(step: float) -> None:
            along(step)
            self._d_lam = d_lam + step * change
            s._lam.value = lam0 + self._d_lam
        return move

    def step(self, ds: float) -> StepRecord | None:
        """Advance the controlled measure by ``ds`` [m].

        Returns None (state unchanged) if no equilibrium was found. The first iterate is the
        last converged increment scaled.
        """
        s = self.solver
        start = time.perf_counter()
        guess = None
        if self._last is not None and self._last_count == len(s.history):
            du, dl, ds_prev = self._last
            guess = (du * (ds / ds_prev), dl * (ds / ds_prev))
        ok, residuals, d_lam = self._newton(ds, guess)
        ok = ok and s._small_strain()
        s.wall_time += time.perf_counter() - start
        if not ok:
            s._lam.value = s.load_factor
            s.sspace.assign(s.stress_q, s.stress)
            self._last = None
            return None
        self._last = (s.Du.x.array.copy(), d_lam, ds)
        record = s._commit(None, 0.0, len(residuals) - 1, residuals, d_lam, 0.0)
        self._last_count = len(s.history)
        return record

    def follow(self, target: float, steps: int, *,
               stop: Callable[[PlasticSolver], bool] | None = None,
               min_increment: float | None = None) -> Analysis:
        """Move the controlled measure to ``target`` [m] in ``steps`` increments.

        Increments are halved when Newton fails, down to ``min_increment`` (default
        ``NewtonOptions.min_increment``) of the first, and regrown after converged ones, as
        in :meth:`PlasticSolver.ramp`. ``stop(solver)`` True after a converged increment ends
        the path there (completed). Returns an :class:`Analysis` whose ``factor`` is the
        controlled displacement reached [m]; the load factor of each step is in
        ``solver.history``. A path that stopped short found the peak if the load fell or the
        structure's stiffness vanished on its last step
        (:meth:`~hybrid.continuum.analysis.Analysis.require_limit`); the collapse load is
        then the largest load factor of the path.
        """
        from hybrid.continuum.plastic import IncrementControl

        if steps < 1:
            raise ValueError(f"follow: steps = {steps} must be >= 1")
        if not math.isfinite(target):
            raise ValueError(f"follow: target = {target!r} m must be a finite displacement")
        s = self.solver
        current = self.displacement()
        stage = f"displacement of '{self.control.boundary}'"
        size = (target - current) / steps
        if size == 0.0:
            return Analysis(True, current, 0, stage, target)
        control = IncrementControl.of(size, s.options)
        if min_increment is not None:
            control.smallest = abs(size) * min_increment
        while abs(target - current) > 1e-12 * max(abs(target), abs(size)):
            inc = control.size if abs(control.size) < abs(target - current) else target - current
            if self.step(inc) is None:
                if not control.cut():
                    log.info("%s: no equilibrium beyond %.6g m", stage, current)
                    return Analysis(False, current, control.cuts, stage, target)
                continue
            control.grow()
            current = self.displacement()
            if stop is not None and stop(s):
                break
        return Analysis(True, current, control.cuts, stage, target)
