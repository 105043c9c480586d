"""Measures of a discrete run on its interfaces: slip, the slip surface and where it runs.

Units: m. An interface is the edge two elements shared at the start; its two node pairs
coincided then, so their separation is the slip (sliding and opening together).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np

from hybrid.discrete.state import DiscreteState

__all__ = ["interface_slip", "slip_surface", "slip_trace", "slipped_interfaces"]


def interface_slip(state: DiscreteState) -> np.ndarray:
    """Relative movement [m] of the two sides of every interface (n_interfaces,).

    The mean over the interface's two node pairs of their distance.
    """
    n = state.interface_nodes
    return 0.5 * (np.linalg.norm(state.x[n[:, 0]] - state.x[n[:, 2]], axis=1)
                  + np.linalg.norm(state.x[n[:, 1]] - state.x[n[:, 3]], axis=1))


def slip_surface(state: DiscreteState, min_slip: float) -> np.ndarray:
    """(n_interfaces,) True for the failed interfaces that slipped at least ``min_slip`` [m]."""
    return ~state.interface_intact & (interface_slip(state) >= min_slip)


def slip_trace(state: DiscreteState, on_surface: np.ndarray,
               width: float = 5.0) -> list[list[float]]:
    """The slip surface as (x, y) points [m] in the start geometry.

    In each ``width`` strip of x, the midpoint of the deepest interface of ``on_surface`` (a
    mask of interfaces).
    """
    mid = state.x_ref[state.interface_nodes[on_surface][:, :2]].mean(axis=1)
    trace = []
    for b in np.unique(np.floor(mid[:, 0] / width)):
        k = np.floor(mid[:, 0] / width) == b
        trace.append(mid[k][np.argmin(mid[k, 1])].tolist())
    return trace


def slipped_interfaces(state: DiscreteState, thresholds: Sequence[float],
                       element_sets: Mapping[str, np.ndarray]) -> dict[str, dict[str, int]]:
    """Count the failed interfaces that slipped at least each threshold t [m].

    For each t (key f"{t:g}"): the failed interfaces that slipped at least t ("interfaces")
    and, per named element set (an (n_elements,) mask), how many of them have an element of
    the set on either side.
    """
    slip = interface_slip(state)
    out = {}
    for t in thresholds:
        pairs = state.interface_elements[~state.interface_intact & (slip >= t)]
        out[f"{t:g}"] = {"interfaces": len(pairs),
                         **{name: int(mask[pairs].any(axis=1).sum())
                            for name, mask in element_sets.items()}}
    return out
