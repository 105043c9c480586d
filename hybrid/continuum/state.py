"""The continuum state: displacements and quadrature-point stress and plastic state."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import ufl
from dolfinx import fem
from mpi4py import MPI

from hybrid.continuum.fields import Discretisation
from hybrid.continuum.probe import evaluate
from hybrid.continuum.quadrature import QuadratureSpace, evaluate_at_points, project
from hybrid.model import Model

__all__ = ["ContinuumState"]


@dataclass
class ContinuumState:
    """A converged continuum state (what the handover and the outputs read).

    Attributes:
        model: the problem.
        disc: displacement space and quadrature rule.
        u: displacement [m] (dolfinx Function).
        stress: Cauchy stress at quadrature points (n_owned_cells, nqp, 4) [kPa],
            (xx, yy, zz, xy), tension positive.
        plastic_strain: accumulated equivalent plastic strain (n_owned_cells, nqp) [-].
        yielded: 1 where the point is on the yield surface at the last step (n_owned_cells, nqp).
        velocity: nodal velocities for a dynamic start (zero after a static solve) [m/s].
        info: solver figures (iterations, load factors, timings).
        active: (n_owned_cells,) True for cells in place (staged construction); None: all.
        strength_factor: the strengths in force are the materials' divided by this (c and
            tan(phi), as in a strength-reduction analysis; 1: the materials as given).
    """

    model: Model
    disc: Discretisation
    u: Any
    stress: np.ndarray
    plastic_strain: np.ndarray
    yielded: np.ndarray
    info: dict[str, Any] = field(default_factory=dict)
    active: np.ndarray | None = None
    strength_factor: float = 1.0

    def materials_at(self, strength_factor: float | None = None) -> list[Any]:
        """The model's materials (in ``material_names`` order) with reduced strengths.

        Every strength is divided by ``strength_factor`` (default: the factor in force in
        this state).
        """
        factor = self.strength_factor if strength_factor is None else strength_factor
        return [m.weakened(factor) if m.is_plastic and factor != 1.0 else m
                for m in (self.model.materials[k] for k in self.model.material_names)]

    @property
    def mesh(self) -> Any:
        """The dolfinx mesh."""
        return self.model.mesh.mesh

    @property
    def comm(self) -> Any:
        """The mesh's MPI communicator."""
        return self.model.mesh.comm

    @property
    def velocity(self) -> np.ndarray:
        """Nodal velocity dof values: zero, the continuum analysis is quasi-static."""
        return np.zeros_like(self.u.x.array)

    def cell_stress(self) -> np.ndarray:
        """Area-weighted mean stress of every owned cell (n_owned_cells, 4) [kPa]."""
        return self.cell_mean(self.stress)

    def cell_plastic_strain(self) -> np.ndarray:
        """Area-weighted mean plastic strain of every owned cell (n_owned_cells,)."""
        return self.cell_mean(self.plastic_strain[..., None])[:, 0]

    def cell_displacement(self, values: np.ndarray | None = None) -> np.ndarray:
        """Area-weighted mean displacement of every owned cell (n_owned_cells, 2) [m].

        ``values``: another displacement-like field as dof values of ``u``'s space (e.g. an
        increment); default the displacement itself.
        """
        field = self.u
        if values is not None:
            field = self.u.copy()
            field.x.array[:] = values
        return self.cell_mean(evaluate_at_points(self.disc, field))

    def yielded_cells(self, threshold: float = 0.0) -> np.ndarray:
        """Owned cells with a yielded point or mean plastic strain above ``threshold``."""
        return np.flatnonzero(np.any(self.yielded > 0, axis=1)
                              | (self.cell_plastic_strain() > threshold))

    def cell_mean(self, values: np.ndarray) -> np.ndarray:
        """Area-weighted cell means (n_owned_cells, k) of quadrature-point values.

        ``values``: (n_owned_cells, nqp, k).
        """
        w = self.point_areas()
        return np.einsum("cq,cqk->ck", w, values) / w.sum(axis=1)[:, None]

    def point_areas(self) -> np.ndarray:
        """The area each quadrature point of every owned cell carries [m2].

        (n_owned_cells, nqp): the rule's weight times |det J| of the undeformed cell at the
        point (the continuum integrates on the undeformed mesh).
        """
        jac = evaluate_at_points(self.disc, abs(ufl.JacobianDeterminant(self.mesh)))[..., 0]
        return jac * self.disc.weights[None, :]

    def extreme_displacement(self, component: int, *, largest: bool = False,
                             cells: np.ndarray | None = None) -> float:
        """Smallest (or ``largest``) cell-mean displacement component (0: x, 1: y) [m].

        Over ``cells`` (owned cell indices; None: all), all MPI ranks (collective).
        """
        u = self.cell_displacement()[:, component]
        if cells is not None:
            u = u[cells]
        if largest:
            return self.comm.allreduce(float(np.max(u, initial=-np.inf)), op=MPI.MAX)
        return self.comm.allreduce(float(np.min(u, initial=np.inf)), op=MPI.MIN)

    def yielded_fraction(self, cells: np.ndarray) -> float:
        """Fraction of ``cells`` (owned cell indices) among :meth:`yielded_cells`.

        Over all MPI ranks (collective); 0 when there are none.
        """
        hit = int(np.isin(self.yielded_cells(), cells).sum())
        return self.comm.allreduce(hit) / max(self.comm.allreduce(len(cells)), 1)

    def yielded_fractions(self, groups: Mapping[str, np.ndarray]) -> dict[str, float]:
        """:meth:`yielded_fraction` of each named set of cells, keyed "<name>_yielded_fraction".

        ``groups``: name -> owned cell indices, e.g. ``{name: mesh.cells(name)}``. Collective.
        """
        return {f"{name}_yielded_fraction": self.yielded_fraction(cells)
                for name, cells in groups.items()}

    def stress_function(self) -> Any:
        """Stress projected on discontinuous Lagrange of degree - 1 (DG0 for degree 1) [kPa]."""
        space = QuadratureSpace(self.disc, (4,))
        q = space.function("stress_q")
        space.assign(q, self.stress)
        target = fem.VectorFunctionSpace(self.mesh, ("DG", self.disc.degree - 1), dim=4)
        out = project(self.disc, q, target)
        out.name = "stress"
        return out

    def displacement_at(self, points: np.ndarray) -> np.ndarray:
        """Displacement (n, 2) [m] at points (n, 2) [m] (same on every MPI rank)."""
        return evaluate(self.u, np.atleast_2d(points))

    def stress_at(self, points: np.ndarray) -> np.ndarray:
        """Stress (n, 4) [kPa] at points (n, 2) [m] from :meth:`stress_function`."""
        return evaluate(self.stress_function(), np.atleast_2d(points))
