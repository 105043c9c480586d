"""Quadrature-point data of the continuum: Voigt stress arrays <-> dolfinx functions.

State at quadrature points is kept as numpy arrays of shape (n_owned_cells, n_points, ...)
(the form the constitutive kernel and the handover use) and copied into dolfinx
"Quadrature" functions when a form needs it.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import ufl
from dolfinx import fem

from hybrid.continuum.fields import Discretisation

__all__ = ["QuadratureSpace", "evaluate_at_points", "project"]


class QuadratureSpace:
    """A vector/tensor quadrature space on the discretisation's rule, with numpy views."""

    def __init__(self, disc: Discretisation, shape: tuple[int, ...] = (4,)) -> None:
        mesh = disc.V.mesh
        cell = mesh.ufl_cell()
        if len(shape) == 1:
            element = ufl.VectorElement("Quadrature", cell, degree=disc.quadrature_degree,
                                        dim=shape[0], quad_scheme="default")
        else:
            element = ufl.TensorElement("Quadrature", cell, degree=disc.quadrature_degree,
                                        shape=shape, quad_scheme="default")
        self.space = fem.FunctionSpace(mesh, element)
        self.shape = shape
        self.num_points = disc.num_points
        self.num_cells = mesh.topology.index_map(2).size_local
        dofs = self.space.dofmap.list.array.reshape(-1, self.num_points)
        self._dofs = dofs[: self.num_cells].ravel()

    def function(self, name: str) -> Any:
        """A new, zero quadrature function of this space called ``name``."""
        return fem.Function(self.space, name=name)

    def assign(self, f: Any, values: np.ndarray) -> None:
        """Write (n_cells, n_points, *shape) values into a quadrature function (+ ghosts)."""
        size = int(np.prod(self.shape))
        f.x.array.reshape(-1, size)[self._dofs] = values.reshape(-1, size)
        f.x.scatter_forward()

    def values(self, f: Any) -> np.ndarray:
        """Owned values of a quadrature function as (n_cells, n_points, *shape)."""
        size = int(np.prod(self.shape))
        out = f.x.array.reshape(-1, size)[self._dofs]
        return out.reshape(self.num_cells, self.num_points, *self.shape).copy()


def evaluate_at_points(disc: Discretisation, expression: Any) -> np.ndarray:
    """A UFL expression at the quadrature points of every owned cell: (n_cells, nqp, ncomp)."""
    mesh = disc.V.mesh
    n = mesh.topology.index_map(2).size_local
    expr = fem.Expression(expression, disc.points)
    values = expr.eval(np.arange(n, dtype=np.int32))
    return values.reshape(n, disc.num_points, -1)


def project(disc: Discretisation, source: Any, space: Any) -> Any:
    """L2 projection of ``source`` (UFL) onto ``space`` with the discretisation's quadrature.

    For discontinuous target spaces the projection is local to each cell.
    """
    from dolfinx.fem.petsc import LinearProblem

    trial, test = ufl.TrialFunction(space), ufl.TestFunction(space)
    problem = LinearProblem(
        ufl.inner(trial, test) * disc.dx, ufl.inner(source, test) * disc.dx,
        petsc_options={"ksp_type": "preonly", "pc_type": "lu",
                       "pc_factor_mat_solver_type": "mumps"},
    )
    return problem.solve()
