"""Outputs users open: XDMF for ParaView, PNG plots, summary.json (a :class:`CaseSummary`).

Everything that writes a file is collective under MPI and writes from rank 0 where the file is
not parallel (PNG, JSON).
"""

from __future__ import annotations

import dataclasses
import json
import math
from collections.abc import Iterator, Mapping, MutableMapping
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

__all__ = ["Check", "CaseSummary", "write_summary", "write_continuum_xdmf", "plot_cell_field",
           "gather_cells", "continuum_figures", "Box", "check_box"]

#: a rectangle (xmin, ymin, xmax, ymax) [m]: the one order of every box (figure windows,
#: contact bounds)
Box = tuple[float, float, float, float]


def check_box(box: Any, name: str = "window") -> Box:
    """``box`` as a :data:`Box`; a clear error for a wrong length or the order of its corners.

    (xmin, xmax, ymin, ymax), the axis-limits order, is refused where it shows (xmin > xmax).
    """
    try:
        values = tuple(float(v) for v in box)
    except (TypeError, ValueError):
        values = ()
    if len(values) != 4 or not all(math.isfinite(v) for v in values):
        raise ValueError(f"{name} = {box!r}: give four numbers (xmin, ymin, xmax, ymax) [m]")
    xmin, ymin, xmax, ymax = values
    if not (xmin < xmax and ymin < ymax):
        raise ValueError(f"{name} = {box!r}: the order is (xmin, ymin, xmax, ymax) [m] with "
                         "xmin < xmax and ymin < ymax (not the axis-limits order xmin, xmax, "
                         "ymin, ymax)")
    return values


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
    def from_dict(cls, data: Mapping[str, Any]) -> Check:
        """Rebuild a check from :meth:`as_dict`'s form, as read back from summary.json.

        ``error`` and ``passed`` are recomputed; a non-finite number may come as the string
        JSON holds it in ("nan", "inf").
        """
        def number(value: Any) -> Any:
            return float(value) if isinstance(value, str) else value

        return cls(number(data["computed"]), number(data.get("reference")),
                   number(data.get("bar")), str(data.get("unit", "")),
                   str(data.get("source", "")))

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


# the fields every case summary has, in their place at the top of summary.json
_COMMON = ("case", "out", "parameters", "checks")


@dataclass
class CaseSummary(MutableMapping[str, Any]):
    """What a case reports: its name, output folder, parameters and checks, and its own results.

    Its JSON form (:meth:`to_json`, summary.json) is one object: ``case``, ``out``,
    ``parameters``, then the sections of ``results`` by name, with ``checks`` after the
    sections given when the summary was made and before those added later. The summary is also
    a mapping over those same top-level names (``summary["discrete"]``, ``"curve" in summary``,
    ``summary.update(...)``): a name other than the four fields is a section of ``results``.

    Attributes:
        case: the case's name and label, e.g. "oedometer (C2)".
        out: the folder the case wrote its outputs to.
        parameters: the case's parameters by name (a ``Parameters`` dataclass given here is
            stored as its dict).
        checks: computed figures beside their references, by name.
        results: the case's own sections (counts, curves, the continuum, handover and
            discrete phases...) by name, in the order they were written.
        checks_at: how many sections of ``results`` come before ``checks`` in the JSON form
            (set when the summary is made: the sections given then).
    """

    case: str
    out: Path
    parameters: dict[str, Any]
    checks: dict[str, Check] = field(default_factory=dict)
    results: dict[str, Any] = field(default_factory=dict)
    checks_at: int = field(default=-1, repr=False)

    def __post_init__(self) -> None:
        """Normalise ``out`` to a path and ``parameters`` to a dict; place the checks.

        Raises:
            ValueError: a section is named like one of the four fields.
        """
        self.out = Path(self.out)
        if dataclasses.is_dataclass(self.parameters) and not isinstance(self.parameters, type):
            self.parameters = asdict(self.parameters)
        if self.checks_at < 0:
            self.checks_at = len(self.results)
        clash = [name for name in _COMMON if name in self.results]
        if clash:
            raise ValueError(f"{', '.join(clash)}: fields of the summary, not sections")

    def as_dict(self) -> dict[str, Any]:
        """The summary as one dict in the order of summary.json (values not yet made JSON)."""
        sections = list(self.results.items())
        return {"case": self.case, "out": str(self.out), "parameters": self.parameters,
                **dict(sections[:self.checks_at]), "checks": self.checks,
                **dict(sections[self.checks_at:])}

    def to_json(self) -> dict[str, Any]:
        """The JSON form: :meth:`as_dict` with checks, paths and numpy values made plain.

        Non-finite floats become strings ("nan", "inf").
        """
        return _jsonable(self.as_dict())

    @classmethod
    def from_json(cls, data: Mapping[str, Any]) -> CaseSummary:
        """Rebuild a summary from its JSON form (checks from their dicts)."""
        missing = [name for name in _COMMON[:3] if name not in data]
        if missing:
            raise ValueError(f"not a case summary: no {', '.join(missing)}")
        names = [name for name in data if name not in _COMMON]
        order = list(data)
        before = order[:order.index("checks")] if "checks" in data else order
        checks = {str(name): c if isinstance(c, Check) else Check.from_dict(c)
                  for name, c in data.get("checks", {}).items()}
        return cls(str(data["case"]), Path(data["out"]), dict(data["parameters"]), checks,
                   {name: data[name] for name in names},
                   checks_at=sum(name not in _COMMON for name in before))

    @classmethod
    def read(cls, path: str | Path) -> CaseSummary:
        """Read a summary.json written by :meth:`write`."""
        return cls.from_json(json.loads(Path(path).read_text()))

    def write(self, path: str | Path, comm: Any = None) -> Path:
        """Write the JSON form as indented JSON from rank 0 (every rank: collective)."""
        return write_summary(path, self, comm)

    def __getitem__(self, key: str) -> Any:
        """A field by its name ("case", "out", "parameters", "checks") or a section."""
        if key in _COMMON:
            return getattr(self, key)
        return self.results[key]

    def __setitem__(self, key: str, value: Any) -> None:
        """Set a field by its name, or a section (a new one goes at the end)."""
        if key == "out":
            self.out = Path(value)
        elif key in _COMMON:
            setattr(self, key, value)
        else:
            self.results[key] = value

    def __delitem__(self, key: str) -> None:
        """Remove a section (the fields stay)."""
        if key in _COMMON:
            raise KeyError(f"'{key}' is a field of every case summary; it cannot be removed")
        del self.results[key]

    def __iter__(self) -> Iterator[str]:
        """The top-level names in the order of the JSON form."""
        return iter(self.as_dict())

    def __len__(self) -> int:
        """The number of top-level names (fields and sections)."""
        return len(_COMMON) + len(self.results)


def _jsonable(value: Any) -> Any:
    if isinstance(value, Check | CaseSummary):
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


def write_summary(path: str | Path, summary: CaseSummary | Mapping[str, Any],
                  comm: Any = None) -> Path:
    """Write ``summary`` (Checks, numpy values allowed) as indented JSON from rank 0.

    A :class:`CaseSummary` is written in its JSON form (:meth:`CaseSummary.to_json`).
    """
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

    One state, with meshio (it opens in ParaView and in ``meshio.read``): the fields of
    :func:`~hybrid.continuum.series.continuum_fields`, named as in the series of both phases
    (``displacement`` [m] at the nodes; ``sigma_xx`` ... [kPa], ``plastic_strain``,
    ``yielded`` (fraction of the points), ``material`` per cell). A series of the steps is
    :class:`~hybrid.continuum.series.ContinuumSeries`. Collective; rank 0 writes.
    """
    import meshio

    from hybrid.continuum.series import continuum_fields

    path = Path(path)
    fields = continuum_fields(state)
    if fields is None:
        return path
    kind = "quad" if state.model.mesh.is_quad else "triangle"
    path.parent.mkdir(parents=True, exist_ok=True)
    cell_data = {**fields.cell_data, "material": fields.material.astype(float)}
    meshio.write(path, meshio.Mesh(np.column_stack([fields.points, np.zeros(len(fields.points))]),
                                   [(kind, fields.cells)],
                                   point_data={"displacement": fields.displacement},
                                   cell_data={k: [v] for k, v in cell_data.items()}))
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
