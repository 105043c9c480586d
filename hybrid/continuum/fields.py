"""UFL building blocks of the plane-strain continuum: spaces, strain, stress, BCs, loads.

Voigt order (xx, yy, zz, xy) with engineering shear strain; tension positive; kPa, m.
The displacement space is Lagrange of ``degree`` (1 or 2) on the first-order gmsh mesh, so
cell vertices stay the geometry the discrete engine takes over.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import basix
import numpy as np
import ufl
from dolfinx import fem
from petsc4py import PETSc

from hybrid.model import Displacement, Fixed, Model, ModelError, Pressure, Roller, Traction

__all__ = ["Discretisation", "strain", "elastic_stress", "MaterialFields", "boundary_conditions",
           "free_rigid_motions", "surface_load", "body_force"]


def quadrature_degree(cell_type: str, degree: int) -> int:
    """Quadrature degree exact for the stiffness of affine cells of the given order.

    Triangles: 1 point (P1), 3 points (P2). Quadrilaterals: 2x2 Gauss (Q1), 3x3 Gauss (Q2).
    """
    if cell_type == "triangle":
        return 2 * (degree - 1) if degree > 1 else 1
    return 2 * degree


@dataclass
class Discretisation:
    """Displacement space, quadrature rule and integration measures of one mesh.

    Attributes:
        degree: Lagrange order of the displacement (1 or 2).
        V: vector displacement space.
        quadrature_degree: degree of the quadrature rule (FFCx "default" scheme).
        points, weights: the rule on the reference cell (nqp, 2), (nqp,).
        dx, ds: integration measures (ds carries the facet tags).
    """

    degree: int
    V: Any
    quadrature_degree: int
    points: np.ndarray
    weights: np.ndarray
    dx: Any
    ds: Any

    @classmethod
    def create(cls, model: Model, degree: int = 2) -> Discretisation:
        """Build the CG ``degree`` (1 or 2) displacement space and its quadrature on the mesh."""
        if degree not in (1, 2):
            raise ValueError(f"displacement degree must be 1 or 2, not {degree}")
        mesh = model.mesh
        V = fem.VectorFunctionSpace(mesh.mesh, ("CG", degree))
        qdeg = quadrature_degree(mesh.cell_type, degree)
        basix_cell = (basix.CellType.quadrilateral if mesh.is_quad else basix.CellType.triangle)
        points, weights = basix.make_quadrature(basix_cell, qdeg)
        dx = ufl.Measure("dx", domain=mesh.mesh,
                         metadata={"quadrature_degree": qdeg, "quadrature_scheme": "default"})
        ds = ufl.Measure("ds", domain=mesh.mesh, subdomain_data=mesh.facet_tags)
        return cls(degree, V, qdeg, np.asarray(points), np.asarray(weights), dx, ds)

    @property
    def num_points(self) -> int:
        """Quadrature points per cell."""
        return len(self.weights)


def strain(u: Any) -> Any:
    """Plane-strain small strain in Voigt form (exx, eyy, ezz = 0, gamma_xy)."""
    return ufl.as_vector([u[0].dx(0), u[1].dx(1), 0.0, u[0].dx(1) + u[1].dx(0)])


def elastic_stress(eps: Any, lam: Any, mu: Any) -> Any:
    """Isotropic Hooke's law on Voigt vectors: sigma = lam tr(eps) m + 2 mu eps.

    The shear component is mu gamma_xy (engineering shear strain).
    """
    tr = eps[0] + eps[1] + eps[2]
    return ufl.as_vector([lam * tr + 2 * mu * eps[0], lam * tr + 2 * mu * eps[1],
                          lam * tr + 2 * mu * eps[2], mu * eps[3]])


@dataclass
class MaterialFields:
    """Per-cell (DG0) material constants as dolfinx functions: lambda, mu [kPa], gamma [kN/m3]."""

    lam: Any
    mu: Any
    unit_weight: Any
    material_id: Any

    @classmethod
    def create(cls, model: Model) -> MaterialFields:
        """Fill the DG0 fields from the model's per-cell material properties."""
        W = fem.FunctionSpace(model.mesh.mesh, ("DG", 0))
        out = []
        for attribute in ("lame_lambda", "shear_modulus", "unit_weight"):
            f = fem.Function(W, name=attribute)
            _set_cellwise(f, model.cell_property(attribute))
            out.append(f)
        ids = fem.Function(W, name="material")
        _set_cellwise(ids, model.material_ids().astype(float))
        lam, mu, unit_weight = out
        return cls(lam, mu, unit_weight, ids)


def _set_cellwise(f: Any, owned_values: np.ndarray) -> None:
    """Write values of the owned cells into a DG0 function and update the ghosts."""
    n = len(owned_values)
    dofs = f.function_space.dofmap.list.array.reshape(-1, 1)[:n, 0]
    f.x.array[dofs] = owned_values
    f.x.scatter_forward()


def body_force(fields: MaterialFields, gravity: float | Any) -> Any:
    """Self-weight body force (0, -gamma) [kN/m3] times ``gravity`` (0..1, switch-on factor)."""
    return ufl.as_vector([0.0, -gravity * fields.unit_weight])


def surface_load(model: Model, v: Any, ds: Any, scale: float | Any = 1.0) -> Any:
    """Virtual work of the model's pressures and tractions [kN/m] (0 if there are none)."""
    n = ufl.FacetNormal(model.mesh.mesh)
    work = 0
    for load in model.loads:
        tag = model.mesh.facet_tag(load.boundary)
        if isinstance(load, Pressure):
            work += -scale * load.value * ufl.dot(n, v) * ds(tag)
        elif isinstance(load, Traction):
            work += scale * (load.tx * v[0] + load.ty * v[1]) * ds(tag)
    return work


@dataclass
class BoundaryConditions:
    """Dirichlet conditions and the constants of prescribed displacements (for stepping)."""

    bcs: list[Any]
    prescribed: list[tuple[Any, float]]  # (fem.Constant, full value [m])

    def scale(self, factor: float) -> None:
        """Set every prescribed displacement to ``factor`` times its full value."""
        for const, value in self.prescribed:
            const.value = factor * value


def free_rigid_motions(held: list[tuple[np.ndarray, int]], comm: Any) -> list[str]:
    """The rigid-body motions that ``held`` displacement components leave free, in words.

    ``held``: (points (n, 2) [m], component 0 or 1) per support component (collective: the
    points of every rank count). A motion (ux, uy) = (a - c (y - y0), b + c (x - x0)) is free
    when no held component sees it: the null space of the normal matrix of the constraints
    (coordinates scaled by the supports' extent). Disconnected bodies are not seen here (the
    solve then refuses the singular system).
    """
    from mpi4py import MPI

    pts = [p for p, _ in held if p.size]
    local = np.concatenate(pts) if pts else np.zeros((0, 2))
    lo = np.array([comm.allreduce(float(v), op=MPI.MIN)
                   for v in (local.min(axis=0) if local.size else np.full(2, np.inf))])
    hi = np.array([comm.allreduce(float(v), op=MPI.MAX)
                   for v in (local.max(axis=0) if local.size else np.full(2, -np.inf))])
    centre = 0.5 * (lo + hi) if np.isfinite(lo).all() else np.zeros(2)
    scale = max(float(np.max(hi - lo)), 1e-300) if np.isfinite(lo).all() else 1.0
    gram = np.zeros((3, 3))
    for points, comp in held:
        p = (points - centre) / scale
        rows = np.zeros((p.shape[0], 3))
        rows[:, comp] = 1.0
        rows[:, 2] = -p[:, 1] if comp == 0 else p[:, 0]
        gram += rows.T @ rows
    gram = comm.allreduce(gram, op=MPI.SUM)
    values, vectors = np.linalg.eigh(gram)
    free = vectors[:, values <= 1e-10 * max(float(values[-1]), 1.0)]
    if free.shape[1] == 3:
        return ["translation in x", "translation in y", "rotation"]
    words = []
    for a, b, c in free.T:
        if abs(c) < 1e-6:
            words.append("translation in x" if abs(b) < 1e-6 else "translation in y"
                         if abs(a) < 1e-6 else f"translation along ({a:.3g}, {b:.3g})")
        else:
            x0, y0 = centre + scale * np.array([-b / c, a / c])
            words.append(f"rotation about ({x0:.4g}, {y0:.4g})")
    return words


def boundary_conditions(model: Model, V: Any) -> BoundaryConditions:
    """Dirichlet BCs of the model's supports on the displacement space ``V``.

    A model whose supports leave a rigid-body motion free is refused (:class:`ModelError`).
    """
    mesh = model.mesh
    bcs: list[Any] = []
    prescribed: list[tuple[Any, float]] = []
    held: list[tuple[np.ndarray, int]] = []
    coordinates = V.tabulate_dof_coordinates()[:, :2]
    for support in model.supports:
        facets = mesh.facets(support.boundary)
        if isinstance(support, Fixed):
            components = {0: 0.0, 1: 0.0}
        elif isinstance(support, Roller):
            components = {0 if support.direction == "x" else 1: 0.0}
        elif isinstance(support, Displacement):
            components = {i: val for i, val in enumerate((support.ux, support.uy))
                          if val is not None}
        else:  # pragma: no cover - the Model type union is closed
            raise TypeError(f"unknown support {support!r}")
        for comp, value in components.items():
            dofs = fem.locate_dofs_topological(V.sub(comp), 1, facets)
            held.append((coordinates[np.asarray(dofs) // 2], comp))
            const = fem.Constant(mesh.mesh, PETSc.ScalarType(value))
            bcs.append(fem.dirichletbc(const, dofs, V.sub(comp)))
            if value != 0.0:
                prescribed.append((const, float(value)))
    free = free_rigid_motions(held, mesh.comm)
    if free:
        raise ModelError(f"the supports leave the body free to move ({', '.join(free)}): the "
                         "stiffness is singular; hold enough boundaries (Fixed, Roller, "
                         "Displacement) to stop every rigid-body motion")
    return BoundaryConditions(bcs, prescribed)
