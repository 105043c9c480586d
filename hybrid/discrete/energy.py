"""Figures of merit of a run's energy ledger (``RunResult.history``), in kJ/m.

supply(t) = E(start) + the work of gravity and loads and of the supports since the start,
with E = kinetic + strain + contact elastic energy and ``start`` the ledger when the run
began (``RunResult.start``; the ledger's works are totals since the state was made, so a
continued run's works count from its own start). A run whose mechanical energy never exceeds its
supply has bounded energy (dissipation takes the difference).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

__all__ = ["mechanical_energy", "energy_excess", "energy_peak_ratio", "conservation_checks",
           "phase_history", "LABELS", "DISSIPATION"]

#: plot labels of the ledger terms
LABELS = {"kinetic": "kinetic", "strain": "strain", "contact_elastic": "contact (elastic)",
          "work_loads": "work of gravity and loads", "work_supports": "work of supports",
          "damping": "damping (mass, local, dashpots)", "friction": "friction",
          "contact_damping": "contact damping",
          "contact_normal_defect": "contact normal defect",
          "residual": "plastic dissipation (+ integration error)"}
#: the dissipation terms (the ledger's residual is the plastic dissipation, see ledger.py)
DISSIPATION = ("damping", "friction", "contact_damping", "residual")


def mechanical_energy(h: Mapping[str, Any], start: Mapping[str, float]
                      ) -> tuple[np.ndarray, np.ndarray]:
    """(E, supply) over the run's records; ``start``: the ledger at the run's start."""
    e = h["kinetic"] + h["strain"] + h.get("contact_elastic", 0.0)
    e0 = start["kinetic"] + start["strain"] + start.get("contact_elastic", 0.0)
    w0 = start["work_loads"] + start["work_supports"]
    return e, e0 + (h["work_loads"] + h["work_supports"] - w0)


def energy_excess(h: Mapping[str, Any], start: Mapping[str, float]) -> float:
    """Maximum over the run of (E - supply) / max |supply| (0 when the energy stays bounded)."""
    e, supply = mechanical_energy(h, start)
    return max(float(np.max(e - supply)) / float(np.max(np.abs(supply))), 0.0)


def energy_peak_ratio(h: Mapping[str, Any], start: Mapping[str, float]) -> float:
    """Maximum over the run of E / supply: how close the energy came to its sources (<= 1)."""
    e, supply = mechanical_energy(h, start)
    ok = np.abs(supply) > 1e-12 * float(np.max(np.abs(supply)))
    return float(np.max(e[ok] / supply[ok])) if ok.any() else 0.0


def conservation_checks(h: Mapping[str, Any], start: Mapping[str, float], state: Any,
                        n_elements: int, mass: float) -> dict[str, Any]:
    """The standard checks of a discrete run (:class:`~hybrid.io.Check`).

    Energy never above its sources since ``start`` (1 %), the ``n_elements`` elements and the
    ``mass`` [t/m] of the start kept.
    """
    from hybrid.io import Check

    return {
        "energy_excess_over_sources": Check(energy_excess(h, start), 0.0, 0.01, "-",
                                            "E_kin + E_strain + E_contact <= E(0) + work"),
        "elements_conserved": Check(float(state.n_elements), float(n_elements), 0.0),
        "mass_conserved": Check(float(state.mass.sum()), mass, 1e-12, "t/m")}


def phase_history(histories: Sequence[Mapping[str, Any]]) -> dict[str, np.ndarray]:
    """The histories of consecutive runs of one solver as one history of the phase.

    ``histories``: ``RunResult.history`` of each run in order (e.g. of
    ``ExplicitSolver.results``: loading, then rest). The ledger's terms are totals since the
    state was made and carry over from run to run; the residual of each run counts from its
    start, so the residual at the end of the runs before is added to it: the residual of the
    phase counts from the start of the first run.
    """
    if not histories:
        raise ValueError("phase_history: give the history of one run at least")
    out: dict[str, list[np.ndarray]] = {key: [] for key in histories[0]}
    offset = 0.0
    for h in histories:
        for key in out:
            values = np.asarray(h[key], dtype=float)
            out[key].append(values + offset if key == "residual" else values)
        if len(h["residual"]):
            offset += float(np.asarray(h["residual"])[-1])
    return {key: np.concatenate(parts) for key, parts in out.items()}
