"""Standard figures of a continuum state: staged construction and strength reduction.

Cell fields in a window with the cells not yet placed left blank, displacement vectors,
profiles up a vertical line and through a column of cells, the strength-reduction mechanism
with a slip circle; the figures an engineer reads first in PLAXIS Output
(:func:`engineering_figures`): the deformed mesh over the undeformed outline, total and
incremental shear strain, plastic points (Mohr-Coulomb and tension cut-off). Built on
:func:`hybrid.io.plot_cell_field` and :func:`hybrid.io.gather_cells`: every function is
collective under MPI and writes from rank 0; each returns the paths written (none on the
other ranks). Axes in m, stresses in kPa (tension positive); ``window`` = (xmin, ymin,
xmax, ymax) [m] (:data:`hybrid.io.Box`).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any, NamedTuple

import numpy as np

from hybrid.io import Box, check_box, gather_cells, plot_cell_field, save_figure
from hybrid.references import Band

if TYPE_CHECKING:
    from hybrid.continuum.staging import Construction
    from hybrid.continuum.state import ContinuumState
    from hybrid.continuum.strength_reduction import SafetyResult
    from hybrid.references import SlipCircle

__all__ = ["Column", "Band", "plot_level_history", "window_overlay", "construction_figures",
           "plot_displacement_vectors", "plot_column_profiles", "safety_figures",
           "staged_figures", "shear_strain", "plastic_points", "plot_deformed_mesh",
           "plot_shear_strain", "plot_plastic_points", "engineering_figures",
           "safety_engineering_figures", "circle_overlay", "MOHR_COULOMB", "TENSION_CUTOFF"]

Window = Box


class Column(NamedTuple):
    """A vertical line and a column of cells whose profiles :func:`plot_column_profiles` draws.

    The line is at ``x`` from ``bottom`` to ``top`` [m]; ``cells``: mask of the owned cells of
    the column; grey lines are drawn at ``levels`` [m]; ``line`` and ``name`` name them in the
    labels.
    """

    cells: np.ndarray
    x: float
    bottom: float
    top: float
    levels: Sequence[float] = ()
    line: str = ""
    name: str = "column"


def plot_level_history(path: str | Path, levels: Sequence[float], values: Sequence[float], *,
                       bands: Sequence[Band] = (), label: str = "this analysis",
                       xlabel: str = "", ylabel: str = "level [m]",
                       title: str = "") -> Path | None:
    """A quantity (x) against the level reached (y), with published ``bands`` as boxes.

    Writes from rank 0 only (None elsewhere).
    """
    from mpi4py import MPI

    if MPI.COMM_WORLD.rank != 0:
        return None
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6.5, 5), dpi=120)
    colours = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    for k, b in enumerate(bands):
        c = colours[(k + 1) % len(colours)]
        dy = max(b.level_high - b.level_low, 0.2)
        ax.add_patch(matplotlib.patches.Rectangle(
            (b.low, 0.5 * (b.level_low + b.level_high) - 0.5 * dy), max(b.high - b.low, 4.0),
            dy, facecolor=c, alpha=0.35, edgecolor=c, label=b.label))
    ax.plot(values, levels, "ko-", ms=4, label=label)
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.set_title(title, fontsize=10)
    ax.grid(alpha=0.3)
    ax.autoscale_view()
    ax.legend(fontsize=7, loc="best")  # placed where it hides fewest of the curve and bands
    return save_figure(fig, path)


def window_overlay(window: Window) -> Callable[[Any], None]:
    """Overlay for :func:`~hybrid.io.plot_cell_field` that crops the axes to ``window``."""
    xmin, ymin, xmax, ymax = check_box(window)

    def crop(ax: Any) -> None:
        ax.set_xlim(xmin, xmax)
        ax.set_ylim(ymin, ymax)

    return crop


def _cell_fields(out: Path, mesh: Any, fields: list[tuple], active: np.ndarray,
                 overlay: Callable[[Any], None]) -> list[Path]:
    """Call plot_cell_field on each (file name, values, title, label, colour map).

    Cells not ``active`` are left blank; "RdBu_r" maps are symmetric about zero.
    """
    paths = []
    for name, values, title, label, cmap in fields:
        path = plot_cell_field(out / name, mesh, np.where(active, 1.0, np.nan) * values,
                               title=title, label=label, cmap=cmap,
                               symmetric=(cmap == "RdBu_r"), overlay=overlay)
        if path is not None:
            paths.append(path)
    return paths


def construction_figures(out: str | Path, mesh: Any, state: Any, strain: np.ndarray, *,
                         active: np.ndarray, window: Window, when: str,
                         column: Column | None = None,
                         prefix: str = "end_of_construction_",
                         elevation_label: str = "y [m]") -> list[Path]:
    """PNGs of ``state`` ("``when``" in the titles) with the cells not ``active`` left blank.

    The cells not ``active`` are those not placed yet. Writes
    ``{prefix}sigma_yy|sigma_xx|sigma_xy|yielded|vertical_strain.png``
    (stress components, yielded zone, vertical strain since placement: ``strain``, cell means
    (n_owned_cells, 4), e.g. :meth:`~hybrid.continuum.staging.PlacementStrain.cell_mean`),
    ``{prefix}displacement_vectors.png`` and, with a ``column``,
    ``{prefix}{column.name}_profiles.png`` (:func:`plot_column_profiles`).
    ``elevation_label``: the vertical axis's label (e.g. "elevation [m OD]").
    """
    out = Path(out)
    stress = state.cell_stress()
    fields = [(f"{prefix}{name}.png", stress[:, i], f"{name} [kPa], {when}",
               f"{name} [kPa] (tension +)", cmap)
              for i, name, cmap in ((1, "sigma_yy", "viridis"), (0, "sigma_xx", "viridis"),
                                    (3, "sigma_xy", "RdBu_r"))]
    fields += [(f"{prefix}yielded.png", np.any(state.yielded > 0, axis=1),
                f"Yielded zone, {when}", "yielded (1) [-]", "Reds"),
               (f"{prefix}vertical_strain.png", strain[:, 1],
                f"Vertical strain from placement, {when}", "eps_yy [-]", "viridis")]
    paths: list[Path | None] = list(_cell_fields(out, mesh, fields, active,
                                                 window_overlay(window)))
    paths.append(plot_displacement_vectors(
        out / f"{prefix}displacement_vectors.png", mesh, state, active=active, window=window,
        title=f"Displacement vectors (from placement), {when}",
        elevation_label=elevation_label))
    if column is not None:
        paths.append(plot_column_profiles(
            out / f"{prefix}{column.name}_profiles.png", mesh, state, strain[:, 1], column,
            title=f"{column.name.capitalize()}, {when} (grey lines: lift tops)",
            elevation_label=elevation_label))
    return [path for path in paths if path is not None]


def plot_displacement_vectors(path: str | Path, mesh: Any, state: Any, *, active: np.ndarray,
                              window: Window, title: str, longest: float = 6.0,
                              elevation_label: str = "y [m]") -> Path | None:
    """Cell-mean displacement vectors of the ``active`` cells whose centre lies in ``window``.

    In the window: x inside, y above its bottom. Coloured by |u|; the longest is drawn
    ``longest`` m long.
    """
    polys, vectors = gather_cells(mesh, state.cell_displacement())
    _, placed = gather_cells(mesh, np.asarray(active, float))
    if polys is None or vectors is None or placed is None:  # all None together, off rank 0
        return None
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    xmin, ymin, xmax, _ = check_box(window)
    centres = polys.mean(axis=1)
    fig, ax = plt.subplots(figsize=(11, 4.5), dpi=120)
    show = ((centres[:, 0] > xmin) & (centres[:, 0] < xmax)
            & (centres[:, 1] > ymin) & (placed > 0.5))
    magnitude = np.linalg.norm(vectors, axis=1)
    q = ax.quiver(centres[show, 0], centres[show, 1], vectors[show, 0], vectors[show, 1],
                  magnitude[show], cmap="viridis", angles="xy", scale_units="xy",
                  scale=float(np.max(magnitude[show], initial=1e-12)) / longest, width=0.0015)
    for poly in polys[show]:
        ax.fill(poly[:, 0], poly[:, 1], facecolor="none", edgecolor="0.85", linewidth=0.2)
    ax.set_aspect("equal")
    ax.set_xlabel("x [m]")
    ax.set_ylabel(elevation_label)
    ax.set_title(f"{title}; longest = {longest:g} m on the plot")
    fig.colorbar(q, ax=ax, label="|u| [m]", shrink=0.8)
    return save_figure(fig, path)


def plot_column_profiles(path: str | Path, mesh: Any, state: Any, strain_yy: np.ndarray,
                         column: Column, *, title: str = "", samples: int = 80,
                         elevation_label: str = "y [m]") -> Path | None:
    """Two profiles of a column against elevation.

    The horizontal displacement up the column's line (``samples`` points, up to its highest
    cell) and the vertical compression -eps_yy (``strain_yy``, per owned cell) of its cells.
    """
    polys, eps = gather_cells(mesh, strain_yy)
    _, flag = gather_cells(mesh, np.asarray(column.cells, float))
    ys = np.linspace(column.bottom, column.top, samples)
    u = state.displacement_at(np.column_stack([np.full_like(ys, column.x), ys]))
    if polys is None or eps is None or flag is None:  # all None together, off rank 0
        return None
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (a1, a2) = plt.subplots(1, 2, figsize=(9, 5), dpi=120, sharey=True)
    cells = flag > 0.5
    placed = ys <= np.max(polys[cells, :, 1], initial=ys[0])
    a1.plot(u[placed, 0] * 1000.0, ys[placed], "k-")
    line = column.line or f"x = {column.x:g} m"
    a1.set_xlabel(f"horizontal displacement at {line} [mm] (+ to the right)")
    a1.set_ylabel(elevation_label)
    a2.plot(-eps[cells] * 100.0, polys[cells].mean(axis=1)[:, 1], "o", ms=2.5)
    a2.set_xlabel(f"vertical compression -eps_yy, {column.name} cells [%]")
    for ax in (a1, a2):
        for level in column.levels:
            ax.axhline(level, color="0.8", linewidth=0.5)
        ax.grid(alpha=0.3)
    fig.suptitle(title)
    return save_figure(fig, path)


def safety_figures(out: str | Path, mesh: Any, safety: Any, *, active: np.ndarray,
                   window: Window, circle: Any = None, prefix: str = "fos_") -> list[Path]:
    """Figures of a :class:`~hybrid.continuum.strength_reduction.SafetyResult`.

    ``{prefix}plastic_strain.png`` at F and, when a reduction step converged,
    ``{prefix}mechanism.png`` (|du| of the last step); cells not ``active`` left blank;
    ``circle`` (a :class:`~hybrid.references.SlipCircle`) drawn dashed.
    """
    crop = window_overlay(window)

    def overlay(ax: Any) -> None:
        crop(ax)
        if circle is not None:
            arc = circle.arc()
            ax.plot(arc[:, 0], arc[:, 1], "r--", lw=1.2,
                    label=f"critical circle (Bishop), F = {circle.factor:.2f}")
            ax.legend(loc="lower left", fontsize=7)

    state = safety.state
    fields = [(f"{prefix}plastic_strain.png", state.cell_plastic_strain(),
               f"Plastic strain at F = {safety.factor:.3f}", "plastic strain [-]", "magma_r")]
    if any(ok for _, ok, _ in safety.trials):  # a reduction step converged: a mechanism
        fields.append((f"{prefix}mechanism.png",
                       np.linalg.norm(state.cell_displacement(safety.mechanism), axis=1),
                       "Failure mechanism: displacement increment of the last reduction step",
                       "|du| [m]", "viridis"))
    return _cell_fields(Path(out), mesh, fields, active, overlay)


def staged_figures(out: str | Path, mesh: Any, state: ContinuumState, built: Construction, *,
                   window: Window, column: Column | None = None,
                   circle: SlipCircle | None = None, elevation_label: str = "y [m]",
                   engineering: str | None = None) -> list[Path]:
    """The figures of a staged construction (:func:`~hybrid.continuum.staging.build_in_lifts`).

    :func:`construction_figures` of ``state``, the end of construction or, when a lift
    collapsed, the last equilibrium before collapse (said in the titles), with the fill not
    yet placed left blank and the strain from placement; then, when a factor of safety was
    found, :func:`safety_figures` of the last one with ``circle``. With ``engineering`` (how
    the titles name the state, e.g. "fill at 200.5 m OD"), also the figures an engineer reads
    first: :func:`engineering_figures` of ``state`` ("end_of_construction_" files) and, with
    a factor of safety, :func:`safety_engineering_figures` of it with ``circle``.
    """
    when = "end of construction" if built.completed else "last equilibrium before collapse"
    active = (np.ones(mesh.num_owned_cells, dtype=bool) if state.active is None
              else state.active)
    paths = construction_figures(out, mesh, state, built.strain.cell_mean(state),
                                 active=active, window=window, when=when, column=column,
                                 elevation_label=elevation_label)
    if built.safety is not None:
        paths += safety_figures(out, mesh, built.safety, active=built.safety_active,
                                window=window, circle=circle)
    if engineering is None:
        return paths
    paths += engineering_figures(out, state, prefix="end_of_construction_", when=engineering,
                                 window=window, elevation_label=elevation_label)
    if built.safety is not None:
        paths += safety_engineering_figures(out, built.safety, circle=circle, window=window,
                                            elevation_label=elevation_label)
    return paths


# --- the figures an engineer reads first (PLAXIS Output's) ---------------------------------

#: kinds of :func:`plastic_points`
MOHR_COULOMB, TENSION_CUTOFF = 1, 2


def shear_strain(state: ContinuumState, increment: np.ndarray | None = None) -> np.ndarray:
    """Cell-mean shear strain gamma_s = eps_1 - eps_3 (in plane) of the owned cells [-].

    gamma_s = sqrt((eps_xx - eps_yy)^2 + gamma_xy^2) at each point, from the displacement
    (total: since the displacements were last set to zero) or from ``increment`` (dof values
    of ``state.u``'s space, e.g. the last step of a strength-reduction search).
    """
    from hybrid.continuum.fields import strain
    from hybrid.continuum.quadrature import evaluate_at_points

    u = state.u
    if increment is not None:
        u = state.u.copy()
        u.x.array[:] = increment
    eps = evaluate_at_points(state.disc, strain(u))
    gamma = np.hypot(eps[..., 0] - eps[..., 1], eps[..., 3])
    return state.cell_mean(gamma[..., None])[:, 0]


def plastic_points(state: ContinuumState) -> tuple[np.ndarray, np.ndarray] | None:
    """The points on the yield surface at the last step, on rank 0 (None elsewhere).

    Returns their coordinates (n, 2) [m] and kinds: :data:`TENSION_CUTOFF` where the largest
    principal stress is at the tension cut-off in force (the apex when none is given), else
    :data:`MOHR_COULOMB` (collective).
    """
    import ufl

    from hybrid.constitutive.softening import (
        characteristic_length,
        softening_fraction,
        strength_at,
    )
    from hybrid.constitutive.table import kernel_table
    from hybrid.continuum.quadrature import evaluate_at_points

    model = state.model
    table = kernel_table([model.materials[k] for k in model.material_names],
                         state.strength_factor)[0]
    nqp = state.stress.shape[1]
    x, cells = model.mesh.cell_vertices()
    length = np.repeat(characteristic_length(x, cells), nqp)
    material = np.repeat(model.material_ids(), nqp)
    coords = evaluate_at_points(state.disc, ufl.SpatialCoordinate(state.mesh)).reshape(-1, 2)
    stress = state.stress.reshape(-1, 4)
    kappa = state.plastic_strain.ravel()
    on = np.flatnonzero(state.yielded.ravel() > 0)
    kinds = np.full(on.size, MOHR_COULOMB, dtype=np.int8)
    for k, q in enumerate(on):
        m = int(material[q])
        c, _, _, _, t = strength_at(table, m, softening_fraction(table, m, kappa[q], length[q]))
        sxx, syy, szz, sxy = stress[q]
        s1 = max(0.5 * (sxx + syy) + np.hypot(0.5 * (sxx - syy), sxy), szz)
        if s1 >= t - 1e-6 * max(abs(t), c, 1.0):
            kinds[k] = TENSION_CUTOFF
    gathered = state.comm.gather((coords[on], kinds), root=0)
    if state.comm.rank != 0:
        return None
    return (np.concatenate([g[0] for g in gathered]).reshape(-1, 2),
            np.concatenate([g[1] for g in gathered]))


def _nice_scale(largest: float, size: float) -> float:
    """A 1-2-5 factor that draws ``largest`` [m] about 5 % of ``size`` [m] (1 when 0)."""
    if not largest > 0.0:
        return 1.0
    raw = 0.05 * size / largest
    decade = 10.0 ** np.floor(np.log10(raw))
    return float(max(f for f in (1.0, 2.0, 5.0) if f * decade <= raw) * decade)


def _outline(polys: np.ndarray) -> np.ndarray:
    """The edges (n, 2, 2) [m] that belong to one cell only: the body's outline."""
    edges = np.stack([polys, np.roll(polys, -1, axis=1)], axis=2).reshape(-1, 2, 2)
    scale = 1e-9 * max(float(np.ptp(polys)), 1.0)
    keys = np.round(edges / scale).astype(np.int64)
    flipped = keys[:, ::-1]
    canon = np.where((keys[:, 0, 0] < flipped[:, 0, 0])[:, None, None]
                     | ((keys[:, 0, 0] == flipped[:, 0, 0])
                        & (keys[:, 0, 1] <= flipped[:, 0, 1]))[:, None, None], keys, flipped)
    _, inverse, counts = np.unique(canon.reshape(len(edges), 4), axis=0, return_inverse=True,
                                   return_counts=True)
    return edges[counts[inverse.ravel()] == 1]


def _mesh_axes(window: Window | None, elevation_label: str, size: tuple[float, float] = (9, 6)
               ) -> tuple[Any, Any]:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=size, dpi=120)
    ax.set_aspect("equal")
    ax.set_xlabel("x [m]")
    ax.set_ylabel(elevation_label)
    return fig, ax


def _crop(ax: Any, window: Window | None) -> None:
    if window is None:
        ax.autoscale_view()
    else:
        window_overlay(window)(ax)


def plot_deformed_mesh(path: str | Path, state: ContinuumState, *,
                       scale: float | None = None, window: Window | None = None,
                       title: str = "Deformed mesh", active: np.ndarray | None = None,
                       elevation_label: str = "y [m]") -> Path | None:
    """The mesh deformed by ``scale`` x the displacement, over the undeformed outline.

    ``scale`` None: a 1-2-5 factor that draws the largest nodal displacement 5 % of the
    model's size; the factor and the largest |u| are in the title. ``active``: the owned
    cells drawn (None: every cell, or those in place in a staged construction).
    """
    if active is None:
        active = (np.ones(state.model.mesh.num_owned_cells, dtype=bool) if state.active is None
                  else state.active)
    polys, flag = gather_cells(state.model.mesh, np.asarray(active, float))
    moved, _ = gather_cells(state.model.mesh, np.asarray(active, float), state.u, 1.0)
    if polys is None or moved is None or flag is None:  # all None together, off rank 0
        return None
    from matplotlib.collections import LineCollection, PolyCollection

    keep = flag > 0.5
    polys, moved = polys[keep], moved[keep]
    u = (moved - polys).reshape(-1, 2)
    largest = float(np.max(np.linalg.norm(u, axis=1), initial=0.0))
    if scale is None:
        scale = _nice_scale(largest, float(np.max(np.ptp(polys.reshape(-1, 2), axis=0))))
    fig, ax = _mesh_axes(window, elevation_label)
    ax.add_collection(LineCollection(_outline(polys), colors="0.45", linewidths=1.0,
                                     linestyles="--", label="undeformed outline"))
    ax.add_collection(PolyCollection(polys + scale * (moved - polys), facecolors="none",
                                     edgecolors="k", linewidths=0.3,
                                     label=f"deformed mesh (x {scale:g})"))
    _crop(ax, window)
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.16), ncol=2, fontsize=8)
    ax.set_title(f"{title}: displacements x {scale:g} (largest |u| = {largest:.3g} m)")
    return save_figure(fig, path)


def plot_shear_strain(path: str | Path, state: ContinuumState, *,
                      increment: np.ndarray | None = None, window: Window | None = None,
                      title: str = "Total shear strain", active: np.ndarray | None = None,
                      overlay: Callable[[Any], None] | None = None) -> Path | None:
    """Shaded cell-mean shear strain gamma_s (:func:`shear_strain`) [%].

    Cells not ``active`` are left blank; ``increment``: of that displacement increment;
    ``overlay(ax)`` draws on top (e.g. a slip circle).
    """
    gamma = 100.0 * shear_strain(state, increment)
    if active is None:
        active = state.active
    if active is not None:
        gamma = np.where(active, gamma, np.nan)
    label = ("incremental" if increment is not None else "total") + " shear strain"
    crop = None if window is None else window_overlay(window)

    def draw(ax: Any) -> None:
        if crop is not None:
            crop(ax)
        if overlay is not None:
            overlay(ax)

    return plot_cell_field(path, state.model.mesh, gamma, title=title,
                           label=f"{label} gamma_s = eps_1 - eps_3 [%]", cmap="magma_r",
                           overlay=draw)


def plot_plastic_points(path: str | Path, state: ContinuumState, *,
                        window: Window | None = None, title: str = "Plastic points",
                        elevation_label: str = "y [m]") -> Path | None:
    """The mesh with the points on the yield surface (:func:`plastic_points`).

    Red squares: Mohr-Coulomb points; white squares: tension cut-off points; their counts
    in the title.
    """
    points = plastic_points(state)
    polys, _ = gather_cells(state.model.mesh, np.zeros(state.model.mesh.num_owned_cells))
    if points is None or polys is None:  # off rank 0
        return None
    from matplotlib.collections import PolyCollection

    xy, kinds = points
    fig, ax = _mesh_axes(window, elevation_label)
    ax.add_collection(PolyCollection(polys, facecolors="none", edgecolors="0.75",
                                     linewidths=0.3))
    counts = []
    for kind, name, face, size in ((MOHR_COULOMB, "Mohr-Coulomb", "red", 2.2),
                                   (TENSION_CUTOFF, "tension cut-off", "white", 3.5)):
        pick = kinds == kind
        counts.append(f"{int(pick.sum())} {name}")
        ax.plot(xy[pick, 0], xy[pick, 1], "s", ms=size, mfc=face, mec="k", mew=0.5 * size / 3,
                label=f"{name} point ({int(pick.sum())})")
    _crop(ax, window)
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.16), ncol=2, fontsize=8)
    ax.set_title(f"{title}: {', '.join(counts)}")
    return save_figure(fig, path)


def engineering_figures(out: str | Path, state: ContinuumState, *, prefix: str = "",
                        when: str = "", window: Window | None = None,
                        scale: float | None = None, increment: np.ndarray | None = None,
                        overlay: Callable[[Any], None] | None = None,
                        elevation_label: str = "y [m]") -> list[Path]:
    """The figures an engineer reads first, of ``state`` ("``when``" in the titles).

    ``{prefix}deformed_mesh.png`` (:func:`plot_deformed_mesh`, ``scale``),
    ``{prefix}shear_strain.png`` (total shear strain), ``{prefix}plastic_points.png`` and,
    with a displacement ``increment`` (e.g. ``SafetyResult.mechanism``),
    ``{prefix}incremental_shear_strain.png``; ``overlay(ax)`` is drawn over the shear
    strains (e.g. the critical slip circle). Collective; the paths on rank 0.
    """
    out = Path(out)
    at = f", {when}" if when else ""
    paths = [plot_deformed_mesh(out / f"{prefix}deformed_mesh.png", state, scale=scale,
                                window=window, title=f"Deformed mesh{at}",
                                elevation_label=elevation_label),
             plot_shear_strain(out / f"{prefix}shear_strain.png", state, window=window,
                               title=f"Total shear strain{at}", overlay=overlay),
             plot_plastic_points(out / f"{prefix}plastic_points.png", state, window=window,
                                 title=f"Plastic points{at}",
                                 elevation_label=elevation_label)]
    if increment is not None:
        paths.append(plot_shear_strain(out / f"{prefix}incremental_shear_strain.png", state,
                                       increment=increment, window=window,
                                       title=f"Incremental shear strain{at}",
                                       overlay=overlay))
    return [p for p in paths if p is not None]


def circle_overlay(circle: SlipCircle) -> Callable[[Any], None]:
    """Overlay that draws a slip ``circle`` dashed, labelled with its factor of safety."""
    arc = circle.arc()

    def draw(ax: Any) -> None:
        ax.plot(arc[:, 0], arc[:, 1], "r--", lw=1.5,
                label=f"critical circle (Bishop), F = {circle.factor:.3f}")
        ax.legend(loc="upper left", fontsize=8)

    return draw


def safety_engineering_figures(out: str | Path, safety: SafetyResult, *,
                               circle: SlipCircle | None = None, window: Window | None = None,
                               prefix: str = "fos_", elevation_label: str = "y [m]"
                               ) -> list[Path]:
    """:func:`engineering_figures` of a strength reduction's state at F.

    The incremental shear strain is that of the last reduction step, drawn only when that
    step showed a mechanism (``safety.mechanism_confirmed``; the title says when none was
    found); ``circle`` (e.g. Bishop's critical circle) is drawn over the shear strains.
    """
    if safety.state is None:
        raise ValueError("safety_engineering_figures: the SafetyResult has no state at F "
                         "(give the result of factor_of_safety)")
    confirmed = safety.mechanism_confirmed
    return engineering_figures(
        out, safety.state, prefix=prefix, window=window,
        overlay=None if circle is None else circle_overlay(circle),
        when=f"F = {safety.factor:.3f}" + ("" if confirmed else " (no mechanism found)"),
        increment=safety.mechanism if confirmed else None, elevation_label=elevation_label)
