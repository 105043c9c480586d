"""Figures of a discrete state: the deformed elements coloured by a field, failed interfaces.

Units: m for coordinates; the colour field in its own unit (kPa for stresses, - for strains).
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

from hybrid.discrete.state import DiscreteState
from hybrid.io import Box, check_box, save_figure

__all__ = ["plot_configuration", "failed_segments", "outline_segments", "Snapshots"]


def failed_segments(state: DiscreteState, *, reference: bool = False) -> np.ndarray:
    """End points [m] of the failed interfaces (n_failed, 2, 2), on element A's side.

    In the current configuration, or the reference one with ``reference``.
    """
    failed = np.flatnonzero(~state.interface_intact)
    xs = state.x_ref if reference else state.x
    return xs[state.interface_nodes[failed][:, :2]]


def outline_segments(state: DiscreteState) -> np.ndarray:
    """The outline of the body at the start of the phase (reference geometry) (n, 2, 2) [m].

    The element edges that were no interface at the start: the ground surface, the model's
    boundaries (and the edges between elements that started apart).
    """
    nodes = state.element_nodes
    edges = np.stack([nodes, np.roll(nodes, -1, axis=1)], axis=2).reshape(-1, 2)
    inner = np.concatenate([state.interface_nodes[:, :2], state.interface_nodes[:, 2:]])
    key = np.int64(state.x_ref.shape[0])
    inner_keys = np.sort(inner, axis=1) @ np.array([key, 1])
    edge_keys = np.sort(edges, axis=1) @ np.array([key, 1])
    return state.x_ref[edges[~np.isin(edge_keys, inner_keys)]]


def plot_configuration(path: str | Path, state: DiscreteState, *, title: str = "",
                       field: str = "plastic_strain", window: Box | None = None,
                       reference: bool = False, dpi: int = 100,
                       lines: dict[str, np.ndarray] | None = None,
                       outline: bool = False) -> Path:
    """PNG of the elements (deformed, or ``reference`` shape) coloured by ``field``.

    ``field``: "plastic_strain" (Gauss-point mean [-]) or "sigma_yy" (mean vertical stress
    [kPa]); the failed interfaces are drawn in red. ``window`` = (xmin, ymin, xmax, ymax) [m]
    crops the view; ``lines`` = {label: segments (n, 2, 2) [m]} are drawn on top (e.g. a
    fitted slip line); ``outline``: the outline at the start of the phase (the original
    surface) dashed (:func:`outline_segments`).
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.collections import LineCollection, PolyCollection
    from matplotlib.transforms import ScaledTranslation

    fields = {"plastic_strain": (state.plastic_strain.mean(axis=1), "plastic strain [-]",
                                 "magma_r"),
              "sigma_yy": (state.stress[:, :, 1].mean(axis=1), "sigma_yy [kPa]", "viridis")}
    if field not in fields:
        raise ValueError(f"field = {field!r}: choose one of {sorted(fields)}")
    values, label, cmap = fields[field]
    xs = state.x_ref if reference else state.x
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    box = check_box(window) if window is not None else None  # checked before it is read
    wide = box is not None and (box[2] - box[0]) > 2.5 * (box[3] - box[1])
    fig, ax = plt.subplots(figsize=(10.0, 5.0) if wide else (7.0, 5.0), dpi=dpi)
    pc = PolyCollection(xs[state.element_nodes], array=values, cmap=cmap, edgecolors="0.5",
                        linewidths=0.15)
    ax.add_collection(pc)
    fig.colorbar(pc, ax=ax, label=label, shrink=0.8)
    if outline:
        ax.add_collection(LineCollection(outline_segments(state), colors="k", linewidths=0.9,
                                         linestyles="--", label="outline at the start"))
    seg = failed_segments(state, reference=reference)
    if len(seg):
        ax.add_collection(LineCollection(seg, colors="red", linewidths=1.0,
                                         label=f"failed interfaces ({len(seg)})"))
    for i, (name, segs) in enumerate((lines or {}).items()):
        ax.add_collection(LineCollection(np.asarray(segs, float), colors=f"C{i}", linewidths=2.0,
                                         label=name))
    if len(seg) or lines or outline:
        below = ax.transAxes + ScaledTranslation(0.0, -0.5, fig.dpi_scale_trans)  # under x label
        ax.legend(fontsize=8, loc="upper center", bbox_to_anchor=(0.5, 0.0),
                  bbox_transform=below, ncol=2)
    ax.autoscale()
    if box is not None:
        xmin, ymin, xmax, ymax = box
        ax.set_xlim(xmin, xmax)
        ax.set_ylim(ymin, ymax)
    ax.set_aspect("equal")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_title(title or f"t = {state.time:.4g} s")
    return save_figure(fig, path)


class Snapshots:
    """``on_check`` callback of :meth:`ExplicitSolver.run` that plots configurations.

    Writes a :func:`plot_configuration` PNG ``{prefix}{t:g}.png`` in ``out`` when the time
    first reaches each of ``times`` [s].

    ``title`` is formatted with the state's ``time``; ``paths`` lists the files written; the
    other keywords go to :func:`plot_configuration`. Never stops the run.
    """

    def __init__(self, out: str | Path, times: Sequence[float], *, prefix: str = "t",
                 title: str = "t = {time:.3g} s", **options: Any) -> None:
        self.out, self.times, self.prefix = Path(out), sorted(times), prefix
        self.title, self.options = title, options
        self.paths: list[Path] = []

    def __call__(self, state: DiscreteState) -> bool:
        """Plot the times reached by ``state``; always False (the run goes on)."""
        while self.times and state.time >= self.times[0]:
            self.paths.append(plot_configuration(
                self.out / f"{self.prefix}{self.times[0]:g}.png", state,
                title=self.title.format(time=state.time), **self.options))
            self.times.pop(0)
        return False
