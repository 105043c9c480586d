"""Sparse linear solves with PETSc (MUMPS LU), shared by the elastic and Newton solvers."""

from __future__ import annotations

import math
from typing import Any

from dolfinx import fem
from dolfinx.fem import petsc as fem_petsc
from petsc4py import PETSc

from hybrid.model import ModelError

__all__ = ["solve_linear", "lu_solver", "SINGULAR_RESIDUAL"]

#: a direct solve whose residual norm exceeds this times the load vector's had a singular
#: (or numerically singular) stiffness
SINGULAR_RESIDUAL = 1e-6


def lu_solver(comm: Any, A: Any) -> Any:
    """A KSP doing one direct LU solve with MUMPS."""
    ksp = PETSc.KSP().create(comm)
    ksp.setOperators(A)
    ksp.setType("preonly")
    pc = ksp.getPC()
    pc.setType("lu")
    pc.setFactorSolverType("mumps")
    return ksp


def solve_linear(a: Any, L: Any, bcs: list[Any], u: Any) -> None:
    """Solve a(du, v) = L(v) with Dirichlet ``bcs`` into the function ``u``.

    Raises :class:`~hybrid.model.ModelError` when the stiffness is singular: MUMPS may report
    success and return huge displacements, so the residual ``|A u - b|`` is checked against
    ``SINGULAR_RESIDUAL |b|`` (and for being finite).
    """
    a_form, L_form = fem.form(a), fem.form(L)
    A = fem_petsc.assemble_matrix(a_form, bcs=bcs)
    A.assemble()
    b = fem_petsc.assemble_vector(L_form)
    fem_petsc.apply_lifting(b, [a_form], bcs=[bcs])
    b.ghostUpdate(addv=PETSc.InsertMode.ADD, mode=PETSc.ScatterMode.REVERSE)
    fem_petsc.set_bc(b, bcs)
    ksp = lu_solver(u.function_space.mesh.comm, A)
    ksp.solve(b, u.vector)
    reason = ksp.getConvergedReason()
    residual = b.duplicate()
    A.mult(u.vector, residual)
    residual.axpy(-1.0, b)
    b_norm, r_norm = b.norm(), residual.norm()
    for obj in (ksp, A, b, residual):
        obj.destroy()
    if reason < 0 or not math.isfinite(r_norm) or r_norm > SINGULAR_RESIDUAL * b_norm:
        raise ModelError(
            f"the stiffness is singular (PETSc reason {reason}, relative residual "
            f"{r_norm / b_norm if b_norm else r_norm:.3g} after the direct solve): part of the "
            "model is free to move (a rigid-body motion left free by the supports, or a part "
            "of the mesh not connected to the rest); check the supports and the mesh")
    u.x.scatter_forward()
