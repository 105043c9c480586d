"""gmsh geometry -> dolfinx mesh with named cell and facet groups.

A gmsh model names its materials with 2-D physical groups and its boundaries with 1-D
physical groups. ``mesh_from_gmsh`` converts the current gmsh model (on rank 0) into a
distributed dolfinx mesh, checks it (one cell type, every cell in exactly one named group,
no empty group) and keeps the names next to the integer tags.
"""

from __future__ import annotations

import contextlib
import logging
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from pathlib import Path
from types import ModuleType
from typing import Any

import numpy as np
from mpi4py import MPI

from hybrid.scripts import import_script

__all__ = ["GeometryError", "MeshData", "build_mesh", "mesh_from_gmsh", "read_msh", "load_builder",
           "load_mesh_script"]

log = logging.getLogger(__name__)

# gmsh element type -> cell name (first order only: the solver raises the order itself)
_GMSH_CELLS = {2: "triangle", 3: "quadrilateral"}
_GMSH_HIGHER_ORDER = {9: "6-node triangle", 10: "9-node quadrilateral", 16: "8-node quadrilateral"}


class GeometryError(ValueError):
    """The gmsh model cannot be turned into a valid hybrid mesh."""


@dataclass
class MeshData:
    """A dolfinx mesh with its cell and facet tags and the physical-group names.

    Attributes:
        mesh: the distributed dolfinx mesh (coordinates in m).
        cell_tags: dolfinx MeshTags of the cells (values = gmsh 2-D physical tags).
        facet_tags: dolfinx MeshTags of the boundary facets (values = gmsh 1-D physical tags).
        cell_groups: 2-D physical-group name -> tag.
        facet_groups: 1-D physical-group name -> tag.
        cell_type: "triangle" or "quadrilateral".
    """

    mesh: Any
    cell_tags: Any
    facet_tags: Any
    cell_groups: dict[str, int]
    facet_groups: dict[str, int]
    cell_type: str

    @property
    def comm(self) -> MPI.Comm:
        """The mesh's MPI communicator."""
        return self.mesh.comm

    @property
    def num_owned_cells(self) -> int:
        """Number of cells owned by this rank (ghosts excluded)."""
        return self.mesh.topology.index_map(2).size_local

    def cell_tag(self, name: str) -> int:
        """Tag of the named 2-D group (material region)."""
        return _lookup(name, self.cell_groups, "cell (material) group")

    def facet_tag(self, name: str) -> int:
        """Tag of the named 1-D group (boundary)."""
        return _lookup(name, self.facet_groups, "boundary (facet) group")

    def cells(self, name: str) -> np.ndarray:
        """Owned local cell indices of the named group."""
        cells = self.cell_tags.find(self.cell_tag(name))
        return cells[cells < self.num_owned_cells]

    def facets(self, name: str) -> np.ndarray:
        """Local facet indices of the named boundary (ghosts included, as dolfinx BCs need)."""
        return self.facet_tags.find(self.facet_tag(name))

    def cell_vertices(self) -> tuple[np.ndarray, np.ndarray]:
        """(coordinates (n_vertices, 2), owned cells' geometry nodes (n_cells, 3|4)).

        Nodes are returned counter-clockwise (dolfinx stores quadrilaterals in tensor order
        0-1-3-2, and either orientation).
        """
        x = self.mesh.geometry.x[:, :2]
        dofs = self.mesh.geometry.dofmap.array.reshape(-1, 4 if self.is_quad else 3)
        dofs = dofs[: self.num_owned_cells]
        if self.is_quad:
            dofs = dofs[:, [0, 1, 3, 2]]
        # dolfinx keeps gmsh's orientation cell by cell: turn clockwise cells around
        p = x[dofs]
        area = np.sum(p[:, :, 0] * np.roll(p[:, :, 1], -1, axis=1)
                      - np.roll(p[:, :, 0], -1, axis=1) * p[:, :, 1], axis=1)
        dofs = dofs.copy()
        dofs[area < 0] = dofs[area < 0, ::-1]
        return x, dofs

    def group_area(self, name: str) -> float:
        """Area of the named cell group [m2] (straight-sided cells; summed over MPI ranks)."""
        x, cells = self.cell_vertices()
        p = x[cells[self.cells(name)]]
        area = 0.5 * float(np.sum(p[:, :, 0] * np.roll(p[:, :, 1], -1, axis=1)
                                  - np.roll(p[:, :, 0], -1, axis=1) * p[:, :, 1]))
        return float(self.comm.allreduce(area))

    def report(self) -> dict[str, Any]:
        """The mesh in numbers (collective).

        "cells" and each group's cells ("groups") over all MPI ranks, "cell_type", each
        group's area ("group_areas_m2", :meth:`group_area`).
        """
        comm = self.comm
        return {"cells": comm.allreduce(self.num_owned_cells), "cell_type": self.cell_type,
                "groups": {name: comm.allreduce(len(self.cells(name)))
                           for name in self.cell_groups},
                "group_areas_m2": {name: self.group_area(name) for name in self.cell_groups}}

    @property
    def is_quad(self) -> bool:
        """True for a quadrilateral mesh, False for triangles."""
        return self.cell_type == "quadrilateral"


def _lookup(name: str, groups: dict[str, int], what: str) -> int:
    if name not in groups:
        known = ", ".join(sorted(groups)) or "none"
        raise GeometryError(
            f"unknown {what} '{name}'; the mesh defines: {known}. "
            "Check the physical-group names in the gmsh script."
        )
    return groups[name]


def _check_gmsh_model(gmsh: Any) -> dict[str, Any]:
    """Validate the current gmsh model (rank 0) and collect group names; raise GeometryError."""
    model = gmsh.model
    types = list(model.mesh.getElementTypes(2))
    if not types:
        raise GeometryError("the gmsh model has no 2-D elements: call gmsh.model.mesh.generate(2)")
    if len(types) > 1:
        names = [_GMSH_CELLS.get(t, _GMSH_HIGHER_ORDER.get(t, f"type {t}")) for t in types]
        raise GeometryError(
            f"the mesh mixes cell types ({', '.join(names)}); use all triangles, or all "
            "quadrilaterals (Mesh.RecombineAll = 1 with Mesh.Algorithm = 6 and "
            "Mesh.RecombinationAlgorithm = 1)"
        )
    if types[0] not in _GMSH_CELLS:
        name = _GMSH_HIGHER_ORDER.get(types[0], f"gmsh element type {types[0]}")
        raise GeometryError(
            f"{name} cells are not supported: mesh with first-order cells; the continuum "
            "solver raises the displacement order itself (degree=2)"
        )
    cell_type = _GMSH_CELLS[types[0]]

    all_cells: list[np.ndarray] = []
    for _, entity in model.getEntities(2):
        _, tags, _ = model.mesh.getElements(2, entity)
        all_cells.extend(np.asarray(t, dtype=np.int64) for t in tags)
    all_cells_arr = np.concatenate(all_cells) if all_cells else np.empty(0, np.int64)

    groups: dict[int, dict[str, int]] = {1: {}, 2: {}}
    covered: list[np.ndarray] = []
    for dim, tag in model.getPhysicalGroups():
        if dim not in (1, 2):
            continue
        name = model.getPhysicalName(dim, tag) or str(tag)
        if name in groups[dim]:
            raise GeometryError(f"two {dim}-D physical groups are both named '{name}'")
        groups[dim][name] = int(tag)
        count = 0
        for entity in model.getEntitiesForPhysicalGroup(dim, tag):
            try:
                _, tags, _ = model.mesh.getElements(dim, entity)
            except Exception:  # gmsh raises for an entity that does not exist: no elements
                tags = []
            for t in tags:
                count += len(t)
                if dim == 2:
                    covered.append(np.asarray(t, dtype=np.int64))
        if count == 0:
            kind = "material" if dim == 2 else "boundary"
            raise GeometryError(
                f"physical group '{name}' ({kind}) is empty: it has no mesh elements; "
                "check the entities it was given"
            )
    if not groups[2]:
        raise GeometryError("the gmsh model has no 2-D physical group: name the material regions")
    covered_arr = np.concatenate(covered) if covered else np.empty(0, np.int64)
    unique, counts = np.unique(covered_arr, return_counts=True)
    if np.any(counts > 1):
        raise GeometryError(
            f"{int(np.sum(counts > 1))} cells belong to more than one material group; "
            "each surface must be in exactly one 2-D physical group"
        )
    missing = np.setdiff1d(all_cells_arr, unique)
    if missing.size:
        raise GeometryError(
            f"{missing.size} of {all_cells_arr.size} cells have no material (their surface is in "
            "no 2-D physical group); add every surface to a named physical group"
        )
    _check_cell_shapes(model)
    return {"cell_type": cell_type, "cell_groups": groups[2], "facet_groups": groups[1]}


def _check_cell_shapes(model: Any) -> None:
    """Refuse non-finite node coordinates and zero-area, inverted or tangled cells.

    Within one gmsh surface every cell runs the same way round (gmsh meshes it so): a cell
    running the other way is inverted (a node moved across the opposite edge). A
    quadrilateral is tangled (a bow tie) when neither diagonal splits it into two triangles
    running its surface's way round. A cell is of zero area below 1e-12 times the square of
    the mesh's extent.
    """
    node_tags, coords, _ = model.mesh.getNodes()
    node_tags = np.asarray(node_tags, dtype=np.int64)
    xy = np.asarray(coords, dtype=float).reshape(-1, 3)[:, :2]
    bad = ~np.isfinite(xy).all(axis=1)
    if bad.any():
        raise GeometryError(f"{int(bad.sum())} mesh node(s) have a non-finite coordinate (node "
                            f"{int(node_tags[bad][0])}: {xy[bad][0].tolist()}): fix the mesh")
    index = np.zeros(int(node_tags.max(initial=0)) + 1, dtype=np.int64)
    index[node_tags] = np.arange(node_tags.size)
    extent = np.ptp(xy, axis=0) if xy.size else np.zeros(2)
    tiny = 1e-12 * float(extent @ extent)
    for _, entity in model.getEntities(2):
        types, tags, nodes = model.mesh.getElements(2, entity)
        for kind, cells, cell_nodes in zip(types, tags, nodes, strict=True):
            nen = 3 if kind == 2 else 4
            p = xy[index[np.asarray(cell_nodes, dtype=np.int64).reshape(-1, nen)]]
            edge_in = p - np.roll(p, 1, axis=1)  # edge arriving at each corner
            edge_out = np.roll(p, -1, axis=1) - p  # edge leaving it
            # twice the area of the triangle (previous, this, next corner), > 0 turning left
            corner = edge_in[..., 0] * edge_out[..., 1] - edge_in[..., 1] * edge_out[..., 0]
            area = 0.5 * np.sum(p[..., 0] * np.roll(p[..., 1], -1, axis=1)
                                - np.roll(p[..., 0], -1, axis=1) * p[..., 1], axis=1)
            way = 1.0 if np.sum(area) >= 0.0 else -1.0
            faults = [("of zero area", np.abs(area) <= tiny),
                      ("inverted (its nodes run the other way round from its neighbours')",
                       area * way < 0.0)]
            if nen == 4:
                c = corner * way
                split = ((c[:, 1] > 0) & (c[:, 3] > 0)) | ((c[:, 0] > 0) & (c[:, 2] > 0))
                faults.append(("tangled (a self-intersecting quadrilateral)", ~split))
            for what, hit in faults:
                if hit.any():
                    i = int(np.argmax(hit))
                    centre = p[i].mean(axis=0)
                    raise GeometryError(
                        f"{int(hit.sum())} cell(s) of surface {entity} are {what}: cell "
                        f"{int(cells[i])} at ({centre[0]:.6g}, {centre[1]:.6g}); fix the mesh "
                        "(a misplaced node?)")


def mesh_from_gmsh(comm: MPI.Comm = MPI.COMM_WORLD, rank: int = 0) -> MeshData:
    """Convert the current gmsh model (alive on ``rank``) into a checked :class:`MeshData`."""
    import gmsh
    from dolfinx.io import gmshio

    info: dict[str, Any] | GeometryError | None = None
    if comm.rank == rank:
        try:
            info = _check_gmsh_model(gmsh)
        except GeometryError as err:
            info = err
        except Exception as err:  # gmsh's own errors: re-raised on every rank
            info = GeometryError(f"the gmsh model cannot be read: {err}")
    info = comm.bcast(info, root=rank)
    if isinstance(info, GeometryError):
        raise info
    assert info is not None
    msh, cell_tags, facet_tags = gmshio.model_to_mesh(gmsh.model, comm, rank, gdim=2)
    msh.topology.create_connectivity(1, 2)
    return MeshData(msh, cell_tags, facet_tags, info["cell_groups"], info["facet_groups"],
                    info["cell_type"])


@contextlib.contextmanager
def gmsh_session(comm: MPI.Comm = MPI.COMM_WORLD, rank: int = 0) -> Iterator[Any]:
    """Initialise gmsh quietly on ``rank`` and finalise it afterwards."""
    import gmsh

    if comm.rank == rank:
        gmsh.initialize(readConfigFiles=False)
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.model.add("hybrid")
    try:
        yield gmsh
    finally:
        if comm.rank == rank:
            gmsh.finalize()


def build_mesh(builder: Callable[..., None], comm: MPI.Comm = MPI.COMM_WORLD,
               **params: Any) -> MeshData:
    """Run a gmsh builder ``builder(gmsh, **params)`` on rank 0 and convert the model.

    The builder creates the geometry, its named physical groups and the 2-D mesh. A
    ``cells`` parameter must be "triangle" or "quadrilateral".
    """
    if "cells" in params and params["cells"] not in ("triangle", "quadrilateral"):
        raise GeometryError(f"cells = {params['cells']!r}: must be 'triangle' or "
                            "'quadrilateral'")
    with gmsh_session(comm) as gmsh:
        error: Exception | None = None
        if comm.rank == 0:
            try:
                builder(gmsh, **params)
            except Exception as err:  # re-raised on every rank below
                error = err
        error = comm.bcast(error, root=0)
        if error is not None:
            raise error
        return mesh_from_gmsh(comm)


def read_msh(path: str | Path, comm: MPI.Comm = MPI.COMM_WORLD) -> MeshData:
    """Read a gmsh ``.msh`` file (with named physical groups) into a checked :class:`MeshData`."""
    path = Path(path)
    if not path.is_file():
        raise GeometryError(f"mesh file '{path}' does not exist")
    with gmsh_session(comm) as gmsh:
        error = None
        if comm.rank == 0:
            try:
                gmsh.merge(str(path))
            except Exception as err:  # gmsh raises a bare Exception; re-raised on every rank
                error = GeometryError(f"mesh file '{path}' cannot be read by gmsh ({err}): "
                                      "check that it is a gmsh .msh file")
        error = comm.bcast(error, root=0)
        if error is not None:
            raise error
        return mesh_from_gmsh(comm)


def load_mesh_script(script: str | Path) -> ModuleType:
    """Import a gmsh script in ``meshes/`` by path.

    The module holds its builder and whatever else it defines, e.g. the dimensions of the
    section it meshes.
    """
    script = Path(script)
    if not script.is_file():
        raise GeometryError(f"gmsh script '{script}' not found")
    return import_script(script, "hybrid_mesh")


def load_builder(script: str | Path, name: str = "build") -> Callable[..., None]:
    """Load the function ``name`` from a gmsh script in ``meshes/`` (by path)."""
    module = load_mesh_script(script)
    if not hasattr(module, name):
        raise GeometryError(f"gmsh script '{script}' defines no function '{name}'")
    return getattr(module, name)


def physical_group(gmsh: Any, dim: int, entities: list[int], name: str) -> int:
    """Add a named physical group to the current gmsh model (gmsh 4.8 has no name argument)."""
    tag = gmsh.model.addPhysicalGroup(dim, entities)
    gmsh.model.setPhysicalName(dim, tag, name)
    return tag


def quad_options(gmsh: Any) -> None:
    """Gmsh options for all-quadrilateral meshes that work with gmsh 4.8 (see dolfinx notes)."""
    gmsh.option.setNumber("Mesh.Algorithm", 6)
    gmsh.option.setNumber("Mesh.RecombineAll", 1)
    gmsh.option.setNumber("Mesh.RecombinationAlgorithm", 1)
