"""Outputs users open: XDMF for ParaView, PNG plots, summary.json.

Everything that writes a file is collective under MPI and writes from rank 0 where the file is
not parallel (PNG, JSON).
"""

from __future__ import annotations

import json
import math
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any

import numpy as np

__all__ = ["Check", "write_summary", "write_continuum_xdmf", "plot_cell_field",
           "gather_cells", "continuum_figures"]

STRESS_NAMES = ("sigma_xx", "sigma_yy", "sigma_zz", "sigma_xy")


@dataclass
class Check:
    """A computed figure next to its reference (None when there is no closed form).

    ``error`` is relative, |computed - reference| / |reference| (absolute when the reference
    is 0); ``passed`` compares it with ``bar``.
    """

    computed: float
    reference: float | None = None
    bar: float | None = None
    unit: str = ""
    source: str = ""

    @property
    def error(self) -> float | None:
        """Relative error (absolute when the reference is 0); None without a reference."""
        if self.reference is None:
            return None
        scale = abs(self.reference) if self.reference != 0 else 1.0
        return abs(self.computed - self.reference) / scale

    @property
    def passed(self) -> bool | None:
        """Whether the error is within ``bar``; None without a bar or a reference."""
        if self.bar is None or self.error is None:
            return None
        return bool(self.error <= self.bar)

    def as_dict(self) -> dict[str, Any]:
        """The fields plus ``error`` and ``passed``, as a plain dict."""
        out = asdict(self)
        out.update(error=self.error, passed=self.passed)
        return out

    @classmethod
    def published(cls, computed: float, reference: float, bar: float | None, unit: str,
                  source: str, *, applies: bool) -> Check:
        """A comparison with a published value, made only when ``applies``.

        ``applies``: the run uses the publication's parameters; otherwise the figure is
        reported with "no reference for these parameters".
        """
        if applies:
            return cls(computed, reference, bar, unit, source)
        return cls(computed, None, None, unit, f"no reference for these parameters ({source})")


def _jsonable(value: Any) -> Any:
    if isinstance(value, Check):
        return _jsonable(value.as_dict())
    if isinstance(value, dict):
        return {str(k): _jsonable(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [_jsonable(v) for v in value]
    if isinstance(value, np.ndarray):
        return _jsonable(value.tolist())
    if isinstance(value, np.generic):
        return _jsonable(value.item())
    if isinstance(value, float) and not math.isfinite(value):
        return str(value)
    if isinstance(value, Path):
        return str(value)
    return value


def write_summary(path: str | Path, summary: dict[str, Any], comm: Any = None) -> Path:
    """Write ``summary`` (Checks, numpy values allowed) as indented JSON from rank 0."""
    path = Path(path)
    if comm is None or comm.rank == 0:
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(json.dumps(_jsonable(summary), indent=2) + "\n")
    return path


def save_figure(fig: Any, path: str | Path) -> Path:
    """Lay out, write (creating the folder) and close a matplotlib figure; returns its path."""
    import matplotlib.pyplot as plt

    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)
    return path


def write_continuum_xdmf(path: str | Path, state: Any) -> Path:
    """Write a :class:`~hybrid.continuum.ContinuumState` to XDMF (+ .h5) for ParaView.

    Point data: displacement [m] at the vertices. Cell data: cell-mean stress components
    [kPa], plastic strain, yield flag, material id. Gathered to rank 0 and written with meshio,
    so the file opens in ParaView and in ``meshio.read``.
    """
    import meshio

    path = Path(path)
    md = state.model.mesh
    x, cells = md.cell_vertices()
    global_ids = np.asarray(md.mesh.geometry.input_global_indices, dtype=np.int64)
    u_nodes = displacement_at_geometry_nodes(md.mesh, state.u)
    cell_stress = state.cell_stress()
    cell_fields = {name: cell_stress[:, i] for i, name in enumerate(STRESS_NAMES)}
    cell_fields["plastic_strain"] = state.cell_plastic_strain()
    cell_fields["yielded"] = np.any(state.yielded > 0, axis=1).astype(float)
    cell_fields["material"] = state.model.material_ids().astype(float)
    comm = state.comm
    gathered = comm.gather((global_ids, x, u_nodes, global_ids[cells], cell_fields), root=0)
    if comm.rank != 0:
        return path
    n_points = 1 + max(int(g[0].max()) for g in gathered if len(g[0]))
    points, displacement = np.zeros((n_points, 3)), np.zeros((n_points, 2))
    for ids, coords, disp, _, _ in gathered:
        points[ids, :2] = coords
        displacement[ids] = disp
    connectivity = np.concatenate([g[3] for g in gathered])
    data = {name: [np.concatenate([g[4][name] for g in gathered])] for name in cell_fields}
    kind = "quad" if md.is_quad else "triangle"
    path.parent.mkdir(parents=True, exist_ok=True)
    meshio.write(path, meshio.Mesh(points, [(kind, connectivity)],
                                   point_data={"displacement": displacement},
                                   cell_data=data))
    return path


def displacement_at_geometry_nodes(msh: Any, u: Any) -> np.ndarray:
    """Displacement (n_geometry_nodes, 2) [m] at the first-order mesh's nodes."""
    from dolfinx import fem

    V1 = fem.VectorFunctionSpace(msh, ("CG", 1))
    u1 = fem.Function(V1)
    u1.interpolate(u)
    return u1.x.array.reshape(-1, 2)[_geometry_to_dof_map(msh, V1)]


def gather_cells(mesh_data: Any, values: np.ndarray, displacement: Any = None,
                 scale: float = 0.0) -> tuple[np.ndarray, np.ndarray] | tuple[None, None]:
    """Cell polygons (n, nv, 2) and per-cell values gathered on rank 0 (None elsewhere).

    With ``displacement`` (a dolfinx function) and ``scale`` > 0 the polygons are deformed.
    """
    x, cells = mesh_data.cell_vertices()
    coords = x.copy()
    if displacement is not None and scale > 0:
        coords = coords + scale * displacement_at_geometry_nodes(mesh_data.mesh, displacement)
    polys = coords[cells]
    comm = mesh_data.comm
    all_polys = comm.gather(polys, root=0)
    all_values = comm.gather(np.asarray(values), root=0)
    if comm.rank != 0:
        return None, None
    return np.concatenate(all_polys), np.concatenate(all_values)


def _geometry_to_dof_map(msh: Any, V1: Any) -> np.ndarray:
    """Index of the P1 dof at each geometry node (first-order meshes: one to one)."""
    num_cells = msh.topology.index_map(2).size_local + msh.topology.index_map(2).num_ghosts
    geo = msh.geometry.dofmap.array.reshape(num_cells, -1)
    dof = V1.dofmap.list.array.reshape(num_cells, -1)
    out = np.zeros(msh.geometry.x.shape[0], dtype=np.int64)
    out[geo.ravel()] = dof.ravel()
    return out


def plot_cell_field(path: str | Path, mesh_data: Any, values: np.ndarray, *, title: str,
                    label: str, cmap: str = "viridis", displacement: Any = None,
                    scale: float = 0.0, symmetric: bool = False,
                    overlay: Any = None) -> Path | None:
    """PNG of a per-cell field on the (optionally deformed) mesh, axes in m.

    ``overlay(ax)``, if given, draws extra items (e.g. reference lines) on the axes.
    """
    polys, vals = gather_cells(mesh_data, values, displacement, scale)
    if polys is None or vals is None:  # both None together, off rank 0
        return None
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.collections import PolyCollection

    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig, ax = plt.subplots(figsize=(8, 6), dpi=120)
    coll = PolyCollection(polys, array=vals, cmap=cmap, edgecolors="face", linewidths=0.2)
    if symmetric:
        vmax = float(np.nanmax(np.abs(vals), initial=0.0)) or 1.0  # NaN: cell left blank
        coll.set_clim(-vmax, vmax)
    ax.add_collection(coll)
    ax.autoscale_view()
    ax.set_aspect("equal")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_title(title + (f" (deformation x {scale:g})" if scale > 0 else ""))
    fig.colorbar(coll, ax=ax, label=label, shrink=0.8)
    if overlay is not None:
        overlay(ax)
    return save_figure(fig, path)


def continuum_figures(out_dir: str | Path, state: Any, *, deformation_scale: float = 0.0,
                      prefix: str = "") -> list[Path]:
    """Standard PNGs of a continuum state: vertical and shear stress, displacement magnitude."""
    out_dir = Path(out_dir)
    md = state.model.mesh
    s = state.cell_stress()
    paths = []
    for i, name, cmap in ((1, "sigma_yy", "viridis"), (0, "sigma_xx", "viridis"),
                          (3, "sigma_xy", "RdBu_r")):
        p = plot_cell_field(out_dir / f"{prefix}{name}.png", md, s[:, i],
                            title=f"{name} (tension positive)", label=f"{name} [kPa]",
                            cmap=cmap, displacement=state.u, scale=deformation_scale,
                            symmetric=(i == 3))
        if p is not None:
            paths.append(p)
    return paths
