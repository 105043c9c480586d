"""Mohr-Coulomb elasto-plastic continuum on dolfinx: incremental loading with Newton.

Each load step solves  R(Du) = int sigma(Du) : eps(v) dx - lambda f_ext(v) = 0  for the
displacement increment Du of the step. ``sigma`` is computed at the quadrature points by the
shared kernel (:mod:`hybrid.constitutive.mohr_coulomb`) from the converged stress of the
previous step and the strain increment eps(Du); its consistent tangent forms the Jacobian.

Globalisation, for non-associated flow (psi < phi) where plain Newton stalls:
  * a safeguarded Newton step: the full step is taken unless it raises the residual norm more
    than ``residual_growth`` (10) times, then it is halved up to ``line_search`` times
    (non-smooth Newton, with points changing return region between iterates, often passes
    through a larger residual on its way to convergence; a strict decrease test makes it
    crawl);
  * an increment whose residual grows ``divergence`` (1e3) times its first value is abandoned
    at once (the iterate has found a mechanism of the trial state: a smaller increment is
    needed, not more iterations);
  * an increment that converges but moves a node by more than ``max_displacement`` (default
    half the smallest cell edge) is rejected like one that does not converge: beyond that the
    small-strain solution no longer describes the geometry, and at a collapse the amplitude
    of the mechanism is indeterminate (Newton may return any of them);
  * with ``hold_flipping`` (off by default), an increment whose Newton solve runs out of
    iterations with points flipping between the elastic and the plastic response is
    retried, holding those points on the elastic branch and releasing the ones that must
    yield (an active-set choice, :meth:`PlasticSolver._newton_holding`); it is accepted
    only as an equilibrium of the unchanged material law. After a retry that fails, the
    increments are halved without one until an increment converges. It tells a Newton
    stall from a limit; it is not the default because it changes the path, and a load
    ramp's collapse test (the displacement running away over the last increment) can then
    fail at the same collapse load;
  * adaptive increments (:class:`IncrementControl`): an increment that does not converge is
    restarted from the last converged state with half its size, down to ``min_increment``
    times the requested one; after each converged increment the size grows by ``growth``
    (1.5), up to the requested one. A stage that cannot go on is returned as an incomplete
    :class:`~hybrid.continuum.analysis.Analysis` holding the last converged factor: the
    caller decides whether that is the answer (a collapse load) or an error
    (:meth:`Analysis.require`).
Convergence: ||R|| <= ``tolerance`` max(||f_ref||, |lambda| + 1) on the free dofs, where f_ref
is the internal force vector of the current stress state and lambda the factor on the surface
loads.
"""

from __future__ import annotations

import logging
import math
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np
import ufl
from dolfinx import fem, la
from dolfinx.fem import petsc as fem_petsc
from mpi4py import MPI
from petsc4py import PETSc

from hybrid.constitutive.mohr_coulomb import elastic_update, mohr_coulomb_update
from hybrid.constitutive.softening import characteristic_length, warn_snap_back
from hybrid.constitutive.table import kernel_table
from hybrid.continuum.analysis import Analysis, largest_nodal_norm
from hybrid.continuum.fields import (
    Discretisation,
    MaterialFields,
    body_force,
    boundary_conditions,
    strain,
    surface_load,
)
from hybrid.continuum.quadrature import QuadratureSpace, evaluate_at_points
from hybrid.continuum.solver import lu_solver
from hybrid.continuum.state import ContinuumState
from hybrid.materials import Material
from hybrid.model import Model
from hybrid.progress import progress

if TYPE_CHECKING:
    from hybrid.continuum.control import (
        ControlledPath,
        DisplacementControl,
        DissipationControl,
    )

__all__ = ["IncrementControl", "NewtonOptions", "PlasticSolver", "StepRecord", "material_table"]

log = logging.getLogger(__name__)

# a Newton solve that runs out of iterations is examined over its last FLIP_WINDOW iterates
# for points whose response flips between elastic and plastic, and retried holding them on
# the elastic branch, in at most HOLD_ROUNDS rounds (PlasticSolver._newton_holding)
FLIP_WINDOW = 6
HOLD_ROUNDS = 10


def material_table(materials: Sequence[Material], strength_factor: float = 1.0) -> np.ndarray:
    """Rows [K, G, c, sin phi, cos phi, sin psi, t] of the kernel, strength divided by F."""
    return kernel_table(materials, strength_factor)[0]


@dataclass(frozen=True)
class NewtonOptions:
    """Newton and increment settings (see the module docstring for the criteria).

    Attributes:
        tolerance: relative residual norm at convergence [-].
        max_iterations: Newton iterations per increment.
        line_search: halvings of the Newton step at most.
        residual_growth: a Newton step raising the residual norm more than this factor is
            halved [-].
        divergence: an increment whose residual norm exceeds this multiple of its first is
            abandoned [-].
        min_increment: smallest increment, as a fraction of the requested one [-].
        max_increment: cap on the load-factor increment of :meth:`PlasticSolver.ramp`.
        growth: factor on the increment after a converged one (1: no regrowth).
        max_displacement: largest nodal displacement of one increment [m] (None: half the
            smallest cell edge of the mesh).
        hold_flipping: retry an increment whose Newton iterates cycle, holding the points
            that flip between the elastic and the plastic response on the elastic branch
            (:meth:`PlasticSolver._newton_holding`; an expert diagnostic that tells a Newton
            stall from a limit, off by default: module docstring).
    """

    tolerance: float = 1e-8
    max_iterations: int = 25
    line_search: int = 4
    residual_growth: float = 10.0
    divergence: float = 1e3
    min_increment: float = 1e-3
    max_increment: float | None = None
    growth: float = 1.5
    max_displacement: float | None = None
    hold_flipping: bool = False

    def __post_init__(self) -> None:
        if not 0 < self.tolerance < 1:
            raise ValueError(f"Newton tolerance {self.tolerance} must be in (0, 1)")
        if self.max_iterations < 1:
            raise ValueError("Newton max_iterations must be >= 1")
        if not 0 < self.min_increment <= 1:
            raise ValueError(f"Newton min_increment {self.min_increment} must be in (0, 1]")
        if self.line_search < 0:
            raise ValueError("Newton line_search must be >= 0")
        if not 1 <= self.growth <= 4:
            raise ValueError(f"Newton growth {self.growth} must be in [1, 4]")
        if self.max_displacement is not None and not self.max_displacement > 0:
            raise ValueError(f"Newton max_displacement {self.max_displacement} must be > 0 m")
        if not 1 <= self.residual_growth < self.divergence:
            raise ValueError("Newton residual_growth must be >= 1 and below divergence")


@dataclass
class IncrementControl:
    """Adaptive increment size: halved after a failure, grown after a success.

    ``size`` is the current signed increment; it never exceeds ``largest`` in magnitude and
    the control gives up (``cut`` returns False) when it falls below ``smallest``.
    """

    size: float
    largest: float
    smallest: float
    growth: float = 1.5
    cuts: int = 0

    @classmethod
    def of(cls, size: float, options: NewtonOptions) -> IncrementControl:
        """Start at ``size``, never above it, down to ``options.min_increment`` of it."""
        return cls(size, abs(size), abs(size) * options.min_increment, options.growth)

    def grow(self) -> None:
        """After a converged increment."""
        self.size = float(np.sign(self.size)) * min(abs(self.size) * self.growth, self.largest)

    def cut(self) -> bool:
        """After a failed increment: halve; False when below the smallest size."""
        self.cuts += 1
        self.size *= 0.5
        return abs(self.size) >= self.smallest


@dataclass
class StepRecord:
    """One converged load step: factor, iterations, residual history, monitored values."""

    load_factor: float
    iterations: int
    residuals: list[float]
    monitors: dict[str, float] = field(default_factory=dict)
    strength_factor: float = 1.0


class PlasticSolver:
    """Incremental elasto-plastic analysis of a :class:`~hybrid.model.Model`.

    The model's surface loads and prescribed displacements are multiplied by the load
    factor lambda; self-weight is a separate factor (``gravity``) switched on by
    :meth:`apply_gravity`. Cells can be switched off (staged construction) with
    :meth:`set_active`. The strengths in force are those of the materials divided by
    ``strength_factor`` (:meth:`set_strength_factor`; 1 by default). Each function in
    ``observers`` is called with (solver, :class:`StepRecord`) after every committed step
    (outputs that only read, e.g. :class:`~hybrid.continuum.series.ContinuumSeries`).
    """

    def __init__(self, model: Model, *, degree: int = 2,
                 options: NewtonOptions | None = None) -> None:
        self.model = model
        self.options = options or NewtonOptions()
        self.disc = disc = Discretisation.create(model, degree)
        self.fields = MaterialFields.create(model)
        V = disc.V
        self.u = fem.Function(V, name="displacement")  # total displacement [m]
        self.Du = fem.Function(V, name="increment")  # increment of the current step [m]
        self.delta = fem.Function(V)
        self.bc = boundary_conditions(model, V)
        self.sspace = QuadratureSpace(disc, (4,))
        self.tspace = QuadratureSpace(disc, (4, 4))
        self.stress_q = self.sspace.function("stress")
        self.tangent_q = self.tspace.function("tangent")
        n, nqp = self.sspace.num_cells, disc.num_points
        self.npoints = n * nqp
        self.stress = np.zeros((self.npoints, 4))  # converged stress [kPa]
        self.plastic_strain = np.zeros(self.npoints)
        self.yielded = np.zeros(self.npoints, dtype=np.int8)
        self._trial = (np.zeros((self.npoints, 4)), np.zeros((self.npoints, 4, 4)),
                       np.zeros(self.npoints), np.zeros(self.npoints, dtype=np.int8))
        materials = [model.materials[k] for k in model.material_names]
        self.materials = materials
        self.strength_factor = 1.0  # c and tan(phi) of the materials divided by this [-]
        self.table = material_table(materials)
        self.point_material = np.repeat(model.material_ids(), nqp).astype(np.int64)
        self.active = np.ones(n, dtype=bool)
        self.load_factor = 0.0
        self.gravity_factor = 0.0
        self.history: list[StepRecord] = []
        self.monitors: dict[str, Callable[[], float]] = {}
        # called with (solver, record) after every committed step (outputs: they only read)
        self.observers: list[Callable[[PlasticSolver, StepRecord], None]] = []

        v, w = ufl.TestFunction(V), ufl.TrialFunction(V)
        self._lam = fem.Constant(V.mesh, PETSc.ScalarType(0.0))
        self._grav = fem.Constant(V.mesh, PETSc.ScalarType(0.0))
        self._active_fn = fem.Function(fem.FunctionSpace(V.mesh, ("DG", 0)), name="active")
        self._active_fn.x.array[:] = 1.0
        external = ufl.inner(body_force(self.fields, self._grav) * self._active_fn, v) * disc.dx
        loads = surface_load(model, v, disc.ds, self._lam)
        if loads != 0:
            external = external + loads
        self._internal_form = fem.form(ufl.inner(self.stress_q, strain(v)) * disc.dx)
        self._residual_form = fem.form(ufl.inner(self.stress_q, strain(v)) * disc.dx - external)
        self._jacobian_form = fem.form(
            ufl.inner(ufl.dot(self.tangent_q, strain(w)), strain(v)) * disc.dx)
        self._strain_expr = fem.Expression(strain(self.Du), disc.points)
        self._cells = np.arange(n, dtype=np.int32)
        x, cells = model.mesh.cell_vertices()
        # crack-band width of each point's cell [m]: the length of strain softening
        cell_length = characteristic_length(x, cells)
        self.point_length = np.repeat(cell_length, nqp)
        warn_snap_back(cell_length, model.material_ids(), self.table)
        edges = np.linalg.norm(x[cells] - x[np.roll(cells, -1, axis=1)], axis=-1)
        smallest = V.mesh.comm.allreduce(float(edges.min(initial=np.inf)), op=MPI.MIN)
        self.max_displacement = (0.5 * smallest if self.options.max_displacement is None
                                 else self.options.max_displacement)  # per increment [m]
        self.A = fem_petsc.create_matrix(self._jacobian_form)
        self.b = fem_petsc.create_vector(self._residual_form)
        self.ksp = lu_solver(V.mesh.comm, self.A)
        self._inactive_bcs: list[Any] = []
        self.iterations_total = 0
        self.wall_time = 0.0
        # the last converged increment, what drove it ("load" or "strength") and its size:
        # scaled, it is the first iterate of the next increment of the same kind
        self._last_increment: tuple[np.ndarray, str, float] | None = None
        # see :meth:`follow`
        self._paths: dict[DisplacementControl | DissipationControl, ControlledPath] = {}
        # points held on the elastic branch (indices; None: none), the yield flags of the
        # iterates of the last Newton solve, whether a retry holding points failed since the
        # last converged increment, and the increments converged by such a retry
        # (:meth:`_newton_holding`)
        self._held: np.ndarray | None = None
        self._flag_history: list[np.ndarray] = []
        self._hold_failed = False
        self.held_increments = 0
        self._solve_scale = 1.0  # the residual reference of the last Newton solve

    # --- constitutive update -------------------------------------------------------------
    def _update_stress(self) -> None:
        """Kernel call: trial stress/tangent from the converged state and eps(Du)."""
        deps = self._strain_expr.eval(self._cells).reshape(self.npoints, 4)
        stress, tangent, pstrain, yielded = self._trial
        pstrain[:] = self.plastic_strain
        mohr_coulomb_update(self.stress, deps, self.point_material, self.table,
                            self.point_length, stress, tangent, pstrain, yielded, True)
        if self._held is not None:
            held = self._held
            elastic_update(self.stress, deps, self.point_material, self.table, held, stress,
                           tangent)
            pstrain[held] = self.plastic_strain[held]
            yielded[held] = 0
        if not self.active.all():  # fill not yet placed carries nothing and never yields
            off = np.repeat(~self.active, self.disc.num_points)
            stress[off] = 0.0
            tangent[off] = 1e-9 * tangent[off]
            pstrain[off] = self.plastic_strain[off]
            yielded[off] = 0
        self.sspace.assign(self.stress_q, stress)
        self.tspace.assign(self.tangent_q, tangent)

    def _residual(self) -> float:
        """Assemble R into self.b (free dofs, BC rows zeroed) and return its norm."""
        with self.b.localForm() as loc:
            loc.set(0.0)
        fem_petsc.assemble_vector(self.b, self._residual_form)
        self.b.ghostUpdate(addv=PETSc.InsertMode.ADD, mode=PETSc.ScatterMode.REVERSE)
        fem_petsc.set_bc(self.b, self._bcs_hom)
        return self.b.norm()

    def _internal_norm(self) -> float:
        f = fem_petsc.assemble_vector(self._internal_form)
        f.ghostUpdate(addv=PETSc.InsertMode.ADD, mode=PETSc.ScatterMode.REVERSE)
        norm = f.norm()
        f.destroy()
        return norm

    # --- one load step --------------------------------------------------------------------
    def _newton(self, d_lambda: float, d_gravity: float,
                guess: np.ndarray | None) -> tuple[bool, list[float]]:
        """Solve one increment; on failure the trial state is discarded by the caller.

        ``guess``: first iterate of the displacement increment (None: zero); the prescribed
        increments are set on the Dirichlet dofs.
        """
        opts = self.options
        self._lam.value = self.load_factor + d_lambda
        self._grav.value = self.gravity_factor + d_gravity
        self.bc.scale(d_lambda)
        bcs = self.bc.bcs + self._inactive_bcs
        if guess is not None:
            self.Du.x.array[:] = guess
        else:
            self.Du.x.array[:] = 0.0
        fem.set_bc(self.Du.x.array, bcs)
        self.Du.x.scatter_forward()
        self.bc.scale(0.0)
        self._bcs_hom = bcs
        residuals: list[float] = []
        self._update_stress()
        self._note_flags(first=True)
        norm = self._residual()
        scale = self._solve_scale = self._scale()
        for _ in range(opts.max_iterations):
            residuals.append(norm)
            if not np.isfinite(norm):
                return False, residuals
            if norm <= opts.tolerance * scale:
                return True, residuals
            if norm > opts.divergence * residuals[0]:
                return False, residuals
            self.A.zeroEntries()
            # the (Mat, form) overload is registered by singledispatch: mypy sees only the
            # base signature (form, bcs, ...)
            fem_petsc.assemble_matrix(self.A, self._jacobian_form, bcs=bcs)  # type: ignore[misc]
            self.A.assemble()
            self.ksp.solve(self.b, self.delta.vector)
            if self.ksp.getConvergedReason() < 0:
                return False, residuals
            self.delta.x.scatter_forward()
            norm = self._line_search(self._along(self.Du.x.array.copy(), -self.delta.x.array),
                                     norm)
            self._note_flags()
            self.iterations_total += 1
        residuals.append(norm)
        return norm <= opts.tolerance * scale, residuals

    def _scale(self) -> float:
        """The residual norm's reference: max(||f_int||, |lambda| + 1, 1) (module docstring)."""
        return max(self._internal_norm(), float(np.abs(self._lam.value)) + 1.0, 1.0)

    def _note_flags(self, first: bool = False) -> None:
        """Keep the yield flags of this iterate (``first``: of a new solve), for a retry.

        Only with ``hold_flipping``: nothing else reads them (:meth:`_flipping`).
        """
        if not self.options.hold_flipping:
            return
        if first:
            self._flag_history = []
        self._flag_history.append(self._trial[3].copy())

    def _flipping(self) -> np.ndarray:
        """The points whose yield flag changed over the last ``FLIP_WINDOW`` iterates."""
        flags = np.array(self._flag_history[-FLIP_WINDOW:])
        return np.flatnonzero((flags != flags[-1]).any(axis=0))

    def _newton_holding(self, solve: Callable[[Any], tuple[bool, list[float]]], start: Any,
                        current: Callable[[], Any]) -> tuple[bool, list[float]]:
        """Retry of an increment whose Newton iterates cycled: a choice of the active set.

        Near a limit (and with softening or non-associated flow) a few points can flip between
        the elastic and the plastic response from one iterate to the next, and the residual
        repeats a cycle far above the tolerance. The points that flipped over the failed
        solve's last ``FLIP_WINDOW`` iterates are held on the elastic branch (stress
        sigma_n + D : d_eps, tangent D), which makes the equations smooth there, and Newton
        is solved again from the same start. At its solution the unchanged response is
        evaluated: where a held point's elastic stress lies inside its yield surface the two
        agree, and the increment is accepted only if the residual of the unchanged response
        meets the tolerance (an equilibrium of the material law itself, not an
        approximation of it). Held points at which the unchanged response yields are
        released and the increment solved again from there (with none left held, by plain
        Newton); when a held solve cycles on other points they are held too; at most
        ``HOLD_ROUNDS`` solves (a primal-dual active-set strategy, as Hintermueller, Ito &
        Kunisch, SIAM J. Optim. 13 (2002) 865-888, analyse for contact-like problems; this
        is a heuristic in its spirit, without its convergence theory).

        ``solve(guess)`` solves the increment from the first iterate ``guess`` with the points
        in ``self._held`` held and returns (converged, residual norms); ``start`` is the
        failed solve's first iterate, ``current()`` the converged iterate as a first one.
        Returns (converged, residual norms).
        """
        comm = self.disc.V.mesh.comm

        def count(points: np.ndarray) -> int:  # over all ranks: every branch is collective
            return int(comm.allreduce(points.size, op=MPI.SUM))

        held = self._flipping()
        residuals: list[float] = []
        guess = start
        try:
            if count(held) == 0:
                return False, residuals
            for _ in range(HOLD_ROUNDS):
                self._held = held
                ok, attempt = solve(guess)
                residuals += attempt
                if ok and count(held) == 0:  # with none held, Newton solved the law itself
                    return True, residuals
                if not ok:  # points beside the held ones cycle now: hold them too
                    more = np.union1d(held, self._flipping())
                    if not self._cycled(attempt) or count(more) == count(held):
                        return False, residuals
                    held = more
                    continue
                guess, scale = current(), self._solve_scale
                self._held = None
                self._update_stress()
                norm = self._residual()
                residuals.append(norm)
                if norm <= self.options.tolerance * scale:
                    return True, residuals
                keep = held[self._trial[3][held] == 0]  # release those that yield
                if count(keep) == count(held):  # none to release: no other choice to try
                    return False, residuals
                held = keep
            return False, residuals
        finally:
            self._held = None

    def _retry_holding(self, ok: bool, residuals: list[float],
                       solve: Callable[[Any], tuple[bool, list[float]]], start: Any,
                       current: Callable[[], Any]) -> tuple[bool, list[float]]:
        """A failed solve's retry holding its flipping points (``hold_flipping``).

        Retried when the solve cycled and no retry failed since the last converged increment
        (:meth:`_newton_holding`'s arguments); returns (converged, all residual norms). Keeps
        the bookkeeping: a retry that ran and failed blocks the next until an increment
        converges; ``held_increments`` counts the retries that converged.
        """
        if not (self.options.hold_flipping and not ok and not self._hold_failed
                and self._cycled(residuals)):
            return ok, residuals
        ok, extra = self._newton_holding(solve, start, current)
        if extra:  # a held solve ran
            self._hold_failed = not ok
            self.held_increments += int(ok)
        return ok, residuals + extra

    def _cycled(self, residuals: list[float]) -> bool:
        """Whether a failed solve ran all its iterations with finite residuals (not diverged)."""
        return (len(residuals) == self.options.max_iterations + 1
                and bool(np.all(np.isfinite(residuals)))
                and residuals[-1] <= self.options.divergence * max(residuals[:2]))

    def _small_strain(self) -> bool:
        """Whether the increment moved no node more than ``max_displacement`` (collective).

        Beyond it the increment is a mechanism of arbitrary amplitude, not a small-strain state.
        """
        moved = largest_nodal_norm(self.Du.x.array, self.disc.V.mesh.comm)
        return moved <= self.max_displacement

    def _along(self, base: np.ndarray, direction: np.ndarray) -> Callable[[float], None]:
        """The move Du = base + step x direction of a line search."""
        def move(step: float) -> None:
            self.Du.x.array[:] = base + step * direction
        return move

    def _line_search(self, move: Callable[[float], None], norm: float) -> float:
        """The safeguarded Newton step (module docstring); the residual norm of the step taken.

        ``move(step)`` for step = 1, 1/2, ... until the residual norm is at most
        ``residual_growth`` x ``norm`` or after ``line_search`` halvings.
        """
        opts = self.options
        step = 1.0
        for halvings in range(opts.line_search + 1):
            move(step)
            self._update_stress()
            trial = self._residual()
            if trial <= opts.residual_growth * norm or halvings == opts.line_search:
                break
            step *= 0.5
        return trial

    def _commit(self, kind: str | None, size: float, iterations: int,
                residuals: list[float], d_lambda: float, d_gravity: float) -> StepRecord:
        stress, _, pstrain, yielded = self._trial
        self.stress[:] = stress
        self.plastic_strain[:] = pstrain
        self.yielded[:] = yielded
        self.u.x.array[:] += self.Du.x.array
        self.u.x.scatter_forward()
        self._last_increment = (None if kind is None or size == 0.0
                                else (self.Du.x.array.copy(), kind, size))
        self.load_factor += d_lambda
        self.gravity_factor += d_gravity
        self._hold_failed = False
        record = StepRecord(self.load_factor, iterations, residuals,
                            {k: f() for k, f in self.monitors.items()}, self.strength_factor)
        self.history.append(record)
        for observe in self.observers:
            observe(self, record)
        return record

    def step(self, d_lambda: float = 0.0, d_gravity: float = 0.0, *,
             strength_factor: float | None = None) -> StepRecord | None:
        """Apply one increment of load factor and/or gravity, or move the strength factor.

        Starts from the converged state; ``strength_factor`` is the new strength factor.
        Returns None (state unchanged) if no equilibrium was found.

        The first iterate is the previous converged increment of the same kind (load or
        strength) scaled to this one: near a collapse the mechanism repeats itself.
        """
        start = time.perf_counter()
        old_factor = self.strength_factor
        kind, size = None, 0.0
        if strength_factor is not None and strength_factor != old_factor:
            if d_lambda != 0.0 or d_gravity != 0.0:
                raise ValueError("step: change the strength or the loads, not both at once")
            self.set_strength_factor(strength_factor)
            kind, size = "strength", strength_factor - old_factor
        elif d_gravity == 0.0 and d_lambda != 0.0:
            kind, size = "load", d_lambda
        prev = self._last_increment
        guess = (prev[0] * (size / prev[2]) if prev is not None and kind == prev[1]
                 else None)
        iterations = self.iterations_total
        ok, residuals = self._newton(d_lambda, d_gravity, guess)
        ok, residuals = self._retry_holding(
            ok, residuals, lambda first: self._newton(d_lambda, d_gravity, first), guess,
            self.Du.x.array.copy)
        ok = ok and self._small_strain()
        self.wall_time += time.perf_counter() - start
        if not ok:
            self._lam.value = self.load_factor
            self._grav.value = self.gravity_factor
            if self.strength_factor != old_factor:
                self.set_strength_factor(old_factor)
            self.sspace.assign(self.stress_q, self.stress)
            return None
        return self._commit(kind, size, self.iterations_total - iterations, residuals, d_lambda,
                            d_gravity)

    def ramp(self, target: float, steps: int, *, gravity: bool = False,
             stop: Callable[[PlasticSolver], bool] | None = None,
             min_increment: float | None = None) -> Analysis:
        """Raise the load factor (or the gravity factor) to ``target`` in increments.

        The increments are (target - current) / ``steps`` (:class:`IncrementControl`: halved
        when Newton fails, down to ``min_increment`` of it, regrown by ``growth`` after each
        converged one).

        Returns an :class:`Analysis`: the target reached (``completed``) or the last
        converged factor; ``stop(solver)`` True after a converged increment ends the ramp
        there (completed). ``min_increment`` replaces the option of the same name.
        """
        if steps < 1:
            raise ValueError(f"ramp: steps = {steps} must be >= 1")
        current = self.gravity_factor if gravity else self.load_factor
        stage = "self-weight" if gravity else "load"
        size = (target - current) / steps
        if self.options.max_increment is not None:
            size = float(np.sign(size)) * min(abs(size), self.options.max_increment)
        control = IncrementControl.of(size, self.options)
        if min_increment is not None:
            control.smallest = abs(size) * min_increment
        start, bar = current, progress(stage, abs(target - current))
        while abs(target - current) > 1e-12 * max(1.0, abs(target)):
            inc = control.size if abs(control.size) < abs(target - current) else target - current
            record = self.step(0.0, inc) if gravity else self.step(inc, 0.0)
            if record is None:
                if not control.cut():
                    log.info("%s: no equilibrium beyond factor %.6g", stage, current)
                    bar.close()
                    return Analysis(False, current, control.cuts, stage, target)
                continue
            control.grow()
            current = self.gravity_factor if gravity else self.load_factor
            bar.update(abs(current - start), factor=current)
            if stop is not None and stop(self):
                break
        bar.close()
        return Analysis(True, current, control.cuts, stage, target)

    def follow(self, control: DisplacementControl | DissipationControl, target: float,
               steps: int, *, stop: Callable[[PlasticSolver], bool] | None = None,
               min_increment: float | None = None) -> Analysis:
        """Drive the surface loads by a displacement or by the energy dissipated.

        Moves ``control``'s measure to ``target`` ([m], or [kJ/m] dissipated since this
        control was first followed) in ``steps`` increments, the load factor an unknown of
        each increment (:mod:`hybrid.continuum.control`). Past a peak the load factor falls:
        a softening branch is followed as long as the measure keeps growing (the dissipation
        grows through a snap-back too). Returns an :class:`Analysis` whose factor is the
        measure reached.
        """
        from hybrid.continuum.control import ControlledPath

        path = self._paths.get(control)
        if path is None:
            path = self._paths[control] = ControlledPath(self, control)
        return path.follow(target, steps, stop=stop, min_increment=min_increment)

    # --- gravity, stages, strength ----------------------------------------------------------
    def apply_gravity(self, steps: int = 1, *, min_increment: float | None = None) -> Analysis:
        """Switch the self-weight on in ``steps`` increments (elasto-plastic).

        The result must be checked (``.require()`` or ``.completed``): an incomplete gravity
        stage leaves a half-loaded state. ``min_increment``: as :meth:`ramp`.
        """
        return self.ramp(1.0, steps, gravity=True, min_increment=min_increment)

    def set_initial_stress(self, stress: np.ndarray) -> None:
        """Start from a given stress state (n_cells, nqp, 4) [kPa], e.g. a K0 state."""
        self.stress[:] = np.asarray(stress, float).reshape(self.npoints, 4)
        self.sspace.assign(self.stress_q, self.stress)

    def geostatic_stress(self, surface_level: float, k0: float | None = None) -> np.ndarray:
        """K0 stress state under horizontal ground at y = ``surface_level`` [m].

        sigma_v = -gamma (surface_level - y), sigma_h = K0 sigma_v (K0 per material's
        nu / (1 - nu) when None). Returns (n_cells, nqp, 4); use :meth:`set_initial_stress`.
        """
        xq = evaluate_at_points(self.disc, ufl.SpatialCoordinate(self.u.function_space.mesh))
        gamma = self.model.cell_property("unit_weight")[:, None]
        k = (self.model.cell_property("k0")[:, None] if k0 is None else k0)
        sv = -gamma * (surface_level - xq[..., 1])
        return np.stack([k * sv, sv, k * sv, 0.0 * sv], axis=-1)

    def set_active(self, groups: Sequence[str]) -> None:
        """Only the named cell groups carry stiffness, weight and stress (staged construction).

        Dofs touching only inactive cells are held fixed. Newly activated cells start with zero
        stress; their displacement increments start from the activation.
        """
        md = self.model.mesh
        for g in groups:
            md.cell_tag(g)  # raises a clear error for an unknown group
        active = np.zeros(self.sspace.num_cells, dtype=bool)
        for g in groups:
            active[md.cells(g)] = True
        newly = active & ~self.active
        pts = np.repeat(newly, self.disc.num_points)
        self.stress[pts] = 0.0
        self.plastic_strain[pts] = 0.0
        self.active = active
        n = self.sspace.num_cells
        dofs0 = self._active_fn.function_space.dofmap.list.array[:n]
        self._active_fn.x.array[dofs0] = active.astype(float)
        self._active_fn.x.scatter_forward()
        # dofs of active cells, marked through a function so that ghosts agree (notes pitfall 4)
        V = self.disc.V
        marker = fem.Function(V)
        dofmap = V.dofmap.list.array.reshape(-1, V.dofmap.dof_layout.num_dofs)
        blocks = dofmap[:n][active].ravel()
        marker.x.array.reshape(-1, 2)[blocks] = 1.0
        marker.x.scatter_reverse(la.ScatterMode.add)
        marker.x.scatter_forward()
        inactive_dofs = np.flatnonzero(marker.x.array.reshape(-1, 2)[:, 0] == 0).astype(np.int32)
        zero = fem.Constant(V.mesh, PETSc.ScalarType((0.0, 0.0)))
        self._inactive_bcs = ([fem.dirichletbc(zero, inactive_dofs, V)]
                              if V.mesh.comm.allreduce(len(inactive_dofs)) else [])
        self.sspace.assign(self.stress_q, self.stress)

    def activate(self, groups: Sequence[str], steps: int = 1) -> Analysis:
        """Place the named cell groups and bring the structure to equilibrium under their weight.

        The groups join the active ones; their weight is ramped in ``steps`` increments
        (staged construction, thesis 6.3.1).

        A failing increment is cut in half, down to ``min_increment`` x the first (as in
        :meth:`ramp`). Returns whether the full weight was reached; if not, the new cells keep
        the last fraction of their weight with equilibrium (``Analysis.factor``): the
        structure collapses while this lift is placed, if the displacement ran away
        (``Analysis.path``: the largest displacement since the lift's placement after every
        converged increment; :meth:`Analysis.runaway`).
        """
        if self.gravity_factor == 0.0:  # placed material comes with its weight
            self.gravity_factor = 1.0
            self._grav.value = 1.0
        before = self.active.copy()
        current = [g for g in self.model.mesh.cell_groups
                   if np.any(before[self.model.mesh.cells(g)])]
        self.set_active(sorted(set(current) | set(groups)))
        newly = self.active & ~before
        n = self.sspace.num_cells
        dofs0 = self._active_fn.function_space.dofmap.list.array[:n]

        def weigh(fraction: float) -> None:
            weight = self.active.astype(float)
            weight[newly] = fraction
            self._active_fn.x.array[dofs0] = weight
            self._active_fn.x.scatter_forward()

        stage = "lift " + ", ".join(f"'{g}'" for g in groups)
        if steps < 1:
            raise ValueError(f"activate: steps = {steps} must be >= 1")
        control = IncrementControl.of(1.0 / steps, self.options)
        placed, bar = 0.0, progress(stage, 1.0)
        u0, path = self.u.x.array.copy(), [(0.0, 0.0)]
        while placed < 1.0 - 1e-12:
            trial = min(placed + control.size, 1.0)
            weigh(trial)
            if self.step() is None:
                if not control.cut():
                    weigh(placed)
                    log.info("%s: no equilibrium beyond %.4g of its weight", stage, placed)
                    bar.close()
                    return Analysis(False, placed, control.cuts, stage, path=tuple(path))
                continue
            control.grow()
            placed = trial
            path.append((placed, largest_nodal_norm(self.u.x.array - u0, self.disc.V.mesh.comm)))
            bar.update(placed)
        bar.close()
        return Analysis(True, 1.0, control.cuts, stage, path=tuple(path))

    def set_strength_factor(self, factor: float) -> None:
        """Divide c and tan(phi), tan(psi) of every plastic material by ``factor``.

        The stress state is kept: call :meth:`step` to find the equilibrium at it.
        """
        if not (math.isfinite(factor) and factor > 0):
            raise ValueError(f"strength factor {factor!r} must be a finite number > 0")
        self.strength_factor = float(factor)
        self.table = material_table(self.materials, factor)

    def reset_displacement(self) -> None:
        """Zero the displacement field (stresses kept): e.g. after the gravity stage."""
        self.u.x.array[:] = 0.0

    # --- checkpoints of the state (for strength reduction, bisection) -------------------
    def snapshot(self) -> tuple[np.ndarray, ...]:
        """Copies of the converged state (stresses, plastic state, displacement, factors)."""
        return (self.stress.copy(), self.plastic_strain.copy(), self.yielded.copy(),
                self.u.x.array.copy(),
                np.array([self.load_factor, self.gravity_factor, self.strength_factor]))

    def restore(self, snap: tuple[np.ndarray, ...]) -> None:
        """Go back to a :meth:`snapshot` (the strength factor included)."""
        self.stress[:], self.plastic_strain[:], self.yielded[:] = snap[0], snap[1], snap[2]
        self.u.x.array[:] = snap[3]
        self.u.x.scatter_forward()
        self.load_factor, self.gravity_factor = float(snap[4][0]), float(snap[4][1])
        self._lam.value, self._grav.value = self.load_factor, self.gravity_factor
        if float(snap[4][2]) != self.strength_factor:
            self.set_strength_factor(float(snap[4][2]))
        self._last_increment = None
        self._hold_failed = False
        self.sspace.assign(self.stress_q, self.stress)

    # --- outputs ---------------------------------------------------------------------------
    def reaction(self, boundary: str, component: int) -> float:
        """Resultant internal force on a boundary's dofs along x (0) or y (1) [kN/m].

        Equals the support reaction (with the opposite sign) where the boundary is held, e.g.
        the force a rigid footing or a wall transmits to the soil.
        """
        V = self.disc.V
        dofs = fem.locate_dofs_topological(V.sub(component), 1,
                                           self.model.mesh.facets(boundary))
        self.sspace.assign(self.stress_q, self.stress)
        f = fem_petsc.assemble_vector(self._internal_form)
        f.ghostUpdate(addv=PETSc.InsertMode.ADD, mode=PETSc.ScatterMode.REVERSE)
        owned = V.dofmap.index_map.size_local * V.dofmap.index_map_bs
        local = f.array_r
        total = float(np.sum(local[dofs[dofs < owned]]))
        f.destroy()
        return V.mesh.comm.allreduce(total, op=MPI.SUM)

    def state(self) -> ContinuumState:
        """The converged state (copies) for outputs and the handover."""
        n, nqp = self.sspace.num_cells, self.disc.num_points
        u = self.u.copy()
        info = {"solver": "mohr-coulomb newton", "degree": self.disc.degree,
                "cells": self.model.mesh.mesh.topology.index_map(2).size_global,
                "dofs": self.disc.V.dofmap.index_map.size_global * 2,
                "steps": len(self.history), "newton_iterations": self.iterations_total,
                "held_increments": self.held_increments,
                "wall_time_s": self.wall_time, "load_factor": self.load_factor,
                "gravity_factor": self.gravity_factor, "strength_factor": self.strength_factor}
        return ContinuumState(self.model, self.disc, u, self.stress.reshape(n, nqp, 4).copy(),
                              self.plastic_strain.reshape(n, nqp).copy(),
                              self.yielded.reshape(n, nqp).copy(), info, self.active.copy(),
                              self.strength_factor)
