"""Sparse linear solves with PETSc (MUMPS LU), shared by the elastic and Newton solvers."""

from __future__ import annotations

from typing import Any

from dolfinx import fem
from dolfinx.fem import petsc as fem_petsc
from petsc4py import PETSc

__all__ = ["solve_linear", "lu_solver"]


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
    """Solve a(du, v) = L(v) with Dirichlet ``bcs`` into the function ``u``."""
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
    if reason < 0:
        raise RuntimeError(f"linear solve failed (PETSc reason {reason}): check the supports "
                           "(a rigid-body motion left free makes the stiffness singular)")
    u.x.scatter_forward()
    for obj in (ksp, A, b):
        obj.destroy()
