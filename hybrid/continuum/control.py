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

Dissipation control (``DissipationControl``): the path parameter is an energy that grows
while material yields, even where the load and every displacement turn back together (a
snap-back, which no displacement measure follows): energy release control (Gutierrez 2004,
Commun. Numer. Meth. Engng 20, 19-29) and the dissipation-based arc-length method (Verhoosel,
Remmers & Gutierrez 2009, IJNME 77, 1290-1321). Here, for an elasto-plastic solid, each
increment prescribes the plastic work of the external force of its start,

    Delta D = F_n . (Du - d lambda y) = tau,        K_e y = f_ext,

F_n the external force of the converged state (its internal force, by equilibrium; gravity
included), y the displacement per unit load factor of the elastic structure (K_e its elastic
stiffness, factorised once per path), so that Du - d lambda y is the part of the increment an
elastic unloading would not recover: 0 for an elastic increment, normally positive while
the material flows (a first-order estimate of the dissipation). y is computed when the path
first moves: the active cells, supports and loads stay as they were along the path. The
constraint is linear (h = F_n, w = -F_n . y in the bordered solve). An elastic state cannot
be steered by it (its slope F_n . (b - y) vanishes): it continues a path on which plastic
flow has begun, after displacement control has stopped for example.
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
from hybrid.continuum.solver import lu_solver

if TYPE_CHECKING:
    from hybrid.continuum.plastic import PlasticSolver, StepRecord

__all__ = ["ControlledPath", "DisplacementControl", "DissipationControl"]

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


@dataclass(frozen=True)
class DissipationControl:
    """The energy dissipated in the structure drives the surface loads [kJ/m] (module docstring).

    Its measure is the energy dissipated since the solver first followed it.
    """


class ControlledPath:
    """Newton under displacement or dissipation control for one :class:`PlasticSolver`.

    Built once (it assembles the reference load vector and locates the controlled dofs);
    :meth:`follow` moves the controlled measure to a target in increments.
    """

    def __init__(self, solver: PlasticSolver,
                 control: DisplacementControl | DissipationControl) -> None:
        model = solver.model
        if not model.loads:
            raise ValueError("a controlled path drives the model's surface loads: the model "
                             "has none; add a Pressure or a Traction")
        if any(value != 0.0 for _, value in solver.bc.prescribed):
            raise ValueError("a controlled path scales the surface loads only: remove the "
                             "prescribed displacements (Displacement supports) from the model, "
                             "or ramp them with PlasticSolver.ramp")
        V = solver.disc.V
        self.solver = solver
        if isinstance(control, DisplacementControl):
            # raises a clear error for an unknown name
            facets = model.mesh.facets(control.boundary)
            dofs = fem.locate_dofs_topological(V.sub(control.component), 1, facets)
            owned = V.dofmap.index_map.size_local * V.dofmap.index_map_bs
            self._dofs = np.asarray(dofs[dofs < owned], dtype=np.int64)
            self._count = V.mesh.comm.allreduce(len(self._dofs), op=MPI.SUM)
            if self._count == 0:
                raise ValueError(f"displacement control: boundary '{control.boundary}' has "
                                 "no dofs; choose a boundary of the mesh")
            self._work: _PlasticWork | None = None
        else:
            self._work = _PlasticWork(solver)
        self._dissipated = 0.0  # energy dissipated along this path [kJ/m] (dissipation only)
        self.control = control
        one = fem.Constant(V.mesh, PETSc.ScalarType(1.0))
        self._load_form = fem.form(surface_load(model, ufl.TestFunction(V), solver.disc.ds, one))
        self._b = fem.Function(V)  # K^-1 f_ext
        # the last converged increment (Du, d lambda, d s) and the step count after it: it is
        # the first iterate of the next one only if nothing else moved the solver since
        self._last: tuple[np.ndarray, float, float] | None = None
        self._last_count = -1
        self._converged: tuple[np.ndarray, float] | None = None  # kept after a failure
        self._d_lam = 0.0  # the load-factor increment of the line search's last move

    # --- the controlled measure ------------------------------------------------------------
    @property
    def stage(self) -> str:
        """The path in words, for messages."""
        if isinstance(self.control, DisplacementControl):
            return f"displacement of '{self.control.boundary}'"
        return "energy dissipated"

    def measure(self, values: np.ndarray) -> float:
        """The measure c . u: the controlled component's mean over the boundary's dofs [m]."""
        if self._work is not None:
            raise TypeError("dissipation control has no displacement measure")
        local = float(np.sum(values[self._dofs]))
        return self.solver.disc.V.mesh.comm.allreduce(local, op=MPI.SUM) / self._count

    def displacement(self) -> float:
        """The controlled measure now: [m] of the total displacement, or [kJ/m] dissipated."""
        if self._work is not None:
            return self._dissipated
        return self.measure(self.solver.u.x.array)

    def _reference_load(self, bcs: list) -> PETSc.Vec:
        f = fem_petsc.assemble_vector(self._load_form)
        f.ghostUpdate(addv=PETSc.InsertMode.ADD, mode=PETSc.ScatterMode.REVERSE)
        fem_petsc.set_bc(f, bcs)
        return f

    # --- one increment --------------------------------------------------------------------
    def _newton(self, ds: float, guess: tuple[np.ndarray, float] | None, fit: bool = False
                ) -> tuple[bool, list[float], float]:
        """Solve one increment of the measure ``ds``; returns (converged, residuals, d lambda).

        ``guess``: the first iterate (Du, d lambda); ``fit``: scale it to the constraint first.
        """
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
        if self._work is not None:
            self._work.start(f_ext)
            if fit:  # another path's increment, scaled to dissipate ds
                done, work = self._work.dissipation(d_lam), self._work.work()
                # an elastic increment dissipates nothing but round-off: no guess then
                scale = ds / done if done > 1e-8 * abs(work) else 0.0
                du *= scale
                d_lam *= scale
                s.Du.x.scatter_forward()
                s._lam.value = lam0 + d_lam
        s._update_stress()
        s._note_flags(first=True)
        norm = s._residual()
        gap = self._gap(du, d_lam, ds)
        residuals: list[float] = []
        scale = s._solve_scale = s._scale()
        try:
            for _ in range(opts.max_iterations):
                residuals.append(norm)
                if not np.isfinite(norm):
                    return False, residuals, d_lam
                if norm <= opts.tolerance * scale and self._closed(gap, ds):
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
                ha, hb = self._slopes()
                if not math.isfinite(hb) or hb == 0.0:
                    return False, residuals, d_lam  # the load does not move the measure
                dd_lam = (ha - gap) / hb
                move = self._joint(du.copy(), -a + dd_lam * b, lam0, d_lam, dd_lam)
                norm = s._line_search(move, norm)
                s._note_flags()
                d_lam = self._d_lam
                gap = self._gap(du, d_lam, ds)
                s.iterations_total += 1
            residuals.append(norm)
            return (norm <= opts.tolerance * scale and self._closed(gap, ds),
                    residuals, d_lam)
        finally:
            f_ext.destroy()

    def _gap(self, du: np.ndarray, d_lam: float, ds: float) -> float:
        """The constraint's residual at the current iterate (its stress updated)."""
        if self._work is None:
            return self.measure(du) - ds
        return self._work.dissipation(d_lam) - ds

    def _closed(self, gap: float, ds: float) -> bool:
        """Whether the constraint holds (to 1e-10 of ds).

        Under dissipation control to 1e-10 of the work F_n . Du if larger: the dissipation is
        a difference of such terms (round-off).
        """
        size = abs(ds) if self._work is None else max(abs(ds), abs(self._work.work()))
        return abs(gap) <= 1e-10 * size

    def _slopes(self) -> tuple[float, float]:
        """The linearised constraint g + h . delta u + w delta lambda: (h . a, h . b + w).

        a = K^-1 R and b = K^-1 f_ext, in ``solver.delta`` and ``_b``.
        """
        s = self.solver
        if self._work is None:
            return self.measure(s.delta.x.array), self.measure(self._b.x.array)
        return self._work.slopes(s.delta.vector, self._b.vector)

    def _recent(self) -> tuple[np.ndarray, float] | None:
        """(Du, d lambda) of the increment that moved the solver last, if it drove the loads.

        A load step of :meth:`PlasticSolver.ramp` or an increment of another controlled path.
        """
        s = self.solver
        for p in s._paths.values():
            if p._converged is not None and p._last_count == len(s.history):
                return p._converged
        last = s._last_increment
        if last is not None and last[1] == "load":
            return last[0], last[2]
        return None

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
        """Advance the controlled measure by ``ds`` ([m], or [kJ/m] dissipated).

        Returns None (state unchanged) if no equilibrium was found. The first iterate is the
        last converged increment scaled.
        """
        s = self.solver
        start = time.perf_counter()
        guess, fit = None, False
        if self._last is not None and self._last_count == len(s.history):
            du, dl, ds_prev = self._last
            guess = (du * (ds / ds_prev), dl * (ds / ds_prev))
        elif self._work is not None:
            # from an elastic first iterate every point answers elastically and the
            # dissipation cannot steer: start from the increment of the path that moved the
            # solver last, scaled to dissipate ds
            recent = self._recent()
            if recent is not None:
                guess, fit = recent, True
        iterations = s.iterations_total
        ok, residuals, d_lam = self._newton(ds, guess, fit)

        def solve(first: tuple[np.ndarray, float] | None) -> tuple[bool, list[float]]:
            nonlocal d_lam
            done, history, d_lam = self._newton(ds, first, fit and first is guess)
            return done, history

        # NewtonOptions.hold_flipping
        ok, residuals = s._retry_holding(ok, residuals, solve, guess,
                                         lambda: (s.Du.x.array.copy(), d_lam))
        ok = ok and s._small_strain()
        s.wall_time += time.perf_counter() - start
        if not ok:
            s._lam.value = s.load_factor
            s.sspace.assign(s.stress_q, s.stress)
            if self._work is None:
                self._last = None
            return None
        self._last = (s.Du.x.array.copy(), d_lam, ds)
        self._converged = (self._last[0], d_lam)
        if self._work is not None:
            self._dissipated += ds
        record = s._commit(None, 0.0, s.iterations_total - iterations, residuals, d_lam, 0.0)
        self._last_count = len(s.history)
        return record

    def follow(self, target: float, steps: int, *,
               stop: Callable[[PlasticSolver], bool] | None = None,
               min_increment: float | None = None) -> Analysis:
        """Move the controlled measure to ``target`` ([m] or [kJ/m]) in ``steps`` increments.

        Increments are halved when Newton fails, down to ``min_increment`` (default
        ``NewtonOptions.min_increment``) of the first, and regrown after converged ones, as
        in :meth:`PlasticSolver.ramp`. ``stop(solver)`` True after a converged increment ends
        the path there (completed). Returns an :class:`Analysis` whose ``factor`` is the
        controlled measure reached; the load factor of each step is in
        ``solver.history``. A path that stopped short found the peak if the load fell or the
        structure's stiffness vanished on its last step
        (:meth:`~hybrid.continuum.analysis.Analysis.require_limit`); the collapse load is
        then the largest load factor of the path.
        """
        from hybrid.continuum.plastic import IncrementControl

        if steps < 1:
            raise ValueError(f"follow: steps = {steps} must be >= 1")
        if not math.isfinite(target):
            raise ValueError(f"follow: target = {target!r} must be a finite number ([m], or "
                             "[kJ/m] dissipated)")
        s = self.solver
        current = self.displacement()
        stage = self.stage
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
                    log.info("%s: no equilibrium beyond %.6g", stage, current)
                    return Analysis(False, current, control.cuts, stage, target)
                continue
            control.grow()
            current = self.displacement()
            if stop is not None and stop(s):
                break
        return Analysis(True, current, control.cuts, stage, target)


class _PlasticWork:
    """The dissipation constraint's pieces (module docstring): F_n and y = K_e^-1 f_ext."""

    def __init__(self, solver: PlasticSolver) -> None:
        self.solver = solver
        self._elastic: PETSc.Vec | None = None  # y, once per path
        self._start: tuple[PETSc.Vec, float] | None = None  # F_n, F_n . y

    def _elastic_displacement(self, f_ext: PETSc.Vec) -> PETSc.Vec:
        """The elastic displacement y = K_e^-1 f_ext (the elastic matrix in the Jacobian form)."""
        s = self.solver
        K = s.table[s.point_material, 0]
        G = s.table[s.point_material, 1]
        lam = K - 2.0 * G / 3.0
        D = np.zeros((s.npoints, 4, 4))
        D[:, :3, :3] = lam[:, None, None]
        D[:, [0, 1, 2], [0, 1, 2]] += 2.0 * G[:, None]
        D[:, 3, 3] = G
        if not s.active.all():  # as in the solver's update: inactive cells nearly void
            D[np.repeat(~s.active, s.disc.num_points)] *= 1e-9
        s.tspace.assign(s.tangent_q, D)
        A = fem_petsc.create_matrix(s._jacobian_form)
        fem_petsc.assemble_matrix(A, s._jacobian_form, bcs=s._bcs_hom)  # type: ignore[misc]
        A.assemble()
        ksp = lu_solver(s.disc.V.mesh.comm, A)
        y = f_ext.duplicate()
        ksp.solve(f_ext, y)
        ok = ksp.getConvergedReason() >= 0
        ksp.destroy()
        A.destroy()
        if not ok:
            raise RuntimeError("dissipation control: the elastic stiffness could not be "
                               "factorised (a mechanism without plasticity: check the supports)")
        return y

    def start(self, f_ext: PETSc.Vec) -> None:
        """At the start of an increment: F_n of the converged state and F_n . y."""
        s = self.solver
        if self._elastic is None:
            self._elastic = self._elastic_displacement(f_ext)
        s.sspace.assign(s.stress_q, s.stress)
        force = fem_petsc.assemble_vector(s._internal_form)
        force.ghostUpdate(addv=PETSc.InsertMode.ADD, mode=PETSc.ScatterMode.REVERSE)
        fem_petsc.set_bc(force, s._bcs_hom)
        if self._start is not None:
            self._start[0].destroy()
        self._start = (force, float(force.dot(self._elastic)))

    def dissipation(self, d_lam: float) -> float:
        """Delta D of the current iterate [kJ/m]."""
        assert self._start is not None
        return self.work() - d_lam * self._start[1]

    def work(self) -> float:
        """F_n . Du of the current iterate [kJ/m]: the work of the force of the start."""
        assert self._start is not None
        return float(self._start[0].dot(self.solver.Du.vector))

    def slopes(self, a: PETSc.Vec, b: PETSc.Vec) -> tuple[float, float]:
        """(h . a, h . b + w) with h = F_n and w = -F_n . y."""
        assert self._start is not None
        force, fy = self._start
        fb = float(force.dot(b))
        hb = fb - fy  # 0 in an elastic state (b = y): round-off taken as 0
        return float(force.dot(a)), (0.0 if abs(hb) <= 1e-12 * (abs(fb) + abs(fy)) else hb)

